"""The compiled footprint-to-cone geometry (``manoeuvres/_cones.py``) against the array expressions it replaced,
to the last bit: first contacts (cone strikes) and the signed clearance to the nearest cone."""

import numpy as np
import pytest

from trikedyn.manoeuvres import CONE_RADIUS_M, double_lane_change, single_lane_change
from trikedyn.manoeuvres.judging import cone_clearance, cone_strikes

FOOTPRINT = (-0.4, 2.6, 0.625)


def _reference_geometry(path, x, y, yaw, footprint, r):
    """The ``(samples, cones)`` arrays of the numpy implementation (until the compiled kernels)."""
    x_rear, x_front, half_width = footprint
    cones = path.cones
    c, s = np.cos(yaw), np.sin(yaw)
    dx = cones[None, :, 0] - x[:, None]
    dy = cones[None, :, 1] - y[:, None]
    bx = c[:, None] * dx + s[:, None] * dy
    by = -s[:, None] * dx + c[:, None] * dy
    ex = bx - np.clip(bx, x_rear, x_front)
    ey = by - np.clip(by, -half_width, half_width)
    return bx, by, ex, ey


def _reference_strikes(path, t, x, y, yaw, footprint, r=CONE_RADIUS_M):
    _, _, ex, ey = _reference_geometry(path, x, y, yaw, footprint, r)
    hit = ex * ex + ey * ey <= r * r
    first = np.where(hit.any(axis=0), np.argmax(hit, axis=0), -1)
    struck = np.flatnonzero(first >= 0)
    order = struck[np.argsort(first[struck], kind="stable")]
    return [{"cone": int(k), "x_m": float(path.cones[k, 0]), "y_m": float(path.cones[k, 1]),
             "time_s": float(t[first[k]])} for k in order]


def _reference_clearance(path, x, y, yaw, footprint, r=CONE_RADIUS_M):
    x_rear, x_front, half_width = footprint
    bx, by, ex, ey = _reference_geometry(path, x, y, yaw, footprint, r)
    outside = np.hypot(ex, ey)
    depth = np.minimum(np.minimum(bx - x_rear, x_front - bx), np.minimum(by + half_width, half_width - by))
    signed = np.where((ex == 0.0) & (ey == 0.0), -depth, outside)
    return signed.min(axis=1) - r


def _wandering(path, rng, n=1500, wander_m=1.2):
    """A trajectory along the path's line, off it by a smooth random lateral error, yawing about its heading."""
    i = np.linspace(0, path.x_m.size - 1, n).astype(int)
    phase = rng.uniform(0, 2 * np.pi, 3)
    u = np.linspace(0, 1, n)
    off = wander_m * (np.sin(7 * u + phase[0]) + 0.5 * np.sin(23 * u + phase[1]))
    yaw = path.heading_rad[i] + 0.15 * np.sin(11 * u + phase[2])
    x = path.x_m[i] - off * np.sin(path.heading_rad[i])
    y = path.y_m[i] + off * np.cos(path.heading_rad[i])
    return np.linspace(0, 10, n), x, y, yaw


@pytest.mark.parametrize("path", [double_lane_change(1.25), single_lane_change()], ids=["dlc", "slc"])
def test_strikes_and_clearance_equal_the_array_reference_to_the_last_bit(path):
    rng = np.random.default_rng(7)
    struck = 0
    for _ in range(25):
        t, x, y, yaw = _wandering(path, rng, wander_m=rng.uniform(0.0, 2.5))
        new = cone_strikes(path, t, x, y, yaw, FOOTPRINT)
        assert new == _reference_strikes(path, t, x, y, yaw, FOOTPRINT)
        struck += len(new)
        np.testing.assert_array_equal(cone_clearance(path, t, x, y, yaw, FOOTPRINT),
                                      _reference_clearance(path, x, y, yaw, FOOTPRINT), strict=True)
    assert struck > 0  # the trajectories do strike cones


def test_a_cone_inside_the_footprint_has_a_negative_clearance_by_its_depth():
    """Samples placed so that cone centres fall inside the rectangle and exactly on its edges."""
    path = single_lane_change()
    cx, cy = path.cones[:, 0], path.cones[:, 1]
    x = np.concatenate((cx - 1.0, cx - 2.6, cx + 0.4, cx - 1.0))
    y = np.concatenate((cy, cy, cy, cy - 0.625))
    yaw = np.zeros_like(x)
    t = np.arange(x.size) * 0.01
    got = cone_clearance(path, t, x, y, yaw, FOOTPRINT)
    np.testing.assert_array_equal(got, _reference_clearance(path, x, y, yaw, FOOTPRINT), strict=True)
    assert np.all(got[: cx.size] < -CONE_RADIUS_M)
    assert cone_strikes(path, t, x, y, yaw, FOOTPRINT) == _reference_strikes(path, t, x, y, yaw, FOOTPRINT)


@pytest.mark.parametrize("path", [double_lane_change(1.25), single_lane_change()], ids=["dlc", "slc"])
def test_near_ties_between_cones_keep_the_nearest_to_the_last_bit(path):
    """The kernel takes ``hypot`` only for cones near the smallest squared distance: positions midway between
    two cones (the lane's two limits), nudged by a few units in the last place, against the reference."""
    cones = path.cones
    a, b = np.triu_indices(cones.shape[0], 1)
    mid_x = 0.5 * (cones[a, 0] + cones[b, 0])
    mid_y = 0.5 * (cones[a, 1] + cones[b, 1])
    x, y = [], []
    for steps in range(-3, 4):
        x.append(mid_x - 1.0 + steps * np.spacing(mid_x))  # the rectangle spans x - 0.4 .. x + 2.6
        y.append(mid_y + steps * np.spacing(np.abs(mid_y) + 1.0))
    x, y = np.concatenate(x), np.concatenate(y)
    yaw = np.zeros_like(x)
    t = np.arange(x.size) * 0.01
    narrow = (-0.4, 2.6, 0.05)  # a narrow footprint: the cones on both sides are outside it, nearly tied
    for footprint in (FOOTPRINT, narrow):
        np.testing.assert_array_equal(cone_clearance(path, t, x, y, yaw, footprint),
                                      _reference_clearance(path, x, y, yaw, footprint), strict=True)
