"""One wheel in quasi-static straight running: its spin balance, the slip that balances it, what its tyre carries.

A wheel spins under ``I omega' = tau_drive - tau_brake tanh(omega / w_low) - F_x R + M_y`` (the model's own
terms, :mod:`trikedyn.analysis.straight_line`); in quasi-static running it keeps its slip, so ``omega' = a (1 +
kappa v^3 / v_ref^3) / R_e``. :func:`solve_slip` finds the slip that balances it, from rolling (a root reached
from zero slip outwards, or by secant steps from the previous slip) or, for a locked wheel, from lock; a braked
wheel whose tyre is past its peak force is locked. :func:`drive_capacity` is the largest drive torque a driven
wheel's tyre carries in rolling.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from .._jit import jit
from ..tyre.interface import tyre_forces

__all__ = ["Wheel", "drive_capacity", "solve_slip", "spin_balance"]

_DRIVING_SLIPS = (1e-5, 1e-4, 3e-4, 1e-3, 3e-3, 0.01, 0.02, 0.035, 0.05, 0.07, 0.1, 0.13, 0.17, 0.22, 0.3, 0.4,
                  0.55, 0.75, 1.0)
"""Slips scanned, from zero outwards, for the root of a wheel's spin balance [1]."""
_LOCKED_SPINS = (0.0, 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0, 8.0, 13.0, 20.0, 35.0, 60.0)
"""Spin rates scanned, in ``w_low``, from a locked wheel upwards for its sliding root [1]."""


@dataclass
class Wheel:
    """One wheel's packed records: its tyre function and coefficients, radius [m], vertical stiffness [N/m],
    spin inertia [kg m^2], whether it is driven and braked, its static load [N], and the model's low-speed
    regularisation of the slip ``v_low`` [m/s] and of the brake and rolling resistance ``w_low`` [rad/s]."""

    name: str
    model: int
    coeffs: np.ndarray
    radius: float
    kz: float
    inertia: float
    driven: bool
    braked: bool
    static_load: float
    v_low: float
    w_low: float


def spin_balance(w: Wheel, kappa, v, v_ref, fz, a, tau_drive, tau_brake):
    """Residual of the wheel's spin balance ``I omega' - (...)`` with its sign flipped, and the tyre's values.

    Parameters
    ----------
    w : Wheel
        The wheel.
    kappa : float
        Longitudinal slip, dimensionless.
    v : float
        Speed [m/s].
    v_ref : float
        Reference speed of the slip ``(v^4 + v_low^4)^(1/4)`` [m/s].
    fz : float
        Vertical load [N].
    a : float
        Acceleration of the vehicle [m/s^2].
    tau_drive : float
        Drive torque on the wheel [N m].
    tau_brake : float
        Brake torque on the wheel [N m].

    Returns
    -------
    g : float
        ``tau_drive - tau_brake tanh(omega / w_low) - F_x R + M_y - I omega'`` [N m]: positive when the wheel
        would spin up.
    fx : float
        Longitudinal tyre force [N].
    my : float
        Rolling-resistance moment [N m].
    spin : float
        Spin rate [rad/s].
    """
    return _balance(*_packed(w), float(kappa), *_floats((v, v_ref, fz, a, tau_drive, tau_brake)))


def _packed(w: Wheel) -> tuple:
    """The wheel's values the compiled balance takes, in its order."""
    return w.model, w.coeffs, w.radius, w.kz, w.inertia, w.v_low, w.w_low


def _floats(args) -> tuple:
    """``(v, v_ref, fz, a, tau_drive, tau_brake)`` as Python floats (one compiled signature)."""
    return tuple(float(x) for x in args)


@jit
def _balance(model, coeffs, radius, kz, inertia, v_low, w_low, kappa, v, v_ref, fz, a, tau_drive, tau_brake):
    """:func:`spin_balance` of a wheel given by its packed values (compiled: the Python arithmetic and the
    tyre function's dispatch around each evaluation were most of a top speed's time)."""
    r_eff = radius - fz / kz / 3.0
    spin = (v + kappa * v_ref) / r_eff
    fx, my = 0.0, 0.0
    if fz > 0.0:
        fx, _, _, _, my, _ = tyre_forces(model, coeffs, kappa, 0.0, 0.0, fz, v, v_ref, spin, r_eff, v_low, w_low)
    spin_rate = a * (1.0 + kappa * math.pow(v / v_ref, 3.0)) / r_eff
    g = tau_drive - tau_brake * math.tanh(spin / w_low) - fx * radius + my - inertia * spin_rate
    return g, fx, my, spin


def _root(w, lo, hi, args):
    """The root of the wheel's spin balance between the slips ``lo`` and ``hi`` (Brent's method)."""
    wheel, rest = _packed(w), _floats(args)
    return brentq(lambda k: _balance(*wheel, k, *rest)[0], lo, hi, xtol=1e-13, rtol=1e-12)


def solve_slip(w: Wheel, v, v_ref, fz, a, tau_drive, tau_brake, locked, guess):
    """The wheel's slip: the root of its spin balance it reaches from rolling (or, locked, from lock).

    Parameters
    ----------
    w : Wheel
        The wheel.
    v : float
        Speed [m/s].
    v_ref : float
        Reference speed of the slip ``(v^4 + v_low^4)^(1/4)`` [m/s].
    fz : float
        Vertical load [N].
    a : float
        Acceleration of the vehicle [m/s^2].
    tau_drive : float
        Drive torque on the wheel [N m].
    tau_brake : float
        Brake torque on the wheel [N m].
    locked : bool
        Whether the wheel was locked (sliding) in the previous state.
    guess : float or None
        The previous slip (dimensionless), a warm start.

    Returns
    -------
    kappa : float or None
        The slip (dimensionless); None when no root exists (a driven wheel whose tyre cannot carry the torque).
    locked : bool
        Whether the wheel is locked.
    """
    args = (v, v_ref, fz, a, tau_drive, tau_brake)
    lock = -v / v_ref  # slip of a wheel that does not turn
    if locked:
        prev, g_prev = lock, spin_balance(w, lock, *args)[0]
        for s in _LOCKED_SPINS[1:]:
            k = lock + s * w.w_low * (w.radius - fz / w.kz / 3.0) / v_ref
            if k >= 0.0:
                k = 0.0
            g = spin_balance(w, k, *args)[0]
            if g_prev > 0.0 >= g:
                return _root(w, prev, k, args), True
            if k == 0.0:
                break
            prev, g_prev = k, g
        locked = False  # no sliding root: the wheel rolls again
    # warm start: secant steps from the previous slip, kept when they settle on a stable root nearby
    if guess is not None and guess != 0.0:
        found = _secant(w, guess, args)
        if found is not None:
            return found, False
    g0 = spin_balance(w, 0.0, *args)[0]
    if g0 == 0.0:
        return 0.0, False
    sign = 1.0 if g0 > 0.0 else -1.0  # the slip moves toward the side the balance pushes it
    prev = 0.0
    for s in _DRIVING_SLIPS:
        k = sign * s
        if sign < 0.0 and tau_brake > 0.0 and k <= lock:  # a braked wheel stops turning, it does not reverse
            k = lock
        g = spin_balance(w, k, *args)[0]
        if g * g0 <= 0.0:
            root = _root(w, min(prev, k), max(prev, k), args)
            return root, _beyond_peak(w, root, args)
        if k == lock:
            break
        prev = k
    return None, False


def _secant(w, guess, args):
    """The root of the spin balance near ``guess`` by secant steps, or None (not settled, too far, or an
    unstable root: the balance must fall with the slip there)."""
    root = _secant_root(*_packed(w), float(guess), *_floats(args))
    return None if math.isnan(root) else root


@jit
def _secant_root(model, coeffs, radius, kz, inertia, v_low, w_low, guess, v, v_ref, fz, a, tau_drive, tau_brake):
    """:func:`_secant` compiled; NaN for None."""
    k0, k1 = guess, guess * (1.0 + 1e-4)
    g0 = _balance(model, coeffs, radius, kz, inertia, v_low, w_low, k0, v, v_ref, fz, a, tau_drive, tau_brake)[0]
    g1 = _balance(model, coeffs, radius, kz, inertia, v_low, w_low, k1, v, v_ref, fz, a, tau_drive, tau_brake)[0]
    reach = 0.2 * abs(guess) + 1e-6
    for _ in range(10):
        if g1 == g0:
            return np.nan
        slope = (g1 - g0) / (k1 - k0)
        if not slope < 0.0:
            return np.nan
        k2 = k1 - g1 / slope
        if abs(k2 - guess) > reach or k2 * guess <= 0.0:
            return np.nan
        if abs(k2 - k1) <= 1e-13 + 1e-10 * abs(k2):
            return k2
        k0, g0, k1 = k1, g1, k2
        g1 = _balance(model, coeffs, radius, kz, inertia, v_low, w_low, k2, v, v_ref, fz, a, tau_drive, tau_brake)[0]
    return np.nan


def _beyond_peak(w, kappa, args):
    """True when the tyre's force falls with more slip at ``kappa`` (the wheel slides: locked)."""
    if kappa >= 0.0:
        return False
    d = max(1e-7, 1e-4 * abs(kappa))
    return abs(spin_balance(w, kappa - d, *args)[1]) < abs(spin_balance(w, kappa, *args)[1])


def drive_capacity(w: Wheel, v, v_ref, fz, a):
    """Largest torque a driven wheel's tyre carries in rolling, and the slip there.

    Parameters
    ----------
    w : Wheel
        The wheel.
    v : float
        Speed [m/s].
    v_ref : float
        Reference speed of the slip ``(v^4 + v_low^4)^(1/4)`` [m/s].
    fz : float
        Vertical load [N].
    a : float
        Acceleration of the vehicle [m/s^2].

    Returns
    -------
    torque : float
        The largest drive torque carried [N m].
    kappa : float
        The slip there, dimensionless.
    """
    def carried(k):
        """Drive torque [N m] the wheel carries in rolling at slip ``k``: ``F_x R - M_y + I omega'``."""
        return -spin_balance(w, k, v, v_ref, fz, a, 0.0, 0.0)[0]

    values = [carried(s) for s in _DRIVING_SLIPS]
    i = int(np.argmax(values))
    lo = _DRIVING_SLIPS[max(i - 1, 0)]
    hi = _DRIVING_SLIPS[min(i + 1, len(_DRIVING_SLIPS) - 1)]
    best = minimize_scalar(lambda k: -carried(k), bounds=(lo, hi), method="bounded", options={"xatol": 1e-9})
    k = float(best.x) if -best.fun > values[i] else _DRIVING_SLIPS[i]
    return max(-best.fun, values[i]), k
