"""``csv``: generic CSV (``,``, ``;`` or tab; decimal point or comma); ``columns=`` maps SI names to headers,
``units=`` gives units, ``time_column=``/``time_unit=`` the time, ``delimiter=``/``decimal=`` the separators."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd

from ...errors import LogFormatError, did_you_mean
from .. import _log_tables as tables
from ..imu_log import CHANNELS, TEMP, TIME, ImuLog
from .base import LogFormat, ReadOptions, register

_COMMA_NUMBER = re.compile(r"^([^,]*\d),(\d+(?:[eE][+-]?\d+)?)$")
"""A cell whose one comma is a decimal mark: ``-0,25``, ``9,81E0``, ``12:00:01,5``."""

TIME_HEADERS = {TIME: "s", "time_ms": "ms", "time_us": "us"}
"""Headers read as the time column without being named, and their units."""


def separator(head: str, first_row: str) -> str:
    """The field separator of a table: of tab, ``;`` and ``,`` (in that order), the first that splits the
    header and the first data row into the same number (> 1) of fields; else the first found in the header;
    else ``,``.

    Parameters
    ----------
    head : str
        The header line.
    first_row : str
        The first data row.

    Returns
    -------
    str
        The separator.
    """
    for sep in ("\t", ";", ","):
        if head.count(sep) and head.count(sep) == first_row.count(sep):
            return sep
    return next((s for s in ",\t;" if s in head), ",")


def _decimal_comma(cells: pd.DataFrame) -> pd.DataFrame:
    """The cells with a decimal comma turned into a point where a cell is such a number."""
    return cells.apply(lambda col: col.str.replace(_COMMA_NUMBER, r"\1.\2", regex=True) if col.dtype.kind == "O"
                       else col)


class GenericCsv(LogFormat):
    """Any separated table: headers that are SI names (or ``time_ms``) are recognised; the others are mapped
    with ``columns=`` (``--column``), ``time_column=`` (``--time-column``) and ``units=``."""

    name = "csv"
    description = ("generic CSV (',', ';' or tab; decimal point or comma); columns= maps SI names to headers, "
                   "units= gives the file's units")
    order = 60
    takes_columns = True

    def sniff(self, head):
        """Any separated header: the fallback.

        Parameters
        ----------
        head : Head
            The file's first bytes.

        Returns
        -------
        float
            0.5 for a separated header, else 0.
        """
        return 0.5 if head.sep else 0.0

    def default_columns(self, header: list[str]) -> dict[str, str]:
        """SI name -> header, for the columns this layout recognises without being told.

        Parameters
        ----------
        header : list of str
            The table's headers.

        Returns
        -------
        dict of str to str
            SI name -> header.
        """
        found = {h: h for h in header if h in (*CHANNELS, TEMP)}
        time = next((h for h in TIME_HEADERS if h in header), None)
        if time is not None:
            found[TIME] = time
        return found

    def read(self, raw: bytes, path: Path, options: ReadOptions) -> ImuLog:
        """The table as an :class:`~trikedyn.measure.logs.ImuLog` (see the module docstring).

        Parameters
        ----------
        raw : bytes
            The file's bytes.
        path : Path
            The file, for errors.
        options : ReadOptions
            What the caller asked for (sensor, rate [Hz], columns, units, ...).

        Returns
        -------
        ImuLog
            The log, SI columns (time [s], accelerations [m/s^2], rates [rad/s], angles [rad]).
        """
        tables._one_sensor(options.sensor, self.name, path)
        columns, units, rate, notes = options.columns, options.units, options.sample_rate_hz, []
        text = tables._decode(raw, path, ("utf-8-sig",))
        lines = [line for line in text.split("\n") if line.strip()]
        head, first_row = (lines + ["", ""])[:2]
        sep = options.delimiter or separator(head, first_row)
        header, cells, lines, at_header = tables._split_table(text, sep, path)
        decimal = options.decimal
        if decimal is None:
            comma = sep != "," and any(tables._DECIMAL_COMMA.match(str(v).strip()) for v in cells.iloc[0])
            decimal = "," if comma else "."
            if comma:
                notes.append("read ',' as the decimal mark (numbers like 1,5 in a "
                             f"{'tab' if sep == chr(9) else repr(sep)}-separated file; --decimal . to refuse it)")
        if decimal == ",":
            cells = _decimal_comma(cells)
        known = (TIME, *CHANNELS, TEMP)
        mapping = self.default_columns(header)
        for si, h in (columns or {}).items():
            if si not in known:
                raise LogFormatError(f"columns= (--column) maps unknown name {si!r}; expected one of "
                                     f"{', '.join(known)}{did_you_mean(si, known)}", where=str(path))
            if h not in header:
                raise LogFormatError(f"columns= (--column or --time-column) names column {h!r} (for {si}) which is "
                                     f"not in the file; columns present: {', '.join(header)}{did_you_mean(h, header)}",
                                     where=at_header)
            mapping[si] = h
        spec = {si: (header.index(h), 1.0) for si, h in mapping.items()}
        given_units = dict(units or {})
        named_time = mapping.get(TIME)
        if TIME not in given_units and TIME_HEADERS.get(named_time, "s") != "s":
            given_units[TIME] = TIME_HEADERS[named_time]
            notes.append(f"time in {named_time!r} read in {given_units[TIME]} (its name says so)")
        for si, unit in given_units.items():
            u = unit.strip().lower().replace("^2", "2").replace("²", "2").replace("°", "deg")
            allowed = tables._KIND_UNITS.get(si.rsplit("_", 1)[-1], ())
            if si not in spec or u not in allowed:
                raise LogFormatError(f"units= (--unit) gives {unit!r} for {si!r}; expected a column mapped to "
                                     f"{si!r} (mapped: {', '.join(spec)}) and one of {', '.join(allowed) or 'no unit'}",
                                     where=str(path))
            spec[si] = (spec[si][0], tables._UNITS[u])
        if TIME in spec:
            t = tables._times(cells[spec[TIME][0]], mapping[TIME], lines, path, notes, factor=spec[TIME][1])
        elif rate is not None:
            t = np.arange(len(lines)) / rate
            notes.append(f"the file has no time column: time built from sample_rate_hz={rate:g}")
        else:
            raise LogFormatError(f"no time column; columns present: {', '.join(header)}; expected a column "
                                 "'time_s' or 'time_ms', or the time column named (--time-column HEADER "
                                 "[--time-unit ms]; time_column= in Python), or the rate (--sample-rate HZ; "
                                 "sample_rate_hz=)", where=at_header)
        return tables._table_log(path, self.name, t, header, cells, lines, spec, set(), notes)

    def write(self, data: pd.DataFrame, path: Path) -> None:
        """The SI columns as they are, comma-separated.

        Parameters
        ----------
        data : pandas.DataFrame
            SI columns (``time_s`` [s] increasing, ...).
        path : Path
            The file to write.
        """
        data.to_csv(path, index=False)


register(GenericCsv())
