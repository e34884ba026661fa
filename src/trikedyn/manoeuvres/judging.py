"""Judging a run against a path: cone strikes and lane-corridor violations of the vehicle's plan-view
footprint along its trajectory."""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .geometry import CONE_RADIUS_M, Path, _array, _number

__all__ = ["cone_clearance", "cone_strikes", "corridor_violations"]

# --------------------------------------------------------------------------------------------------------------
# judging a run
# --------------------------------------------------------------------------------------------------------------
def _trajectory(time_s, x_m, y_m, yaw_rad):
    arrays = []
    for value, name in ((time_s, "time_s"), (x_m, "x_m"), (y_m, "y_m"), (yaw_rad, "yaw_rad")):
        arrays.append(_array(value, name))
    n = arrays[0].size
    for arr, name in zip(arrays[1:], ("x_m", "y_m", "yaw_rad"), strict=True):
        if arr.size != n:
            raise InputError(f"has {arr.size} samples, time_s has {n}", where=name)
    return arrays


def _footprint(footprint):
    try:
        x_rear, x_front, half_width = (float(v) for v in footprint)
    except (TypeError, ValueError):
        raise InputError(
            f"expected (x_rear_m, x_front_m, half_width_m), got {footprint!r}", where="footprint"
        ) from None
    if not (math.isfinite(x_rear) and math.isfinite(x_front) and math.isfinite(half_width)):
        raise InputError("values must be finite", where="footprint")
    if x_front <= x_rear or half_width <= 0.0:
        raise InputError(f"expected x_rear_m < x_front_m and half_width_m > 0, got {footprint!r}", where="footprint")
    return x_rear, x_front, half_width


def cone_strikes(
    path: Path, time_s, x_m, y_m, yaw_rad, footprint, *, cone_radius_m: float = CONE_RADIUS_M
) -> list[dict]:
    """Cones the vehicle footprint touches, each once, with the time of first contact.

    Parameters
    ----------
    path : Path
        The manoeuvre (its ``cones``).
    time_s, x_m, y_m, yaw_rad : array_like
        Trajectory samples: time [s], position of the vehicle reference point [m] and yaw angle [rad].
    footprint : tuple of float
        ``(x_rear_m, x_front_m, half_width_m)``: the vehicle's plan rectangle in its own axes relative to the
        reference point [m] (e.g. ``(-0.6, 2.4, 0.625)`` for a reference point on the rear axle).
    cone_radius_m : float
        Radius of a cone's base circle [m].

    Returns
    -------
    list of dict
        ``{"cone": index, "x_m": ..., "y_m": ..., "time_s": ...}`` ordered by time.

    Notes
    -----
    A cone is struck at a sample when its base circle overlaps the rectangle (distance from the cone
    centre to the rectangle <= radius). Contact between samples is not interpolated: sample finely
    (0.01 s is 0.2 m at 72 km/h).
    """
    t, x, y, yaw = _trajectory(time_s, x_m, y_m, yaw_rad)
    x_rear, x_front, half_width = _footprint(footprint)
    r = _number(cone_radius_m, "cone_radius_m", minimum=0.0)
    cones = path.cones
    if cones.shape[0] == 0 or t.size == 0:
        return []
    from ._cones import first_contacts

    first = first_contacts(x, y, np.cos(yaw), np.sin(yaw), np.ascontiguousarray(cones, dtype=np.float64),
                           x_rear, x_front, half_width, r)
    struck = np.flatnonzero(first >= 0)
    order = struck[np.argsort(first[struck], kind="stable")]
    return [
        {"cone": int(k), "x_m": float(cones[k, 0]), "y_m": float(cones[k, 1]), "time_s": float(t[first[k]])}
        for k in order
    ]


def cone_clearance(path: Path, time_s, x_m, y_m, yaw_rad, footprint, *,
                   cone_radius_m: float = CONE_RADIUS_M) -> np.ndarray:
    """The signed clearance between the footprint and the nearest cone at each sample [m].

    Parameters
    ----------
    path : Path
        The manoeuvre (its ``cones``).
    time_s, x_m, y_m, yaw_rad : array_like
        Trajectory samples: time [s], position of the vehicle reference point [m] and yaw angle [rad].
    footprint : tuple of float
        ``(x_rear_m, x_front_m, half_width_m)`` in vehicle axes relative to the reference point [m].
    cone_radius_m : float
        Radius of a cone's base circle [m].

    Returns
    -------
    ndarray
        Per sample, the smallest over the cones of (distance from the cone centre to the rectangle, negative
        inside it, by the depth) minus the cone radius [m]: positive while every cone is clear, zero at the
        first touch (:func:`cone_strikes`), negative by how far the footprint overlaps a cone. It is
        continuous in the trajectory: the threshold search extrapolates it (+inf without cones).
    """
    t, x, y, yaw = _trajectory(time_s, x_m, y_m, yaw_rad)
    x_rear, x_front, half_width = _footprint(footprint)
    r = _number(cone_radius_m, "cone_radius_m", minimum=0.0)
    cones = path.cones
    out = np.full(t.size, np.inf)
    if cones.shape[0] == 0 or t.size == 0:
        return out
    from ._cones import nearest_clearance

    out = nearest_clearance(x, y, np.cos(yaw), np.sin(yaw), np.ascontiguousarray(cones, dtype=np.float64),
                            x_rear, x_front, half_width, r)
    return out


def corridor_violations(path: Path, time_s, x_m, y_m, yaw_rad, footprint) -> list[dict]:
    """Episodes in which a footprint corner leaves the lane section it is in.

    Parameters
    ----------
    path : Path
        The manoeuvre (its ``corridors``).
    time_s, x_m, y_m, yaw_rad : array_like
        Trajectory samples: time [s], position of the vehicle reference point [m] and yaw angle [rad].
    footprint : tuple of float
        ``(x_rear_m, x_front_m, half_width_m)`` in vehicle axes relative to the reference point [m].

    Returns
    -------
    list of dict
        One entry per corridor and run of consecutive violating samples, ordered by start time:
        ``{"corridor": index, "name", "side": "left"|"right", "time_start_s", "time_end_s",
        "time_worst_s", "worst_excursion_m", "samples"}``; the excursion is how far the worst corner is
        beyond the lane limit [m].

    Notes
    -----
    A corner is judged against a corridor when its x lies within the corridor's x range. The corners
    bound the rectangle's lateral extent, so a straight lane limit is crossed first by a corner.
    """
    t, x, y, yaw = _trajectory(time_s, x_m, y_m, yaw_rad)
    x_rear, x_front, half_width = _footprint(footprint)
    if not path.corridors or t.size == 0:
        return []
    bx = np.array([x_front, x_front, x_rear, x_rear])
    by = np.array([half_width, -half_width, half_width, -half_width])
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    cx = x[:, None] + c * bx - s * by
    cy = y[:, None] + s * bx + c * by
    out = []
    for index, lane in enumerate(path.corridors):
        within = (cx >= lane.x_start_m) & (cx <= lane.x_end_m)
        left = np.where(within, cy - lane.y_max_m, -np.inf)
        right = np.where(within, lane.y_min_m - cy, -np.inf)
        excess = np.maximum(left.max(axis=1), right.max(axis=1))
        bad = excess > 0.0
        if not np.any(bad):
            continue
        edges = np.diff(np.concatenate(([0], bad.astype(np.int8), [0])))
        for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True):
            worst = a + int(np.argmax(excess[a:b]))
            out.append(
                {
                    "corridor": index,
                    "name": lane.name,
                    "side": "left" if left[worst].max() >= right[worst].max() else "right",
                    "time_start_s": float(t[a]),
                    "time_end_s": float(t[b - 1]),
                    "time_worst_s": float(t[worst]),
                    "worst_excursion_m": float(excess[worst]),
                    "samples": int(b - a),
                }
            )
    out.sort(key=lambda v: (v["time_start_s"], v["corridor"]))
    return out
