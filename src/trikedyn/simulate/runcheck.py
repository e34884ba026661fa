"""Run files read back and checked once, where they are read, so that every reader -- ``trikedyn plot``,
``trikedyn animate``, ``trikedyn compare``, the report's figures -- gets a table it can use, and a user's mistake
is one :class:`~trikedyn.errors.InputError` naming the file, the column or field and the row.

:func:`read_run` reads a run file (:func:`read_run_table`, :func:`check_run_table`) and its metadata
(:func:`run_meta`, :func:`check_meta`):

* the files are read by the one bounded reader (:mod:`trikedyn._reading`): a folder, a pipe or a device is
  refused unopened; the table at most :data:`MAX_RUN_BYTES`, the sidecar at most :data:`MAX_SIDECAR_BYTES`;
  a Parquet file's size once decompressed, from its own footer, is bounded before it is decoded;
* the table: at most :data:`MAX_RUN_ROWS` rows, :data:`MAX_RUN_COLUMNS` columns and :data:`MAX_WHEELS` wheel
  loads (``<wheel>_fz_N``), at least 2 rows; a ``time_s`` column [s] (or index) finite and strictly
  increasing, spanning at most :data:`MAX_RUN_ROWS` of its median steps (no gap that would make a resampled
  grid huge: ``compare`` resamples at 10 times the median rate); every column numbers (returned as float64),
  none infinite or beyond +-:data:`MAX_ABS_VALUE` (NaN is kept: a value undefined at that sample, as RI with
  both wheels of the pair off the ground); read as a run, its time spans at most :data:`MAX_RUN_S` (the
  longest manoeuvre);
* the metadata (the sidecar's and a Parquet file's own, the latter taking precedence): each field trikedyn
  reads has its type and range (:func:`check_meta`); fields it does not read are left alone. A sidecar that
  is there but cannot be read (not a regular file, too large, not UTF-8 JSON, not an object) is refused: move
  it away to read the table alone.

Writing a run and rebuilding its vehicle and course: :mod:`trikedyn.simulate.runfile`.
"""

from __future__ import annotations

import io
import json
import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError
from ..manoeuvres.base import MAX_DURATION_S

__all__ = ["MAX_ABS_VALUE", "MAX_RUN_BYTES", "MAX_RUN_COLUMNS", "MAX_RUN_ROWS", "MAX_RUN_S", "MAX_SIDECAR_BYTES",
           "MAX_TEXT_CHARS", "MAX_WHEELS", "READ_FROM", "RUN_SUFFIXES", "RunFile", "check_meta", "check_run_table",
           "read_run", "read_run_table", "run_meta"]

MAX_SIDECAR_BYTES = 16 * 2**20
"""Largest ``.json`` sidecar read [bytes]: a run's is a few kB; a bigger one is refused unread."""
MAX_RUN_BYTES = 256 * 2**20
"""Largest run table read [bytes] (a run of an hour at 100 Hz is about 60 MiB of Parquet)."""
MAX_RUN_ROWS = 1_000_000
"""Most rows of a run table (an hour at 100 Hz is 360,001)."""
MAX_RUN_COLUMNS = 1000
"""Most columns of a run table (a three-wheeler's run has about 70)."""
MAX_WHEELS = 8
"""Most wheel loads (``<wheel>_fz_N`` columns) of a run."""
MAX_ABS_VALUE = 1e12
"""Largest magnitude of a value in a run table: nothing a run records comes near it (forces are kN, times
hours)."""
MAX_RUN_S = MAX_DURATION_S
"""Longest time span of a run [s]: the longest manoeuvre (:data:`trikedyn.manoeuvres.base.MAX_DURATION_S`)."""
MAX_TEXT_CHARS = 200
"""Longest text field of the metadata (a vehicle's or manoeuvre's name) [characters]."""
RUN_SUFFIXES = (".parquet", ".pq", ".csv")
"""File name endings of a run table."""
TIME = "time_s"
_MAX_DECODED_BYTES = 4 * MAX_RUN_BYTES  # a Parquet file's data once decompressed, from its own footer
READ_FROM = "read_from"
"""The key :func:`run_meta` sets to the run file it read (the folder a path CSV of the record is in)."""


# ------------------------------------------------------------------------------------------------------------
# reading a run back: the table
# ------------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RunFile:
    """A run file read back and checked (:func:`read_run`).

    Attributes
    ----------
    table : pandas.DataFrame
        ``time_s`` [s] first, then every channel, all float64 (:func:`check_run_table`).
    meta : dict
        The run's metadata, checked (:func:`check_meta`).
    kind : str
        ``"run-parquet"`` or ``"run-csv"``.
    path : Path
        The table's file.
    """

    table: object
    meta: dict
    kind: str
    path: Path


def read_run(path) -> RunFile:
    """A run file written by ``trikedyn simulate --out``: its table and metadata, read and checked once.

    Parameters
    ----------
    path : str or Path
        The run's table (``.parquet``, ``.pq`` or ``.csv``); its ``.json`` sidecar is read when it is there.

    Returns
    -------
    RunFile

    Raises
    ------
    InputError
        Another suffix; the file is missing, not a regular file, too large or unreadable; the table or the
        metadata fails a check of the module docstring (naming the column or field and the row).
    """
    path = Path(path)
    if path.suffix.lower() not in RUN_SUFFIXES:
        raise InputError("expected a run file (.parquet or .csv) written by `trikedyn simulate --out`",
                         where=str(path))
    table, kind = read_run_table(path)
    return RunFile(table, run_meta(path, table.attrs), kind, path)


def read_run_table(path, *, as_run: bool = True):
    """The table of a run file, read by the bounded reader and checked by :func:`check_run_table`.

    Parameters
    ----------
    path : str or Path
        ``.parquet``/``.pq``: Parquet; anything else: CSV (``,``, ``;`` or tab) with ``time_s`` in its header.
    as_run : bool
        True: the file must be a run (a CSV without a numeric ``time_s`` column is refused) and its time span
        is bounded by :data:`MAX_RUN_S`. False (:func:`trikedyn.analysis.compare.load_table`): a CSV
        without ``time_s`` in its header, or whose ``time_s`` is not numbers (clock times), gives None (it
        may be an IMU log), and the span is not bounded.

    Returns
    -------
    (pandas.DataFrame, str) or None
        The checked table (the Parquet file's own metadata in ``.attrs``) and ``"run-parquet"`` or
        ``"run-csv"``.

    Raises
    ------
    InputError
        As :func:`read_run`.
    """
    from .._reading import read_bytes

    path = Path(path)
    where = str(path)
    parquet = path.suffix.lower() in (".parquet", ".pq")
    missing = ("file not found; expected a run file written by `trikedyn simulate --out`" if as_run
               else "file not found; expected a Parquet run file" if parquet else "file not found")
    raw = read_bytes(path, where, max_bytes=MAX_RUN_BYTES, missing=missing,
                     expected="a run file written by `trikedyn simulate --out`" if as_run or parquet
                     else "a run file or an IMU log")
    if parquet:
        frame, kind = _parse_parquet(raw, where), "run-parquet"
    else:
        frame, kind = _parse_csv(raw, where, as_run), "run-csv"
        if frame is None:
            return None
    return check_run_table(frame, where, as_run=as_run), kind


def _parse_parquet(raw: bytes, where: str):
    """A DataFrame from Parquet bytes; its size, from the file's own footer, bounded before it is decoded."""
    import pandas as pd

    try:
        import pyarrow.parquet as pq
    except ImportError:
        pq = None
    try:
        if pq is not None:
            info = pq.ParquetFile(io.BytesIO(raw)).metadata
            _check_shape(info.num_rows, info.num_columns, where)
            decoded = sum(info.row_group(i).total_byte_size for i in range(info.num_row_groups))
            if decoded > _MAX_DECODED_BYTES:
                raise InputError(f"holds {decoded / 2**20:.0f} MiB once decompressed, more than the "
                                 f"{_MAX_DECODED_BYTES // 2**20} MiB read; expected a run file", where=where)
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a reader's complaint is a bad file, said once, below
            return pd.read_parquet(io.BytesIO(raw))
    except InputError:
        raise
    except ImportError:
        raise InputError("reading Parquet needs pyarrow or fastparquet, which are not installed; install "
                         "one or write the run as CSV", where=where) from None
    except MemoryError:
        raise InputError("too large to decode in memory; expected a run file", where=where) from None
    except Exception as exc:  # any reader failure is a bad file here
        raise InputError(f"cannot read as Parquet ({_said(exc)})", where=where) from None


def _said(exc: BaseException, limit: int = 160) -> str:
    """An exception as a short line: its type and the start of its message."""
    text = " ".join(str(exc).split())
    text = text if len(text) <= limit else text[: limit - 3] + "..."
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _check_shape(rows: int, columns: int, where: str) -> None:
    if rows > MAX_RUN_ROWS:
        raise InputError(f"{rows} rows, more than the {MAX_RUN_ROWS} of a run file", where=where)
    if columns > MAX_RUN_COLUMNS:
        raise InputError(f"{columns} columns, more than the {MAX_RUN_COLUMNS} of a run file", where=where)


def _parse_csv(raw: bytes, where: str, as_run: bool):
    """A DataFrame from CSV bytes whose first line (the header) names ``time_s``; None (``as_run`` False)
    when it does not, or when its ``time_s`` is not numbers."""
    import pandas as pd

    from .._reading import excerpt

    nul = raw.find(b"\x00")
    if nul >= 0:
        raise InputError(f"binary data (a NUL byte at byte {nul}); expected a CSV run file", where=where)
    try:
        text = raw.decode("utf-8").removeprefix("\ufeff")
    except UnicodeDecodeError as exc:
        if not as_run:
            return None  # perhaps a log in another encoding: the log reader decides
        raise InputError(f"not UTF-8 text ({exc.reason} at byte {exc.start}); expected a CSV run file",
                         where=where) from None
    lines = (line for line in io.StringIO(text) if line.strip())
    first = next(lines, "")
    sep = next((s for s in ",;\t" if s in first), None)
    names = [h.strip().strip('"').strip() for h in first.split(sep)] if sep else [first.strip()]
    if TIME not in names:
        if not as_run:
            return None
        raise InputError(f"not a run file: no '{TIME}' column in its first line (columns: "
                         f"{excerpt(', '.join(names), 80)}); expected a run file written by `trikedyn simulate "
                         "--out`", where=where)
    _check_shape(text.count("\n"), len(names), where)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a row of more fields than the header, ... : a bad file
            frame = pd.read_csv(io.StringIO(text), sep=sep, skipinitialspace=True, index_col=False,
                                engine="c", low_memory=False)
    except MemoryError:
        raise InputError("too large to read in memory; expected a run file", where=where) from None
    except Exception as exc:  # the parser's complaints: rows of too many fields, unbalanced quotes, ...
        raise InputError(f"cannot read as CSV ({_said(exc)})", where=where) from None
    frame.columns = [str(c).strip() for c in frame.columns]
    if not as_run and TIME in frame.columns and not _numeric(frame[TIME]):
        return None  # clock times: a log for the log reader
    return frame


def _numeric(column) -> bool:
    import pandas as pd

    return (pd.api.types.is_numeric_dtype(column) and not pd.api.types.is_complex_dtype(column)) \
        or pd.api.types.is_bool_dtype(column)


def check_run_table(frame, where: str = "run", *, as_run: bool = True):
    """A run table checked (module docstring) and returned with ``time_s`` first and every column float64.

    Parameters
    ----------
    frame : pandas.DataFrame
        ``time_s`` [s] as a column or as the index; ``frame.attrs`` is kept.
    where : str
        Names the table in errors (its file).
    as_run : bool
        Bound the time span by :data:`MAX_RUN_S` (a run); False for any time table
        (:func:`trikedyn.analysis.compare.load_table`).

    Returns
    -------
    pandas.DataFrame

    Raises
    ------
    InputError
        Not a table, no ``time_s``, a column twice, too many rows, columns or wheels, fewer than 2 rows, a
        column that is not numbers, an infinite or too large value, a time not finite or not increasing or
        spanning more than :data:`MAX_RUN_ROWS` median steps, or (``as_run``) a time span over
        :data:`MAX_RUN_S`.
    """
    import numpy as np
    import pandas as pd

    from .._reading import excerpt

    if not isinstance(frame, pd.DataFrame):
        raise InputError(f"is a {type(frame).__name__}; expected a table (pandas DataFrame) with a '{TIME}' "
                         "column", where=where)
    attrs = dict(frame.attrs)
    if TIME not in frame.columns and frame.index.name == TIME:
        frame = frame.reset_index()
    names = [str(c) for c in frame.columns]
    if TIME not in names:
        raise InputError(f"not a run: no '{TIME}' column (columns: {excerpt(', '.join(names), 80)})", where=where)
    twice = next((n for n in names if names.count(n) > 1), None)
    if twice is not None:
        raise InputError(f"column {excerpt(twice)} appears twice", where=where)
    _check_shape(len(frame), len(names), where)
    wheels = [n for n in names if n.endswith("_fz_N")]
    if len(wheels) > MAX_WHEELS:
        raise InputError(f"{len(wheels)} wheel loads ('<wheel>_fz_N' columns), more than the {MAX_WHEELS} a run "
                         "has", where=where)
    if len(frame) < 2:
        raise InputError(f"{len(frame)} row(s); a run has at least 2 samples", where=where)
    columns = {}
    for name, column in zip(names, (frame.iloc[:, k] for k in range(len(names))), strict=True):
        columns[name] = _numbers(column, name, where)
    t = columns[TIME]
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise InputError(f"'{TIME}': time is not finite at row {bad[0]}; expected finite seconds", where=where)
    step = np.diff(t)
    bad = np.flatnonzero(step <= 0)
    if bad.size:
        i = bad[0] + 1
        raise InputError(f"'{TIME}': time does not increase at row {i} ({t[i - 1]:.6g} s then {t[i]:.6g} s); "
                         "expected strictly increasing time", where=where)
    span = float(t[-1] - t[0])
    median = float(np.median(step))
    if span > MAX_RUN_ROWS * median:  # a gap (or a value far off): resampling it would make a huge grid
        i = int(np.argmax(step)) + 1
        raise InputError(f"'{TIME}': a gap of {step[i - 1]:.6g} s at row {i} ({t[i - 1]:.6g} s then {t[i]:.6g} s); "
                         f"the time spans {span / median:.3g} of its median step ({median:.3g} s), expected at most "
                         f"{MAX_RUN_ROWS}", where=where)
    if as_run and span > MAX_RUN_S * (1 + 1e-9):
        raise InputError(f"'{TIME}': the run spans {span:.6g} s, more than the longest run ({MAX_RUN_S:g} s); "
                         "is its time in seconds?", where=where)
    table = pd.DataFrame(columns, index=pd.RangeIndex(len(t)))
    table = table[[TIME, *(n for n in names if n != TIME)]]
    table.attrs = attrs
    return table


def _numbers(column, name: str, where: str):
    """A column as float64: numbers (bool as 0/1), none infinite or beyond :data:`MAX_ABS_VALUE`."""
    import numpy as np
    import pandas as pd

    from .._reading import excerpt

    label = excerpt(name)
    if not _numeric(column):
        text = column.dtype == object or pd.api.types.is_string_dtype(column)
        if not text:
            raise InputError(f"column {label} holds {column.dtype} values, not numbers", where=where)
        try:
            values = pd.to_numeric(column, errors="coerce")
        except (TypeError, ValueError):  # lists, objects: nothing to convert
            values = pd.Series(np.nan, index=column.index)
        bad = np.flatnonzero(values.isna().to_numpy() & column.notna().to_numpy())
        if bad.size:
            raise InputError(f"column {label}: row {bad[0]} is {excerpt(str(column.iloc[bad[0]]), 24)}, not a "
                             "number", where=where)
        column = values
    try:
        x = column.to_numpy(dtype=float, na_value=np.nan)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"column {label} holds values that are not numbers", where=where) from None
    with np.errstate(invalid="ignore"):
        bad = np.flatnonzero(np.isinf(x) | (np.abs(x) > MAX_ABS_VALUE))
    if bad.size:
        raise InputError(f"column {label}: row {bad[0]} is {x[bad[0]]:g}, beyond +-{MAX_ABS_VALUE:g}; expected "
                         "the values of a run (NaN where one is undefined)", where=where)
    return x


# ------------------------------------------------------------------------------------------------------------
# reading a run back: the metadata
# ------------------------------------------------------------------------------------------------------------
_TEXTS = ("vehicle", "manoeuvre", "manoeuvre_name", "speed_control", "status", "left", "right")
_NUMBERS = {"dt_s": (0.0, 60.0, "s"), "target_speed_kmh": (0.0, 400.0, "km/h")}
_TABLES = ("window", "summary", "manoeuvre_spec", "vehicle_params", "driver")
_SUMMARY_TEXTS = ("vehicle", "manoeuvre", "verdict")
_SUMMARY_NUMBERS = {"speed_kmh": (0.0, 400.0, "km/h"), "payload_kg": (0.0, 1e5, "kg")}


def run_meta(run, attrs: Mapping) -> dict:
    """A run's metadata, checked: the table's own (Parquet) metadata ``attrs`` over the ``.json`` sidecar beside
    ``run`` (when there is one), each checked by :func:`check_meta`; ``read_from`` (:data:`READ_FROM`) names
    ``run``.

    Parameters
    ----------
    run : str or Path
        The run file.
    attrs : Mapping
        The table's own metadata.

    Returns
    -------
    dict
        The checked metadata.

    Raises
    ------
    InputError
        The sidecar is there but is not a regular file, is over :data:`MAX_SIDECAR_BYTES`, is not UTF-8 JSON
        or not an object; a field of either fails its check.
    """
    from .._reading import file_problem, read_bytes

    side = Path(run).with_suffix(".json")
    own = check_meta(attrs, f"{run} (its own metadata)") | {READ_FROM: str(run)}
    if file_problem(side) == "no such file":
        return own
    where = str(side)
    hint = "; move it away to read the run without it"
    raw = read_bytes(side, where, max_bytes=MAX_SIDECAR_BYTES, expected=f"the run's JSON sidecar{hint}",
                     too_large=lambda _: f"larger than {MAX_SIDECAR_BYTES // 2**20} MiB; expected the run's "
                                         f"JSON sidecar (a few kB){hint}")
    try:
        found = json.loads(raw.decode("utf-8").removeprefix("\ufeff"), parse_constant=_no_constant)
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text ({exc.reason} at byte {exc.start}){hint}", where=where) from None
    except json.JSONDecodeError as exc:
        raise InputError(f"not JSON ({exc.msg} at line {exc.lineno} column {exc.colno}){hint}",
                         where=where) from None
    except (ValueError, RecursionError) as exc:  # NaN, Infinity; nesting beyond the parser; a huge integer
        why = "nested too deep" if isinstance(exc, RecursionError) else " ".join(str(exc).split())[:120]
        raise InputError(f"not the run's JSON ({why}){hint}", where=where) from None
    if not isinstance(found, dict):
        raise InputError(f"holds a JSON {type(found).__name__}; expected the run's metadata (an object){hint}",
                         where=where)
    return {**check_meta(found, where), **own}


def _no_constant(name: str):
    raise ValueError(f"{name} is not a JSON number")


def check_meta(meta, where: str = "run metadata") -> dict:
    """A run's metadata with each field trikedyn reads checked; other fields are kept as they are.

    Parameters
    ----------
    meta : mapping
        The metadata (a sidecar's JSON object, a Parquet file's own, a :class:`Result`'s ``meta``).
    where : str
        Names its source in errors.

    Returns
    -------
    dict

    Raises
    ------
    InputError
        Not a mapping; ``wheels`` not a list of 1 to :data:`MAX_WHEELS` distinct names; a text field not a
        text of at most :data:`MAX_TEXT_CHARS` characters; a number not a finite number in its range (``dt_s``
        0-60 s, ``target_speed_kmh`` 0-400 km/h, ``summary.speed_kmh``, ``summary.payload_kg`` 0-1e5 kg);
        ``footprint_m`` not ``[x_rear, x_front, half_width]`` [m] with ``x_rear < x_front``, ``half_width > 0``;
        a table field (``window``, ``summary``, ``manoeuvre_spec`` and its ``parameters``, ``vehicle_params``,
        ``driver``) not an object. Null is allowed for every field.
    """
    if meta is None:
        return {}
    if not isinstance(meta, Mapping):
        raise InputError(f"is a {type(meta).__name__}; expected the run's metadata (an object)", where=where)
    meta = {str(k): v for k, v in meta.items()}
    for key in _TEXTS:
        _text(meta.get(key), f"{where}: {key}")
    for key, bounds in _NUMBERS.items():
        _number(meta.get(key), f"{where}: {key}", *bounds)
    for key in _TABLES:
        if meta.get(key) is not None and not isinstance(meta[key], Mapping):
            raise InputError(f"expected an object or null, got {_kind_of(meta[key])}", where=f"{where}: {key}")
    _wheel_names(meta.get("wheels"), f"{where}: wheels")
    _footprint(meta.get("footprint_m"), f"{where}: footprint_m")
    summary = meta.get("summary") or {}
    for key in _SUMMARY_TEXTS:
        _text(summary.get(key), f"{where}: summary.{key}")
    for key, bounds in _SUMMARY_NUMBERS.items():
        _number(summary.get(key), f"{where}: summary.{key}", *bounds)
    spec = meta.get("manoeuvre_spec") or {}
    _text(spec.get("name"), f"{where}: manoeuvre_spec.name")
    if spec.get("parameters") is not None and not isinstance(spec["parameters"], Mapping):
        raise InputError(f"expected an object or null, got {_kind_of(spec['parameters'])}",
                         where=f"{where}: manoeuvre_spec.parameters")
    return meta


def _kind_of(value) -> str:
    """A JSON value's kind in words (``a list``, ``a text``, ``true``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    kinds = {dict: "an object", list: "a list", tuple: "a list", str: "a text", int: "a number", float: "a number"}
    return next((v for k, v in kinds.items() if isinstance(value, k)), f"a {type(value).__name__}")


def _text(value, where: str) -> None:
    if value is None:
        return
    if not isinstance(value, str):
        raise InputError(f"expected a text or null, got {_kind_of(value)}", where=where)
    if len(value) > MAX_TEXT_CHARS:
        raise InputError(f"a text of {len(value)} characters, more than {MAX_TEXT_CHARS}", where=where)


def _number(value, where: str, low: float, high: float, unit: str) -> None:
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(f"expected a number [{unit}] or null, got {_kind_of(value)}", where=where)
    if not (math.isfinite(float(value)) and low <= value <= high):
        raise InputError(f"got {float(value):g}, expected {low:g} to {high:g} {unit}", where=where)


def _wheel_names(value, where: str) -> None:
    if value is None:
        return
    ok = (isinstance(value, list | tuple) and 1 <= len(value) <= MAX_WHEELS
          and all(isinstance(n, str) and 0 < len(n) <= 64 for n in value) and len(set(value)) == len(value))
    if not ok:
        raise InputError(f"expected a list of 1 to {MAX_WHEELS} distinct wheel names, got {_kind_of(value)}",
                         where=where)


def _footprint(value, where: str) -> None:
    if value is None:
        return
    numbers = isinstance(value, list | tuple) and len(value) == 3 and all(
        isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) and abs(v) <= 100 for v in value)
    if not (numbers and value[0] < value[1] and value[2] > 0):
        raise InputError("expected [x_rear, x_front, half_width] in m with x_rear < x_front and half_width > 0, "
                         f"got {_kind_of(value)}", where=where)
