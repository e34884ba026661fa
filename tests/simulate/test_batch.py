"""Lockstep batches (:mod:`trikedyn.simulate.batch`) equal the scalar loop run by run, and the batched
threshold search (:mod:`trikedyn.analysis.batch_search`) finds the scalar search's thresholds."""

import math

import numpy as np
import pytest

from trikedyn.analysis.batch_search import batch_margin_search
from trikedyn.analysis.search import Grid, Probe
from trikedyn.analysis.threshold import threshold_velocity
from trikedyn.errors import InputError
from trikedyn.model.statics import rolling_state, static_equilibrium
from trikedyn.model.vehicle import build_model
from trikedyn.params.ops import scale_suspension, with_freight
from trikedyn.simulate.batch import run_batch, run_prepared
from trikedyn.simulate.closed_loop import run
from trikedyn.simulate.run import input_table, simulate, time_step

LOADS = ("front_fz_N", "rear_left_fz_N", "rear_right_fz_N")


def eight_lanes(reference):
    """Eight closed-loop double lane changes: six speeds of reference-etrike (the two fastest roll over
    early) and two parameter variants (100 kg of freight; rear and front springs 1.5 times as stiff), as
    (models, speeds [km/h])."""
    base = build_model(reference)
    freight = build_model(with_freight(reference, 100.0))
    stiff = build_model(scale_suspension(reference, stiffness=1.5))
    return [base] * 6 + [freight, stiff], [20.0, 35.0, 45.0, 50.0, 58.0, 70.0, 40.0, 48.0]


@pytest.fixture(scope="module")
def lanes(reference):
    """:func:`eight_lanes` and their scalar runs."""
    vehicles, speeds = eight_lanes(reference)
    scalar = [run(m, "dlc", speed_kmh=v) for m, v in zip(vehicles, speeds, strict=True)]
    return vehicles, speeds, scalar


def assert_same_records(batch, scalar):
    """Same status and the same records, bit for bit: times, states, wheel loads, path error (the issue asks
    1e-9; each lane does its scalar run's arithmetic in the same order, so they are equal)."""
    assert batch.status == scalar.status
    assert batch.time_s.shape == scalar.time_s.shape
    np.testing.assert_array_equal(batch.time_s, scalar.time_s)
    np.testing.assert_array_equal(batch.states, scalar.states)
    for name in LOADS:
        np.testing.assert_array_equal(batch.channels[name], scalar.channels[name])
    np.testing.assert_array_equal(batch.channels["path_error_m"], scalar.channels["path_error_m"])


def test_a_batch_of_eight_equals_eight_scalar_runs(lanes):
    vehicles, speeds, scalar = lanes
    stopped = [r for r in scalar if not r.success]
    assert len(stopped) >= 2 and all(r.time_s[-1] < 9.0 for r in stopped)  # lanes that end early ...
    assert max(r.time_s[-1] for r in scalar) > 2 * max(r.time_s[-1] for r in stopped)  # ... while others go on
    assert all(name in scalar[0].channels for name in LOADS)
    batch = run_batch(vehicles, "dlc", speeds, lanes=8)
    assert len(batch) == 8
    for b, s in zip(batch, scalar, strict=True):
        assert_same_records(b, s)
        assert b.meta["target_speed_kmh"] == s.meta["target_speed_kmh"]


def test_refilled_lanes_give_the_same_runs(lanes):
    """Three lanes for eight runs: each lane takes the next run when its own ends."""
    vehicles, speeds, scalar = lanes
    for b, s in zip(run_batch(vehicles, "dlc", speeds, lanes=3), scalar, strict=True):
        assert_same_records(b, s)


def test_an_open_loop_batch_equals_the_scalar_loop(reference):
    model = build_model(reference)
    eq = static_equilibrium(model.on_flat_road())
    specs, scalar = [], []
    for v, amp in ((20.0, 0.02), (30.0, 0.04), (40.0, 0.03)):
        x0 = rolling_state(model, eq, v / 3.6)
        dt = time_step(model, x0, None)
        steer = lambda t, amp=amp: amp * np.sin(2 * np.pi * 0.5 * t)  # noqa: E731
        specs.append({"model": model, "x0": x0, "inputs": input_table(4.0, dt, steer, 40.0), "duration_s": 4.0,
                      "dt": dt})
        scalar.append(simulate(model, duration_s=4.0, speed_kmh=v, steer_rad=steer, drive_torque_Nm=40.0))
    for b, s in zip(run_prepared(specs, lanes=2), scalar, strict=True):
        assert b.status == s.status and b.time_s.shape == s.time_s.shape
        np.testing.assert_allclose(b.states, s.states, rtol=0, atol=1e-9)
        for name in LOADS:
            np.testing.assert_allclose(b.channels[name], s.channels[name], rtol=0, atol=1e-9)


def test_bad_lanes_are_an_input_error(reference):
    with pytest.raises(InputError, match="lanes"):
        run_batch(reference, "dlc", [30.0], lanes=0)
    with pytest.raises(InputError, match="broadcast"):
        run_batch([reference, reference], "dlc", [30.0, 40.0, 50.0])


# ------------------------------------------------------------------------------------------------------------
# the batched threshold search
# ------------------------------------------------------------------------------------------------------------
def _synthetic(crossing_kmh):
    """Probes of a wheel whose load falls linearly in v^2 to zero at ``crossing_kmh`` [km/h] (static 1000 N),
    and the speeds asked for, round by round."""
    rounds = []

    def probe_many(speeds):
        rounds.append(list(speeds))
        out = []
        for v in speeds:
            m = 1000.0 * (1.0 - (v / crossing_kmh) ** 2) if crossing_kmh > 0 else -1.0
            out.append(Probe(v, m > 0, np.full((1, 3), m), np.array([1000.0])))
        return out

    return probe_many, rounds


@pytest.mark.parametrize("crossing", [5.0, 10.05, 23.37, 47.81, 61.0, 89.99, 95.0])
@pytest.mark.parametrize("lanes_per_round", [1, 4, 8])
def test_the_batched_search_certifies_the_crossing(crossing, lanes_per_round):
    grid = Grid(10.0, 90.0, 0.1)
    probe_many, rounds = _synthetic(crossing)
    out = batch_margin_search(probe_many, grid, seed_kmh=40.0, lanes=lanes_per_round)
    if crossing <= 10.0:
        assert out.passed is None and out.failed == 0
    elif crossing > 90.0:
        assert out.passed == grid.last and out.failed is None
    else:
        assert grid.speed(out.passed) < crossing <= grid.speed(out.failed) and out.failed == out.passed + 1
    assert all(len(r) <= lanes_per_round for r in rounds)
    tried = [v for r in rounds for v in r]
    assert len(tried) == len(set(tried))  # no speed run twice
    if lanes_per_round == 8 and 10.0 < crossing < 90.0:
        assert len(rounds) <= 4


def _paper_models():
    from trikedyn.study.scenarios import expand
    from trikedyn.study.spec import load_spec

    spec = load_spec("paper")
    base = spec.load_vehicle()
    chosen = {}
    for s in expand(spec):  # one scenario per manoeuvre and stiffness, the spec's first freight
        key = (s["manoeuvre"], s["stiffness_scale"])
        if key not in chosen and not s["overrides"] and s["damping_scale"] == 1.0:
            chosen[key] = s
    picked = sorted(chosen.values(), key=lambda s: (s["manoeuvre"], s["stiffness_scale"]))
    picked = picked[:: max(1, len(picked) // 4)][:4]
    for s in picked:
        pset = scale_suspension(base, stiffness=s["stiffness_scale"], damping=s["damping_scale"])
        yield s, build_model(with_freight(pset, s["freight_kg"]))


@pytest.mark.parametrize("criterion", ["course", "lift-off"])
def test_the_batch_method_finds_the_margin_searchs_threshold_on_paper_scenarios(criterion):
    count = 0
    for s, model in _paper_models():
        search = dict(low_kmh=s["low_kmh"], high_kmh=s["high_kmh"], step_kmh=s["step_kmh"],
                      resolution_kmh=s["resolution_kmh"], speed_control=s["speed_control"], criterion=criterion)
        margin = threshold_velocity(model, s["manoeuvre"], **search)
        batch = threshold_velocity(model, s["manoeuvre"], method="batch", **search)
        assert batch.method == "batch"
        for f in ("threshold_speed_kmh", "first_failure_kmh", "limit", "limiting_wheel", "lift_time_s"):
            assert getattr(batch, f) == getattr(margin, f), (s["manoeuvre"], s["stiffness_scale"], f)
        assert batch.threshold_speed_kmh in batch.speeds_kmh and batch.first_failure_kmh in batch.speeds_kmh
        assert math.isclose(batch.first_failure_kmh - batch.threshold_speed_kmh, s["resolution_kmh"], abs_tol=1e-9)
        count += 1
    assert count >= 3


def test_the_batch_runs_on_the_scalar_loops_kernels(reference, monkeypatch):
    """With ``TRIKEDYN_KERNELS=generic`` both the scalar and the batch loop run on the generic kernels."""
    from trikedyn.simulate.batch import BATCH_KERNELS
    from trikedyn.simulate.lockstep import batch_loop

    monkeypatch.setenv("TRIKEDYN_KERNELS", "generic")
    model = build_model(reference)
    assert BATCH_KERNELS["generic"](model.plant) is batch_loop
    assert BATCH_KERNELS["generated"](model.plant) is not batch_loop
    speeds = [30.0, 60.0]
    scalar = [run(model, "dlc", speed_kmh=v) for v in speeds]
    assert not scalar[1].success
    for b, s in zip(run_batch(model, "dlc", speeds), scalar, strict=True):
        assert_same_records(b, s)
