"""ISO 7975 braking in a turn: from a steady circle, steering held, brake at a set deceleration."""

from __future__ import annotations

import math

import numpy as np

from .. import paths, speed
from ..base import AFTER_EXIT_S, Manoeuvre, Window, check_duration, time_to_cover, with_run_out
from ..registry import Option, register
from ..speed import SpeedProfile

OPTIONS = (
    Option("radius_m", 20.0, "m", "radius of the initial circle"),
    Option("deceleration_mps2", 3.0, "m/s^2", "target deceleration"),
    Option("settle_s", 5.0, "s", "driving on the circle before the brakes go on"),
    Option("final_speed_ratio", 0.3, "", "braking ends at this fraction of the initial speed"),
    Option("direction", "left", "", "turning direction", choices=("left", "right")),
)
RUN_IN_M = 10.0


@register("braking-in-turn", "ISO 7975 braking in a turn", options=OPTIONS)
def build(params, speed_kmh: float, *, radius_m: float, deceleration_mps2: float, settle_s: float,
          final_speed_ratio: float, direction: str):
    """Steady on a circle, then the steering held still and the speed brought down at a set deceleration.

    Judged from the brake onset to the end of braking (time window); the path (the circle) is kept so the
    deviation from it is recorded.
    """
    from ...errors import InputError

    if deceleration_mps2 <= 0 or not (0 <= final_speed_ratio < 1) or settle_s <= 0 or radius_m <= 0:
        raise InputError("needs deceleration > 0, 0 <= final_speed_ratio < 1, settle_s > 0", where="braking-in-turn")
    v0 = speed_kmh / 3.6
    circle = paths.circle(radius_m, laps=1.0, run_in_m=RUN_IN_M, direction=direction)
    t_brake = time_to_cover(speed.constant(speed_kmh, 1.0), RUN_IN_M + settle_s * v0)
    t_end = check_duration("braking-in-turn", t_brake + v0 * (1.0 - final_speed_ratio) / deceleration_mps2 + 1.0) - 1.0
    grid = np.linspace(0.0, t_end + 1.0, int(math.ceil((t_end + 1.0) / 0.01)) + 1)
    target = np.clip(v0 - deceleration_mps2 * np.clip(grid - t_brake, 0.0, None), final_speed_ratio * v0, None)
    profile = SpeedProfile("record", grid, target)
    covered = RUN_IN_M + v0 * t_end + 30.0 + v0 * 2.0
    path = with_run_out(circle, max(0.0, covered - float(circle.s_m[-1])))
    return Manoeuvre("braking-in-turn", "ISO 7975 braking in a turn", profile, t_end + AFTER_EXIT_S * 0.5,
                     Window("time", t_brake, t_end), path=path, steer_hold_s=t_brake,
                     parameters={"brake_start_s": t_brake, "centre_x_m": RUN_IN_M,
                                 "centre_y_m": radius_m if direction == "left" else -radius_m},
                     description=(f"ISO 7975 braking in a turn: circle R = {radius_m:g} m at {speed_kmh:g} km/h, "
                                  f"steering held and the target speed falling at {deceleration_mps2:g} m/s^2 from "
                                  f"{t_brake:.2f} s to {final_speed_ratio:g} of the initial speed."),
                     speed_judged="entry")
