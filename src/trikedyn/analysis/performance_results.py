"""What the straight-line performance functions return (:mod:`trikedyn.analysis.performance`): the top speed
(:class:`TopSpeed`), the acceleration run (:class:`Acceleration`), the stop (:class:`Braking`) and the three of
one vehicle on one grade (:class:`Performance`); each ``to_dict`` is plain JSON (non-finite numbers as None).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Acceleration", "Braking", "Performance", "TopSpeed"]


def _plain(value):
    """JSON-ready: floats (None when not finite), lists, dicts with string keys."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    return value.item() if isinstance(value, np.generic) else value


class _Result:
    def to_dict(self) -> dict:
        """Plain JSON types (non-finite numbers as None)."""
        return _plain(dict(self.__dict__))


@dataclass(frozen=True)
class TopSpeed(_Result):
    """The highest steady speed at full drive, and what holds it there.

    Attributes
    ----------
    top_speed_kmh : float or None
        [km/h]; 0 when the vehicle cannot climb (or move), None when nothing balances the drive (it runs
        away downhill).
    limit : str
        ``"power"``, ``"torque"``, ``"traction"``, ``"cannot climb"``, ``"cannot move"``,
        ``"runs away downhill"`` or ``"no balance"``.
    grade_percent : float
        Road grade [%], ``tan(theta) = grade / 100``; negative downhill.
    drive_torque_Nm : float
        Total drive torque at the driven wheels [N m] (at the top speed; at
        :data:`~trikedyn.analysis.performance.CRAWL_KMH` when it cannot move).
    power_W : float
        Drive power at the wheels, torque times the driven wheels' mean spin rate [W].
    drive_force_N : float
        Drive torque over the wheel radius, ``sum tau_i / R_i`` [N].
    rolling_resistance_N : float
        ``sum f_r F_z,i R_e,i / R_i``: the tyres' rolling-resistance moments as a force at the road [N].
    aero_drag_N : float
        ``0.5 rho C_d A v^2`` [N].
    grade_resistance_N : float
        ``M g sin(theta)`` [N], negative downhill.
    wheel_loads_N : dict
        Vertical load per wheel [N].
    slips : dict
        Longitudinal slip per wheel [1].
    detail : str
        The result in words.
    """

    top_speed_kmh: float | None
    limit: str
    grade_percent: float
    drive_torque_Nm: float
    power_W: float
    drive_force_N: float
    rolling_resistance_N: float
    aero_drag_N: float
    grade_resistance_N: float
    wheel_loads_N: dict = field(default_factory=dict)
    slips: dict = field(default_factory=dict)
    detail: str = ""


@dataclass(frozen=True)
class Acceleration(_Result):
    """Acceleration at full drive from one speed to another.

    Attributes
    ----------
    from_kmh, to_kmh : float
        [km/h].
    time_s : float or None
        Time taken [s]; None when the vehicle does not reach ``to_kmh`` (its top speed is lower).
    distance_m : float or None
        Distance covered [m].
    grade_percent : float
        [%].
    power_limited_from_kmh : float or None
        Speed above which the power, not the torque, limits the drive [km/h] (None: not in the range).
    traction_limited : bool
        True when a driven wheel was at its tyre's peak force somewhere in the range.
    detail : str
    """

    from_kmh: float
    to_kmh: float
    time_s: float | None
    distance_m: float | None
    grade_percent: float
    power_limited_from_kmh: float | None
    traction_limited: bool
    detail: str = ""


@dataclass(frozen=True)
class Braking(_Result):
    """Braking with the full brake torque on every braked wheel, from a speed to rest.

    Attributes
    ----------
    from_kmh : float
        [km/h].
    distance_m : float or None
        Distance to slow to :data:`~trikedyn.analysis.performance.STOP_KMH` [m]; None when the brakes cannot (a
        steep downhill grade).
    time_s : float or None
        Time to slow to :data:`~trikedyn.analysis.performance.STOP_KMH` [s].
    mean_deceleration_mps2 : float or None
        ``v0^2 / (2 s)`` [m/s^2].
    grade_percent : float
        [%].
    locked_wheels : dict
        Each wheel that locks, and the speed at which it locks [km/h].
    detail : str
    """

    from_kmh: float
    distance_m: float | None
    time_s: float | None
    mean_deceleration_mps2: float | None
    grade_percent: float
    locked_wheels: dict = field(default_factory=dict)
    detail: str = ""


@dataclass(frozen=True)
class Performance:
    """Top speed, acceleration and braking of one vehicle on one grade
    (:func:`~trikedyn.analysis.performance.performance`)."""

    vehicle: str
    mass_kg: float
    grade_percent: float
    top_speed: TopSpeed
    acceleration: Acceleration
    braking: Braking

    def to_dict(self) -> dict:
        """Plain JSON types: the top speed's figures at the top level (``top_speed_kmh``, ``limit``, ...), the
        acceleration and braking as their own objects.

        Returns
        -------
        dict
            The figures, JSON-safe (speeds [km/h], times [s], distances [m]).
        """
        return {"vehicle": self.vehicle, "mass_kg": float(self.mass_kg), "grade_percent": float(self.grade_percent),
                **self.top_speed.to_dict(), "acceleration": self.acceleration.to_dict(),
                "braking": self.braking.to_dict()}
