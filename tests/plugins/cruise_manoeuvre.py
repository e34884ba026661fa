"""A manoeuvre from outside the package: a straight cruise, judged over its middle; one option, stated once."""

from trikedyn.manoeuvres import paths, speed
from trikedyn.manoeuvres.base import path_manoeuvre
from trikedyn.manoeuvres.registry import Option, register

NAME = "test-cruise"


@register(NAME, "straight cruise (test plug-in)",
          options=(Option("length_m", 80.0, "m", "length of the straight", minimum=20.0, maximum=500.0),))
def build(params, speed_kmh, *, length_m):
    """Drive straight at a constant speed; judged from a quarter to three quarters of the line."""
    line = paths.straight(length_m)
    return path_manoeuvre(NAME, "straight cruise", line, speed.constant(speed_kmh, 1.0), entry_m=0.25 * length_m,
                          exit_m=0.75 * length_m)
