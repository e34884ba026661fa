"""Kinematics of a floating-base tree, compiled with numba: where the bodies are and how they move.

The tree and its coordinates are those of :mod:`trikedyn.model.dynamics`: ``q`` holds the base position in the
world [m], the base ZYX Euler angles [rad] and one coordinate per joint; ``u`` the base's spatial velocity in
base coordinates ``(omega, v)`` and one rate per joint. From the parent-to-body transforms
(:func:`~trikedyn.model.dynamics.joint_transforms_into`) this module gives the world poses of the bodies, their
spatial velocities and ``dq/dt``.

The ``*_into`` functions are the hot path (they allocate nothing); :func:`joint_transforms` and
:func:`world_transforms` allocate, for setup code and tests.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from .dynamics import JOINT_PRISMATIC, joint_transforms_into
from .spatial import xform_motion

__all__ = [
    "body_velocities_into",
    "euler_rates_into",
    "joint_transforms",
    "world_transforms",
    "world_transforms_into",
]


@jit(inline="always")
def world_transforms_into(parent, e, r, ew, pw):
    """World-to-body rotations ``ew[i]`` and body origins in the world ``pw[i]``.

    Parameters
    ----------
    parent : numpy.ndarray of int, shape (nb,)
        Parent index of each body (body 0, the floating base, has none).
    e, r : numpy.ndarray
        Parent -> body rotations (nb, 3, 3), dimensionless (world -> base for body 0), and body origins in
        parent coordinates (nb, 3) [m].
    ew : numpy.ndarray, shape (nb, 3, 3)
        Written with the world -> body rotations.
    pw : numpy.ndarray, shape (nb, 3)
        Written with the body origins in the world [m].
    """
    for i in range(3):
        pw[0, i] = r[0, i]
        for j in range(3):
            ew[0, i, j] = e[0, i, j]
    for b in range(1, parent.shape[0]):
        p = parent[b]
        for i in range(3):
            pw[b, i] = pw[p, i] + ew[p, 0, i] * r[b, 0] + ew[p, 1, i] * r[b, 1] + ew[p, 2, i] * r[b, 2]
            for j in range(3):
                ew[b, i, j] = e[b, i, 0] * ew[p, 0, j] + e[b, i, 1] * ew[p, 1, j] + e[b, i, 2] * ew[p, 2, j]


@jit(inline="always")
def body_velocities_into(e, r, u, parent, jtype, jaxis, v):
    """Spatial velocity of every body in its own coordinates.

    Parameters
    ----------
    e, r : numpy.ndarray
        Parent -> body rotations (nb, 3, 3), dimensionless (world -> base for body 0), and body origins in
        parent coordinates (nb, 3) [m].
    u : numpy.ndarray, shape (n,)
        Generalised velocities: base spatial velocity (omega [rad/s], v [m/s]) in base coordinates, joint
        rates [rad/s or m/s].
    parent, jtype, jaxis : numpy.ndarray
        Parent indices (nb,), joint types (nb,) and unit joint axes (nb, 3), dimensionless.
    v : numpy.ndarray, shape (nb, 6)
        Written with each body's velocity (omega [rad/s], v [m/s]) in its own coordinates.
    """
    for k in range(6):
        v[0, k] = u[k]
    for b in range(1, parent.shape[0]):
        xform_motion(e[b], r[b], v[parent[b]], v[b])
        off = 3 if jtype[b] == JOINT_PRISMATIC else 0
        for k in range(3):
            v[b, off + k] += jaxis[b, k] * u[5 + b]


@jit(inline="always")
def euler_rates_into(q, u, e0, out):
    """``dq/dt``: base position rate in the world, Euler-angle rates, joint rates.

    With ``R`` body-to-world, ``dp/dt = R v``; ZYX Euler rates from the body angular velocity
    ``omega``: ``roll' = wx + (wy sin(roll) + wz cos(roll)) tan(pitch)``,
    ``pitch' = wy cos(roll) - wz sin(roll)``, ``yaw' = (wy sin(roll) + wz cos(roll)) / cos(pitch)``.
    ``e0`` is the base's world-to-body rotation, ``R^T``.

    Parameters
    ----------
    q : numpy.ndarray, shape (n,)
        Generalised coordinates: base position [m], ZYX Euler angles [rad], joint coordinates [rad or m].
    u : numpy.ndarray, shape (n,)
        Generalised velocities: base spatial velocity (omega [rad/s], v [m/s]) in base coordinates, joint
        rates [rad/s or m/s].
    e0 : numpy.ndarray, shape (3, 3)
        World -> base rotation, dimensionless.
    out : numpy.ndarray, shape (n,)
        Written with ``dq/dt`` (position rates [m/s], angle rates [rad/s], joint rates).
    """
    for i in range(3):
        out[i] = e0[0, i] * u[3] + e0[1, i] * u[4] + e0[2, i] * u[5]
    # the angles' sines and cosines from the rotation already computed: R[2] = (-sp, cp sr, cp cr)
    sp = -e0[0, 2]
    cp = np.sqrt(1.0 - sp * sp)
    sr = e0[1, 2] / cp
    cr = e0[2, 2] / cp
    tp = sp / cp
    wx, wy, wz = u[0], u[1], u[2]
    out[3] = wx + (wy * sr + wz * cr) * tp
    out[4] = wy * cr - wz * sr
    out[5] = (wy * sr + wz * cr) / cp
    for i in range(6, q.shape[0]):
        out[i] = u[i]


# ---- allocating wrappers (setup code, tests) ---------------------------------------------------
@jit
def joint_transforms(q, parent, jtype, jaxis, tree_e, tree_r):
    """Parent-to-body transforms at ``q`` (allocating).

    Parameters
    ----------
    q : numpy.ndarray, shape (n,)
        Generalised coordinates: base position [m], ZYX Euler angles [rad], joint coordinates [rad or m].
    parent, jtype, jaxis, tree_e, tree_r : numpy.ndarray
        The tree (:meth:`~trikedyn.model.topology.Tree.arrays`): parent indices (nb,), joint types (nb,), unit joint
        axes (nb, 3) and, at zero joint coordinate, rotations parent -> body (nb, 3, 3), all dimensionless, and
        joint origins in parent coordinates (nb, 3) [m].

    Returns
    -------
    e : numpy.ndarray, shape (nb, 3, 3)
        Parent -> body rotations (world -> base for body 0), dimensionless.
    r : numpy.ndarray, shape (nb, 3)
        Body origins in parent coordinates [m].
    """
    nb = parent.shape[0]
    e = np.empty((nb, 3, 3))
    r = np.empty((nb, 3))
    joint_transforms_into(q, parent, jtype, jaxis, tree_e, tree_r, e, r, np.empty((3, 3)))
    return e, r


@jit
def world_transforms(parent, e, r):
    """World-to-body rotations and body origins (allocating).

    Parameters
    ----------
    parent : numpy.ndarray of int, shape (nb,)
        Parent index of each body (body 0, the floating base, has none).
    e, r : numpy.ndarray
        Parent -> body rotations (nb, 3, 3), dimensionless (world -> base for body 0), and body origins in
        parent coordinates (nb, 3) [m].

    Returns
    -------
    ew : numpy.ndarray, shape (nb, 3, 3)
        World -> body rotations, dimensionless.
    pw : numpy.ndarray, shape (nb, 3)
        Body origins in the world [m].
    """
    nb = parent.shape[0]
    ew = np.empty((nb, 3, 3))
    pw = np.empty((nb, 3))
    world_transforms_into(parent, e, r, ew, pw)
    return ew, pw
