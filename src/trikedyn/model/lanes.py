"""Dynamics kernels generated over a batch's lanes: the kinematics and forward dynamics of B runs in one call,
vectorised across the runs.

The kernels of :mod:`trikedyn.model.codegen` are straight-line code for one run. Here the same code (the
same :class:`~trikedyn.model._unrolled.UnrolledTree`, the same folding, the same order of operations) is the
body of a loop over ``B`` *lanes*, and each scalar the scalar kernels read or write (``q[k]``,
``tree_e[b, i, j]``, ``out[k]``...) is a *row* of ``B`` consecutive entries, one per lane, of one flat
buffer (:class:`LaneLayout`). ``B`` is a constant of the generated code, so LLVM sees each row's address as
the buffer's start plus a constant plus the lane index and proves the rows apart: the loop over lanes is
innermost and vectorises. The body calls no library function: sines and cosines are
:func:`~trikedyn.model.lane_math.sincos` (branch-free), and a mass matrix that is not positive definite
gives NaN by a select, not a branch.

Measured on the reference machine (AVX-512, numba from the package registry; ``python benchmarks/lanes.py``,
two runs): the forward dynamics of the reference e-trike take 0.073-0.094 us per lane-evaluation in a batch of
8 against 0.38-0.53 us for the scalar generated kernel (5.2-5.6x; 4 lanes 3.3-4.3x, 16 lanes no better than 8),
the kinematics 0.093 against 0.28 us (3x: they store 264 numbers a lane), the dynamics keeping the mass matrix's
factor 0.070 against 0.491 us (7.0x); the tadpole alike (5.5-5.8x, 2.3-2.9x, 5.7x). Every lane does the
scalar kernel's arithmetic in the same order (both take their sines and cosines from ``sincos``), so a lane
equals the scalar kernel bit for bit (``tests/model/test_lanes.py`` asks 1e-12). The lockstep batch evaluates
every stage of a step over its lanes with them (:mod:`trikedyn.simulate.lane_batch`).

The source is written and cached as the scalar kernels are (:func:`~trikedyn.model.codegen.load_module`,
``lanes<key>.py``), keyed by the structure, ``B`` and this module's and :mod:`trikedyn.model.lane_math`'s
source.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._folding import Emitter
from ._unrolled import UnrolledTree
from .codegen import TreeStructure, load_module

__all__ = ["LANE_ARRAYS", "LaneLayout", "lane_functions", "lane_kernels", "lane_source"]

LANE_ARRAYS = (
    ("q", "n"), ("u", "n"), ("tau", "n"), ("fext", "nb,6"), ("gravity", "3"),
    ("tree_e", "nb,3,3"), ("tree_r", "nb,3"), ("mass", "nb"), ("h", "nb,3"), ("ibar", "nb,3,3"),
    ("udot", "n"), ("e", "nb,3,3"), ("r", "nb,3"), ("ew", "nb,3,3"), ("pw", "nb,3"), ("v", "nb,6"),
    ("low", "n,n"),
)
"""The arrays of a lane buffer, in order, with their shapes per lane (``n`` degrees of freedom, ``nb`` bodies):
the scalar kernels' arguments (coordinates [m, rad], velocities, generalised forces, external wrenches, gravity
[m/s^2] and the tree's values), ``udot`` (the forward dynamics' output), the kinematics' outputs and ``low``,
the factor ``H = L^T D L`` of the mass matrix (as the scalar ``forward_dynamics_factor_into`` keeps it)."""


@dataclass(frozen=True)
class LaneLayout:
    """Where each array of :data:`LANE_ARRAYS` lies in a flat lane buffer.

    Attributes
    ----------
    n_bodies : int
        Bodies of the tree (the degrees of freedom are ``n_bodies + 5``).
    lanes : int
        Lanes ``B``: each scalar is a row of ``B`` consecutive entries.
    """

    n_bodies: int
    lanes: int

    def shape(self, name: str) -> tuple[int, ...]:
        """The shape of array ``name`` for one lane.

        Parameters
        ----------
        name : str
            One of :data:`LANE_ARRAYS`.

        Returns
        -------
        tuple of int
            Its shape.
        """
        sizes = {"n": self.n_bodies + 5, "nb": self.n_bodies}
        spec = dict(LANE_ARRAYS)[name]
        return tuple(sizes[d] if d in sizes else int(d) for d in spec.split(","))

    def start(self, name: str) -> int:
        """The first row of array ``name``.

        Parameters
        ----------
        name : str
            One of :data:`LANE_ARRAYS`.

        Returns
        -------
        int
            The row (the entry ``row * lanes`` of the buffer is lane 0's).
        """
        row = 0
        for other, _ in LANE_ARRAYS:
            if other == name:
                return row
            row += int(np.prod(self.shape(other)))
        raise KeyError(name)

    def row(self, name: str, index: tuple) -> int:
        """The row of ``name[index]``.

        Parameters
        ----------
        name : str
            One of :data:`LANE_ARRAYS`.
        index : tuple of int
            The entry's index for one lane.

        Returns
        -------
        int
            The row.
        """
        return self.start(name) + int(np.ravel_multi_index(index, self.shape(name)))

    @property
    def rows(self) -> int:
        """Rows of the buffer."""
        return sum(int(np.prod(self.shape(name))) for name, _ in LANE_ARRAYS)

    def buffer(self) -> np.ndarray:
        """A new zeroed buffer.

        Returns
        -------
        numpy.ndarray
            ``rows * lanes`` floats.
        """
        return np.zeros(self.rows * self.lanes)

    def view(self, buf: np.ndarray, name: str) -> np.ndarray:
        """Array ``name`` of every lane, a view of ``buf`` of shape ``(*shape(name), lanes)``.

        Parameters
        ----------
        buf : numpy.ndarray
            A buffer of this layout (:meth:`buffer`).
        name : str
            One of :data:`LANE_ARRAYS`.

        Returns
        -------
        numpy.ndarray
            The view: ``view(buf, "q")[:, lane]`` is lane ``lane``'s coordinates.
        """
        shape = self.shape(name)
        start = self.start(name) * self.lanes
        return buf[start:start + int(np.prod(shape)) * self.lanes].reshape(*shape, self.lanes)


class _LaneEmitter(Emitter):
    """The emitter of :mod:`trikedyn.model.codegen` with each array entry read from its row at lane ``l``."""

    def __init__(self, layout: LaneLayout):
        super().__init__(indent="        ")
        self.layout = layout

    def address(self, array, index):
        """The code of lane ``l``'s entry ``array[index]``: its row of the buffer."""
        return f"buf[{self.layout.row(array, index) * self.layout.lanes} + l]"


def _body(lines: list[str]) -> str:
    """The body's text; it must call no library sine or cosine (one call keeps the whole loop scalar)."""
    text = "\n".join(lines)
    if "np.cos(" in text or "np.sin(" in text or "math." in text:
        raise RuntimeError("the lane kernels call a library function: the loop over lanes would not vectorise")
    return text


def _function(name: str, doc: str, layout: LaneLayout, body: str) -> str:
    return (f"\n\n@jit\ndef {name}(buf):\n    \"\"\"{doc}\"\"\"\n    for l in range({layout.lanes}):\n{body}\n")


def _dynamics_body(structure: TreeStructure, layout: LaneLayout, with_factor: bool) -> str:
    """The body of the lane forward dynamics (:meth:`~trikedyn.model._unrolled.UnrolledTree.forward_dynamics`),
    then ``udot``, NaN by a select where ``H`` is not positive definite; with ``with_factor`` the factor goes into
    ``low``."""
    em = _LaneEmitter(layout)
    x = UnrolledTree(structure, em).forward_dynamics("low" if with_factor else None)
    em.line("definite = dmin > 0.0")
    for i in range(len(x)):
        em.store("udot", (i,), f"{x[i]} if definite else np.nan")
    return _body(em.lines)


def lane_functions(structure: TreeStructure, lanes: int) -> str:
    """The lane kernels of ``structure`` over ``lanes`` lanes, as source: the three functions of
    :func:`lane_source` without the module's header (for a module that imports ``np``, ``jit`` and
    ``sincos`` itself, as the batch loop's does: :mod:`trikedyn.simulate.batch`).

    Parameters
    ----------
    structure : TreeStructure
        The tree's structure.
    lanes : int
        Lanes ``B``, >= 1.

    Returns
    -------
    str
        The functions' text.
    """
    layout = LaneLayout(len(structure.parent), int(lanes))
    em = _LaneEmitter(layout)
    UnrolledTree(structure, em).store_kinematics()
    kinematics = _function("kinematics_lanes", "Every lane's ``kinematics_into``: ``e``, ``r``, ``ew``, ``pw`` and ``v``.",
                           layout, _body(em.lines))
    dynamics = _function("forward_dynamics_lanes",
                         "Every lane's ``forward_dynamics_into``: ``udot = H^-1 (tau - C)``, NaN where ``H`` is not "
                         "positive definite.", layout, _dynamics_body(structure, layout, with_factor=False))
    factor = _function("forward_dynamics_factor_lanes",
                       "Every lane's ``forward_dynamics_factor_into``: ``forward_dynamics_lanes``, and the factor "
                       "``H = L^T D L`` into ``low`` (``D`` on the diagonal, ``L_ij`` where ``j`` is an ancestor of "
                       "``i``, other entries untouched).", layout, _dynamics_body(structure, layout, with_factor=True))
    return kinematics + dynamics + factor


def lane_source(structure: TreeStructure, lanes: int) -> str:
    """The source of the lane kernels of ``structure`` over ``lanes`` lanes.

    The module defines ``kinematics_lanes(buf)`` (reads ``q``, ``u``, ``tree_e``, ``tree_r``; writes ``e``,
    ``r``, ``ew``, ``pw``, ``v`` as the scalar ``kinematics_into``) and ``forward_dynamics_lanes(buf)``
    (reads ``q``, ``u``, ``tau``, ``fext``, ``gravity`` and the tree's values; writes ``udot``, NaN in a lane
    whose mass matrix is not positive definite) and ``forward_dynamics_factor_lanes(buf)`` (the same, and the
    mass matrix's factor into ``low``), ``buf`` a :class:`LaneLayout` buffer, and ``LANES``.

    Parameters
    ----------
    structure : TreeStructure
        The tree's structure.
    lanes : int
        Lanes ``B``, >= 1.

    Returns
    -------
    str
        The module's text.
    """
    nb = len(structure.parent)
    layout = LaneLayout(nb, int(lanes))
    header = (f'"""Generated by trikedyn.model.lanes for one tree structure and {layout.lanes} lanes: do not edit.\n\n'
              f"Structure key {structure.key()}. Bodies {nb}, degrees of freedom {nb + 5}, buffer rows {layout.rows}.\n"
              '"""\n\nimport numpy as np\n\nfrom trikedyn._jit import jit\nfrom trikedyn.model.lane_math import sincos\n\n'
              f"LANES = {layout.lanes}\nROWS = {layout.rows}\n")
    return header + lane_functions(structure, lanes)


def lane_kernels(structure: TreeStructure, lanes: int):
    """The compiled lane kernels of ``structure`` over ``lanes`` lanes: generated and written at first use,
    then imported (numba's cache keeps the compiled code across processes).

    Parameters
    ----------
    structure : TreeStructure
        The tree's structure.
    lanes : int
        Lanes ``B``, >= 1.

    Returns
    -------
    module
        See :func:`lane_source`.
    """
    lanes = int(lanes)
    if lanes < 1:
        raise ValueError(f"lanes must be >= 1, got {lanes}")
    here = Path(__file__).parent
    own = b"".join((here / name).read_bytes() for name in ("lanes.py", "lane_math.py"))
    key = hashlib.sha256(own + f"{structure.key()}:{lanes}".encode()).hexdigest()[:24]
    return load_module(f"lanes{key}", lambda: lane_source(structure, lanes))
