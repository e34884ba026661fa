"""Tyre forces: vertical spring-damper, Magic Formula pure slip, similarity combined slip.

Every force function is a small ``numba.njit(cache=True)`` function of scalar floats and one float64
coefficient vector, so the compiled time loop calls them with plain arrays and never touches a Python
object. Build the vector once from a :class:`~trikedyn.params.schema.TyreSpec` with
:func:`tyre_coefficients`; the module-level integer constants (``KZ``, ``CZ``, ``FZ0``, ...) name its
entries (both defined in :mod:`trikedyn.tyre.mf_coefficients`, importable from here).

Axes and sign convention (ISO 8855 as adapted by Pacejka, *Tyre and Vehicle Dynamics*, 2006, 2.2)
---------------------------------------------------------------------------------------------------
Tyre axes have their origin at the contact point: ``x`` along the line where the wheel plane meets the
road plane, pointing forward; ``z`` along the road normal, up; ``y = z x x``, to the left (the wheel's
spin axis projected on the road). The wheel spin rate ``omega`` is positive about ``+y``, i.e. positive
when rolling forward. ``vx``, ``vy`` are the velocity components, in tyre axes, of the contact point
moving with the wheel carrier (the hub, not the spinning tyre material); on flat ground that is the
wheel centre's velocity projected on the road. ``R_e`` is the effective rolling radius.

- Longitudinal slip ``kappa = (omega R_e - vx) / |vx|``: positive when driving (the tread moves
  backwards faster than the road passes), negative when braking, ``-1`` for a locked wheel. Positive
  ``kappa`` gives positive ``Fx`` (a driving force, forward).
- Slip angle ``alpha`` with ``tan(alpha) = -vy / |vx|``: a wheel sliding to the left (``vy > 0``) has
  ``alpha < 0``; the lateral force is ``Fy = +C_alpha alpha`` for small ``alpha``, so it points to the
  right (negative), against the sliding. Both signs hold when driving backwards (``vx < 0``) too.
- ``Fz`` acts along ``+z`` on the wheel (the road pushes it up), never negative.
- The rolling resistance moment ``My`` acts about ``+y`` on the wheel and opposes ``omega``.

Pure slip (Magic Formula)
-------------------------
``F = D sin(C atan(B x - E (B x - atan(B x))))`` with ``D = mu(Fz) Fz``, ``C`` the shape factor, ``E``
the curvature and ``B = K / (C D)`` so that the slope at zero slip is ``K``: the slip stiffness
``C_kappa = slip_stiffness_factor Fz`` for ``x = kappa``, the cornering stiffness
``C_alpha = cornering_stiffness_factor Fz0 sin(2 atan(Fz / (cornering_stiffness_load_factor Fz0)))``
for ``x = alpha`` [rad]. The peak friction falls (``load_sensitivity < 0``) or rises linearly with the
load: ``mu = mu0 (1 + load_sensitivity (Fz - Fz0) / Fz0)``, floored at ``MU_FLOOR_FRACTION mu0``. For
``1 < C <= 2`` and ``E <= 1`` the curve is odd, never changes sign for ``x > 0`` and peaks at exactly
``D`` where ``B x`` equals ``u_peak``, the root of ``u - E (u - atan u) = tan(pi / (2 C))``; ``u_peak``
depends on ``C`` and ``E`` only, so it is solved once, in :func:`tyre_coefficients`.

Combined slip (similarity method with normalised slips)
-------------------------------------------------------
After Pacejka (2006) 4.3.2 (and Bakker, Nyborg & Pacejka 1987), each slip is normalised by its own
peak slip, ``kappa_n = kappa / kappa_peak = B_x kappa / u_peak_x`` and ``alpha_n = alpha / alpha_peak =
B_y alpha / u_peak_y``, giving the total normalised slip ``rho = sqrt(kappa_n^2 + alpha_n^2)``. Each force
is its pure-slip curve evaluated at the same fraction ``rho`` of its own peak slip, directed along its
share of the total slip::

    Fx = (kappa_n / rho) Fx0(rho kappa_peak),   Fy = (alpha_n / rho) Fy0(rho alpha_peak)

so both directions reach their own peak (``mu_x Fz``, ``mu_y Fz``) together at ``rho = 1`` and
``(Fx / (mu_x Fz))^2 + (Fy / (mu_y Fz))^2 = (kappa_n^2 f_x^2 + alpha_n^2 f_y^2) / rho^2 <= 1`` with
``|f| <= 1`` the normalised pure curves: the force never leaves the friction ellipse. With ``alpha = 0``
it is the pure ``Fx``, with ``kappa = 0`` the pure ``Fy``. ``Fx0(rho x_peak) / rho`` is an even, analytic
function of ``rho``, so the forces are smooth (analytic in ``kappa``, ``alpha``) everywhere; below
``rho = RHO_LINEAR`` its limit ``D C u_peak`` is used (relative difference ``O(rho^2)`` ~ 1e-18), so zero
slip gives ``(0, 0)`` with the exact slip stiffnesses, no 0/0.

The practical slips (``kappa``, ``alpha``) are used rather than Pacejka's theoretical slips
``kappa / (1 + kappa)``, ``tan(alpha) / (1 + kappa)``: those are singular at a locked wheel
(``kappa = -1``) and change sign for a wheel spinning backwards (``kappa < -1``), whereas the practical
slips stay finite and keep the force against the sliding for any wheel spin. The price is that the
method is symmetric between driving and braking at equal ``|kappa|``, and at large combined slip the
force follows the normalised slip direction rather than exactly the sliding velocity (as in all
normalised similarity methods; MF 5.2 corrects it with fitted weighting functions, for which the
parameter set has no data).

Low-speed regularisation
------------------------
:func:`slip_quantities` divides by ``v_ref = (vx^4 + v_low^4)^(1/4)`` instead of ``|vx|``: ``v_ref``
is smooth, never below ``v_low``, and differs from ``|vx|`` by a relative ``(v_low / vx)^4 / 4`` only
(2.5e-5 at ``vx = 10 v_low``), so the slips are exact at driving speeds and shrink smoothly to zero with
the speed below ``v_low``, where the tyre acts as a viscous damper. See :func:`slip_quantities` for the
recommended ``v_low`` and the fixed-step stability limit it sets.
"""

from __future__ import annotations

import math

from .._jit import jit
from .mf_coefficients import (
    CORNERING_STIFFNESS_FACTOR,
    CORNERING_STIFFNESS_LOAD_FACTOR,
    CURVATURE_X,
    CURVATURE_Y,
    CZ,
    FZ0,
    KZ,
    LOAD_SENSITIVITY,
    MU_X,
    MU_Y,
    N_COEFFS,
    ROLLING_RESISTANCE,
    SHAPE_X,
    SHAPE_Y,
    SLIP_STIFFNESS_FACTOR,
    U_PEAK_X,
    U_PEAK_Y,
    peak_input,
    tyre_coefficients,
)

__all__ = ["CORNERING_STIFFNESS_FACTOR", "CORNERING_STIFFNESS_LOAD_FACTOR", "CURVATURE_X", "CURVATURE_Y", "CZ", "FZ0",
           "KZ", "LOAD_SENSITIVITY", "MU_FLOOR_FRACTION", "MU_X", "MU_Y", "N_COEFFS", "RHO_LINEAR",
           "ROLLING_RESISTANCE", "SHAPE_X", "SHAPE_Y", "SLIP_STIFFNESS_FACTOR", "U_PEAK_X", "U_PEAK_Y",
           "combined_forces", "cornering_stiffness", "magic_formula_curve", "peak_friction", "peak_input",
           "pure_lateral", "pure_longitudinal", "rolling_resistance_moment", "slip_quantities", "slip_stiffness",
           "tyre_coefficients", "tyre_forces", "vertical_force"]

MU_FLOOR_FRACTION = 0.01  #: peak friction never falls below this fraction of mu0
RHO_LINEAR = 1e-8  #: total normalised slip below which the combined forces use their zero-slip limit


# ---- compiled force functions -------------------------------------------------------------------------
@jit(inline="always")
def vertical_force(penetration_m, penetration_rate_mps, coeffs):
    """Vertical (normal) tyre force, non-adhesive.

    Parameters
    ----------
    penetration_m : float
        Tyre deflection ``d`` = unloaded radius less the centre-to-road distance [m]; ``d <= 0`` out
        of contact.
    penetration_rate_mps : float
        ``d'`` [m/s], positive when compressing.
    coeffs : numpy.ndarray
        Coefficient vector from :func:`tyre_coefficients`.

    Returns
    -------
    float
        ``Fz = max(0, kz d + cz d')`` in contact, 0 out of contact [N]; never pulls.
    """
    if penetration_m <= 0.0:
        return 0.0
    fz = coeffs[KZ] * penetration_m + coeffs[CZ] * penetration_rate_mps
    return max(fz, 0.0)


@jit(inline="always")
def peak_friction(fz, coeffs):
    """Peak friction coefficients at a load.

    Parameters
    ----------
    fz : float
        Vertical load [N].
    coeffs : numpy.ndarray
        Coefficient vector.

    Returns
    -------
    mu_x, mu_y : float
        ``mu0 (1 + load_sensitivity dfz)`` with ``dfz = (Fz - Fz0) / Fz0``, each floored at
        ``MU_FLOOR_FRACTION mu0`` [1].
    """
    scale = 1.0 + coeffs[LOAD_SENSITIVITY] * (fz - coeffs[FZ0]) / coeffs[FZ0]
    scale = max(scale, MU_FLOOR_FRACTION)
    return coeffs[MU_X] * scale, coeffs[MU_Y] * scale


@jit(inline="always")
def slip_stiffness(fz, coeffs):
    """Longitudinal slip stiffness ``C_kappa = slip_stiffness_factor Fz`` [N] (per unit slip), 0 for Fz <= 0.

    Parameters
    ----------
    fz : float
        Vertical load [N].
    coeffs : numpy.ndarray
        The similarity tyre's coefficients.

    Returns
    -------
    float
        Slip stiffness [N].
    """
    if fz <= 0.0:
        return 0.0
    return coeffs[SLIP_STIFFNESS_FACTOR] * fz


@jit(inline="always")
def cornering_stiffness(fz, coeffs):
    """Cornering stiffness ``C_alpha = pKy1 Fz0 sin(2 atan(Fz / (pKy2 Fz0)))`` [N/rad], 0 for Fz <= 0.

    Its maximum, ``pKy1 Fz0``, is at ``Fz = pKy2 Fz0``. Computed as ``pKy1 Fz0 2 r / (1 + r^2)`` with
    ``r = Fz / (pKy2 Fz0)``, the same function (``sin 2a = 2 tan a / (1 + tan^2 a)``) without a sine and an
    arctangent: within a few units of the last place of the trigonometric form.

    Parameters
    ----------
    fz : float
        Vertical load [N].
    coeffs : numpy.ndarray
        The similarity tyre's coefficients.

    Returns
    -------
    float
        Cornering stiffness [N/rad].
    """
    if fz <= 0.0:
        return 0.0
    fz0 = coeffs[FZ0]
    ratio = fz / (coeffs[CORNERING_STIFFNESS_LOAD_FACTOR] * fz0)
    # sin(2 atan r) = 2 r / (1 + r^2): the same curve without a sine and an arctangent per call
    return coeffs[CORNERING_STIFFNESS_FACTOR] * fz0 * (2.0 * ratio / (1.0 + ratio * ratio))


@jit(inline="always")
def magic_formula_curve(u, shape, curvature):
    """Normalised Magic Formula ``sin(C atan(u - E (u - atan u)))`` [1] of the input ``u = B x`` [1].

    Odd in ``u`` (exactly, in floating point); slope ``C`` at 0; peak 1 at ``u = u_peak``.

    Parameters
    ----------
    u : float
        Scaled input ``B x``, dimensionless.
    shape : float
        Shape factor ``C``, dimensionless.
    curvature : float
        Curvature factor ``E``, dimensionless.

    Returns
    -------
    float
        The normalised force, dimensionless.
    """
    return math.sin(shape * math.atan(u - curvature * (u - math.atan(u))))


@jit(inline="always")
def _stiffness_factors(fz, mu_x, mu_y, coeffs):
    """Magic Formula B_x [1] and B_y [1/rad] at a load ``fz > 0`` with its peak frictions."""
    bx = coeffs[SLIP_STIFFNESS_FACTOR] / (coeffs[SHAPE_X] * mu_x)  # K/(C D) with K, D both ~ Fz
    by = cornering_stiffness(fz, coeffs) / (coeffs[SHAPE_Y] * mu_y * fz)
    return bx, by


@jit(inline="always")
def pure_longitudinal(kappa, fz, coeffs):
    """Longitudinal force in pure longitudinal slip (Magic Formula).

    Parameters
    ----------
    kappa : float
        Longitudinal slip ``(omega R_e - vx) / |vx|`` [1], positive when driving.
    fz : float
        Vertical load [N]; no force for ``fz <= 0``.
    coeffs : numpy.ndarray
        Coefficient vector.

    Returns
    -------
    float
        ``Fx`` [N]: slope ``C_kappa`` at zero slip, peak ``mu_x(Fz) Fz``, odd in ``kappa``.
    """
    if fz <= 0.0:
        return 0.0
    mu_x, _ = peak_friction(fz, coeffs)
    bx = coeffs[SLIP_STIFFNESS_FACTOR] / (coeffs[SHAPE_X] * mu_x)
    return mu_x * fz * magic_formula_curve(bx * kappa, coeffs[SHAPE_X], coeffs[CURVATURE_X])


@jit(inline="always")
def pure_lateral(alpha, fz, coeffs):
    """Lateral force in pure side slip (Magic Formula).

    Parameters
    ----------
    alpha : float
        Slip angle, ``tan(alpha) = -vy / |vx|`` [rad].
    fz : float
        Vertical load [N]; no force for ``fz <= 0``.
    coeffs : numpy.ndarray
        Coefficient vector.

    Returns
    -------
    float
        ``Fy`` [N]: slope ``C_alpha(Fz)`` at zero slip (``Fy = +C_alpha alpha``), peak ``mu_y(Fz) Fz``,
        odd in ``alpha``.
    """
    if fz <= 0.0:
        return 0.0
    _, mu_y = peak_friction(fz, coeffs)
    by = cornering_stiffness(fz, coeffs) / (coeffs[SHAPE_Y] * mu_y * fz)
    return mu_y * fz * magic_formula_curve(by * alpha, coeffs[SHAPE_Y], coeffs[CURVATURE_Y])


@jit(inline="always")
def combined_forces(kappa, alpha, fz, coeffs):
    """Longitudinal and lateral forces in combined slip (similarity method, normalised slips).

    Parameters
    ----------
    kappa : float
        Longitudinal slip [1].
    alpha : float
        Slip angle [rad].
    fz : float
        Vertical load [N]; no force for ``fz <= 0``.
    coeffs : numpy.ndarray
        Coefficient vector.

    Returns
    -------
    fx, fy : float
        Forces [N], inside the friction ellipse ``(fx/(mu_x Fz))^2 + (fy/(mu_y Fz))^2 <= 1``; equal to
        the pure forces when the other slip is zero; ``fx`` odd in ``kappa`` and even in ``alpha``,
        ``fy`` odd in ``alpha`` and even in ``kappa``. See the module docstring for the method.
    """
    if fz <= 0.0:
        return 0.0, 0.0
    mu_x, mu_y = peak_friction(fz, coeffs)
    bx, by = _stiffness_factors(fz, mu_x, mu_y, coeffs)
    cx, cy = coeffs[SHAPE_X], coeffs[SHAPE_Y]
    ux, uy = coeffs[U_PEAK_X], coeffs[U_PEAK_Y]
    kn = bx * kappa / ux  # kappa / kappa_peak
    an = by * alpha / uy  # alpha / alpha_peak
    rho = math.sqrt(kn * kn + an * an)
    if rho < RHO_LINEAR:  # limits of f(rho u) / rho: slope C u at zero slip
        gx = cx * ux
        gy = cy * uy
    else:
        gx = magic_formula_curve(rho * ux, cx, coeffs[CURVATURE_X]) / rho
        gy = magic_formula_curve(rho * uy, cy, coeffs[CURVATURE_Y]) / rho
    return mu_x * fz * (kn * gx), mu_y * fz * (an * gy)


@jit(inline="always")
def slip_quantities(vx_contact, vy_contact, omega_wheel, radius_eff, v_low):
    """Longitudinal slip and slip angle, regularised at low speed.

    Parameters
    ----------
    vx_contact, vy_contact : float
        Contact-point velocity (moving with the wheel carrier) in tyre axes [m/s].
    omega_wheel : float
        Wheel spin rate about the tyre ``+y`` axis, positive rolling forward [rad/s].
    radius_eff : float
        Effective rolling radius ``R_e`` [m].
    v_low : float
        Regularisation speed [m/s], > 0. Recommended: 1 m/s.

    Returns
    -------
    kappa : float
        ``(omega R_e - vx) / v_ref`` [1].
    alpha : float
        ``atan(-vy / v_ref)`` [rad], in (-pi/2, pi/2).

    Notes
    -----
    ``v_ref = (vx^4 + v_low^4)^(1/4)`` replaces ``|vx|``: smooth, at least ``v_low``, and within a
    relative ``(v_low/vx)^4 / 4`` of ``|vx|`` (2.5e-5 at ``vx = 10 v_low``, 1.6e-6 at 20 v_low), so the
    slips are exact at driving speeds. Below ``v_low`` the slips shrink in proportion to the slip
    velocities and the tyre becomes a linear viscous damper (``Fx ~ C_kappa (omega R_e - vx) / v_low``,
    ``Fy ~ -C_alpha vy / v_low``) instead of a singular one: no NaN or inf at standstill, and the wheel
    spin mode's rate stays bounded by ``|lambda| ~ C_kappa R_e^2 / (I_wheel v_ref)``.

    That rate sets the fixed step: RK4 is stable for ``|lambda| h < 2.78``. For the reference e-trike
    (``C_kappa = 16 x 1900 N``, ``R_e = 0.27 m``, ``I_wheel = 0.224 kg m^2``) ``|lambda| ~ 9900 / v_ref``
    [1/s], so a 1 ms step needs ``v_ref > 3.6 m/s``: runs at driving speed are fine with
    ``v_low = 1 m/s``, while starting from rest needs a smaller step (or a larger ``v_low``, at the cost
    of slip errors of ``(v_low/vx)^4/4`` at speed). ``v_low = 0`` with ``vx = 0`` returns zero slips.
    """
    v4 = vx_contact * vx_contact * vx_contact * vx_contact + v_low * v_low * v_low * v_low
    if v4 <= 0.0:
        return 0.0, 0.0
    v_ref = math.sqrt(math.sqrt(v4))
    kappa = (omega_wheel * radius_eff - vx_contact) / v_ref
    alpha = math.atan(-vy_contact / v_ref)
    return kappa, alpha


@jit(inline="always")
def rolling_resistance_moment(fz, omega, radius, coeffs, w_low):
    """Rolling resistance moment on the wheel about its spin axis.

    Parameters
    ----------
    fz : float
        Vertical load [N].
    omega : float
        Wheel spin rate [rad/s].
    radius : float
        Moment arm, the (loaded or effective) radius [m].
    coeffs : numpy.ndarray
        Coefficient vector.
    w_low : float
        Spin rate over which the moment's sign is smoothed [rad/s], > 0; recommended 1 rad/s
        (0.27 m/s on the reference tyre; the moment is at 99.9 % of its value from 3.8 rad/s).

    Returns
    -------
    float
        ``-f_r Fz R tanh(omega / w_low)`` [N m]; opposes the spin, zero at ``omega = 0``.
    """
    if fz <= 0.0:
        return 0.0
    return -coeffs[ROLLING_RESISTANCE] * fz * radius * math.tanh(omega / w_low)


@jit(inline="always")
def tyre_forces(
    penetration_m, penetration_rate_mps, vx_contact, vy_contact, omega_wheel, radius_eff, coeffs, v_low, w_low
):
    """All tyre forces of one wheel, for the compiled time loop.

    Parameters
    ----------
    penetration_m : float
        Tyre deflection ``d`` [m]; ``<= 0`` out of contact.
    penetration_rate_mps : float
        ``d'`` [m/s].
    vx_contact, vy_contact : float
        Contact-point velocity (moving with the wheel carrier) in tyre axes [m/s].
    omega_wheel : float
        Wheel spin rate, positive rolling forward [rad/s].
    radius_eff : float
        Effective rolling radius [m], also the rolling-resistance moment arm.
    coeffs : numpy.ndarray
        Coefficient vector from :func:`tyre_coefficients`.
    v_low : float
        Slip regularisation speed [m/s] (:func:`slip_quantities`).
    w_low : float
        Rolling-resistance sign smoothing spin rate [rad/s] (:func:`rolling_resistance_moment`).

    Returns
    -------
    fx, fy, fz : float
        Forces on the wheel at the contact point, in tyre axes [N].
    my : float
        Rolling resistance moment about the spin axis [N m].
    """
    fz = vertical_force(penetration_m, penetration_rate_mps, coeffs)
    if fz <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    kappa, alpha = slip_quantities(vx_contact, vy_contact, omega_wheel, radius_eff, v_low)
    fx, fy = combined_forces(kappa, alpha, fz, coeffs)
    my = rolling_resistance_moment(fz, omega_wheel, radius_eff, coeffs, w_low)
    return fx, fy, fz, my
