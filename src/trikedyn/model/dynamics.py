"""Exact rigid multibody dynamics of a floating-base tree, compiled with numba.

The tree is data (:class:`~trikedyn.model.topology.Tree`): body 0 is the floating base (the chassis,
6 DOF), every other body hangs on one revolute or prismatic joint from a body with a smaller index.
Generalised coordinates ``q``: base position in the world [m], base ZYX Euler angles (roll, pitch,
yaw) [rad], then one coordinate per joint. Generalised velocities ``u``: the base's spatial velocity in
base coordinates, ``(omega, v)`` (Featherstone's floating-base convention), then one rate per joint.

Algorithms (Featherstone, *Rigid Body Dynamics Algorithms*, 2008): recursive Newton-Euler (RNEA, ch. 5)
for the bias forces with gravity and external forces, composite-rigid-body (CRBA, ch. 6) for the joint-
space mass matrix, and a Cholesky solve (:mod:`trikedyn.model.cholesky`): ``H(q) du/dt + C(q, u, f_ext) = tau``.
The joints place each body in its parent (:func:`joint_transforms_into`); the world poses, the body velocities
and ``dq/dt`` are :mod:`trikedyn.model.kinematics`'.

The ``*_into`` functions are the hot path: they fill a :func:`workspace` and allocate nothing. The plain
functions (:func:`rnea`, :func:`crba`, :func:`forward_dynamics`) allocate a workspace per call, for
setup code and tests.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from .._jit import jit
from .cholesky import cholesky_solve_into
from .spatial import (
    euler_zyx_into,
    inertia_times_motion,
    inertia_to_parent,
    inertia_translate_to_parent,
    motion_cross_force,
    motion_cross_motion,
    rot_axis_into,
    xform_force_inv,
    xform_motion,
)

__all__ = [
    "JOINT_FREE",
    "JOINT_PRISMATIC",
    "JOINT_REVOLUTE",
    "crba",
    "crba_into",
    "forward_dynamics",
    "joint_transforms_into",
    "rnea",
    "rnea_into",
    "workspace",
]

JOINT_FREE, JOINT_REVOLUTE, JOINT_PRISMATIC, JOINT_ROTOR = 0, 1, 2, 3
"""Joint types. A *rotor* is a revolute joint whose body is axisymmetric about the joint axis (a wheel):
its frame is kept fixed to the parent (it does not spin with the body), which leaves the inertia, and so
every equation, unchanged while saving the spin rotation in every transform."""

# workspace slots
Workspace = namedtuple("Workspace", "e r ew pw v a f fext mc hc ic hmat low vec t6a t6b t33 tau bias zero")
"""Scratch arrays of the compiled dynamics, by name (see :func:`workspace`)."""


@jit
def workspace(parent):
    """Scratch arrays for the tree of ``parent`` (``nb + 5`` DOF), allocated once per time loop.

    Parameters
    ----------
    parent : numpy.ndarray of int, shape (nb,)
        Parent index of each body (body 0, the floating base, has none).

    Returns
    -------
    Workspace
        A named tuple of uninitialised arrays sized for ``nb`` bodies and ``nb + 5`` DOF.
    """
    nb = parent.shape[0]
    n = nb + 5
    return Workspace(
        np.empty((nb, 3, 3)),  # e: parent -> body rotations
        np.empty((nb, 3)),  # r: body origins in parent coordinates
        np.empty((nb, 3, 3)),  # ew: world -> body rotations
        np.empty((nb, 3)),  # pw: body origins in the world
        np.empty((nb, 6)),  # v: body velocities
        np.empty((nb, 6)),  # a: body accelerations
        np.empty((nb, 6)),  # f: body forces
        np.empty((nb, 6)),  # fext: external forces
        np.empty(nb),  # mc: composite masses
        np.empty((nb, 3)),  # hc: composite first moments
        np.empty((nb, 3, 3)),  # ic: composite rotational inertias
        np.empty((n, n)),  # hmat: mass matrix
        np.empty((n, n)),  # low: Cholesky factor
        np.empty(n),  # vec: solve scratch
        np.empty(6),
        np.empty(6),
        np.empty((3, 3)),
        np.empty(n),  # tau: applied generalised forces
        np.empty(n),  # bias: C(q, u, f_ext)
        np.zeros(n),  # zero accelerations (never written)
    )


@jit(inline="always")
def joint_transforms_into(q, parent, jtype, jaxis, tree_e, tree_r, e, r, rot):
    """Parent-to-body transforms ``(e[i], r[i])`` at ``q``; for the base, world to base.

    Parameters
    ----------
    q : numpy.ndarray, shape (n,)
        Generalised coordinates: base position [m], ZYX Euler angles [rad], joint coordinates [rad or m].
    parent, jtype, jaxis, tree_e, tree_r : numpy.ndarray
        The tree (:meth:`~trikedyn.model.topology.Tree.arrays`): parent indices (nb,), joint types (nb,), unit joint
        axes (nb, 3) and, at zero joint coordinate, rotations parent -> body (nb, 3, 3), all dimensionless, and
        joint origins in parent coordinates (nb, 3) [m].
    e : numpy.ndarray, shape (nb, 3, 3)
        Written with the rotations.
    r : numpy.ndarray, shape (nb, 3)
        Written with the origins [m].
    rot : numpy.ndarray, shape (3, 3)
        Scratch.
    """
    euler_zyx_into(q[3], q[4], q[5], rot)
    for i in range(3):
        r[0, i] = q[i]
        for j in range(3):
            e[0, i, j] = rot[j, i]
    for b in range(1, parent.shape[0]):
        qi = q[5 + b]
        te = tree_e[b]
        if jtype[b] == JOINT_REVOLUTE:
            rot_axis_into(jaxis[b], qi, rot)
            # E = rot^T tree_e ; r = tree_r
            for i in range(3):
                r[b, i] = tree_r[b, i]
                for j in range(3):
                    e[b, i, j] = rot[0, i] * te[0, j] + rot[1, i] * te[1, j] + rot[2, i] * te[2, j]
        elif jtype[b] == JOINT_ROTOR:
            for i in range(3):
                r[b, i] = tree_r[b, i]
                for j in range(3):
                    e[b, i, j] = te[i, j]
        else:
            # E = tree_e ; r = tree_r + tree_e^T (axis q)
            ax = jaxis[b]
            for i in range(3):
                r[b, i] = tree_r[b, i] + qi * (te[0, i] * ax[0] + te[1, i] * ax[1] + te[2, i] * ax[2])
                for j in range(3):
                    e[b, i, j] = te[i, j]


@jit(inline="always")
def rnea_into(e, r, u, udot, fext, gravity, parent, jtype, jaxis, mass, h, ibar, ws, tau, have_velocities=False):
    """Inverse dynamics: ``tau = H udot + C(q, u, f_ext)`` (RNEA, gravity as a base acceleration).

    ``fext[i]`` is the external spatial force on body ``i`` in its coordinates, about its origin.
    The first six entries of ``tau`` are the force on the base in base coordinates. Fills ``ws.v``
    with the body velocities, or uses them as they are with ``have_velocities``.

    Parameters
    ----------
    e, r : numpy.ndarray
        Parent -> body rotations (nb, 3, 3), dimensionless (world -> base for body 0), and body origins in
        parent coordinates (nb, 3) [m].
    u : numpy.ndarray, shape (n,)
        Generalised velocities: base spatial velocity (omega [rad/s], v [m/s]) in base coordinates, joint
        rates [rad/s or m/s].
    udot : numpy.ndarray, shape (n,)
        Generalised accelerations [rad/s^2, m/s^2].
    fext : numpy.ndarray, shape (nb, 6)
        External spatial force on each body, in its coordinates about its origin (moment [N m], force [N]).
    gravity : numpy.ndarray, shape (3,)
        Gravity vector in the world [m/s^2], e.g. (0, 0, -9.81).
    parent, jtype, jaxis : numpy.ndarray
        Parent indices (nb,), joint types (nb,) and unit joint axes (nb, 3), dimensionless.
    mass, h, ibar : numpy.ndarray
        Body masses (nb,) [kg], first moments (nb, 3) [kg m] and rotational inertias (nb, 3, 3) [kg m^2] about
        each body's origin.
    ws : Workspace
        Scratch arrays from :func:`workspace`.
    tau : numpy.ndarray, shape (n,)
        Written with the generalised forces.
    have_velocities : bool
        Use the body velocities already in ``ws.v`` instead of computing them.
    """
    nb = parent.shape[0]
    v, a, f = ws.v, ws.a, ws.f
    t6a, t6b = ws.t6a, ws.t6b
    e0 = e[0]
    for k in range(6):
        v[0, k] = u[k]
    for k in range(3):
        a[0, k] = udot[k]
        a[0, 3 + k] = udot[3 + k] - (e0[k, 0] * gravity[0] + e0[k, 1] * gravity[1] + e0[k, 2] * gravity[2])
    for b in range(1, nb):
        p = parent[b]
        off = 3 if jtype[b] == JOINT_PRISMATIC else 0
        qd = u[5 + b]
        if not have_velocities:
            xform_motion(e[b], r[b], v[p], v[b])
            for k in range(3):
                v[b, off + k] += jaxis[b, k] * qd
        xform_motion(e[b], r[b], a[p], a[b])
        # a += S udot + v x (S qd)
        for k in range(6):
            t6a[k] = 0.0
        for k in range(3):
            t6a[off + k] = jaxis[b, k] * qd
            a[b, off + k] += jaxis[b, k] * udot[5 + b]
        motion_cross_motion(v[b], t6a, t6b)
        for k in range(6):
            a[b, k] += t6b[k]
    for b in range(nb):
        inertia_times_motion(mass[b], h[b], ibar[b], a[b], f[b])
        inertia_times_motion(mass[b], h[b], ibar[b], v[b], t6a)
        motion_cross_force(v[b], t6a, t6b)
        for k in range(6):
            f[b, k] += t6b[k] - fext[b, k]
    for b in range(nb - 1, 0, -1):
        off = 3 if jtype[b] == JOINT_PRISMATIC else 0
        tau[5 + b] = jaxis[b, 0] * f[b, off] + jaxis[b, 1] * f[b, off + 1] + jaxis[b, 2] * f[b, off + 2]
        xform_force_inv(e[b], r[b], f[b], t6a)
        p = parent[b]
        for k in range(6):
            f[p, k] += t6a[k]
    for k in range(6):
        tau[k] = f[0, k]


@jit(inline="always")
def crba_into(e, r, parent, jtype, jaxis, mass, h, ibar, ws):
    """Joint-space mass matrix ``H(q)`` into ``ws.hmat`` by the composite-rigid-body algorithm.

    Parameters
    ----------
    e, r : numpy.ndarray
        Parent -> body rotations (nb, 3, 3), dimensionless (world -> base for body 0), and body origins in
        parent coordinates (nb, 3) [m].
    parent, jtype, jaxis : numpy.ndarray
        Parent indices (nb,), joint types (nb,) and unit joint axes (nb, 3), dimensionless.
    mass, h, ibar : numpy.ndarray
        Body masses (nb,) [kg], first moments (nb, 3) [kg m] and rotational inertias (nb, 3, 3) [kg m^2] about
        each body's origin.
    ws : Workspace
        Scratch arrays from :func:`workspace`.
    """
    nb = parent.shape[0]
    mc, hc, ic, hmat = ws.mc, ws.hc, ws.ic, ws.hmat
    f, tmp, scratch = ws.t6a, ws.t6b, ws.t33
    hmat[:, :] = 0.0
    for b in range(nb):
        mc[b] = mass[b]
        for i in range(3):
            hc[b, i] = h[b, i]
            for j in range(3):
                ic[b, i, j] = ibar[b, i, j]
    for b in range(nb - 1, 0, -1):
        p = parent[b]
        eb = e[b]
        if eb[0, 0] == 1.0 and eb[1, 1] == 1.0 and eb[2, 2] == 1.0:  # no rotation: a rotor frame, a slider
            inertia_translate_to_parent(r[b], mc[b], hc[b], ic[b], hc[p], ic[p])
        else:
            inertia_to_parent(eb, r[b], mc[b], hc[b], ic[b], hc[p], ic[p], scratch)
        mc[p] += mc[b]
    for b in range(1, nb):
        off = 3 if jtype[b] == JOINT_PRISMATIC else 0
        for k in range(6):
            tmp[k] = 0.0
        for k in range(3):
            tmp[off + k] = jaxis[b, k]
        inertia_times_motion(mc[b], hc[b], ic[b], tmp, f)
        di = 5 + b
        hmat[di, di] = jaxis[b, 0] * f[off] + jaxis[b, 1] * f[off + 1] + jaxis[b, 2] * f[off + 2]
        j = b
        while parent[j] > 0:
            xform_force_inv(e[j], r[j], f, tmp)
            for k in range(6):
                f[k] = tmp[k]
            j = parent[j]
            offj = 3 if jtype[j] == JOINT_PRISMATIC else 0
            value = jaxis[j, 0] * f[offj] + jaxis[j, 1] * f[offj + 1] + jaxis[j, 2] * f[offj + 2]
            hmat[di, 5 + j] = value
            hmat[5 + j, di] = value
        xform_force_inv(e[j], r[j], f, tmp)
        for k in range(6):
            hmat[di, k] = tmp[k]
            hmat[k, di] = tmp[k]
    for k in range(6):
        for i in range(6):
            tmp[i] = 0.0
        tmp[k] = 1.0
        inertia_times_motion(mc[0], hc[0], ic[0], tmp, f)
        for i in range(6):
            hmat[i, k] = f[i]


# ---- allocating wrappers (setup code, tests) ---------------------------------------------------
@jit
def rnea(q, u, udot, fext, gravity, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar):
    """``H udot + C(q, u, f_ext)`` (allocating; see :func:`rnea_into`).

    Parameters
    ----------
    q : numpy.ndarray, shape (n,)
        Generalised coordinates: base position [m], ZYX Euler angles [rad], joint coordinates [rad or m].
    u : numpy.ndarray, shape (n,)
        Generalised velocities: base spatial velocity (omega [rad/s], v [m/s]) in base coordinates, joint
        rates [rad/s or m/s].
    udot : numpy.ndarray, shape (n,)
        Generalised accelerations [rad/s^2, m/s^2].
    fext : numpy.ndarray, shape (nb, 6)
        External spatial force on each body, in its coordinates about its origin (moment [N m], force [N]).
    gravity : numpy.ndarray, shape (3,)
        Gravity vector in the world [m/s^2], e.g. (0, 0, -9.81).
    parent, jtype, jaxis, tree_e, tree_r : numpy.ndarray
        The tree (:meth:`~trikedyn.model.topology.Tree.arrays`): parent indices (nb,), joint types (nb,), unit joint
        axes (nb, 3) and, at zero joint coordinate, rotations parent -> body (nb, 3, 3), all dimensionless, and
        joint origins in parent coordinates (nb, 3) [m].
    mass, h, ibar : numpy.ndarray
        Body masses (nb,) [kg], first moments (nb, 3) [kg m] and rotational inertias (nb, 3, 3) [kg m^2] about
        each body's origin.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The generalised forces that give ``udot`` (base wrench [N m, N], joint torques [N m] or forces [N]).
    """
    ws = workspace(parent)
    joint_transforms_into(q, parent, jtype, jaxis, tree_e, tree_r, ws.e, ws.r, ws.t33)
    tau = np.empty(u.shape[0])
    rnea_into(ws.e, ws.r, u, udot, fext, gravity, parent, jtype, jaxis, mass, h, ibar, ws, tau)
    return tau


@jit
def crba(q, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar):
    """Joint-space mass matrix ``H(q)`` (allocating; see :func:`crba_into`).

    Parameters
    ----------
    q : numpy.ndarray, shape (n,)
        Generalised coordinates: base position [m], ZYX Euler angles [rad], joint coordinates [rad or m].
    parent, jtype, jaxis, tree_e, tree_r : numpy.ndarray
        The tree (:meth:`~trikedyn.model.topology.Tree.arrays`): parent indices (nb,), joint types (nb,), unit joint
        axes (nb, 3) and, at zero joint coordinate, rotations parent -> body (nb, 3, 3), all dimensionless, and
        joint origins in parent coordinates (nb, 3) [m].
    mass, h, ibar : numpy.ndarray
        Body masses (nb,) [kg], first moments (nb, 3) [kg m] and rotational inertias (nb, 3, 3) [kg m^2] about
        each body's origin.

    Returns
    -------
    numpy.ndarray, shape (n, n)
        The symmetric positive definite mass matrix [kg, kg m, kg m^2 by entry].
    """
    ws = workspace(parent)
    joint_transforms_into(q, parent, jtype, jaxis, tree_e, tree_r, ws.e, ws.r, ws.t33)
    crba_into(ws.e, ws.r, parent, jtype, jaxis, mass, h, ibar, ws)
    return ws.hmat.copy()


@jit
def forward_dynamics(q, u, tau, fext, gravity, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar):
    """Accelerations ``du/dt = H^-1 (tau - C(q, u, f_ext))`` (allocating).

    Parameters
    ----------
    q : numpy.ndarray, shape (n,)
        Generalised coordinates: base position [m], ZYX Euler angles [rad], joint coordinates [rad or m].
    u : numpy.ndarray, shape (n,)
        Generalised velocities: base spatial velocity (omega [rad/s], v [m/s]) in base coordinates, joint
        rates [rad/s or m/s].
    tau : numpy.ndarray, shape (n,)
        Applied generalised forces (base wrench in base coordinates [N m, N], joint torques [N m] or forces
        [N]).
    fext : numpy.ndarray, shape (nb, 6)
        External spatial force on each body, in its coordinates about its origin (moment [N m], force [N]).
    gravity : numpy.ndarray, shape (3,)
        Gravity vector in the world [m/s^2], e.g. (0, 0, -9.81).
    parent, jtype, jaxis, tree_e, tree_r : numpy.ndarray
        The tree (:meth:`~trikedyn.model.topology.Tree.arrays`): parent indices (nb,), joint types (nb,), unit joint
        axes (nb, 3) and, at zero joint coordinate, rotations parent -> body (nb, 3, 3), all dimensionless, and
        joint origins in parent coordinates (nb, 3) [m].
    mass, h, ibar : numpy.ndarray
        Body masses (nb,) [kg], first moments (nb, 3) [kg m] and rotational inertias (nb, 3, 3) [kg m^2] about
        each body's origin.

    Returns
    -------
    numpy.ndarray, shape (n,)
        ``du/dt`` [rad/s^2, m/s^2]; NaN if the mass matrix is not positive definite.
    """
    ws = workspace(parent)
    joint_transforms_into(q, parent, jtype, jaxis, tree_e, tree_r, ws.e, ws.r, ws.t33)
    n = u.shape[0]
    bias = np.empty(n)
    rnea_into(ws.e, ws.r, u, np.zeros(n), fext, gravity, parent, jtype, jaxis, mass, h, ibar, ws, bias)
    crba_into(ws.e, ws.r, parent, jtype, jaxis, mass, h, ibar, ws)
    out = np.empty(n)
    cholesky_solve_into(ws.hmat, tau - bias, ws.low, ws.vec, out)
    return out
