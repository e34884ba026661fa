"""Centre of gravity from wheel weighings, and mass composition (payload added or removed).

The paper (section 2.1, Fig. 3) finds the CG of its trike from the loads under the three wheels:
x and y from a level weighing, z from weighings with one axle raised to several heights. These are the
reductions here, as pure functions with uncertainties (after BicycleParameters' ``com.py``):

* :func:`cg_from_level_weighing` -- x and y from the wheel loads and the contact points (moment balance);
* :func:`cg_height_from_tilted_weighings` -- z from weighings with the front (or rear) axle raised,
  least squares over all heights, with a standard uncertainty from the residuals;
* :func:`wheel_loads_from_cg` -- the inverse (static loads of a rigid three-point support), for round
  trips and for audits.

Mass composition (:class:`MassProperties`, point masses, boxes, payloads) and the static support loads
live in :mod:`trikedyn.mechanics` and are re-exported here.
All lengths [m], masses [kg], forces [N], angles [rad]; vehicle axes x forward, y left, z up.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..mechanics import Box, MassProperties, Payload, PointMass, combine, wheel_loads_from_cg
from ..mechanics.support import as_points
from ..units import STANDARD_GRAVITY

__all__ = [
    "Box",
    "LevelWeighingResult",
    "MassProperties",
    "Payload",
    "PointMass",
    "TiltedWeighingResult",
    "cg_from_level_weighing",
    "cg_height_from_tilted_weighings",
    "combine",
    "tilted_wheel_loads",
    "wheel_loads_from_cg",
]


# ------------------------------------------------------------------------------------------------
# Weighing reduction
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class LevelWeighingResult:
    """CG ground projection from a level weighing, with its standard uncertainty."""

    mass_kg: float
    cg_x_m: float
    cg_y_m: float
    mass_std_kg: float
    cg_x_std_m: float
    cg_y_std_m: float

    def to_dict(self) -> dict:
        """The result as a dict of floats (masses [kg], lengths [m], as the fields).

        Returns
        -------
        dict
            Field name -> value.
        """
        return {k: float(v) for k, v in self.__dict__.items()}


def cg_from_level_weighing(
    loads_N, contacts_xy_m, *, load_std_N: float = 0.0, position_std_m: float = 0.0, g: float = STANDARD_GRAVITY
) -> LevelWeighingResult:
    """CG x and y from the vertical loads of level wheels (the paper's Fig. 3a-b).

    ``x = sum(F_i x_i) / sum(F_i)``, ``y = sum(F_i y_i) / sum(F_i)`` (moment balance about the origin).

    Parameters
    ----------
    loads_N : array_like, shape (n,)
        Load under each wheel [N] (scale readings times g).
    contacts_xy_m : array_like, shape (n, 2)
        Contact points (x, y) [m].
    load_std_N : float
        Standard uncertainty of each load reading [N].
    position_std_m : float
        Standard uncertainty of each contact coordinate [m].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    LevelWeighingResult
        Mass [kg], CG x and y [m] and their first-order standard uncertainties.
    """
    loads = np.asarray(loads_N, dtype=float)
    pts = as_points(contacts_xy_m)
    if loads.shape != (pts.shape[0],):
        raise InputError(f"need one load per contact point ({pts.shape[0]}), got {loads.size}", where="loads")
    if not np.all(np.isfinite(loads)) or np.any(loads < 0):
        raise InputError("wheel loads must be finite and >= 0 N", where="loads")
    total = loads.sum()
    if total <= 0:
        raise InputError("the wheel loads sum to zero", where="loads")
    cg = loads @ pts / total
    # first-order propagation: d cg / d F_i = (p_i - cg) / W, d cg / d p_i = F_i / W
    dcg_dload = (pts - cg) / total
    var = (load_std_N**2) * np.sum(dcg_dload**2, axis=0) + (position_std_m**2) * np.sum((loads / total) ** 2)
    std = np.sqrt(var)
    return LevelWeighingResult(
        total / g, cg[0], cg[1], load_std_N * np.sqrt(loads.size) / g, float(std[0]), float(std[1])
    )


def tilted_wheel_loads(
    mass_kg, cg_m, wheelbase_m, raise_heights_m, *, wheel_radius_m, raised="front", g=STANDARD_GRAVITY
):
    """Axle loads [N] when one axle is raised by ``raise_heights_m`` (forward model of Fig. 3c).

    The vehicle pivots about the lower axle; each contact stays below its axle, so the raised axle's
    load is ``W (x_r cos(theta) - (z - r) sin(theta)) / (L cos(theta))`` with ``x_r`` the CG's distance
    from the lower axle, ``z - r`` its height above the axle line (equal wheel radii ``r``) and
    ``sin(theta) = H / L``.

    Parameters
    ----------
    mass_kg : float
        Vehicle mass [kg].
    cg_m : array_like, shape (3,)
        CG (x from the rear axle, y, z above the ground) [m].
    wheelbase_m : float
        Wheelbase [m].
    raise_heights_m : array_like
        Heights the axle is raised by [m].
    wheel_radius_m : float
        Loaded wheel radius [m].
    raised : {"front", "rear"}
        Which axle is raised.
    g : float
        Gravity [m/s^2].

    Returns
    -------
    numpy.ndarray, shape (n,)
        Load on the raised axle [N] for each height.
    """
    h = np.asarray(raise_heights_m, dtype=float)
    theta = np.arcsin(h / wheelbase_m)
    x, z = float(cg_m[0]), float(cg_m[2]) - wheel_radius_m
    lever = x if raised == "front" else wheelbase_m - x
    return mass_kg * g * (lever * np.cos(theta) - z * np.sin(theta)) / (wheelbase_m * np.cos(theta))


@dataclass(frozen=True)
class TiltedWeighingResult:
    """CG height from tilted weighings: estimate, standard uncertainty and residuals."""

    cg_z_m: float
    cg_z_std_m: float
    heights_m: np.ndarray
    per_height_z_m: np.ndarray
    residuals_N: np.ndarray

    def to_dict(self) -> dict:
        """The result as a JSON-ready dict.

        Returns
        -------
        dict
            ``cg_z_m``, ``cg_z_std_m`` [m], ``heights_m`` [m] and ``per_height_z_m`` [m] as lists.
        """
        return {
            "cg_z_m": float(self.cg_z_m),
            "cg_z_std_m": float(self.cg_z_std_m),
            "heights_m": self.heights_m.tolist(),
            "per_height_z_m": self.per_height_z_m.tolist(),
        }


def cg_height_from_tilted_weighings(
    raised_axle_loads_N,
    raise_heights_m,
    *,
    mass_kg: float,
    cg_x_m: float,
    wheelbase_m: float,
    wheel_radius_m: float,
    raised: str = "front",
    load_std_N: float = 0.0,
    g: float = STANDARD_GRAVITY,
) -> TiltedWeighingResult:
    """CG height from the raised axle's load at several raise heights (the paper's Fig. 3c).

    With ``theta = asin(H / L)``, moment balance about the lower contact line gives
    ``F L cos(theta) = W (x_r cos(theta) - (z - r) sin(theta))`` for every height, linear in ``z``:
    ``z - r = (W x_r - F L) / (W tan(theta))``. All heights are combined by least squares in the loads,
    ``(W tan(theta_i)) (z - r) = W x_r - F_i L``, so the heights that tell most about ``z`` (large tilt)
    weigh most. The uncertainty is the larger of the residual scatter and the propagated
    ``load_std_N`` (the scatter needs at least two heights).

    Parameters
    ----------
    raised_axle_loads_N : array_like
        Load on the raised axle at each height [N] (for a delta trike raised at the front, the front
        wheel's load; raised at the rear, the sum of both rear wheels).
    raise_heights_m : array_like
        Height of the raised axle's contact above the other's [m]; > 0.
    mass_kg, cg_x_m, wheelbase_m : float
        From the level weighing: mass [kg], CG ahead of the rear axle [m], wheelbase [m].
    wheel_radius_m : float
        Loaded wheel radius, the axle height [m] (equal front and rear).
    raised : {"front", "rear"}
        Which axle is raised.
    load_std_N : float
        Standard uncertainty of one load reading [N].
    g : float
        Gravity [m/s^2].

    Returns
    -------
    TiltedWeighingResult
    """
    loads = np.asarray(raised_axle_loads_N, dtype=float).ravel()
    h = np.asarray(raise_heights_m, dtype=float).ravel()
    if loads.size != h.size or loads.size == 0:
        raise InputError("need one raised-axle load per raise height", where="raised_axle_loads_N")
    if np.any(h <= 0) or np.any(h >= wheelbase_m):
        raise InputError(f"raise heights must lie in (0, {wheelbase_m:g}) m", where="raise_heights_m")
    if raised not in ("front", "rear"):
        raise InputError(f"raised must be 'front' or 'rear', got {raised!r}", where="raised")
    weight = mass_kg * g
    tan = np.tan(np.arcsin(h / wheelbase_m))
    lever = cg_x_m if raised == "front" else wheelbase_m - cg_x_m
    a = weight * tan
    b = weight * lever - loads * wheelbase_m
    z_axle = float(a @ b / (a @ a))
    residuals = b - a * z_axle
    z = z_axle + wheel_radius_m
    per_height = b / a + wheel_radius_m
    # uncertainty: d z / d F_i = -L a_i / (a.a)
    propagated = load_std_N * wheelbase_m / np.sqrt(a @ a)
    scatter = np.sqrt((residuals @ residuals) / (loads.size - 1) / (a @ a)) if loads.size > 1 else 0.0
    return TiltedWeighingResult(z, float(max(propagated, scatter)), h, per_height, residuals)
