"""``bwt901cl-csv``: the CSV of the get_bwt901cl_data logger (two sensors, m/s², °/s, °, zeros until heard)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd

from ...errors import LogFormatError
from .. import _log_tables as tables
from .._log_tables import _DEG
from ..clocktime import clock_fields, clock_text
from ..imu_log import CHANNELS, TIME, ImuLog
from .base import LogFormat, ReadOptions, register

_BWT = {"Acc": CHANNELS[0:3], "AngVel": CHANNELS[3:6], "Ang": CHANNELS[6:9]}


class Bwt901clCsv(LogFormat):
    """The get_bwt901cl_data logger's CSV (see the module docstring): ``Time`` as HH:MM:SS.fff, ``AccX1`` ..
    ``AngZ2`` in m/s², °/s and °, zeros until a sensor is heard."""

    name = "bwt901cl-csv"
    description = "get_bwt901cl_data logger CSV (Time HH:MM:SS.fff, AccX1 .. AngZ2 in m/s2, deg/s, deg)"
    order = 50

    def sniff(self, head):
        """2 when the header holds ``Time`` and ``AccX1``, else 0.

        Parameters
        ----------
        head : Head
            The file's first bytes.

        Returns
        -------
        float
            The score.
        """
        return 2.0 if {"time", "accx1"} <= head.keys else 0.0

    def read(self, raw: bytes, path: Path, options: ReadOptions) -> ImuLog:
        """The log of sensor ``options.sensor`` as an :class:`~trikedyn.measure.logs.ImuLog`, its leading rows of
        zeros (before the logger heard it) dropped, accelerations kept as written (g x 9.8).

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
        sensor, notes = options.sensor, []
        header, cells, lines, at_header = tables._split_table(tables._decode(raw, path, ("utf-8-sig",)), ",", path)
        sensors = sorted({int(m[1]) for h in header if (m := re.fullmatch(r"AccX(\d+)", h))})
        if sensor not in sensors:
            raise LogFormatError(f"sensor={sensor} but the file has columns for sensor(s) "
                                 f"{', '.join(map(str, sensors)) or 'none'}; expected AccX{sensor}",
                                 where=at_header)
        want = {"Time": TIME} | {f"{p}{c}{sensor}": si for p, sis in _BWT.items()
                                 for c, si in zip("XYZ", sis, strict=False)}
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
        t = tables._times(cells[spec[TIME][0]], "Time", lines, path, notes)
        if n:
            notes.append(f"dropped the first {n} row(s): sensor {sensor} had not reported yet (the logger writes "
                         f"0 until then); time_s starts {t[n]:.3f} s after the file's first row")
        notes.append("accelerations kept in m/s2 as the logger wrote them: g x 9.8, 0.07 % below g x 9.80665")
        others = {j for j, h in enumerate(header) if re.fullmatch(r"(Acc|AngVel|Ang)[XYZ]\d+", h)}
        cells = cells.iloc[n:].reset_index(drop=True)
        return tables._table_log(path, self.name, t[n:], header, cells, lines[n:], spec, others, notes)

    def write(self, data: pd.DataFrame, path: Path) -> None:
        """The SI columns as sensor 1: ``Time`` as HH:MM:SS.fff, accelerations in m/s², rates in °/s, angles in °,
        the other columns under their own names.

        Parameters
        ----------
        data : pandas.DataFrame
            SI columns (``time_s`` [s] increasing, ...).
        path : Path
            The file to write.
        """
        out = {"Time": clock_text(clock_fields(data[TIME].to_numpy(float), path, self.name), "clock")}
        for prefix, sis in _BWT.items():
            for c, si in zip("XYZ", sis, strict=False):
                if si in data:
                    out[f"{prefix}{c}1"] = data[si].to_numpy(float) / (1.0 if prefix == "Acc" else _DEG)
        pd.DataFrame(out | tables._extras(data, CHANNELS)).to_csv(path, index=False)


register(Bwt901clCsv())
