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

from collections.abc import Iterator, Mapping
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

from .._reading import read_bytes
from ..errors import LogFormatError, did_you_mean
from ._log_tables import _KIND_UNITS
from .imu_log import CHANNELS, TEMP, TIME, ImuLog
from .limits import LOG_RATE_HZ, MAX_LOG_BYTES

__all__ = ["CHANNELS", "FORMATS", "TEMP", "TIME", "ImuLog", "detect_format", "read_log", "write_log"]


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
    from . import formats  # imported on use: the layouts (and the plug-ins) load with the first log read

    return formats


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
