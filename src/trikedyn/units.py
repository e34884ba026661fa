"""Unit conversions. trikedyn is SI inside; other units appear only at the edges (CLI, files).

Unit labels: the terminal, JSON keys, file formats and docstrings write plain ASCII (``m/s^2``, ``kg m^2``,
``mps2`` in names); figures and the HTML report write them typeset (``m/s²``).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["STANDARD_GRAVITY", "deg_to_rad", "g_to_mps2", "kmh_to_mps", "mps_to_kmh", "rad_to_deg"]

STANDARD_GRAVITY = 9.80665
"""Standard acceleration of gravity [m/s^2] (ISO 80000-3)."""


def kmh_to_mps(speed_kmh):
    """Convert a speed from [km/h] to [m/s].

    Parameters
    ----------
    speed_kmh : float or array_like
        Speed [km/h].

    Returns
    -------
    float or numpy.ndarray
        Speed [m/s] (a float for a scalar input).
    """
    return np.asarray(speed_kmh, dtype=float) / 3.6 if np.ndim(speed_kmh) else float(speed_kmh) / 3.6


def mps_to_kmh(speed_mps):
    """Convert a speed from [m/s] to [km/h].

    Parameters
    ----------
    speed_mps : float or array_like
        Speed [m/s].

    Returns
    -------
    float or numpy.ndarray
        Speed [km/h] (a float for a scalar input).
    """
    return np.asarray(speed_mps, dtype=float) * 3.6 if np.ndim(speed_mps) else float(speed_mps) * 3.6


def deg_to_rad(angle_deg):
    """Convert an angle from [deg] to [rad].

    Parameters
    ----------
    angle_deg : float or array_like
        Angle [deg].

    Returns
    -------
    float or numpy.ndarray
        Angle [rad] (a float for a scalar input).
    """
    return np.deg2rad(angle_deg) if np.ndim(angle_deg) else math.radians(angle_deg)


def rad_to_deg(angle_rad):
    """Convert an angle from [rad] to [deg].

    Parameters
    ----------
    angle_rad : float or array_like
        Angle [rad].

    Returns
    -------
    float or numpy.ndarray
        Angle [deg] (a float for a scalar input).
    """
    return np.rad2deg(angle_rad) if np.ndim(angle_rad) else math.degrees(angle_rad)


def g_to_mps2(accel_g):
    """Convert an acceleration from standard gravities [g] to [m/s^2].

    Parameters
    ----------
    accel_g : float or array_like
        Acceleration in standard gravities [g] (1 g = 9.80665 m/s^2).

    Returns
    -------
    float or numpy.ndarray
        Acceleration [m/s^2] (a float for a scalar input).
    """
    return np.asarray(accel_g, dtype=float) * STANDARD_GRAVITY if np.ndim(accel_g) else float(accel_g) * STANDARD_GRAVITY
