"""``csv``: generic CSV (``,``, ``;`` or tab); ``columns=`` maps SI names to headers, ``units=`` gives units."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...errors import LogFormatError
from .. import logs
from ..logs import CHANNELS, TEMP, TIME, ImuLog
from . import LogFormat, ReadOptions, register


class GenericCsv(LogFormat):
    name = "csv"
    description = "generic CSV; columns= maps SI names to headers, units= gives the file's units"
    order = 60
    takes_columns = True

    def sniff(self, head):
        return 0.5 if head.sep else 0.0  # any separated header: the fallback

    def read(self, raw: bytes, path: Path, options: ReadOptions) -> ImuLog:
        logs._one_sensor(options.sensor, self.name, path)
        columns, units, rate, notes = options.columns, options.units, options.sample_rate_hz, []
        text = logs._decode(raw, path, ("utf-8-sig",))
        head = next((line for line in text.split("\n") if line.strip()), "")
        header, cells, lines, at_header = logs._split_table(text, next((s for s in ",\t;" if s in head), ","),
                                                            path)
        known = (TIME, *CHANNELS, TEMP)
        mapping = {h: h for h in header if h in known}
        for si, h in (columns or {}).items():
            if si not in known:
                raise LogFormatError(f"columns= maps unknown name {si!r}; expected one of {', '.join(known)}"
                                     f"{logs._hint(si, known)}", where=str(path))
            if h not in header:
                raise LogFormatError(f"columns= names column {h!r} (for {si}) which is not in the file; "
                                     f"columns present: {', '.join(header)}{logs._hint(h, header)}",
                                     where=at_header)
            mapping[si] = h
        spec = {si: (header.index(h), 1.0) for si, h in mapping.items()}
        for si, unit in (units or {}).items():
            u = unit.strip().lower().replace("^2", "2").replace("²", "2").replace("°", "deg")
            allowed = logs._KIND_UNITS.get(si.rsplit("_", 1)[-1], ())
            if si not in spec or u not in allowed:
                raise LogFormatError(f"units= gives {unit!r} for {si!r}; expected a column mapped to {si!r} "
                                     f"(mapped: {', '.join(spec)}) and one of {', '.join(allowed) or 'no unit'}",
                                     where=str(path))
            spec[si] = (spec[si][0], logs._UNITS[u])
        if TIME in spec:
            t = logs._times(cells[spec[TIME][0]], mapping[TIME], lines, path, notes, factor=spec[TIME][1])
        elif rate is not None:
            t = np.arange(len(lines)) / rate
            notes.append(f"the file has no time column: time built from sample_rate_hz={rate:g}")
        else:
            raise LogFormatError(f"no time column; columns present: {', '.join(header)}; expected a column "
                                 "'time_s', or columns={'time_s': <header>}, or sample_rate_hz=",
                                 where=at_header)
        return logs._table_log(path, self.name, t, header, cells, lines, spec, set(), notes)

    def write(self, data: pd.DataFrame, path: Path) -> None:
        data.to_csv(path, index=False)


register(GenericCsv())
