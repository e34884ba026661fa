"""The workspaces of a batch's lanes: the scratch arrays of :func:`~trikedyn.model.dynamics.workspace`, one
stack per array with the lanes on its first axis (``ws.ew[lane]`` is lane ``lane``'s ``ew``).

One stack of arrays rather than a list of workspaces: reading a workspace out of a list holds and releases each
of its twenty arrays (about 0.2 us), and the lockstep batch (:mod:`trikedyn.simulate.lane_batch`) reads the
lanes' arrays several times per lane and stage.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from .dynamics import Workspace, workspace

__all__ = ["stacked_workspace"]


@jit(inline="always")
def _stacked(a, lanes):
    """An array of ``lanes`` copies of ``a``'s shape, uninitialised (as the workspace's)."""
    return np.empty((lanes,) + a.shape)


@jit
def stacked_workspace(parent, lanes):
    """A :data:`~trikedyn.model.dynamics.Workspace` for ``lanes`` lanes: each array of
    :func:`~trikedyn.model.dynamics.workspace` with a first axis over the lanes (``zero`` zeros).

    Parameters
    ----------
    parent : numpy.ndarray of int
        The tree's parent bodies.
    lanes : int
        Lanes.

    Returns
    -------
    Workspace
        The stacked arrays.
    """
    w = workspace(parent)
    return Workspace(_stacked(w.e, lanes), _stacked(w.r, lanes), _stacked(w.ew, lanes), _stacked(w.pw, lanes),
                     _stacked(w.v, lanes), _stacked(w.a, lanes), _stacked(w.f, lanes), _stacked(w.fext, lanes),
                     _stacked(w.mc, lanes), _stacked(w.hc, lanes), _stacked(w.ic, lanes), _stacked(w.hmat, lanes),
                     _stacked(w.low, lanes), _stacked(w.vec, lanes), _stacked(w.t6a, lanes), _stacked(w.t6b, lanes),
                     _stacked(w.t33, lanes), _stacked(w.tau, lanes), _stacked(w.bias, lanes),
                     np.zeros((lanes,) + w.zero.shape))
