"""Dynamics kernels generated for one tree's structure: straight-line numba code, cached on disk.

The generic kernels of :mod:`trikedyn.model.dynamics` loop over any tree and read each body's joint type and
axis at run time. Here a small generator of our own unrolls the same algorithms (RNEA, CRBA) for one
*structure* into straight-line Python source: each body's parent, joint type and axis are constants, and so
is which entry of each body's fixed rotation is exactly 0 or 1 and which entry of its offset, first moment
and inertia is exactly 0. Products with those constants fold out at generation time (a wheel's rotor frame,
a slider's axis, a wheel's centred mass cost nothing). The values (masses, inertias, offsets, the rotations'
other entries) stay run-time arguments, so one compiled kernel serves every vehicle of that structure.

The mass matrix is factorised leaves first, ``H = L^T D L`` (Featherstone, *Rigid Body Dynamics Algorithms*,
2008, section 6.5): ``L`` is unit lower triangular with entries only where one degree of freedom is an
ancestor of the other, and the factorisation makes no fill-in, so it touches only the tree's entries instead
of the dense ``n^3 / 6`` of a Cholesky factorisation. The six base coordinates form a chain.

The source is written once to ``<cache>/<key>.py`` (atomically: a temporary file then :func:`os.replace`),
keyed by a hash of the structure, the generator's version and its own source, and imported with
``njit(cache=True)``, so a later process loads the compiled code from numba's cache. ``<cache>`` is
``$TRIKEDYN_CACHE_DIR/generated``, else ``$XDG_CACHE_HOME/trikedyn/generated``, else
``~/.cache/trikedyn/generated``. SymPy was not needed: the algorithms are recursive and their folding is
local, so a term-folding emitter of ~100 lines does it and generates a 13-DOF kernel in milliseconds.
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import os
import sys
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._jit import FASTMATH
from ._folding import (
    Emitter,
    cross_force,
    cross_motion,
    inertia_times,
    inertia_to_parent,
    term,
    xform_force_inv,
    xform_motion,
)
from .dynamics import JOINT_PRISMATIC, JOINT_REVOLUTE

__all__ = ["GENERATOR_VERSION", "TreeStructure", "cache_dir", "generate_source", "kernels", "kernels_for_tree"]

GENERATOR_VERSION = 1
"""Raised whenever the generated code changes meaning (the key also hashes this module's source)."""

_LOCK = threading.Lock()
_LOADED: dict[str, object] = {}


@dataclass(frozen=True)
class TreeStructure:
    """What a generated kernel is specialised to: the tree's structure, not its values.

    Attributes
    ----------
    parent, jtype : tuple of int
        Parent index and joint type of each body (body 0 the floating base).
    jaxis : tuple of tuple of float
        Unit joint axes, dimensionless.
    e_const : tuple
        Per body, the 3x3 fixed rotation's entries that are exactly 0.0, 1.0 or -1.0 (as floats) or None.
    r_zero, h_zero, ibar_zero : tuple
        Per body, which entries of the joint offset, first moment and rotational inertia are exactly zero.
    """

    parent: tuple
    jtype: tuple
    jaxis: tuple
    e_const: tuple
    r_zero: tuple
    h_zero: tuple
    ibar_zero: tuple

    @classmethod
    def of(cls, parent, jtype, jaxis, tree_e, tree_r, h, ibar) -> TreeStructure:
        """The structure of a tree given as arrays (:meth:`~trikedyn.model.topology.Tree.arrays`).

        Parameters
        ----------
        parent, jtype : numpy.ndarray of int, shape (nb,)
            Parent indices and joint types.
        jaxis : numpy.ndarray, shape (nb, 3)
            Unit joint axes, dimensionless.
        tree_e : numpy.ndarray, shape (nb, 3, 3)
            Fixed rotations parent -> body at zero joint coordinate, dimensionless.
        tree_r : numpy.ndarray, shape (nb, 3)
            Joint origins in parent coordinates [m].
        h, ibar : numpy.ndarray
            First moments (nb, 3) [kg m] and rotational inertias (nb, 3, 3) [kg m^2].

        Returns
        -------
        TreeStructure
            The structure, hashable, for :func:`kernels`.
        """

        def const(x):
            """The entry if it is exactly 0 or +-1, else None."""
            x = float(x)
            return x if x in (0.0, 1.0, -1.0) else None

        nb = len(parent)
        return cls(
            parent=tuple(int(p) for p in parent),
            jtype=tuple(int(t) for t in jtype),
            jaxis=tuple(tuple(float(a) for a in np.asarray(jaxis)[b]) for b in range(nb)),
            e_const=tuple(tuple(const(x) for x in np.asarray(tree_e)[b].ravel()) for b in range(nb)),
            r_zero=tuple(tuple(bool(x == 0.0) for x in np.asarray(tree_r)[b]) for b in range(nb)),
            h_zero=tuple(tuple(bool(x == 0.0) for x in np.asarray(h)[b]) for b in range(nb)),
            ibar_zero=tuple(tuple(bool(x == 0.0) for x in np.asarray(ibar)[b].ravel()) for b in range(nb)),
        )

    def key(self) -> str:
        """A hash of the structure, the generator's version and source (with its emitter's) and the numba options.

        Returns
        -------
        str
            24 hexadecimal digits, the cached module's name.
        """
        here = Path(__file__).parent
        own = (here / "codegen.py").read_bytes() + (here / "_folding.py").read_bytes()
        blob = json.dumps([GENERATOR_VERSION, sorted(FASTMATH), self.parent, self.jtype,
                           [[float(a).hex() for a in ax] for ax in self.jaxis], self.e_const, self.r_zero,
                           self.h_zero, self.ibar_zero])
        return hashlib.sha256(own + blob.encode()).hexdigest()[:24]


# ---- the algorithms, unrolled ------------------------------------------------------------------
class _Tree:
    """The structure's constants and the run-time values loaded from the argument arrays."""

    def __init__(self, s: TreeStructure, em: Emitter):
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
            em.line(f"c{name} = np.cos({angle})")
            em.line(f"s{name} = np.sin({angle})")
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
                em.line(f"{c} = np.cos({qb})")
                em.line(f"{sn} = np.sin({qb})")
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

    def dof_parent(self):
        """Parent of each degree of freedom in the expanded tree (the base's six form a chain), -1 at the root."""
        return [-1, 0, 1, 2, 3, 4] + [5 + p if p > 0 else 5 for p in self.s.parent[1:]]

    def solve(self, hmat, rhs):
        """Emit ``H x = rhs`` by the leaves-first ``L^T D L`` factorisation; returns x and the pivots."""
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
        return x, [mat[k, k] for k in range(n)]


_HEADER = '''"""Generated by trikedyn.model.codegen (version {version}) for one tree structure: do not edit.

Key {key}. Bodies {nb}, degrees of freedom {n}. Parents {parent}, joint types {jtype}.
"""

import numpy as np

from trikedyn._jit import jit

N_DOF = {n}
'''


def _function(name, args, doc, body_lines):
    return f"\n\n@jit\ndef {name}({', '.join(args)}):\n    \"\"\"{doc}\"\"\"\n" + "\n".join(body_lines) + "\n"


def generate_source(structure: TreeStructure) -> str:
    """The Python source of the kernels for ``structure``.

    The module defines ``rnea_into``/``rnea`` (``H udot + C``), ``mass_matrix_into``/``mass_matrix`` and
    ``forward_dynamics_into``/``forward_dynamics_generated`` (``du/dt``, NaN if ``H`` is not positive
    definite), with the arguments of their generic namesakes in :mod:`trikedyn.model.dynamics` less the
    structure (``parent``, ``jtype``, ``jaxis``), and ``out`` last for the ``_into`` forms.

    Parameters
    ----------
    structure : TreeStructure
        The tree's structure.

    Returns
    -------
    str
        The module's source.
    """
    nb = len(structure.parent)
    n = nb + 5
    values = ["tree_e", "tree_r", "mass", "h", "ibar"]
    src = [_HEADER.format(version=GENERATOR_VERSION, key=structure.key(), nb=nb, n=n,
                          parent=list(structure.parent), jtype=list(structure.jtype))]

    em = Emitter()
    tree = _Tree(structure, em)
    tree.transforms()
    tau = tree.rnea([em.load("udot", k) for k in range(n)])
    for i in range(n):
        em.line(f"out[{i}] = {tau[i]}")
    src.append(_function("rnea_into", ["q", "u", "udot", "fext", "gravity", *values, "out"],
                         "Generalised forces ``H udot + C(q, u, f_ext)`` into ``out``.", em.lines))

    em = Emitter()
    tree = _Tree(structure, em)
    tree.transforms()
    hmat = tree.crba()
    for i in range(n):
        for j in range(n):
            em.line(f"out[{i}, {j}] = {hmat.get((max(i, j), min(i, j)), 0.0)}")
    src.append(_function("mass_matrix_into", ["q", *values, "out"], "Mass matrix ``H(q)`` into ``out``.",
                         em.lines))

    em = Emitter()
    tree = _Tree(structure, em)
    tree.transforms()
    bias = tree.rnea([0.0] * n)
    hmat = tree.crba()
    rhs = [em.sum(term(em.load("tau", i)), term(-1.0, bias[i])) for i in range(n)]
    x, pivots = tree.solve(hmat, rhs)
    em.line("dmin = np.inf")
    for pv in pivots:
        em.line(f"dmin = min(dmin, {pv})")
    em.line("if dmin > 0.0:")
    for i in range(n):
        em.line(f"    out[{i}] = {x[i]}")
    em.line("else:")
    em.line("    out[:] = np.nan")
    src.append(_function("forward_dynamics_into", ["q", "u", "tau", "fext", "gravity", *values, "out"],
                         "``du/dt = H^-1 (tau - C)`` into ``out``; NaN if ``H`` is not positive definite.",
                         em.lines))

    src.append(_function("rnea", ["q", "u", "udot", "fext", "gravity", *values], "Allocating ``rnea_into``.",
                         [f"    out = np.empty({n})",
                          f"    rnea_into(q, u, udot, fext, gravity, {', '.join(values)}, out)", "    return out"]))
    src.append(_function("mass_matrix", ["q", *values], "Allocating ``mass_matrix_into``.",
                         [f"    out = np.empty(({n}, {n}))", f"    mass_matrix_into(q, {', '.join(values)}, out)",
                          "    return out"]))
    src.append(_function("forward_dynamics_generated", ["q", "u", "tau", "fext", "gravity", *values],
                         "Allocating ``forward_dynamics_into``.",
                         [f"    out = np.empty({n})",
                          f"    forward_dynamics_into(q, u, tau, fext, gravity, {', '.join(values)}, out)",
                          "    return out"]))
    return "".join(src)


def cache_dir() -> Path:
    """The folder of the generated modules (created if missing).

    Returns
    -------
    pathlib.Path
        ``$TRIKEDYN_CACHE_DIR/generated``, else ``$XDG_CACHE_HOME/trikedyn/generated``, else
        ``~/.cache/trikedyn/generated``; a folder under the temporary directory if that cannot be created.
    """
    if os.environ.get("TRIKEDYN_CACHE_DIR"):
        base = Path(os.environ["TRIKEDYN_CACHE_DIR"])
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "trikedyn"
    folder = base / "generated"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        if not os.access(folder, os.W_OK):
            raise PermissionError(folder)
    except OSError:
        folder = Path(tempfile.gettempdir()) / f"trikedyn-generated-{os.getuid()}"
        folder.mkdir(parents=True, exist_ok=True)
    return folder


def _write_atomic(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.stem + ".", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def kernels(structure: TreeStructure):
    """The compiled kernels of ``structure``: generated and written at first use, then imported.

    The module file is rewritten only when missing or different, so numba's cache of it (keyed by the
    file's time stamp) stays valid across processes.

    Parameters
    ----------
    structure : TreeStructure
        The tree's structure.

    Returns
    -------
    module
        The generated module (see :func:`generate_source`); ``module.GENERATED_NOW`` says whether this
        process wrote its file.
    """
    key = structure.key()
    with _LOCK:
        if key in _LOADED:
            return _LOADED[key]
        path = cache_dir() / f"k{key}.py"
        source = generate_source(structure)
        written = not path.exists() or path.read_text() != source
        if written:
            _write_atomic(path, source)
        name = f"trikedyn_generated_k{key}"
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            del sys.modules[name]
            raise
        module.GENERATED_NOW = written
        _LOADED[key] = module
        return module


def kernels_for_tree(tree):
    """The compiled kernels of a :class:`~trikedyn.model.topology.Tree` (or a plant with its arrays).

    Parameters
    ----------
    tree : Tree or Plant
        Anything with ``parent``, ``jtype``, ``jaxis``, ``tree_e``, ``tree_r``, ``h`` and ``ibar``.

    Returns
    -------
    module
        See :func:`kernels`.
    """
    return kernels(TreeStructure.of(tree.parent, tree.jtype, tree.jaxis, tree.tree_e, tree.tree_r, tree.h, tree.ibar))
