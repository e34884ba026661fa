"""Clock times of IMU logs: clock texts and chip-time fields to seconds, and seconds back to clock fields.

Times are counted from the first row; a clock without a date that jumps back by more than 12 h has passed
midnight (see :mod:`trikedyn.measure.logs`).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import LogFormatError

__all__ = ["clock_fields", "clock_seconds", "clock_text", "seconds"]

CLOCK = re.compile(r"^\s*(?:(\d{4})[-/](\d{1,2})[-/](\d{1,2})[ T]+)?"
                   r"(\d{1,2}):(\d{1,2}):(\d{1,2})(?:[.,](\d+))?\s*$")


def seconds(ymd: np.ndarray | None, hms: np.ndarray, frac_s: np.ndarray) -> tuple[np.ndarray, int]:
    """Seconds from the first row (NaN where invalid, to 1 ns) and how often a dateless clock wrapped.

    ``ymd`` and ``hms`` have rows (year, month, day) and (hour, minute, second); ``ymd=None``: no date,
    and a clock that goes back by more than 12 h has passed midnight.

    Parameters
    ----------
    ymd : numpy.ndarray or None
        Rows (year, month, day), or None for no date.
    hms : numpy.ndarray
        Rows (hour, minute, second).
    frac_s : numpy.ndarray
        Fractions of a second [s].

    Returns
    -------
    seconds : numpy.ndarray
        Time from the first row [s].
    wraps : int
        Midnight wraps.
    """
    h, m, s = hms.T
    sod = np.where((h < 24) & (m < 60) & (s < 61), h * 3600 + m * 60 + s + frac_s, np.nan)
    if ymd is not None:
        dates = pd.to_datetime(pd.DataFrame(ymd, columns=["year", "month", "day"]), errors="coerce")
        days = ((dates - dates.iloc[0]) / pd.Timedelta(days=1)).to_numpy(float)
        return np.round(sod - sod[0] + 86400.0 * days, 9), 0
    wraps = np.concatenate([[0], np.cumsum(np.diff(sod) < -43200.0)])
    return np.round(sod - sod[0] + 86400.0 * wraps, 9), int(wraps[-1])


def clock_seconds(text: pd.Series, ms_field: bool) -> tuple[np.ndarray, int]:
    """:func:`seconds` of clock texts ``[YYYY-M-D ]h:m:s[.f]``; ``ms_field``: up to 3 digits count ms.

    Parameters
    ----------
    text : pandas.Series
        The clock texts.
    ms_field : bool
        Read a fraction of up to 3 digits as milliseconds.

    Returns
    -------
    seconds : numpy.ndarray
        Time from the first row [s].
    wraps : int
        Midnight wraps of a dateless clock.
    """
    p = text.astype(str).str.extract(CLOCK)
    num = p.iloc[:, :6].apply(pd.to_numeric).to_numpy(float)
    frac = p[6].fillna("").astype(object)
    nd = frac.str.len().to_numpy(int)
    fnum = pd.to_numeric(frac.where(nd > 0, "0")).to_numpy(float)
    frac_s = np.where(ms_field & (nd <= 3), fnum / 1000.0, fnum / 10.0 ** nd)
    return seconds(num[:, :3] if p[0].notna().any() else None, num[:, 3:6], frac_s)


def clock_fields(t: np.ndarray, path: Path, fmt: str) -> pd.DataFrame:
    """Date and clock fields of ``t`` [s] counted from 2000-01-01 00:00:00, to 1 ms.

    Parameters
    ----------
    t : numpy.ndarray
        Times [s] from 2000-01-01 00:00:00, increasing.
    path : Path
        The file written, for errors.
    fmt : str
        The format, for errors.

    Returns
    -------
    pandas.DataFrame
        Columns year, month, day, hour, minute, second, ms.

    Raises
    ------
    LogFormatError
        When samples are less than 1 ms apart.
    """
    ms = np.round(t * 1000.0).astype(np.int64)
    if (np.diff(ms) <= 0).any():
        raise LogFormatError(f"samples less than 1 ms apart; format {fmt!r} stores time to 1 ms",
                             where=str(path))
    d = pd.Series(pd.Timestamp("2000-01-01") + pd.to_timedelta(ms, unit="ms"))
    return pd.DataFrame({k: getattr(d.dt, k) for k in ("year", "month", "day", "hour", "minute", "second")}
                        | {"ms": ms % 1000})


def clock_text(f: pd.DataFrame, style: str) -> pd.Series:
    """``sdk``: `` 2000-1-1 0:0:5.7``; ``clock``: ``00:00:05.007``; ``date``: ``2000-1-1 00:00:05.007``.

    Parameters
    ----------
    f : pandas.DataFrame
        Fields from :func:`clock_fields`.
    style : {"sdk", "clock", "date"}
        The text style.

    Returns
    -------
    pandas.Series
        The texts.
    """
    s = {k: v.astype(str) for k, v in f.items()}
    if style == "sdk":
        return (" " + s["year"] + "-" + s["month"] + "-" + s["day"] + " " + s["hour"] + ":" + s["minute"]
                + ":" + s["second"] + "." + s["ms"])
    clock = (s["hour"].str.zfill(2) + ":" + s["minute"].str.zfill(2) + ":" + s["second"].str.zfill(2) + "."
             + s["ms"].str.zfill(3))
    return clock if style == "clock" else s["year"] + "-" + s["month"] + "-" + s["day"] + " " + clock
