"""Static loads of a rigid vehicle on its contact points."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..units import STANDARD_GRAVITY

__all__ = ["as_points", "wheel_loads_from_cg"]


def as_points(contacts) -> np.ndarray:
    """Contact points as an ``(n >= 3, 2)`` float array of (x, y) [m]; an InputError otherwise.

    Parameters
    ----------
    contacts : array_like, shape (n, 2)
        Contact points (x, y) in vehicle axes [m], at least three.

    Returns
    -------
    numpy.ndarray, shape (n, 2)
        The points as floats [m].

    Raises
    ------
    InputError
        If the array is not of shape (n >= 3, 2).
    """
    pts = np.asarray(contacts, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 3:
        raise InputError("contact points must be an (n >= 3, 2) array of (x, y) [m]", where="contacts")
    return pts


def wheel_loads_from_cg(mass_kg: float, cg_xy_m, contacts_xy_m, g: float = STANDARD_GRAVITY) -> np.ndarray:
    """Static wheel loads [N] of a rigid vehicle on three level contact points.

    Solves vertical force balance and the two moment balances (statically determinate for three
    non-collinear points).

    Parameters
    ----------
    mass_kg : float
        Mass [kg].
    cg_xy_m : array_like, shape (2,)
        CG ground projection (x, y) [m].
    contacts_xy_m : array_like, shape (3, 2)
        Wheel contact points (x, y) [m].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    numpy.ndarray, shape (3,)
        Vertical load on each wheel [N], in the order of ``contacts_xy_m``.
    """
    pts = as_points(contacts_xy_m)
    a = np.vstack([np.ones(3), pts[:, 0], pts[:, 1]])
    b = mass_kg * g * np.array([1.0, cg_xy_m[0], cg_xy_m[1]])
    return np.linalg.solve(a, b)
