"""Manoeuvres: the paths the driver follows (ISO 3888-1/-2, ISO 14791, ISO 4138, CSV) and target speeds.

Geometry lives in :mod:`.paths`, speed profiles in :mod:`.speed`; both are plain numpy arrays in thin frozen
dataclasses, ready for the compiled time loop.
"""

from .paths import (
    CONE_RADIUS_M,
    DS_MAX_M,
    Corridor,
    Path,
    circle,
    cone_strikes,
    corridor_violations,
    double_lane_change,
    path_from_csv,
    single_lane_change,
    straight,
)
from .speed import SpeedProfile, constant, from_record, linear

__all__ = [
    "CONE_RADIUS_M",
    "DS_MAX_M",
    "Corridor",
    "Path",
    "SpeedProfile",
    "circle",
    "cone_strikes",
    "constant",
    "corridor_violations",
    "double_lane_change",
    "from_record",
    "linear",
    "path_from_csv",
    "single_lane_change",
    "straight",
]
