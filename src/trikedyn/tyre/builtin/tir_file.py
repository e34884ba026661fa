"""``magic-formula``: the full Magic Formula of a wheel's ``.tir`` file (:mod:`trikedyn.tyre.pac2002`: PAC2002 /
MF 5.2 / MF 6.1), with its validity ranges (inputs clamped, named by :func:`clamp_names`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..models import COEFFS_WIDTH, MAGIC_FORMULA, TyreModel, TyreSetup, register
from ..pac2002 import (
    N_PACKED,
    VERTICAL_DAMPING,
    VERTICAL_STIFFNESS,
    clamped_names,
    mf_relaxation_lengths,
    mf_stiffness,
)
from ..pac2002_pack import pack
from ..tir_once import read_tir_once


def claims(params, wheel) -> bool:
    """Whether the wheel names a ``.tir`` file.

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
    return wheel.tyre_file is not None


def setup(params, wheel, static_load_N: float) -> TyreSetup:
    """The ``.tir`` file packed for the wheel's side; relaxation lengths at the static load [N].

    A file without relaxation data (zero or NaN lengths) or vertical stiffness falls back to the ``[tyre]``
    section's.

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
    path = Path(wheel.tyre_file)
    tir = read_tir_once(path)
    side = "left" if wheel.y_m > 1e-9 else "right" if wheel.y_m < -1e-9 else None
    row = np.zeros(COEFFS_WIDTH)
    row[:N_PACKED] = pack(tir, side)
    sigma_x, sigma_y = mf_relaxation_lengths(float(static_load_N), 0.0, row[:N_PACKED])
    if not (np.isfinite(sigma_x) and sigma_x > 1e-3):
        sigma_x = params.tyre.relaxation_length_x_m
    if not (np.isfinite(sigma_y) and sigma_y > 1e-3):
        sigma_y = params.tyre.relaxation_length_y_m
    kz, cz = row[VERTICAL_STIFFNESS], row[VERTICAL_DAMPING]
    if not kz > 0:
        kz = params.tyre.vertical_stiffness_N_per_m
    return TyreSetup(MAGIC_FORMULA, row, float(kz), float(cz), float(sigma_x), float(sigma_y), str(path),
                     "magic-formula")


def stiffnesses(coefficients: np.ndarray, fz: float) -> tuple[float, float]:
    """Slip stiffness [N] and cornering stiffness ``dFy/d(-alpha_ISO)`` [N/rad] at the load ``fz`` [N].

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
    kx, kya = mf_stiffness(float(fz), 0.0, coefficients[:N_PACKED])
    return float(kx), float(-kya)


def vertical(params, wheel) -> tuple[float, float, float, str]:
    """The file's vertical stiffness [N/m] (the ``[tyre]`` one where it gives none), damping [N s/m],
    ``FNOMIN`` [N] and its name and family.

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
    tir = read_tir_once(wheel.tyre_file)
    kz = tir.coefficients.get("VERTICAL_STIFFNESS", 0.0) or params.tyre.vertical_stiffness_N_per_m
    cz = tir.coefficients.get("VERTICAL_DAMPING", 0.0) or 0.0
    return float(kz), float(cz), float(tir.coefficients["FNOMIN"]), f"{Path(wheel.tyre_file).name} ({tir.family})"


def clamp_names(mask: int) -> list[str]:
    """Names (``fz``, ``kappa``, ``alpha``, ``gamma``) of the bits set in a clamp mask.

    Parameters
    ----------
    mask : int
        Bit mask of ``CLAMPED_*`` flags.

    Returns
    -------
    list of str
        The names.
    """
    return clamped_names(mask)


register(TyreModel("magic-formula", MAGIC_FORMULA, claims, setup, stiffnesses, vertical, clamp_names))
