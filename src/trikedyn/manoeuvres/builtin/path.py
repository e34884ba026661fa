"""A path from a CSV file (a designed line or a measured trajectory), driven at a constant speed."""

from __future__ import annotations

from pathlib import Path as FilePath

from .. import paths, speed
from ..base import path_manoeuvre
from ..registry import Option, register

OPTIONS = (
    Option("file", "", "", "CSV file with x_m, y_m columns (see the file-format docs)"),
    Option("smoothing_m", 0.01, "m", "smoothing of the line"),
    Option("entry_m", 0.0, "m", "entry gate: arc length where judging starts"),
    Option("exit_m", 0.0, "m", "exit gate: arc length where judging ends (0: the end of the line)"),
)


@register("path", "path from a CSV file", options=OPTIONS)
def build(params, speed_kmh: float, *, file: str, smoothing_m: float, entry_m: float, exit_m: float):
    """Follow the line of a CSV file at a constant target speed, judged over the whole line by default.

    The line is continued straight (or on its end curvature) beyond its end so the driver never runs out.
    """
    from ...errors import InputError

    if not file:
        raise InputError("needs file=PATH.csv", where="path")
    path = paths.path_from_csv(file, smoothing_m=smoothing_m)
    end = float(path.s_m[-1]) if exit_m <= 0 else exit_m
    return path_manoeuvre("path", f"path {FilePath(file).name}", path, speed.constant(speed_kmh, 1.0),
                          entry_m=entry_m, exit_m=end,
                          parameters={"exit_m": end},
                          description=path.description)
