"""Fishhook: the NHTSA-style steer reversal, the rollover test for light vehicles and three-wheelers."""

from __future__ import annotations

import math

import numpy as np

from .. import speed
from ..base import Manoeuvre, Window
from ..registry import Option, register

OPTIONS = (
    Option("scale", 6.5, "", "amplitude as a multiple of the steer that gives ay_ref_g (NHTSA: 6.5)"),
    Option("ay_ref_g", 0.3, "g", "lateral acceleration of the reference steer (NHTSA: 0.3 g)"),
    Option("ref_speed_kmh", 30.0, "km/h", "speed at which the reference steer is taken"),
    Option("dwell_s", 0.25, "s", "hold at the first peak before the reversal (NHTSA: 0.25 s)"),
    Option("hold_s", 3.0, "s", "hold at the second peak (NHTSA: 3 s)"),
    Option("rate_deg_per_s", 0.0, "deg/s", "steering rate about the steering axis (0: the vehicle's fastest)"),
    Option("start_s", 1.0, "s", "start of the first steer"),
    Option("direction", "left", "", "side of the first steer", choices=("left", "right")),
)


@register("fishhook", "Fishhook steer reversal (NHTSA-style)", options=OPTIONS, closed_loop=False)
def build(params, speed_kmh: float, *, scale: float, ay_ref_g: float, ref_speed_kmh: float, dwell_s: float,
          hold_s: float, rate_deg_per_s: float, start_s: float, direction: str):
    """Steer to A, dwell, reverse to -A, hold, return to centre; speed held. Judged from the first steer
    to the end of the hold.

    ``A = scale x delta_ref``, with ``delta_ref`` the steer about the steering axis that gives ``ay_ref_g``
    in steady turning at ``ref_speed_kmh``, from the linear single-track model at the static loads
    (:func:`trikedyn.model.linear.single_track`). NHTSA's fishhook (49 CFR 575.106 test procedure) takes it
    from a slowly increasing steer at 50 mph; a trike's test speeds are lower, hence ``ref_speed_kmh``.
    The amplitude is capped at the steering lock. The dwell is fixed (NHTSA's version 1 ties it to the
    roll rate; the fixed 250 ms is its common simplification). NHTSA coasts (throttle off); here the
    speed is held, so that the threshold search compares speeds, not decelerations.
    """
    from ...errors import InputError
    from ...model.linear import single_track
    from ...model.vehicle import build_model

    if scale <= 0 or ay_ref_g <= 0 or ref_speed_kmh <= 0 or dwell_s < 0 or hold_s <= 0 or start_s < 0:
        raise InputError("needs positive scale, ay_ref_g, ref_speed_kmh and hold_s", where="fishhook")
    track = single_track(build_model(params))
    cos_rake = math.cos(math.radians(params.steering.axis_angle_deg))
    ref = track.road_steer_rad(ref_speed_kmh / 3.6, ay_ref_g * 9.80665) / cos_rake
    lock = math.radians(params.steering.max_angle_deg)
    amplitude = min(scale * ref, 0.95 * lock)
    rate = math.radians(rate_deg_per_s if rate_deg_per_s > 0 else params.steering.max_rate_deg_per_s)
    sign = 1.0 if direction == "left" else -1.0
    t1 = start_s + amplitude / rate
    t2 = t1 + dwell_s
    t3 = t2 + 2 * amplitude / rate
    t4 = t3 + hold_s
    t5 = t4 + amplitude / rate
    steer = np.array([[0.0, 0.0], [start_s, 0.0], [t1, amplitude], [t2, amplitude], [t3, -amplitude],
                      [t4, -amplitude], [t5, 0.0], [t5 + 1.0, 0.0]])
    steer[:, 1] *= sign
    return Manoeuvre("fishhook", "Fishhook (NHTSA-style)", speed.constant(speed_kmh, 1.0), t4 + 0.5,
                     Window("time", start_s, t4), steer=steer,
                     parameters={"rate_deg_per_s": math.degrees(rate), "reference_steer_deg": math.degrees(ref),
                                 "amplitude_deg": math.degrees(amplitude)},
                     description=(f"Fishhook: {math.degrees(amplitude):.2f} deg about the steering axis "
                                  f"({scale:g} x {math.degrees(ref):.2f} deg for {ay_ref_g:g} g at {ref_speed_kmh:g} "
                                  f"km/h{', capped at the lock' if amplitude < scale * ref else ''}), "
                                  f"{math.degrees(rate):.0f} deg/s, dwell {dwell_s:g} s, hold {hold_s:g} s; "
                                  f"the driver holds {speed_kmh:g} km/h; the speed is judged at the first steer."),
                     speed_judged="entry")
