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


@jit(inline="always")
def point_motion(state, deriv, point, n):
    """Velocity and classical acceleration [m/s, m/s^2] of a point fixed in the chassis, chassis axes, as six
    floats ``(vx, vy, vz, ax, ay, az)`` (no allocation: it runs once per recorded sample).

    With the chassis' body-frame velocity ``(w, v)`` and its rate: ``v_p = v + w x p`` and
    ``a_p = dv/dt + dw/dt x p + w x v_p``.
    """
    w0, w1, w2 = state[n], state[n + 1], state[n + 2]
    d0, d1, d2 = deriv[n], deriv[n + 1], deriv[n + 2]
    p0, p1, p2 = point[0], point[1], point[2]
    v0 = state[n + 3] + (w1 * p2 - w2 * p1)
    v1 = state[n + 4] + (w2 * p0 - w0 * p2)
    v2 = state[n + 5] + (w0 * p1 - w1 * p0)
    a0 = deriv[n + 3] + (d1 * p2 - d2 * p1) + (w1 * v2 - w2 * v1)
    a1 = deriv[n + 4] + (d2 * p0 - d0 * p2) + (w2 * v0 - w0 * v2)
    a2 = deriv[n + 5] + (d0 * p1 - d1 * p0) + (w0 * v1 - w1 * v0)
    return v0, v1, v2, a0, a1, a2


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
        v0, v1, v2, a0, a1, a2 = point_motion(x, derivs[i], cg, n)
        for k in range(6):
            base[i, k] = x[k]
        for k in range(3):
            base[i, 6 + k] = x[n + k]
        base[i, 9], base[i, 10], base[i, 11] = v0, v1, v2
        base[i, 12], base[i, 13], base[i, 14] = a0, a1, a2
        base[i, 15] = np.sqrt(v0 * v0 + v1 * v1)
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
        _, _, _, a0, a1, a2 = point_motion(x, derivs[i], sensor, n)
        cr, sr = np.cos(x[3]), np.sin(x[3])
        cp, sp = np.cos(x[4]), np.sin(x[4])
        # gravity (0, 0, -g) in chassis axes: R^T (0, 0, -g) = -g (third row of R)
        gx = gravity * sp
        gy = -gravity * cp * sr
        gz = -gravity * cp * cr
        out[i, 0] = a0 - gx
        out[i, 1] = a1 - gy
        out[i, 2] = a2 - gz
        for k in range(3):
            out[i, 3 + k] = x[n + k]
            out[i, 6 + k] = x[3 + k]
    return out
