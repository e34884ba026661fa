"""What the three WitMotion text layouts share: headers, the reader (devices, chip or PC clock), the writer."""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

import pandas as pd

from ...errors import LogFormatError
from .. import _log_tables as tables
from ..clocktime import clock_fields, clock_text
from ..imu_log import CHANNELS, TEMP, TIME, ImuLog
from .base import LogFormat, ReadOptions

# Headers of each WitMotion text layout: time, the 9 channels, temperature.
HEADERS = {
    "witmotion-sdk": ["Chiptime", *(f"a{c}(g)" for c in "xyz"), *(f"w{c}(deg/s)" for c in "xyz"),
                      *(f"Angle{c}(deg)" for c in "XYZ"), "T(°)"],
    "witmotion-pc": ["ChipTime", *(f"Acc{c}(g)" for c in "XYZ"), *(f"As{c}(°/s)" for c in "XYZ"),
                     *(f"Angle{c}(°)" for c in "XYZ"), "T(°C)"],
    "witmotion-2025": ["Chip Time()", *(f"Acceleration {c}(g)" for c in "XYZ"),
                       *(f"Angular velocity {c}(°/s)" for c in "XYZ"), *(f"Angle {c}(°)" for c in "XYZ"),
                       "Temperature(℃)"],
}
LOOKUP = {tables._norm(h): si for hs in HEADERS.values()
          for h, si in zip(hs, (TIME, *CHANNELS, TEMP), strict=False)}


class WitMotionText(LogFormat):
    """A WitMotion text export: ``sep``-separated, optional PC-clock and device columns."""

    sep: ClassVar[str] = "\t"
    pc_columns: ClassVar[tuple[str, str] | None] = None  # (PC clock, device name) headers
    chip_style: ClassVar[str] = "date"  # clock_text style of the chip time
    pc_style: ClassVar[str] = "date"  # clock_text style of the PC clock
    encoding: ClassVar[str] = "utf-8"
    line_end: ClassVar[str] = "\n"

    @property
    def headers(self) -> list[str]:
        """This layout's headers: the time, the 9 channels and the temperature, as the layout names them."""
        return HEADERS[self.name]

    def read(self, raw: bytes, path: Path, options: ReadOptions) -> ImuLog:
        """The log as an :class:`~trikedyn.measure.logs.ImuLog`: chip time (or the PC clock where it is empty), the
        rows of device ``options.sensor`` of a file with several."""
        fmt, sensor, notes = self.name, options.sensor, []
        text = tables._decode(raw, path, ("utf-8-sig", "gb18030"))
        header, cells, lines, at_header = tables._split_table(text, self.sep, path)
        norm = [tables._norm(h) for h in header]
        spec: dict[str, tuple[int, float]] = {}
        for j, key in enumerate(norm):
            if key in LOOKUP:
                spec.setdefault(LOOKUP[key], (j, tables._FACTOR.get(LOOKUP[key], 1.0)))
        pc = {k: norm.index(k) for k in ("time", "devicename") if k in norm}
        if TIME not in spec or (cells[spec[TIME][0]] == "").all():
            if "time" not in pc:
                raise LogFormatError(f"no time column; columns present: {', '.join(header)}; expected "
                                     f"{self.headers[0]!r}", where=at_header)
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
            tables._one_sensor(sensor, fmt, path)
        j = spec[TIME][0]
        t = tables._times(cells[j], header[j], lines, path, notes, ms_field=True)
        return tables._table_log(path, fmt, t, header, cells, lines, spec, set(pc.values()), notes)

    def write(self, data: pd.DataFrame, path: Path) -> None:
        """Write ``data`` in this layout: chip time (and PC clock and device name) as clock text, the channels in
        g, °/s and °, temperature in °C, the other columns under their own names."""
        f = clock_fields(data[TIME].to_numpy(float), path, self.name)
        out = {}
        if self.pc_columns:
            pc_time, device = self.pc_columns
            out[pc_time] = clock_text(f, self.pc_style)
            out[device] = "trikedyn"
        out[self.headers[0]] = clock_text(f, self.chip_style)
        for si, h in zip((*CHANNELS, TEMP), self.headers[1:], strict=False):
            if si in data:
                out[h] = data[si].to_numpy(float) / tables._FACTOR.get(si, 1.0)
        pd.DataFrame(out | tables._extras(data, (*CHANNELS, TEMP))).to_csv(
            path, sep=self.sep, index=False, encoding=self.encoding, lineterminator=self.line_end)


