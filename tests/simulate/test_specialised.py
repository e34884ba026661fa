"""The time loop on the kernels generated for the tree (trikedyn.simulate.specialised) against the generic loop.

The generic loop (RNEA, CRBA, Cholesky over any tree) is the reference. On both reference trikes, a closed-loop
double lane change and an open-loop sine steer with drive torque give the same states and wheel loads with
either loop, to 1e-9 of each quantity's largest magnitude over the run (at least 1 in its unit: m, rad, m/s,
rad/s, N); they agree to ~1e-13 (the generated code sums in another order). The exponential integrator's
``(H^-1)_ss`` from the generated ``L^T D L`` factor equals the inverse of the mass matrix's diagonal. The
lockstep batch on the generated kernels (the lane batch) gives each run of the generated loop bit for bit: its
tests are here, in the process that compiles the generated loop anyway (on a cold cache, ~50 s saved).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import trikedyn as td
from trikedyn.errors import InputError
from trikedyn.model.statics import rolling_state, static_equilibrium
from trikedyn.model.vehicle import build_model
from trikedyn.simulate import integrator
from trikedyn.simulate.batch import run_batch, run_prepared
from trikedyn.simulate.closed_loop import run
from trikedyn.simulate.specialised import KERNELS_ENV, kernel_choice, loop_module, time_loop

from .test_batch import LOADS, assert_same_records, eight_lanes

PRESETS = ["reference-etrike", "reference-tadpole"]
TOLERANCE = 1e-9


def sine_steer(t):
    """0.03 rad at 0.5 Hz about the steering axis."""
    return 0.03 * np.sin(np.pi * t)


def scaled_difference(a, b):
    """Largest ``|a - b|`` over the run, per column divided by the column's largest ``|b|`` (at least 1)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.max(np.abs(a - b) / np.maximum(1.0, np.abs(b).max(axis=0))))


def wheel_loads(result):
    """The wheels' vertical loads [N], one column per wheel."""
    names = [name for name in result.channels if name.endswith("_fz_N")]
    assert len(names) == 3
    return np.column_stack([result[name] for name in names])


def both(monkeypatch, runner):
    """``runner()`` with the generic loop, then with the generated one."""
    out = {}
    for kernels in ("generic", "generated"):
        monkeypatch.setenv(KERNELS_ENV, kernels)
        out[kernels] = runner()
    return out["generic"], out["generated"]


@pytest.fixture(scope="module", params=PRESETS)
def model(request):
    return build_model(td.load_vehicle(request.param))


def test_closed_loop_lane_change_equals_generic(model, monkeypatch):
    ref, got = both(monkeypatch, lambda: td.run(model, "dlc", speed_kmh=40.0))
    assert ref.success and got.success
    assert ref.states.shape == got.states.shape and ref.states.shape[0] > 1000
    assert scaled_difference(got.states, ref.states) < TOLERANCE
    assert scaled_difference(wheel_loads(got), wheel_loads(ref)) < TOLERANCE
    assert np.ptp(ref["y_m"]) > 2.0  # it did change lanes


def test_open_loop_run_equals_generic(model, monkeypatch):
    ref, got = both(monkeypatch, lambda: td.run_open_loop(model, duration_s=4.0, speed_kmh=30.0, steer_rad=sine_steer,
                                                         drive_torque_Nm=40.0))
    assert ref.success and got.success
    assert scaled_difference(got.states, ref.states) < TOLERANCE
    assert scaled_difference(wheel_loads(got), wheel_loads(ref)) < TOLERANCE
    assert np.ptp(wheel_loads(ref)) > 100.0  # the steering moved load between the wheels


def test_selection(model, monkeypatch):
    monkeypatch.delenv(KERNELS_ENV, raising=False)
    assert kernel_choice() == "generated"
    assert time_loop(model.plant) is loop_module(model.plant).rk4_loop
    assert time_loop(model.plant) is not integrator.rk4_loop
    assert time_loop(model.plant, "generic") is integrator.rk4_loop
    monkeypatch.setenv(KERNELS_ENV, "generic")
    assert time_loop(model.plant) is integrator.rk4_loop
    assert time_loop(model.plant, "generated") is loop_module(model.plant).rk4_loop
    module = loop_module(model.plant)
    text = open(module.__file__).read()
    assert "forward_dynamics_factor_into(" in text and "def rk4_loop(" in text
    assert "cholesky_solve_into" not in text and "crba_into" not in text  # no generic dynamics in this loop


def test_unknown_kernels_is_one_line(monkeypatch):
    monkeypatch.setenv(KERNELS_ENV, "fast")
    with pytest.raises(InputError, match=r"^TRIKEDYN_KERNELS: unknown kernels 'fast': expected one of generated, generic$"):
        kernel_choice()
    with pytest.raises(InputError, match="^kernels: unknown kernels 'x'"):
        kernel_choice("x")


def test_inverse_mass_diagonal_from_the_generated_factor(model):
    from numba import njit

    from trikedyn.model.codegen import kernels_for_tree
    from trikedyn.model.dynamics import crba
    from trikedyn.model.inverse_mass import ltdl_inverse_diagonal

    @njit
    def diagonal(factor, parent, n):
        z = np.empty(n)
        return np.array([ltdl_inverse_diagonal(factor, parent, s, z) for s in range(n)])

    p = model.plant
    k = kernels_for_tree(p)
    n = p.parent.shape[0] + 5
    rng = np.random.default_rng(4)
    for _ in range(5):
        q = rng.normal(0.0, 0.2, n)
        u = rng.normal(0.0, 3.0, n)
        factor = np.full((n, n), np.nan)  # the entries off the tree are never read
        out = np.empty(n)
        k.forward_dynamics_factor_into(q, u, rng.normal(0.0, 100.0, n), np.zeros((n - 5, 6)),
                                       np.array([0.0, 0.0, -9.81]), p.tree_e, p.tree_r, p.mass, p.h, p.ibar, out,
                                       factor)
        expected = np.diag(np.linalg.inv(crba(q, p.parent, p.jtype, p.jaxis, p.tree_e, p.tree_r, p.mass, p.h, p.ibar)))
        got = diagonal(factor, p.parent, n)
        assert np.all(expected > 0.0)
        assert np.max(np.abs(got - expected) / expected) < 1e-10


def test_the_generated_step_is_the_integrators_with_its_calls_written_out():
    """The generated ``etd_step`` is :func:`trikedyn.simulate.integrator.etd_step`'s own text, compiled on its own,
    with its spin-slip blocks and its three inner right-hand sides written out: every other line of the
    integrator's step is in it, in order, and no call of the inlined helpers is left."""
    import inspect
    import re

    from trikedyn.simulate import integrator, specialised

    step = specialised._step_source()
    assert step.lstrip().startswith("@jit\ndef etd_step(")
    assert "evaluate_stage_into(" not in step and "spin_slip_blocks(" not in step
    assert step.count("forward_dynamics_into(") == 3 and step.count("wrenches_into(") == 3
    source = inspect.getsource(integrator.etd_step.py_func)
    code = source[source.index('"""', source.index('"""') + 3) + 4:]
    replaced = re.compile(r"evaluate_stage_into|spin_slip_blocks")
    kept = [line for line in code.splitlines() if line.strip() and not replaced.search(line)]
    at = 0
    for line in kept:
        at = step.index(line + "\n", at) + len(line)


def test_the_stage_right_hand_side_equals_the_full_one(model):
    """``evaluate_stage_into`` (inner RK stages, no factor kept) gives ``evaluate_into``'s derivative and wheel
    outputs bit for bit on random states; it leaves the workspace's factor as it found it."""
    from trikedyn.model.packing import WHEEL_OUT
    from trikedyn.model.rhs import workspace
    from trikedyn.model.statics import rolling_state, static_equilibrium

    p = model.plant
    module = loop_module(p)
    x0 = rolling_state(model, static_equilibrium(model), 30 / 3.6)
    rng = np.random.default_rng(11)
    nw = p.wheels.shape[0]
    for _ in range(5):
        x = x0 + rng.normal(0.0, 1e-3, x0.size)
        u = np.array([rng.normal(0.0, 0.05), rng.normal(0.0, 30.0), 0.0])
        outs = []
        for evaluate in (module.evaluate_into, module.evaluate_stage_into):
            ws, wout, xdot = workspace(p.parent), np.zeros(nw, WHEEL_OUT), np.empty(x.size)
            ws.low[:] = 7.0
            evaluate(0.0, x, u, p, wout, ws, xdot)
            outs.append((xdot, wout, ws.low.copy()))
        (full, wfull, low_full), (stage, wstage, low_stage) = outs
        assert np.all(np.isfinite(full))
        assert np.array_equal(full, stage)
        assert all(np.array_equal(wfull[name], wstage[name]) for name in WHEEL_OUT.names)
        assert not np.all(low_full == 7.0) and np.all(low_stage == 7.0)


_PROBE = textwrap.dedent("""
    import json
    import trikedyn as td
    from trikedyn.model.vehicle import build_model
    from trikedyn.simulate.specialised import loop_module
    model = build_model(td.load_vehicle("reference-etrike"))
    r = td.run_open_loop(model, duration_s=0.5, speed_kmh=20.0)
    stats = loop_module(model.plant).rk4_loop.stats
    print(json.dumps({"ok": bool(r.success), "hits": sum(stats.cache_hits.values()),
                      "misses": sum(stats.cache_misses.values())}))
""")


def test_a_fresh_process_loads_the_compiled_loop(monkeypatch):
    monkeypatch.setenv(KERNELS_ENV, "generated")
    model = build_model(td.load_vehicle("reference-etrike"))
    assert td.run_open_loop(model, duration_s=0.5, speed_kmh=20.0).success  # compiled (or loaded) here
    done = subprocess.run([sys.executable, "-c", _PROBE], env=dict(os.environ), capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    probe = json.loads(done.stdout.strip().splitlines()[-1])
    assert probe["ok"] and probe["hits"] >= 1 and probe["misses"] == 0  # numba's cache, not a compilation


# ------------------------------------------------------------------------------------------------------------
# the lockstep batch on the generated kernels (trikedyn.simulate.lane_batch): each lane its scalar run, bit for bit
# ------------------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def generated_lanes(reference):
    """The eight runs of :func:`~tests.simulate.test_batch.eight_lanes`, the scalar ones on the generated kernels
    (the suite runs on the generic: the two kernel sets differ in the last bits, which grow to 2e-6 on a lane
    that rolls over). Here, in the file that compiles the generated loop anyway."""
    vehicles, speeds = eight_lanes(reference)
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("TRIKEDYN_KERNELS", "generated")
        return vehicles, speeds, [run(m, "dlc", speed_kmh=v) for m, v in zip(vehicles, speeds, strict=True)]


def test_the_lane_batch_gives_the_scalar_runs_bit_for_bit(generated_lanes):
    """On the generated kernels the batch evaluates each stage over its lanes (the lane kernels): each run
    equals the scalar run bit for bit, nine lanes for eight runs included (two groups of the lane kernels,
    one mostly idle)."""
    from trikedyn.simulate.batch import BATCH_KERNELS, LANE_WIDTH

    vehicles, speeds, scalar = generated_lanes
    assert BATCH_KERNELS["generated"](vehicles[0].plant).__name__ == "lane_batch_loop"
    for count in (8, LANE_WIDTH + 1):
        for b, s in zip(run_batch(vehicles, "dlc", speeds, lanes=count, kernels="generated"), scalar, strict=True):
            assert_same_records(b, s)


def test_a_batch_of_few_runs_goes_through_the_scalar_loop(generated_lanes, monkeypatch):
    """A lane step computes the kernels of every lane: fewer runs than ``FEWEST_LANES`` (or fewer lanes) go
    through the scalar loop, run after run, never the lane loop, and give the scalar runs."""
    from trikedyn.simulate import batch

    vehicles, speeds, scalar = generated_lanes

    def refused(plant):
        raise AssertionError("the lane loop ran a batch of fewer than FEWEST_LANES runs")

    monkeypatch.setitem(batch.BATCH_KERNELS, "generated", refused)
    few = batch.FEWEST_LANES - 1
    for b, s in zip(run_batch(vehicles[:few], "dlc", speeds[:few], kernels="generated"), scalar[:few], strict=True):
        assert_same_records(b, s)
    for b, s in zip(run_batch(vehicles, "dlc", speeds, lanes=few, kernels="generated"), scalar, strict=True):
        assert_same_records(b, s)
    with pytest.raises(AssertionError, match="FEWEST_LANES"):
        run_batch(vehicles[:4], "dlc", speeds[:4], kernels="generated")


@pytest.mark.slow
def test_the_stepwise_batch_on_the_generated_kernels_gives_the_scalar_runs(generated_lanes):
    """``generated-scalar``, the batch stepping each lane through the scalar step on the generated kernels (the
    lane batch's reference and the benchmark's), gives each scalar run bit for bit (slow: it compiles another
    loop, about 30 s on a cold cache)."""
    vehicles, speeds, scalar = generated_lanes
    for b, s in zip(run_batch(vehicles, "dlc", speeds, lanes=8, kernels="generated-scalar"), scalar, strict=True):
        assert_same_records(b, s)


def test_lanes_near_a_stop_take_their_substeps_alone(reference):
    """Thrown onto stops ten times as stiff (the wheel hop needs substeps of 3.7 ms at a 10 ms step), some
    lanes take their substeps alone while the others step together: every run equals its
    scalar run, and the thrown ones did reach their stops."""
    from trikedyn.params.ops import override
    from trikedyn.simulate.run import run_model, stop_step

    model = build_model(override(reference, {"suspension.front.bump_stop_stiffness_N_per_m": 5e6,
                                             "suspension.rear.bump_stop_stiffness_N_per_m": 4e6}))
    assert stop_step(model)[0] < 0.01
    eq = static_equilibrium(model.on_flat_road())
    specs = []
    for vz in (0.0, -1.5, 0.0, -1.0, -0.5):
        x0 = rolling_state(model, eq, 30 / 3.6)
        x0[model.n_dof + 5] = vz
        specs.append({"model": model, "x0": x0, "inputs": np.zeros((1, 4)), "duration_s": 1.0, "dt": 0.01})
    scalar = [run_model(**spec, output_rate_hz=100.0, kernels="generated") for spec in specs]
    bump = model.plant.wheels["bump_travel"]
    names = ("front", "rear_left", "rear_right")
    peaks = [[float(np.max(r.channels[f"{w}_travel_m"])) for w in names] for r in scalar]
    assert all(peak > limit for peak, limit in zip(peaks[1], bump, strict=True))  # every stop hit
    assert max(peaks[0]) < bump.min()  # the undisturbed lanes stay off them
    for b, s in zip(run_prepared(specs, lanes=4, kernels="generated"), scalar, strict=True):
        assert b.status == s.status
        np.testing.assert_array_equal(b.states, s.states)
        for name in LOADS:
            np.testing.assert_array_equal(b.channels[name], s.channels[name])
