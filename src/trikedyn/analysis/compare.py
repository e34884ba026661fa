"""Compare a measured log with a simulation (or two runs): time alignment, resampling, error metrics.

Both sides are *tables*: a :class:`pandas.DataFrame` with a ``time_s`` column [s] (strictly increasing,
not necessarily uniform; the two sides may have different rates, e.g. a 10 Hz IMU log and a 100 Hz run)
and channels named as the IMU channels of :mod:`trikedyn.measure.logs` (``ax_mps2 ... wz_radps
roll_rad ...``). Channels present on one side only (``speed_mps``, ``temperature_degC``) are ignored.

Method (:func:`compare`)
------------------------
1. **Offset.** One channel (``align_on``; by default the yaw rate ``wz_radps``, which the paper compares,
   else the lateral acceleration ``ay_mps2``) of each side is resampled by linear interpolation onto a
   uniform grid at ``rate_hz`` (default: 10 times the slower side's median rate, at most 1000 Hz). Means
   are removed and the normalised cross-correlation ``sum x_m(t) x_s(t + d) / sqrt(sum x_m^2 sum x_s^2)``
   is evaluated for the offsets ``|d| <= max_offset_s``; its peak is refined to a fraction of a grid step
   by a parabola through the peak and its two neighbours (:func:`find_offset`).
2. **Sign convention.** ``offset_s`` is the time to *add to the measured clock to get the simulated
   clock*: an event at measured time ``t`` is at simulated time ``t + offset_s``. A measured record that
   lags the simulation by 0.3 s (its events 0.3 s later) has ``offset_s = -0.3``.
3. **Common time base.** Both sides are resampled (linear interpolation) onto a uniform grid at ``rate_hz``
   spanning the overlap of the shifted measured record with the simulated one. The grid is in the
   *simulated* clock: the measured sample at grid time ``t`` is the log's value at ``t - offset_s``.
4. **Metrics** per channel, the measured side being the reference: :func:`channel_metrics`.

Bad input (no common channel, unknown channel, time not strictly increasing, too few samples, NaN in a
used channel, no overlap after alignment) raises :class:`~trikedyn.errors.InputError` naming the side and
the channel.
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from ..measure.logs import CHANNELS, detect_format, read_log

__all__ = ["ChannelComparison", "Comparison", "channel_metrics", "compare", "find_offset", "load_table"]

TIME = "time_s"
MIN_SAMPLES = 5
"""Fewest samples a side, and the overlap of both, must have."""
MAX_RATE_HZ = 1000.0
"""Cap of the default common rate [Hz]."""
DEFAULT_ALIGN = "wz_radps"
FALLBACK_ALIGN = "ay_mps2"
_TIME_RESOLUTION_S = 1e-9  # offsets are rounded to 1 ns, so that a table compared with itself gives 0 exactly


# ------------------------------------------------------------------------------------------ results
@dataclass(frozen=True)
class ChannelComparison:
    """Error metrics of one channel; the difference is simulated minus measured.

    Attributes
    ----------
    channel : str
        Channel name (its unit is the name's suffix).
    rmse : float
        Root-mean-square difference [channel unit].
    nrmse : float
        ``rmse`` over the range (max - min) of the measured (reference) channel [-]; NaN if that range is 0.
    peak_error : float
        Largest absolute difference [channel unit].
    correlation : float
        Pearson correlation coefficient [-]; NaN if either side is constant.
    n_samples : int
        Number of samples of the common time base the metrics use.
    """

    channel: str
    rmse: float
    nrmse: float
    peak_error: float
    correlation: float
    n_samples: int


@dataclass(frozen=True)
class Comparison:
    """Two tables aligned in time, resampled onto a common base, and their per-channel metrics.

    Attributes
    ----------
    offset_s : float
        Time shift [s]: measured time + ``offset_s`` = simulated time (an event at measured time ``t``
        happens at simulated time ``t + offset_s``).
    rate_hz : float
        Rate of the common time base [Hz].
    channels : tuple of ChannelComparison
        Metrics, one per compared channel.
    time_s : ndarray
        Common time base [s], in the simulated clock.
    measured, simulated : dict of str to ndarray
        Each compared channel resampled onto ``time_s`` (the measured one shifted by ``offset_s``).
    align_on : str or None
        Channel the offset was found on; None if no alignment was made.
    labels : tuple of str
        Names of the two sides (legend of :meth:`plot`).
    """

    offset_s: float
    rate_hz: float
    channels: tuple[ChannelComparison, ...]
    time_s: np.ndarray
    measured: dict[str, np.ndarray]
    simulated: dict[str, np.ndarray]
    align_on: str | None = DEFAULT_ALIGN
    labels: tuple[str, str] = ("measured", "simulated")

    def __getitem__(self, channel: str) -> ChannelComparison:
        """The metrics of ``channel``; InputError naming the compared channels if it was not compared."""
        for c in self.channels:
            if c.channel == channel:
                return c
        raise InputError(_unknown(channel, [c.channel for c in self.channels], "compared"), where="channel")

    def to_dict(self) -> dict:
        """JSON-safe summary: ``offset_s``, ``rate_hz``, ``align_on`` and per channel the metrics.

        NaN and infinite values become None.
        """
        return {
            "offset_s": _json_float(self.offset_s),
            "rate_hz": _json_float(self.rate_hz),
            "align_on": self.align_on,
            "channels": {c.channel: {"rmse": _json_float(c.rmse), "nrmse": _json_float(c.nrmse),
                                     "peak_error": _json_float(c.peak_error),
                                     "correlation": _json_float(c.correlation), "n_samples": int(c.n_samples)}
                         for c in self.channels},
        }

    def to_pandas(self) -> pd.DataFrame:
        """The aligned records: ``time_s`` [s] (simulated clock), then ``measured_<channel>`` and
        ``simulated_<channel>`` per channel; ``attrs`` hold ``offset_s``, ``rate_hz`` and ``align_on``."""
        data = {TIME: self.time_s}
        for c in self.channels:
            data[f"measured_{c.channel}"] = self.measured[c.channel]
            data[f"simulated_{c.channel}"] = self.simulated[c.channel]
        frame = pd.DataFrame(data)
        frame.attrs.update(offset_s=self.offset_s, rate_hz=self.rate_hz, align_on=self.align_on)
        return frame

    def plot(self, channels=None):
        """Measured over simulated, one axis per channel (as the paper's Figs. 7-8); returns the Figure.

        Parameters
        ----------
        channels : sequence of str, optional
            Channels to draw (default: all compared ones).
        """
        import matplotlib.pyplot as plt

        names = [c.channel for c in self.channels] if channels is None else list(channels)
        metrics = [self[name] for name in names]
        if not metrics:
            raise InputError("no channel to plot; pass one or more compared channels", where="channels")
        fig, axes = plt.subplots(len(metrics), 1, sharex=True, figsize=(7, 2.0 * len(metrics)), squeeze=False)
        for ax, m in zip(axes[:, 0], metrics, strict=True):
            ax.plot(self.time_s, self.measured[m.channel], label=self.labels[0], color="k", lw=1.0)
            ax.plot(self.time_s, self.simulated[m.channel], label=self.labels[1], color="tab:red", lw=1.2,
                    ls="--")
            ax.set_ylabel(m.channel)
            ax.set_title(f"RMSE {m.rmse:.3g}, NRMSE {m.nrmse:.1%}, r = {m.correlation:.3f}", fontsize=8,
                         loc="right")
            ax.grid(alpha=0.3)
        axes[0, 0].legend(loc="upper left", fontsize=8)
        axes[-1, 0].set_xlabel(f"time [s] ({self.labels[1]} clock; {self.labels[0]} shifted by "
                               f"{self.offset_s:+.3f} s)")
        fig.tight_layout()
        return fig


# ------------------------------------------------------------------------------------------ helpers
def _json_float(value: float) -> float | None:
    value = float(value)
    return value if math.isfinite(value) else None


def _unknown(name: str, choices: list[str], what: str) -> str:
    close = difflib.get_close_matches(name, choices, n=1)
    hint = f"; did you mean {close[0]!r}?" if close else ""
    return f"unknown channel {name!r}; {what} channels: {', '.join(choices) or 'none'}{hint}"


def _check_time(t, where: str, min_samples: int = MIN_SAMPLES) -> np.ndarray:
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


def _check_values(x, n: int, where: str, t: np.ndarray | None = None) -> np.ndarray:
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


# ------------------------------------------------------------------------------------------ algorithms
def channel_metrics(measured, simulated, *, channel: str = "") -> ChannelComparison:
    """Error metrics of two equally long records on the same time base; measured is the reference.

    Parameters
    ----------
    measured, simulated : array_like
        Values [channel unit] at the same times.
    channel : str
        Name stored in the result.

    Returns
    -------
    ChannelComparison
        ``rmse = sqrt(mean((s - m)^2))``, ``nrmse = rmse / (max(m) - min(m))`` (NaN if that range is 0),
        ``peak_error = max|s - m|``, ``correlation`` = Pearson's r (NaN if either side is constant),
        ``n_samples``.
    """
    m = np.asarray(measured, dtype=float)
    s = np.asarray(simulated, dtype=float)
    if m.shape != s.shape or m.ndim != 1 or m.size == 0:
        raise InputError(f"measured and simulated must be 1-D of equal, non-zero length; got {m.shape} and "
                         f"{s.shape}", where=f"channel {channel!r}" if channel else None)
    diff = s - m
    rmse = float(np.sqrt(np.mean(diff * diff)))
    span = float(m.max() - m.min())
    nrmse = rmse / span if span > 0 else math.nan
    dm, ds = m - m.mean(), s - s.mean()
    den = math.sqrt(float(dm @ dm) * float(ds @ ds))
    corr = float(np.clip((dm @ ds) / den, -1.0, 1.0)) if den > 0 else math.nan
    return ChannelComparison(channel, rmse, nrmse, float(np.max(np.abs(diff))), corr, int(m.size))


def _xcorr_offset(t_ref, x_ref, t_other, x_other, max_offset_s, rate_hz, names) -> float:
    """:func:`find_offset` on checked arrays; ``names`` name the two sides in errors."""
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
    t_ref = _check_time(t_ref, f"{names[0]} time")
    t_other = _check_time(t_other, f"{names[1]} time")
    x_ref = _check_values(x_ref, t_ref.size, f"{names[0]} values", t_ref)
    x_other = _check_values(x_other, t_other.size, f"{names[1]} values", t_other)
    rate_hz = _check_rate(rate_hz, t_ref, t_other)
    max_offset_s = _check_max_offset(max_offset_s)
    return _xcorr_offset(t_ref, x_ref, t_other, x_other, max_offset_s, rate_hz, names)


def _check_rate(rate_hz, *times) -> float:
    if rate_hz is None:
        return _default_rate(*times)
    if not (isinstance(rate_hz, (int, float, np.number)) and math.isfinite(rate_hz) and rate_hz > 0):
        raise InputError(f"rate_hz={rate_hz!r} must be a positive number [Hz]", where="rate_hz")
    return float(rate_hz)


def _check_max_offset(max_offset_s) -> float | None:
    if max_offset_s is None:
        return None
    if not (isinstance(max_offset_s, (int, float, np.number)) and math.isfinite(max_offset_s)
            and max_offset_s >= 0):
        raise InputError(f"max_offset_s={max_offset_s!r} must be a number >= 0 [s] or None", where="max_offset_s")
    return float(max_offset_s)


# ------------------------------------------------------------------------------------------ tables
def _table_time(frame, side: str) -> tuple[pd.DataFrame, np.ndarray]:
    """The table (``time_s`` moved from the index to a column if it is there) and its checked time."""
    if not isinstance(frame, pd.DataFrame):
        raise InputError(f"is a {type(frame).__name__}; expected a pandas DataFrame with a 'time_s' column",
                         where=side)
    if TIME not in frame.columns and frame.index.name == TIME:
        frame = frame.reset_index()
    if TIME not in frame.columns:
        raise InputError(f"has no 'time_s' column; columns: {', '.join(map(str, frame.columns)) or 'none'}",
                         where=side)
    return frame, _check_time(frame[TIME].to_numpy(), f"{side} {TIME!r}")


def _numeric_channels(frame: pd.DataFrame) -> list[str]:
    return [c for c in frame.columns if c != TIME and isinstance(c, str)
            and pd.api.types.is_numeric_dtype(frame[c]) and not pd.api.types.is_bool_dtype(frame[c])]


def _order(names) -> list[str]:
    """IMU channels first, in their usual order, then the others as given."""
    names = list(names)
    return [c for c in CHANNELS if c in names] + [c for c in names if c not in CHANNELS]


def compare(measured: pd.DataFrame, simulated: pd.DataFrame, *, channels=None, align_on: str | None = DEFAULT_ALIGN,
            max_offset_s: float | None = 5.0, rate_hz: float | None = None,
            labels: tuple[str, str] = ("measured", "simulated")) -> Comparison:
    """Align a measured table with a simulated one in time and compare their common channels.

    Parameters
    ----------
    measured, simulated : pandas.DataFrame
        Tables with a ``time_s`` column [s] (or index) and channels in SI units. The measured side is the
        reference of ``nrmse``. Any two tables work (two runs, two logs).
    channels : sequence of str, optional
        Channels to compare; default: every numeric channel the two tables share.
    align_on : str or None
        Channel whose cross-correlation gives the offset (need not be among ``channels``). The default
        ``"wz_radps"`` (yaw rate) falls back to ``"ay_mps2"`` if a side lacks it. None: no alignment
        (offset 0).
    max_offset_s : float or None
        Largest absolute offset searched [s]; 0 means no alignment, None any offset with overlap.
    rate_hz : float, optional
        Rate of the common time base [Hz]; default: 10 times the slower side's median rate, at most 1000 Hz.
    labels : tuple of str
        Names of the two sides in error messages and plot legends.

    Returns
    -------
    Comparison
        Offset (measured time + ``offset_s`` = simulated time), the resampled records over the overlap in
        the simulated clock, and the metrics per channel.

    Raises
    ------
    InputError
        No common channel, an unknown channel, time not strictly increasing, fewer than
        :data:`MIN_SAMPLES` samples (on a side or in the overlap), NaN in a used channel, no overlap after
        alignment, a constant alignment channel, or a correlation peak at the edge of the search window.
    """
    labels = (str(labels[0]), str(labels[1]))
    measured, t_m = _table_time(measured, labels[0])
    simulated, t_s = _table_time(simulated, labels[1])
    sim_channels = set(_numeric_channels(simulated))
    common = _order(c for c in _numeric_channels(measured) if c in sim_channels)
    if not common:
        raise InputError(f"no channel in common; {labels[0]} has {', '.join(_numeric_channels(measured)) or 'none'}"
                         f", {labels[1]} has {', '.join(_order(sim_channels)) or 'none'}",
                         where=f"{labels[0]} vs {labels[1]}")
    if channels is None:
        used = common
    else:
        used = [channels] if isinstance(channels, str) else list(dict.fromkeys(channels))
        for name in used:
            if name not in common:
                raise InputError(_unknown(name, common, "common"), where="channels")
        if not used:
            raise InputError(f"no channel asked; common channels: {', '.join(common)}", where="channels")
    rate_hz = _check_rate(rate_hz, t_m, t_s)
    max_offset_s = _check_max_offset(max_offset_s)

    if align_on == DEFAULT_ALIGN and align_on not in common and FALLBACK_ALIGN in common:
        align_on = FALLBACK_ALIGN
    if align_on is not None and align_on not in common:
        raise InputError(_unknown(align_on, common, "common") + "; or align_on=None for no alignment",
                         where="align_on")

    def values(frame, t, side, name):
        return _check_values(frame[name].to_numpy(), t.size, f"{side} {name!r}", t)

    xm = {c: values(measured, t_m, labels[0], c) for c in used}
    xs = {c: values(simulated, t_s, labels[1], c) for c in used}
    if align_on is None or max_offset_s == 0:
        align_on, offset = None, 0.0
    else:
        am = xm[align_on] if align_on in xm else values(measured, t_m, labels[0], align_on)
        a_s = xs[align_on] if align_on in xs else values(simulated, t_s, labels[1], align_on)
        offset = _xcorr_offset(t_m, am, t_s, a_s, max_offset_s, rate_hz,
                               (f"{labels[0]} {align_on!r}", f"{labels[1]} {align_on!r}"))

    start, end = max(t_m[0] + offset, t_s[0]), min(t_m[-1] + offset, t_s[-1])
    n = int(math.floor((end - start) * rate_hz + 1e-9)) + 1 if end >= start else 0
    if n < MIN_SAMPLES:
        what = "no overlap" if end < start else f"an overlap of {end - start:.3g} s ({n} samples at {rate_hz:g} Hz)"
        raise InputError(f"{what} after alignment: {labels[0]} spans {t_m[0] + offset:.3f}..{t_m[-1] + offset:.3f} s "
                         f"(shifted by {offset:+.3f} s), {labels[1]} {t_s[0]:.3f}..{t_s[-1]:.3f} s; expected at "
                         f"least {MIN_SAMPLES} samples in common", where=f"{labels[0]} vs {labels[1]}")
    grid = np.minimum(start + np.arange(n) / rate_hz, end)
    rm = {c: np.interp(grid - offset, t_m, xm[c]) for c in used}
    rs = {c: np.interp(grid, t_s, xs[c]) for c in used}
    metrics = tuple(channel_metrics(rm[c], rs[c], channel=c) for c in used)
    return Comparison(offset, rate_hz, metrics, grid, rm, rs, align_on, labels)


def load_table(path) -> tuple[pd.DataFrame, str]:
    """Read a table to compare: an IMU log or a run file written by the simulator.

    Parameters
    ----------
    path : str or Path
        ``.parquet``/``.pq``: a run file (Parquet with a ``time_s`` column or index). Otherwise a CSV whose
        header holds ``time_s`` and whose ``time_s`` is numeric is read as it is (a run file, or a log
        converted to SI CSV); any other file is read by :func:`trikedyn.measure.logs.read_log` (format
        detected).

    Returns
    -------
    table : pandas.DataFrame
        ``time_s`` [s] column first, then the channels.
    kind : str
        What the file was: ``"run-parquet"``, ``"run-csv"``, or the IMU log format (a key of
        :data:`trikedyn.measure.logs.FORMATS`, e.g. ``"witmotion-sdk"``).

    Raises
    ------
    InputError
        The file is missing, unreadable, has no ``time_s`` or a bad time (LogFormatError for IMU logs).
    """
    path = Path(path)
    where = str(path)
    if path.suffix.lower() in (".parquet", ".pq"):
        if not path.is_file():
            raise InputError("file not found; expected a Parquet run file", where=where)
        try:
            frame = pd.read_parquet(path)
        except ImportError:
            raise InputError("reading Parquet needs pyarrow or fastparquet, which are not installed; install "
                             "one or write the run as CSV", where=where) from None
        except Exception as e:  # any reader failure is a bad file here
            raise InputError(f"cannot read as Parquet ({type(e).__name__}: {e})", where=where) from None
        return _run_table(frame, where), "run-parquet"
    fmt = detect_format(path)
    if fmt == "csv":
        frame = _read_run_csv(path)
        if frame is not None:
            return _run_table(frame, where), "run-csv"
    return read_log(path, fmt).data, fmt


def _read_run_csv(path: Path) -> pd.DataFrame | None:
    """The CSV as it is if its header holds ``time_s`` and that column is numeric, else None."""
    with path.open("r", encoding="utf-8", errors="replace") as f:
        first = next((line for line in f if line.strip()), "")
    sep = next((s for s in ",;\t" if s in first), None)
    if sep is None or TIME not in [h.strip().lstrip("\ufeff") for h in first.split(sep)]:
        return None
    try:
        frame = pd.read_csv(path, sep=sep, skipinitialspace=True, encoding="utf-8-sig")
    except (ValueError, UnicodeDecodeError, pd.errors.ParserError) as e:
        raise InputError(f"cannot read as CSV ({e})".replace("\n", " "), where=str(path)) from None
    frame.columns = [str(c).strip() for c in frame.columns]
    if not pd.api.types.is_numeric_dtype(frame[TIME]):
        return None
    return frame


def _run_table(frame: pd.DataFrame, where: str) -> pd.DataFrame:
    if TIME not in frame.columns and frame.index.name == TIME:
        frame = frame.reset_index()
    if TIME not in frame.columns:
        raise InputError(f"no 'time_s' column; columns: {', '.join(map(str, frame.columns))}", where=where)
    _check_time(frame[TIME].to_numpy(), f"{where}: {TIME!r}", min_samples=1)
    return frame[[TIME, *(c for c in frame.columns if c != TIME)]].reset_index(drop=True)
