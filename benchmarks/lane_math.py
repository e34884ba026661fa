"""Issue 25: the branch-free functions of trikedyn.model.lane_math over lanes against the C library's, and the
similarity tyre over 8 lanes (trikedyn.tyre.lanes) against the scalar tyre function, one process.

Each timing of a function fills an array of 64 arguments' values in a loop compiled as the lane kernels are (no
fast-math, ``error_model="numpy"``): with the branch-free functions LLVM vectorises that loop, with the C library's it
cannot (a call per value). The arguments move by 1e-12 a pass, so the work can be neither dropped nor hoisted.
Figures: the best of ``REPEATS`` timings, nanoseconds per value. The tyre: 8 lanes of the reference trike's
tyres at spread slips and loads, each pass moving a slip by 1e-15; nanoseconds per lane (per call for the scalar
function, as the lockstep batch calls it today).

usage: python benchmarks/lane_math.py
"""

from __future__ import annotations

import math
import os
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

from trikedyn.model import lane_math  # noqa: E402
from trikedyn.tyre.interface import tyre_forces  # noqa: E402
from trikedyn.tyre.lanes import _curve as lanes_curve  # noqa: E402
from trikedyn.tyre.lanes import similarity_forces_lanes  # noqa: E402
from trikedyn.tyre.magic_formula import magic_formula_curve  # noqa: E402
from trikedyn.tyre.models import SIMILARITY  # noqa: E402


@njit(inline="always", error_model="numpy")
def _curve_lanes(u):
    """The Magic Formula's normalised curve ``sin(C atan(u - E (u - atan u)))`` (C = 1.6, E = 0.3), branch-free."""
    return lanes_curve(u, 1.6, 0.3)


@njit(inline="always", error_model="numpy")
def _curve_library(u):
    """The same curve from the C library (the scalar tyre's ``magic_formula_curve``)."""
    return magic_formula_curve(u, 1.6, 0.3)


REPEATS = 5
PASSES = 20_000
FUNCTIONS = {"atan": (lane_math.arctan, math.atan, 10.0), "asin": (lane_math.arcsin, math.asin, 0.9),
             "tanh": (lane_math.tanh, math.tanh, 3.0), "tan": (lane_math.tan, math.tan, 1.4),
             "magic_formula_curve": (_curve_lanes, _curve_library, 5.0)}
"""name -> (branch-free function, the C library's, half-width of the arguments' range)."""


def _filler(func):
    """A compiled ``fill(xs, out, passes)``: ``out[i] = func(xs[i] + pass * 1e-12)``, every pass."""

    @njit(error_model="numpy")
    def fill(xs, out, passes):
        for r in range(passes):
            for i in range(xs.size):
                out[i] = func(xs[i] + r * 1e-12)
        return out[0]

    return fill


def _ns_per_value(func, xs) -> float:
    """Best of ``REPEATS`` timings of ``PASSES`` passes over ``xs``, nanoseconds per value."""
    fill, out = _filler(func), np.empty_like(xs)
    fill(xs, out, 1)
    best = math.inf
    for _ in range(REPEATS):
        start = time.perf_counter()
        fill(xs, out, PASSES)
        best = min(best, time.perf_counter() - start)
    return best / (PASSES * xs.size) * 1e9


@njit(error_model="numpy")
def _tyre_lanes(coeffs, kappa, alpha, fz, spin, r_eff, passes):
    """``passes`` calls of the tyre over the lanes, a slip nudged each time; a sum of the outputs."""
    fx, fy, my = np.empty(kappa.size), np.empty(kappa.size), np.empty(kappa.size)
    w_low = np.ones(kappa.size)
    acc = 0.0
    for _ in range(passes):
        kappa[0] += 1e-15
        similarity_forces_lanes(coeffs, kappa, alpha, fz, spin, r_eff, w_low, fx, fy, my)
        acc += fx[0] + fy[-1] + my[1]
    return acc


@njit(error_model="numpy")
def _tyre_scalar(rows, kappa, alpha, fz, spin, r_eff, passes):
    """The same with the scalar tyre function, lane by lane."""
    acc = 0.0
    for _ in range(passes):
        kappa[0] += 1e-15
        for j in range(kappa.size):
            f = tyre_forces(SIMILARITY, rows[j], kappa[j], alpha[j], 0.0, fz[j], 10.0, 10.0, spin[j], r_eff[j], 1.0,
                            1.0)
            acc += f[0] + f[1] + f[4]
    return acc


def _tyre_ns_per_lane() -> dict:
    """Nanoseconds per lane of the similarity tyre over 8 lanes and of the scalar tyre function."""
    from trikedyn.model.vehicle import build_model
    from trikedyn.params import load_vehicle

    rng = np.random.default_rng(1)
    tyres = build_model(load_vehicle("reference-etrike")).plant.tyres
    rows = np.ascontiguousarray(tyres[np.arange(8) % tyres.shape[0]])
    lanes = (rng.normal(0, 0.05, 8), rng.normal(0, 0.05, 8), rng.uniform(500, 1500, 8), rng.uniform(20, 40, 8),
             rng.uniform(0.25, 0.3, 8))
    out = {}
    for name, func, coeffs in (("lanes_ns", _tyre_lanes, np.ascontiguousarray(rows.T)), ("scalar_ns", _tyre_scalar, rows)):
        func(coeffs, *(a.copy() for a in lanes), 1)
        best = math.inf
        for _ in range(REPEATS):
            args = [a.copy() for a in lanes]
            start = time.perf_counter()
            func(coeffs, *args, PASSES)
            best = min(best, time.perf_counter() - start)
        out[name] = best / (PASSES * 8) * 1e9
    return out


def bench_lane_math() -> dict:
    """``make bench``'s entry: nanoseconds per value of each function, branch-free and the C library's, and per lane
    of the similarity tyre over lanes and of the scalar tyre function."""
    rng = np.random.default_rng(0)
    out = {}
    for name, (lane, library, half) in FUNCTIONS.items():
        xs = rng.uniform(-half, half, 64)
        out[name] = {"lanes_ns": _ns_per_value(lane, xs), "library_ns": _ns_per_value(library, xs)}
    return {"lane_math_ns_per_value": out, "similarity_tyre_ns_per_lane": _tyre_ns_per_lane()}


def main() -> int:
    """Print the figures."""
    results = bench_lane_math()
    for name, v in results["lane_math_ns_per_value"].items():
        print(f"{name}: branch-free over lanes {v['lanes_ns']:.2f} ns a value, the C library {v['library_ns']:.2f} ns")
    tyre = results["similarity_tyre_ns_per_lane"]
    print(f"similarity tyre: over 8 lanes {tyre['lanes_ns']:.2f} ns a lane, the scalar function {tyre['scalar_ns']:.2f} ns")
    return 0


if __name__ == "__main__":
    sys.exit(main())
