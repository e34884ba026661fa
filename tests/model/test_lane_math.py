"""trikedyn.model.lane_math: the branch-free functions against the C library's, and a loop over lanes that calls
them vectorised (their reason to be)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from numba import njit

from trikedyn.model.lane_math import arcsin, arctan, sincos, tan, tanh


@njit(cache=False)
def _worst(xs):
    """Largest absolute differences of ``sincos`` from ``math.sin`` and ``math.cos`` over ``xs``."""
    worst_sin = worst_cos = 0.0
    for x in xs:
        s, c = sincos(x)
        worst_sin = max(worst_sin, abs(s - math.sin(x)))
        worst_cos = max(worst_cos, abs(c - math.cos(x)))
    return worst_sin, worst_cos


@pytest.mark.parametrize("largest", [4.0, 1e4, 1e6])
def test_within_a_bit_of_the_c_library(largest):
    """Within 2.3e-16 of libm up to |x| = 1e6 rad (the docstring's figure; a wheel's spin angle after an
    hour at 100 km/h is 1e5 rad)."""
    xs = np.random.default_rng(int(largest)).uniform(-largest, largest, 200_000)
    assert max(_worst(xs)) <= 2.3e-16


def test_quadrant_boundaries_and_special_values():
    edges = np.array([k * math.pi / 4 for k in range(-16, 17)] + [1e-300, 5e-324, -1e-300, 0.5, -0.5, 2.0, -2.0])
    assert max(_worst(edges)) <= 2.3e-16
    assert sincos(0.0) == (0.0, 1.0)
    assert all(math.isnan(v) for v in sincos(math.nan))
    assert all(math.isnan(v) for v in sincos(math.inf))


FUNCTIONS = {"arctan": (arctan, math.atan), "arcsin": (arcsin, math.asin), "tanh": (tanh, math.tanh), "tan": (tan, math.tan)}
ULPS = {"arctan": 1.0, "arcsin": 1.0, "tanh": 2.0, "tan": 3.0}  # the module docstring's figures


def _ulp_checker(lane, library):
    """A compiled ``worst(xs)``: the largest difference of ``lane`` from ``library`` over ``xs``, in units in the last
    place of the library's value (of the smallest subnormal at zero)."""

    @njit(cache=False, error_model="numpy")
    def worst(xs):
        most = 0.0
        for x in xs:
            a, b = lane(x), library(x)
            if a != b:
                step = np.nextafter(abs(b), np.inf) - abs(b) if b != 0.0 else 5e-324
                most = max(most, abs(a - b) / step)
        return most

    return worst


def _arguments(name, rng):
    """10^6 random arguments over each function's working range, and the edges of its reduced ranges."""
    n = 1_000_000
    if name == "arctan":
        sets = [rng.uniform(-1, 1, n), rng.uniform(-100, 100, n),
                np.exp(rng.uniform(-40, 40, n)) * rng.choice([-1.0, 1.0], n),
                [0.66, np.nextafter(0.66, 1), 2.414213562373095, np.nextafter(2.414213562373095, 3), 1.0, 1e-300,
                 5e-324, 1e300]]
    elif name == "arcsin":
        sets = [rng.uniform(-1, 1, n), 1.0 - np.exp(rng.uniform(-40, 0, n)),
                [0.625, np.nextafter(0.625, 1), 1.0, -1.0, 1e-300, 0.5]]
    elif name == "tanh":
        sets = [rng.uniform(-1, 1, n), rng.uniform(-25, 25, n), np.exp(rng.uniform(-40, 5, n)),
                [0.625, np.nextafter(0.625, 0), 20.0, np.nextafter(20.0, 0), 21.0, 44.1, 1e-300]]
    else:
        sets = [rng.uniform(-1.5, 1.5, n), rng.uniform(-0.3, 0.3, n)]
    return [np.asarray(s, dtype=float) for s in sets]


@pytest.mark.parametrize("name", list(FUNCTIONS))
def test_each_function_within_its_ulps_of_the_c_library(name):
    lane, library = FUNCTIONS[name]
    worst = _ulp_checker(lane, library)
    for xs in _arguments(name, np.random.default_rng(7)):
        assert worst(xs) <= ULPS[name]
        assert worst(-xs) <= ULPS[name]


@pytest.mark.parametrize("name", ["arctan", "arcsin", "tanh"])
def test_odd_to_the_last_bit_with_signed_zeros(name):
    lane, _ = FUNCTIONS[name]
    xs = np.random.default_rng(3).uniform(-1, 1, 1000)
    assert all(lane(-x) == -lane(x) for x in xs)
    assert math.copysign(1.0, lane(-0.0)) == -1.0 and math.copysign(1.0, lane(0.0)) == 1.0


def test_special_values():
    assert arctan(math.inf) == math.pi / 2 and arctan(-math.inf) == -math.pi / 2
    assert tanh(math.inf) == 1.0 and tanh(-math.inf) == -1.0 and tanh(30.0) == 1.0
    assert arcsin(1.0) == math.pi / 2 and arcsin(-1.0) == -math.pi / 2
    assert all(math.isnan(v) for v in (arctan(math.nan), tanh(math.nan), arcsin(math.nan), arcsin(1.5), tan(math.nan)))


def _vector_arithmetic(compiled) -> bool:
    """Whether the LLVM IR of ``compiled`` does arithmetic on vectors of doubles (loads and stores of vectors alone
    do not count: LLVM moves the values of a scalar loop that way too)."""
    ir = next(iter(compiled.inspect_llvm().values()))
    return re.search(r"\b(fadd|fsub|fmul|fdiv) <\d+ x double>", ir) is not None


@pytest.mark.parametrize("name", ["sincos", *FUNCTIONS])
def test_a_loop_over_lanes_that_calls_it_is_vectorised(name):
    """What the functions are for: LLVM vectorises a loop that calls them (a call into the C library, or a branch,
    keeps it scalar). Compiled as the lane kernels are (``error_model="numpy"``: a division needs no zero check)."""
    lane = sincos if name == "sincos" else FUNCTIONS[name][0]

    @njit(cache=False, error_model="numpy")
    def fill(xs, out):
        for i in range(xs.size):
            out[i] = lane(xs[i]) if name != "sincos" else lane(xs[i])[0]

    xs = np.linspace(-1.0, 1.0, 64)
    out = np.empty_like(xs)
    fill(xs, out)
    expected = np.sin(xs) if name == "sincos" else np.array([FUNCTIONS[name][1](x) for x in xs])
    np.testing.assert_allclose(out, expected, rtol=1e-15, atol=1e-16)
    assert _vector_arithmetic(fill), f"the loop over {name} was not vectorised"


def test_a_library_call_is_not_vectorised():
    """The test above can fail: the same loop over the C library's arctangent stays scalar."""

    @njit(cache=False, error_model="numpy")
    def fill(xs, out):
        for i in range(xs.size):
            out[i] = math.atan(xs[i])

    xs = np.linspace(-1.0, 1.0, 64)
    fill(xs, np.empty_like(xs))
    assert not _vector_arithmetic(fill)
