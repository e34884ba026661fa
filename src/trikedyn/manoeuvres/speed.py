"""Target speed profiles: the speed the driver's speed controller aims at, over time.

A :class:`SpeedProfile` holds the target speed on a uniform time grid (step <= 0.01 s) as plain float64
arrays, for the compiled time loop. Three kinds:

- :func:`constant`: a constant target, as the paper's single lane change (ISO 14791) was driven;
- :func:`linear`: a linear ramp, the paper's double lane change (ISO 3888-1), where the throttle was held
  and the speed rose about linearly (its Fig. 8a);
- :func:`from_record`: a measured velocity record (the paper's Fig. 7a input), resampled.

Before its start and after its end a profile holds its first and last values.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..units import kmh_to_mps

__all__ = ["DT_S", "KINDS", "SpeedProfile", "constant", "from_record", "linear"]

DT_S = 0.01
"""Largest step of a profile's time grid [s]."""

KINDS = ("constant", "linear", "record")


@dataclass(frozen=True, eq=False)
class SpeedProfile:
    """Target speed on a uniform time grid.

    Parameters
    ----------
    kind : {"constant", "linear", "record"}
        How the profile was made.
    time_s : numpy.ndarray
        Uniform time grid starting at 0 [s], step <= 0.01 s.
    speed_mps : numpy.ndarray
        Target speed at those times [m/s], >= 0.
    """

    kind: str
    time_s: np.ndarray
    speed_mps: np.ndarray

    def __post_init__(self):
        if self.kind not in KINDS:
            raise InputError(f"expected one of {', '.join(KINDS)}, got {self.kind!r}", where="kind")
        t = np.ascontiguousarray(self.time_s, dtype=np.float64)
        v = np.ascontiguousarray(self.speed_mps, dtype=np.float64)
        if t.ndim != 1 or t.size < 2:
            raise InputError(f"expected a 1-D grid of at least 2 times, got shape {t.shape}", where="time_s")
        if v.shape != t.shape:
            raise InputError(f"has shape {v.shape}, time_s has {t.shape}", where="speed_mps")
        _check_speeds(v, "speed_mps")
        step = np.diff(t)
        if not np.all(np.isfinite(t)) or t[0] != 0.0 or np.any(step <= 0.0):
            raise InputError("expected an increasing grid starting at 0 s", where="time_s")
        if step.max() - step.min() > 1e-9 * max(1.0, t[-1]) or step.max() > DT_S * (1 + 1e-9):
            raise InputError(f"expected a uniform grid with a step <= {DT_S} s", where="time_s")
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "speed_mps", v)

    @property
    def duration_s(self) -> float:
        """End of the grid [s]."""
        return float(self.time_s[-1])

    def at(self, t) -> np.ndarray:
        """Target speed [m/s] at time(s) ``t`` [s], linearly interpolated; the end values hold outside.

        Parameters
        ----------
        t : float or array_like
            Time [s].

        Returns
        -------
        numpy.ndarray
            Target speed [m/s].
        """
        return np.interp(np.asarray(t, dtype=np.float64), self.time_s, self.speed_mps)

    def as_array(self) -> np.ndarray:
        """The profile as one ``(n, 2)`` float64 C-contiguous array: time [s], speed [m/s].

        Returns
        -------
        numpy.ndarray, shape (n, 2)
            Time [s] and speed [m/s] columns.
        """
        return np.ascontiguousarray(np.column_stack((self.time_s, self.speed_mps)))

    def to_dict(self) -> dict:
        """JSON-safe summary.

        Returns
        -------
        dict
            Kind, duration [s], point count, start, end and top speed [m/s].
        """
        return {
            "kind": self.kind,
            "duration_s": self.duration_s,
            "n_points": int(self.time_s.size),
            "speed_start_mps": float(self.speed_mps[0]),
            "speed_end_mps": float(self.speed_mps[-1]),
            "speed_max_mps": float(self.speed_mps.max()),
        }


def _check_speeds(v: np.ndarray, where: str) -> None:
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        raise InputError(f"value {v[bad[0]]!r} is not a finite number", where=f"{where}[{bad[0]}]")
    bad = np.flatnonzero(v < 0.0)
    if bad.size:
        raise InputError(f"speed must be >= 0, got {v[bad[0]]:g}", where=f"{where}[{bad[0]}]")


def _scalar(value, where: str, *, positive: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise InputError(f"expected a number, got {value!r}", where=where)
    value = float(value)
    if not math.isfinite(value):
        raise InputError(f"expected a finite number, got {value!r}", where=where)
    if positive and value <= 0.0:
        raise InputError(f"must be > 0, got {value:g}", where=where)
    if value < 0.0:
        raise InputError(f"must be >= 0, got {value:g}", where=where)
    return value


def _grid(duration_s: float) -> np.ndarray:
    return np.linspace(0.0, duration_s, int(math.ceil(duration_s / DT_S - 1e-9)) + 1)


def constant(speed_kmh: float, duration_s: float) -> SpeedProfile:
    """A constant target speed.

    Parameters
    ----------
    speed_kmh : float
        Target speed [km/h], >= 0.
    duration_s : float
        Length of the profile [s] (the target holds afterwards).

    Returns
    -------
    SpeedProfile
        The profile.
    """
    v = kmh_to_mps(_scalar(speed_kmh, "speed_kmh"))
    t = _grid(_scalar(duration_s, "duration_s", positive=True))
    return SpeedProfile("constant", t, np.full_like(t, v))


def linear(start_kmh: float, end_kmh: float, duration_s: float) -> SpeedProfile:
    """A target speed changing linearly from ``start_kmh`` to ``end_kmh`` over ``duration_s``.

    Parameters
    ----------
    start_kmh, end_kmh : float
        Target speed at 0 and at ``duration_s`` [km/h], >= 0.
    duration_s : float
        Duration of the ramp [s]; the end speed holds afterwards.

    Returns
    -------
    SpeedProfile
        The profile.

    Notes
    -----
    The paper's double lane change was driven with the throttle held; its speed rose about linearly and
    the simulation used a linear approximation of it (section 3.1, Fig. 8a).
    """
    v0 = kmh_to_mps(_scalar(start_kmh, "start_kmh"))
    v1 = kmh_to_mps(_scalar(end_kmh, "end_kmh"))
    t = _grid(_scalar(duration_s, "duration_s", positive=True))
    return SpeedProfile("linear", t, v0 + (v1 - v0) * (t / t[-1]))


def from_record(time_s, speed_mps, *, duration_s: float | None = None) -> SpeedProfile:
    """A measured velocity record as a target, resampled to a uniform 0.01 s grid.

    Parameters
    ----------
    time_s : array_like
        Sample times [s], strictly increasing; the profile's time 0 is the first sample.
    speed_mps : array_like
        Measured speed [m/s], finite and >= 0.
    duration_s : float, optional
        Length of the profile [s]; by default the record's. Longer than the record: the last speed holds.

    Returns
    -------
    SpeedProfile
        The profile on a 0.01 s grid.

    Notes
    -----
    Linear interpolation, no filtering: smooth a noisy record first, or the speed controller will chase
    the noise. The paper fed the simulation of its single lane change with an approximation of the
    measured longitudinal velocity (section 3.1, Fig. 7a).
    """
    t = np.asarray(time_s, dtype=np.float64)
    v = np.asarray(speed_mps, dtype=np.float64)
    if t.ndim != 1 or t.size < 2:
        raise InputError(f"expected a 1-D array of at least 2 times, got shape {t.shape}", where="time_s")
    if v.shape != t.shape:
        raise InputError(f"has shape {v.shape}, time_s has {t.shape}", where="speed_mps")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise InputError(f"value {t[bad[0]]!r} is not a finite number", where=f"time_s[{bad[0]}]")
    bad = np.flatnonzero(np.diff(t) <= 0.0)
    if bad.size:
        i = bad[0] + 1
        raise InputError(f"time must increase: {t[i]:g} s follows {t[i - 1]:g} s", where=f"time_s[{i}]")
    _check_speeds(v, "speed_mps")
    rel = t - t[0]
    end = rel[-1] if duration_s is None else _scalar(duration_s, "duration_s", positive=True)
    grid = _grid(end)
    return SpeedProfile("record", grid, np.interp(grid, rel, v))
