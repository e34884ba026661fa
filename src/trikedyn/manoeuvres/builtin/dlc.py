"""ISO 3888-1 double lane change (the paper's DLC), or ISO 3888-2 obstacle avoidance."""

from __future__ import annotations

import numpy as np

from .. import paths, speed
from ..base import path_manoeuvre
from ..registry import Option, register

OPTIONS = (
    Option("standard", "ISO 3888-1", "", "ISO 3888-1 (double lane change) or ISO 3888-2 (obstacle avoidance)",
           choices=("ISO 3888-1", "ISO 3888-2")),
    Option("direction", "left", "", "side of the first lane change", choices=("left", "right")),
    Option("run_in_m", 30.0, "m", "straight approach before the entry gate"),
    Option("course_width_m", 0.0, "m", "vehicle width the lanes are laid out for (ISO 3888: the lane widths follow "
           "it); 0: the vehicle's own overall width. Design studies lay them out for the reference vehicle"),
)


@register("dlc", "ISO 3888-1 double lane change", options=OPTIONS)
def build(params, speed_kmh: float, *, standard: str, direction: str, run_in_m: float, course_width_m: float):
    """Double lane change through cones at a constant target speed; lanes from the vehicle's width.

    Judged from the entry gate (start of section 1) to the exit gate (end of the last section); the speed
    is held through the window (ISO 3888-1) or judged at the entry gate (ISO 3888-2, whose driver releases
    the throttle there; here the driver still holds it).
    """
    from ...errors import InputError

    if not course_width_m >= 0:
        raise InputError(f"must be >= 0 m (0: the vehicle's own width), got {course_width_m!r}",
                         where="dlc.course_width_m")
    width = course_width_m if course_width_m > 0 else float(params.body.overall_width_m)
    path = paths.double_lane_change(width, run_in_m=run_in_m, standard=standard, direction=direction)
    x_exit = max(c.x_end_m for c in path.corridors)
    exit_m = float(np.interp(x_exit, path.x_m, path.s_m))
    entry_m = float(np.interp(run_in_m, path.x_m, path.s_m))
    return path_manoeuvre("dlc", path.name, path, speed.constant(speed_kmh, 1.0), entry_m=entry_m, exit_m=exit_m,
                          parameters={"course_width_m": width},
                          description=path.description,
                          speed_judged="window" if standard == "ISO 3888-1" else "entry")
