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
   by a parabola through the peak and its two neighbours
   (:func:`~trikedyn.analysis.alignment.find_offset`).
2. **Sign convention.** ``offset_s`` is the time to *add to the measured clock to get the simulated
   clock*: an event at measured time ``t`` is at simulated time ``t + offset_s``. A measured record that
   lags the simulation by 0.3 s (its events 0.3 s later) has ``offset_s = -0.3``.
3. **Common time base.** Both sides are resampled (linear interpolation) onto a uniform grid at ``rate_hz``
   spanning the overlap of the shifted measured record with the simulated one. The grid is in the
   *simulated* clock: the measured sample at grid time ``t`` is the log's value at ``t - offset_s``.
4. **Metrics** per channel, the measured side being the reference:
   :func:`~trikedyn.analysis.scoring.channel_metrics`, in a :class:`~trikedyn.analysis.scoring.Comparison`.

This module reads the tables (:func:`load_table`) and runs the method; the alignment is in
:mod:`trikedyn.analysis.alignment`, the metrics and the result in :mod:`trikedyn.analysis.scoring`.

Bad input (no common channel, unknown channel, time not strictly increasing, too few samples, NaN in a
used channel, no overlap after alignment) raises :class:`~trikedyn.errors.InputError` naming the side and
the channel.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from ..measure.logs import CHANNELS, detect_format, read_log
from .alignment import (  # noqa: F401  (MAX_RATE_HZ, find_offset: importable from here as before the split)
    DEFAULT_ALIGN,
    FALLBACK_ALIGN,
    MAX_RATE_HZ,
    MIN_SAMPLES,
    TIME,
    checked_max_offset,
    checked_rate,
    checked_time,
    checked_values,
    find_offset,
    xcorr_offset,
)
from .scoring import ChannelComparison, Comparison, channel_metrics, unknown_channel  # noqa: F401

__all__ = ["compare", "load_table"]


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
    return frame, checked_time(frame[TIME].to_numpy(), f"{side} {TIME!r}")


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
                raise InputError(unknown_channel(name, common, "common"), where="channels")
        if not used:
            raise InputError(f"no channel asked; common channels: {', '.join(common)}", where="channels")
    rate_hz = checked_rate(rate_hz, t_m, t_s)
    max_offset_s = checked_max_offset(max_offset_s)

    if align_on == DEFAULT_ALIGN and align_on not in common and FALLBACK_ALIGN in common:
        align_on = FALLBACK_ALIGN
    if align_on is not None and align_on not in common:
        raise InputError(unknown_channel(align_on, common, "common") + "; or align_on=None for no alignment",
                         where="align_on")

    def values(frame, t, side, name):
        """The checked values of channel ``name`` of one side."""
        return checked_values(frame[name].to_numpy(), t.size, f"{side} {name!r}", t)

    xm = {c: values(measured, t_m, labels[0], c) for c in used}
    xs = {c: values(simulated, t_s, labels[1], c) for c in used}
    if align_on is None or max_offset_s == 0:
        align_on, offset = None, 0.0
    else:
        am = xm[align_on] if align_on in xm else values(measured, t_m, labels[0], align_on)
        a_s = xs[align_on] if align_on in xs else values(simulated, t_s, labels[1], align_on)
        offset = xcorr_offset(t_m, am, t_s, a_s, max_offset_s, rate_hz,
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
        detected). Run tables are read and checked by :func:`trikedyn.simulate.runcheck.read_run_table`
        (bounded read, every column numbers, time finite and increasing), as ``plot`` and ``animate`` read
        them.

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
        The file is missing, not a regular file, too large, unreadable, has no ``time_s`` or a bad time, or a
        column that is not numbers (LogFormatError for IMU logs).
    """
    from .._reading import file_problem
    from ..simulate.runcheck import read_run_table

    path = Path(path)
    if path.suffix.lower() in (".parquet", ".pq"):
        return read_run_table(path, as_run=False)
    problem = file_problem(path)
    if problem is not None:  # before anything is opened: a pipe or a device is refused unopened
        raise InputError("file not found" if problem == "no such file" else problem, where=str(path))
    found = read_run_table(path, as_run=False)  # None: no numeric time_s in a CSV header, an IMU log then
    if found is not None:
        return found
    fmt = detect_format(path)
    return read_log(path, fmt).data, fmt
