"""Run files read back and checked once, where they are read, so that every reader -- ``trikedyn plot``,
``trikedyn animate``, ``trikedyn compare``, the report's figures -- gets a table it can use, and a user's mistake
is one :class:`~trikedyn.errors.InputError` naming the file, the column or field and the row.

:func:`read_run` reads a run file (:func:`read_run_table`, :func:`check_run_table`) and its metadata
(:func:`~trikedyn.simulate.runmeta.run_meta`, :func:`~trikedyn.simulate.runmeta.check_meta`):

* the files are read by the one bounded reader (:mod:`trikedyn._reading`): a folder, a pipe or a device is
  refused unopened; the table at most :data:`MAX_RUN_BYTES`, the sidecar at most
  :data:`~trikedyn.simulate.runmeta.MAX_SIDECAR_BYTES`; a Parquet file's size once decompressed, from its own
  footer, is bounded before it is decoded;
* the table: at most :data:`MAX_RUN_ROWS` rows, :data:`MAX_RUN_COLUMNS` columns and
  :data:`~trikedyn.simulate.runmeta.MAX_WHEELS` wheel loads (``<wheel>_fz_N``), at least 2 rows; a ``time_s``
  column [s] (or index) finite and strictly increasing, spanning at most :data:`MAX_RUN_ROWS` of its median
  steps (no gap that would make a resampled grid huge: ``compare`` resamples at 10 times the median rate);
  every column numbers (returned as float64), none infinite or beyond +-:data:`MAX_ABS_VALUE` (NaN is kept: a
  value undefined at that sample, as RI with both wheels of the pair off the ground); read as a run, its time
  spans at most :data:`MAX_RUN_S` (the longest manoeuvre);
* the metadata (the sidecar's and a Parquet file's own, the latter taking precedence): each field trikedyn
  reads has its type and range (:mod:`trikedyn.simulate.runmeta`); fields it does not read are left alone.

Writing a run and rebuilding its vehicle and course: :mod:`trikedyn.simulate.runfile`.
"""

from __future__ import annotations

import io
import warnings
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError
from ..manoeuvres.base import MAX_DURATION_S
from .runmeta import MAX_WHEELS, run_meta

__all__ = ["MAX_ABS_VALUE", "MAX_RUN_BYTES", "MAX_RUN_COLUMNS", "MAX_RUN_ROWS", "MAX_RUN_S", "RUN_SUFFIXES", "RunFile",
           "check_run_table", "read_run", "read_run_table"]

MAX_RUN_BYTES = 256 * 2**20
"""Largest run table read [bytes] (a run of an hour at 100 Hz is about 60 MiB of Parquet)."""
MAX_RUN_ROWS = 1_000_000
"""Most rows of a run table (an hour at 100 Hz is 360,001)."""
MAX_RUN_COLUMNS = 1000
"""Most columns of a run table (a three-wheeler's run has about 70)."""
MAX_ABS_VALUE = 1e12
"""Largest magnitude of a value in a run table: nothing a run records comes near it (forces are kN, times
hours)."""
MAX_RUN_S = MAX_DURATION_S
"""Longest time span of a run [s]: the longest manoeuvre (:data:`trikedyn.manoeuvres.base.MAX_DURATION_S`)."""
RUN_SUFFIXES = (".parquet", ".pq", ".csv")
"""File name endings of a run table."""
TIME = "time_s"
_MAX_DECODED_BYTES = 4 * MAX_RUN_BYTES  # a Parquet file's data once decompressed, from its own footer


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
        The run's metadata, checked (:func:`~trikedyn.simulate.runmeta.check_meta`).
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

