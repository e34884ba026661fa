"""Exact rigid multibody dynamics of a floating-base tree, compiled with numba.

The tree is data (:class:`~trikedyn.model.topology.Tree`): body 0 is the floating base (the chassis,
6 DOF), every other body hangs on one revolute or prismatic joint from a body with a smaller index.
Generalised coordinates ``q``: base position in the world [m], base ZYX Euler angles (roll, pitch,
yaw) [rad], then one coordinate per joint. Generalised velocities ``u``: the base's spatial velocity in
base coordinates, ``(omega, v)`` (Featherstone's floating-base convention), then one rate per joint.

Algorithms (Featherstone, *Rigid Body Dynamics Algorithms*, 2008): recursive Newton-Euler (RNEA, ch. 5)
for the bias forces with gravity and external forces, composite-rigid-body (CRBA, ch. 6) for the joint-
space mass matrix, and a Cholesky solve. ``H(q) du/dt + C(q, u, f_ext) = tau``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .spatial import (
    compose,
    euler_zyx_to_matrix,
    inertia_times_motion,
    inertia_to_parent,
    motion_cross_force,
    motion_cross_motion,
    rot_axis,
    xform_force_inv,
    xform_motion,
)

__all__ = [
    "JOINT_FREE",
    "JOINT_REVOLUTE",
    "JOINT_PRISMATIC",
    "joint_transforms",
    "world_transforms",
    "rnea",
    "rnea_er",
    "crba",
    "crba_er",
    "cholesky_solve",
    "forward_dynamics",
    "euler_rates",
]

JOINT_FREE, JOINT_REVOLUTE, JOINT_PRISMATIC = 0, 1, 2


@njit(cache=True)
def joint_transforms(q, parent, jtype, jaxis, tree_e, tree_r):
    """Parent-to-body transforms ``(E[i], r[i])`` at ``q``; for the base, world to base."""
    nb = parent.shape[0]
    e = np.empty((nb, 3, 3))
    r = np.empty((nb, 3))
    e[0] = euler_zyx_to_matrix(q[3], q[4], q[5]).T
    r[0] = q[:3]
    for i in range(1, nb):
        qi = q[5 + i]
        if jtype[i] == JOINT_REVOLUTE:
            ej = rot_axis(jaxis[i], qi).T
            e[i], r[i] = compose(ej, np.zeros(3), tree_e[i], tree_r[i])
        else:
            e[i], r[i] = compose(np.eye(3), jaxis[i] * qi, tree_e[i], tree_r[i])
    return e, r


@njit(cache=True)
def world_transforms(parent, e, r):
    """World-to-body rotations ``Ew[i]`` and body origins in the world ``pw[i]``."""
    nb = parent.shape[0]
    ew = np.empty((nb, 3, 3))
    pw = np.empty((nb, 3))
    ew[0] = e[0]
    pw[0] = r[0]
    for i in range(1, nb):
        p = parent[i]
        ew[i], pw[i] = compose(e[i], r[i], ew[p], pw[p])
    return ew, pw


@njit(cache=True)
def _motion_subspace(jtype, axis):
    s = np.zeros(6)
    if jtype == JOINT_REVOLUTE:
        s[:3] = axis
    else:
        s[3:] = axis
    return s


@njit(cache=True)
def rnea(q, u, udot, fext, gravity, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar):
    """Inverse dynamics: generalised forces ``tau`` that produce ``udot`` (RNEA, with gravity).

    Parameters
    ----------
    q, u, udot : ndarray (n,)
        Coordinates, velocities, accelerations (base first, see the module docstring).
    fext : ndarray (nb, 6)
        External spatial force on each body, in that body's coordinates, about its origin [N m, N].
    gravity : ndarray (3,)
        Gravity in world coordinates [m/s^2], e.g. (0, 0, -9.81).
    parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar
        The tree (:class:`~trikedyn.model.topology.Tree`).

    Returns
    -------
    ndarray (n,)
        ``H udot + C``: the first six entries are the force on the base in base coordinates.
    """
    e, r = joint_transforms(q, parent, jtype, jaxis, tree_e, tree_r)
    v = np.empty((parent.shape[0], 6))
    return rnea_er(e, r, u, udot, fext, gravity, parent, jtype, jaxis, mass, h, ibar, v)


@njit(cache=True)
def rnea_er(e, r, u, udot, fext, gravity, parent, jtype, jaxis, mass, h, ibar, v):
    """:func:`rnea` with the joint transforms given; also fills ``v`` with the body velocities."""
    nb = parent.shape[0]
    a = np.empty((nb, 6))
    f = np.empty((nb, 6))
    tmp = np.empty(6)
    tmp2 = np.empty(6)
    v[0] = u[:6]
    a[0, :3] = udot[:3]
    a[0, 3:] = udot[3:6] - e[0] @ gravity
    for i in range(1, nb):
        p = parent[i]
        s = _motion_subspace(jtype[i], jaxis[i])
        xform_motion(e[i], r[i], v[p], tmp)
        vj = s * u[5 + i]
        v[i] = tmp + vj
        xform_motion(e[i], r[i], a[p], tmp)
        motion_cross_motion(v[i], vj, tmp2)
        a[i] = tmp + s * udot[5 + i] + tmp2
    for i in range(nb):
        inertia_times_motion(mass[i], h[i], ibar[i], a[i], f[i])
        inertia_times_motion(mass[i], h[i], ibar[i], v[i], tmp)
        motion_cross_force(v[i], tmp, tmp2)
        f[i] += tmp2 - fext[i]
    tau = np.empty(u.shape[0])
    for i in range(nb - 1, 0, -1):
        s = _motion_subspace(jtype[i], jaxis[i])
        tau[5 + i] = s @ f[i]
        xform_force_inv(e[i], r[i], f[i], tmp)
        f[parent[i]] += tmp
    tau[:6] = f[0]
    return tau


@njit(cache=True)
def crba(q, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar):
    """Joint-space mass matrix ``H(q)`` (n x n, symmetric positive definite) by CRBA."""
    e, r = joint_transforms(q, parent, jtype, jaxis, tree_e, tree_r)
    return crba_er(e, r, parent, jtype, jaxis, mass, h, ibar)


@njit(cache=True)
def crba_er(e, r, parent, jtype, jaxis, mass, h, ibar):
    """:func:`crba` with the joint transforms given."""
    nb = parent.shape[0]
    n = nb + 5
    mc = mass.copy()
    hc = h.copy()
    ic = ibar.copy()
    for i in range(nb - 1, 0, -1):
        p = parent[i]
        hp, ip = inertia_to_parent(e[i], r[i], mc[i], hc[i], ic[i])
        mc[p] += mc[i]
        hc[p] += hp
        ic[p] += ip
    hmat = np.zeros((n, n))
    f = np.empty(6)
    tmp = np.empty(6)
    for i in range(1, nb):
        s = _motion_subspace(jtype[i], jaxis[i])
        inertia_times_motion(mc[i], hc[i], ic[i], s, f)
        di = 5 + i
        hmat[di, di] = s @ f
        j = i
        while parent[j] > 0:
            xform_force_inv(e[j], r[j], f, tmp)
            f[:] = tmp
            j = parent[j]
            sj = _motion_subspace(jtype[j], jaxis[j])
            hmat[di, 5 + j] = sj @ f
            hmat[5 + j, di] = hmat[di, 5 + j]
        xform_force_inv(e[j], r[j], f, tmp)
        for k in range(6):
            hmat[di, k] = tmp[k]
            hmat[k, di] = tmp[k]
    unit = np.zeros(6)
    for k in range(6):
        unit[:] = 0.0
        unit[k] = 1.0
        inertia_times_motion(mc[0], hc[0], ic[0], unit, f)
        hmat[:6, k] = f
    return hmat


@njit(cache=True)
def cholesky_solve(a, b):
    """Solve ``a x = b`` for symmetric positive definite ``a`` (small, dense) by Cholesky."""
    n = a.shape[0]
    low = np.zeros((n, n))
    for j in range(n):
        d = a[j, j]
        for k in range(j):
            d -= low[j, k] * low[j, k]
        if d <= 0.0:
            return np.full(n, np.nan)
        low[j, j] = np.sqrt(d)
        for i in range(j + 1, n):
            s = a[i, j]
            for k in range(j):
                s -= low[i, k] * low[j, k]
            low[i, j] = s / low[j, j]
    y = np.empty(n)
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= low[i, k] * y[k]
        y[i] = s / low[i, i]
    x = np.empty(n)
    for i in range(n - 1, -1, -1):
        s = y[i]
        for k in range(i + 1, n):
            s -= low[k, i] * x[k]
        x[i] = s / low[i, i]
    return x


@njit(cache=True)
def forward_dynamics(q, u, tau, fext, gravity, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar):
    """Accelerations ``du/dt = H^-1 (tau - C(q, u, f_ext))``."""
    zero = np.zeros(u.shape[0])
    bias = rnea(q, u, zero, fext, gravity, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar)
    hmat = crba(q, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar)
    return cholesky_solve(hmat, tau - bias)


@njit(cache=True)
def euler_rates(q, u):
    """``dq/dt``: base position rate in the world, Euler-angle rates, joint rates.

    With ``R`` body-to-world, ``d p / dt = R v``; ZYX Euler rates from the body angular velocity
    ``omega``: ``roll' = wx + (wy sin(roll) + wz cos(roll)) tan(pitch)``,
    ``pitch' = wy cos(roll) - wz sin(roll)``, ``yaw' = (wy sin(roll) + wz cos(roll)) / cos(pitch)``.
    """
    out = np.empty(q.shape[0])
    rmat = euler_zyx_to_matrix(q[3], q[4], q[5])
    out[:3] = rmat @ u[3:6]
    sr, cr = np.sin(q[3]), np.cos(q[3])
    cp = np.cos(q[4])
    tp = np.tan(q[4])
    wx, wy, wz = u[0], u[1], u[2]
    out[3] = wx + (wy * sr + wz * cr) * tp
    out[4] = wy * cr - wz * sr
    out[5] = (wy * sr + wz * cr) / cp
    out[6:] = u[6:]
    return out
