"""ISO 4138 steady-state circular driving, constant radius, speed raised slowly: the handling diagram."""

from __future__ import annotations

import math

import numpy as np

from .. import paths
from ..base import AFTER_EXIT_S, Manoeuvre, Window, check_duration, with_run_out
from ..registry import Option, register
from ..speed import SpeedProfile

OPTIONS = (
    Option("radius_m", 20.0, "m", "radius of the circle"),
    Option("ay_rate_mps2_per_s", 0.1, "m/s^2/s", "rise of the lateral acceleration per second"),
    Option("max_ay_mps2", 9.0, "m/s^2", "lateral acceleration at which the speed stops rising"),
    Option("settle_s", 5.0, "s", "driving on the circle at the start speed before the rise"),
    Option("direction", "left", "", "turning direction", choices=("left", "right")),
)
RUN_IN_M = 10.0


@register("steady-state-circle", "ISO 4138 steady-state circular driving (rising speed)", options=OPTIONS)
def build(params, speed_kmh: float, *, radius_m: float, ay_rate_mps2_per_s: float, max_ay_mps2: float,
          settle_s: float, direction: str):
    """Round a circle from ``speed_kmh``, the speed raised so that ``v^2 / R`` rises slowly and steadily.

    Judged from the start of the rise to the end (time window); the run normally ends with a lift-off, a
    lost path or the steering lock before ``max_ay_mps2``: the handling analysis says which.
    """
    from ...errors import InputError

    if radius_m <= 0 or ay_rate_mps2_per_s <= 0 or settle_s <= 0:
        raise InputError("needs radius_m, ay_rate_mps2_per_s and settle_s > 0", where="steady-state-circle")
    v0 = speed_kmh / 3.6
    a0 = v0 * v0 / radius_m
    if max_ay_mps2 <= a0:
        raise InputError(f"max_ay_mps2 must exceed v^2/R = {a0:.2f} m/s^2 at the start speed",
                         where="steady-state-circle")
    t_start = RUN_IN_M / v0 + settle_s  # on the circle and settled
    t_rise = check_duration("steady-state-circle", t_start + (max_ay_mps2 - a0) / ay_rate_mps2_per_s + AFTER_EXIT_S)
    t_rise -= AFTER_EXIT_S
    grid = np.linspace(0.0, t_rise, int(math.ceil(t_rise / 0.01)) + 1)
    ay = a0 + ay_rate_mps2_per_s * np.clip(grid - t_start, 0.0, None)
    profile = SpeedProfile("record", grid, np.sqrt(radius_m * ay))
    distance = float(np.trapezoid(profile.speed_mps, grid))
    lap = 2 * math.pi * radius_m
    circle = paths.circle(radius_m, laps=max(1.0, (distance + 40.0) / lap), run_in_m=RUN_IN_M, direction=direction)
    path = with_run_out(circle, 20.0 + AFTER_EXIT_S * float(profile.speed_mps[-1]))
    return Manoeuvre("steady-state-circle", "ISO 4138 steady-state circular driving", profile, t_rise + AFTER_EXIT_S,
                     Window("time", t_start, t_rise), path=path,
                     description=(f"ISO 4138 constant radius R = {radius_m:g} m: {speed_kmh:g} km/h for {settle_s:g} s on the circle, "
                                  f"then v^2/R rising at {ay_rate_mps2_per_s:g} m/s^2 per s up to {max_ay_mps2:g} m/s^2."))
