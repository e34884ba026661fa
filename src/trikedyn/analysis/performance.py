"""Straight-line performance: top speed (on the flat or a grade), acceleration 0-30 km/h, braking from 30 km/h.

Everything here is the model's own straight running, quasi-static: the forces the compiled right-hand side
(:func:`trikedyn.model.rhs.evaluate_into`) applies, taken in balance at each speed, with no simulation. The
model (drive, wheels, vehicle, wheel loads, braked wheels that lock) is described in, and evaluated by,
:mod:`trikedyn.analysis.straight_line`; this module gives its results.

Top speed (:func:`top_speed`)
-----------------------------
The speed at which the acceleration at full drive is zero (Brent's method on the quasi-static
acceleration, from a closed-form first guess). ``limit`` names the term that holds the drive torque there:
``"power"``, ``"torque"``, or ``"traction"`` (the weaker driven wheel is at its tyre's peak force, and the
open differential gives the other no more torque: what a traction control would hold; without one the
simulated wheel spins up and the power limit takes its torque). At the top speed the balance reads
``sum tau_i / R_i = F_rolling + F_aero + F_grade`` with ``F_rolling = sum f_r F_z,i R_e,i / R_i``. Three
words say the vehicle has no top speed:

* ``"cannot climb"`` (``"cannot move"`` on the flat or downhill), top speed 0: at :data:`CRAWL_KMH` the full
  drive does not overcome the grade and the rolling resistance. Slower balances are reported so too: below
  a few km/h the model's low-speed regularisation (slip over ``v_low``, rolling resistance smoothed over
  ``w_low``) rules, and the vehicle at best creeps.
* ``"runs away downhill"`` (``"no balance"`` on the flat or uphill), top speed None: no speed up to
  :data:`MAX_SPEED_KMH` balances drive, drag and slope (a vehicle without drag on a slope that pulls
  harder than its rolling resistance).

Downhill the top speed is the finite balance of drive and slope against the drag (reference-etrike: 74.5 km/h
at -5 %, 180.5 km/h at -50 %); ``detail`` says when the slope alone pulls harder than the rolling resistance
(the vehicle would coast downhill). The model has no motor speed limit: the drive gives its full power at
any speed.

Verified (``tests/analysis/test_performance.py``): reference-etrike's top speed is 54.87 km/h, 0.49 % below
the hand power balance ``P = (M g C_rr + rho C_d A v^2 / 2) v`` (55.14 km/h). The difference is the model's
own, not an approximation here: the driven wheels' slip (0.5 %) and the force arm ``R`` against their rolling
radius ``R_e`` (1.0 %) take 1.5 % of the power at the road. Simulated full-drive runs of 150 s
(:func:`trikedyn.simulate.run.simulate`) settle 0.001 % above it (reference-tadpole: 0.003 % below; the
residual is the rigid load transfer and the drag along the slightly pitched chassis axis). The grade is
checked by the closed form only (the simulated road is flat): with the same two losses by hand within 0.3 %.

Acceleration (:func:`acceleration`) and braking (:func:`braking`)
-----------------------------------------------------------------
Integrated over speed, ``t = int dv / a(v)``, ``s = int v dv / a(v)``, with the quasi-static acceleration
at full drive (torque, power and traction limits, the wheels' inertia and load transfer) or with
``max_brake_torque_Nm`` on every braked wheel; a braked wheel whose tyre cannot carry the brake torque locks,
and stays locked, sliding with its tyre's force near full lock (:mod:`trikedyn.analysis.straight_line`).
Against open-loop simulations on reference-etrike: acceleration 3 -> 30 km/h 0.02 % in time, 0.03 % in
distance (at the default 10 ms step); braking from 30 km/h to :data:`STOP_KMH` 0.3 % in distance
and 0.5 % in time, both rear wheels locked from the start (at a 1 ms step: at the default 10 ms the brake's
``tanh(omega / w_low)``, stiff for a wheel near lock, makes the simulated wheels chatter; the residual is the
suspension's pitch overshoot at the brake's onset). reference-tadpole: 0.13 % and 0.2 % (its front pair
locks); on a PAC2002 ``.tir`` tyre at every wheel 0.13 % and 0.7 %.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .performance_results import Acceleration, Braking, Performance, TopSpeed
from .straight_balance import full_drive_balance, power_takeover
from .straight_line import StraightRunning, cache_key, straight_running, vehicle_model

__all__ = ["CRAWL_KMH", "MAX_GRADE_PERCENT", "MAX_SPEED_KMH", "STOP_KMH", "acceleration", "braking", "performance",
           "top_speed"]

CRAWL_KMH = 5.0
"""Slowest top speed reported [km/h]: a slower balance (or none) is ``"cannot climb"`` / ``"cannot move"``."""
MAX_SPEED_KMH = 400.0
"""Fastest top speed searched [km/h]; no balance below it is ``"runs away downhill"`` (``"no balance"``)."""
MAX_GRADE_PERCENT = 100.0
"""Steepest grade the functions take, up or down [%] (45 deg)."""
STOP_KMH = 0.5
"""Braking stops here [km/h]: distance and time are to this speed."""


def _grade(grade_percent: float) -> tuple[float, float]:
    grade = float(grade_percent)
    if not (math.isfinite(grade) and abs(grade) <= MAX_GRADE_PERCENT):
        raise InputError(f"must be within -{MAX_GRADE_PERCENT:g} .. {MAX_GRADE_PERCENT:g} %, got {grade_percent!r}",
                         where="grade_percent")
    theta = math.atan(grade / 100.0)
    return math.sin(theta), math.cos(theta)


def _speed(value: float, where: str, low: float = 0.0) -> float:
    speed = float(value)
    if not (math.isfinite(speed) and low <= speed <= MAX_SPEED_KMH):
        raise InputError(f"must be within {low:g} .. {MAX_SPEED_KMH:g} km/h, got {value!r}", where=where)
    return speed


def _where(grade: float) -> str:
    return "on the flat" if grade == 0.0 else f"{'up' if grade > 0 else 'down'} a {abs(grade):g} % grade"


# ------------------------------------------------------------------------------------------------------------
# top speed
# ------------------------------------------------------------------------------------------------------------
def _top_speed(straight: StraightRunning, grade: float) -> TopSpeed:
    sin_t, cos_t = _grade(grade)
    crawl, fastest = CRAWL_KMH / 3.6, MAX_SPEED_KMH / 3.6
    v_top, s = full_drive_balance(straight, sin_t, cos_t, crawl, fastest)
    if v_top is None:
        limit, at = "runs away downhill" if grade < 0.0 else "no balance", fastest
    elif v_top == 0.0:
        limit, at = "cannot climb" if grade > 0 else "cannot move", crawl
    else:
        limit, at = s.limit, v_top
    radii = straight.radius
    shares = np.where(straight.driven, s.torque / straight.n_driven, 0.0)
    mean_spin = float(np.abs(s.spin[straight.driven]).mean()) if straight.driven.any() else 0.0
    power = s.torque * mean_spin
    rolling = float(np.sum(-s.my / radii))
    aero = straight.drag * at * at
    slope = straight.mass * straight.g * sin_t
    names = [w.name for w in straight.wheels]
    where = _where(grade)
    pull = f"{-slope:.0f} N downhill pull"
    if v_top is None:
        detail = (f"{limit} {where}: no speed up to {MAX_SPEED_KMH:g} km/h balances the drive"
                  + (f" and the {pull}" if slope < 0.0 else "") + f" against {rolling:.0f} N rolling resistance and "
                  f"the drag")
    elif v_top == 0.0:
        against = f"{rolling:.0f} N rolling" + (f" + {slope:.0f} N grade" if slope > 0.0 else "")
        detail = (f"{limit} {where}: at {CRAWL_KMH:g} km/h the full drive ({s.torque:.0f} N m, {_limit_word(s.limit)})"
                  f" gives {float(np.sum(shares / radii)):.0f} N against {against}")
    else:
        against = f"{rolling:.0f} N rolling + {aero:.0f} N aero" + (f" + {slope:.0f} N grade" if slope > 0.0 else "")
        detail = f"{limit}-limited: {power / 1000:.1f} kW at the wheels against {against}"
        if slope < 0.0:
            detail += f", with {pull}"
    if slope < 0.0 and -slope > rolling:
        detail += "; the slope alone pulls harder than the rolling resistance: it would coast downhill"
    return TopSpeed(
        top_speed_kmh=None if v_top is None else float(v_top * 3.6),
        limit=limit,
        grade_percent=float(grade),
        drive_torque_Nm=float(s.torque),
        power_W=float(power),
        drive_force_N=float(np.sum(shares / radii)),
        rolling_resistance_N=rolling,
        aero_drag_N=float(aero),
        grade_resistance_N=float(slope),
        wheel_loads_N={n: float(f) for n, f in zip(names, s.fz, strict=True)},
        slips={n: float(k) for n, k in zip(names, s.kappa, strict=True)},
        detail=detail,
    )


def _limit_word(limit: str) -> str:
    """The limit as an adjective: ``"power"`` -> ``"power-limited"``; other words unchanged."""
    return f"{limit}-limited" if limit in ("power", "torque", "traction") else limit


def top_speed(vehicle, grade_percent: float = 0.0) -> TopSpeed:
    """The vehicle's top speed at full drive on the flat or on a grade, and what limits it.

    Quasi-static, no simulation: about 2.5 ms for a parameter set (the model built and its static equilibrium
    solved), 1.2 ms for a :class:`~trikedyn.model.vehicle.VehicleModel` whose equilibrium is known (kept in
    ``model.cache``, with this function's setup and results; each wheel's spin balance and its secant steps are
    compiled, :mod:`~trikedyn.analysis.wheel_balance`); the first call in a process also loads the compiled
    tyre function and right-hand side from numba's cache (about 0.3 s). The model is
    :mod:`trikedyn.analysis.straight_line`'s; see the module docstring for its verification (a simulated
    full-drive run settles within 0.001 % of it).

    Parameters
    ----------
    vehicle : ParameterSet, VehicleParameters or VehicleModel
        The vehicle with its payload (:func:`trikedyn.params.with_freight`).
    grade_percent : float
        Road grade [%], ``tan(theta) = grade / 100``, within +-:data:`MAX_GRADE_PERCENT`; negative downhill.

    Returns
    -------
    TopSpeed
        ``top_speed_kmh`` [km/h] and ``limit`` (``"power"``, ``"torque"``, ``"traction"``; ``"cannot climb"``
        / ``"cannot move"`` with 0 km/h; ``"runs away downhill"`` / ``"no balance"`` with None), the
        resistances at that speed [N] and the drive power [W].

    Raises
    ------
    InputError
        For a grade out of range or not a number.
    """
    _grade(grade_percent)
    model = vehicle_model(vehicle)
    key = cache_key(model, "top_speed", float(grade_percent))
    if key not in model.cache:
        model.cache[key] = _top_speed(straight_running(model), float(grade_percent))
    return model.cache[key]


# ------------------------------------------------------------------------------------------------------------
# acceleration and braking
# ------------------------------------------------------------------------------------------------------------
def _integrate(speeds, accels):
    """Time [s] and distance [m] over a speed grid with the accelerations there (trapezoidal rule)."""
    speeds, accels = np.asarray(speeds), np.asarray(accels)
    dv = np.diff(speeds)
    inv = 1.0 / accels
    time = float(np.sum(0.5 * (inv[1:] + inv[:-1]) * dv))
    distance = float(np.sum(0.5 * (speeds[1:] * inv[1:] + speeds[:-1] * inv[:-1]) * dv))
    return time, distance


def acceleration(vehicle, to_kmh: float = 30.0, *, from_kmh: float = 0.0, grade_percent: float = 0.0,
                 points: int = 160) -> Acceleration:
    """Time and distance to accelerate at full drive from ``from_kmh`` to ``to_kmh``.

    ``t = int dv / a(v)``, ``s = int v dv / a(v)`` over ``points`` speeds (denser at the start), with the
    quasi-static acceleration at full drive: torque, power and traction limits, resistances, the wheels'
    spin inertia and the load transfer (:mod:`trikedyn.analysis.straight_line`). Against an open-loop
    simulation at full drive from 3 km/h (``tests/analysis/test_performance.py``): 0.02 % in time, 0.03 % in
    distance.

    Parameters
    ----------
    vehicle : ParameterSet, VehicleParameters or VehicleModel
    to_kmh, from_kmh : float
        End and start speeds [km/h], ``0 <= from_kmh < to_kmh``.
    grade_percent : float
        Road grade [%].
    points : int
        Speeds of the quadrature.

    Returns
    -------
    Acceleration
        ``time_s`` [s] and ``distance_m`` [m] (None when the top speed is below ``to_kmh``).
    """
    to_kmh, from_kmh = _speed(to_kmh, "to_kmh"), _speed(from_kmh, "from_kmh")
    if not from_kmh < to_kmh:
        raise InputError(f"must be below to_kmh ({to_kmh:g} km/h), got {from_kmh:g}", where="from_kmh")
    sin_t, cos_t = _grade(grade_percent)
    model = vehicle_model(vehicle)
    straight = straight_running(model)
    v0, v1 = from_kmh / 3.6, to_kmh / 3.6
    top = top_speed(model, grade_percent)
    if top.top_speed_kmh is not None and top.top_speed_kmh <= to_kmh:
        why = (f"{top.limit} {_where(grade_percent)}" if top.top_speed_kmh == 0.0 else
               f"does not reach {to_kmh:g} km/h {_where(grade_percent)}: top speed {top.top_speed_kmh:.1f} km/h "
               f"({top.limit})")
        return Acceleration(from_kmh, to_kmh, None, None, float(grade_percent), None, False, why)
    # denser at the start, where the regularisation and the slip change fastest
    u = np.linspace(0.0, 1.0, int(points))
    speeds = v0 + (v1 - v0) * u**1.5
    accels, corner, traction, state, before = [], None, False, None, None
    for v in speeds:
        state = straight.state(v, straight.max_torque, 0.0, sin_t, cos_t, start=state)
        accels.append(state.a)
        if state.limit == "power" and corner is None:
            corner = v * 3.6 if before is None else power_takeover(straight, before, v, sin_t, cos_t) * 3.6
        traction |= state.limit == "traction"
        before = v
    time, distance = _integrate(speeds, accels)
    detail = (f"{from_kmh:g} -> {to_kmh:g} km/h {_where(grade_percent)} in {time:.2f} s over {distance:.1f} m"
              + (f"; power-limited from {corner:.1f} km/h" if corner is not None else "; torque-limited throughout")
              + ("; a driven wheel at its grip limit" if traction else ""))
    return Acceleration(from_kmh, to_kmh, time, distance, float(grade_percent),
                        None if corner is None else float(corner), bool(traction), detail)


def braking(vehicle, from_kmh: float = 30.0, *, grade_percent: float = 0.0, points: int = 200) -> Braking:
    """Distance and time to stop from ``from_kmh`` with the full brake torque on every braked wheel.

    Quasi-static over speed, ``s = int v dv / |a(v)|`` on ``points`` speeds (geometric, from ``from_kmh``
    down to :data:`STOP_KMH`; the rest of the way, a few millimetres, is left out): each braked wheel takes
    ``max_brake_torque_Nm``; its force is limited by its tyre's grip at its load (with the load transfer); a
    wheel whose tyre cannot carry the brake torque locks and slides with its tyre's force near full lock,
    and stays locked (:mod:`trikedyn.analysis.straight_line`). Against open-loop simulations from 30 km/h
    (at a 1 ms step: the default 10 ms step is too long for a wheel near lock): 0.3 % in distance, 0.5 % in
    time (``tests/analysis/test_performance.py``).

    Parameters
    ----------
    vehicle : ParameterSet, VehicleParameters or VehicleModel
    from_kmh : float
        Initial speed [km/h], above :data:`STOP_KMH`.
    grade_percent : float
        Road grade [%]; downhill lengthens the distance.
    points : int
        Speeds of the quadrature.

    Returns
    -------
    Braking
        ``distance_m`` [m] and ``time_s`` [s] to :data:`STOP_KMH` (None when the brakes cannot slow the
        vehicle to it: a steep downhill grade; the model's brakes fade below a wheel spin of ``w_low``, so on
        a slope the vehicle creeps on below that), the mean deceleration and the wheels that lock, with the
        speed at which they lock.
    """
    from_kmh = _speed(from_kmh, "from_kmh")
    if from_kmh <= STOP_KMH:
        raise InputError(f"must be > {STOP_KMH:g} km/h, got {from_kmh:g}", where="from_kmh")
    sin_t, cos_t = _grade(grade_percent)
    model = vehicle_model(vehicle)
    straight = straight_running(model)
    v0 = from_kmh / 3.6
    speeds = np.geomspace(v0, STOP_KMH / 3.6, int(points))
    names = [w.name for w in straight.wheels]
    accels, locked, locked_at, state = [], None, {}, None
    for i, v in enumerate(speeds):
        state = straight.state(v, 0.0, straight.max_brake, sin_t, cos_t, locked=locked, start=state)
        locked = state.locked
        for k, name in enumerate(names):
            if locked[k] and name not in locked_at:
                locked_at[name] = from_kmh if i == 0 else float(v * 3.6)
        if state.a >= 0.0:
            if v * 3.6 < CRAWL_KMH:
                why = (f"the brakes hold the vehicle to a creep of {v * 3.6:.1f} km/h {_where(grade_percent)}, not "
                       f"to a stop (the model's brakes fade below a wheel spin of w_low = {straight.w_low:g} rad/s)")
            else:
                why = f"the brakes do not slow the vehicle below {v * 3.6:.1f} km/h {_where(grade_percent)}"
            return Braking(from_kmh, None, None, None, float(grade_percent), locked_at, why)
        accels.append(state.a)
    accels = np.array(accels)
    time, distance = _integrate(speeds[::-1], -accels[::-1])
    mean = v0**2 / (2.0 * distance)
    which = ", ".join(f"{n} at {s:.1f} km/h" for n, s in locked_at.items()) or "none"
    detail = (f"from {from_kmh:g} km/h {_where(grade_percent)}: {distance:.2f} m and {time:.2f} s to {STOP_KMH:g} km/h, "
              f"mean {mean:.2f} m/s^2; locked wheels: {which}")
    return Braking(from_kmh, distance, time, float(mean), float(grade_percent), locked_at, detail)


def performance(vehicle, grade_percent: float = 0.0, *, accelerate_to_kmh: float = 30.0,
                brake_from_kmh: float = 30.0) -> Performance:
    """Top speed, acceleration from rest to ``accelerate_to_kmh`` and braking from ``brake_from_kmh``.

    Parameters
    ----------
    vehicle : ParameterSet, VehicleParameters or VehicleModel
    grade_percent : float
        Road grade [%] for all three.
    accelerate_to_kmh, brake_from_kmh : float
        [km/h].

    Returns
    -------
    Performance
    """
    _grade(grade_percent)
    model = vehicle_model(vehicle)
    return Performance(
        vehicle=model.params.name,
        mass_kg=float(model.tree.total_mass()),
        grade_percent=float(grade_percent),
        top_speed=top_speed(model, grade_percent),
        acceleration=acceleration(model, accelerate_to_kmh, grade_percent=grade_percent),
        braking=braking(model, brake_from_kmh, grade_percent=grade_percent),
    )
