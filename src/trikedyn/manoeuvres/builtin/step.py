"""ISO 7401 step steer (lateral transient response), the speed held by the driver."""

from __future__ import annotations

import math

import numpy as np

from .. import speed
from ..base import Manoeuvre, Window
from ..registry import Option, register

OPTIONS = (
    Option("steer_deg", 5.0, "deg", "step angle about the steering axis, positive left"),
    Option("start_s", 1.0, "s", "time of the step"),
    Option("ramp_s", 0.15, "s", "rise time of the steer (ISO 7401: 0.15 s at most)"),
    Option("hold_s", 4.0, "s", "time the angle is held after the ramp"),
)


@register("step", "ISO 7401 step steer", options=OPTIONS, closed_loop=False)
def build(params, speed_kmh: float, *, steer_deg: float, start_s: float, ramp_s: float, hold_s: float):
    """Straight ahead, then the steering turned to a set angle as a fast ramp and held; speed held.

    Judged from the start of the step to the end of the run.
    """
    from ...errors import InputError

    if ramp_s <= 0 or start_s < 0 or hold_s <= 0:
        raise InputError("needs ramp_s > 0, start_s >= 0 and hold_s > 0", where="step")
    angle = math.radians(steer_deg)
    end = start_s + ramp_s + hold_s
    steer = np.array([[0.0, 0.0], [start_s, 0.0], [start_s + ramp_s, angle], [end + 1.0, angle]])
    return Manoeuvre("step", "ISO 7401 step steer", speed.constant(speed_kmh, 1.0), end, Window("time", start_s, end),
                     steer=steer,
                     description=(f"ISO 7401 step steer: {steer_deg:g} deg about the steering axis at {start_s:g} s, "
                                  f"ramp {ramp_s:g} s, held {hold_s:g} s; the driver holds {speed_kmh:g} km/h, judged at "
                                  f"the start of the step."),
                     speed_judged="entry")
