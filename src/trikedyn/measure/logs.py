"""Read and write IMU logs; every reader returns an :class:`ImuLog` in SI units.

Formats (keys of :data:`FORMATS`) and their quirks
---------------------------------------------------
``witmotion-sdk``
    Text export of WitMotion's Python SDK: tab-separated, header ``Chiptime ax(g) ... AngleZ(deg) T(°)
    magx ... q4``. The ``°`` is GBK-encoded (bytes A1 E3); lines end in ``\\r\\r\\n``. ``Chiptime`` is
    ``" 2022-7-5 11:58:22.115"``: leading space, no zero padding anywhere, and the millisecond field is a
    count, not a decimal fraction (``.7`` = 7 ms, ``.30`` = 30 ms). The SDK writes one row per received
    packet, so rows repeat a time; only the first row of each time is kept.
``witmotion-pc``
    Older WitMotion PC software, tab-separated: ``time DeviceName ChipTime AccX(g) AccY(g) AccZ(g)
    AsX(°/s) ... AngleX(°) ...``; UTF-8 or GBK. Time comes from ``ChipTime`` (``2023-1-2 10:11:12.345``:
    date unpadded, clock padded) or, if that column is empty, from the PC clock ``time``. Several devices
    may be interleaved; ``sensor=k`` picks the k-th device name in order of appearance.
``witmotion-2025``
    The 2025 PC software's CSV: ``Time, Device name, Chip Time(), Acceleration X(g), ...,
    Angular velocity X(°/s), ..., Angle X(°), ..., Temperature(℃)``; same rules as ``witmotion-pc``.
``wt901sd-binary``
    Raw 11-byte frames as the WT901SD writes them to its card: ``0x55``, type, four little-endian
    int16, checksum (low byte of the sum of the first 10 bytes). 0x51: acceleration raw/32768*16 g and
    temperature/100 °C; 0x52: rate raw/32768*2000 °/s; 0x53: angle raw/32768*180 °; 0x54: magnetometer
    counts; 0x50: chip time YY MM DD hh mm ss ms(uint16). A sample starts at each 0x51 frame (a 0x50
    frame right before a 0x51 belongs to that sample; a sample holding a frame type twice lost its 0x51
    and is dropped). Without 0x50 frames the file stores no time: ``sample_rate_hz`` (10 Hz when not
    given) builds it. After a bad checksum the reader skips to the next valid frame; more than 10 % bad
    frames is an error.
``bwt901cl-csv``
    The CSV of the third-party logger github.com/e-ke/get_bwt901cl_data: ``Time`` as ``HH:MM:SS.fff``,
    then ``AccX1 ... AngZ2`` for two sensors (suffix = sensor) without units: m/s² (the logger used
    g = 9.8, kept as written), °/s and °. The logger writes 0 in every field of a sensor that has not
    reported yet, so leading rows whose acceleration or angle triple is exactly 0 are dropped.
``phyphox``
    The phyphox phone app's CSV export: quoted headers ``"Time (s)","Acceleration x (m/s^2)",...`` (also
    ``Linear Acceleration`` and ``Gyroscope x (rad/s)``), with ``,`` and a decimal point, or ``;`` and a
    decimal comma, or tab; the other rules as ``csv``. Linear acceleration (gravity removed by the phone) is
    read into ``ax..az_mps2`` with a note.
``csv``
    Generic CSV, UTF-8: headers that are SI names are recognised (and ``time_ms``, ``time_us``: time in ms,
    µs); ``columns`` (``--column NAME=HEADER``, ``time_column``/``--time-column``) maps SI names to the
    other headers, ``units`` (``--unit``, ``time_unit``/``--time-unit``) gives the file's units (``g m/s2
    deg/s rad/s deg rad s ms us``). The separator (``,``, ``;`` or tab) is the one that splits the header and
    the first row alike, or ``delimiter``/``--delimiter``; the decimal mark is ``,`` where ``;`` or tab
    separates numbers like ``1,5`` (a European spreadsheet's CSV), or ``decimal``/``--decimal``. Double quotes
    around a header are taken off. Time may be numbers or clock times ``[YYYY-MM-DD ]HH:MM:SS[.fff]``
    (decimal fraction).

Detection (``format="auto"``): a first byte 0x55 with valid frame checksums is ``wt901sd-binary``; else the
header line decides (``Chiptime``, ``DeviceName``, ``Chip Time()``, ``AccX1``, phyphox's ``Time (s)`` with
its acceleration or gyroscope headers), and any other separated header is ``csv``.

Each layout is one module of :mod:`trikedyn.measure.formats` that registers itself there; :data:`FORMATS`,
detection, :func:`read_log` and :func:`write_log` go through that registry, so a new layout is one new
module (or a ``formats.register`` call) and nothing here changes.

Common rules: fields are not quoted (headers may be, in double quotes); lines are counted by ``\\n``; clock
times become seconds from the first row and a clock without a date that jumps back by more than 12 h has
passed midnight; rows that repeat the previous time are dropped (kept the first); time must then increase
strictly.

Bounds (:mod:`trikedyn.measure.limits`): a file of at most 256 MiB; a ``sample_rate_hz`` given by the user
within 0.01 Hz .. 10 kHz. Non-finite data are refused, not dropped: a value that is not a finite number, or
that overflows once converted to SI units (``1e308`` g), or a time that overflows once counted from the
first row, is an error naming the file, the line and the column.
"""

from __future__ import annotations

import csv
import io
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd

from .._reading import read_bytes
from ..errors import LogFormatError, did_you_mean
from ..units import STANDARD_GRAVITY
from .clocktime import clock_seconds
from .limits import LOG_RATE_HZ, MAX_LOG_BYTES

TIME = "time_s"
CHANNELS = ("ax_mps2", "ay_mps2", "az_mps2", "wx_radps", "wy_radps", "wz_radps",
            "roll_rad", "pitch_rad", "yaw_rad")
TEMP = "temperature_degC"
_DEG = np.pi / 180.0
_G = STANDARD_GRAVITY
_UNITS = {"g": _G, "m/s2": 1.0, "deg/s": _DEG, "rad/s": 1.0, "deg": _DEG, "rad": 1.0, "s": 1.0, "ms": 1e-3,
          "us": 1e-6}
_KIND_UNITS = {"mps2": ("m/s2", "g"), "radps": ("rad/s", "deg/s"), "rad": ("rad", "deg"), "s": ("s", "ms", "us")}
_DECIMAL_COMMA = re.compile(r"^[+-]?\d*,\d+(?:[eE][+-]?\d+)?$")
"""A number written with a decimal comma (``-0,25``, ``9,81E0``)."""
_FACTOR = dict.fromkeys(CHANNELS[:3], _G) | dict.fromkeys(CHANNELS[3:], _DEG)  # WitMotion units -> SI

# Headers of each WitMotion text format: time, the 9 channels, temperature.


class _Formats(Mapping):
    """Format key -> one-line description, read live from :mod:`trikedyn.measure.formats`."""

    def __getitem__(self, name: str) -> str:
        try:  # a lookup, not a membership test: a layout installed as a plug-in since is found
            return _registry().get(name).description
        except LogFormatError:
            raise KeyError(name) from None

    def __iter__(self) -> Iterator[str]:
        return iter(_registry().available())

    def __len__(self) -> int:
        return len(_registry().available())

    def __repr__(self) -> str:
        return repr(dict(self))


FORMATS: Mapping[str, str] = _Formats()
"""The registered layouts: key -> description (a live view of :mod:`trikedyn.measure.formats`)."""


def _registry():
    from . import formats  # imported on use: the layouts import this module's helpers

    return formats




def _norm(header: str) -> str:
    """A header reduced for matching: lower case, no spaces, ``°``/``℃`` spelled ``deg``/``degc``."""
    h = re.sub(r"\s+", "", header).lower()
    return h.replace("℃", "degc").replace("°", "deg").replace("º", "deg")



@dataclass(frozen=True, eq=False)
class ImuLog:
    """An IMU log in SI units.

    Attributes
    ----------
    data : pandas.DataFrame
        ``time_s`` [s] first (from the first sample, strictly increasing), then any of ``ax_mps2 ay_mps2
        az_mps2`` [m/s^2], ``wx_radps wy_radps wz_radps`` [rad/s], ``roll_rad pitch_rad yaw_rad`` [rad],
        then extras as the file has them (``temperature_degC`` [°C], ...).
    source : str
        Path of the file read.
    format : str
        A key of :data:`FORMATS`.
    original_columns : dict
        Column of ``data`` -> header (or frame field) in the file.
    notes : tuple of str
        What the reader did that a user should know.
    """

    data: pd.DataFrame
    source: str
    format: str
    original_columns: dict[str, str]
    notes: tuple[str, ...] = ()

    @property
    def sample_rate_hz(self) -> float:
        """Median sample rate [Hz] (NaN with fewer than two samples)."""
        dt = np.diff(self.data[TIME].to_numpy(float))
        return float(np.median(1.0 / dt)) if dt.size else float("nan")

    def to_pandas(self) -> pd.DataFrame:
        """A copy of :attr:`data`.

        Returns
        -------
        pandas.DataFrame
            The copy.
        """
        return self.data.copy()

    def channel(self, name: str) -> np.ndarray:
        """The values of column ``name`` (SI units) as a float array; LogFormatError if absent.

        Parameters
        ----------
        name : str
            A column (``ax_mps2``, ...).

        Returns
        -------
        numpy.ndarray
            Its values, SI units.
        """
        if name not in self.data.columns:
            present = list(self.data.columns)
            raise LogFormatError(f"no channel {name!r}; channels present: {', '.join(present)}"
                                 f"{did_you_mean(name, present)}", where=self.source)
        return self.data[name].to_numpy(dtype=float, copy=True)


# ----------------------------------------------------------------------------------------- helpers
def _read_bytes(path: Path) -> bytes:
    """The log's bytes, by the one bounded reader (:mod:`trikedyn._reading`): a folder, a pipe or a device is
    refused before it is opened, a file over :data:`MAX_LOG_BYTES` unread."""
    limit = MAX_LOG_BYTES

    def too_large(size: int | None) -> str:
        """The message for a file over the bound (``size`` [bytes]; None: it grew while read)."""
        amount = f"{size / 2**20:.0f} MiB, more" if size is not None else "grew while read to more"
        return f"{amount} than the {limit // 2**20} MiB read; cut the log to the part to analyse"

    raw = read_bytes(path, str(path), max_bytes=limit, error=LogFormatError, expected="an IMU log file",
                     missing="file not found; expected an IMU log", too_large=too_large)
    if not raw:
        raise LogFormatError("empty file (0 bytes); expected an IMU log", where=str(path))
    return raw


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

# --------------------------------------------------------------------------------------- public API
def _detect(raw: bytes, path: Path) -> str:
    return _registry().detect(raw, str(path))


def detect_format(path) -> str:
    """The format key of the log at ``path``, sniffed from its first bytes or header line.

    Parameters
    ----------
    path : str or Path
        The log file.

    Returns
    -------
    str
        The format key.

    Raises
    ------
    LogFormatError
        If the file is missing or empty, or no known format fits (the message lists them).
    """
    path = Path(path)
    return _detect(_read_bytes(path), path)

_DELIMITERS = {",": ",", ";": ";", "\t": "\t", "tab": "\t", "\\t": "\t", "comma": ",", "semicolon": ";"}


def _time_options(columns, units, time_column, time_unit, path: Path) -> tuple[dict | None, dict | None]:
    """``columns`` and ``units`` with ``time_column`` and ``time_unit`` folded in under ``time_s``."""
    if time_column is not None:
        if not isinstance(time_column, str) or not time_column.strip():
            raise LogFormatError("time_column= (--time-column) must name a column header", where=str(path))
        if columns and TIME in columns and columns[TIME] != time_column:
            raise LogFormatError(f"time_column={time_column!r} and columns={{'time_s': {columns[TIME]!r}}} name "
                                 "two time columns; give one", where=str(path))
        columns = {**(columns or {}), TIME: time_column.strip()}
    if time_unit is not None:
        allowed = _KIND_UNITS["s"]
        if time_unit not in allowed:
            raise LogFormatError(f"time_unit={time_unit!r} (--time-unit); expected one of {', '.join(allowed)}"
                                 f"{did_you_mean(str(time_unit), allowed)}", where=str(path))
        if units and TIME in units and units[TIME] != time_unit:
            raise LogFormatError(f"time_unit={time_unit!r} and units={{'time_s': {units[TIME]!r}}} disagree",
                                 where=str(path))
        units = {**(units or {}), TIME: time_unit}
    return columns, units


def _separators(delimiter, decimal, path: Path) -> tuple[str | None, str | None]:
    """The field separator and the decimal mark asked for, checked (None: detect)."""
    if delimiter is not None:
        if delimiter not in _DELIMITERS:
            raise LogFormatError(f"delimiter={delimiter!r} (--delimiter); expected ',', ';' or 'tab'",
                                 where=str(path))
        delimiter = _DELIMITERS[delimiter]
    if decimal is not None:
        if decimal not in (".", ","):
            raise LogFormatError(f"decimal={decimal!r} (--decimal); expected '.' or ','", where=str(path))
        if decimal == delimiter:
            raise LogFormatError(f"the decimal mark {decimal!r} is also the delimiter; a decimal-comma file "
                                 "separates its fields with ';' or tab", where=str(path))
    return delimiter, decimal


def read_log(path, format: str = "auto", *, columns: dict[str, str] | None = None, sensor: int = 1,
             sample_rate_hz: float | None = None, units: dict[str, str] | None = None,
             time_column: str | None = None, time_unit: str | None = None, delimiter: str | None = None,
             decimal: str | None = None) -> ImuLog:
    """Read an IMU log into SI units.

    Parameters
    ----------
    path : str or Path
        The log file.
    format : str
        A key of :data:`FORMATS`, or ``"auto"`` to sniff it.
    columns : dict, optional
        ``csv`` only: SI name -> header in the file, e.g. ``{"time_s": "t", "az_mps2": "AccZ"}``.
    sensor : int
        Which sensor (1-based): the suffix of ``bwt901cl-csv`` columns, or the device in order of
        appearance in ``witmotion-pc``/``witmotion-2025``.
    sample_rate_hz : float, optional
        Sample rate [Hz] that builds the time of a file that stores none (``wt901sd-binary`` without 0x50
        frames: 10 Hz when not given; ``csv`` without a time column); noted as ignored otherwise.
    units : dict, optional
        ``csv`` only: SI name -> the file's unit, one of ``g m/s2 deg/s rad/s deg rad s ms us``.
    time_column, time_unit : str, optional
        Table layouts (``csv``, ``phyphox``): the header of the time column (``columns={"time_s": ...}``) and
        its unit, ``s``, ``ms`` or ``us`` (``units={"time_s": ...}``). The command line's ``--time-column``
        and ``--time-unit``.
    delimiter : str, optional
        Table layouts: the field separator, ``","``, ``";"`` or ``"tab"`` (``"\\t"``); detected by default
        (the one that splits the header and the first row alike). ``--delimiter``.
    decimal : str, optional
        Table layouts: the decimal mark, ``"."`` or ``","`` (a European spreadsheet's CSV); detected by
        default (``,`` where ``;`` or tab separates fields holding ``1,5``-like numbers). ``--decimal``.

    Returns
    -------
    ImuLog

    Raises
    ------
    LogFormatError
        For any problem of the file or the arguments; ``where`` names the file and line (or byte).
    """
    path = Path(path)
    if format != "auto" and format not in FORMATS:
        raise LogFormatError(f"unknown format {format!r}; known formats: auto, {', '.join(FORMATS)}"
                             f"{did_you_mean(format, FORMATS)}", where=str(path))
    raw = _read_bytes(path)
    fmt = _detect(raw, path) if format == "auto" else format
    layout = _registry().get(fmt)
    table = {"columns=": columns, "units=": units, "time_column= (--time-column)": time_column,
             "time_unit= (--time-unit)": time_unit, "delimiter= (--delimiter)": delimiter,
             "decimal= (--decimal)": decimal}
    given = [k for k, v in table.items() if v]
    if not layout.takes_columns and given:
        takers = " or ".join(repr(k) for k in FORMATS if _registry().get(k).takes_columns)
        raise LogFormatError(f"{' and '.join(given)} apply to format {takers} only, not {fmt!r}", where=str(path))
    columns, units = _time_options(columns, units, time_column, time_unit, path)
    delimiter, decimal = _separators(delimiter, decimal, path)
    low, high = LOG_RATE_HZ
    if sample_rate_hz is not None and not (np.isfinite(sample_rate_hz) and low <= sample_rate_hz <= high):
        raise LogFormatError(f"sample_rate_hz={sample_rate_hz:g} must lie within {low:g} .. {high:g} Hz",
                             where=str(path))
    if not isinstance(sensor, (int, np.integer)) or sensor < 1:
        raise LogFormatError(f"sensor={sensor!r} must be an integer >= 1", where=str(path))
    options = _registry().ReadOptions(columns=columns, units=units, sensor=sensor, sample_rate_hz=sample_rate_hz,
                                      delimiter=delimiter, decimal=decimal)
    log = layout.read(raw, path, options)
    if sample_rate_hz is not None and TIME in log.original_columns:
        note = f"sample_rate_hz={sample_rate_hz:g} ignored: the file stores time"
        log = replace(log, notes=(*log.notes, note))
    return log


# ------------------------------------------------------------------------------------------ writers
def _extras(data: pd.DataFrame, used) -> dict:
    return {c: data[c].to_numpy() for c in data.columns if c not in used and c != TIME}

def write_log(log: ImuLog | pd.DataFrame, path, format: str = "witmotion-sdk") -> Path:
    """Write a log (SI columns as in :class:`ImuLog`) in one of :data:`FORMATS`.

    WitMotion text formats and ``bwt901cl-csv`` store time to 1 ms as a clock counted from 2000-01-01
    00:00:00 and values as exact decimal text; ``wt901sd-binary`` quantises to one LSB of its int16 fields
    and writes 0x50 chip-time frames; ``csv`` writes the SI columns exactly. Only the channels present are
    written; extra columns are appended (text formats) or dropped (binary keeps temperature and magx..z).

    Parameters
    ----------
    log : ImuLog or pandas.DataFrame
        The log, SI columns.
    path : str or Path
        The file to write.
    format : str
        A writable format.

    Returns
    -------
    Path
        The file written.
    """
    path = Path(path)
    data = log.data if isinstance(log, ImuLog) else log
    if format not in FORMATS:
        raise LogFormatError(f"unknown format {format!r}; known formats: {', '.join(FORMATS)}"
                             f"{did_you_mean(format, FORMATS)}", where=str(path))
    if TIME not in data:
        raise LogFormatError(f"no column 'time_s' to write; columns: {', '.join(map(str, data.columns))}",
                             where=str(path))
    t = data[TIME].to_numpy(float)
    if t.size == 0 or not np.isfinite(t).all() or (np.diff(t) <= 0).any():
        raise LogFormatError("time_s must be finite and strictly increasing, with one row or more",
                             where=str(path))
    _registry().get(format).write(data, path)
    return path
