"""The tyre behind one compiled entry point: contact, transient slip and forces of one wheel.

:func:`wheel_wrench` is what the compiled right-hand side calls for every wheel: it finds the contact
(:func:`~trikedyn.tyre.contact.contact_geometry`), the rates of the transient slips
(:func:`~trikedyn.tyre.contact.slip_rates`), the vertical force, and the horizontal forces and moments of
the wheel's tyre model, and returns the resultant on the wheel (force, and moment about its centre, in
world axes). The tyre model is chosen per wheel when the vehicle is built (:func:`tyre_setup`):

``similarity`` (:data:`SIMILARITY`)
    The reduced Magic Formula with similarity combined slip of :mod:`trikedyn.tyre.magic_formula`, from the
    vehicle file's ``[tyre]`` section (the paper's "Pacejka similarity" tyre): Fx, Fy and a rolling
    resistance moment; no aligning or overturning moment, no camber.
``magic-formula`` (:data:`MAGIC_FORMULA`)
    The full Magic Formula of a ``.tir`` file (:mod:`trikedyn.tyre.pac2002`: PAC2002 / MF 5.2 / MF 6.1):
    Fx, Fy, the aligning moment Mz (it acts on the wheel about the road normal, so the steering feels it),
    the overturning moment Mx and the rolling resistance My, with load and camber dependence, the file's
    scaling factors, ``TYRESIDE`` mirroring (a tyre on the left of the vehicle is mounted as a left tyre)
    and its validity ranges (inputs clamped; the loop reports which, :data:`WHEEL_OUT` ``clamped``).
    Vertical stiffness and damping come from ``VERTICAL_STIFFNESS`` / ``VERTICAL_DAMPING``; the relaxation
    lengths from ``PTX*`` / ``PTY*`` (MF 6.1: the carcass stiffnesses), evaluated at the wheel's static
    load and held constant through the run (a load-dependent length would make the slip equations stiffer
    as a wheel unloads; the paper's tyre has constant lengths too).

Signs: the loop keeps trikedyn's slip angle (``tan(alpha) = -vy / |vx|``,
:mod:`~trikedyn.tyre.magic_formula`); the full Magic Formula is evaluated at the ISO slip angle
``-alpha``, and its outputs are in the same axes. The rolling resistance moment of the full Magic
Formula is evaluated at the regularised forward speed ``v_ref`` and smoothed like the similarity model's
(``tanh(omega / w_low)``), so that it has no jump at standstill. Below the slip regularisation speed
``v_low`` the full Magic Formula's zero-slip forces and moments (its offsets ``SHx``, ``SVx``, ``SHy``,
``SVy``, the residual torque, camber thrust and overturning couple at zero slip) fade out smoothly
(:func:`standstill_weight`), as MF-Tyre does below ``VXLOW``: a tyre at rest carries no force that slip
does not cause, so that a vehicle on such tyres can stand still (static equilibrium exists).

The models are registered in :mod:`trikedyn.tyre.models` (Python side: which wheels, setup, stiffnesses,
the audit's label, clamp names); a new tyre model is one module there that registers itself, plus its branch
in :func:`tyre_forces` when it does not reuse one (its ``kernel`` number).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .._jit import jit
from .contact import contact_geometry, slip_rates
from .magic_formula import combined_forces, rolling_resistance_moment
from .models import COEFFS_WIDTH, MAGIC_FORMULA, SIMILARITY, TYRE_MODELS, TyreSetup, for_wheel
from .pac2002 import mf_forces

__all__ = ["COEFFS_WIDTH", "MAGIC_FORMULA", "SIMILARITY", "TYRE_MODELS", "TyreSetup", "linear_stiffnesses",
           "standstill_weight", "tyre_forces", "tyre_setup", "vertical_force", "wheel_wrench"]


def tyre_setup(params, wheel, static_load_N: float) -> TyreSetup:
    """The tyre of one wheel station, by the tyre model that claims it (:func:`~trikedyn.tyre.models.for_wheel`):
    its ``.tir`` file when it names one, else the ``[tyre]`` section.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    wheel : WheelSpec
        The wheel station.
    static_load_N : float
        The wheel's static load [N]: the relaxation lengths of a ``.tir`` tyre are taken there.

    Returns
    -------
    TyreSetup
        With ``name`` the tyre model's.
    """
    model = for_wheel(params, wheel)
    setup = model.setup(params, wheel, static_load_N)
    return setup if setup.name == model.name else replace(setup, name=model.name)


def linear_stiffnesses(setup_model: int | str, coefficients: np.ndarray, fz: float) -> tuple[float, float]:
    """Slip stiffness [N] and cornering stiffness ``dFy/d(-alpha_ISO)`` > 0 [N/rad] at a load, zero camber.

    In trikedyn's sign (``Fy = C_alpha alpha`` with ``tan(alpha) = -vy / |vx|``) both are positive for a
    normal tyre, for either model.

    Parameters
    ----------
    setup_model : str or int
        The tyre model's name (:attr:`TyreSetup.name`), or its kernel number (the first model registered
        with it).
    coefficients : numpy.ndarray
        The wheel's coefficient row.
    fz : float
        Vertical load [N].

    Returns
    -------
    kx, ky : float
        Slip stiffness [N] and cornering stiffness [N/rad].
    """
    if isinstance(setup_model, str):
        model = TYRE_MODELS.get(setup_model)
    else:
        model = next(m for m in TYRE_MODELS.values() if m.kernel == int(setup_model))
    return model.stiffnesses(coefficients, fz)


@jit(inline="always")
def vertical_force(deflection, rate, w):
    """``Fz = max(0, kz d + cz d')`` in contact (``d > 0``), else 0 [N]; ``w`` a wheel record.

    Parameters
    ----------
    deflection : float
        Tyre deflection [m].
    rate : float
        Deflection rate [m/s].
    w : record
        The wheel record (``vertical_stiffness`` [N/m], ``vertical_damping`` [N s/m]).

    Returns
    -------
    float
        Fz [N].
    """
    if deflection <= 0.0:
        return 0.0
    fz = w.vertical_stiffness * deflection + w.vertical_damping * rate
    return max(fz, 0.0)


@jit(inline="always")
def standstill_weight(vx, v_low):
    """``0.5 (1 - cos(pi |vx| / v_low))`` below ``v_low``, 1 above: how much of a tyre's zero-slip force
    (the Magic Formula's offsets and camber thrust) it carries at the forward speed ``vx`` [m/s].

    Parameters
    ----------
    vx : float
        Forward speed [m/s].
    v_low : float
        Regularisation speed [m/s].

    Returns
    -------
    float
        The weight, 0 to 1, dimensionless.
    """
    speed = abs(vx)
    if speed >= v_low:
        return 1.0
    return 0.5 * (1.0 - math.cos(math.pi * speed / v_low))


@jit(inline="always")
def tyre_forces(model, c, kappa, alpha, camber, fz, vx, v_ref, spin, r_eff, v_low, w_low):
    """Horizontal forces and moments of a tyre model, tyre axes.

    Parameters
    ----------
    model : int
        ``SIMILARITY`` or ``MAGIC_FORMULA``.
    c : ndarray
        The wheel's coefficient row.
    kappa : float
        Longitudinal slip [1].
    alpha : float
        Slip angle, trikedyn's sign (``tan(alpha) = -vy / |vx|``) [rad].
    camber : float
        Inclination, ISO [rad].
    fz : float
        Vertical load [N], > 0.
    vx : float
        Forward speed of the wheel centre [m/s].
    v_ref : float
        Regularised forward speed [m/s].
    spin : float
        Wheel spin rate [rad/s].
    r_eff : float
        Effective rolling radius [m].
    v_low : float
        Slip regularisation speed [m/s]: below it the full Magic Formula's zero-slip forces fade out
        (:func:`standstill_weight`).
    w_low : float
        Spin rate smoothing the rolling resistance's sign [rad/s].

    Returns
    -------
    fx, fy, mz, mx, my : float
        [N], [N], [N m], [N m], [N m] (``my`` about the spin axis, against the spin).
    clamped : float
        Clamp bits of the inputs outside the tyre data's validity ranges (0 for the similarity model).
    """
    if model == MAGIC_FORMULA:
        fx, fy, mz, mx, my, mask = mf_forces(fz, kappa, -alpha, camber, v_ref, c)
        weight = standstill_weight(vx, v_low)
        if weight < 1.0:  # a tyre at rest carries no force that slip does not cause
            fx0, fy0, mz0, mx0, _, _ = mf_forces(fz, 0.0, 0.0, camber, v_ref, c)
            fade = 1.0 - weight
            fx, fy, mz, mx = fx - fade * fx0, fy - fade * fy0, mz - fade * mz0, mx - fade * mx0
        return fx, fy, mz, mx, my * math.tanh(spin / w_low), float(mask)
    fx, fy = combined_forces(kappa, alpha, fz, c)
    my = rolling_resistance_moment(fz, spin, r_eff, c, w_low)
    return fx, fy, 0.0, 0.0, my, 0.0


@jit(inline="always")
def wheel_wrench(w, c, veh, road, e, cx, cy, cz, vb, kappa, tan_alpha, out):
    """Everything the tyre does to one wheel, the compiled entry point of the loop.

    Parameters
    ----------
    w : record
        The wheel (:data:`~trikedyn.model.packing.WHEEL`).
    c : ndarray
        Its tyre coefficient row.
    veh : record
        The vehicle (:data:`~trikedyn.model.packing.VEHICLE`: ``v_low``, ``w_low``, ``slip_forces``).
    road : record
        The road.
    e : ndarray (3, 3)
        World -> wheel rotation.
    cx, cy, cz : float
        Wheel centre in the world [m].
    vb : ndarray (6,)
        Wheel spatial velocity in its own axes.
    kappa, tan_alpha : float
        The wheel's transient slip states.
    out : record
        Filled with the wheel's outputs (:data:`~trikedyn.model.packing.WHEEL_OUT`), ``travel`` excepted.

    Returns
    -------
    fwx, fwy, fwz : float
        Force on the wheel, world axes [N].
    mwx, mwy, mwz : float
        Moment on the wheel about its centre, world axes [N m].
    dkappa, dtan_alpha : float
        Rates of the transient slips [1/s].
    """
    (rx, ry, rz, nx, ny, nz, exx, exy, exz, eyx, eyy, eyz, ax, ay, az, deflection, rate, vx, vy, spin,
     camber) = contact_geometry(w.radius, road, e, cx, cy, cz, vb)
    r_eff = w.radius - deflection / 3.0
    dkappa, dtan_alpha, v_ref = slip_rates(kappa, tan_alpha, vx, vy, spin, r_eff, veh.v_low, w.relaxation_x,
                                           w.relaxation_y)
    alpha = math.atan(tan_alpha)
    fz = vertical_force(deflection, rate, w)
    fx, fy, mz, mx, my, clamped = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if fz > 0.0 and veh.slip_forces > 0.0:
        fx, fy, mz, mx, my, clamped = tyre_forces(w.tyre_model, c, kappa, alpha, camber, fz, vx, v_ref, spin, r_eff,
                                                  veh.v_low, veh.w_low)
    fwx = fx * exx + fy * eyx + fz * nx
    fwy = fx * exy + fy * eyy + fz * ny
    fwz = fx * exz + fy * eyz + fz * nz
    mwx = ry * fwz - rz * fwy + my * ax
    mwy = rz * fwx - rx * fwz + my * ay
    mwz = rx * fwy - ry * fwx + my * az
    if mz != 0.0 or mx != 0.0:
        mwx += mz * nx + mx * exx
        mwy += mz * ny + mx * exy
        mwz += mz * nz + mx * exz
    out.fx = fx
    out.fy = fy
    out.fz = fz
    out.kappa = kappa
    out.alpha = alpha
    out.deflection = deflection
    out.spin = spin
    out.vx = vx
    out.mz = mz
    out.camber = camber
    out.clamped = clamped
    return fwx, fwy, fwz, mwx, mwy, mwz, dkappa, dtan_alpha
