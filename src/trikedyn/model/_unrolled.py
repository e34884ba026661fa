"""The algorithms of :mod:`trikedyn.model.codegen` unrolled over one tree structure (the kinematics, RNEA,
CRBA, the solve).

Each method emits straight-line code through an :class:`~trikedyn.model._folding.Emitter` and returns the
*values* (float constants or names of locals) of its results; products with the structure's constants fold
out as the code is written (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, ch. 5, 6).
"""

from __future__ import annotations

from ._folding import (
    cross_force,
    cross_motion,
    inertia_times,
    inertia_to_parent,
    term,
    xform_force_inv,
    xform_motion,
)
from .dynamics import JOINT_PRISMATIC, JOINT_REVOLUTE

__all__ = ["UnrolledTree"]


class UnrolledTree:
    """The structure's constants and the run-time values loaded from the argument arrays.

    Parameters
    ----------
    s : TreeStructure
        The structure (:class:`trikedyn.model.codegen.TreeStructure`).
    em : Emitter
        Where the code goes.
    """

    def __init__(self, s, em):
        self.s, self.em, self.nb = s, em, len(s.parent)

    def e_fixed(self, b):
        """The fixed rotation of body ``b``: constants where the structure has them, else loaded."""
        em, c = self.em, self.s.e_const[b]
        return [[c[3 * i + j] if c[3 * i + j] is not None else em.load("tree_e", b, i, j) for j in range(3)]
                for i in range(3)]

    def inertia(self, b):
        """Mass, first moment and rotational inertia of body ``b`` as values (structural zeros as 0.0)."""
        em, s = self.em, self.s
        h = [0.0 if s.h_zero[b][i] else em.load("h", b, i) for i in range(3)]
        ibar = [[0.0 if s.ibar_zero[b][3 * i + j] else em.load("ibar", b, i, j) for j in range(3)] for i in range(3)]
        return em.load("mass", b), h, ibar

    def motion_subspace(self, b):
        """The joint's motion subspace ``S`` (6 constants)."""
        off = 3 if self.s.jtype[b] == JOINT_PRISMATIC else 0
        sub = [0.0] * 6
        for k in range(3):
            sub[off + k] = self.s.jaxis[b][k]
        return sub

    def transforms(self):
        """Emit the joint transforms at ``q``: base rotation world -> base, then ``(E, r)`` of every joint."""
        em, s = self.em, self.s
        for k, name in ((3, "r"), (4, "p"), (5, "y")):
            angle = em.load("q", k)
            em.line(f"s{name}, c{name} = sincos({angle})")
        em.line("rot00 = cy * cp")
        em.line("rot01 = cy * sp * sr - sy * cr")
        em.line("rot02 = cy * sp * cr + sy * sr")
        em.line("rot10 = sy * cp")
        em.line("rot11 = sy * sp * sr + cy * cr")
        em.line("rot12 = sy * sp * cr - cy * sr")
        em.line("rot20 = -sp")
        em.line("rot21 = cp * sr")
        em.line("rot22 = cp * cr")
        self.e = [[[f"rot{j}{i}" for j in range(3)] for i in range(3)]]
        self.r = [None]
        for b in range(1, self.nb):
            qb = em.load("q", 5 + b)
            te = self.e_fixed(b)
            r = [0.0 if s.r_zero[b][i] else em.load("tree_r", b, i) for i in range(3)]
            ax = s.jaxis[b]
            if s.jtype[b] == JOINT_REVOLUTE:
                c, sn, t = f"c_{b}", f"s_{b}", f"t_{b}"
                em.line(f"{sn}, {c} = sincos({qb})")
                em.line(f"{t} = 1.0 - {c}")
                x, y, z = ax
                rot = [[em.sum(term(t, x * x), term(c)), em.sum(term(t, x * y), term(-z, sn)),
                        em.sum(term(t, x * z), term(y, sn))],
                       [em.sum(term(t, x * y), term(z, sn)), em.sum(term(t, y * y), term(c)),
                        em.sum(term(t, y * z), term(-x, sn))],
                       [em.sum(term(t, x * z), term(-y, sn)), em.sum(term(t, y * z), term(x, sn)),
                        em.sum(term(t, z * z), term(c))]]
                e = [[em.sum(*(term(rot[k][i], te[k][j]) for k in range(3))) for j in range(3)] for i in range(3)]
            elif s.jtype[b] == JOINT_PRISMATIC:
                e = te
                r = [em.sum(term(r[i]), *(term(qb, te[k][i], ax[k]) for k in range(3))) for i in range(3)]
            else:  # a rotor: its frame stays fixed to the parent
                e = te
            self.e.append(e)
            self.r.append(r)

    def kinematics(self):
        """Emit the world poses and body velocities at ``q``, ``u`` (after :meth:`transforms`), as the generic
        :func:`~trikedyn.model.kinematics.world_transforms_into` and
        :func:`~trikedyn.model.kinematics.body_velocities_into` give them.

        Returns
        -------
        ew, pw, v : list
            Per body the values of the world -> body rotation (3 x 3), the body origin in the world (3) [m] and
            the body's velocity ``(omega, v)`` in its own axes (6).
        """
        em, s = self.em, self.s
        r0 = [em.load("q", k) for k in range(3)]
        self.r[0] = r0
        ew, pw, v = [self.e[0]], [r0], [[em.load("u", k) for k in range(6)]]
        for b in range(1, self.nb):
            p, e, r = s.parent[b], self.e[b], self.r[b]
            pw.append([em.sum(term(pw[p][i]), *(term(ew[p][k][i], r[k]) for k in range(3))) for i in range(3)])
            ew.append([[em.sum(*(term(e[i][k], ew[p][k][j]) for k in range(3))) for j in range(3)]
                       for i in range(3)])
            sub = self.motion_subspace(b)
            qd = em.load("u", 5 + b)
            xv = xform_motion(em, e, r, v[p])
            v.append([em.sum(term(xv[k]), term(sub[k], qd)) for k in range(6)])
        return ew, pw, v

    def store_kinematics(self):
        """Emit the transforms and the kinematics and store them as ``kinematics_into`` writes its outputs: ``e``,
        ``r`` (the joint transforms), ``ew``, ``pw`` (the world poses) and ``v`` (the body velocities)."""
        em = self.em
        self.transforms()
        ew, pw, v = self.kinematics()
        for b in range(self.nb):
            for i in range(3):
                em.store("r", (b, i), self.r[b][i])
                em.store("pw", (b, i), pw[b][i])
                for j in range(3):
                    em.store("e", (b, i, j), self.e[b][i][j])
                    em.store("ew", (b, i, j), ew[b][i][j])
            for k in range(6):
                em.store("v", (b, k), v[b][k])

    def forward_dynamics(self, factor=None):
        """Emit ``du/dt = H^-1 (tau - C)``: the transforms, the RNEA bias, the CRBA, the ``L^T D L`` solve, and
        ``dmin``, the smallest pivot (``H`` is positive definite when it is > 0); with ``factor`` (an array's
        name) the factor's entries are stored into it (``D`` on the diagonal, ``L_ij`` where ``j`` is an ancestor
        of ``i``).

        Returns
        -------
        list
            The values of ``du/dt``, valid where ``dmin > 0``.
        """
        em = self.em
        n = self.nb + 5
        self.transforms()
        bias = self.rnea([0.0] * n)
        hmat = self.crba()
        rhs = [em.sum(term(em.load("tau", i)), term(-1.0, bias[i])) for i in range(n)]
        x, pivots, multipliers = self.solve(hmat, rhs)
        em.line("dmin = np.inf")
        for pv in pivots:
            em.line(f"dmin = min(dmin, {pv})")
        if factor is not None:
            for k in range(n):
                em.store(factor, (k, k), pivots[k])
            for (i, j), value in sorted(multipliers.items()):
                em.store(factor, (i, j), value)
        return x

    def rnea(self, udot, fext_zero=False):
        """Emit ``tau = H udot + C``; ``udot`` a list of values (0.0 folds out). Returns the values of tau."""
        em, s, nb = self.em, self.s, self.nb
        g = [em.load("gravity", k) for k in range(3)]
        e0 = self.e[0]
        v = [[em.load("u", k) for k in range(6)]]
        a = [udot[:3] + [em.sum(term(udot[3 + k]), *(term(-1.0, e0[k][j], g[j]) for j in range(3)))
                         for k in range(3)]]
        for b in range(1, nb):
            p = s.parent[b]
            sub = self.motion_subspace(b)
            qd = em.load("u", 5 + b)
            sqd = [em.sum(term(sub[k], qd)) for k in range(6)]
            xv = xform_motion(em, self.e[b], self.r[b], v[p])
            v.append([em.add(xv[k], sqd[k]) for k in range(6)])
            xa = xform_motion(em, self.e[b], self.r[b], a[p])
            vs = cross_motion(em, v[b], sqd)
            a.append([em.sum(term(xa[k]), term(sub[k], udot[5 + b]), term(vs[k])) for k in range(6)])
        f = []
        for b in range(nb):
            m, h, ibar = self.inertia(b)
            ia = inertia_times(em, m, h, ibar, a[b])
            iv = inertia_times(em, m, h, ibar, v[b])
            vf = cross_force(em, v[b], iv)
            f.append([em.sum(term(ia[k]), term(vf[k]), None if fext_zero else term(-1.0, em.load("fext", b, k)))
                      for k in range(6)])
        tau = [0.0] * (nb + 5)
        for b in range(nb - 1, 0, -1):
            sub = self.motion_subspace(b)
            tau[5 + b] = em.dot(sub, f[b])
            xf = xform_force_inv(em, self.e[b], self.r[b], f[b])
            p = s.parent[b]
            f[p] = [em.add(f[p][k], xf[k]) for k in range(6)]
        tau[:6] = f[0]
        return tau

    def crba(self):
        """Emit the mass matrix; returns its lower triangle as a dict ``{(i, j): value}`` with ``i >= j``."""
        em, s, nb = self.em, self.s, self.nb
        mc, hc, ic = [], [], []
        for b in range(nb):
            m, h, ibar = self.inertia(b)
            mc.append(m)
            hc.append(h)
            ic.append(ibar)
        for b in range(nb - 1, 0, -1):
            p = s.parent[b]
            hp, ip = inertia_to_parent(em, self.e[b], self.r[b], mc[b], hc[b], ic[b])
            hc[p] = [em.add(hc[p][i], hp[i]) for i in range(3)]
            ic[p] = [[em.add(ic[p][i][j], ip[i][j]) for j in range(3)] for i in range(3)]
            mc[p] = em.add(mc[p], mc[b])
        hmat = {}
        for b in range(1, nb):
            sub = self.motion_subspace(b)
            f = inertia_times(em, mc[b], hc[b], ic[b], sub)
            di = 5 + b
            hmat[di, di] = em.dot(sub, f)
            j = b
            while s.parent[j] > 0:
                f = xform_force_inv(em, self.e[j], self.r[j], f)
                j = s.parent[j]
                hmat[di, 5 + j] = em.dot(self.motion_subspace(j), f)
            f = xform_force_inv(em, self.e[j], self.r[j], f)
            for k in range(6):
                hmat[di, k] = f[k]
        for k in range(6):
            unit = [1.0 if i == k else 0.0 for i in range(6)]
            f = inertia_times(em, mc[0], hc[0], ic[0], unit)
            for i in range(k, 6):
                hmat[i, k] = f[i]
        return hmat

    def ancestors(self, k):
        """The ancestors of degree of freedom ``k`` in the expanded tree, nearest first."""
        lam, out = self.dof_parent(), []
        j = lam[k]
        while j != -1:
            out.append(j)
            j = lam[j]
        return out

    def dof_parent(self):
        """Parent of each degree of freedom in the expanded tree (the base's six form a chain), -1 at the root."""
        return [-1, 0, 1, 2, 3, 4] + [5 + p if p > 0 else 5 for p in self.s.parent[1:]]

    def solve(self, hmat, rhs):
        """Emit ``H x = rhs`` by the leaves-first ``L^T D L`` factorisation.

        Returns
        -------
        x : list
            The solution's values.
        pivots : list
            ``D``, one value per degree of freedom.
        multipliers : dict
            ``{(i, j): L_ij}`` for each ``j`` an ancestor of ``i`` (``L`` unit lower triangular).
        """
        em, lam = self.em, self.dof_parent()
        n = len(lam)
        mat = dict(hmat)
        inv = [None] * n
        for k in range(n - 1, -1, -1):
            if isinstance(mat[k, k], float):
                inv[k] = 1.0 / mat[k, k]
            else:
                em.line(f"inv{k} = 1.0 / {mat[k, k]}")
                inv[k] = f"inv{k}"
            i = lam[k]
            while i != -1:
                factor = em.sum(term(mat.get((k, i), 0.0), inv[k]))
                j = i
                while j != -1:
                    mat[i, j] = em.sum(term(mat.get((i, j), 0.0)), term(-1.0, factor, mat.get((k, j), 0.0)))
                    j = lam[j]
                mat[k, i] = factor
                i = lam[i]
        x = list(rhs)
        for i in range(n - 1, -1, -1):
            j = lam[i]
            while j != -1:
                x[j] = em.sum(term(x[j]), term(-1.0, mat.get((i, j), 0.0), x[i]))
                j = lam[j]
        x = [em.sum(term(x[i], inv[i])) for i in range(n)]
        for i in range(n):
            j = lam[i]
            while j != -1:
                x[i] = em.sum(term(x[i]), term(-1.0, mat.get((i, j), 0.0), x[j]))
                j = lam[j]
        return x, [mat[k, k] for k in range(n)], {(k, i): mat[k, i] for k in range(n) for i in self.ancestors(k)}
