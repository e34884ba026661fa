"""Plausibility of a vehicle file at load: values the schema accepts that look typed in another unit, or a
tyre file made for another wheel.

The schema (:mod:`trikedyn.params.schema`) refuses what no vehicle has; what is left may still be a slip. A
loaded parameter set is looked at once (:func:`warn_implausible`, called by
:func:`trikedyn.params.load_vehicle` and :func:`~trikedyn.params.parse_vehicle`), and each finding is one
:class:`~trikedyn.plausibility.PlausibilityWarning` naming the file, the field, the value and why it looks
wrong; the set loads all the same. The findings (:func:`implausible_values`):

- **an angle in radians in a degree field**, field by field. ``steering.axis_angle_deg`` in
  :data:`RAKE_AS_RADIANS` (0.05 to 0.8): as degrees, a rake under 1 deg, which no fork or kingpin is built
  with (a vertical axis is written 0); as radians, 2.9 to 46 deg, the rakes trikes have.
  ``steering.max_angle_deg`` and ``steering.max_rate_deg_per_s`` need no rule here: their least values
  (5 deg, 10 deg/s) already refuse any lock or rate in radians (at most 1.4 rad, and human rates in rad/s
  below 10), with a hint of radians in the error (:func:`trikedyn.plausibility.unit_slip_hint`); above
  them a value is plausible only in degrees (10 rad/s is 573 deg/s, beyond the 200-500 deg/s of ISO 7401).
- **a tyre file of another size**: a wheel's ``.tir`` whose ``UNLOADED_RADIUS`` differs from the wheel's
  ``radius_m`` by more than :data:`TYRE_RADIUS_TOLERANCE` (10 %). The model rolls the wheel on ``radius_m``
  while the file's Magic Formula takes its moment arms (aligning, overturning, rolling resistance) and
  relaxation lengths from ``UNLOADED_RADIUS``; when one is twice the other, a diameter is named.
- **a tyre file of another load**: ``FNOMIN`` more than :data:`FNOMIN_FACTOR` (10) times off the wheel's
  static load, as a force unit slip (kN, kgf) or a tyre made for another vehicle gives. ``trikedyn vehicle
  check`` also rates the nominal load against the static loads, more finely (:mod:`trikedyn.params.audit`).
- **a spring rate in N/mm**: a ``stiffness_N_per_m`` on which a wheel's static load would sink more than
  :data:`MAX_STATIC_SAG_M` (1 m, a natural frequency under 0.5 Hz, which no road vehicle has) while the
  value in N/mm would give a sag under 0.3 m.
- **a damping in N s/mm**: a ``damping_Ns_per_m`` giving a damping ratio under :data:`MIN_DAMPING_RATIO`
  (0.01) on the wheel's static load while the value in N s/mm gives 0.05 to 2.

Static loads here are those of the vehicle with its driver on level ground (rigid, without payload), from
``[mass]`` and the contact points; a wheel whose load is not positive (a CG outside the support, which the
audit reports) is left out.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

from ..mechanics import wheel_loads_from_cg
from ..plausibility import PlausibilityWarning
from ..units import STANDARD_GRAVITY
from .schema import VehicleParameters

__all__ = ["FNOMIN_FACTOR", "MAX_STATIC_SAG_M", "MIN_DAMPING_RATIO", "RAKE_AS_RADIANS", "TYRE_RADIUS_TOLERANCE",
           "implausible_values", "warn_implausible"]

RAKE_AS_RADIANS = (0.05, 0.8)
"""``steering.axis_angle_deg`` in this interval [deg] is warned about as radians (see the module docstring)."""

TYRE_RADIUS_TOLERANCE = 0.10
"""Largest relative difference of a ``.tir`` file's ``UNLOADED_RADIUS`` from its wheel's ``radius_m`` [1]."""

FNOMIN_FACTOR = 10.0
"""Largest factor between a ``.tir`` file's ``FNOMIN`` and its wheel's static load, either way [1]."""

MAX_STATIC_SAG_M = 1.0
"""Largest static sag of a spring under its wheel's static load [m] before its rate is taken for N/mm."""

MIN_DAMPING_RATIO = 0.01
"""Least damping ratio on a wheel's static load before a (non-zero) damping is taken for N s/mm [1]."""

_TYPICAL_SAG_M = 0.3
_TYPICAL_DAMPING = (0.05, 2.0)


def _static_loads(params: VehicleParameters) -> dict[str, float]:
    """Static load of each wheel [N]: the vehicle with its driver, rigid, on level ground (no payload)."""
    m = params.mass
    contacts = [(w.x_m, w.y_m) for w in params.wheels]
    loads = wheel_loads_from_cg(m.total_kg, (m.cg_x_m, m.cg_y_m), contacts, STANDARD_GRAVITY)
    return {w.name: float(f) for w, f in zip(params.wheels, loads, strict=True)}


def _angles(params: VehicleParameters) -> list[str]:
    rake = params.steering.axis_angle_deg
    low, high = RAKE_AS_RADIANS
    if not low <= rake <= high:
        return []
    return [f"steering.axis_angle_deg = {rake:g} looks like radians ({rake:g} rad is {math.degrees(rake):.1f} "
            f"deg): as degrees, a rake under 1 deg, which no steering axis is built with (a vertical one is 0); "
            "write the angle in degrees"]


def _tyre_files(params: VehicleParameters, tyres: dict, loads: dict[str, float]) -> list[str]:
    found = []
    by_radius: dict[tuple, list[str]] = {}
    by_load: dict[str, list[str]] = {}
    for w in params.wheels:
        tir = tyres.get(w.tyre_file) if w.tyre_file is not None else None
        if tir is None:
            continue
        by_radius.setdefault((w.tyre_file, w.radius_m), []).append(w.name)
        by_load.setdefault(w.tyre_file, []).append(w.name)
    for (file, radius), names in by_radius.items():
        r0 = tyres[file].unloaded_radius
        off = r0 / radius - 1.0
        if abs(off) <= TYRE_RADIUS_TOLERANCE:
            continue
        ratio = max(r0 / radius, radius / r0)
        twice = (" (radius_m looks like the diameter)" if radius > r0 else " (UNLOADED_RADIUS looks like the "
                 "diameter)") if abs(ratio - 2.0) <= 2.0 * TYRE_RADIUS_TOLERANCE else ""
        found.append(
            f"{_wheels(names)}.tyre_file: UNLOADED_RADIUS {r0:g} m of {Path(file).name} is {off:+.0%} off the "
            f"wheel's radius_m {radius:g} m (more than {TYRE_RADIUS_TOLERANCE:.0%}){twice}: the wheel rolls on "
            "radius_m, the file's moment arms and relaxation lengths are for UNLOADED_RADIUS; is it this "
            "wheel's tyre?")
    for file, names in by_load.items():
        fnom = tyres[file].fnomin
        static = [loads[n] for n in names if loads[n] > 0.0]
        if not static:
            continue
        mean = float(np.mean(static))
        if 1.0 / FNOMIN_FACTOR <= fnom / mean <= FNOMIN_FACTOR:
            continue
        found.append(
            f"{_wheels(names)}.tyre_file: FNOMIN {fnom:g} N of {Path(file).name} is {fnom / mean:.3g} times the "
            f"wheel's static load ({mean:.0f} N): beyond a factor {FNOMIN_FACTOR:g}, the Magic Formula is used "
            "far outside its fit; is the file's [UNITS] FORCE right, and is it this wheel's tyre?")
    return found


def _wheels(names: list[str]) -> str:
    return f"wheels[{names[0]}]" if len(names) == 1 else f"wheels[{', '.join(names)}]"


def _suspensions(params: VehicleParameters, loads: dict[str, float]) -> list[str]:
    found = []
    g = STANDARD_GRAVITY
    for name, s in params.suspension.items():
        static = [loads[w.name] for w in params.wheels if w.suspension == name and loads[w.name] > 0.0]
        if not static:
            continue
        load = float(np.mean(static))
        k, c = s.stiffness_N_per_m, s.damping_Ns_per_m
        sag = load / k
        if sag > MAX_STATIC_SAG_M and load / (k * 1e3) < _TYPICAL_SAG_M:
            found.append(
                f"suspension.{name}.stiffness_N_per_m = {k:g}: its wheels' static load ({load:.0f} N) would sink "
                f"it {sag:.3g} m (natural frequency {math.sqrt(g / sag) / (2 * math.pi):.2f} Hz, no road "
                f"vehicle's); did you type N/mm? {k:g} N/mm is {k * 1e3:g} N/m")
            continue
        ratio = c / (2.0 * math.sqrt(k * load / g))
        low, high = _TYPICAL_DAMPING
        if 0.0 < ratio < MIN_DAMPING_RATIO and low <= ratio * 1e3 <= high:
            found.append(
                f"suspension.{name}.damping_Ns_per_m = {c:g}: a damping ratio of {ratio:.2g} on its wheels' static "
                f"load ({load:.0f} N), next to none; did you type N s/mm? {c:g} N s/mm is {c * 1e3:g} N s/m "
                f"(ratio {ratio * 1e3:.2f})")
    return found


def implausible_values(params: VehicleParameters, tyres: dict | None = None) -> list[str]:
    """What in a parameter set looks like a slip (see the module docstring), one message per finding.

    Parameters
    ----------
    params : VehicleParameters
        The values, as validated by the schema.
    tyres : dict, optional
        ``tyre_file`` -> :class:`~trikedyn.tyre.tir.TyreProperties` of the wheels' ``.tir`` files as read;
        without it the tyre files are not looked at.

    Returns
    -------
    list of str
        ``'FIELD: what and why'`` for each finding; empty for a plausible set.
    """
    loads = _static_loads(params)
    return _angles(params) + _tyre_files(params, tyres or {}, loads) + _suspensions(params, loads)


def warn_implausible(params: VehicleParameters, origin: str, tyres: dict | None = None) -> None:
    """One :class:`~trikedyn.plausibility.PlausibilityWarning` ``'ORIGIN: FIELD: what and why'`` per finding
    of :func:`implausible_values`.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    origin : str
        Where the set came from (the warning's prefix).
    tyres : dict, optional
        Parsed tyre files by wheel.
    """
    for message in implausible_values(params, tyres):
        warnings.warn(f"{origin}: {message}", PlausibilityWarning, stacklevel=4)
