"""The driver: a preview path-follower on the steering servo and a PI speed controller (compiled).

Steering: **pure pursuit** (Amidi 1990; Coulter 1992, CMU-RI-TR-92-01), the single-point preview model
of many driver studies. The reference point is the centre of the rear axle (the chassis origin); the goal
point lies on the path a preview distance ``L_d = max(L_min, T_p v)`` ahead of the nearest path point
(speed-dependent preview). With ``alpha`` the angle between the vehicle heading and the line to the goal
point, the kinematic road steer angle is ``delta = atan(2 L sin(alpha) / L_d)`` (``L`` the wheelbase),
optionally plus an understeer feed-forward ``K_us v^2 kappa``. Like MacAdam's (1981) preview driver, the
driver looks from where the vehicle *will be* when the steering acts: the pose is predicted ahead by
``T_pred`` (its delay plus its lag) at the current speed and yaw rate. The driver's own dynamics:

* a reaction delay ``tau`` (a delay line at the step rate),
* a first-order neuromuscular lag with time constant ``T_n`` (the few-Hz bandwidth of the arms),
* a steering-rate limit,

and the road steer angle is turned into the angle about the raked steering axis, ``delta / cos(rake)``,
which the steering servo of the model tracks.

Speed: a PI controller on the speed error toward a target speed profile; a positive demand is drive
torque (through the open differential), a negative one brake torque shared by the braked wheels; the
integral is clamped (anti-windup) to what the drive and brakes can give.

The controller is discrete: it runs once per time step at the step's start and holds its commands over
the step (zero-order hold), as a digital controller would.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._jit import jit
from ..model.rhs import interpolate_inputs

__all__ = ["DRIVER", "DRIVER_STATE", "PATH_COLUMNS", "DriverSettings", "driver_array", "driver_step", "open_loop_driver",
           "past_end_gate", "with_end_gate", "with_steering"]

DRIVER = np.dtype(
    [
        ("on", "f8"),  # 1: the driver closes the loop; 0: open-loop inputs
        ("preview_time", "f8"),  # T_p [s]
        ("preview_min", "f8"),  # L_min [m]
        ("rate_limit", "f8"),  # steering rate limit about the steering axis [rad/s]; < 0: the vehicle's
        ("delay_steps", "i8"),  # reaction delay in time steps
        ("lag", "f8"),  # neuromuscular lag T_n [s]
        ("kp", "f8"),  # speed controller P gain [N m / (m/s)]
        ("ki", "f8"),  # speed controller I gain [N m / m]
        ("kus", "f8"),  # understeer feed-forward K_us [rad / (m/s^2)]
        ("predict", "f8"),  # T_pred [s]
        ("steer_open", "f8"),  # 1: the steer comes from the input table
        ("hold_after", "f8"),  # hold the steering from this time on [s]; < 0: never
        ("end_at_gate", "f8"),  # 1: the run ends at the first record with the CG beyond the end gate (past_end_gate)
        ("gate_x", "f8"),  # a point of the end gate's line [m]
        ("gate_y", "f8"),
        ("gate_cos", "f8"),  # the direction the gate is passed in (unit vector)
        ("gate_sin", "f8"),
        ("cg_x", "f8"),  # the CG in chassis axes from the chassis origin, plan view [m]
        ("cg_y", "f8"),
    ],
    align=True,
)
"""The driver's settings (one record)."""

DRIVER_STATE = np.dtype(
    [("integral", "f8"), ("write", "i8"), ("lagged", "f8"), ("output", "f8"), ("index", "i8")], align=True
)
"""The driver's memory: speed error integral, delay-line write position, lagged steer, rate-limited steer,
path index."""
PATH_COLUMNS = ("x_m", "y_m", "s_m", "heading_rad", "curvature_per_m")


def open_loop_driver() -> np.ndarray:
    """The driver record of an open-loop run (``on = 0``).

    Returns
    -------
    numpy.ndarray, shape (1,), dtype DRIVER
        The record, all zeros.
    """
    return np.zeros(1, DRIVER)


@dataclass(frozen=True)
class DriverSettings:
    """The driver's parameters (defaults: an attentive test driver; see the module docstring).

    Attributes
    ----------
    preview_time_s : float
        ``T_p``: preview distance per speed [s].
    preview_min_m : float
        ``L_min``: shortest preview distance [m].
    reaction_delay_s : float
        ``tau`` [s].
    neuromuscular_lag_s : float
        ``T_n`` [s].
    steer_rate_limit_radps : float
        Fastest steering about the steering axis [rad/s] (the vehicle's ``max_rate_deg_per_s`` if None).
    speed_kp_Nm_per_mps, speed_ki_Nm_per_m : float
        PI gains of the speed controller [N m / (m/s)], [N m / m].
    understeer_gradient_rad_per_mps2 : float
        Feed-forward ``K_us`` [rad / (m/s^2)]; 0 for a purely kinematic driver.
    prediction_s : float, optional
        ``T_pred`` [s]; the reaction delay plus the neuromuscular lag by default.
    """

    preview_time_s: float = 0.3
    preview_min_m: float = 3.0
    reaction_delay_s: float = 0.05
    neuromuscular_lag_s: float = 0.05
    steer_rate_limit_radps: float | None = None
    speed_kp_Nm_per_mps: float = 300.0
    speed_ki_Nm_per_m: float = 150.0
    understeer_gradient_rad_per_mps2: float = 0.0
    prediction_s: float | None = None


def driver_array(settings: DriverSettings, params, dt: float) -> np.ndarray:
    """The driver's settings as a :data:`DRIVER` record (a length-1 array) for the compiled loop.

    The vehicle values the driver uses (wheelbase, rake, lock, drive and brake torques) it reads from the
    plant's vehicle record; ``params`` gives only the default steering rate limit.

    Parameters
    ----------
    settings : DriverSettings
        The driver's settings (preview time [s], preview distance [m], delay [s], lag [s], gains ...).
    params : VehicleParameters
        The vehicle (its steering rate limit).
    dt : float
        Time step of the loop [s] (the delay line's length).

    Returns
    -------
    numpy.ndarray, shape (1,), dtype DRIVER
        The record.

    Raises
    ------
    InputError
        On a negative or non-finite time, or a steering rate limit that is not positive.
    """
    from ..errors import InputError

    for name in ("preview_time_s", "preview_min_m", "reaction_delay_s", "neuromuscular_lag_s"):
        value = getattr(settings, name)
        if not np.isfinite(value) or value < 0:
            raise InputError(f"must be a finite number >= 0, got {value!r}", where=f"driver.{name}")
    rate = settings.steer_rate_limit_radps
    rate = math.radians(params.steering.max_rate_deg_per_s) if rate is None else rate
    if rate <= 0:
        raise InputError(f"must be > 0, got {rate!r}", where="driver.steer_rate_limit_radps")
    out = np.zeros(1, DRIVER)
    d = out[0]
    d["on"] = 1.0
    d["preview_time"] = settings.preview_time_s
    d["preview_min"] = max(settings.preview_min_m, 0.1)
    d["rate_limit"] = rate
    d["delay_steps"] = int(round(settings.reaction_delay_s / dt))
    d["lag"] = settings.neuromuscular_lag_s
    d["kp"] = settings.speed_kp_Nm_per_mps
    d["ki"] = settings.speed_ki_Nm_per_m
    d["kus"] = settings.understeer_gradient_rad_per_mps2
    predict = settings.prediction_s
    d["predict"] = settings.reaction_delay_s + settings.neuromuscular_lag_s if predict is None else predict
    d["hold_after"] = -1.0
    return out


def with_steering(drv: np.ndarray, *, open_loop: bool = False, hold_after_s: float | None = None) -> np.ndarray:
    """The driver array with its steering mode set: ``open_loop`` takes the steer command from the input
    table (the driver only holds the speed); ``hold_after_s`` freezes the steering from that time on [s].

    Parameters
    ----------
    drv : numpy.ndarray, shape (1,), dtype DRIVER
        The driver record (not changed).
    open_loop : bool
        Steer from the input table.
    hold_after_s : float, optional
        Time from which the steering is held [s]; never when None.

    Returns
    -------
    numpy.ndarray, shape (1,), dtype DRIVER
        The copy.
    """
    out = drv.copy()
    out[0]["steer_open"] = 1.0 if open_loop else 0.0
    out[0]["hold_after"] = -1.0 if hold_after_s is None else float(hold_after_s)
    return out


def with_end_gate(drv: np.ndarray, gate: tuple[float, float, float, float], cg: tuple[float, float]) -> np.ndarray:
    """The driver array of a run that ends at the first record with its CG beyond a gate line
    (:func:`past_end_gate`): a threshold search's runs end past their exit gate, where the judging ends.

    Parameters
    ----------
    drv : numpy.ndarray, shape (1,), dtype DRIVER
        The driver record (not changed).
    gate : tuple of float
        ``(x, y, cos, sin)``: a point of the gate's line [m] and the unit direction it is passed in.
    cg : tuple of float
        The CG from the chassis origin in chassis axes, plan view ``(x, y)`` [m].

    Returns
    -------
    numpy.ndarray, shape (1,), dtype DRIVER
        The copy.
    """
    out = drv.copy()
    d = out[0]
    d["end_at_gate"] = 1.0
    d["gate_x"], d["gate_y"], d["gate_cos"], d["gate_sin"] = (float(v) for v in gate)
    d["cg_x"], d["cg_y"] = (float(v) for v in cg)
    return out


@jit(inline="always")
def past_end_gate(px, py, yaw, d):
    """Whether a run that ends at a gate (``d.end_at_gate``, :func:`with_end_gate`) has its CG beyond it.

    Parameters
    ----------
    px, py : float
        The chassis origin's plan-view position [m].
    yaw : float
        The chassis heading [rad].
    d : record
        The run's :data:`DRIVER` record (its gate and the CG's place in the chassis).

    Returns
    -------
    bool
        True when the CG lies on the far side of the gate's line; False for a run without a gate.
    """
    if d.end_at_gate <= 0.0:
        return False
    c, s = math.cos(yaw), math.sin(yaw)
    gx = px + d.cg_x * c - d.cg_y * s
    gy = py + d.cg_x * s + d.cg_y * c
    return (gx - d.gate_x) * d.gate_cos + (gy - d.gate_y) * d.gate_sin > 0.0


@jit
def _nearest(path, px, py, start):
    """Index of the path point nearest to (px, py), searching forward and backward from ``start``."""
    m = path.shape[0]
    best = start
    dx = path[start, 0] - px
    dy = path[start, 1] - py
    dbest = dx * dx + dy * dy
    i = start + 1
    while i < m:
        dx = path[i, 0] - px
        dy = path[i, 1] - py
        d = dx * dx + dy * dy
        if d < dbest:
            dbest = d
            best = i
        elif d > dbest + 4.0:  # moved well past the nearest point
            break
        i += 1
    i = start - 1
    while i >= 0:
        dx = path[i, 0] - px
        dy = path[i, 1] - py
        d = dx * dx + dy * dy
        if d < dbest:
            dbest = d
            best = i
        elif d > dbest + 4.0:
            break
        i -= 1
    return best


@jit
def _pursuit(t, dt, px, py, yaw, yaw_rate, speed, path, drv, veh, state, delay_line):
    """Pure pursuit from the pose predicted ``T_pred`` ahead, through the delay, lag and rate limit."""
    tp = drv.predict
    mid = yaw + 0.5 * yaw_rate * tp
    px = px + speed * tp * math.cos(mid)
    py = py + speed * tp * math.sin(mid)
    yaw = yaw + yaw_rate * tp
    idx = _nearest(path, px, py, state.index)
    state.index = idx
    m = path.shape[0]
    preview = max(drv.preview_min, drv.preview_time * abs(speed))
    ds = path[1, 2] - path[0, 2]
    goal = min(m - 1, idx + int(preview / ds))
    gx = path[goal, 0] - px
    gy = path[goal, 1] - py
    alpha = math.atan2(gy, gx) - yaw
    alpha = math.atan2(math.sin(alpha), math.cos(alpha))
    dist = max(math.sqrt(gx * gx + gy * gy), 1e-6)
    road = math.atan(2.0 * veh.wheelbase * math.sin(alpha) / dist)
    road += drv.kus * speed * speed * path[idx, 4]
    wanted = road / veh.cos_rake
    # reaction delay: write now, read what was written delay steps ago
    n_delay = drv.delay_steps
    size = delay_line.shape[0]
    write = state.write
    delay_line[write] = wanted
    delayed = delay_line[(write - n_delay) % size]
    state.write = (write + 1) % size
    # neuromuscular lag (exact discretisation of a first-order lag), then the rate limit
    if drv.lag > 0.0:
        a = math.exp(-dt / drv.lag)
        state.lagged = a * state.lagged + (1.0 - a) * delayed
    else:
        state.lagged = delayed
    rate = drv.rate_limit if drv.rate_limit > 0.0 else veh.max_steer_rate
    step_max = rate * dt
    change = min(max(state.lagged - state.output, -step_max), step_max)
    steer = min(max(state.output + change, -veh.max_steer), veh.max_steer)
    state.output = steer
    return steer


@jit
def driver_step(t, dt, px, py, yaw, yaw_rate, speed, path, speed_profile, drv, veh, memory, delay_line, inputs):
    """One step of the driver: steer command about the steering axis [rad], drive torque [N m], brake
    torque per braked wheel [N m]. ``(px, py)`` is the rear-axle centre, ``yaw`` the heading, ``speed``
    the forward speed; ``drv`` the :data:`DRIVER` record, ``veh`` the plant's vehicle record; ``memory`` (a
    length-1 :data:`DRIVER_STATE` array, owned by the caller for the whole run: a record taken from a temporary
    array would outlive its memory) and ``delay_line`` carry the controller's memory between steps.

    Parameters
    ----------
    t : float
        Time [s].
    dt : float
        Time step [s].
    px, py : float
        Rear-axle centre in the world [m].
    yaw : float
        Heading [rad].
    yaw_rate : float
        Yaw rate [rad/s].
    speed : float
        Forward speed [m/s].
    path : numpy.ndarray, shape (m, 5)
        Path rows (x [m], y [m], s [m], heading [rad], curvature [1/m]).
    speed_profile : numpy.ndarray, shape (k, 2)
        Target speed rows (time [s], speed [m/s]).
    drv : record
        The :data:`DRIVER` record.
    veh : record
        The plant's vehicle record.
    memory : numpy.ndarray, shape (1,), dtype DRIVER_STATE
        The controller's memory, updated.
    delay_line : numpy.ndarray
        Past steer demands [rad], updated.
    inputs : numpy.ndarray, shape (m, 4)
        The input table (time [s], steer [rad], drive [N m], brake [N m]) for open-loop steering.

    Returns
    -------
    steer, drive, brake : float
        Steer command [rad], drive torque [N m], brake torque per braked wheel [N m].
    """
    state = memory[0]
    # --- steering: held still, from the input table (open loop), or pure pursuit on the path
    if drv.hold_after >= 0.0 and t >= drv.hold_after:
        steer = state.output
    elif drv.steer_open > 0.0:
        steer, _, _ = interpolate_inputs(t, inputs)
        state.output = steer
    else:
        steer = _pursuit(t, dt, px, py, yaw, yaw_rate, speed, path, drv, veh, state, delay_line)
    # --- speed: PI toward the target speed, with anti-windup
    if speed_profile.shape[0] == 1:
        target = speed_profile[0, 1]
    else:
        target = np.interp(t, speed_profile[:, 0], speed_profile[:, 1])
    error = target - speed
    max_brake = veh.max_brake * veh.n_braked
    demand = drv.kp * error + drv.ki * (state.integral + error * dt)
    if -max_brake < demand < veh.max_torque:
        state.integral += error * dt
    drive = 0.0
    brake = 0.0
    if demand >= 0.0:
        drive = min(demand, veh.max_torque)
    else:
        brake = min(-demand, max_brake) / max(veh.n_braked, 1)
    return steer, drive, brake
