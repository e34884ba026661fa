"""Centre of gravity from wheel weighings, and mass composition (payload added or removed).

The paper (section 2.1, Fig. 3) finds the CG of its trike from the loads under the three wheels:
x and y from a level weighing, z from weighings with one axle raised to several heights. These are the
reductions here, as pure functions with uncertainties (after BicycleParameters' ``com.py``):

* :func:`cg_from_level_weighing` -- x and y from the wheel loads and the contact points (moment balance);
* :func:`cg_height_from_tilted_weighings` -- z from weighings with the front (or rear) axle raised,
  least squares over all heights, with a standard uncertainty from the residuals;
* :func:`wheel_loads_from_cg` -- the inverse (static loads of a rigid three-point support), for round
  trips and for audits.

Mass composition uses :class:`MassProperties` (mass, CG, inertia about the CG) with point masses and
boxes; adding and removing payloads is exact (parallel-axis theorem).
All lengths [m], masses [kg], forces [N], angles [rad]; vehicle axes x forward, y left, z up.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
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
    "tilted_wheel_loads",
    "wheel_loads_from_cg",
]


# ------------------------------------------------------------------------------------------------
# Mass composition
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class MassProperties:
    """Mass, centre of gravity and inertia tensor of a rigid body or assembly.

    Parameters
    ----------
    mass_kg : float
        Mass [kg]; negative only transiently, never in a result.
    cg_m : array_like, shape (3,)
        Centre of gravity in vehicle axes [m].
    inertia_kgm2 : array_like, shape (3, 3), optional
        Inertia tensor about the CG in vehicle axes [kg m^2]; zero for a point mass.
    """

    mass_kg: float
    cg_m: np.ndarray
    inertia_kgm2: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))

    def __post_init__(self):
        object.__setattr__(self, "cg_m", np.asarray(self.cg_m, dtype=float).reshape(3))
        object.__setattr__(self, "inertia_kgm2", np.asarray(self.inertia_kgm2, dtype=float).reshape(3, 3))

    def _inertia_about_origin(self) -> np.ndarray:
        r = self.cg_m
        return self.inertia_kgm2 + self.mass_kg * (np.dot(r, r) * np.eye(3) - np.outer(r, r))

    def __add__(self, other: MassProperties) -> MassProperties:
        return combine([self, other])

    def __sub__(self, other: MassProperties) -> MassProperties:
        """Remove ``other`` (a part of ``self``) from the assembly."""
        mass = self.mass_kg - other.mass_kg
        if mass <= 1e-9 * max(self.mass_kg, 1.0):
            raise InputError(
                f"cannot remove {other.mass_kg:g} kg from an assembly of {self.mass_kg:g} kg", where="payload"
            )
        cg = (self.mass_kg * self.cg_m - other.mass_kg * other.cg_m) / mass
        about_origin = self._inertia_about_origin() - other._inertia_about_origin()
        return MassProperties(mass, cg, about_origin - mass * (np.dot(cg, cg) * np.eye(3) - np.outer(cg, cg)))


def combine(parts) -> MassProperties:
    """Combine rigidly attached parts into one :class:`MassProperties` (parallel-axis theorem)."""
    parts = [p.mass_properties() if hasattr(p, "mass_properties") else p for p in parts]
    mass = sum(p.mass_kg for p in parts)
    if mass <= 0:
        raise InputError(f"total mass must be positive, got {mass:g} kg", where="payload")
    cg = sum(p.mass_kg * p.cg_m for p in parts) / mass
    about_origin = sum(p._inertia_about_origin() for p in parts)
    return MassProperties(mass, cg, about_origin - mass * (np.dot(cg, cg) * np.eye(3) - np.outer(cg, cg)))


def _check_mass(mass_kg: float, what: str) -> float:
    if not np.isfinite(mass_kg) or mass_kg < 0:
        raise InputError(f"mass must be a finite number >= 0 kg, got {mass_kg!r}", where=what)
    return float(mass_kg)


@dataclass(frozen=True)
class PointMass:
    """A point mass [kg] at ``position_m`` (x, y, z) [m]."""

    mass_kg: float
    position_m: tuple[float, float, float]
    name: str = "point mass"

    def mass_properties(self) -> MassProperties:
        return MassProperties(_check_mass(self.mass_kg, self.name), self.position_m)


@dataclass(frozen=True)
class Box:
    """A uniform box [kg] centred at ``centre_m`` with edge lengths ``size_m`` (along x, y, z) [m]."""

    mass_kg: float
    centre_m: tuple[float, float, float]
    size_m: tuple[float, float, float]
    name: str = "box"

    def mass_properties(self) -> MassProperties:
        m = _check_mass(self.mass_kg, self.name)
        a, b, c = (float(s) for s in self.size_m)
        if min(a, b, c) < 0:
            raise InputError(f"box edge lengths must be >= 0 m, got {self.size_m}", where=self.name)
        inertia = m / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
        return MassProperties(m, self.centre_m, inertia)


@dataclass(frozen=True)
class Payload:
    """A named set of point masses and boxes, added to (or removed from) a vehicle.

    Examples
    --------
    >>> freight = Payload("paper-freight", (PointMass(100.0, (0.146, 0.0, 1.094)),))
    >>> freight.mass_kg
    100.0
    """

    name: str
    items: tuple = ()

    @property
    def mass_kg(self) -> float:
        return float(sum(_check_mass(i.mass_kg, i.name) for i in self.items))

    def mass_properties(self) -> MassProperties:
        return combine(self.items) if self.mass_kg > 0 else MassProperties(0.0, np.zeros(3))

    def added_to(self, base: MassProperties) -> MassProperties:
        """The assembly ``base`` with this payload aboard."""
        return base if self.mass_kg == 0 else base + self.mass_properties()

    def removed_from(self, base: MassProperties) -> MassProperties:
        """The assembly ``base`` with this payload taken off."""
        return base if self.mass_kg == 0 else base - self.mass_properties()


# ------------------------------------------------------------------------------------------------
# Weighing reduction
# ------------------------------------------------------------------------------------------------
def _as_points(contacts) -> np.ndarray:
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
    pts = _as_points(contacts_xy_m)
    a = np.vstack([np.ones(3), pts[:, 0], pts[:, 1]])
    b = mass_kg * g * np.array([1.0, cg_xy_m[0], cg_xy_m[1]])
    return np.linalg.solve(a, b)


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
    pts = _as_points(contacts_xy_m)
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
