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

Every value is a number (an integer or a float; not a text or true/false), finite and in a physical range:
readings 0 .. 10 000 kg, ``reading_std_kg`` 0 .. 100 kg, ``wheel_radius_m`` up to 2 m, contact coordinates
within 20 m of the origin, raise heights up to 5 m and below the wheelbase; 3 to 16 wheels, at most 100
tilted weighings. Unknown keys are errors with a close-match hint (:class:`WeighingRecord`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import AfterValidator, AllowInfNan, BaseModel, BeforeValidator, ConfigDict, Field, Strict, ValidationError

from .._validation import describe_validation_error
from ..errors import InputError
from ..units import STANDARD_GRAVITY
from .cg import (
    LevelWeighingResult,
    TiltedWeighingResult,
    cg_from_level_weighing,
    cg_height_from_tilted_weighings,
)

__all__ = ["CgMeasurement", "WeighingRecord", "load_weighing", "reduce_weighing"]

_Number = Annotated[float, Strict(), AllowInfNan(False)]
"""A finite number written as one (an integer or a float; not a text, not true/false)."""


def _pair(value):
    if not isinstance(value, list | tuple) or len(value) != 2:
        raise ValueError("expected [x, y] in m")
    return value


def _reading(value: float) -> float:
    if value < 0:
        raise ValueError(f"scale reading must be >= 0 kg (got {value:g})")
    return value


_Reading = Annotated[_Number, AfterValidator(_reading), Field(le=10_000.0)]
"""A scale reading [kg]: 0 .. 10 t."""

_Coordinate = Annotated[_Number, Field(ge=-20.0, le=20.0)]
"""A contact coordinate [m], within 20 m of the origin."""


class _Record(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class TiltedWeighing(_Record):
    """One weighing with an axle raised."""

    raised: Literal["front", "rear"]
    height_m: _Number = Field(gt=0.0, le=5.0, description="lift of the raised axle's contact [m]")
    raised_axle_kg: _Reading


class WeighingRecord(_Record):
    """A weighing file (see the module docstring): types and ranges checked, unknown keys refused."""

    description: str | None = Field(default=None, max_length=2000)
    reading_std_kg: _Number = Field(default=0.0, ge=0.0, le=100.0)
    wheel_radius_m: _Number | None = Field(default=None, gt=0.0, le=2.0)
    contacts: dict[str, Annotated[tuple[_Coordinate, _Coordinate], BeforeValidator(_pair)]] = Field(
        min_length=3, max_length=16
    )
    level: dict[str, _Reading] = Field(min_length=3, max_length=16)
    tilted: list[TiltedWeighing] = Field(default_factory=list, max_length=100)


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


def _validated(record, where: str) -> WeighingRecord:
    if not isinstance(record, dict):
        raise InputError(f"expected a table of keys, got {type(record).__name__}", where=where)
    try:
        return WeighingRecord.model_validate(record)
    except ValidationError as exc:
        raise InputError(describe_validation_error(exc, record, WeighingRecord), where=where) from None


def load_weighing(path: str | Path) -> dict:
    """Read a weighing file (see the module docstring) into a plain dict, with clear errors.

    The file must be UTF-8 TOML of at most 1 MiB (:mod:`trikedyn.params.tomlfile`) and follow
    :class:`WeighingRecord`; the dict returned is the file's content as read.
    """
    from ..params.tomlfile import is_file, parse_toml, read_text

    path = Path(path)
    where = str(path)
    if not is_file(path):
        raise InputError("no such weighing file", where=where)
    record = parse_toml(read_text(path, where), where)
    _validated(record, where)
    return record


def reduce_weighing(record: dict, where: str = "weighing") -> CgMeasurement:
    """Reduce a weighing record to mass and CG (x, y from the level weighing; z from the tilted ones)."""
    g = STANDARD_GRAVITY
    rec = _validated(record, where)
    if set(rec.contacts) != set(rec.level):
        raise InputError(
            f"[level] wheels {sorted(rec.level)} differ from [contacts] wheels {sorted(rec.contacts)}", where=where
        )
    names = list(rec.contacts)
    pts = np.array([rec.contacts[n] for n in names], dtype=float)
    readings = np.array([rec.level[n] for n in names])
    if readings.sum() <= 0.0:
        raise InputError("the scale readings sum to 0 kg", where=f"{where}: level")
    std_kg = rec.reading_std_kg
    lvl = cg_from_level_weighing(readings * g, pts, load_std_N=std_kg * g)
    if not rec.tilted:
        return CgMeasurement(lvl, None)
    if rec.wheel_radius_m is None:
        raise InputError("missing: [[tilted]] weighings need the axle height", where=f"{where}: wheel_radius_m")
    wheelbase = float(pts[:, 0].max() - pts[:, 0].min())
    raised = {t.raised for t in rec.tilted}
    if len(raised) != 1:
        raise InputError("every [[tilted]] entry needs the same raised = 'front' or 'rear'", where=where)
    for i, t in enumerate(rec.tilted):
        if t.height_m >= wheelbase:
            raise InputError(f"must be below the wheelbase of the contacts ({wheelbase:g} m), got {t.height_m:g}",
                             where=f"{where}: tilted[{i}].height_m")
    height = cg_height_from_tilted_weighings(
        [t.raised_axle_kg * g for t in rec.tilted],
        [t.height_m for t in rec.tilted],
        mass_kg=lvl.mass_kg,
        cg_x_m=lvl.cg_x_m - pts[:, 0].min(),
        wheelbase_m=wheelbase,
        wheel_radius_m=rec.wheel_radius_m,
        raised=raised.pop(),
        load_std_N=std_kg * g,
    )
    return CgMeasurement(lvl, height)
