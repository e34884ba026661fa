"""Output channels computed from recorded states (compiled; one pass over the samples).

Channels per sample: chassis pose and rates, velocities and accelerations at the vehicle's CG in chassis
axes (as an accelerometer there would read them without gravity), the steer angle, and per wheel the
tyre forces, slips, deflection, suspension travel and spin; the rollover index of Eq. 5,
``RI = (Fz_right - Fz_left) / (Fz_right + Fz_left)`` over the two-wheel axle, and the load transfer
ratio over all wheels, ``LTR = (sum Fz_right - sum Fz_left) / sum Fz``.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit

__all__ = ["BASE_CHANNELS", "WHEEL_CHANNELS", "IMU_CHANNELS", "compute_channels", "imu_readings"]

IMU_CHANNELS = ("ax_mps2", "ay_mps2", "az_mps2", "wx_radps", "wy_radps", "wz_radps", "roll_rad", "pitch_rad", "yaw_rad")
"""An IMU fixed to the chassis: specific force and angular rate in chassis axes, and its Euler angles
(the names of :mod:`trikedyn.measure.logs`)."""

BASE_CHANNELS = (
    "x_m",
    "y_m",
    "z_m",
    "roll_rad",
    "pitch_rad",
    "yaw_rad",
    "roll_rate_radps",
    "pitch_rate_radps",
    "yaw_rate_radps",
    "vx_mps",
    "vy_mps",
    "vz_mps",
    "ax_mps2",
    "ay_mps2",
    "az_mps2",
    "speed_mps",
    "steer_rad",
)
WHEEL_CHANNELS = {
    "fx_N": "fx", "fy_N": "fy", "fz_N": "fz", "kappa": "kappa", "alpha_rad": "alpha", "deflection_m": "deflection",
    "travel_m": "travel", "spin_radps": "spin", "vx_mps": "vx", "mz_Nm": "mz", "camber_rad": "camber",
}
"""Per-wheel channels (``<wheel>_<name>``) and the :data:`~trikedyn.model.packing.WHEEL_OUT` field of each."""


@jit
def point_motion(state, deriv, point, n):
    """Velocity and classical acceleration [m/s, m/s^2] of a point fixed in the chassis, chassis axes.

    With the chassis' body-frame velocity ``(w, v)`` and its rate: ``v_p = v + w x p`` and
    ``a_p = dv/dt + dw/dt x p + w x v_p``.
    """
    w = state[n : n + 3]
    vp = state[n + 3 : n + 6] + np.cross(w, point)
    ap = deriv[n + 3 : n + 6] + np.cross(deriv[n : n + 3], point) + np.cross(w, vp)
    return vp, ap


@jit
def compute_channels(states, derivs, cg, steer_index, n):
    """Chassis channels from recorded states and their derivatives (no re-evaluation).

    Parameters
    ----------
    states : numpy.ndarray, shape (m, n_states)
        Recorded states.
    derivs : numpy.ndarray, shape (m, n_states)
        Their derivatives.
    cg : numpy.ndarray, shape (3,)
        Chassis CG in chassis axes [m].
    steer_index : int
        State index of the steer joint (negative when none).
    n : int
        Number of generalised coordinates (the velocities start at ``n``).

    Returns
    -------
    ndarray (m, len(BASE_CHANNELS))
    """
    m = states.shape[0]
    base = np.empty((m, 17))
    for i in range(m):
        x = states[i]
        vc, ac = point_motion(x, derivs[i], cg, n)
        base[i, 0:6] = x[0:6]
        base[i, 6:9] = x[n : n + 3]
        base[i, 9:12] = vc
        base[i, 12:15] = ac
        base[i, 15] = np.sqrt(vc[0] * vc[0] + vc[1] * vc[1])
        base[i, 16] = x[5 + steer_index] if steer_index > 0 else 0.0
    return base


@jit
def imu_readings(states, derivs, sensor, gravity, n):
    """What an IMU fixed to the chassis at ``sensor`` (chassis axes [m]) reads at each recorded sample.

    Accelerometer: the specific force ``a - g`` of the sensor point in chassis axes (reads ``+g`` up at
    rest); gyroscope: the chassis angular velocity; angles: roll, pitch, yaw.

    Parameters
    ----------
    states : numpy.ndarray, shape (m, n_states)
        Recorded states.
    derivs : numpy.ndarray, shape (m, n_states)
        Their derivatives.
    sensor : numpy.ndarray, shape (3,)
        Sensor position in chassis axes [m].
    gravity : float
        Gravity [m/s^2].
    n : int
        Number of generalised coordinates (the velocities start at ``n``).

    Returns
    -------
    ndarray (m, 9)
        Columns as :data:`IMU_CHANNELS`.
    """
    m = states.shape[0]
    out = np.empty((m, 9))
    for i in range(m):
        x = states[i]
        w = x[n : n + 3]
        _, acc = point_motion(x, derivs[i], sensor, n)
        cr, sr = np.cos(x[3]), np.sin(x[3])
        cp, sp = np.cos(x[4]), np.sin(x[4])
        # gravity (0, 0, -g) in chassis axes: R^T (0, 0, -g) = -g (third row of R)
        gx = gravity * sp
        gy = -gravity * cp * sr
        gz = -gravity * cp * cr
        out[i, 0] = acc[0] - gx
        out[i, 1] = acc[1] - gy
        out[i, 2] = acc[2] - gz
        out[i, 3:6] = w
        out[i, 6:9] = x[3:6]
    return out
