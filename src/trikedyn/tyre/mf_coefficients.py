"""The coefficient vector of the similarity Magic Formula tyre (:mod:`trikedyn.tyre.magic_formula`): its
layout (the integer constants ``KZ``, ``CZ``, ``FZ0``, ... that index it) and its building from a
:class:`~trikedyn.params.schema.TyreSpec` (:func:`tyre_coefficients`, in Python, once per vehicle), the peak
inputs of the curves solved here once (:func:`peak_input`). The compiled force functions read the vector.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from trikedyn.errors import ParameterError

__all__ = ["CORNERING_STIFFNESS_FACTOR", "CORNERING_STIFFNESS_LOAD_FACTOR", "CURVATURE_X", "CURVATURE_Y", "CZ", "FZ0",
           "KZ", "LOAD_SENSITIVITY", "MU_X", "MU_Y", "N_COEFFS", "ROLLING_RESISTANCE", "SHAPE_X", "SHAPE_Y",
           "SLIP_STIFFNESS_FACTOR", "U_PEAK_X", "U_PEAK_Y", "peak_input", "tyre_coefficients"]


# ---- coefficient vector layout ----------------------------------------------------------------------
KZ = 0  #: vertical stiffness kz [N/m]
CZ = 1  #: vertical damping cz [N s/m]
FZ0 = 2  #: nominal load Fz0 [N]
MU_X = 3  #: longitudinal peak friction mu_x0 at Fz0 [1]
MU_Y = 4  #: lateral peak friction mu_y0 at Fz0 [1]
LOAD_SENSITIVITY = 5  #: d mu / d dfz, relative to mu0 [1]
SHAPE_X = 6  #: Magic Formula C, longitudinal [1]
SHAPE_Y = 7  #: Magic Formula C, lateral [1]
CURVATURE_X = 8  #: Magic Formula E, longitudinal [1]
CURVATURE_Y = 9  #: Magic Formula E, lateral [1]
SLIP_STIFFNESS_FACTOR = 10  #: C_kappa / Fz [1]
CORNERING_STIFFNESS_FACTOR = 11  #: pKy1: peak C_alpha / Fz0 [1/rad]
CORNERING_STIFFNESS_LOAD_FACTOR = 12  #: pKy2: load of peak C_alpha, over Fz0 [1]
ROLLING_RESISTANCE = 13  #: rolling resistance coefficient f_r [1]
U_PEAK_X = 14  #: derived: B_x kappa at the peak of the longitudinal curve [1]
U_PEAK_Y = 15  #: derived: B_y alpha at the peak of the lateral curve [1]
N_COEFFS = 16  #: length of the coefficient vector
# ---- building the coefficient vector (Python, once per vehicle) --------------------------------------
def peak_input(shape: float, curvature: float) -> float:
    """Magic Formula input ``u = B x`` at which the curve peaks.

    Parameters
    ----------
    shape : float
        Shape factor C, ``1 < C <= 2`` [1].
    curvature : float
        Curvature factor E, ``E <= 1`` [1].

    Returns
    -------
    float
        The root of ``u - E (u - atan u) = tan(pi / (2 C))`` [1].

    Raises
    ------
    ValueError
        If the curve never reaches its peak (``E = 1`` with ``C <= 1/atan(pi/2) * pi/2``, about 1.565)
        or the factors are out of range.
    """
    c, e = float(shape), float(curvature)
    if not (1.0 < c <= 2.0) or not e <= 1.0:
        raise ValueError(f"Magic Formula needs 1 < C <= 2 and E <= 1; got C = {c:g}, E = {e:g}")
    target = math.tan(0.5 * math.pi / c)
    if e == 1.0:  # u - E (u - atan u) = atan u < pi/2
        if target >= 0.5 * math.pi:
            raise ValueError(
                f"with E = 1 the curve tends to D sin(C atan(pi/2)) and never peaks for C = {c:g} "
                "(needs C > 1.565)"
            )
        return math.tan(target)
    # The left side is increasing in u for E < 1; bracket: root <= target / (1 - E) (E >= 0), <= target (E < 0)
    hi = target / (1.0 - e) if e > 0.0 else target
    return brentq(
        lambda u: u - e * (u - math.atan(u)) - target,
        0.0,
        hi * (1.0 + 1e-12) + 1e-300,
        xtol=1e-300,
        rtol=4.0 * np.finfo(float).eps,
        maxiter=500,
    )


def tyre_coefficients(tyre) -> np.ndarray:
    """Coefficient vector of a tyre, for the compiled force functions.

    Parameters
    ----------
    tyre : TyreSpec
        Validated tyre parameters (``load_vehicle(name).params.tyre``).

    Returns
    -------
    numpy.ndarray
        float64 vector of length ``N_COEFFS``; the constants ``KZ``, ``CZ``, ``FZ0``, ``MU_X``, ``MU_Y``,
        ``LOAD_SENSITIVITY``, ``SHAPE_X``, ``SHAPE_Y``, ``CURVATURE_X``, ``CURVATURE_Y``,
        ``SLIP_STIFFNESS_FACTOR``, ``CORNERING_STIFFNESS_FACTOR``, ``CORNERING_STIFFNESS_LOAD_FACTOR``,
        ``ROLLING_RESISTANCE`` index the tyre's own values (SI units), ``U_PEAK_X`` and ``U_PEAK_Y``
        the derived peak inputs (:func:`peak_input`).

    Raises
    ------
    ParameterError
        If a Magic Formula curve never reaches its peak (``curvature = 1`` with ``shape < 1.565``).
    """
    c = np.zeros(N_COEFFS, dtype=np.float64)
    c[KZ] = tyre.vertical_stiffness_N_per_m
    c[CZ] = tyre.vertical_damping_Ns_per_m
    c[FZ0] = tyre.nominal_load_N
    c[MU_X] = tyre.mu_x
    c[MU_Y] = tyre.mu_y
    c[LOAD_SENSITIVITY] = tyre.load_sensitivity
    c[SHAPE_X] = tyre.shape_x
    c[SHAPE_Y] = tyre.shape_y
    c[CURVATURE_X] = tyre.curvature_x
    c[CURVATURE_Y] = tyre.curvature_y
    c[SLIP_STIFFNESS_FACTOR] = tyre.slip_stiffness_factor
    c[CORNERING_STIFFNESS_FACTOR] = tyre.cornering_stiffness_factor
    c[CORNERING_STIFFNESS_LOAD_FACTOR] = tyre.cornering_stiffness_load_factor
    c[ROLLING_RESISTANCE] = tyre.rolling_resistance
    for index, axis in ((U_PEAK_X, "x"), (U_PEAK_Y, "y")):
        try:
            c[index] = peak_input(getattr(tyre, f"shape_{axis}"), getattr(tyre, f"curvature_{axis}"))
        except ValueError as exc:
            raise ParameterError(str(exc), where=f"tyre.curvature_{axis}") from None
    return c
