"""A run file's metadata read back and checked: the table's own (Parquet) metadata over the ``.json`` sidecar
beside it (:func:`run_meta`), each field trikedyn reads with its type and range (:func:`check_meta`); fields it
does not read are left alone. A sidecar that is there but cannot be read (not a regular file, over
:data:`MAX_SIDECAR_BYTES`, not UTF-8 JSON, not an object) is refused: move it away to read the table alone.

The table itself: :mod:`trikedyn.simulate.runcheck`.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path

from ..errors import InputError

__all__ = ["MAX_SIDECAR_BYTES", "MAX_TEXT_CHARS", "MAX_WHEELS", "READ_FROM", "check_meta", "run_meta"]


MAX_SIDECAR_BYTES = 16 * 2**20
"""Largest ``.json`` sidecar read [bytes]: a run's is a few kB; a bigger one is refused unread."""
MAX_WHEELS = 8
"""Most wheel loads (``<wheel>_fz_N`` columns) of a run."""
MAX_TEXT_CHARS = 200
"""Longest text field of the metadata (a vehicle's or manoeuvre's name) [characters]."""
READ_FROM = "read_from"
"""The key :func:`run_meta` sets to the run file it read (the folder a path CSV of the record is in)."""

_TEXTS = ("vehicle", "manoeuvre", "manoeuvre_name", "speed_control", "status", "left", "right")
_NUMBERS = {"dt_s": (0.0, 60.0, "s"), "target_speed_kmh": (0.0, 400.0, "km/h")}
_TABLES = ("window", "summary", "manoeuvre_spec", "vehicle_params", "driver")
_SUMMARY_TEXTS = ("vehicle", "manoeuvre", "verdict")
_SUMMARY_NUMBERS = {"speed_kmh": (0.0, 400.0, "km/h"), "payload_kg": (0.0, 1e5, "kg")}


def run_meta(run, attrs: Mapping) -> dict:
    """A run's metadata, checked: the table's own (Parquet) metadata ``attrs`` over the ``.json`` sidecar beside
    ``run`` (when there is one), each checked by :func:`check_meta`; ``read_from`` (:data:`READ_FROM`) names
    ``run``.

    Parameters
    ----------
    run : str or Path
        The run file.
    attrs : Mapping
        The table's own metadata.

    Returns
    -------
    dict
        The checked metadata.

    Raises
    ------
    InputError
        The sidecar is there but is not a regular file, is over :data:`MAX_SIDECAR_BYTES`, is not UTF-8 JSON
        or not an object; a field of either fails its check.
    """
    from .._reading import file_problem, read_bytes

    side = Path(run).with_suffix(".json")
    own = check_meta(attrs, f"{run} (its own metadata)") | {READ_FROM: str(run)}
    if file_problem(side) == "no such file":
        return own
    where = str(side)
    hint = "; move it away to read the run without it"
    raw = read_bytes(side, where, max_bytes=MAX_SIDECAR_BYTES, expected=f"the run's JSON sidecar{hint}",
                     too_large=lambda _: f"larger than {MAX_SIDECAR_BYTES // 2**20} MiB; expected the run's "
                                         f"JSON sidecar (a few kB){hint}")
    try:
        found = json.loads(raw.decode("utf-8").removeprefix("\ufeff"), parse_constant=_no_constant)
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text ({exc.reason} at byte {exc.start}){hint}", where=where) from None
    except json.JSONDecodeError as exc:
        raise InputError(f"not JSON ({exc.msg} at line {exc.lineno} column {exc.colno}){hint}",
                         where=where) from None
    except (ValueError, RecursionError) as exc:  # NaN, Infinity; nesting beyond the parser; a huge integer
        why = "nested too deep" if isinstance(exc, RecursionError) else " ".join(str(exc).split())[:120]
        raise InputError(f"not the run's JSON ({why}){hint}", where=where) from None
    if not isinstance(found, dict):
        raise InputError(f"holds a JSON {type(found).__name__}; expected the run's metadata (an object){hint}",
                         where=where)
    return {**check_meta(found, where), **own}


def _no_constant(name: str):
    raise ValueError(f"{name} is not a JSON number")


def check_meta(meta, where: str = "run metadata") -> dict:
    """A run's metadata with each field trikedyn reads checked; other fields are kept as they are.

    Parameters
    ----------
    meta : mapping
        The metadata (a sidecar's JSON object, a Parquet file's own, a :class:`Result`'s ``meta``).
    where : str
        Names its source in errors.

    Returns
    -------
    dict

    Raises
    ------
    InputError
        Not a mapping; ``wheels`` not a list of 1 to :data:`MAX_WHEELS` distinct names; a text field not a
        text of at most :data:`MAX_TEXT_CHARS` characters; a number not a finite number in its range (``dt_s``
        0-60 s, ``target_speed_kmh`` 0-400 km/h, ``summary.speed_kmh``, ``summary.payload_kg`` 0-1e5 kg);
        ``footprint_m`` not ``[x_rear, x_front, half_width]`` [m] with ``x_rear < x_front``, ``half_width > 0``;
        a table field (``window``, ``summary``, ``manoeuvre_spec`` and its ``parameters``, ``vehicle_params``,
        ``driver``) not an object. Null is allowed for every field.
    """
    if meta is None:
        return {}
    if not isinstance(meta, Mapping):
        raise InputError(f"is a {type(meta).__name__}; expected the run's metadata (an object)", where=where)
    meta = {str(k): v for k, v in meta.items()}
    for key in _TEXTS:
        _text(meta.get(key), f"{where}: {key}")
    for key, bounds in _NUMBERS.items():
        _number(meta.get(key), f"{where}: {key}", *bounds)
    for key in _TABLES:
        if meta.get(key) is not None and not isinstance(meta[key], Mapping):
            raise InputError(f"expected an object or null, got {_kind_of(meta[key])}", where=f"{where}: {key}")
    _wheel_names(meta.get("wheels"), f"{where}: wheels")
    _footprint(meta.get("footprint_m"), f"{where}: footprint_m")
    summary = meta.get("summary") or {}
    for key in _SUMMARY_TEXTS:
        _text(summary.get(key), f"{where}: summary.{key}")
    for key, bounds in _SUMMARY_NUMBERS.items():
        _number(summary.get(key), f"{where}: summary.{key}", *bounds)
    spec = meta.get("manoeuvre_spec") or {}
    _text(spec.get("name"), f"{where}: manoeuvre_spec.name")
    if spec.get("parameters") is not None and not isinstance(spec["parameters"], Mapping):
        raise InputError(f"expected an object or null, got {_kind_of(spec['parameters'])}",
                         where=f"{where}: manoeuvre_spec.parameters")
    return meta


def _kind_of(value) -> str:
    """A JSON value's kind in words (``a list``, ``a text``, ``true``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    kinds = {dict: "an object", list: "a list", tuple: "a list", str: "a text", int: "a number", float: "a number"}
    return next((v for k, v in kinds.items() if isinstance(value, k)), f"a {type(value).__name__}")


def _text(value, where: str) -> None:
    if value is None:
        return
    if not isinstance(value, str):
        raise InputError(f"expected a text or null, got {_kind_of(value)}", where=where)
    if len(value) > MAX_TEXT_CHARS:
        raise InputError(f"a text of {len(value)} characters, more than {MAX_TEXT_CHARS}", where=where)


def _number(value, where: str, low: float, high: float, unit: str) -> None:
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(f"expected a number [{unit}] or null, got {_kind_of(value)}", where=where)
    if not (math.isfinite(float(value)) and low <= value <= high):
        raise InputError(f"got {float(value):g}, expected {low:g} to {high:g} {unit}", where=where)


def _wheel_names(value, where: str) -> None:
    if value is None:
        return
    ok = (isinstance(value, list | tuple) and 1 <= len(value) <= MAX_WHEELS
          and all(isinstance(n, str) and 0 < len(n) <= 64 for n in value) and len(set(value)) == len(value))
    if not ok:
        raise InputError(f"expected a list of 1 to {MAX_WHEELS} distinct wheel names, got {_kind_of(value)}",
                         where=where)


def _footprint(value, where: str) -> None:
    if value is None:
        return
    numbers = isinstance(value, list | tuple) and len(value) == 3 and all(
        isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) and abs(v) <= 100 for v in value)
    if not (numbers and value[0] < value[1] and value[2] > 0):
        raise InputError("expected [x_rear, x_front, half_width] in m with x_rear < x_front and half_width > 0, "
                         f"got {_kind_of(value)}", where=where)
