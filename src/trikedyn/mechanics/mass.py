"""Mass properties of rigid bodies and their composition (parallel-axis theorem).

:class:`MassProperties` (mass, CG, inertia about the CG) with point masses and boxes; adding and removing
payloads is exact. Used by the measurement side (CG from weighings, payload), the parameter sets and the
multibody model alike. Lengths [m], masses [kg], inertias [kg m^2]; vehicle axes x forward, y left, z up.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError

__all__ = ["Box", "MassProperties", "Payload", "PointMass", "combine"]


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
    """Combine rigidly attached parts into one :class:`MassProperties` (parallel-axis theorem).

    Parameters
    ----------
    parts : iterable of MassProperties, PointMass, Box or Payload
        The parts, each in vehicle axes; anything with a ``mass_properties()`` method is reduced to its
        :class:`MassProperties` first.

    Returns
    -------
    MassProperties
        Total mass [kg], combined CG [m] and inertia about that CG [kg m^2].

    Raises
    ------
    InputError
        If the total mass is not positive.
    """
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
        """The :class:`MassProperties` of the point: its mass [kg] at its position [m], no inertia of its own.

        Returns
        -------
        MassProperties
            Mass [kg], CG at ``position_m`` [m], zero inertia about the CG [kg m^2].
        """
        return MassProperties(_check_mass(self.mass_kg, self.name), self.position_m)


@dataclass(frozen=True)
class Box:
    """A uniform box [kg] centred at ``centre_m`` with edge lengths ``size_m`` (along x, y, z) [m]."""

    mass_kg: float
    centre_m: tuple[float, float, float]
    size_m: tuple[float, float, float]
    name: str = "box"

    def mass_properties(self) -> MassProperties:
        """The :class:`MassProperties` of the uniform box, inertia m/12 (b^2 + c^2) etc. about its centre.

        Returns
        -------
        MassProperties
            Mass [kg], CG at ``centre_m`` [m], diagonal inertia about the centre [kg m^2].

        Raises
        ------
        InputError
            On a negative or non-finite mass or a negative edge length.
        """
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
        """Total mass of the payload's items [kg]."""
        return float(sum(_check_mass(i.mass_kg, i.name) for i in self.items))

    def mass_properties(self) -> MassProperties:
        """The :class:`MassProperties` of all the items together (zero mass at the origin when empty).

        Returns
        -------
        MassProperties
            Total mass [kg], combined CG [m] and inertia about it [kg m^2].
        """
        return combine(self.items) if self.mass_kg > 0 else MassProperties(0.0, np.zeros(3))

    def added_to(self, base: MassProperties) -> MassProperties:
        """The assembly ``base`` with this payload aboard.

        Parameters
        ----------
        base : MassProperties
            The vehicle (or assembly) without the payload: mass [kg], CG [m], inertia [kg m^2].

        Returns
        -------
        MassProperties
            ``base`` plus the payload (``base`` itself for an empty payload).
        """
        return base if self.mass_kg == 0 else base + self.mass_properties()

    def removed_from(self, base: MassProperties) -> MassProperties:
        """The assembly ``base`` with this payload taken off.

        Parameters
        ----------
        base : MassProperties
            The vehicle (or assembly) with the payload aboard.

        Returns
        -------
        MassProperties
            ``base`` minus the payload (``base`` itself for an empty payload).

        Raises
        ------
        InputError
            If the payload weighs as much as ``base`` or more.
        """
        return base if self.mass_kg == 0 else base - self.mass_properties()
