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
of the dense ``n^3 / 6`` of a Cholesky factorisation. The six base coordinates form a chain. Sines and
cosines are :func:`~trikedyn.model.lane_math.sincos`, the function the lane kernels of
:mod:`trikedyn.model.lanes` must use (it vectorises), so that a run's lane in a batch rounds as its scalar run
does, bit for bit (measured no slower than the C library's here: 6.842 against 6.856 ms a DLC loop).

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
from ._folding import Emitter
from ._unrolled import UnrolledTree

__all__ = ["GENERATOR_VERSION", "TreeStructure", "cache_dir", "generate_source", "kernels", "kernels_for_tree",
           "load_module"]

GENERATOR_VERSION = 3
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

        def rows(values, width):
            """Rows of Python floats (``tolist``: no numpy scalars, the sign of a zero kept)."""
            return np.asarray(values, dtype=np.float64).reshape(nb, width).tolist()

        nb = len(parent)
        return cls(
            parent=tuple(int(p) for p in np.asarray(parent).tolist()),
            jtype=tuple(int(t) for t in np.asarray(jtype).tolist()),
            jaxis=tuple(tuple(row) for row in rows(jaxis, 3)),
            e_const=tuple(tuple(x if x in (0.0, 1.0, -1.0) else None for x in row) for row in rows(tree_e, 9)),
            r_zero=tuple(tuple(x == 0.0 for x in row) for row in rows(tree_r, 3)),
            h_zero=tuple(tuple(x == 0.0 for x in row) for row in rows(h, 3)),
            ibar_zero=tuple(tuple(x == 0.0 for x in row) for row in rows(ibar, 9)),
        )

    def key(self) -> str:
        """A hash of the structure, the generator's version and source (with its emitter's) and the numba options.

        Returns
        -------
        str
            24 hexadecimal digits, the cached module's name.
        """
        here = Path(__file__).parent
        own = b"".join((here / name).read_bytes()
                       for name in ("codegen.py", "_folding.py", "_unrolled.py", "lane_math.py"))
        blob = json.dumps([GENERATOR_VERSION, sorted(FASTMATH), self.parent, self.jtype,
                           [[float(a).hex() for a in ax] for ax in self.jaxis], self.e_const, self.r_zero,
                           self.h_zero, self.ibar_zero])
        return hashlib.sha256(own + blob.encode()).hexdigest()[:24]


_HEADER = '''"""Generated by trikedyn.model.codegen (version {version}) for one tree structure: do not edit.

Key {key}. Bodies {nb}, degrees of freedom {n}. Parents {parent}, joint types {jtype}.
"""

import numpy as np

from trikedyn._jit import jit
from trikedyn.model.lane_math import sincos

N_DOF = {n}
'''


def _function(name, args, doc, body_lines):
    return f"\n\n@jit\ndef {name}({', '.join(args)}):\n    \"\"\"{doc}\"\"\"\n" + "\n".join(body_lines) + "\n"


def _forward_dynamics_lines(structure, with_factor):
    """The body of the forward dynamics (:meth:`~trikedyn.model._unrolled.UnrolledTree.forward_dynamics`), then
    ``out``, or NaN when ``H`` is not positive definite; with ``with_factor`` the factor goes into ``factor``."""
    em = Emitter()
    x = UnrolledTree(structure, em).forward_dynamics("factor" if with_factor else None)
    em.line("if dmin > 0.0:")
    for i in range(len(x)):
        em.line(f"    out[{i}] = {x[i]}")
    em.line("else:")
    em.line("    out[:] = np.nan")
    return em.lines


def generate_source(structure: TreeStructure) -> str:
    """The Python source of the kernels for ``structure``.

    The module defines ``kinematics_into`` (the joint transforms, world poses and body velocities),
    ``rnea_into``/``rnea`` (``H udot + C``), ``mass_matrix_into``/``mass_matrix`` and
    ``forward_dynamics_into``/``forward_dynamics_generated`` (``du/dt``, NaN if ``H`` is not positive
    definite) and ``forward_dynamics_factor_into`` (the same, keeping the factorisation of ``H`` for
    :func:`trikedyn.simulate.exponential.ltdl_inverse_diagonal`), with the arguments of their generic namesakes in :mod:`trikedyn.model.dynamics` less the
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
    tree = UnrolledTree(structure, em)
    tree.transforms()
    tau = tree.rnea([em.load("udot", k) for k in range(n)])
    for i in range(n):
        em.line(f"out[{i}] = {tau[i]}")
    src.append(_function("rnea_into", ["q", "u", "udot", "fext", "gravity", *values, "out"],
                         "Generalised forces ``H udot + C(q, u, f_ext)`` into ``out``.", em.lines))

    em = Emitter()
    tree = UnrolledTree(structure, em)
    tree.transforms()
    hmat = tree.crba()
    for i in range(n):
        for j in range(n):
            em.line(f"out[{i}, {j}] = {hmat.get((max(i, j), min(i, j)), 0.0)}")
    src.append(_function("mass_matrix_into", ["q", *values, "out"], "Mass matrix ``H(q)`` into ``out``.",
                         em.lines))

    em = Emitter()
    UnrolledTree(structure, em).store_kinematics()
    src.append(_function("kinematics_into", ["q", "u", "tree_e", "tree_r", "e", "r", "ew", "pw", "v"],
                         "The joint transforms ``e``, ``r``, the world poses ``ew``, ``pw`` [m] and the body velocities "
                         "``v`` [rad/s, m/s] at ``q``, ``u``, as the generic ``joint_transforms_into``, "
                         "``world_transforms_into`` and ``body_velocities_into``.", em.lines))

    src.append(_function("forward_dynamics_into", ["q", "u", "tau", "fext", "gravity", *values, "out"],
                         "``du/dt = H^-1 (tau - C)`` into ``out``; NaN if ``H`` is not positive definite.",
                         _forward_dynamics_lines(structure, with_factor=False)))
    src.append(_function("forward_dynamics_factor_into", ["q", "u", "tau", "fext", "gravity", *values, "out", "factor"],
                         "``forward_dynamics_into``, and the factorisation ``H = L^T D L`` into ``factor`` (n, n): "
                         "``D`` on the diagonal, ``L_ij`` where ``j`` is an ancestor of ``i``, other entries untouched.",
                         _forward_dynamics_lines(structure, with_factor=True)))

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
    return load_module(f"k{structure.key()}", lambda: generate_source(structure))


def load_module(stem: str, source):
    """Import the generated module ``<cache>/<stem>.py``, writing it first when missing or different.

    The file is rewritten only when its text differs from ``source``, so numba's cache of it (keyed by the
    file's time stamp) stays valid across processes. One module per ``stem`` and process.

    Parameters
    ----------
    stem : str
        The file's name without ``.py``: a prefix and a key that changes whenever the source does.
    source : callable
        Returns the module's source (called only when this process has not imported ``stem`` yet).

    Returns
    -------
    module
        The module; ``module.GENERATED_NOW`` says whether this process wrote its file.
    """
    with _LOCK:
        if stem in _LOADED:
            return _LOADED[stem]
        path = cache_dir() / f"{stem}.py"
        source = source()
        written = not path.exists() or path.read_text() != source
        if written:
            _write_atomic(path, source)
        name = f"trikedyn_generated_{stem}"
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            del sys.modules[name]
            raise
        module.GENERATED_NOW = written
        _LOADED[stem] = module
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
