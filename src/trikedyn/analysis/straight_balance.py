"""Speeds at which the model's straight running balances (:mod:`trikedyn.analysis.straight_line`): the speed
at which the full drive balances the resistances on a grade (:func:`full_drive_balance`: Brent's method from a
closed-form first guess), and the speed at which the power limit takes over from the torque limit
(:func:`power_takeover`). The top speed and the acceleration of :mod:`trikedyn.analysis.performance` are built
on these.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from .straight_line import State, StraightRunning

__all__ = ["full_drive_balance", "power_takeover"]


def _closed_form_speed(straight: StraightRunning, crawling: State, sin_t: float, fastest: float) -> float:
    """Top speed [m/s] of ``min(T_max, P / omega) / R = F_rolling + M g sin + k v^2`` with the rolling
    resistance at crawling speed, no slip and ``omega = v / R``: the search's first guess."""
    radius = float(np.mean(straight.radius[straight.driven])) if straight.driven.any() else float(
        np.mean(straight.radius))
    resist = float(np.sum(-crawling.my / straight.radius)) + straight.mass * straight.g * sin_t

    def net(v):
        """Drive less resistance [N] at ``v`` [m/s]."""
        return min(straight.max_torque / radius, straight.max_power / v) - resist - straight.drag * v * v

    if net(fastest) > 0.0:
        return fastest
    low = 1e-3
    return brentq(net, low, fastest) if net(low) > 0.0 else low


def full_drive_balance(straight: StraightRunning, sin_t: float, cos_t: float, slowest: float,
                       fastest: float) -> tuple[float | None, State]:
    """The speed at which the acceleration at full drive is zero, between ``slowest`` and ``fastest``.

    Brent's method on the quasi-static acceleration, bracketed around a closed-form first guess (the drive
    limits against the rolling resistance at ``slowest``, the grade and the drag, without slip).

    Parameters
    ----------
    straight : StraightRunning
    sin_t, cos_t : float
        Sine and cosine of the road's slope angle, ``tan(theta) = grade / 100``.
    slowest, fastest : float
        The speeds searched [m/s].

    Returns
    -------
    speed : float or None
        The balance [m/s]; 0 when the full drive does not accelerate the vehicle at ``slowest``, None when it
        still does at ``fastest``.
    state : State
        The state at full drive at that speed (at ``slowest`` for 0, at ``fastest`` for None).
    """
    full = straight.max_torque
    states = {}  # speed [m/s] -> quasi-static state at full drive

    def accel(v):
        """Acceleration [m/s^2] at full drive at ``v`` [m/s], from the nearest state found so far."""
        if v not in states:
            near = min(states, key=lambda u: abs(u - v)) if states else None
            states[v] = straight.state(v, full, 0.0, sin_t, cos_t, start=None if near is None else states[near])
        return states[v].a

    if accel(slowest) <= 0.0:
        v_top, at = 0.0, slowest
    else:
        # a first guess from the closed form with the rolling resistance at the slowest speed, then a bracket
        guess = _closed_form_speed(straight, states[slowest], sin_t, fastest)
        lo, hi = max(slowest, 0.99 * guess), min(fastest, 1.01 * guess)
        while accel(lo) <= 0.0 and lo > slowest:
            lo, hi = max(slowest, lo - 2.0 * (hi - lo)), lo
        while accel(hi) > 0.0 and hi < fastest:
            lo, hi = hi, min(fastest, hi + 2.0 * (hi - lo))
        if accel(hi) > 0.0:
            v_top, at = None, hi
        else:
            v_top = brentq(accel, lo, hi, xtol=1e-8, rtol=1e-11)
            at = v_top
    accel(at)
    return v_top, states[at]


def power_takeover(straight: StraightRunning, below: float, above: float, sin_t: float, cos_t: float) -> float:
    """The speed [m/s] between ``below`` (torque-limited) and ``above`` (power-limited) at which the power
    takes over at full drive, to 1 mm/s (bisection), on a grade ``(sin, cos)``.

    Parameters
    ----------
    straight : StraightRunning
        The vehicle's straight-line model.
    below, above : float
        Speeds bracketing the takeover [m/s].
    sin_t, cos_t : float
        Grade sine and cosine, dimensionless.

    Returns
    -------
    float
        Speed [m/s].
    """
    while above - below > 1e-3:
        middle = 0.5 * (below + above)
        if straight.state(middle, straight.max_torque, 0.0, sin_t, cos_t).limit == "power":
            above = middle
        else:
            below = middle
    return 0.5 * (below + above)
