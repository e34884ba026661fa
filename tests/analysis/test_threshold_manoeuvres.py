"""Threshold on any manoeuvre: open-loop (fishhook), a path from a CSV file, a manoeuvre plugged in by a
test; and the same plug-in through simulate, threshold and a study spec without touching trikedyn."""

import json

import numpy as np
import pytest

from trikedyn.analysis.threshold import threshold_velocity
from trikedyn.cli import main
from trikedyn.params import load_vehicle

from ..manoeuvres import slalom_plugin  # noqa: F401  (registers "test-slalom")


def _crossing(result):
    passed = [r.speed_kmh for r in result.runs if r.passed]
    failed = [r.speed_kmh for r in result.runs if not r.passed]
    assert passed and failed
    assert max(passed) == pytest.approx(result.threshold_speed_kmh)
    assert min(failed) > max(passed)


def test_threshold_on_the_fishhook(reference):
    result = threshold_velocity(reference, "fishhook", options={"scale": 2.0}, low_kmh=5.0, resolution_kmh=0.5)
    assert result.limit == "lift-off" and result.limiting_wheel in ("rear_left", "rear_right")
    assert 5.0 < result.threshold_speed_kmh < 90.0
    _crossing(result)
    harsher = threshold_velocity(reference, "fishhook", options={"scale": 3.0}, low_kmh=5.0, resolution_kmh=0.5)
    assert harsher.threshold_speed_kmh < result.threshold_speed_kmh


def test_threshold_on_a_path_from_a_csv_file(reference, tmp_path):
    x = np.linspace(0.0, 120.0, 241)
    y = 3.0 / (1.0 + np.exp(-(x - 50.0) / 3.0))  # a sharp lane change to the left
    file = tmp_path / "change.csv"
    file.write_text("x_m,y_m\n" + "\n".join(f"{a:.4f},{b:.6f}" for a, b in zip(x, y, strict=True)), encoding="utf-8")
    result = threshold_velocity(reference, str(file), resolution_kmh=0.5)
    assert result.limit in ("lift-off", "tracking") and result.threshold_speed_kmh < 90.0
    _crossing(result)
    code = main(["threshold", "reference-etrike", "--manoeuvre", str(file), "--resolution", "0.5", "--json"])
    assert code == 0


def test_a_plugged_in_manoeuvre_works_everywhere(reference, tmp_path, capsys):
    assert main(["simulate", "reference-etrike", "--manoeuvre", "test-slalom", "--speed", "20", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["manoeuvre"] == "Slalom" and data["success"] and data["window_complete"]
    assert main(["threshold", "reference-etrike", "--manoeuvre", "test-slalom", "-o", "amplitude_m=2",
                 "--resolution", "1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["options"] == {"amplitude_m": "2"} and data["threshold_speed_kmh"] is not None
    assert main(["manoeuvres", "--json"]) == 0
    assert "test-slalom" in [k["name"] for k in json.loads(capsys.readouterr().out)]

    from trikedyn.study import run_study

    spec = tmp_path / "slalom.toml"
    spec.write_text('name = "slalom"\nmanoeuvres = ["test-slalom"]\nfreight_kg = [0]\nresolution_kmh = 2.0\n',
                    encoding="utf-8")
    frame = run_study(spec, tmp_path / "out", workers=0, progress=False)
    assert list(frame["status"]) == ["ok"] and frame.loc[0, "manoeuvre"] == "test-slalom"
    # the default slalom (1.5 m) is gentler than the 2 m one the CLI searched
    assert frame.loc[0, "threshold_speed_kmh"] > data["threshold_speed_kmh"]


def test_study_spec_rejects_an_unknown_manoeuvre(tmp_path):
    from trikedyn.errors import InputError
    from trikedyn.study import load_spec

    spec = tmp_path / "bad.toml"
    spec.write_text('name = "bad"\nmanoeuvres = ["dlcc"]\n', encoding="utf-8")
    with pytest.raises(InputError, match="did you mean 'dlc'"):
        load_spec(spec)


def test_old_names_keep_working(capsys):
    """dlc/slc and the JSON keys of simulate stay as they were."""
    code = main(["simulate", "reference-etrike", "--manoeuvre", "circle", "--radius", "15", "--speed", "25", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0
    for key in ("manoeuvre", "status", "duration_s", "cone_strikes", "max_abs_ri", "max_abs_ri_all_wheels_down",
                "min_wheel_load_N", "wheel_lifted", "max_lateral_acceleration_mps2", "max_yaw_rate_radps",
                "max_path_error_m", "max_speed_kmh", "min_speed_kmh"):
        assert key in data
    assert data["max_abs_ri"] < 0.4  # the end-of-path swerve (0.59) is gone
    assert load_vehicle("reference-etrike") is not None
