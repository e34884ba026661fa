"""Steady circular driving at a constant speed (ISO 4138, constant radius, one speed)."""

from __future__ import annotations

import math

from .. import paths, speed
from ..base import path_manoeuvre
from ..registry import Option, register

OPTIONS = (
    Option("radius_m", 20.0, "m", "radius of the circle"),
    Option("laps", 1.0, "", "laps judged"),
    Option("direction", "left", "", "turning direction", choices=("left", "right")),
    Option("settle_s", 4.0, "s", "driving on the circle before the judged window opens"),
)
RUN_IN_M = 10.0


@register("circle", "ISO 4138 steady circle, constant speed", options=OPTIONS)
def build(params, speed_kmh: float, *, radius_m: float, laps: float, direction: str, settle_s: float):
    """Drive round a circle at a constant target speed; judged once the run has settled on the circle.

    The window opens ``settle_s`` of driving after the circle's entry (the driver's entry transient dies
    out) and closes after ``laps`` laps; the path goes on round the circle beyond it.
    """
    v = speed_kmh / 3.6
    lap = 2 * math.pi * radius_m
    settle_m = max(0.0, settle_s * v)
    path = paths.circle(radius_m, laps=laps + settle_m / lap, run_in_m=RUN_IN_M, direction=direction)
    entry_m = RUN_IN_M + settle_m
    return path_manoeuvre("circle", path.name, path, speed.constant(speed_kmh, 1.0), entry_m=entry_m,
                          exit_m=entry_m + laps * lap,
                          description=path.description + f" Judged over {laps:g} lap(s) after {settle_s:g} s on the circle.")
