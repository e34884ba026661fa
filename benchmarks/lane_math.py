"""Issue 25: the branch-free functions of trikedyn.model.lane_math over lanes against the C library's, one process.

Each timing fills an array of 64 arguments' values in a loop compiled as the lane kernels are (no fast-math,
``error_model="numpy"``): with the branch-free functions LLVM vectorises that loop, with the C library's it
cannot (a call per value). The arguments move by 1e-12 a pass, so the work can be neither dropped nor hoisted.
Figures: the best of ``REPEATS`` timings, nanoseconds per value.

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


@njit(inline="always", error_model="numpy")
def _curve_lanes(u):
    """The Magic Formula's normalised curve ``sin(C atan(u - E (u - atan u)))`` (C = 1.6, E = 0.3), branch-free."""
    return lane_math.sincos(1.6 * lane_math.arctan(u - 0.3 * (u - lane_math.arctan(u))))[0]


@njit(inline="always", error_model="numpy")
def _curve_library(u):
    """The same curve from the C library (``trikedyn.tyre.magic_formula.magic_formula_curve``)."""
    return math.sin(1.6 * math.atan(u - 0.3 * (u - math.atan(u))))


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


def bench_lane_math() -> dict:
    """``make bench``'s entry: nanoseconds per value of each function, branch-free and the C library's."""
    rng = np.random.default_rng(0)
    out = {}
    for name, (lane, library, half) in FUNCTIONS.items():
        xs = rng.uniform(-half, half, 64)
        out[name] = {"lanes_ns": _ns_per_value(lane, xs), "library_ns": _ns_per_value(library, xs)}
    return {"lane_math_ns_per_value": out}


def main() -> int:
    """Print the figures."""
    for name, v in bench_lane_math()["lane_math_ns_per_value"].items():
        print(f"{name}: branch-free over lanes {v['lanes_ns']:.2f} ns a value, the C library {v['library_ns']:.2f} ns")
    return 0


if __name__ == "__main__":
    sys.exit(main())
