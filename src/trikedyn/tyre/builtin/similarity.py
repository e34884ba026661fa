"""``similarity``: the reduced Magic Formula with similarity combined slip, from the vehicle file's ``[tyre]``
section (:mod:`trikedyn.tyre.magic_formula`; the paper's "Pacejka similarity" tyre); every wheel without a
``.tir`` file."""

from __future__ import annotations

import numpy as np

from ..magic_formula import cornering_stiffness, slip_stiffness
from ..mf_coefficients import N_COEFFS, tyre_coefficients
from ..models import COEFFS_WIDTH, SIMILARITY, TyreModel, TyreSetup, register


def claims(params, wheel) -> bool:
    """Whether the wheel has no ``.tir`` file (its tyre is the ``[tyre]`` section).

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    wheel : WheelSpec
        One of its wheels.

    Returns
    -------
    bool
        Whether this model takes the wheel.
    """
    return wheel.tyre_file is None


def setup(params, wheel, static_load_N: float) -> TyreSetup:
    """The ``[tyre]`` section's coefficients, springs and relaxation lengths (the load [N] is not used).

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    wheel : WheelSpec
        One of its wheels.
    static_load_N : float
        The wheel's static load [N].

    Returns
    -------
    TyreSetup
        Kernel id, coefficient row, vertical stiffness [N/m] and damping [N s/m], relaxation lengths [m], source and name.
    """
    spec = params.tyre
    row = np.zeros(COEFFS_WIDTH)
    row[:N_COEFFS] = tyre_coefficients(spec)
    return TyreSetup(SIMILARITY, row, spec.vertical_stiffness_N_per_m, spec.vertical_damping_Ns_per_m,
                     spec.relaxation_length_x_m, spec.relaxation_length_y_m, "[tyre]", "similarity")


def stiffnesses(coefficients: np.ndarray, fz: float) -> tuple[float, float]:
    """Slip stiffness [N] and cornering stiffness [N/rad] at the load ``fz`` [N].

    Parameters
    ----------
    coefficients : numpy.ndarray
        The wheel's coefficient row.
    fz : float
        Vertical load [N].

    Returns
    -------
    kx : float
        Slip stiffness [N].
    ky : float
        Cornering stiffness [N/rad], > 0 for a normal tyre.
    """
    return float(slip_stiffness(float(fz), coefficients)), float(cornering_stiffness(float(fz), coefficients))


def vertical(params, wheel) -> tuple[float, float, float, str]:
    """The ``[tyre]`` section's vertical stiffness [N/m], damping [N s/m] and nominal load [N].

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    wheel : WheelSpec
        One of its wheels.

    Returns
    -------
    kz : float
        Vertical stiffness [N/m].
    cz : float
        Vertical damping [N s/m].
    fz0 : float
        Nominal load [N].
    label : str
        Where they come from, for the audit.
    """
    spec = params.tyre
    return (spec.vertical_stiffness_N_per_m, spec.vertical_damping_Ns_per_m, spec.nominal_load_N,
            "Magic Formula of [tyre]")


register(TyreModel("similarity", SIMILARITY, claims, setup, stiffnesses, vertical))
