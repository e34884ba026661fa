"""What the layouts of :mod:`trikedyn.measure.formats` share to read a text table or assemble a log: decoding,
splitting, numbers and clock times checked line by line, repeated times dropped.

Private to the log readers (:mod:`trikedyn.measure.logs` and the layouts); it imports neither, so that the
layouts and the reader that dispatches to them import each other in one direction only.
"""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import LogFormatError
from ..units import STANDARD_GRAVITY
from .clocktime import clock_seconds
from .imu_log import CHANNELS, TIME, ImuLog

_DEG = np.pi / 180.0
_G = STANDARD_GRAVITY
_UNITS = {"g": _G, "m/s2": 1.0, "deg/s": _DEG, "rad/s": 1.0, "deg": _DEG, "rad": 1.0, "s": 1.0, "ms": 1e-3,
          "us": 1e-6}
_KIND_UNITS = {"mps2": ("m/s2", "g"), "radps": ("rad/s", "deg/s"), "rad": ("rad", "deg"), "s": ("s", "ms", "us")}
_DECIMAL_COMMA = re.compile(r"^[+-]?\d*,\d+(?:[eE][+-]?\d+)?$")
"""A number written with a decimal comma (``-0,25``, ``9,81E0``)."""
_FACTOR = dict.fromkeys(CHANNELS[:3], _G) | dict.fromkeys(CHANNELS[3:], _DEG)  # WitMotion units -> SI


def _norm(header: str) -> str:
    """A header reduced for matching: lower case, no spaces, ``°``/``℃`` spelled ``deg``/``degc``."""
    h = re.sub(r"\s+", "", header).lower()
    return h.replace("℃", "degc").replace("°", "deg").replace("º", "deg")


def _decode(raw: bytes, path: Path, encodings: tuple[str, ...]) -> str:
    """Text of ``raw`` in the first encoding that fits; LogFormatError naming the first bad byte."""
    nul = raw.find(b"\x00")
    if nul >= 0:
        raise LogFormatError("binary data (NUL byte) where a text log was expected; a WT901SD card file "
                             "is format 'wt901sd-binary'", where=f"{path}: byte {nul}")
    errors = []
    for enc in encodings:
        try:
            text = raw.decode(enc)
            return text if "\n" in text else text.replace("\r", "\n")
        except UnicodeDecodeError as e:
            errors.append(e)
    off = max(e.start for e in errors)  # the encoding that got furthest points at the real culprit
    line = raw.count(b"\n", 0, off) + 1
    raise LogFormatError(f"invalid byte 0x{raw[off]:02X} at byte {off} for encoding "
                         f"{' or '.join(encodings)}; expected a text log in that encoding",
                         where=f"{path}:{line}")


def _split_table(text: str, sep: str, path: Path) -> tuple[list[str], pd.DataFrame, np.ndarray, str]:
    """Header, cells (numbered columns: numbers, else text), 1-based lines of the rows, header's where."""
    for pad in (" " + sep, sep + " "):  # strip the fields of spaces, all at once
        while pad in text:
            text = text.replace(pad, sep)
    lines = pd.Series(text.split("\n"), dtype=object).str.strip(" \r\t".replace(sep, ""))
    keep = (lines.str.strip() != "").to_numpy()
    if not keep.any():
        raise LogFormatError("holds only blank lines; expected a header and data rows", where=str(path))
    lineno = np.flatnonzero(keep) + 1
    body = lines[keep]
    header = [h.strip().removeprefix('"').removesuffix('"').strip() for h in body.iloc[0].split(sep)]
    rows, lineno, at_header = body.iloc[1:], lineno[1:], f"{path}:{lineno[0]}"
    if rows.empty:
        raise LogFormatError("has a header but no data rows", where=at_header)
    nfields = (rows.str.count(re.escape(sep)) + 1).to_numpy()
    bad = np.flatnonzero(nfields != len(header))
    if bad.size:
        i = bad[0]
        cut = "; the file looks truncated" if i == len(rows) - 1 and nfields[i] < len(header) else ""
        raise LogFormatError(f"row has {nfields[i]} fields but the header has {len(header)}{cut}; expected "
                             f"{len(header)} {'tab' if sep == chr(9) else repr(sep)}-separated fields",
                             where=f"{path}:{lineno[i]}")
    cells = pd.read_csv(io.StringIO("\n".join(rows)), sep=sep, header=None, names=range(len(header)),
                        na_filter=False, quoting=csv.QUOTE_NONE, engine="c", low_memory=False)
    return header, cells, lineno, at_header


def _numbers(cells: pd.Series, name: str, lines: np.ndarray, path: Path, factor: float = 1.0) -> np.ndarray:
    """Finite floats times ``factor``; LogFormatError naming the first bad line and the column."""
    values = pd.to_numeric(cells, errors="coerce").to_numpy(dtype=float)
    with np.errstate(over="ignore"):
        si = values * factor
    bad = np.flatnonzero(~np.isfinite(si))
    if bad.size:
        why = "overflows in SI units" if np.isfinite(values[bad[0]]) else "is not a finite number"
        cell = str(cells.iloc[bad[0]])
        comma = (" (a decimal comma? --decimal , on the command line, decimal=',' in Python)"
                 if _DECIMAL_COMMA.match(cell) else "")
        raise LogFormatError(f"column {name!r} holds {cell!r}, which {why}; expected a number{comma}",
                             where=f"{path}:{lines[bad[0]]}")
    return si


def _extra(cells: pd.Series) -> np.ndarray:
    """An extra column as numbers if every non-empty cell is one, else as text."""
    num = pd.to_numeric(cells, errors="coerce")
    return num.to_numpy(float) if (num.notna() | (cells == "")).all() else cells.to_numpy(object)


def _times(cells: pd.Series, name: str, lines: np.ndarray, path: Path, notes: list[str], *,
           ms_field: bool = False, factor: float = 1.0) -> np.ndarray:
    """Seconds from the first row of a time column holding numbers (times ``factor``) or clock times."""
    numeric = np.isfinite(pd.to_numeric(cells.iloc[:1], errors="coerce").to_numpy(float))[0]
    if numeric:
        with np.errstate(over="ignore", invalid="ignore"):
            t = pd.to_numeric(cells, errors="coerce").to_numpy(float) * factor
            t = t - t[0]  # counted from the first row: a time far from it overflows here
    else:
        t, wraps = clock_seconds(cells, ms_field)
        if wraps:
            notes.append(f"the clock in {name!r} passed midnight {wraps} time(s); counted on")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        what = "a number (finite, counted from the first row)" if numeric else \
            "a clock time [YYYY-MM-DD ]HH:MM:SS[.fff]"
        cell = str(cells.iloc[bad[0]])
        if _DECIMAL_COMMA.match(cell):
            what += " (a decimal comma? --decimal , on the command line, decimal=',' in Python)"
        raise LogFormatError(f"time column {name!r} holds {cell!r}; expected {what}", where=f"{path}:{lines[bad[0]]}")
    return t - t[0]


def _assemble(path: Path, fmt: str, t: np.ndarray, locs: np.ndarray, cols: dict, original: dict,
              notes: list[str], binary: bool = False) -> ImuLog:
    """Drop repeated times, check that time increases, order the columns and build the log."""
    dup = np.concatenate([[False], np.diff(t) == 0])
    if dup.any():
        keep = ~dup
        first = np.flatnonzero(keep)[np.cumsum(keep) - 1]
        differ = [k for k, v in cols.items() if np.any(np.asarray(v)[dup] != np.asarray(v)[first[dup]])]
        differ = f"; they differed in {', '.join(differ)}" if differ else ""
        notes.append(f"dropped {int(dup.sum())} of {t.size} rows that repeat the time of the row before "
                     f"(kept the first of each){differ}")
        t, locs, cols = t[keep], locs[keep], {k: np.asarray(v)[keep] for k, v in cols.items()}
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:
        i = back[0] + 1
        raise LogFormatError(f"time goes backwards: {t[i]:.6g} s after {t[i - 1]:.6g} s; expected time "
                             "increasing from row to row",
                             where=f"{path}: byte {locs[i]}" if binary else f"{path}:{locs[i]}")
    order = [c for c in CHANNELS if c in cols] + [c for c in cols if c not in CHANNELS]
    data = pd.DataFrame({TIME: t - t[0], **{c: cols[c] for c in order}})
    return ImuLog(data, str(path), fmt, dict(original), tuple(notes))


def _table_log(path: Path, fmt: str, t: np.ndarray, header: list[str], cells: pd.DataFrame, lines: np.ndarray,
               spec: dict[str, tuple[int, float]], skip: set[int], notes: list[str]) -> ImuLog:
    """The log of a text table: ``spec`` maps SI name -> (column, factor to SI); other columns are extras."""
    cols = {si: _numbers(cells[j], header[j], lines, path, f) for si, (j, f) in spec.items() if si != TIME}
    used = skip | {j for j, _ in spec.values()}
    extras = [j for j, h in enumerate(header) if j not in used and h and h not in (*spec, TIME)]
    cols |= {header[j]: _extra(cells[j]) for j in extras}
    original = {si: header[j] for si, (j, _) in spec.items()} | {h: h for h in cols if h not in spec}
    return _assemble(path, fmt, t, lines, cols, original, notes)


def _one_sensor(sensor: int, fmt: str, path: Path) -> None:
    if sensor != 1:
        raise LogFormatError(f"sensor={sensor} but format {fmt!r} holds one sensor; expected sensor=1",
                             where=str(path))


def _extras(data: pd.DataFrame, used) -> dict:
    return {c: data[c].to_numpy() for c in data.columns if c not in used and c != TIME}
