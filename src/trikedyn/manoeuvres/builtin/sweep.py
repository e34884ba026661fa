"""ISO 7401 frequency response: a sine-sweep steer, the speed held by the driver."""

from __future__ import annotations

import math

import numpy as np

from .. import speed
from ..base import Manoeuvre, Window, check_duration
from ..registry import Option, register
from ..steer import sine_sweep

OPTIONS = (
    Option("amplitude_deg", 1.0, "deg", "steer amplitude about the steering axis"),
    Option("f_start_hz", 0.2, "Hz", "start frequency"),
    Option("f_end_hz", 3.0, "Hz", "end frequency"),
    Option("sweep_s", 20.0, "s", "duration of the sweep"),
    Option("start_s", 1.0, "s", "start of the sweep"),
    Option("method", "logarithmic", "", "frequency law: equal time per octave, or linear",
           choices=("logarithmic", "linear")),
)


@register("sweep", "ISO 7401 sine-sweep steer (frequency response)", options=OPTIONS, closed_loop=False)
def build(params, speed_kmh: float, *, amplitude_deg: float, f_start_hz: float, f_end_hz: float, sweep_s: float,
          start_s: float, method: str):
    """A sine sweep of the steer with tapered ends; speed held. Judged over the sweep."""
    end = check_duration("sweep", start_s + sweep_s + 0.5) - 0.5
    t = np.arange(0.0, end + 0.5, 0.005)
    table = np.column_stack((t, sine_sweep(t, math.radians(amplitude_deg), f_start_hz, f_end_hz, sweep_s, start_s,
                                           method=method)))
    return Manoeuvre("sweep", "ISO 7401 sine-sweep steer", speed.constant(speed_kmh, 1.0), end + 0.5,
                     Window("time", start_s, end), steer=table,
                     description=(f"{method.capitalize()} sine sweep {f_start_hz:g}-{f_end_hz:g} Hz over {sweep_s:g} s, amplitude "
                                  f"{amplitude_deg:g} deg about the steering axis; the driver holds {speed_kmh:g} km/h."))
