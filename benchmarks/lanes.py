"""Issue 25: the lane kernels (trikedyn.model.lanes) against the scalar generated kernels, one process.

The same 64 random states as ``benchmarks/codegen.py`` (its ``states``) are packed ``B`` to a buffer (64 / B
buffers); each timing loops, inside compiled code, over the buffers, evaluates every lane's ``du/dt`` (or its
kinematics) and adds every output entry to an accumulator that is returned, so LLVM can neither drop nor hoist
the work. The scalar side is ``codegen.generated_loop`` (and its kinematics twin here) over the same states; the
accumulators are checked against each other. Figures: the median of ``REPEATS`` timings, microseconds per
lane-evaluation. The kinematics' sums take the body velocities only (see ``kinematics_loop``).

usage: python benchmarks/lanes.py [--json]
"""

from __future__ import annotations

import json
import os
import sys

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from codegen import GRAVITY, REPEATS, generated_loop, median_time, states  # noqa: E402
from numba import njit  # noqa: E402

from trikedyn.model.codegen import TreeStructure, kernels_for_tree  # noqa: E402
from trikedyn.model.lanes import LaneLayout, lane_kernels  # noqa: E402
from trikedyn.model.topology import build_tree  # noqa: E402
from trikedyn.params import load_vehicle  # noqa: E402

LANES = (4, 8, 16)


@njit(cache=True)
def lanes_loop(kernel, bufs, first, count, reps):
    """Sum of rows ``first`` to ``first + count`` of every buffer after ``kernel(buf)``, ``reps`` passes."""
    acc = 0.0
    for _ in range(reps):
        for s in range(bufs.shape[0]):
            kernel(bufs[s])
            for i in range(first, first + count):
                acc += bufs[s, i]
    return acc


@njit(cache=True)
def factor_loop(kernel, qs, us, taus, fexts, gravity, tree_e, tree_r, mass, h, ibar, reps):
    """As ``codegen.generated_loop`` on a scalar ``forward_dynamics_factor_into`` (the factor kept too)."""
    n = qs.shape[1]
    out = np.empty(n)
    factor = np.zeros((n, n))
    acc = 0.0
    for _ in range(reps):
        for s in range(qs.shape[0]):
            kernel(qs[s], us[s], taus[s], fexts[s], gravity, tree_e, tree_r, mass, h, ibar, out, factor)
            for i in range(n):
                acc += out[i]
    return acc


@njit(cache=True)
def kinematics_loop(kernel, qs, us, tree_e, tree_r, reps):
    """Sum of the body velocities ``v`` of a scalar ``kinematics_into`` over the states, ``reps`` passes (the
    other outputs are stored too; summing only ``v`` keeps the accumulation from outweighing the kernel)."""
    nb = tree_e.shape[0]
    e, r, ew, pw, v = (np.empty((nb, 3, 3)), np.empty((nb, 3)), np.empty((nb, 3, 3)), np.empty((nb, 3)),
                       np.empty((nb, 6)))
    acc = 0.0
    for _ in range(reps):
        for s in range(qs.shape[0]):
            kernel(qs[s], us[s], tree_e, tree_r, e, r, ew, pw, v)
            acc += v.sum()
    return acc


def packed(tree, layout: LaneLayout, qs, us, taus, fexts) -> np.ndarray:
    """The states ``layout.lanes`` to a buffer: an array (buffers, buffer size)."""
    count = qs.shape[0] // layout.lanes
    bufs = np.stack([layout.buffer() for _ in range(count)])
    for s in range(count):
        for lane in range(layout.lanes):
            k = s * layout.lanes + lane
            for name, value in (("q", qs[k]), ("u", us[k]), ("tau", taus[k]), ("fext", fexts[k]), ("gravity", GRAVITY),
                                ("tree_e", tree.tree_e), ("tree_r", tree.tree_r), ("mass", tree.mass), ("h", tree.h),
                                ("ibar", tree.ibar)):
                layout.view(bufs[s], name)[..., lane] = value
    return bufs


def measure(preset: str = "reference-etrike", reps: int = 3000, lanes=LANES) -> dict:
    """Microseconds per lane-evaluation of the lane kernels for each ``B`` of :data:`LANES`, and the scalar ones.

    Parameters
    ----------
    preset : str
        The vehicle preset.
    reps : int
        Passes over the 64 states per timing.
    lanes : sequence of int
        The lane counts ``B`` (each divides 64).

    Returns
    -------
    dict
        ``scalar_dynamics_us``, ``scalar_kinematics_us`` and per ``B``: ``dynamics_us``, ``kinematics_us``,
        the speed-ups and the accumulators' relative differences.
    """
    tree = build_tree(load_vehicle(preset).params)
    structure = TreeStructure.of(tree.parent, tree.jtype, tree.jaxis, tree.tree_e, tree.tree_r, tree.h, tree.ibar)
    scalar = kernels_for_tree(tree)
    qs, us, taus, fexts = states(tree, np.random.default_rng(25))
    evaluations = reps * qs.shape[0]
    values = (tree.tree_e, tree.tree_r, tree.mass, tree.h, tree.ibar)
    t_fd, acc_fd = median_time(lambda: generated_loop(scalar.forward_dynamics_into, qs, us, taus, fexts, GRAVITY,
                                                      *values, reps))
    t_kin, acc_kin = median_time(lambda: kinematics_loop(scalar.kinematics_into, qs, us, tree.tree_e, tree.tree_r, reps))
    t_fac, _ = median_time(lambda: factor_loop(scalar.forward_dynamics_factor_into, qs, us, taus, fexts, GRAVITY, *values,
                                               reps))
    out = {"preset": preset, "dof": tree.n_dof, "evaluations": evaluations, "repeats": REPEATS,
           "scalar_dynamics_us": t_fd / evaluations * 1e6, "scalar_kinematics_us": t_kin / evaluations * 1e6,
           "scalar_factor_us": t_fac / evaluations * 1e6, "lanes": {}}
    for b in lanes:
        layout = LaneLayout(tree.n_bodies, b)
        module = lane_kernels(structure, b)
        bufs = packed(tree, layout, qs, us, taus, fexts)
        udot = layout.start("udot") * b, tree.n_dof * b
        kin = layout.start("v") * b, tree.n_bodies * 6 * b
        t_l, acc_l = median_time(lambda m=module, x=bufs, w=udot: lanes_loop(m.forward_dynamics_lanes, x, *w, reps))
        t_k, acc_k = median_time(lambda m=module, x=bufs, w=kin: lanes_loop(m.kinematics_lanes, x, *w, reps))
        t_f, acc_f = median_time(lambda m=module, x=bufs, w=udot: lanes_loop(m.forward_dynamics_factor_lanes, x, *w,
                                                                             reps))
        if acc_f != acc_l:
            raise AssertionError(f"the lane forward dynamics with and without the factor disagree ({preset}, B={b})")
        agree_fd, agree_kin = abs(acc_l - acc_fd) / abs(acc_fd), abs(acc_k - acc_kin) / abs(acc_kin)
        if not (agree_fd < 1e-9 and agree_kin < 1e-9):
            raise AssertionError(f"lane and scalar kernels disagree ({preset}, B={b}): {agree_fd}, {agree_kin}")
        out["lanes"][b] = {"dynamics_us": t_l / evaluations * 1e6, "kinematics_us": t_k / evaluations * 1e6,
                           "factor_us": t_f / evaluations * 1e6, "factor_speedup": t_fac / t_f,
                           "dynamics_speedup": t_fd / t_l, "kinematics_speedup": t_kin / t_k,
                           "dynamics_rel_diff": agree_fd, "kinematics_rel_diff": agree_kin}
    return out


def bench_lane_kernels() -> dict:
    """``make bench``'s entry: :func:`measure` on reference-etrike.

    Returns
    -------
    dict
        ``{"lane_kernels": measure()}``.
    """
    return {"lane_kernels": measure("reference-etrike")}


def main() -> int:
    """Print the figures of both presets (``--json``: as one JSON object)."""
    results = {p: measure(p) for p in ("reference-etrike", "reference-tadpole")}
    if "--json" in sys.argv:
        print(json.dumps(results, indent=1))
        return 0
    for preset, r in results.items():
        print(f"{preset} ({r['dof']} DOF), per evaluation, median of {r['repeats']} timings of {r['evaluations']}: "
              f"scalar generated forward dynamics {r['scalar_dynamics_us']:.3f} us, kinematics "
              f"{r['scalar_kinematics_us']:.3f} us, with the factor kept {r['scalar_factor_us']:.3f} us")
        for b, lane in r["lanes"].items():
            print(f"  B={b:2d} lanes: forward dynamics {lane['dynamics_us']:.4f} us per lane ({lane['dynamics_speedup']:.1f}x), "
                  f"kinematics {lane['kinematics_us']:.4f} us ({lane['kinematics_speedup']:.1f}x), with the factor "
                  f"{lane['factor_us']:.4f} us ({lane['factor_speedup']:.1f}x); sums agree to "
                  f"{lane['dynamics_rel_diff']:.1e} / {lane['kinematics_rel_diff']:.1e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
