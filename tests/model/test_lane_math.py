"""trikedyn.model.lane_math: the branch-free sine and cosine against the C library's."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numba import njit

from trikedyn.model.lane_math import sincos


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
