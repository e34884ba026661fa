"""A vehicle's numeric values by dotted path (:func:`numeric_parameters`), its design knobs' values, and the
ranges its file declares next to them (:func:`declared_ranges`: ``[ranges.mass] cg_x_m = [0.70, 0.95]`` or
``{ rel = 0.1 }``; see :mod:`trikedyn.params.schema`): what the factors of a sampled design
(:mod:`trikedyn.study.designs.factors`) are made of.
"""

from __future__ import annotations

from collections.abc import Iterable

from ...errors import ParameterError, did_you_mean
from ...params.io import ParameterSet

__all__ = ["PAIR_SEPARATOR", "declared_ranges", "numeric_parameters"]

PAIR_SEPARATOR = "+"
"""Joins the two wheels of a mirrored pair in a range key: ``wheels.LEFT+RIGHT.ATTR``."""


def _is_number(value) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _leaves(node, prefix: str = ""):
    """``(dotted path, value)`` of every leaf, list items keyed by their ``name`` (as :func:`override` reads)."""
    if isinstance(node, dict):
        for key, value in node.items():
            if key == "name" and prefix:
                continue
            yield from _leaves(value, f"{prefix}.{key}" if prefix else key)
    elif isinstance(node, list | tuple) and node and all(isinstance(i, dict) for i in node):
        for i, item in enumerate(node):
            yield from _leaves(item, f"{prefix}.{item.get('name', str(i))}")
    else:
        yield prefix, node


def numeric_parameters(pset: ParameterSet) -> dict[str, float]:
    """Every numeric parameter of the vehicle by dotted path (booleans, names and the payload left out).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.

    Returns
    -------
    dict of str to float
        Dotted path -> value [its unit].
    """
    return {path: float(value) for path, value in _leaves(pset.params.model_dump(exclude={"ranges"}))
            if _is_number(value) and not path.startswith("payload.")}


def _pairs(pset: ParameterSet) -> list[tuple[str, str]]:
    """Mirrored pairs of wheels ``(left, right)``: same axle position and suspension, one each side."""
    wheels = list(pset.params.wheels)
    pairs = []
    for i, a in enumerate(wheels):
        for b in wheels[i + 1:]:
            if abs(a.x_m - b.x_m) < 1e-9 and a.y_m * b.y_m < 0 and a.suspension == b.suspension:
                pairs.append((a.name, b.name) if a.y_m > b.y_m else (b.name, a.name))
    return pairs


def _note(pset: ParameterSet, path: str) -> str:
    note = pset.notes.get(path, {})
    for key in ("assumed", "source", "note"):
        if key in note:
            return f"{key}: {note[key]}"
    return ""


def _range_key_value(pset: ParameterSet, key: str, values: dict[str, float]) -> float | None:
    """The vehicle's value that a ``[ranges]`` key names: a numeric parameter, a design knob, or a value a
    mirrored pair of wheels shares (``wheels.LEFT+RIGHT.ATTR``); None if it names none."""
    if key in values:
        return values[key]
    if _knobs() is not None and key in _knobs().knob_names(pset):
        known = _knob_value(pset, key)
        if known is not None:
            return known[0]
    parts = key.split(".")
    if len(parts) == 3 and parts[0] == "wheels" and PAIR_SEPARATOR in parts[1]:
        left, right = parts[1].split(PAIR_SEPARATOR, 1)
        a, b = values.get(f"wheels.{left}.{parts[2]}"), values.get(f"wheels.{right}.{parts[2]}")
        if a is not None and a == b:
            return a
    return None


def declared_ranges(pset: ParameterSet) -> dict[str, tuple[float, float]]:
    """The ranges the vehicle file declares (its ``[ranges]`` tables, :class:`~trikedyn.params.schema.VehicleParameters`),
    by key, as ``(low, high)`` in the value's unit (a ``{ rel = f }`` resolved against the value).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.

    Returns
    -------
    dict of str to tuple of float
        Key -> (low, high).

    Raises
    ------
    ParameterError
        ``where="FILE: ranges.KEY"``: the key names no number of the vehicle (with the closest one), or the range
        does not hold the value strictly inside (``low < value < high``; a relative range of a zero value).
    """
    declared = getattr(pset.params, "ranges", None) or {}
    if not declared:
        return {}
    values = numeric_parameters(pset)
    out: dict[str, tuple[float, float]] = {}
    origin = pset.origin or pset.name
    for key, spec in declared.items():
        where = f"{origin}: ranges.{key}"
        value = _range_key_value(pset, key, values)
        if value is None:
            known = [*values, *(_knobs().knob_names(pset) if _knobs() is not None else ())]
            tip = did_you_mean(key, known) or " (a dotted path of a number, or a design knob)"
            raise ParameterError(f"no number of the vehicle is called '{key}'{tip}", where=where)
        rel = getattr(spec, "rel", None)
        if rel is not None:
            if value == 0.0:
                raise ParameterError(f"{{ rel = {rel:g} }} of a value of 0 is empty; give [low, high]", where=where)
            low, high = sorted((value * (1.0 - rel), value * (1.0 + rel)))
        else:
            low, high = (float(b) for b in spec)
            if not low < value < high:
                raise ParameterError(f"[{low:g}, {high:g}] does not hold the value {value:g} "
                                     "(expected low < value < high)", where=where)
        out[key] = (low, high)
    return out


def _declared_range(pset: ParameterSet, name: str, value: float, keys: Iterable[str],
                    declared: dict[str, tuple[float, float]] | None = None) -> tuple[float, float] | None:
    """The range declared for a factor: under its own name, else under one of the parameters it sets or
    explains whose value is the factor's (a knob's range is never taken from a wheel's ``y_m``)."""
    declared = declared_ranges(pset) if declared is None else declared
    if not declared:
        return None
    if name in declared:
        return declared[name]
    values = numeric_parameters(pset)
    for key in keys:
        if key in declared and key in values and values[key] == value:
            return declared[key]
    return None


def _knobs():
    """:mod:`trikedyn.params.knobs` (design knobs that keep a vehicle consistent), if this trikedyn has it."""
    try:
        from ...params import knobs
    except ImportError:  # pragma: no cover - an older trikedyn: the pair's track is moved here
        return None
    return knobs if hasattr(knobs, "apply_knobs") else None


def _knob_value(pset: ParameterSet, name: str) -> tuple[float, str] | None:
    """A design knob's value on this vehicle and the parameter path whose note explains it (None: unknown)."""
    p = pset.params
    steered = [w for w in p.wheels if w.steered]
    fixed = [w for w in p.wheels if not w.steered]
    front = sum(w.x_m for w in steered) / len(steered)
    rear = sum(w.x_m for w in fixed) / len(fixed)
    if name == "wheelbase_m":
        return front - rear, f"wheels.{steered[0].name}.x_m"
    if name == "track_m":
        pair = [w for w in p.wheels if w.steered == (p.layout == "tadpole")]
        return abs(pair[0].y_m - pair[1].y_m), f"wheels.{pair[0].name}.y_m"
    if name == "cg_height_m":
        return p.mass.cg_z_m, "mass.cg_z_m"
    if name == "cg_x_fraction":
        return (p.mass.cg_x_m - rear) / (front - rear), "mass.cg_x_m"
    keys = name.split(".")
    if keys[0] == "component" and len(keys) == 3:
        component = next((c for c in p.components if c.name == keys[1]), None)
        return None if component is None else (float(getattr(component, keys[2])), f"components.{keys[1]}.{keys[2]}")
    if keys[0] == "freight" and len(keys) == 2:
        return float(getattr(p.freight, keys[1])), name
    return None
