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
``csv``
    Generic CSV (``,``, ``;`` or tab), UTF-8: ``columns`` maps SI names to headers, ``units`` gives the
    file's units (``g m/s2 deg/s rad/s deg rad s ms``); headers that are SI names are recognised. Time may
    be numbers or clock times ``[YYYY-MM-DD ]HH:MM:SS[.fff]`` (decimal fraction).

Detection (``format="auto"``): a first byte 0x55 with valid frame checksums is ``wt901sd-binary``; else the
header line decides (``Chiptime``, ``DeviceName``, ``Chip Time()``, ``AccX1``), and any other separated
header is ``csv``.

Common rules: fields are not quoted; lines are counted by ``\\n``; clock times become seconds from the
first row and a clock without a date that jumps back by more than 12 h has passed midnight; rows that
repeat the previous time are dropped (kept the first); time must then increase strictly.

Bounds (:mod:`trikedyn.measure.limits`): a file of at most 256 MiB; a ``sample_rate_hz`` given by the user
within 0.01 Hz .. 10 kHz. Non-finite data are refused, not dropped: a value that is not a finite number, or
that overflows once converted to SI units (``1e308`` g), or a time that overflows once counted from the
first row, is an error naming the file, the line and the column.
"""

from __future__ import annotations

import csv
import difflib
import io
import re
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import LogFormatError
from ..units import STANDARD_GRAVITY
from .clocktime import clock_fields, clock_seconds, clock_text, seconds
from .limits import LOG_RATE_HZ, MAX_LOG_BYTES

__all__ = ["CHANNELS", "FORMATS", "ImuLog", "detect_format", "read_log", "write_log"]

FORMATS: dict[str, str] = {
    "witmotion-sdk": "WitMotion Python SDK text export (tab-separated, GBK, one row per packet)",
    "witmotion-pc": "older WitMotion PC software export (tab-separated: time DeviceName ChipTime AccX(g)..)",
    "witmotion-2025": "WitMotion PC software 2025 CSV (Time, Device name, Chip Time(), Acceleration X(g)..)",
    "wt901sd-binary": "raw 11-byte 0x55 WIT frames as the WT901SD logger writes them to its card",
    "bwt901cl-csv": "get_bwt901cl_data logger CSV (Time HH:MM:SS.fff, AccX1 .. AngZ2 in m/s2, deg/s, deg)",
    "csv": "generic CSV; columns= maps SI names to headers, units= gives the file's units",
}

TIME = "time_s"
CHANNELS = ("ax_mps2", "ay_mps2", "az_mps2", "wx_radps", "wy_radps", "wz_radps",
            "roll_rad", "pitch_rad", "yaw_rad")
TEMP = "temperature_degC"
_DEG = np.pi / 180.0
_G = STANDARD_GRAVITY
_UNITS = {"g": _G, "m/s2": 1.0, "deg/s": _DEG, "rad/s": 1.0, "deg": _DEG, "rad": 1.0, "s": 1.0, "ms": 1e-3}
_KIND_UNITS = {"mps2": ("m/s2", "g"), "radps": ("rad/s", "deg/s"), "rad": ("rad", "deg"), "s": ("s", "ms")}
_FACTOR = dict.fromkeys(CHANNELS[:3], _G) | dict.fromkeys(CHANNELS[3:], _DEG)  # WitMotion units -> SI

# Headers of each WitMotion text format: time, the 9 channels, temperature.
_WIT_HEADERS = {
    "witmotion-sdk": ["Chiptime", *(f"a{c}(g)" for c in "xyz"), *(f"w{c}(deg/s)" for c in "xyz"),
                      *(f"Angle{c}(deg)" for c in "XYZ"), "T(°)"],
    "witmotion-pc": ["ChipTime", *(f"Acc{c}(g)" for c in "XYZ"), *(f"As{c}(°/s)" for c in "XYZ"),
                     *(f"Angle{c}(°)" for c in "XYZ"), "T(°C)"],
    "witmotion-2025": ["Chip Time()", *(f"Acceleration {c}(g)" for c in "XYZ"),
                       *(f"Angular velocity {c}(°/s)" for c in "XYZ"), *(f"Angle {c}(°)" for c in "XYZ"),
                       "Temperature(℃)"],
}
_WIT_PC_COLUMNS = {"witmotion-pc": ("time", "DeviceName"), "witmotion-2025": ("Time", "Device name")}
_WIT_SEP = {"witmotion-sdk": "\t", "witmotion-pc": "\t", "witmotion-2025": ","}
_BWT = {"Acc": CHANNELS[0:3], "AngVel": CHANNELS[3:6], "Ang": CHANNELS[6:9]}
_BIN_SCALE = {0x51: 16.0 / 32768 * _G, 0x52: 2000.0 / 32768 * _DEG, 0x53: 180.0 / 32768 * _DEG}
_BIN_CHANNELS = {0x51: CHANNELS[0:3], 0x52: CHANNELS[3:6], 0x53: CHANNELS[6:9],
                 0x54: ("magx", "magy", "magz")}


def _norm(header: str) -> str:
    """A header reduced for matching: lower case, no spaces, ``°``/``℃`` spelled ``deg``/``degc``."""
    h = re.sub(r"\s+", "", header).lower()
    return h.replace("℃", "degc").replace("°", "deg").replace("º", "deg")


def _hint(name: str, choices) -> str:
    close = difflib.get_close_matches(name, list(choices), n=1)
    return f"; did you mean {close[0]!r}?" if close else ""


_WIT_LOOKUP = {_norm(h): si for hs in _WIT_HEADERS.values() for h, si in zip(hs, (TIME, *CHANNELS, TEMP), strict=False)}


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
        """A copy of :attr:`data`."""
        return self.data.copy()

    def channel(self, name: str) -> np.ndarray:
        """The values of column ``name`` (SI units) as a float array; LogFormatError if absent."""
        if name not in self.data.columns:
            present = list(self.data.columns)
            raise LogFormatError(f"no channel {name!r}; channels present: {', '.join(present)}"
                                 f"{_hint(name, present)}", where=self.source)
        return self.data[name].to_numpy(dtype=float, copy=True)


# ----------------------------------------------------------------------------------------- helpers
def _read_bytes(path: Path) -> bytes:
    if not path.exists():
        raise LogFormatError("file not found; expected an IMU log", where=str(path))
    if not path.is_file():
        raise LogFormatError("is not a file; expected an IMU log file", where=str(path))
    size = path.stat().st_size
    if size > MAX_LOG_BYTES:
        raise LogFormatError(f"{size / 2**20:.0f} MiB, more than the {MAX_LOG_BYTES // 2**20} MiB read; cut the "
                             "log to the part to analyse", where=str(path))
    raw = path.read_bytes()
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
    header = [h.strip() for h in body.iloc[0].split(sep)]
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
        raise LogFormatError(f"column {name!r} holds {str(cells.iloc[bad[0]])!r}, which {why}; expected a "
                             "number", where=f"{path}:{lines[bad[0]]}")
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
        raise LogFormatError(f"time column {name!r} holds {str(cells.iloc[bad[0]])!r}; expected {what}",
                             where=f"{path}:{lines[bad[0]]}")
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


# ------------------------------------------------------------------------------------------ readers
def _read_witmotion(raw: bytes, path: Path, fmt: str, sensor: int, notes: list[str]) -> ImuLog:
    text = _decode(raw, path, ("utf-8-sig", "gb18030"))
    header, cells, lines, at_header = _split_table(text, _WIT_SEP[fmt], path)
    norm = [_norm(h) for h in header]
    spec: dict[str, tuple[int, float]] = {}
    for j, key in enumerate(norm):
        if key in _WIT_LOOKUP:
            spec.setdefault(_WIT_LOOKUP[key], (j, _FACTOR.get(_WIT_LOOKUP[key], 1.0)))
    pc = {k: norm.index(k) for k in ("time", "devicename") if k in norm}
    if TIME not in spec or (cells[spec[TIME][0]] == "").all():
        if "time" not in pc:
            raise LogFormatError(f"no time column; columns present: {', '.join(header)}; expected "
                                 f"{_WIT_HEADERS[fmt][0]!r}", where=at_header)
        if TIME in spec:
            notes.append(f"{header[spec[TIME][0]]!r} is empty; time from the PC clock {header[pc['time']]!r}")
        spec[TIME] = (pc["time"], 1.0)
    if "devicename" in pc:
        dev = cells[pc["devicename"]]
        names = [str(d) for d in pd.unique(dev)]
        if not 1 <= sensor <= len(names):
            raise LogFormatError(f"sensor={sensor} but the file holds {len(names)} device(s): "
                                 f"{', '.join(names)}", where=str(path))
        if len(names) > 1:
            notes.append(f"the file holds {len(names)} devices ({', '.join(names)}); read sensor={sensor}: "
                         f"{names[sensor - 1]!r}")
            rows = (dev.astype(str) == names[sensor - 1]).to_numpy()
            cells, lines = cells[rows].reset_index(drop=True), lines[rows]
    else:
        _one_sensor(sensor, fmt, path)
    j = spec[TIME][0]
    t = _times(cells[j], header[j], lines, path, notes, ms_field=True)
    return _table_log(path, fmt, t, header, cells, lines, spec, set(pc.values()), notes)


def _read_bwt(raw: bytes, path: Path, sensor: int, notes: list[str]) -> ImuLog:
    header, cells, lines, at_header = _split_table(_decode(raw, path, ("utf-8-sig",)), ",", path)
    sensors = sorted({int(m[1]) for h in header if (m := re.fullmatch(r"AccX(\d+)", h))})
    if sensor not in sensors:
        raise LogFormatError(f"sensor={sensor} but the file has columns for sensor(s) "
                             f"{', '.join(map(str, sensors)) or 'none'}; expected AccX{sensor}",
                             where=at_header)
    want = {"Time": TIME} | {f"{p}{c}{sensor}": si for p, sis in _BWT.items() for c, si in zip("XYZ", sis, strict=False)}
    missing = [h for h in want if h not in header]
    if missing:
        raise LogFormatError(f"no column {', '.join(missing)}; columns present: {', '.join(header)}",
                             where=at_header)
    spec = {si: (header.index(h), 1.0 if si in CHANNELS[:3] else _DEG) for h, si in want.items()}
    zero = [np.all([pd.to_numeric(cells[spec[c][0]], errors="coerce") == 0 for c in g], axis=0)
            for g in (CHANNELS[0:3], CHANNELS[6:9])]
    n = int(np.cumprod(zero[0] | zero[1]).sum())
    if n == len(lines):
        raise LogFormatError(f"sensor {sensor} never reported: its acceleration or angle fields are 0 in "
                             "every row", where=str(path))
    t = _times(cells[spec[TIME][0]], "Time", lines, path, notes)
    if n:
        notes.append(f"dropped the first {n} row(s): sensor {sensor} had not reported yet (the logger writes "
                     f"0 until then); time_s starts {t[n]:.3f} s after the file's first row")
    notes.append("accelerations kept in m/s2 as the logger wrote them: g x 9.8, 0.07 % below g x 9.80665")
    others = {j for j, h in enumerate(header) if re.fullmatch(r"(Acc|AngVel|Ang)[XYZ]\d+", h)}
    cells = cells.iloc[n:].reset_index(drop=True)
    return _table_log(path, "bwt901cl-csv", t[n:], header, cells, lines[n:], spec, others, notes)


def _read_csv(raw: bytes, path: Path, columns: dict | None, units: dict | None, rate: float | None,
              notes: list[str]) -> ImuLog:
    text = _decode(raw, path, ("utf-8-sig",))
    head = next((line for line in text.split("\n") if line.strip()), "")
    header, cells, lines, at_header = _split_table(text, next((s for s in ",\t;" if s in head), ","), path)
    known = (TIME, *CHANNELS, TEMP)
    mapping = {h: h for h in header if h in known}
    for si, h in (columns or {}).items():
        if si not in known:
            raise LogFormatError(f"columns= maps unknown name {si!r}; expected one of {', '.join(known)}"
                                 f"{_hint(si, known)}", where=str(path))
        if h not in header:
            raise LogFormatError(f"columns= names column {h!r} (for {si}) which is not in the file; columns "
                                 f"present: {', '.join(header)}{_hint(h, header)}", where=at_header)
        mapping[si] = h
    spec = {si: (header.index(h), 1.0) for si, h in mapping.items()}
    for si, unit in (units or {}).items():
        u = unit.strip().lower().replace("^2", "2").replace("²", "2").replace("°", "deg")
        allowed = _KIND_UNITS.get(si.rsplit("_", 1)[-1], ())
        if si not in spec or u not in allowed:
            raise LogFormatError(f"units= gives {unit!r} for {si!r}; expected a column mapped to {si!r} "
                                 f"(mapped: {', '.join(spec)}) and one of {', '.join(allowed) or 'no unit'}",
                                 where=str(path))
        spec[si] = (spec[si][0], _UNITS[u])
    if TIME in spec:
        t = _times(cells[spec[TIME][0]], mapping[TIME], lines, path, notes, factor=spec[TIME][1])
    elif rate is not None:
        t = np.arange(len(lines)) / rate
        notes.append(f"the file has no time column: time built from sample_rate_hz={rate:g}")
    else:
        raise LogFormatError(f"no time column; columns present: {', '.join(header)}; expected a column "
                             "'time_s', or columns={'time_s': <header>}, or sample_rate_hz=", where=at_header)
    return _table_log(path, "csv", t, header, cells, lines, spec, set(), notes)


def _valid_starts(b: np.ndarray) -> np.ndarray:
    """For every offset, whether a frame with a WIT type (0x50-0x5F) and a good checksum starts there."""
    m = b.size - 10
    if m <= 0:
        return np.zeros(0, bool)
    c = np.concatenate([[0], np.cumsum(b, dtype=np.int64)])
    return (b[:m] == 0x55) & ((b[1:m + 1] & 0xF0) == 0x50) & (((c[10:10 + m] - c[:m]) & 0xFF) == b[10:10 + m])


def _scan_frames(b: np.ndarray, path: Path, notes: list[str]) -> np.ndarray:
    """Offsets of the good frames; after a bad one, skip to the next valid 0x55 and count the frames lost."""
    ok = _valid_starts(b)
    valid = np.flatnonzero(ok)
    starts, pos, bad, first_bad = [], 0, 0, None
    while pos <= b.size - 11:
        run = ok[pos::11][:4096]  # a run of good frames, taken in blocks
        good = run.size if run.all() else int(np.argmin(run))
        if good:
            starts.append(np.arange(pos, pos + 11 * good, 11))
            pos += 11 * good
            continue
        k = np.searchsorted(valid, pos)
        nxt = int(valid[k]) if k < valid.size else b.size
        first_bad = pos if first_bad is None else first_bad
        bad += max(1, round((nxt - pos) / 11))
        pos = nxt
    starts = np.concatenate(starts) if starts else np.zeros(0, np.int64)
    if bad > 0.1 * (starts.size + bad):
        raise LogFormatError(f"{bad} of about {starts.size + bad} frames are bad (more than 10 %); expected "
                             "11-byte frames: 0x55, type, 8 data bytes, checksum = low byte of the sum "
                             "of the first 10", where=f"{path}: byte {first_bad}")
    if bad:
        notes.append(f"skipped {bad} bad frame(s) (checksum or sync), the first at byte {first_bad}")
    if pos < b.size:
        notes.append(f"ignored {b.size - pos} byte(s) at the end of the file (a partial frame)")
    return starts


def _read_binary(raw: bytes, path: Path, rate: float | None, notes: list[str]) -> ImuLog:
    b = np.frombuffer(raw, np.uint8)
    starts = _scan_frames(b, path, notes)
    frames = b[starts[:, None] + np.arange(11)] if starts.size else np.zeros((0, 11), np.uint8)
    types = frames[:, 1]
    sid = np.cumsum(types == 0x51) - 1
    sid[:-1] += (types[:-1] == 0x50) & (types[1:] == 0x51)  # a chip time right before 0x51 is that sample's
    n = int((types == 0x51).sum())
    if n == 0:
        raise LogFormatError("no complete sample: no 0x51 acceleration frame; expected WT901SD frames",
                             where=f"{path}: byte 0")
    words = np.ascontiguousarray(frames[:, 2:10]).view("<i2").astype(float)
    cols, original, have = {}, {}, np.ones(n, bool)
    key, counts = np.unique(sid[sid >= 0] * 256 + types[sid >= 0], return_counts=True)
    have[key[counts > 1] // 256] = False  # a type twice in one sample: its 0x51 was lost; do not mix samples
    for typ, names in _BIN_CHANNELS.items():
        sel = (types == typ) & (sid >= 0)
        if sel.any():
            arr = np.full((n, 4), np.nan)
            arr[sid[sel]] = words[sel]
            have &= ~np.isnan(arr[:, 0]) | (typ == 0x54)  # the magnetometer is an extra a sample may lack
            cols |= {name: arr[:, k] * _BIN_SCALE.get(typ, 1.0) for k, name in enumerate(names)}
            original |= {name: f"0x{typ:02X} word {k}" for k, name in enumerate(names)}
            if typ == 0x51:
                cols[TEMP], original[TEMP] = arr[:, 3] / 100.0, "0x51 word 3"
    sel = (types == 0x50) & (sid >= 0)
    fields = np.full((n, 7), np.nan)
    if sel.any():
        fields[sid[sel]] = np.column_stack([frames[sel, 2:8], frames[sel, 8] + 256.0 * frames[sel, 9]])
        have &= ~np.isnan(fields[:, 0])
    if not have.all():
        notes.append(f"dropped {int((~have).sum())} incomplete sample(s) (a frame missing or repeated)")
    if not have.any():
        raise LogFormatError("no complete sample: every sample misses a frame", where=f"{path}: byte 0")
    locs, cols = starts[types == 0x51][have], {k: v[have] for k, v in cols.items()}
    if sel.any():
        f = fields[have]
        t, _ = seconds(f[:, :3] + [2000, 0, 0], f[:, 3:6], f[:, 6] / 1000.0)
        if np.isnan(t).any():  # a chip whose date was never set: use the clock alone
            t, wraps = seconds(None, f[:, 3:6], f[:, 6] / 1000.0)
            notes.append(f"0x50 chip-time dates are not valid; used the clock alone ({wraps} midnight(s))")
        bad = np.flatnonzero(np.isnan(t))
        if bad.size:
            raise LogFormatError("0x50 chip time is not a valid clock; expected hh < 24, mm < 60, ss < 60",
                                 where=f"{path}: byte {locs[bad[0]]}")
        original[TIME] = "0x50 chip time"
    else:
        t = np.arange(have.sum()) / (rate or 10.0)
        notes.append(f"the file stores no time (no 0x50 frames): time built from sample_rate_hz="
                     f"{rate or 10.0:g}" + ("" if rate else " (assumed: pass sample_rate_hz= to set it)"))
    return _assemble(path, "wt901sd-binary", t, locs, cols, original, notes, binary=True)


# --------------------------------------------------------------------------------------- public API
def _detect(raw: bytes, path: Path) -> str:
    ok = _valid_starts(np.frombuffer(raw[:4096], np.uint8))
    if raw[0] == 0x55 and ok.size and all(ok[i] for i in range(0, min(ok.size, 34), 11)):
        return "wt901sd-binary"
    known = f"known formats: {', '.join(FORMATS)}"
    if b"\x00" in raw[:4096]:
        raise LogFormatError(f"binary data that are not 0x55 WIT frames; cannot detect the format ({known})",
                             where=str(path))
    text = raw[:4096].decode("utf-8", errors="replace").lstrip("\ufeff")
    first = next((line for line in text.replace("\r", "\n").split("\n") if line.strip()), "")
    sep = next((s for s in "\t,;" if s in first), None)
    keys = {_norm(h) for h in first.split(sep)} if sep else set()
    for fmt, need in (("witmotion-pc", {"devicename", "chiptime"}), ("witmotion-sdk", {"chiptime"}),
                      ("witmotion-2025", {"devicename", "chiptime()"}), ("bwt901cl-csv", {"time", "accx1"})):
        if need <= keys:
            return fmt
    if sep:
        return "csv"
    raise LogFormatError(f"cannot detect the format from the first line {first[:60]!r}; {known}",
                         where=str(path))


def detect_format(path) -> str:
    """The format key of the log at ``path``, sniffed from its first bytes or header line.

    Raises
    ------
    LogFormatError
        If the file is missing or empty, or no known format fits (the message lists them).
    """
    path = Path(path)
    return _detect(_read_bytes(path), path)


def read_log(path, format: str = "auto", *, columns: dict[str, str] | None = None, sensor: int = 1,
             sample_rate_hz: float | None = None, units: dict[str, str] | None = None) -> ImuLog:
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
        ``csv`` only: SI name -> the file's unit, one of ``g m/s2 deg/s rad/s deg rad s ms``.

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
                             f"{_hint(format, FORMATS)}", where=str(path))
    raw = _read_bytes(path)
    fmt = _detect(raw, path) if format == "auto" else format
    if fmt != "csv" and (columns or units):
        raise LogFormatError(f"columns= and units= apply to format 'csv' only, not {fmt!r}", where=str(path))
    low, high = LOG_RATE_HZ
    if sample_rate_hz is not None and not (np.isfinite(sample_rate_hz) and low <= sample_rate_hz <= high):
        raise LogFormatError(f"sample_rate_hz={sample_rate_hz:g} must lie within {low:g} .. {high:g} Hz",
                             where=str(path))
    if not isinstance(sensor, (int, np.integer)) or sensor < 1:
        raise LogFormatError(f"sensor={sensor!r} must be an integer >= 1", where=str(path))
    if fmt in _WIT_HEADERS:
        log = _read_witmotion(raw, path, fmt, sensor, [])
    elif fmt == "bwt901cl-csv":
        log = _read_bwt(raw, path, sensor, [])
    else:
        _one_sensor(sensor, fmt, path)
        log = (_read_csv(raw, path, columns, units, sample_rate_hz, []) if fmt == "csv"
               else _read_binary(raw, path, sample_rate_hz, []))
    if sample_rate_hz is not None and TIME in log.original_columns:
        note = f"sample_rate_hz={sample_rate_hz:g} ignored: the file stores time"
        log = replace(log, notes=(*log.notes, note))
    return log


# ------------------------------------------------------------------------------------------ writers
def _extras(data: pd.DataFrame, used) -> dict:
    return {c: data[c].to_numpy() for c in data.columns if c not in used and c != TIME}


def _write_witmotion(data: pd.DataFrame, path: Path, fmt: str) -> None:
    f = clock_fields(data[TIME].to_numpy(float), path, fmt)
    out = {}
    if fmt in _WIT_PC_COLUMNS:
        pc_time, device = _WIT_PC_COLUMNS[fmt]
        out[pc_time] = clock_text(f, "clock" if fmt == "witmotion-pc" else "date")
        out[device] = "trikedyn"
    out[_WIT_HEADERS[fmt][0]] = clock_text(f, "sdk" if fmt == "witmotion-sdk" else "date")
    for si, h in zip((*CHANNELS, TEMP), _WIT_HEADERS[fmt][1:], strict=False):
        if si in data:
            out[h] = data[si].to_numpy(float) / _FACTOR.get(si, 1.0)
    sdk = fmt == "witmotion-sdk"
    pd.DataFrame(out | _extras(data, (*CHANNELS, TEMP))).to_csv(
        path, sep=_WIT_SEP[fmt], index=False, encoding="gbk" if sdk else "utf-8",
        lineterminator="\r\r\n" if sdk else "\n")


def _write_bwt(data: pd.DataFrame, path: Path) -> None:
    out = {"Time": clock_text(clock_fields(data[TIME].to_numpy(float), path, "bwt901cl-csv"), "clock")}
    for prefix, sis in _BWT.items():
        for c, si in zip("XYZ", sis, strict=False):
            if si in data:
                out[f"{prefix}{c}1"] = data[si].to_numpy(float) / (1.0 if prefix == "Acc" else _DEG)
    pd.DataFrame(out | _extras(data, CHANNELS)).to_csv(path, index=False)


def _write_binary(data: pd.DataFrame, path: Path) -> None:
    n = len(data)
    f = clock_fields(data[TIME].to_numpy(float), path, "wt901sd-binary")
    temp = np.round(data[TEMP].to_numpy(float) * 100) if TEMP in data else np.zeros(n)
    ms = f["ms"].to_numpy()
    payloads = {0x50: np.column_stack([f["year"] - 2000, f["month"], f["day"], f["hour"], f["minute"],
                                       f["second"], ms & 0xFF, ms >> 8]).astype(np.uint8)}
    for typ, names in _BIN_CHANNELS.items():
        present = [c for c in names if c in data]
        if len(present) < (3 if typ == 0x51 else 1 if present else 0) or 0 < len(present) < 3:
            raise LogFormatError(f"format 'wt901sd-binary' stores {', '.join(names)} together (and needs the "
                                 f"0x51 acceleration); the log has {', '.join(present) or 'none'}",
                                 where=str(path))
        if present:
            scale = _BIN_SCALE.get(typ, 1.0)
            raw = np.column_stack([np.round(data[c].to_numpy(float) / scale) for c in names])
            raw = (raw + 32768) % 65536 - 32768 if typ == 0x53 else raw  # angles wrap at +-180 deg
            raw = np.column_stack([raw, temp])
            if (np.abs(raw + 0.5) > 32768).any() or np.isnan(raw).any():
                raise LogFormatError(f"a value of {', '.join(names)} or {TEMP} is outside the int16 range of "
                                     "format 'wt901sd-binary'", where=str(path))
            payloads[typ] = raw.astype("<i2").view(np.uint8).reshape(n, 8)
    frames = np.zeros((n, len(payloads), 11), np.uint8)
    for k, (typ, payload) in enumerate(payloads.items()):
        frames[:, k, 0], frames[:, k, 1], frames[:, k, 2:10] = 0x55, typ, payload
        frames[:, k, 10] = frames[:, k, :10].sum(axis=1, dtype=np.int64) & 0xFF
    path.write_bytes(frames.tobytes())


def write_log(log: ImuLog | pd.DataFrame, path, format: str = "witmotion-sdk") -> Path:
    """Write a log (SI columns as in :class:`ImuLog`) in one of :data:`FORMATS`.

    WitMotion text formats and ``bwt901cl-csv`` store time to 1 ms as a clock counted from 2000-01-01
    00:00:00 and values as exact decimal text; ``wt901sd-binary`` quantises to one LSB of its int16 fields
    and writes 0x50 chip-time frames; ``csv`` writes the SI columns exactly. Only the channels present are
    written; extra columns are appended (text formats) or dropped (binary keeps temperature and magx..z).

    Returns
    -------
    Path
        The file written.
    """
    path = Path(path)
    data = log.data if isinstance(log, ImuLog) else log
    if format not in FORMATS:
        raise LogFormatError(f"unknown format {format!r}; known formats: {', '.join(FORMATS)}"
                             f"{_hint(format, FORMATS)}", where=str(path))
    if TIME not in data:
        raise LogFormatError(f"no column 'time_s' to write; columns: {', '.join(map(str, data.columns))}",
                             where=str(path))
    t = data[TIME].to_numpy(float)
    if t.size == 0 or not np.isfinite(t).all() or (np.diff(t) <= 0).any():
        raise LogFormatError("time_s must be finite and strictly increasing, with one row or more",
                             where=str(path))
    if format in _WIT_HEADERS:
        _write_witmotion(data, path, format)
    elif format == "bwt901cl-csv":
        _write_bwt(data, path)
    elif format == "wt901sd-binary":
        _write_binary(data, path)
    else:
        data.to_csv(path, index=False)
    return path
