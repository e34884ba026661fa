"""What the handling reductions share: a JSON-safe result base and the checks of sampled input signals.

Used by :mod:`~trikedyn.analysis.handling`, :mod:`~trikedyn.analysis.steady_state` and
:mod:`~trikedyn.analysis.steer_shape`. Bad input raises :class:`~trikedyn.errors.InputError` naming the
argument.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import InputError

__all__ = ["PlainResult", "as_time", "as_values", "crossing", "json_float", "positive"]


def json_float(value) -> float | None:
    """``value`` as a float, None for NaN or infinity."""
    value = float(value)
    return value if math.isfinite(value) else None


def _plain(value):
    if hasattr(value, "to_dict"):
        return value.to_dict()
    if isinstance(value, str) or value is None:
        return value
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (np.ndarray, list, tuple)):
        return [_plain(v) for v in value]
    return json_float(value)


class PlainResult:
    """Base of the frozen result dataclasses: :meth:`to_dict` of their fields."""

    def to_dict(self) -> dict:
        """JSON-safe plain values: floats (None for NaN or infinity), ints, strings, lists for arrays and
        tuples, and the ``to_dict()`` of nested results."""
        return {f.name: _plain(getattr(self, f.name)) for f in dataclasses.fields(self)}


def as_time(t, min_samples=5) -> np.ndarray:
    """Time [s] as a 1-D float array of at least ``min_samples`` finite, strictly increasing samples."""
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size < min_samples:
        raise InputError(f"expected a 1-D array of at least {min_samples} samples, got shape {t.shape}", "time_s")
    if not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise InputError("time must be finite and strictly increasing", "time_s")
    return t


def as_values(x, n, where) -> np.ndarray:
    """``x`` as a float array of shape ``(n,)``, finite throughout; ``where`` names it in the error."""
    x = np.asarray(x, dtype=float)
    if x.shape != (n,):
        raise InputError(f"has shape {x.shape}; expected ({n},), one value per sample", where)
    if not np.all(np.isfinite(x)):
        raise InputError(f"holds NaN or infinity at sample {int(np.flatnonzero(~np.isfinite(x))[0])}", where)
    return x


def positive(value, where) -> float:
    """``value`` as a float if positive and finite; ``where`` names it in the error."""
    value = float(value)
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"must be a positive finite number, got {value}", where)
    return value


def crossing(t, y, level, start=0) -> float:
    """Time ``y`` first reaches ``level`` at or after index ``start``, interpolated linearly; NaN if never."""
    idx = np.flatnonzero(y[start:] >= level)
    if idx.size == 0:
        return math.nan
    i = start + int(idx[0])
    if i == 0 or y[i - 1] >= level:
        return float(t[i])
    return float(t[i - 1] + (level - y[i - 1]) / (y[i] - y[i - 1]) * (t[i] - t[i - 1]))
