"""Issue 25: forward dynamics of the generic kernels against the kernels generated for the tree, one process.

Each timing loops, inside compiled code, over 64 distinct random states, evaluates ``du/dt`` into a buffer
and adds every entry of it to an accumulator that is returned, so LLVM can neither drop nor hoist the work;
the two accumulators are checked against each other. Both sides allocate nothing per evaluation (the generic
side as the right-hand side runs it: transforms, RNEA, CRBA, Cholesky on a preallocated workspace). The
figure is the median of ``REPEATS`` timings, in microseconds per evaluation.

usage: python benchmarks/codegen.py [--json] [--dlc]
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

from trikedyn.model import cholesky, dynamics, rhs  # noqa: E402
from trikedyn.model.codegen import kernels_for_tree  # noqa: E402
from trikedyn.model.packing import WHEEL_OUT  # noqa: E402
from trikedyn.model.statics import rolling_state, static_equilibrium  # noqa: E402
from trikedyn.model.topology import build_tree  # noqa: E402
from trikedyn.model.vehicle import build_model  # noqa: E402
from trikedyn.params import load_vehicle  # noqa: E402

REPEATS = 7
STATES = 64
GRAVITY = np.array([0.0, 0.0, -9.81])


@njit(cache=True)
def generic_loop(qs, us, taus, fexts, gravity, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar, reps):
    """Sum of every ``du/dt`` entry over ``reps`` passes of the states, by the generic kernels."""
    ws = dynamics.workspace(parent)
    n = qs.shape[1]
    rhs = np.empty(n)
    out = np.empty(n)
    acc = 0.0
    for _ in range(reps):
        for s in range(qs.shape[0]):
            dynamics.joint_transforms_into(qs[s], parent, jtype, jaxis, tree_e, tree_r, ws.e, ws.r, ws.t33)
            dynamics.rnea_into(ws.e, ws.r, us[s], ws.zero, fexts[s], gravity, parent, jtype, jaxis, mass, h, ibar,
                               ws, ws.bias)
            dynamics.crba_into(ws.e, ws.r, parent, jtype, jaxis, mass, h, ibar, ws)
            for i in range(n):
                rhs[i] = taus[s, i] - ws.bias[i]
            cholesky.cholesky_solve_into(ws.hmat, rhs, ws.low, ws.vec, out)
            for i in range(n):
                acc += out[i]
    return acc


@njit(cache=True)
def generated_loop(kernel, qs, us, taus, fexts, gravity, tree_e, tree_r, mass, h, ibar, reps):
    """The same sum by a generated ``forward_dynamics_into`` (passed in as ``kernel``)."""
    n = qs.shape[1]
    out = np.empty(n)
    acc = 0.0
    for _ in range(reps):
        for s in range(qs.shape[0]):
            kernel(qs[s], us[s], taus[s], fexts[s], gravity, tree_e, tree_r, mass, h, ibar, out)
            for i in range(n):
                acc += out[i]
    return acc


@njit(cache=True)
def rhs_loop(xs, u, p, reps):
    """Sum of every ``dx/dt`` entry over ``reps`` passes of the states ``xs``: the whole generic right-hand side."""
    ws = rhs.workspace(p.parent)
    wout = np.zeros(p.wheels.shape[0], WHEEL_OUT)
    out = np.empty(xs.shape[1])
    acc = 0.0
    for _ in range(reps):
        for s in range(xs.shape[0]):
            rhs.evaluate_into(0.0, xs[s], u, p, wout, ws, out)
            for i in range(out.shape[0]):
                acc += out[i]
    return acc


def states(tree, rng, count=STATES):
    """``count`` random states (q, u, tau, fext) of ``tree``, as stacked arrays."""
    n, nb = tree.n_dof, tree.n_bodies
    qs = rng.uniform(-0.3, 0.3, (count, n))
    us = rng.normal(0.0, 2.0, (count, n))
    taus = rng.normal(0.0, 200.0, (count, n))
    fexts = rng.normal(0.0, 500.0, (count, nb, 6))
    for b in range(1, nb):
        if tree.jtype[b] == dynamics.JOINT_PRISMATIC:
            qs[:, 5 + b] *= 0.1
    return qs, us, taus, fexts


def median_time(func, repeats=REPEATS):
    """Median wall time [s] of ``func()`` over ``repeats`` calls after one warm-up, and its last value."""
    value = func()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        value = func()
        times.append(time.perf_counter() - start)
    return statistics.median(times), value


def measure(preset: str = "reference-etrike", reps: int = 3000) -> dict:
    """Microseconds per forward-dynamics evaluation, generic and generated, on ``preset``'s tree.

    Parameters
    ----------
    preset : str
        The vehicle preset.
    reps : int
        Passes over the 64 states per timing.

    Returns
    -------
    dict
        ``generic_us``, ``generated_us``, ``speedup``, the two accumulators' relative difference, and the
        whole generic right-hand side per evaluation with the dynamics' share of it and the time projected
        with the generated kernel in its place.
    """
    tree = build_tree(load_vehicle(preset).params)
    kernel = kernels_for_tree(tree).forward_dynamics_into
    qs, us, taus, fexts = states(tree, np.random.default_rng(25))
    values = (tree.tree_e, tree.tree_r, tree.mass, tree.h, tree.ibar)
    evaluations = reps * qs.shape[0]
    t_gen, acc_gen = median_time(lambda: generic_loop(qs, us, taus, fexts, GRAVITY, *tree.arrays(), reps))
    t_cg, acc_cg = median_time(lambda: generated_loop(kernel, qs, us, taus, fexts, GRAVITY, *values, reps))
    # the whole right-hand side (tyres, springs, drive, dynamics) at 64 states near rolling at 30 km/h
    model = build_model(load_vehicle(preset))
    x0 = rolling_state(model, static_equilibrium(model), 30 / 3.6)
    rng = np.random.default_rng(26)
    xs = x0 + rng.normal(0.0, 1e-3, (qs.shape[0], x0.shape[0])) * np.maximum(np.abs(x0), 1.0)
    t_rhs, acc_rhs = median_time(lambda: rhs_loop(xs, np.array([0.01, 20.0, 0.0]), model.plant, reps))
    if not np.isfinite(acc_rhs):
        raise AssertionError("the right-hand side gave a non-finite sum")
    agreement = abs(acc_cg - acc_gen) / abs(acc_gen)
    if not agreement < 1e-9:
        raise AssertionError(f"generated and generic kernels disagree: {acc_cg} vs {acc_gen}")
    return {"preset": preset, "dof": tree.n_dof, "evaluations": evaluations, "repeats": REPEATS,
            "generic_us": t_gen / evaluations * 1e6, "generated_us": t_cg / evaluations * 1e6,
            "speedup": t_gen / t_cg, "accumulator_rel_diff": agreement,
            "rhs_generic_us": t_rhs / evaluations * 1e6, "dynamics_share_of_rhs": t_gen / t_rhs,
            "rhs_projected_with_generated_us": (t_rhs - t_gen + t_cg) / evaluations * 1e6}


def measure_dlc(preset: str = "reference-etrike", speed_kmh: float = 30.0, duration_s: float = 10.0,
                repeats: int = REPEATS) -> dict:
    """A closed-loop double lane change (the driver in the loop), generic and generated loop, one process.

    The run is :func:`trikedyn.simulate.closed_loop.drive` on ISO 3888-1's path as in ``benchmarks/run.py``
    (end to end: statics, the compiled loop, the channels); the compiled loop's own time is taken inside the
    same calls. Best of ``repeats`` after a warm-up, the two kernels alternating; the states of the two runs
    are compared.

    Returns
    -------
    dict
        Per kernel ``wall_s``, ``real_time_factor``, ``loop_wall_s``, ``loop_real_time_factor``; the largest
        state difference scaled by each state's largest magnitude (at least 1).
    """
    from trikedyn.manoeuvres.paths import double_lane_change
    from trikedyn.simulate import specialised as run_module  # model_time_loop looks the loop up there
    from trikedyn.simulate.closed_loop import drive

    pset = load_vehicle(preset)
    model = build_model(pset)
    path = double_lane_change(pset.params.body.overall_width_m)
    chosen = run_module.time_loop
    loop_times = []

    def timed(plant, kernels=None):
        loop = chosen(plant, kernels)

        def call(*args):
            start = time.perf_counter()
            out = loop(*args)
            loop_times.append(time.perf_counter() - start)
            return out
        return call

    best, results = {}, {}
    run_module.time_loop = timed
    try:
        for kernels in ("generic", "generated"):
            os.environ["TRIKEDYN_KERNELS"] = kernels
            results[kernels] = drive(model, path, speed_kmh, duration_s=duration_s)  # warm-up, compiles
            best[kernels] = [np.inf, np.inf]
        for _ in range(repeats):
            for kernels in ("generic", "generated"):
                os.environ["TRIKEDYN_KERNELS"] = kernels
                start = time.perf_counter()
                drive(model, path, speed_kmh, duration_s=duration_s)
                wall = time.perf_counter() - start
                best[kernels] = [min(best[kernels][0], wall), min(best[kernels][1], loop_times[-1])]
    finally:
        run_module.time_loop = chosen
        os.environ.pop("TRIKEDYN_KERNELS", None)
    a, b = results["generic"].states, results["generated"].states
    out = {"preset": preset, "speed_kmh": speed_kmh, "simulated_s": duration_s, "repeats": repeats,
           "state_diff_scaled": float(np.max(np.abs(a - b) / np.maximum(1.0, np.abs(a).max(axis=0))))}
    for kernels, (wall, loop) in best.items():
        out[kernels] = {"wall_s": wall, "real_time_factor": duration_s / wall, "loop_wall_s": loop,
                        "loop_real_time_factor": duration_s / loop}
    out["speedup_end_to_end"] = best["generic"][0] / best["generated"][0]
    out["speedup_loop"] = best["generic"][1] / best["generated"][1]
    return out


def bench_generated_kernels() -> dict:
    """``make bench``'s entry: :func:`measure` and :func:`measure_dlc` on reference-etrike.

    Returns
    -------
    dict
        ``{"forward_dynamics_generated_vs_generic": measure(), "dlc_10s_generated_vs_generic": measure_dlc()}``.
    """
    return {"forward_dynamics_generated_vs_generic": measure("reference-etrike"),
            "dlc_10s_generated_vs_generic": measure_dlc("reference-etrike")}


def main() -> int:
    """Print the figures of both presets (``--json``: as one JSON object; ``--dlc``: the lane change only)."""
    presets = ("reference-etrike", "reference-tadpole")
    dlc = {p: measure_dlc(p) for p in presets}
    results = {} if "--dlc" in sys.argv else {p: measure(p) for p in presets}
    if "--json" in sys.argv:
        print(json.dumps({"kernels": results, "dlc": dlc}, indent=1))
        return 0
    for preset, r in dlc.items():
        g, c = r["generic"], r["generated"]
        print(f"{preset}: closed-loop {r['simulated_s']:.0f} s DLC at {r['speed_kmh']:.0f} km/h, end to end generic "
              f"{g['wall_s'] * 1e3:.1f} ms ({g['real_time_factor']:.0f}x real time), generated {c['wall_s'] * 1e3:.1f} ms "
              f"({c['real_time_factor']:.0f}x); the loop alone {g['loop_wall_s'] * 1e3:.1f} vs "
              f"{c['loop_wall_s'] * 1e3:.1f} ms ({g['loop_real_time_factor']:.0f}x vs {c['loop_real_time_factor']:.0f}x, "
              f"{r['speedup_loop']:.2f}x); states agree to {r['state_diff_scaled']:.1e} (best of {r['repeats']})")
    for preset, r in results.items():
        print(f"{preset} ({r['dof']} DOF): forward dynamics generic {r['generic_us']:.3f} us, generated "
              f"{r['generated_us']:.3f} us per evaluation: {r['speedup']:.1f}x (median of {r['repeats']}, "
              f"{r['evaluations']} evaluations each; accumulators agree to {r['accumulator_rel_diff']:.1e})")
        print(f"  whole right-hand side (generic) {r['rhs_generic_us']:.3f} us, of which dynamics "
              f"{100 * r['dynamics_share_of_rhs']:.0f} %; projected with the generated kernel "
              f"{r['rhs_projected_with_generated_us']:.3f} us (not wired in: a projection, optimistic as the right-hand "
              "side would still compute its transforms for the tyres)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
