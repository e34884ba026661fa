"""A tyre model from outside the package (Python side): the ``[tyre]`` Magic Formula on the compiled similarity
branch, with half the vertical stiffness and fixed relaxation lengths, on the front wheel only."""

from dataclasses import replace

from trikedyn.tyre.builtin import similarity
from trikedyn.tyre.models import SIMILARITY, TyreModel, register

NAME = "test-soft"
RELAXATION_M = 0.123


def claims(params, wheel):
    """The front wheel, when it has no .tir file."""
    return wheel.name == "front" and wheel.tyre_file is None


def setup(params, wheel, static_load_N):
    """The similarity setup, softer and with fixed relaxation lengths."""
    base = similarity.setup(params, wheel, static_load_N)
    return replace(base, vertical_stiffness_N_per_m=0.5 * base.vertical_stiffness_N_per_m,
                   relaxation_x_m=RELAXATION_M, relaxation_y_m=RELAXATION_M, source="soft tyre", name=NAME)


def stiffnesses(coefficients, fz):
    """The similarity model's slip and cornering stiffnesses, at 80 %."""
    kx, ky = similarity.stiffnesses(coefficients, fz)
    return 0.8 * kx, 0.8 * ky


def vertical(params, wheel):
    """Half the [tyre] vertical stiffness, labelled."""
    kz, cz, fz0, _ = similarity.vertical(params, wheel)
    return 0.5 * kz, cz, fz0, "soft test tyre"


def clamp_names(mask):
    """Bit 1 is the load."""
    return ["fz"] if int(mask) & 1 else []


register(TyreModel(NAME, SIMILARITY, claims, setup, stiffnesses, vertical, clamp_names, priority=10.0))
