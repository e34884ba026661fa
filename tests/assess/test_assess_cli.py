"""``trikedyn assess``: the dossier's numbers are the commands' numbers, a failing requirement is exit 1 and
named everywhere, a malformed requirements file is one line and exit 2, and the report passes the paper
report's Chromium checks (no overflow at 1280 and 800 px, every image loads, no console message)."""

from __future__ import annotations

import contextlib
import io
import json
import math

import pytest

from trikedyn.assess.transient import sweep_summary
from trikedyn.cli import main
from trikedyn.paper.cells import format_value

from ..paper.browser import WIDTHS, assert_fits_and_loads, probe

REQUIREMENTS = """
title = "test requirements"
source = "the test"
[[requirement]]
id = "tilt-ok"
metric = "tilt_angle_deg"
at_least = 20
[[requirement]]
id = "tilt-impossible"
metric = "tilt_angle_deg"
at_least = 80
note = "no trike tilts this far"
"""


def cli(*args) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def etrike(tmp_path_factory):
    """The reference trike's quick dossier, judged against a file with one failing item (--json)."""
    folder = tmp_path_factory.mktemp("etrike")
    reqs = folder.parent / "etrike-requirements.toml"
    reqs.write_text(REQUIREMENTS, encoding="utf-8")
    out = folder / "dossier"
    code, stdout, stderr = cli("assess", "reference-etrike", "--quick", "--out", str(out), "--requirements",
                               str(reqs), "--json")
    return {"out": out, "reqs": reqs, "code": code, "stdout": stdout, "stderr": stderr}


@pytest.fixture(scope="module")
def tadpole(tmp_path_factory):
    out = tmp_path_factory.mktemp("tadpole") / "dossier"
    code, stdout, stderr = cli("assess", "reference-tadpole", "--quick", "--out", str(out))
    return {"out": out, "code": code, "stdout": stdout, "stderr": stderr}


def test_failing_requirement_is_exit_1_and_named_in_json_text_and_report(etrike):
    assert etrike["code"] == 1, etrike["stderr"]
    shown = json.loads(etrike["stdout"])
    assert shown["requirements"]["failed"] == ["tilt-impossible"]
    verdicts = {j["id"]: j["verdict"] for j in shown["requirements"]["judgements"]}
    assert verdicts == {"tilt-ok": "PASS", "tilt-impossible": "FAIL"}
    saved = json.loads((etrike["out"] / "assess.json").read_text())
    assert saved["requirements"]["failed"] == ["tilt-impossible"]
    report = (etrike["out"] / "report.html").read_text()
    assert "tilt-impossible" in report and "FAIL" in report and "1 of 2 requirements" in report
    assert "assess: thresholds" in etrike["stderr"]  # progress on stderr
    # the text, from the pieces kept (--resume computes nothing again)
    code, text, err = cli("assess", "reference-etrike", "--quick", "--out", str(etrike["out"]), "--requirements",
                          str(etrike["reqs"]), "--resume")
    assert code == 1
    assert "FAIL  tilt-impossible" in text and "PASS  tilt-ok" in text
    assert "kept from the earlier run" in err and "threshold: dlc" not in err


def _command(*args) -> dict:
    code, out, err = cli(*args, "--json")
    assert code == 0, err
    return json.loads(out)


def test_numbers_are_the_commands_numbers(etrike):
    data = json.loads((etrike["out"] / "assess.json").read_text())
    metrics = data["states"]["as_given"]["metrics"]
    report = (etrike["out"] / "report.html").read_text()
    expected = {
        "tilt_angle_deg": _command("tilt", "reference-etrike")["tilt_angle_deg"],
        "dlc_threshold_kmh": _command("threshold", "reference-etrike")["threshold_speed_kmh"],
        "slc_threshold_kmh": _command("threshold", "reference-etrike", "--manoeuvre", "slc")["threshold_speed_kmh"],
        "dlc_lift_off_kmh": _command("threshold", "reference-etrike", "--criterion", "lift-off")["threshold_speed_kmh"],
        "top_speed_kmh": _command("performance", "reference-etrike")["top_speed_kmh"],
        "understeer_gradient_deg_per_g": _command("handling", "reference-etrike")["understeer_gradient_deg_per_g"],
    }
    for name, value in expected.items():
        assert value is not None, name
        assert metrics[name] == value, name
        assert f">{format_value(value)}<" in report, f"{name} = {format_value(value)} not in the report"


@pytest.mark.parametrize("manoeuvre", ["step", "sweep"])
def test_transient_figures_are_simulates_figures(etrike, manoeuvre):
    data = json.loads((etrike["out"] / "assess.json").read_text())
    state = data["states"]["as_given"]
    piece = state[manoeuvre]
    # 30 km/h unless 80 % of the DLC course threshold is lower
    assert piece["speed_kmh"] == min(30.0, math.floor(0.8 * state["metrics"]["dlc_threshold_kmh"]))
    shown = _command("simulate", "reference-etrike", "--manoeuvre", manoeuvre, "--speed", f"{piece['speed_kmh']:g}")
    assert piece["failure"] is None
    assert piece["figures"] == shown["figures"]
    assert (etrike["out"] / f"assess-parts/{manoeuvre}-{piece['speed_kmh']:g}.json").is_file()
    report = (etrike["out"] / "report.html").read_text()
    assert f'src="{manoeuvre}.png"' in report
    if manoeuvre == "step":
        yaw = shown["figures"]["yaw_rate"]
        for value in (yaw["response_time_s"], yaw["peak_response_time_s"], 100 * yaw["overshoot"]):
            assert f">{format_value(value)}<" in report
    else:
        summary = piece["summary"]["yaw_rate"]
        assert summary["low_frequency_gain"] == shown["figures"]["yaw_rate"]["gain"][0]
        assert f">{format_value(summary['phase_1hz_deg'])}<" in report


def test_sweep_summary_interpolates_the_3db_frequency_and_1hz():
    response = {"frequency_hz": [0.5, 1.0, 2.0], "gain": [2.0, 2.0, 1.0], "phase_deg": [-10.0, -20.0, -60.0]}
    s = sweep_summary(response)
    level = 2.0 / math.sqrt(2.0)
    assert s["minus_3db_hz"] == pytest.approx(1.0 + (2.0 - level) / 1.0 * 1.0)
    assert s["gain_1hz"] == 2.0 and s["phase_1hz_deg"] == -20.0 and s["low_frequency_gain"] == 2.0
    assert sweep_summary({**response, "gain": [2.0, 2.5, 2.0]})["minus_3db_hz"] is None
    assert sweep_summary({**response, "frequency_hz": [1.5, 2.0, 3.0]})["phase_1hz_deg"] is None


def test_tadpole_dossier(tadpole):
    assert tadpole["code"] == 0, tadpole["stderr"]
    data = json.loads((tadpole["out"] / "assess.json").read_text())
    assert data["vehicle"]["layout"] == "tadpole"
    assert "Static stability" in (tadpole["out"] / "report.html").read_text()
    assert "wrote" in tadpole["stdout"]


@pytest.mark.parametrize("width", WIDTHS)
@pytest.mark.parametrize("which", ["etrike", "tadpole"])
def test_report_fits_and_its_images_load_in_chromium(request, which, width, tmp_path):
    dossier = request.getfixturevalue(which)
    result, _, console = probe(dossier["out"] / "report.html", tmp_path, width)
    assert console == ""
    assert_fits_and_loads(result, width)
    loaded = {image["src"] for image in result["images"]}
    assert {"tilt.png", "handling.png", "step.png", "sweep.png"} <= loaded, loaded


@pytest.mark.parametrize(("text", "needle"), [
    ("[[requirement]]\nid = 'x'\nmetric = 'tilt'\nat_least = 3\n", "unknown requirement metric 'tilt'"),
    ("not toml [", "not valid TOML"),
])
def test_malformed_requirements_is_one_line_and_exit_2(tmp_path, text, needle):
    bad = tmp_path / "bad.toml"
    bad.write_text(text, encoding="utf-8")
    code, out, err = cli("assess", "reference-etrike", "--quick", "--out", str(tmp_path / "o"), "--requirements",
                         str(bad))
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith(f"trikedyn: error: {bad}: ") and needle in err
    assert not (tmp_path / "o").exists()  # nothing computed or written
    code, out, _ = cli("assess", "reference-etrike", "--requirements", "no-such-preset", "--json")
    assert code == 2 and json.loads(out)["where"] == "--requirements"
