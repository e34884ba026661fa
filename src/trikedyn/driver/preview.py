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

__all__ = ["DriverSettings", "driver_array", "driver_step", "with_steering", "N_DRIVER", "N_DRIVER_STATE",
           "PATH_COLUMNS"]

(
    D_ON,
    D_PREVIEW_TIME,
    D_PREVIEW_MIN,
    D_WHEELBASE,
    D_COS_RAKE,
    D_MAX_STEER,
    D_RATE_LIMIT,
    D_DELAY_STEPS,
    D_LAG,
    D_KP,
    D_KI,
    D_MAX_DRIVE,
    D_MAX_BRAKE,
    D_KUS,
    D_PREDICT,
    D_STEER_OPEN,
    D_HOLD_AFTER,
) = range(17)
N_DRIVER = 17
# controller state: speed error integral, delayed-line write position, lagged steer, rate-limited steer, path index
S_INTEGRAL, S_WRITE, S_LAGGED, S_OUTPUT, S_INDEX = range(5)
N_DRIVER_STATE = 5
PATH_COLUMNS = ("x_m", "y_m", "s_m", "heading_rad", "curvature_per_m")


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
    """Pack the driver's settings and the vehicle values it uses into the compiled loop's array."""
    from ..errors import InputError

    for name in ("preview_time_s", "preview_min_m", "reaction_delay_s", "neuromuscular_lag_s"):
        value = getattr(settings, name)
        if not np.isfinite(value) or value < 0:
            raise InputError(f"must be a finite number >= 0, got {value!r}", where=f"driver.{name}")
    rate = settings.steer_rate_limit_radps
    rate = math.radians(params.steering.max_rate_deg_per_s) if rate is None else rate
    if rate <= 0:
        raise InputError(f"must be > 0, got {rate!r}", where="driver.steer_rate_limit_radps")
    out = np.zeros(N_DRIVER)
    out[D_ON] = 1.0
    out[D_PREVIEW_TIME] = settings.preview_time_s
    out[D_PREVIEW_MIN] = max(settings.preview_min_m, 0.1)
    out[D_WHEELBASE] = params.wheelbase_m
    out[D_COS_RAKE] = math.cos(math.radians(params.steering.axis_angle_deg))
    out[D_MAX_STEER] = math.radians(params.steering.max_angle_deg)
    out[D_RATE_LIMIT] = rate
    out[D_DELAY_STEPS] = float(int(round(settings.reaction_delay_s / dt)))
    out[D_LAG] = settings.neuromuscular_lag_s
    out[D_KP] = settings.speed_kp_Nm_per_mps
    out[D_KI] = settings.speed_ki_Nm_per_m
    out[D_MAX_DRIVE] = params.drive.max_drive_torque_Nm
    n_braked = sum(w.braked for w in params.wheels)
    out[D_MAX_BRAKE] = params.drive.max_brake_torque_Nm * n_braked
    out[D_KUS] = settings.understeer_gradient_rad_per_mps2
    predict = settings.prediction_s
    out[D_PREDICT] = settings.reaction_delay_s + settings.neuromuscular_lag_s if predict is None else predict
    out[D_HOLD_AFTER] = -1.0
    return out


def with_steering(drv: np.ndarray, *, open_loop: bool = False, hold_after_s: float | None = None) -> np.ndarray:
    """The driver array with its steering mode set: ``open_loop`` takes the steer command from the input
    table (the driver only holds the speed); ``hold_after_s`` freezes the steering from that time on [s]."""
    out = drv.copy()
    out[D_STEER_OPEN] = 1.0 if open_loop else 0.0
    out[D_HOLD_AFTER] = -1.0 if hold_after_s is None else float(hold_after_s)
    return out


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
def _pursuit(t, dt, px, py, yaw, yaw_rate, speed, path, drv, state, delay_line):
    """Pure pursuit from the pose predicted ``T_pred`` ahead, through the delay, lag and rate limit."""
    tp = drv[D_PREDICT]
    mid = yaw + 0.5 * yaw_rate * tp
    px = px + speed * tp * math.cos(mid)
    py = py + speed * tp * math.sin(mid)
    yaw = yaw + yaw_rate * tp
    idx = _nearest(path, px, py, int(state[S_INDEX]))
    state[S_INDEX] = idx
    m = path.shape[0]
    preview = max(drv[D_PREVIEW_MIN], drv[D_PREVIEW_TIME] * abs(speed))
    ds = path[1, 2] - path[0, 2]
    goal = min(m - 1, idx + int(preview / ds))
    gx = path[goal, 0] - px
    gy = path[goal, 1] - py
    alpha = math.atan2(gy, gx) - yaw
    alpha = math.atan2(math.sin(alpha), math.cos(alpha))
    dist = max(math.sqrt(gx * gx + gy * gy), 1e-6)
    road = math.atan(2.0 * drv[D_WHEELBASE] * math.sin(alpha) / dist)
    road += drv[D_KUS] * speed * speed * path[idx, 4]
    wanted = road / drv[D_COS_RAKE]
    # reaction delay: write now, read what was written delay steps ago
    n_delay = int(drv[D_DELAY_STEPS])
    size = delay_line.shape[0]
    write = int(state[S_WRITE])
    delay_line[write] = wanted
    delayed = delay_line[(write - n_delay) % size]
    state[S_WRITE] = (write + 1) % size
    # neuromuscular lag (exact discretisation of a first-order lag), then the rate limit
    if drv[D_LAG] > 0.0:
        a = math.exp(-dt / drv[D_LAG])
        state[S_LAGGED] = a * state[S_LAGGED] + (1.0 - a) * delayed
    else:
        state[S_LAGGED] = delayed
    step_max = drv[D_RATE_LIMIT] * dt
    change = min(max(state[S_LAGGED] - state[S_OUTPUT], -step_max), step_max)
    steer = min(max(state[S_OUTPUT] + change, -drv[D_MAX_STEER]), drv[D_MAX_STEER])
    state[S_OUTPUT] = steer
    return steer


@jit
def driver_step(t, dt, px, py, yaw, yaw_rate, speed, path, speed_profile, drv, state, delay_line, n_braked, inputs):
    """One step of the driver: steer command about the steering axis [rad], drive torque [N m], brake
    torque per braked wheel [N m]. ``(px, py)`` is the rear-axle centre, ``yaw`` the heading, ``speed``
    the forward speed; ``state`` and ``delay_line`` carry the controller's memory between steps."""
    # --- steering: held still, from the input table (open loop), or pure pursuit on the path
    if drv[D_HOLD_AFTER] >= 0.0 and t >= drv[D_HOLD_AFTER]:
        steer = state[S_OUTPUT]
    elif drv[D_STEER_OPEN] > 0.0:
        steer, _, _ = interpolate_inputs(t, inputs)
        state[S_OUTPUT] = steer
    else:
        steer = _pursuit(t, dt, px, py, yaw, yaw_rate, speed, path, drv, state, delay_line)
    # --- speed: PI toward the target speed, with anti-windup
    if speed_profile.shape[0] == 1:
        target = speed_profile[0, 1]
    else:
        target = np.interp(t, speed_profile[:, 0], speed_profile[:, 1])
    error = target - speed
    demand = drv[D_KP] * error + drv[D_KI] * (state[S_INTEGRAL] + error * dt)
    if -drv[D_MAX_BRAKE] < demand < drv[D_MAX_DRIVE]:
        state[S_INTEGRAL] += error * dt
    drive = 0.0
    brake = 0.0
    if demand >= 0.0:
        drive = min(demand, drv[D_MAX_DRIVE])
    else:
        brake = min(-demand, drv[D_MAX_BRAKE]) / max(n_braked, 1)
    return steer, drive, brake
