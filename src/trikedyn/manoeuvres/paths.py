"""Manoeuvre geometry: reference lines, cones and lane corridors.

A :class:`Path` is what the driver model follows: a reference line sampled uniformly in arc length (every
``ds <= 0.05 m``) as plain float64 arrays, with its heading and curvature, plus the cones and the lane
corridors that judge the run. Axes are ISO 8855 (x forward, y left). Every path starts at the origin,
heading +x, with a straight run-in, and ends with a straight run-out (:func:`circle` excepted: it ends on
the circle).

Manoeuvres
----------
- :func:`double_lane_change`: ISO 3888-1 double lane change (default) or ISO 3888-2 obstacle avoidance;
- :func:`single_lane_change`: ISO 14791 single lane change (one sine period of lateral acceleration);
- :func:`circle`: ISO 4138 steady-state circular driving, constant radius;
- :func:`straight`;
- :func:`path_from_csv`: a measured or designed line from a CSV file, smoothed and resampled.

Judging a run
-------------
:func:`cone_strikes` and :func:`corridor_violations` take the vehicle trajectory (a reference point and the
yaw angle at each sample) and the vehicle's footprint rectangle.

The standards prescribe cones, not a line to drive: the reference lines here are our choice and each
function's docstring says which. All functions are pure; arrays are returned C-contiguous.


The pieces live in :mod:`.geometry` (:class:`Path`, :class:`Corridor`), :mod:`.tracks` (the standard
tracks), :mod:`.csv_path` (CSV import) and :mod:`.judging` (cones, corridors); this module gathers them.
"""

from .csv_path import path_from_csv
from .geometry import CONE_RADIUS_M, DS_MAX_M, MAX_LENGTH_M, Corridor, Path
from .judging import cone_clearance, cone_strikes, corridor_violations
from .tracks import circle, double_lane_change, single_lane_change, straight

__all__ = [
    "CONE_RADIUS_M",
    "DS_MAX_M",
    "MAX_LENGTH_M",
    "Corridor",
    "Path",
    "circle",
    "cone_clearance",
    "cone_strikes",
    "corridor_violations",
    "double_lane_change",
    "path_from_csv",
    "single_lane_change",
    "straight",
]
