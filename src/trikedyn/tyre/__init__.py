"""Tyre models: the Magic Formula with load dependence and combined slip, compiled with numba.

:func:`tyre_coefficients` turns a :class:`~trikedyn.params.schema.TyreSpec` into a float64 vector (its
entries named by the constants ``KZ``, ``CZ``, ``FZ0``, ...); the force functions are
``numba.njit(cache=True)`` functions of scalars and that vector, callable from a compiled time loop.
The module :mod:`trikedyn.tyre.magic_formula` documents the axes, signs and methods.
"""

from .magic_formula import (
    CORNERING_STIFFNESS_FACTOR,
    CORNERING_STIFFNESS_LOAD_FACTOR,
    CURVATURE_X,
    CURVATURE_Y,
    CZ,
    FZ0,
    KZ,
    LOAD_SENSITIVITY,
    MU_FLOOR_FRACTION,
    MU_X,
    MU_Y,
    N_COEFFS,
    RHO_LINEAR,
    ROLLING_RESISTANCE,
    SHAPE_X,
    SHAPE_Y,
    SLIP_STIFFNESS_FACTOR,
    U_PEAK_X,
    U_PEAK_Y,
    combined_forces,
    cornering_stiffness,
    magic_formula_curve,
    peak_friction,
    peak_input,
    pure_lateral,
    pure_longitudinal,
    rolling_resistance_moment,
    slip_quantities,
    slip_stiffness,
    tyre_coefficients,
    tyre_forces,
    vertical_force,
)

__all__ = [
    "CORNERING_STIFFNESS_FACTOR",
    "CORNERING_STIFFNESS_LOAD_FACTOR",
    "CURVATURE_X",
    "CURVATURE_Y",
    "CZ",
    "FZ0",
    "KZ",
    "LOAD_SENSITIVITY",
    "MU_FLOOR_FRACTION",
    "MU_X",
    "MU_Y",
    "N_COEFFS",
    "RHO_LINEAR",
    "ROLLING_RESISTANCE",
    "SHAPE_X",
    "SHAPE_Y",
    "SLIP_STIFFNESS_FACTOR",
    "U_PEAK_X",
    "U_PEAK_Y",
    "combined_forces",
    "cornering_stiffness",
    "magic_formula_curve",
    "peak_friction",
    "peak_input",
    "pure_lateral",
    "pure_longitudinal",
    "rolling_resistance_moment",
    "slip_quantities",
    "slip_stiffness",
    "tyre_coefficients",
    "tyre_forces",
    "vertical_force",
]

# Tyre property files (.tir) and the full Magic Formula (PAC2002 / MF 5.2 / MF 6.1): see trikedyn.tyre.tir,
# trikedyn.tyre.pac2002 (compiled kernels, ISO signs) and trikedyn.tyre.mf_figures (stiffnesses, peaks, plots).
from . import mf_figures, pac2002, tir  # noqa: E402
from .tir import read_tir  # noqa: E402
from .tir_properties import TyreProperties  # noqa: E402

__all__ += ["TyreProperties", "mf_figures", "pac2002", "read_tir", "tir"]
