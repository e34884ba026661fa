"""Runs that end at their exit gate (``end_at_exit``, :func:`trikedyn.simulate.closed_loop.exit_gate`): a
threshold search's runs stop where the judging ends, about a second (7-13 %) before the manoeuvre's end. Their
records are the whole run's first ones, bit for bit, in the scalar loop and in every batch loop, and their
verdicts and margin tables are the whole run's."""

import numpy as np
import pytest

import trikedyn.simulate.closed_loop as closed_loop
from trikedyn.analysis.margins import run_margins
from trikedyn.analysis.threshold import threshold_velocity
from trikedyn.analysis.verdict import Judging, judge
from trikedyn.manoeuvres import registry
from trikedyn.model.vehicle import build_model
from trikedyn.params.ops import with_freight
from trikedyn.simulate.batch import run_batch
from trikedyn.simulate.closed_loop import GATE_MARGIN_M, exit_gate, run


@pytest.mark.parametrize("manoeuvre, speed_kmh, control", [("dlc", 41.1, "driver"), ("dlc", 44.0, "driver"),
                                                           ("slc", 60.0, "ideal")])
def test_a_run_that_ends_at_its_exit_gate_is_the_whole_runs_beginning(reference, manoeuvre, speed_kmh, control):
    model = build_model(reference)
    whole = run(model, manoeuvre, speed_kmh=speed_kmh, speed_control=control)
    short = run(model, manoeuvre, speed_kmh=speed_kmh, speed_control=control, end_at_exit=True)
    n = short.time_s.size
    assert short.success and 0.8 < whole.time_s[-1] - short.time_s[-1] < 1.1  # AFTER_EXIT_S = 1 s, less the margin
    np.testing.assert_array_equal(short.states, whole.states[:n])
    for name, values in short.channels.items():
        np.testing.assert_array_equal(values, whole.channels[name][:n], err_msg=name)
    exit_m = short.manoeuvre.window.end
    s = short.channels["path_s_m"]
    assert s[-1] > exit_m + GATE_MARGIN_M - 1e-9 and s[-2] <= exit_m + GATE_MARGIN_M + 1e-9  # the first record past
    judging = Judging()
    verdict = judge(short, judging)
    assert verdict == judge(whole, judging)
    for criterion in ("course", "lift-off"):
        a, b = run_margins(short, verdict, criterion, judging), run_margins(whole, verdict, criterion, judging)
        np.testing.assert_array_equal(a[0], b[0])
        np.testing.assert_array_equal(a[1], b[1])
        assert a[2] == b[2]


@pytest.mark.parametrize("kernels", ["generated", "generated-scalar", "generic"])
def test_lanes_that_end_at_their_gates_equal_their_scalar_runs(reference, kernels, monkeypatch):
    """Five double lane changes on three lanes (refilled), three of them ending at the gate at different
    times, two rolling over before it; on the lane kernels and on each lane stepping through the scalar step
    (the scalar runs on the same kernels: the generic and the generated agree to 1e-12, not to the bit)."""
    monkeypatch.setenv("TRIKEDYN_KERNELS", "generic" if kernels == "generic" else "generated")
    base, laden = build_model(reference), build_model(with_freight(reference, 100.0))
    vehicles, speeds = [base, base, laden, base, base], [30.0, 41.0, 38.0, 58.0, 70.0]
    scalar = [run(m, "dlc", speed_kmh=v, end_at_exit=True) for m, v in zip(vehicles, speeds, strict=True)]
    assert sum(r.success for r in scalar) == 3 and sum(not r.success for r in scalar) == 2
    for b, s in zip(run_batch(vehicles, "dlc", speeds, lanes=3, kernels=kernels, end_at_exit=True), scalar,
                    strict=True):
        assert b.status == s.status
        np.testing.assert_array_equal(b.time_s, s.time_s)
        np.testing.assert_array_equal(b.states, s.states)


def test_a_run_ends_at_its_gate_only_where_the_path_is_straight_past_the_exit(reference):
    params = reference.params
    dlc = registry.build("dlc", params, 40.0)
    x, y, c, s = exit_gate(dlc)
    assert (c, s) == (1.0, 0.0) and np.isclose(x, np.interp(dlc.window.end + GATE_MARGIN_M, dlc.path.s_m,
                                                           dlc.path.x_m))
    bent = registry.build("circle", params, 30.0)  # its window is on the circle
    assert exit_gate(bent) is None
    assert exit_gate(registry.build("step", params, 40.0)) is None  # open loop, judged by time
    short = run(build_model(reference), bent, end_at_exit=True)
    assert short.time_s[-1] == pytest.approx(bent.duration_s, abs=0.011)  # the whole run


def test_a_search_on_runs_that_end_at_the_gate_finds_what_whole_runs_find(reference, monkeypatch):
    """The same speeds tried, the same threshold and limit (the margins and verdicts are the same)."""
    model = build_model(reference)
    short = threshold_velocity(model, "dlc", criterion="course")
    monkeypatch.setattr(closed_loop, "exit_gate", lambda manoeuvre: None)
    whole = threshold_velocity(model, "dlc", criterion="course")
    assert short.speeds_kmh == whole.speeds_kmh
    assert (short.threshold_speed_kmh, short.limit) == (whole.threshold_speed_kmh, whole.limit)
