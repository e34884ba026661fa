"""ISO 14791 single lane change (the paper's SLC)."""

from __future__ import annotations

import numpy as np

from .. import paths, speed
from ..base import path_manoeuvre
from ..registry import Option, register

OPTIONS = (
    Option("lateral_offset_m", 3.5, "m", "lateral displacement of the change, positive to the left"),
    Option("length_m", 50.0, "m", "longitudinal length of the change"),
    Option("run_in_m", 30.0, "m", "straight before the change"),
    Option("lane_width_m", 3.5, "m", "width of the start and target lanes"),
)


@register("slc", "ISO 14791 single lane change", options=OPTIONS)
def build(params, speed_kmh: float, *, lateral_offset_m: float, length_m: float, run_in_m: float,
          lane_width_m: float):
    """One sine period of lateral acceleration at a constant target speed.

    Judged from the start of the change to the end of the target lane (30 m after the change).
    """
    path = paths.single_lane_change(lateral_offset_m=lateral_offset_m, length_m=length_m, run_in_m=run_in_m,
                                    lane_width_m=lane_width_m)
    entry_m = float(np.interp(run_in_m, path.x_m, path.s_m))
    exit_m = float(path.s_m[-1])
    return path_manoeuvre("slc", path.name, path, speed.constant(speed_kmh, 1.0), entry_m=entry_m, exit_m=exit_m,
                          description=path.description)
