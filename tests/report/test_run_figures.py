"""``trikedyn plot --kind`` and :mod:`trikedyn.report.run_figures` (issue 13, "Figures"): titles naming the
vehicle, manoeuvre and speed; axis labels with units (speed in km/h); the wheel lift shaded; plan view with the
cones and footprints; g-g diagram; roll against lateral acceleration; PNGs written, never overwritten without
--force; a bad --kind exits 2."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from trikedyn.analysis.compare import load_table
from trikedyn.cli import main
from trikedyn.report.run_channels import lift_spans, title_of
from trikedyn.report.run_figures import KINDS, figure, figure_time, figure_wheel_loads
from trikedyn.simulate.runfile import run_meta


def _simulate(folder, speed):
    path = folder / f"dlc{speed}.parquet"
    assert main(["simulate", "reference-etrike", "--manoeuvre", "dlc", "--speed", str(speed), "--out", str(path)]) == 0
    return path


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Double lane changes of the reference e-trike at 30 km/h (all wheels down) and 50 km/h (a wheel lifts)."""
    folder = tmp_path_factory.mktemp("run_figures")
    return {speed: _simulate(folder, speed) for speed in (30, 50)}


def _read(path):
    frame, _ = load_table(path)
    return frame, run_meta(path, frame.attrs)


def _labels(fig):
    texts = []
    for ax in fig.axes:
        texts += [ax.get_xlabel(), ax.get_ylabel(), ax.get_title(loc="left"), ax.get_title()]
    return " | ".join(texts)


@pytest.mark.parametrize("kind", list(KINDS))
def test_each_kind_renders_with_units_and_a_title(runs, kind):
    frame, meta = _read(runs[30])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the course is rebuilt: no "no course drawn" warning
        fig = figure(kind, frame, meta)
    title = fig.get_suptitle()
    assert "reference-etrike" in title and "double lane change" in title and "30 km/h" in title
    labels = _labels(fig)
    expected = {"time": ["[km/h]", "[m/s²]", "[deg/s]", "[deg]", "time [s]"], "wheel-loads": ["[N]", "time [s]"],
                "plan": ["x [m]", "y [m]"], "gg": ["[g]"], "roll": ["roll [deg]", "[m/s²]"]}[kind]
    for unit in expected:
        assert unit in labels, (unit, labels)
    assert "speed_mps" not in labels and "_mps2" not in labels
    fig.canvas.draw()  # renders


def test_time_histories_show_km_h_and_the_judged_window(runs):
    frame, meta = _read(runs[30])
    fig = figure_time(frame, meta)
    speed_line = fig.axes[0].get_lines()[0].get_ydata()
    assert np.isclose(np.max(speed_line), frame["speed_mps"].max() * 3.6)
    assert any(p.get_gid() == "judged" for p in fig.axes[0].patches)
    assert "Eq. 5" in _labels(fig)


def test_plan_draws_the_cones_and_footprints(runs):
    frame, meta = _read(runs[30])
    fig = figure("plan", frame, meta)
    ax = fig.axes[0]
    assert sum(len(c.get_offsets()) for c in ax.collections) >= 10  # the cones
    assert sum(p.get_gid() == "footprint" for p in ax.patches) >= 10  # every second of a ~20 s run
    assert "cones" in fig.get_suptitle()


def test_wheel_loads_shade_the_lift(runs):
    frame, meta = _read(runs[50])
    lifted = [n for n in meta["wheels"] if (frame[f"{n}_fz_N"] <= 0).any()]
    assert lifted, "the 50 km/h double lane change should lift a wheel"
    fig = figure_wheel_loads(frame, meta)
    shaded = {ax.get_title(loc="left").split(" wheel")[0]: sum(p.get_gid() == "lift" for p in ax.patches)
              for ax in fig.axes}
    for name in lifted:
        assert shaded[name.replace("_", " ")] >= 1
    assert shaded["front"] == 0
    calm = figure_wheel_loads(*_read(runs[30]))
    assert not any(p.get_gid() == "lift" for ax in calm.axes for p in ax.patches)


def test_lift_spans_and_title():
    t = np.arange(8) * 0.1
    assert np.allclose(lift_spans(t, [5, 0, 0, 3, 2, -1, 0, 4]), [(0.1, 0.2), (0.5, 0.6)])
    assert lift_spans(t, np.ones(8)) == []
    assert title_of({"vehicle": "v", "manoeuvre": "m", "target_speed_kmh": 42.0}) == "v - m at 42 km/h"


def test_figures_from_a_result_in_memory():
    from trikedyn.params import load_vehicle
    from trikedyn.simulate.closed_loop import run

    result = run(load_vehicle("reference-etrike"), "slc", speed_kmh=30.0)
    for kind in KINDS:
        fig = figure(kind, result)
        assert "reference-etrike" in fig.get_suptitle(), kind


def _call(capsys, *args):
    code = main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_cli_writes_pngs_and_keeps_them(capsys, runs, tmp_path):
    out = tmp_path / "loads.png"
    code, text, err = _call(capsys, "plot", runs[50], "--kind", "wheel-loads", "--out", out, "--json")
    assert code == 0, err
    assert json.loads(text)["kind"] == "wheel-loads"
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 10_000
    before = out.stat().st_mtime_ns
    code, _, err = _call(capsys, "plot", runs[50], "--kind", "wheel-loads", "--out", out)
    assert code == 2 and "--force" in err and out.stat().st_mtime_ns == before
    assert _call(capsys, "plot", runs[50], "--kind", "wheel-loads", "--out", out, "--force")[0] == 0
    code, text, err = _call(capsys, "plot", runs[30], "--kind", "plan", "--force")
    assert code == 0, err
    assert runs[30].with_name(f"{runs[30].stem}-plan.png").stat().st_size > 10_000


@pytest.mark.parametrize(("args", "needle"), [(["--kind", "bogus"], "--kind"),
                                              (["--kind", "gg", "--channels", "ri"], "--channels"),
                                              (["--channels", "nope"], "nope")])
def test_cli_mistakes_exit_2(capsys, runs, tmp_path, args, needle):
    code, out, err = _call(capsys, "plot", runs[30], "--out", tmp_path / "x.png", *args)
    assert code == 2 and out == "" and err.startswith("trikedyn: error: ") and err.count("\n") == 1, err
    assert needle in err and not (tmp_path / "x.png").exists()
