"""The footprint-to-cone geometry of :func:`~trikedyn.manoeuvres.judging.cone_strikes` and
:func:`~trikedyn.manoeuvres.judging.cone_clearance`, compiled (imported lazily: loading the manoeuvres does not
load numba).

Per sample and cone, the same IEEE operations in the same order as the array expressions they replace
(``tests/manoeuvres/test_cones.py`` holds those as the reference), without their ``(samples, cones)``
temporaries: equal to the last bit. The cosine and sine of the yaw come in computed by numpy, whose
vectorised ``cos`` may round differently from the C library's.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit


@jit(inline="always")
def _in_vehicle_axes(cx, cy, x, y, c, s):
    """A cone centre ``(cx, cy)`` [m] in the axes of a vehicle at ``(x, y)`` [m] with heading cosine and sine
    ``c``, ``s``."""
    dx = cx - x
    dy = cy - y
    return c * dx + s * dy, -s * dx + c * dy


@jit(inline="always")
def _clip(value, lo, hi):
    """``numpy.clip`` of one float (NaN stays NaN)."""
    if value < lo:
        return lo
    if value > hi:
        return hi
    return value


@jit(inline="always")
def _outside(cx, cy, x, y, c, s, x_rear, x_front, half_width):
    """How far a cone centre ``(cx, cy)`` lies outside the footprint rectangle along each vehicle axis [m]
    (both 0 inside it), and the centre in vehicle axes [m]."""
    bx, by = _in_vehicle_axes(cx, cy, x, y, c, s)
    return bx - _clip(bx, x_rear, x_front), by - _clip(by, -half_width, half_width), bx, by


@jit
def first_contacts(x, y, c, s, cones, x_rear, x_front, half_width, radius):
    """Index of the first sample at which each cone's base circle overlaps the footprint rectangle (-1: never).

    Parameters
    ----------
    x, y : numpy.ndarray
        Position of the vehicle reference point at each sample [m].
    c, s : numpy.ndarray
        Cosine and sine of its yaw angle at each sample.
    cones : numpy.ndarray, shape (n, 2)
        Cone centres [m].
    x_rear, x_front, half_width : float
        The rectangle in vehicle axes [m].
    radius : float
        Cone base radius [m].

    Returns
    -------
    numpy.ndarray of int64, shape (n,)
        Sample index of the first contact, -1 for a cone never touched.
    """
    n = cones.shape[0]
    first = np.full(n, -1, dtype=np.int64)
    left = n
    r2 = radius * radius
    for k in range(x.size):
        if left == 0:
            break
        for j in range(n):
            if first[j] >= 0:
                continue
            ex, ey, _, _ = _outside(cones[j, 0], cones[j, 1], x[k], y[k], c[k], s[k], x_rear, x_front, half_width)
            if ex * ex + ey * ey <= r2:
                first[j] = k
                left -= 1
    return first


@jit
def nearest_clearance(x, y, c, s, cones, x_rear, x_front, half_width, radius):
    """Signed clearance [m] between the footprint rectangle and the nearest cone at each sample.

    Parameters
    ----------
    x, y : numpy.ndarray
        Position of the vehicle reference point at each sample [m].
    c, s : numpy.ndarray
        Cosine and sine of its yaw angle at each sample.
    cones : numpy.ndarray, shape (n, 2), n >= 1
        Cone centres [m].
    x_rear, x_front, half_width : float
        The rectangle in vehicle axes [m].
    radius : float
        Cone base radius [m].

    Returns
    -------
    numpy.ndarray
        Per sample, the smallest over the cones of the centre's distance to the rectangle (minus its depth
        inside it) less ``radius`` [m] (the inputs are finite: :func:`~trikedyn.manoeuvres.judging.cone_clearance`
        checks them).

    Notes
    -----
    ``hypot`` is taken only for the cones that can be the nearest: those whose squared distance (rounded) is
    within a factor ``1 + 2^-40`` of the smallest. Rounding moves a squared distance by a few units of 2^-53
    and ``hypot`` by under two, so a cone beyond that factor has a larger ``hypot`` than the nearest for
    certain; the minimum is the one over all cones, bit for bit. Below 1e-200 m^2 (where squares lose
    precision) every cone is taken.
    """
    n = cones.shape[0]
    out = np.empty(x.size)
    exs = np.empty(n)
    eys = np.empty(n)
    for k in range(x.size):
        inside = False
        low = np.inf
        for j in range(n):
            ex, ey, _, _ = _outside(cones[j, 0], cones[j, 1], x[k], y[k], c[k], s[k], x_rear, x_front, half_width)
            exs[j] = ex
            eys[j] = ey
            if ex == 0.0 and ey == 0.0:
                inside = True
            else:
                low = min(low, ex * ex + ey * ey)
        limit = -1.0 if inside else (low * (1.0 + 2.0**-40) if low > 1e-200 else np.inf)
        best = np.inf
        for j in range(n):
            ex = exs[j]
            ey = eys[j]
            if ex == 0.0 and ey == 0.0:
                bx, by = _in_vehicle_axes(cones[j, 0], cones[j, 1], x[k], y[k], c[k], s[k])
                signed = -min(min(bx - x_rear, x_front - bx), min(by + half_width, half_width - by))
            elif ex * ex + ey * ey <= limit:
                signed = math.hypot(ex, ey)
            else:
                continue
            if signed < best:
                best = signed
        out[k] = best - radius
    return out
