"""Declared ranges of a vehicle file's assumed values (the ``ranges`` field of
:class:`~trikedyn.params.schema.VehicleParameters`; the form is described in :mod:`trikedyn.params.schema`):
``[low, high]`` in the value's unit, or ``{ rel = f }`` for ``value * (1 -/+ f)``, in ``[ranges.SECTION]``
tables or with dotted keys in ``[ranges]``. What they are for: :mod:`trikedyn.study.designs.factors`."""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field

__all__ = ["MAX_RANGES", "RangeSpec", "RelativeRange", "flat_ranges"]


class RelativeRange(BaseModel):
    """A range relative to its value: ``value * (1 -/+ rel)``."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True, allow_inf_nan=False)

    rel: float = Field(gt=0, lt=1, description="half-width as a fraction of the value (0.2: +/-20 %)")


def _range(value):
    """``[low, high]`` (two finite numbers, low < high) or ``{ rel = f }``; one clear message otherwise."""
    if isinstance(value, RelativeRange):
        return value
    if isinstance(value, dict):
        rel = value.get("rel")
        if set(value) != {"rel"}:
            raise ValueError(f"expected {{ rel = fraction }} alone, got the keys {', '.join(map(str, value))}")
        if isinstance(rel, bool) or not isinstance(rel, int | float) or not (math.isfinite(rel) and 0 < rel < 1):
            raise ValueError(f"rel: expected a fraction between 0 and 1 (0.2 = +/-20 %), got {rel!r}")
        return RelativeRange(rel=float(rel))
    if isinstance(value, list | tuple) and len(value) == 2 and all(
            isinstance(v, int | float) and not isinstance(v, bool) for v in value):
        low, high = (float(v) for v in value)
        if not (math.isfinite(low) and math.isfinite(high)):
            raise ValueError(f"expected finite numbers, got [{low:g}, {high:g}]")
        if not low < high:
            raise ValueError(f"expected [low, high] with low < high, got [{low:g}, {high:g}]")
        return (low, high)
    raise ValueError(f"expected [low, high] (two numbers) or {{ rel = fraction }}, got {value!r}")


RangeSpec = Annotated[tuple[float, float] | RelativeRange, BeforeValidator(_range)]
"""A declared range: ``[low, high]`` in the value's unit, or ``{ rel = f }``."""

MAX_RANGES = 500


def flat_ranges(node, prefix: str = "") -> dict:
    """``[ranges.mass] cg_z_m = ...`` and ``[ranges] "mass.cg_z_m" = ...`` alike: ``{"mass.cg_z_m": ...}``.

    A table is a range (``{ rel = f }``) if it has a ``rel`` key, else a section to descend into. A key given
    in both forms keeps the later one (after ``extends`` merged the tables, the extending file's).

    Parameters
    ----------
    node : dict
        The ``[ranges]`` table.
    prefix : str
        Path of ``node``.

    Returns
    -------
    dict
        Dotted parameter path -> range.

    Raises
    ------
    ValueError
        When ``node`` is not a table.
    """
    if not isinstance(node, dict):
        raise ValueError("expected a table of ranges keyed by parameter path ([ranges.mass] cg_z_m = [low, high])")
    out = {}
    for key, value in node.items():
        path = f"{prefix}.{key}" if prefix else str(key)
        if isinstance(value, dict) and value and "rel" not in value:
            out.update(flat_ranges(value, path))
        else:
            out.pop(path, None)
            out[path] = value  # the later wins: a file's own range over the one of the file it extends
        if len(out) > MAX_RANGES:
            raise ValueError(f"more than {MAX_RANGES} ranges")
    return out
