"""Time alignment of two records by cross-correlation, and the checks of the records it takes.

:func:`find_offset` finds the time offset between two records of one quantity (a measured yaw rate and a
simulated one): both are resampled by linear interpolation onto uniform grids at ``rate_hz`` (default: 10
times the slower record's median rate, at most :data:`MAX_RATE_HZ`), their means removed, and the normalised
cross-correlation ``sum x_m(t) x_s(t + d) / sqrt(sum x_m^2 sum x_s^2)`` evaluated for the offsets
``|d| <= max_offset_s``; its peak is refined to a fraction of a grid step by a parabola through the peak and
its two neighbours. The offset ``d`` is the time to add to the reference clock to get the other clock.

The checks (``checked_time``, ``checked_values``, ``checked_rate``, ``checked_max_offset``) raise
:class:`~trikedyn.errors.InputError` naming the record: :func:`trikedyn.analysis.compare.compare` uses
them on its tables too.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

__all__ = ["DEFAULT_ALIGN", "FALLBACK_ALIGN", "MAX_RATE_HZ", "MIN_SAMPLES", "TIME", "find_offset"]

TIME = "time_s"
"""Name of the time column [s] of a table."""
MIN_SAMPLES = 5
"""Fewest samples a side, and the overlap of both, must have."""
MAX_RATE_HZ = 1000.0
"""Cap of the default common rate [Hz]."""
DEFAULT_ALIGN = "wz_radps"
"""Channel aligned on by default: the yaw rate, which the paper compares."""
FALLBACK_ALIGN = "ay_mps2"
"""Channel aligned on when a side lacks :data:`DEFAULT_ALIGN`: the lateral acceleration."""
_TIME_RESOLUTION_S = 1e-9  # offsets are rounded to 1 ns, so that a table compared with itself gives 0 exactly


def checked_time(t, where: str, min_samples: int = MIN_SAMPLES) -> np.ndarray:
    """``t`` as a float array: finite, strictly increasing, at least ``min_samples`` long."""
    try:
        t = np.asarray(t, dtype=float)
    except (TypeError, ValueError):
        raise InputError("time holds values that are not numbers; expected seconds", where=where) from None
    if t.ndim != 1 or t.size < min_samples:
        raise InputError(f"too few samples ({t.size}); expected at least {min_samples}", where=where)
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise InputError(f"time is not finite at row {bad[0]} ({t[bad[0]]}); expected finite seconds",
                         where=where)
    step = np.diff(t)
    bad = np.flatnonzero(step <= 0)
    if bad.size:
        i = bad[0] + 1
        raise InputError(f"time does not increase at row {i} ({t[i - 1]:.6g} s then {t[i]:.6g} s); expected "
                         "strictly increasing time", where=where)
    return t


def checked_values(x, n: int, where: str, t: np.ndarray | None = None) -> np.ndarray:
    """``x`` as a float array of length ``n`` without NaN or infinity."""
    try:
        x = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise InputError("holds values that are not numbers", where=where) from None
    if x.shape != (n,):
        raise InputError(f"has {x.size} values but the time has {n}; expected one value per time", where=where)
    bad = np.flatnonzero(~np.isfinite(x))
    if bad.size:
        at = f" (time_s = {t[bad[0]]:.6g} s)" if t is not None else ""
        raise InputError(f"holds {x[bad[0]]} at row {bad[0]}{at}; expected finite values", where=where)
    return x


def checked_rate(rate_hz, *times) -> float:
    """``rate_hz`` [Hz] as a positive float; None: 10 times the slowest median rate of ``times``, at most
    :data:`MAX_RATE_HZ`."""
    if rate_hz is None:
        return _default_rate(*times)
    if not (isinstance(rate_hz, (int, float, np.number)) and math.isfinite(rate_hz) and rate_hz > 0):
        raise InputError(f"rate_hz={rate_hz!r} must be a positive number [Hz]", where="rate_hz")
    return float(rate_hz)


def checked_max_offset(max_offset_s) -> float | None:
    """``max_offset_s`` [s] as a float >= 0, or None (any offset)."""
    if max_offset_s is None:
        return None
    if not (isinstance(max_offset_s, (int, float, np.number)) and math.isfinite(max_offset_s)
            and max_offset_s >= 0):
        raise InputError(f"max_offset_s={max_offset_s!r} must be a number >= 0 [s] or None", where="max_offset_s")
    return float(max_offset_s)


def _median_rate(t: np.ndarray) -> float:
    """Median sample rate [Hz] of strictly increasing times ``t`` [s], to 6 significant digits."""
    return float(f"{1.0 / np.median(np.diff(t)):.6g}")


def _default_rate(*times) -> float:
    """Default common rate [Hz]: 10 times the slowest median rate of ``times``, at most 1000 Hz."""
    return min(10.0 * min(_median_rate(np.asarray(t, float)) for t in times), MAX_RATE_HZ)


def _uniform(t: np.ndarray, x: np.ndarray, rate_hz: float) -> tuple[float, np.ndarray]:
    """Start [s] and values of ``x(t)`` linearly interpolated onto a grid at ``rate_hz`` over ``t``."""
    n = int(math.floor((t[-1] - t[0]) * rate_hz + 1e-9)) + 1
    grid = t[0] + np.arange(n) / rate_hz
    return float(t[0]), np.interp(grid, t, x)


def xcorr_offset(t_ref, x_ref, t_other, x_other, max_offset_s, rate_hz, names) -> float:
    """:func:`find_offset` on checked arrays (:func:`checked_time`, ...) and a checked rate and search window;
    ``names`` name the two sides in errors."""
    r0, xr = _uniform(t_ref, x_ref, rate_hz)
    o0, xo = _uniform(t_other, x_other, rate_hz)
    xr = xr - xr.mean()
    xo = xo - xo.mean()
    for x, name in ((xr, names[0]), (xo, names[1])):
        if not np.any(x):
            raise InputError("is constant; cannot find a time offset on it (align on another channel, or "
                             "not at all)", where=name)
    from scipy.signal import correlate, correlation_lags

    # c[k] = sum_i xr[i] xo[i + k]: the reference sample i matches the other's sample i + k, i.e.
    # the offset d = o0 - r0 + k / rate_hz (reference time + d = other time).
    c = correlate(xo, xr, mode="full", method="auto") / math.sqrt(float(xr @ xr) * float(xo @ xo))
    lags = correlation_lags(xo.size, xr.size, mode="full")
    d = o0 - r0 + lags / rate_hz
    inside = np.ones(d.size, bool) if max_offset_s is None else np.abs(d) <= max_offset_s + 1e-9 / rate_hz
    idx = np.flatnonzero(inside)
    if idx.size < 3:
        raise InputError(f"the search window |offset| <= {max_offset_s:g} s holds {idx.size} lag(s) at "
                         f"{rate_hz:g} Hz; the records' starts are {o0 - r0:+.3f} s apart; raise max_offset_s",
                         where=f"{names[0]} vs {names[1]}")
    k = idx[np.argmax(c[idx])]
    if k == idx[0] or k == idx[-1]:
        limit = (f"the search window |offset| <= {max_offset_s:g} s" if max_offset_s is not None
                 else "the records' overlap")
        raise InputError(f"the cross-correlation peaks at the edge of {limit} (offset {d[k]:+.3f} s, "
                         f"correlation {c[k]:.2f}); the records may be further apart (raise max_offset_s) or "
                         "not alike", where=f"{names[0]} vs {names[1]}")
    lo, mid, hi = c[k - 1], c[k], c[k + 1]
    curvature = lo - 2.0 * mid + hi
    frac = 0.5 * (lo - hi) / curvature if curvature < 0 else 0.0
    offset = float(d[k] + frac / rate_hz)
    return round(offset / _TIME_RESOLUTION_S) * _TIME_RESOLUTION_S + 0.0


def find_offset(t_ref, x_ref, t_other, x_other, *, max_offset_s: float | None = None,
                rate_hz: float | None = None) -> float:
    """Time offset between two records of one quantity, by normalised cross-correlation.

    Both records are linearly interpolated onto uniform grids at ``rate_hz``, their means removed, and the
    normalised cross-correlation evaluated over the offsets ``|d| <= max_offset_s``; the peak is refined by
    parabolic interpolation to a fraction of ``1 / rate_hz``.

    Parameters
    ----------
    t_ref, x_ref : array_like
        Times [s] (strictly increasing) and values of the reference record (the measured one).
    t_other, x_other : array_like
        Times [s] and values of the other record (the simulated one), in the same unit as ``x_ref``.
    max_offset_s : float, optional
        Largest absolute offset searched [s]; default: any offset at which the records overlap.
    rate_hz : float, optional
        Rate of the correlation grid [Hz]; default: 10 times the slower record's median rate, at most
        1000 Hz.

    Returns
    -------
    float
        Offset ``d`` [s] such that ``x_other(t + d)`` matches ``x_ref(t)``: reference time + ``d`` = other
        time. Rounded to 1 ns.

    Raises
    ------
    InputError
        If a time is not strictly increasing, a record is shorter than :data:`MIN_SAMPLES` or holds NaN or
        is constant, or the correlation peaks at the edge of the search window.
    """
    names = ("reference", "other")
    t_ref = checked_time(t_ref, f"{names[0]} time")
    t_other = checked_time(t_other, f"{names[1]} time")
    x_ref = checked_values(x_ref, t_ref.size, f"{names[0]} values", t_ref)
    x_other = checked_values(x_other, t_other.size, f"{names[1]} values", t_other)
    rate_hz = checked_rate(rate_hz, t_ref, t_other)
    max_offset_s = checked_max_offset(max_offset_s)
    return xcorr_offset(t_ref, x_ref, t_other, x_other, max_offset_s, rate_hz, names)
