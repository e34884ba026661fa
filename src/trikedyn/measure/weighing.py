"""Wheel-weighing records (TOML) and their reduction to a centre of gravity.

A weighing file holds the contact points, one level weighing and, optionally, weighings with one axle
raised (the paper's Fig. 3)::

    reading_std_kg = 0.5          # standard uncertainty of one scale reading [kg]
    wheel_radius_m = 0.27         # loaded radius: axle height [m]

    [contacts]                    # wheel contact points (x ahead of the rear axle, y left) [m]
    front = [1.95, 0.0]
    rear_left = [0.0, 0.55]
    rear_right = [0.0, -0.55]

    [level]                       # scale readings, vehicle level [kg]
    front = 249.1
    rear_left = 175.6
    rear_right = 158.3

    [[tilted]]                    # one entry per raise height
    raised = "front"              # the axle lifted
    height_m = 0.20               # lift of its contact above the other axle's [m]
    raised_axle_kg = 236.4        # scale reading under the raised axle (sum of its wheels) [kg]
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..units import STANDARD_GRAVITY
from .cg import (
    LevelWeighingResult,
    TiltedWeighingResult,
    cg_from_level_weighing,
    cg_height_from_tilted_weighings,
)

__all__ = ["CgMeasurement", "load_weighing", "reduce_weighing"]


@dataclass(frozen=True)
class CgMeasurement:
    """Mass and CG from a weighing record, with standard uncertainties."""

    level: LevelWeighingResult
    height: TiltedWeighingResult | None

    def to_dict(self) -> dict:
        out = self.level.to_dict()
        if self.height is not None:
            out.update(self.height.to_dict())
        return out


def _number(value, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not np.isfinite(value):
        raise InputError(f"expected a number, got {value!r}", where=where)
    return float(value)


def load_weighing(path: str | Path) -> dict:
    """Read a weighing file (see the module docstring) into a plain dict, with clear errors."""
    path = Path(path)
    if not path.is_file():
        raise InputError("no such weighing file", where=str(path))
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"not a readable TOML file: {exc}", where=str(path)) from None


def reduce_weighing(record: dict, where: str = "weighing") -> CgMeasurement:
    """Reduce a weighing record to mass and CG (x, y from the level weighing; z from the tilted ones)."""
    g = STANDARD_GRAVITY
    known = {"reading_std_kg", "wheel_radius_m", "contacts", "level", "tilted", "description"}
    for key in record:
        if key not in known:
            from difflib import get_close_matches

            hint = get_close_matches(key, sorted(known), n=1)
            raise InputError(
                f"unknown key '{key}'" + (f"; did you mean '{hint[0]}'?" if hint else ""), where=where
            )
    contacts = record.get("contacts")
    level = record.get("level")
    if not isinstance(contacts, dict) or not isinstance(level, dict):
        raise InputError("needs a [contacts] table and a [level] table", where=where)
    if set(contacts) != set(level):
        raise InputError(
            f"[level] wheels {sorted(level)} differ from [contacts] wheels {sorted(contacts)}", where=where
        )
    names = list(contacts)
    pts = []
    for n in names:
        xy = contacts[n]
        if not isinstance(xy, list) or len(xy) != 2:
            raise InputError("expected [x, y] in m", where=f"{where}: contacts.{n}")
        pts.append([_number(v, f"{where}: contacts.{n}") for v in xy])
    readings = np.array([_number(level[n], f"{where}: level.{n}") for n in names])
    if np.any(readings < 0):
        bad = names[int(np.argmin(readings))]
        raise InputError("scale reading must be >= 0 kg", where=f"{where}: level.{bad}")
    std_kg = _number(record.get("reading_std_kg", 0.0), f"{where}: reading_std_kg")
    lvl = cg_from_level_weighing(readings * g, pts, load_std_N=std_kg * g)
    tilted = record.get("tilted", [])
    if not tilted:
        return CgMeasurement(lvl, None)
    if "wheel_radius_m" not in record:
        raise InputError("missing: [[tilted]] weighings need the axle height", where=f"{where}: wheel_radius_m")
    radius = _number(record["wheel_radius_m"], f"{where}: wheel_radius_m")
    pts = np.array(pts)
    front_x = pts[:, 0].max()
    wheelbase = front_x - pts[:, 0].min()
    raised = {t.get("raised") for t in tilted}
    if len(raised) != 1 or not raised <= {"front", "rear"}:
        raise InputError("every [[tilted]] entry needs the same raised = 'front' or 'rear'", where=where)
    heights = [_number(t.get("height_m"), f"{where}: tilted[{i}].height_m") for i, t in enumerate(tilted)]
    loads = [_number(t.get("raised_axle_kg"), f"{where}: tilted[{i}].raised_axle_kg") * g for i, t in enumerate(tilted)]
    height = cg_height_from_tilted_weighings(
        loads,
        heights,
        mass_kg=lvl.mass_kg,
        cg_x_m=lvl.cg_x_m - pts[:, 0].min(),
        wheelbase_m=wheelbase,
        wheel_radius_m=radius,
        raised=raised.pop(),
        load_std_N=std_kg * g,
    )
    return CgMeasurement(lvl, height)
