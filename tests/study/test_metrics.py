"""Issue 12, general studies: metrics beyond the threshold, one executor interface, figures chosen from a
study's shape, and a progress line without a terminal."""

from __future__ import annotations

import concurrent.futures as cf
import math
import textwrap

import pandas as pd
import pytest

from trikedyn.errors import InputError
from trikedyn.study import count_scenarios, expand, load_spec, parse_spec, run_study
from trikedyn.study.metrics import label, study_metric

from . import warm_numba_cache, write_spec


@pytest.fixture(scope="module")
def warm():
    warm_numba_cache()


# ------------------------------------------------------------------------------------------------
# metrics in the spec
# ------------------------------------------------------------------------------------------------
def test_default_metric_is_the_threshold_and_keeps_the_ids(tmp_path):
    plain = expand(load_spec(write_spec(tmp_path)))
    explicit = expand(load_spec(write_spec(tmp_path, name="explicit", extra="")))
    assert [s["scenario_id"] for s in plain] == [s["scenario_id"] for s in explicit]
    text = write_spec(tmp_path, name="listed").read_text().replace('manoeuvres = ["slc"]',
                                                                  'manoeuvres = ["slc"]\nmetrics = ["threshold"]')
    listed = parse_spec(text)
    assert [s["scenario_id"] for s in expand(listed)] == [s["scenario_id"] for s in plain]
    assert {s["metric"] for s in plain} == {"threshold"} and {s["metric_label"] for s in plain} == {"threshold"}
    assert len(expand(load_spec("paper"))) == 50


MIXED = textwrap.dedent("""
    name = "mixed"
    manoeuvres = ["slc", "dlc"]
    freight_kg = [0, 100]
    metrics = ["threshold", "tilt_angle", { name = "peak_ri", speed_kmh = 30 }, "understeer_gradient"]
""")


def test_metrics_multiply_manoeuvres_only_when_per_manoeuvre():
    spec = parse_spec(MIXED)
    scenarios = expand(spec)
    # threshold and peak_ri per manoeuvre (2 x 2 freights each), tilt and understeer once per variation
    assert len(scenarios) == 2 * 2 + 2 + 2 * 2 + 2 == count_scenarios(spec)[0]
    by = {}
    for s in scenarios:
        by.setdefault(s["metric_label"], set()).add(s["manoeuvre"])
    assert by == {"threshold": {"slc", "dlc"}, "tilt_angle": {None}, "peak_ri(speed_kmh=30)": {"slc", "dlc"},
                  "understeer_gradient": {None}}
    tilt = next(s for s in scenarios if s["metric"] == "tilt_angle")
    assert tilt["resolution_kmh"] is None  # no search: its settings are not part of it
    assert next(s for s in scenarios if s["metric"] == "understeer_gradient")["metric_options"] == {"radius_m": 20.0}
    assert len({s["scenario_id"] for s in scenarios}) == len(scenarios)


@pytest.mark.parametrize(("entry", "needle"), [
    ('"tilt_angel"', "unknown metric 'tilt_angel'; did you mean 'tilt_angle'?"),
    ('"peak_ri"', "metric 'peak_ri' needs the option 'speed_kmh'"),
    ('{ name = "peak_ri", speed = 30 }', "no option 'speed'; did you mean 'speed_kmh'?"),
    ('{ name = "peak_ri", speed_kmh = -3 }', "option 'speed_kmh' must be within"),
    ('"tilt_angle", "tilt_angle"', "'tilt_angle' is listed twice"),
])
def test_metric_mistakes_are_one_line_with_a_hint(entry, needle):
    with pytest.raises(InputError) as info:
        parse_spec(f'name = "x"\nmanoeuvres = ["slc"]\nmetrics = [{entry}]\n', origin="bad.toml")
    assert needle in str(info.value) and str(info.value).startswith("bad.toml: ")


def test_labels_leave_defaults_out():
    assert label("understeer_gradient", {"radius_m": 20.0}) == "understeer_gradient"
    assert label("understeer_gradient", {"radius_m": 40.0}) == "understeer_gradient(radius_m=40)"
    assert label("min_wheel_load", {"speed_kmh": 35.0}) == "min_wheel_load(speed_kmh=35)"


# ------------------------------------------------------------------------------------------------
# running metrics
# ------------------------------------------------------------------------------------------------
def test_a_study_of_other_metrics_runs_and_draws(tmp_path, warm):
    spec = tmp_path / "m.toml"
    spec.write_text(textwrap.dedent("""
        name = "metrics"
        manoeuvres = ["slc"]
        freight_kg = [0, 150]
        metrics = ["tilt_angle", "understeer_gradient", { name = "peak_ri", speed_kmh = 30 },
                   { name = "min_wheel_load", speed_kmh = 30 }]
    """), encoding="utf-8")
    table = run_study(spec, tmp_path / "out", workers=0, progress=False)
    assert list(table["metric"].unique()) == ["tilt_angle", "understeer_gradient", "peak_ri(speed_kmh=30)",
                                              "min_wheel_load(speed_kmh=30)"]
    assert set(table["status"]) == {"ok"} and table["value"].notna().all()
    assert table["threshold_speed_kmh"].isna().all()
    units = dict(zip(table["metric"], table["unit"], strict=False))
    assert units == {"tilt_angle": "deg", "understeer_gradient": "deg/g", "peak_ri(speed_kmh=30)": "-",
                     "min_wheel_load(speed_kmh=30)": "N"}
    tilt = table[table["metric"] == "tilt_angle"]["value"].to_numpy()
    assert 20 < tilt[0] < 60 and 20 < tilt[1] < 60
    ri = table[table["metric"].str.startswith("peak_ri")]["value"].to_numpy()
    assert all(0 <= v <= 1 for v in ri)
    assert list(table.columns[:8]) == ["scenario_id", "groups", "vehicle", "manoeuvre", "freight_kg",
                                       "stiffness_scale", "damping_scale", "metric"]
    for name in ("tilt_angle", "understeer_gradient", "peak_ri_speed_kmh_30", "min_wheel_load_speed_kmh_30"):
        assert (tmp_path / "out" / f"fig_{name}.png").is_file(), name
    exported = pd.read_csv(tmp_path / "out" / "results.csv")
    assert list(exported["metric"]) == list(table["metric"])


@study_metric("mass_for_test", unit="kg", per_manoeuvre=False)
def _mass(pset, scenario):
    """total mass, freight included (a metric registered by a test, not in the runner)"""
    import numpy as np

    from trikedyn.model.vehicle import build_model

    return {"value": float(np.asarray(build_model(pset).tree.total_mass()))}


def test_a_metric_registered_elsewhere_needs_no_runner_edit(tmp_path):
    spec = tmp_path / "mass.toml"
    spec.write_text('name = "mass"\nmanoeuvres = ["slc"]\nfreight_kg = [0, 50]\nmetrics = ["mass_for_test"]\n',
                    encoding="utf-8")
    table = run_study(spec, tmp_path / "out", workers=0, progress=False, figures=False)
    assert table["value"].iloc[1] - table["value"].iloc[0] == pytest.approx(50.0)
    assert list(table["unit"]) == ["kg", "kg"]


# ------------------------------------------------------------------------------------------------
# one executor interface
# ------------------------------------------------------------------------------------------------
def test_every_executor_is_a_concurrent_futures_executor():
    from trikedyn.study.engine.executors import InlineExecutor, ProcessPool, make_executor

    inline = make_executor(0, None, None, 3)
    assert isinstance(inline, InlineExecutor) and isinstance(inline, cf.Executor)
    fut = inline.submit(math.sqrt, 4.0)
    assert fut.done() and fut.result() == 2.0 and not fut.cancel()
    bad = inline.submit(math.sqrt, -1.0)
    assert isinstance(bad.exception(), ValueError)  # in the future, as a pool's would be
    inline.shutdown()
    pool = make_executor(1, None, None, 3)
    try:
        assert isinstance(pool, ProcessPool) and isinstance(pool, cf.ProcessPoolExecutor)
        futures = [pool.submit(math.sqrt, v) for v in (1.0, 9.0)]
        done, _ = cf.wait(futures, timeout=60, return_when=cf.ALL_COMPLETED)
        assert [f.result() for f in futures] == [1.0, 3.0] and pool.window == 2
    finally:
        pool.shutdown(wait=False, cancel_futures=True)  # what a second Ctrl-C asks: workers stopped
    assert not any(p.is_alive() for p in (getattr(pool, "_processes", None) or {}).values())


def test_the_runner_has_no_command_line_of_its_own():
    import trikedyn.study.designs.runner as runner

    assert not hasattr(runner, "main") and not hasattr(runner, "study_command")
    import trikedyn as td

    assert td.run_study is runner.run_study


# ------------------------------------------------------------------------------------------------
# figures from the study's shape
# ------------------------------------------------------------------------------------------------
def _frame(**axes):
    """A threshold-only study table over the given axes (each a list of values), two manoeuvres."""
    import itertools

    rows = []
    names = list(axes)
    for man in ("dlc", "slc"):
        for combo in itertools.product(*axes.values()):
            rec = {"scenario_id": "x", "groups": "g", "vehicle": "v", "manoeuvre": man, "freight_kg": 0.0,
                   "stiffness_scale": 1.0, "damping_scale": 1.0}
            overrides = {}
            for n, v in zip(names, combo, strict=True):
                (rec if n in rec else overrides)[n] = v
            rec.update(overrides)
            rec.update(status="ok", threshold_speed_kmh=50.0 - sum(float(v) for v in combo) + (man == "slc"))
            rows.append(rec)
    return pd.DataFrame(rows)


@pytest.mark.parametrize(("axes", "kind"), [
    ({}, "bars"),
    ({"freight_kg": [0.0, 100.0, 200.0]}, "one factor"),
    ({"track_m": [1.0, 1.2], "component.battery.x_m": [0.4, 1.0]}, "two factors"),
    ({"track_m": [1.0, 1.1, 1.2, 1.3, 1.4], "freight_kg": [0.0, 50.0, 100.0, 150.0, 200.0]}, "heat map"),
    ({"freight_kg": [0.0, 100.0], "stiffness_scale": [0.8, 1.2], "damping_scale": [0.8, 1.2]}, "main effects"),
])
def test_figures_follow_the_study_shape(tmp_path, axes, kind):
    from trikedyn.study.designs.figures import plan, study_figures

    frame = _frame(**axes)
    assert plan(frame) == [("threshold", kind, list(axes))] or kind in ("two factors", "heat map")
    assert plan(frame)[0][1] == kind
    paths = study_figures(frame, tmp_path, title="t")
    assert [p.name for p in paths] == ["fig_threshold.png"] and paths[0].stat().st_size > 1000


def test_the_paper_table_gives_main_effects():
    from trikedyn.study.designs.figures import plan

    frame = _frame(freight_kg=[0.0, 50.0], stiffness_scale=[0.8, 1.0], damping_scale=[1.0, 1.2])
    assert plan(frame)[0][1] == "main effects"


# ------------------------------------------------------------------------------------------------
# progress without a terminal
# ------------------------------------------------------------------------------------------------
def test_progress_without_a_terminal_is_a_plain_line(tmp_path, monkeypatch, capsys):
    import trikedyn.study.designs.runner as runner

    from .test_bounds import _fake_scenario

    monkeypatch.setattr(runner, "run_scenario", _fake_scenario)
    run_study(write_spec(tmp_path), tmp_path / "out", workers=0, figures=False)  # progress=True, stderr not a TTY
    lines = [line for line in capsys.readouterr().err.splitlines() if line.startswith("study: ")]
    assert lines[0].startswith("study: 0/4 scenarios, ") and lines[-1].startswith("study: 4/4 scenarios, ")
    assert all(" s" in line for line in lines)


def test_progress_line_says_the_time_spent_and_left(monkeypatch, capsys):
    from trikedyn.study.engine import progress

    now = [100.0]
    monkeypatch.setattr(progress.time, "monotonic", lambda: now[0])
    line = progress.LineProgress(every_s=0.0)
    line(2, 50)  # two stored before this run: not part of its pace
    now[0] = 108.1
    line(12, 50)
    assert capsys.readouterr().err.splitlines() == ["study: 2/50 scenarios, 0.0 s",
                                                    "study: 12/50 scenarios, 8.1 s, ~31 s left"]
