"""Spatial (6D) vector algebra for rigid-body trees, compiled with numba (Featherstone 2008, ch. 2).

Conventions (Featherstone's):

* A motion vector is ``(omega, v)``: angular velocity, then the linear velocity of the point at the
  frame's origin. A force vector is ``(n, f)``: moment about the origin, then force.
* A coordinate transform from frame A to frame B is a pair ``(E, r)``: ``E`` rotates A coordinates
  into B coordinates (``x_B = E x_A``), ``r`` is B's origin in A coordinates. It maps motion vectors
  ``X m = (E omega, E (v - r x omega))`` and force vectors ``X* f = (E (n - r x f), E f)``.
* A rigid-body inertia about a frame's origin is kept as ``(m, h, Ibar)``: mass, first moment
  ``h = m c`` (``c`` the centre of mass) and the rotational inertia about the origin
  ``Ibar = I_c + m [c]x [c]x^T``. The 6x6 matrix is ``[[Ibar, [h]x], [[h]x^T, m 1]]``.

Every function works on small numpy arrays in place where it can; all are ``njit(cache=True)``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "cross",
    "rot_axis",
    "compose",
    "xform_motion",
    "xform_force_inv",
    "motion_cross_motion",
    "motion_cross_force",
    "inertia_times_motion",
    "inertia_to_parent",
    "inertia_matrix6",
    "euler_zyx_to_matrix",
]


@njit(cache=True)
def cross(a, b):
    """Cross product of two 3-vectors."""
    out = np.empty(3)
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
    return out


@njit(cache=True)
def rot_axis(axis, angle):
    """Rotation matrix (Rodrigues) that turns vectors by ``angle`` [rad] about the unit ``axis``."""
    c = np.cos(angle)
    s = np.sin(angle)
    t = 1.0 - c
    x, y, z = axis[0], axis[1], axis[2]
    out = np.empty((3, 3))
    out[0, 0] = t * x * x + c
    out[0, 1] = t * x * y - s * z
    out[0, 2] = t * x * z + s * y
    out[1, 0] = t * x * y + s * z
    out[1, 1] = t * y * y + c
    out[1, 2] = t * y * z - s * x
    out[2, 0] = t * x * z - s * y
    out[2, 1] = t * y * z + s * x
    out[2, 2] = t * z * z + c
    return out


@njit(cache=True)
def euler_zyx_to_matrix(roll, pitch, yaw):
    """Rotation matrix body -> world for ISO 8855 yaw-pitch-roll (Z, then Y, then X) angles [rad]."""
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp = np.cos(pitch), np.sin(pitch)
    cy, sy = np.cos(yaw), np.sin(yaw)
    out = np.empty((3, 3))
    out[0, 0] = cy * cp
    out[0, 1] = cy * sp * sr - sy * cr
    out[0, 2] = cy * sp * cr + sy * sr
    out[1, 0] = sy * cp
    out[1, 1] = sy * sp * sr + cy * cr
    out[1, 2] = sy * sp * cr - cy * sr
    out[2, 0] = -sp
    out[2, 1] = cp * sr
    out[2, 2] = cp * cr
    return out


@njit(cache=True)
def compose(e2, r2, e1, r1):
    """Transform ``X2 X1`` (first X1: A->B, then X2: B->C) as ``(E, r)`` of A->C."""
    return e2 @ e1, r1 + e1.T @ r2


@njit(cache=True)
def xform_motion(e, r, m, out):
    """``out = X m`` for a motion vector ``m`` (6,), transform ``(e, r)``."""
    w = m[:3]
    v = m[3:] - cross(r, w)
    out[:3] = e @ w
    out[3:] = e @ v


@njit(cache=True)
def xform_force_inv(e, r, f, out):
    """``out = X^T f``: a force in the child frame B expressed in the parent frame A."""
    n = e.T @ f[:3]
    ff = e.T @ f[3:]
    out[:3] = n + cross(r, ff)
    out[3:] = ff


@njit(cache=True)
def motion_cross_motion(v, m, out):
    """``out = v x m`` (spatial cross product of motion vectors)."""
    w, vl = v[:3], v[3:]
    out[:3] = cross(w, m[:3])
    out[3:] = cross(w, m[3:]) + cross(vl, m[:3])


@njit(cache=True)
def motion_cross_force(v, f, out):
    """``out = v x* f`` (spatial cross product of a motion and a force vector)."""
    w, vl = v[:3], v[3:]
    out[:3] = cross(w, f[:3]) + cross(vl, f[3:])
    out[3:] = cross(w, f[3:])


@njit(cache=True)
def inertia_times_motion(m, h, ibar, a, out):
    """``out = I a`` for the inertia ``(m, h, Ibar)`` and a motion vector ``a``."""
    w, v = a[:3], a[3:]
    out[:3] = ibar @ w + cross(h, v)
    out[3:] = m * v - cross(h, w)


@njit(cache=True)
def inertia_to_parent(e, r, m, h, ibar):
    """``X^T I X``: an inertia about the child frame's origin, expressed about the parent's.

    Returns ``(h_parent, ibar_parent)``; the mass is unchanged. With ``y = E^T h``:
    ``h' = y + m r`` and ``Ibar' = E^T Ibar E - [r]x [y]x - [y + m r]x [r]x`` (Featherstone, Table 2.5).
    """
    y = e.T @ h
    hp = y + m * r
    ib = e.T @ ibar @ e
    # - [r]x [y]x - [hp]x [r]x, written out: [a]x [b]x = b a^T - (a.b) 1
    ry = r[0] * y[0] + r[1] * y[1] + r[2] * y[2]
    hr = hp[0] * r[0] + hp[1] * r[1] + hp[2] * r[2]
    for i in range(3):
        for j in range(3):
            ib[i, j] -= y[i] * r[j] + r[i] * hp[j]
        ib[i, i] += ry + hr
    return hp, ib


@njit(cache=True)
def inertia_matrix6(m, h, ibar):
    """The 6x6 spatial inertia matrix of ``(m, h, Ibar)`` (for tests and linear algebra)."""
    out = np.zeros((6, 6))
    hx = np.array([[0.0, -h[2], h[1]], [h[2], 0.0, -h[0]], [-h[1], h[0], 0.0]])
    out[:3, :3] = ibar
    out[:3, 3:] = hx
    out[3:, :3] = hx.T
    for i in range(3):
        out[3 + i, 3 + i] = m
    return out
