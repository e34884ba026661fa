"""trikedyn.model.lane_workspace: the workspaces of a batch's lanes, stacked."""

from trikedyn.model.dynamics import Workspace, workspace
from trikedyn.model.lane_workspace import stacked_workspace
from trikedyn.model.vehicle import build_model


def test_each_array_of_the_workspace_stacked_over_the_lanes(reference):
    parent = build_model(reference).plant.parent
    one = workspace(parent)
    stacked = stacked_workspace(parent, 3)
    assert isinstance(stacked, Workspace)
    for name in Workspace._fields:
        array = getattr(stacked, name)
        assert array.shape == (3, *getattr(one, name).shape) and array.dtype == getattr(one, name).dtype, name
        assert array[1].flags.c_contiguous  # a lane's rows are contiguous, as the scalar kernels take them
    assert not stacked.zero.any()
