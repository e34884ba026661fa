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

The hot-path functions write into output arrays and use no temporaries and no BLAS calls (numba calls
BLAS for ``@`` on small arrays, which costs far more than the arithmetic): the time loop allocates
nothing per body. All are ``njit(cache=True)``.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit

__all__ = [
    "cross_into",
    "euler_zyx_into",
    "euler_zyx_to_matrix",
    "inertia_times_motion",
    "inertia_to_parent",
    "inertia_translate_to_parent",
    "motion_cross_force",
    "motion_cross_motion",
    "rot_axis_into",
    "xform_force_inv",
    "xform_motion",
]


@jit(inline="always")
def cross_into(a, b, out):
    """``out = a x b`` (``out`` must not alias ``a`` or ``b``).

    Parameters
    ----------
    a, b : numpy.ndarray, shape (3,)
        The vectors (any unit; ``out`` carries the product of theirs).
    out : numpy.ndarray, shape (3,)
        Written with the cross product.
    """
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@jit(inline="always")
def rot_axis_into(axis, angle, out):
    """Rotation matrix (Rodrigues) turning vectors by ``angle`` [rad] about the unit ``axis``, into ``out``.

    Parameters
    ----------
    axis : numpy.ndarray, shape (3,)
        Unit rotation axis, dimensionless.
    angle : float
        Angle [rad].
    out : numpy.ndarray, shape (3, 3)
        Written with the rotation matrix, dimensionless.
    """
    c = np.cos(angle)
    s = np.sin(angle)
    t = 1.0 - c
    x, y, z = axis[0], axis[1], axis[2]
    out[0, 0] = t * x * x + c
    out[0, 1] = t * x * y - s * z
    out[0, 2] = t * x * z + s * y
    out[1, 0] = t * x * y + s * z
    out[1, 1] = t * y * y + c
    out[1, 2] = t * y * z - s * x
    out[2, 0] = t * x * z - s * y
    out[2, 1] = t * y * z + s * x
    out[2, 2] = t * z * z + c


@jit(inline="always")
def euler_zyx_to_matrix(roll, pitch, yaw):
    """Rotation matrix body -> world for ISO 8855 yaw-pitch-roll (Z, then Y, then X) angles [rad].

    Parameters
    ----------
    roll, pitch, yaw : float
        ISO 8855 angles about x, y and z [rad].

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        ``R = Rz(yaw) Ry(pitch) Rx(roll)``, dimensionless.
    """
    out = np.empty((3, 3))
    euler_zyx_into(roll, pitch, yaw, out)
    return out


@jit(inline="always")
def euler_zyx_into(roll, pitch, yaw, out):
    """:func:`euler_zyx_to_matrix` into ``out``.

    Parameters
    ----------
    roll, pitch, yaw : float
        ISO 8855 angles about x, y and z [rad].
    out : numpy.ndarray, shape (3, 3)
        Written with the rotation matrix body -> world, dimensionless.
    """
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp = np.cos(pitch), np.sin(pitch)
    cy, sy = np.cos(yaw), np.sin(yaw)
    out[0, 0] = cy * cp
    out[0, 1] = cy * sp * sr - sy * cr
    out[0, 2] = cy * sp * cr + sy * sr
    out[1, 0] = sy * cp
    out[1, 1] = sy * sp * sr + cy * cr
    out[1, 2] = sy * sp * cr - cy * sr
    out[2, 0] = -sp
    out[2, 1] = cp * sr
    out[2, 2] = cp * cr


@jit(inline="always")
def xform_motion(e, r, m, out):
    """``out = X m`` for a motion vector ``m`` (6,), transform ``(e, r)``; ``out`` must not alias ``m``.

    Parameters
    ----------
    e : numpy.ndarray, shape (3, 3)
        Rotation A -> B, dimensionless.
    r : numpy.ndarray, shape (3,)
        B's origin in A coordinates [m].
    m : numpy.ndarray, shape (6,)
        Motion vector in A (angular [rad/s], linear [m/s]).
    out : numpy.ndarray, shape (6,)
        Written with the motion vector in B.
    """
    w0, w1, w2 = m[0], m[1], m[2]
    v0 = m[3] - (r[1] * w2 - r[2] * w1)
    v1 = m[4] - (r[2] * w0 - r[0] * w2)
    v2 = m[5] - (r[0] * w1 - r[1] * w0)
    for i in range(3):
        out[i] = e[i, 0] * w0 + e[i, 1] * w1 + e[i, 2] * w2
        out[3 + i] = e[i, 0] * v0 + e[i, 1] * v1 + e[i, 2] * v2


@jit(inline="always")
def xform_force_inv(e, r, f, out):
    """``out = X^T f``: a force in the child frame B expressed in the parent frame A (no aliasing).

    Parameters
    ----------
    e : numpy.ndarray, shape (3, 3)
        Rotation A -> B, dimensionless.
    r : numpy.ndarray, shape (3,)
        B's origin in A coordinates [m].
    f : numpy.ndarray, shape (6,)
        Force vector in B (moment [N m], force [N]).
    out : numpy.ndarray, shape (6,)
        Written with the force vector in A.
    """
    n0 = e[0, 0] * f[0] + e[1, 0] * f[1] + e[2, 0] * f[2]
    n1 = e[0, 1] * f[0] + e[1, 1] * f[1] + e[2, 1] * f[2]
    n2 = e[0, 2] * f[0] + e[1, 2] * f[1] + e[2, 2] * f[2]
    f0 = e[0, 0] * f[3] + e[1, 0] * f[4] + e[2, 0] * f[5]
    f1 = e[0, 1] * f[3] + e[1, 1] * f[4] + e[2, 1] * f[5]
    f2 = e[0, 2] * f[3] + e[1, 2] * f[4] + e[2, 2] * f[5]
    out[0] = n0 + r[1] * f2 - r[2] * f1
    out[1] = n1 + r[2] * f0 - r[0] * f2
    out[2] = n2 + r[0] * f1 - r[1] * f0
    out[3] = f0
    out[4] = f1
    out[5] = f2


@jit(inline="always")
def motion_cross_motion(v, m, out):
    """``out = v x m`` (spatial cross product of motion vectors; no aliasing).

    Parameters
    ----------
    v : numpy.ndarray, shape (6,)
        Motion vector (angular [rad/s], linear [m/s]).
    m : numpy.ndarray, shape (6,)
        Motion vector.
    out : numpy.ndarray, shape (6,)
        Written with ``v x m``.
    """
    out[0] = v[1] * m[2] - v[2] * m[1]
    out[1] = v[2] * m[0] - v[0] * m[2]
    out[2] = v[0] * m[1] - v[1] * m[0]
    out[3] = v[1] * m[5] - v[2] * m[4] + v[4] * m[2] - v[5] * m[1]
    out[4] = v[2] * m[3] - v[0] * m[5] + v[5] * m[0] - v[3] * m[2]
    out[5] = v[0] * m[4] - v[1] * m[3] + v[3] * m[1] - v[4] * m[0]


@jit(inline="always")
def motion_cross_force(v, f, out):
    """``out = v x* f`` (spatial cross product of a motion and a force vector; no aliasing).

    Parameters
    ----------
    v : numpy.ndarray, shape (6,)
        Motion vector (angular [rad/s], linear [m/s]).
    f : numpy.ndarray, shape (6,)
        Force vector (moment [N m], force [N]) or momentum.
    out : numpy.ndarray, shape (6,)
        Written with ``v x* f``.
    """
    out[0] = v[1] * f[2] - v[2] * f[1] + v[4] * f[5] - v[5] * f[4]
    out[1] = v[2] * f[0] - v[0] * f[2] + v[5] * f[3] - v[3] * f[5]
    out[2] = v[0] * f[1] - v[1] * f[0] + v[3] * f[4] - v[4] * f[3]
    out[3] = v[1] * f[5] - v[2] * f[4]
    out[4] = v[2] * f[3] - v[0] * f[5]
    out[5] = v[0] * f[4] - v[1] * f[3]


@jit(inline="always")
def inertia_times_motion(m, h, ibar, a, out):
    """``out = I a`` for the inertia ``(m, h, Ibar)`` and a motion vector ``a`` (no aliasing).

    Parameters
    ----------
    m : float
        Mass [kg].
    h : numpy.ndarray, shape (3,)
        First moment of mass about the frame's origin [kg m].
    ibar : numpy.ndarray, shape (3, 3)
        Rotational inertia about the origin [kg m^2].
    a : numpy.ndarray, shape (6,)
        Motion vector (angular [rad/s or rad/s^2], linear [m/s or m/s^2]).
    out : numpy.ndarray, shape (6,)
        Written with the force vector (moment [N m], force [N] for an acceleration).
    """
    w0, w1, w2, v0, v1, v2 = a[0], a[1], a[2], a[3], a[4], a[5]
    for i in range(3):
        out[i] = ibar[i, 0] * w0 + ibar[i, 1] * w1 + ibar[i, 2] * w2
    out[0] += h[1] * v2 - h[2] * v1
    out[1] += h[2] * v0 - h[0] * v2
    out[2] += h[0] * v1 - h[1] * v0
    out[3] = m * v0 - (h[1] * w2 - h[2] * w1)
    out[4] = m * v1 - (h[2] * w0 - h[0] * w2)
    out[5] = m * v2 - (h[0] * w1 - h[1] * w0)


@jit(inline="always")
def inertia_to_parent(e, r, m, h, ibar, h_out, ibar_out, tmp):
    """``X^T I X``: add an inertia about the child frame's origin to one about the parent's.

    Accumulates into ``h_out`` and ``ibar_out`` (the mass is unchanged and is added by the caller);
    ``tmp`` is a 3x3 scratch array.
    With ``y = E^T h``: ``h' = y + m r`` and ``Ibar' = E^T Ibar E - [r]x [y]x - [y + m r]x [r]x``
    (Featherstone, Table 2.5); ``[a]x [b]x = b a^T - (a.b) 1``.

    Parameters
    ----------
    e : numpy.ndarray, shape (3, 3)
        Rotation of the transform parent -> child, dimensionless.
    r : numpy.ndarray, shape (3,)
        Child origin in parent coordinates [m].
    m : float
        Mass [kg].
    h : numpy.ndarray, shape (3,)
        First moment about the child origin, child coordinates [kg m].
    ibar : numpy.ndarray, shape (3, 3)
        Rotational inertia about the child origin, child coordinates [kg m^2].
    h_out : numpy.ndarray, shape (3,)
        Accumulates the first moment about the parent origin [kg m].
    ibar_out : numpy.ndarray, shape (3, 3)
        Accumulates the rotational inertia about the parent origin [kg m^2].
    tmp : numpy.ndarray, shape (3, 3)
        Scratch space.
    """
    y0 = e[0, 0] * h[0] + e[1, 0] * h[1] + e[2, 0] * h[2]
    y1 = e[0, 1] * h[0] + e[1, 1] * h[1] + e[2, 1] * h[2]
    y2 = e[0, 2] * h[0] + e[1, 2] * h[1] + e[2, 2] * h[2]
    hp0 = y0 + m * r[0]
    hp1 = y1 + m * r[1]
    hp2 = y2 + m * r[2]
    h_out[0] += hp0
    h_out[1] += hp1
    h_out[2] += hp2
    # E^T Ibar E
    for i in range(3):
        for j in range(3):
            tmp[i, j] = ibar[i, 0] * e[0, j] + ibar[i, 1] * e[1, j] + ibar[i, 2] * e[2, j]
    y = (y0, y1, y2)
    hp = (hp0, hp1, hp2)
    diag = r[0] * y0 + r[1] * y1 + r[2] * y2 + hp0 * r[0] + hp1 * r[1] + hp2 * r[2]
    for i in range(3):
        for j in range(3):
            value = e[0, i] * tmp[0, j] + e[1, i] * tmp[1, j] + e[2, i] * tmp[2, j]
            value -= y[i] * r[j] + r[i] * hp[j]
            if i == j:
                value += diag
            ibar_out[i, j] += value


@jit(inline="always")
def inertia_translate_to_parent(r, m, h, ibar, h_out, ibar_out):
    """:func:`inertia_to_parent` for a transform without rotation (``E = 1``): a wheel's rotor frame, a slider.

    Parameters
    ----------
    r : numpy.ndarray, shape (3,)
        Child origin in parent coordinates [m].
    m : float
        Mass [kg].
    h : numpy.ndarray, shape (3,)
        First moment about the child origin [kg m].
    ibar : numpy.ndarray, shape (3, 3)
        Rotational inertia about the child origin [kg m^2].
    h_out : numpy.ndarray, shape (3,)
        Accumulates the first moment about the parent origin [kg m].
    ibar_out : numpy.ndarray, shape (3, 3)
        Accumulates the rotational inertia about the parent origin [kg m^2].
    """
    hp0 = h[0] + m * r[0]
    hp1 = h[1] + m * r[1]
    hp2 = h[2] + m * r[2]
    h_out[0] += hp0
    h_out[1] += hp1
    h_out[2] += hp2
    y = (h[0], h[1], h[2])
    hp = (hp0, hp1, hp2)
    diag = r[0] * h[0] + r[1] * h[1] + r[2] * h[2] + hp0 * r[0] + hp1 * r[1] + hp2 * r[2]
    for i in range(3):
        for j in range(3):
            ibar_out[i, j] += ibar[i, j] - (y[i] * r[j] + r[i] * hp[j])
        ibar_out[i, i] += diag


