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
tilted weighings. Unknown keys are errors with a close-match hint (:class:`WeighingRecord`); a value refused
that would be accepted in another unit says so (``contacts.front[0]: ... (got 1950); did you type
millimetres or centimetres? 1950 mm is 1.95 m, 1950 cm is 19.5 m``).

What no vehicle gives is refused too (:func:`reduce_weighing`), each in one line naming the table or entry:

- contact points that lie within :data:`MIN_SUPPORT_WIDTH_M` of one line (the vehicle could not stand);
- a mass outside :data:`MIN_MASS_KG` .. :data:`MAX_MASS_KG` (with a hint when the readings look typed in
  newtons or tonnes);
- of three wheels, one that reads 0 kg (the CG on the line through the other two: tipping over);
- a raised-axle reading above the whole vehicle's mass;
- raised-axle readings that rise as the axle is raised (beyond twice the result's standard deviation): they
  put the CG below the wheel centres, or below the ground; for a CG above the wheel centres, as on every
  trike, the raised axle's reading falls;
- a CG above :data:`MAX_CG_HEIGHT_M`, or so high that the vehicle would have tipped onto its lower axle at
  the largest raise.

A raised-axle reading further than :data:`OUTLIER_SIGMAS` ``reading_std_kg`` from the fit through all
heights is warned about (:class:`~trikedyn.plausibility.PlausibilityWarning`); the result stands.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import AfterValidator, AllowInfNan, BaseModel, BeforeValidator, ConfigDict, Field, Strict, ValidationError

from .._validation import describe_validation_error
from ..errors import InputError
from ..plausibility import PlausibilityWarning, unit_of, unit_slip_hint
from ..units import STANDARD_GRAVITY
from .cg import (
    LevelWeighingResult,
    TiltedWeighingResult,
    cg_from_level_weighing,
    cg_height_from_tilted_weighings,
)

__all__ = ["MAX_CG_HEIGHT_M", "MAX_MASS_KG", "MIN_MASS_KG", "MIN_SUPPORT_WIDTH_M", "OUTLIER_SIGMAS", "CgMeasurement",
           "WeighingRecord", "load_weighing", "reduce_weighing"]

MIN_MASS_KG = 10.0
"""Least mass a weighing may give [kg]: the vehicle schema's least mass; a trike with its rider weighs more."""

MAX_MASS_KG = 2500.0
"""Most mass a weighing may give [kg]. The heaviest three-wheelers, three-wheeled trucks, are built up to about
2 t laden; readings typed in newtons give 9.81 times the mass (a 375 kg trike: 3679 kg)."""

MAX_CG_HEIGHT_M = 2.0
"""Highest CG a tilted weighing may give [m]: three-wheelers are at most about 2 m high overall, and their CG
well below that."""

MIN_SUPPORT_WIDTH_M = 0.1
"""Least distance of the contact points from a line through them [m] (the vehicle schema's least support
height): below it the vehicle could not stand."""

OUTLIER_SIGMAS = 4.0
"""A raised-axle reading further than this many ``reading_std_kg`` from the fit through all heights is warned
about."""

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
        """The measurement as one flat JSON-ready dict: the level weighing's fields, and the height's when measured.

        Returns
        -------
        dict
            Masses [kg], CG coordinates and uncertainties [m].
        """
        out = self.level.to_dict()
        if self.height is not None:
            out.update(self.height.to_dict())
        return out


def _unit(loc: tuple) -> str | None:
    """The unit suffix of a weighing field (contact coordinates in m, scale readings in kg)."""
    if loc[0] == "contacts":
        return "_m"
    if loc[0] == "level":
        return "_kg"
    return unit_of(next((p for p in reversed(loc) if isinstance(p, str)), None))


def _validated(record, where: str) -> WeighingRecord:
    if not isinstance(record, dict):
        raise InputError(f"expected a table of keys, got {type(record).__name__}", where=where)
    try:
        return WeighingRecord.model_validate(record)
    except ValidationError as exc:
        hint = unit_slip_hint(exc, record, WeighingRecord, _unit)
        raise InputError(describe_validation_error(exc, record, WeighingRecord) + hint, where=where) from None


def load_weighing(path: str | Path) -> dict:
    """Read a weighing file (see the module docstring) into a plain dict, with clear errors.

    The file must be UTF-8 TOML of at most 1 MiB (:mod:`trikedyn.params.tomlfile`) and follow
    :class:`WeighingRecord`; the dict returned is the file's content as read.

    Parameters
    ----------
    path : str or Path
        The weighing file.

    Returns
    -------
    dict
        Its content.

    Raises
    ------
    InputError
        Missing, too large, not TOML or not a weighing record.
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
    """Reduce a weighing record to mass and CG (x, y from the level weighing; z from the tilted ones).

    Besides the record's types and ranges (:class:`WeighingRecord`), what no vehicle can give is refused with
    an :class:`~trikedyn.errors.InputError` naming the file and the table or entry (see the module
    docstring), and a raised-axle reading far off the others is warned about
    (:class:`~trikedyn.plausibility.PlausibilityWarning`).

    Parameters
    ----------
    record : dict
        The weighing record (:func:`load_weighing`).
    where : str
        Its name, for errors.

    Returns
    -------
    CgMeasurement
        Mass [kg], CG (x, y, z) [m] with uncertainties.
    """
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
    _check_level(names, pts, readings, where)
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
        if t.raised_axle_kg > lvl.mass_kg:
            raise InputError(f"{t.raised_axle_kg:g} kg is more than the whole vehicle weighs ({lvl.mass_kg:.1f} kg "
                             "in [level]); one axle cannot carry more", where=f"{where}: tilted[{i}].raised_axle_kg")
    side = raised.pop()
    cg_x = lvl.cg_x_m - pts[:, 0].min()
    height = cg_height_from_tilted_weighings(
        [t.raised_axle_kg * g for t in rec.tilted],
        [t.height_m for t in rec.tilted],
        mass_kg=lvl.mass_kg,
        cg_x_m=cg_x,
        wheelbase_m=wheelbase,
        wheel_radius_m=rec.wheel_radius_m,
        raised=side,
        load_std_N=std_kg * g,
    )
    lever = cg_x if side == "front" else wheelbase - cg_x
    _check_height(rec, height, lvl.mass_kg, lever, wheelbase, where)
    return CgMeasurement(lvl, height)


# ------------------------------------------------------------------------------------------------------------
# what no vehicle gives
# ------------------------------------------------------------------------------------------------------------
def _footprint_width(pts: np.ndarray) -> float:
    """Least width of the contact points [m]: the smallest extent across the line through any two of them
    (0 when they all lie on one line)."""
    width = 0.0 if len(pts) < 3 else math.inf
    for i in range(len(pts)):
        for j in range(i + 1, len(pts)):
            d = pts[j] - pts[i]
            length = math.hypot(*d)
            if length < 1e-9:
                continue
            across = (pts - pts[i]) @ np.array([-d[1], d[0]]) / length
            width = min(width, float(across.max() - across.min()))
    return 0.0 if math.isinf(width) else width


def _check_level(names: list[str], pts: np.ndarray, readings: np.ndarray, where: str) -> None:
    """The contacts span an area; the mass is a vehicle's (a hint for newtons or tonnes); no wheel of three
    reads 0."""
    width = _footprint_width(pts)
    if width < MIN_SUPPORT_WIDTH_M:
        raise InputError(f"the contact points lie within {width * 1000:.0f} mm of one line; a vehicle stands on "
                         f"wheels at least {MIN_SUPPORT_WIDTH_M:g} m off the line through the others",
                         where=f"{where}: contacts")
    mass, g = float(readings.sum()), STANDARD_GRAVITY
    if not MIN_MASS_KG <= mass <= MAX_MASS_KG:
        heavy = mass > MAX_MASS_KG
        converted = mass / g if heavy else mass * 1000.0
        hint = ((f"; did you type newtons? divide by {g:.2f} ({converted:.1f} kg)" if heavy else
                 f"; did you type tonnes? multiply by 1000 ({converted:.1f} kg)")
                if MIN_MASS_KG <= converted <= MAX_MASS_KG else "")
        raise InputError(f"the readings sum to {mass:.1f} kg: {'heavier' if heavy else 'lighter'} than any "
                         f"three-wheeler ({MIN_MASS_KG:g} to {MAX_MASS_KG:g} kg){hint}", where=f"{where}: level")
    if len(names) == 3:
        for name, reading in zip(names, readings, strict=True):
            if reading == 0.0:
                raise InputError("reads 0 kg: the vehicle would stand on its other two wheels alone, its CG on "
                                 "the line through them (tipping over); was the wheel on the scale?",
                                 where=f"{where}: level.{name}")


def _check_height(rec: WeighingRecord, height: TiltedWeighingResult, mass_kg: float, lever_m: float,
                  wheelbase_m: float, where: str) -> None:
    """The CG height is above the wheel centres (the raised axle's reading falls), below any trike's highest,
    and keeps the vehicle on its raised axle at every height; each reading fits the others."""
    z, sigma, r = height.cg_z_m, height.cg_z_std_m, rec.wheel_radius_m
    level_kg = mass_kg * lever_m / wheelbase_m
    shown = ", ".join(f"{t.raised_axle_kg:g} kg at {t.height_m:g} m" for t in rec.tilted[:3])
    shown += ", ..." if len(rec.tilted) > 3 else ""
    if z <= 0.0 or z < r - 2.0 * sigma:
        place = "below the ground" if z <= 0.0 else f"below the wheel centres (wheel_radius_m {r:g} m)"
        raise InputError(
            f"the raised axle's reading rises as it is raised ({level_kg:.1f} kg level; {shown}) instead of "
            f"falling: that puts the CG {z * 1000:.1f} mm high, {place}; it falls for any CG above the wheel "
            "centres, as every trike's is. Is raised_axle_kg read under the raised axle, and raised the axle "
            "lifted?", where=f"{where}: tilted")
    if z > MAX_CG_HEIGHT_M:
        raise InputError(
            f"the readings ({level_kg:.1f} kg level; {shown}) put the CG {z * 1000:.0f} mm high, above any "
            f"three-wheeler's (at most {MAX_CG_HEIGHT_M:g} m); check height_m (in m) and raised_axle_kg",
            where=f"{where}: tilted")
    tan = np.tan(np.arcsin(height.heights_m / wheelbase_m))
    left = lever_m - (z - r) * tan  # the raised axle's load at the fitted CG, times L / W [m]
    if left.min() <= 1e-9 * wheelbase_m:
        k = int(np.argmin(left))
        raise InputError(
            f"a CG {z * 1000:.0f} mm high would have tipped the vehicle onto its lower axle at the raise of "
            f"{height.heights_m[k]:g} m (its weight passes beyond the lower contacts once tan(theta) > {lever_m:.3f} "
            f"m / {z - r:.3f} m, the CG's distances from the lower axle along and above the vehicle); the "
            "readings do not fit the geometry", where=f"{where}: tilted")
    std_kg = rec.reading_std_kg
    if std_kg > 0.0 and len(rec.tilted) > 1:
        off_kg = height.residuals_N / wheelbase_m / STANDARD_GRAVITY  # fitted less measured reading [kg]
        k = int(np.argmax(np.abs(off_kg)))
        if abs(off_kg[k]) > OUTLIER_SIGMAS * std_kg:
            t = rec.tilted[k]
            warnings.warn(
                f"{where}: tilted[{k}].raised_axle_kg: {t.raised_axle_kg:g} kg at {t.height_m:g} m is "
                f"{-off_kg[k]:+.1f} kg off the fit through all {len(rec.tilted)} heights, "
                f"{abs(off_kg[k]) / std_kg:.0f} x reading_std_kg; the heights give CG heights from "
                f"{height.per_height_z_m.min() * 1000:.0f} to {height.per_height_z_m.max() * 1000:.0f} mm: a "
                "misread scale or a wheel moved on it?", PlausibilityWarning, stacklevel=3)
