"""Plausibility of inputs, shared by every reader: the warning for a value that is allowed but looks wrong,
and the hint for a value refused because it was typed in another unit.

A reader refuses what is impossible with an :class:`~trikedyn.errors.InputError` (one line, ``WHERE: WHAT``)
and warns with :class:`PlausibilityWarning` about what is possible but looks like a slip (an angle in a
degree field small enough to be radians, a tyre file of another wheel size). :func:`unit_slip_hint` adds to
a refusal of the schema the unit the value was probably typed in, when the value converted from that unit
is accepted: ``steering.max_angle_deg: input should be at least 5 deg (got 0.7); did you type radians?
0.7 rad is 40.1 deg``.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable

from pydantic import BaseModel, ValidationError

from .units import STANDARD_GRAVITY

__all__ = ["PlausibilityWarning", "UNIT_SLIPS", "unit_of", "unit_slip_hint"]


class PlausibilityWarning(UserWarning):
    """A value that a reader accepts but that looks wrong: another unit, another wheel's tyre, a reading off
    the others. The message names the file and the field, the value, and why it looks wrong."""


UNIT_SLIPS: dict[str, tuple[tuple[str, str, float, str], ...]] = {
    "_deg": (("radians", "rad", math.degrees(1.0), "deg"),),
    "_deg_per_s": (("rad/s", "rad/s", math.degrees(1.0), "deg/s"),),
    "_m": (("millimetres", "mm", 1e-3, "m"), ("centimetres", "cm", 1e-2, "m")),
    "_N_per_m": (("N/mm", "N/mm", 1e3, "N/m"),),
    "_Ns_per_m": (("N s/mm", "N s/mm", 1e3, "N s/m"),),
    "_N": (("kilonewtons", "kN", 1e3, "N"),),
    "_kg": (("grams", "g", 1e-3, "kg"), ("newtons", "N", 1.0 / STANDARD_GRAVITY, "kg")),
}
"""Unit suffix of a field -> the units a value of it is often typed in by mistake: (the unit's name, its
symbol, factor to the field's unit, the field's unit)."""


def unit_of(key) -> str | None:
    """The unit suffix of a field name (``'axis_angle_deg'`` -> ``'_deg'``), one of :data:`UNIT_SLIPS`, or
    None.

    Parameters
    ----------
    key : str or object
        A field name; anything but a string has no unit.

    Returns
    -------
    str or None
        The longest matching suffix, or None.
    """
    if not isinstance(key, str):
        return None
    found = [suffix for suffix in UNIT_SLIPS if key.endswith(suffix)]
    return max(found, key=len) if found else None


def _replaced(data, loc: tuple, value):
    """A deep copy of ``data`` with the item at ``loc`` replaced by ``value``, or None if ``loc`` is not in it."""
    trial = copy.deepcopy(data)
    node = trial
    for part in loc[:-1]:
        try:
            node = node[part]
        except (KeyError, IndexError, TypeError):
            return None
    try:
        node[loc[-1]]
        node[loc[-1]] = value
    except (KeyError, IndexError, TypeError):
        return None
    return trial


def _plain(value: float) -> str:
    """``value`` to 4 significant digits, without an exponent (``45800``, ``0.0204``)."""
    text = f"{float(f'{value:.4g}'):f}"
    return text.rstrip("0").rstrip(".") if "." in text else text


def unit_slip_hint(exc: ValidationError, data, model: type[BaseModel],
                   unit: Callable[[tuple], str | None] | None = None) -> str:
    """``'; did you type radians? 0.7 rad is 40.1 deg'`` when the value refused by ``exc`` is accepted once
    converted from a unit often typed by mistake (:data:`UNIT_SLIPS`), else ``''``.

    Parameters
    ----------
    exc : pydantic.ValidationError
        The refusal of ``data`` by ``model``; its first error (an unknown key first, as
        :func:`trikedyn._validation.describe_validation_error` says) is the one looked at.
    data : dict
        What was validated, as read.
    model : type of pydantic.BaseModel
        The model that refused it; the converted value is validated by it again, in place.
    unit : callable, optional
        ``loc -> unit suffix`` for fields whose name carries no unit (a scale reading under ``[level]``); by
        default the suffix of the last named part of the location (:func:`unit_of`).

    Returns
    -------
    str
        The hint for the end of an error message, or an empty string.
    """
    errors = exc.errors()
    if any(e["type"] == "extra_forbidden" for e in errors):
        return ""
    loc = tuple(p for p in errors[0]["loc"] if p not in ("function-after", "function-before"))
    value = errors[0].get("input")
    if not loc or isinstance(value, bool) or not isinstance(value, int | float):
        return ""
    if not math.isfinite(value) or value == 0 or abs(value) > 1e12:
        return ""
    suffix = unit(loc) if unit is not None else unit_of(next((p for p in reversed(loc) if isinstance(p, str)), None))
    fits = []
    for typed, symbol, factor, si in UNIT_SLIPS.get(suffix, ()):
        converted = value * factor
        trial = _replaced(data, loc, converted)
        if trial is None:
            continue
        try:
            model.model_validate(trial)
        except ValidationError as again:
            if any(tuple(p for p in e["loc"] if p not in ("function-after", "function-before")) == loc
                   for e in again.errors()):
                continue
        fits.append((typed, f"{value:g} {symbol} is {_plain(converted)} {si}"))
    if not fits:
        return ""
    return f"; did you type {' or '.join(t for t, _ in fits)}? {', '.join(c for _, c in fits)}"
