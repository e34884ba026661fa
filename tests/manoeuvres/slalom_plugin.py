"""A manoeuvre defined outside trikedyn, in one file: a slalom of sine half-waves (used by the tests)."""

import numpy as np

from trikedyn.manoeuvres import speed
from trikedyn.manoeuvres.base import path_manoeuvre
from trikedyn.manoeuvres.paths import Path
from trikedyn.manoeuvres.registry import Option, register


@register("test-slalom", "Slalom (test plug-in)", options=(Option("amplitude_m", 1.5, "m", "lateral amplitude"),
                                                           Option("pitch_m", 18.0, "m", "distance between gates")),
          replace=True)
def build(params, speed_kmh, amplitude_m=1.5, pitch_m=18.0):
    """A straight, four sine half-waves, a straight; judged over the half-waves."""
    run_in, gates = 20.0, 4
    x = np.arange(0.0, run_in + gates * pitch_m + 20.0, 0.02)
    u = np.clip((x - run_in) / pitch_m, 0.0, gates)
    k = np.pi / pitch_m
    y = amplitude_m * np.sin(np.pi * u)
    dy = np.where((u > 0) & (u < gates), amplitude_m * k * np.cos(np.pi * u), 0.0)
    ddy = np.where((u > 0) & (u < gates), -amplitude_m * k**2 * np.sin(np.pi * u), 0.0)
    s = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))))
    path = Path("slalom", x, y, s, np.arctan(dy), ddy / (1 + dy**2) ** 1.5)
    entry = float(np.interp(run_in, x, s))
    exit_ = float(np.interp(run_in + gates * pitch_m, x, s))
    return path_manoeuvre("test-slalom", "Slalom", path, speed.constant(speed_kmh, 1.0), entry_m=entry, exit_m=exit_,
                          parameters={"amplitude_m": amplitude_m, "pitch_m": pitch_m})
