"""trikedyn.model.lane_workspace: the workspaces of a batch's lanes, stacked."""

import numba
import numpy as np

from trikedyn.model.dynamics import Workspace, workspace
from trikedyn.model.lane_workspace import lane_workspace, stacked_workspace
from trikedyn.model.vehicle import build_model


@numba.njit
def _lane_views(stacked, lane):
    w = lane_workspace(stacked, lane)
    w.tau[0] = 7.0 + lane  # written through the view
    return w


def test_a_lanes_workspace_is_a_view_shaped_as_the_scalar_one(reference):
    parent = build_model(reference).plant.parent
    one = workspace(parent)
    stacked = stacked_workspace(parent, 3)
    assert isinstance(stacked, Workspace)
    for name in Workspace._fields:
        assert getattr(stacked, name).shape == (3, *getattr(one, name).shape), name
    assert not stacked.zero.any()
    lane = _lane_views(stacked, 2)
    assert numba.typeof(lane) == numba.typeof(one)  # the scalar kernels take it as they take a workspace
    assert stacked.tau[2, 0] == 9.0 and np.shares_memory(lane.tau, stacked.tau)
