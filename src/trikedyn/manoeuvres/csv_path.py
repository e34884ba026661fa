"""A path from a CSV file of points (a designed line or a measured trajectory): read with bounds, smoothed
and resampled uniformly in arc length."""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path as _FilePath

import numpy as np

from .._reading import excerpt, open_binary
from ..errors import InputError
from .geometry import _DENSE_DX_M, MAX_LENGTH_M, Path, _number, _uniform_count

__all__ = ["path_from_csv"]

MAX_CSV_POINTS = 1_000_000
"""Most points of a path CSV."""

CSV_SPACING_M = (0.001, 1000.0)
"""Least and largest distance between consecutive points of a path CSV [m]."""

MAX_CSV_COORDINATE_M = 1e7
"""Largest magnitude of a path CSV coordinate [m] (UTM northings reach 1e7 m; beyond, float64 rounds the
millimetre)."""

MAX_CSV_BYTES = 256 * 2**20
"""Largest path CSV read [bytes]."""

# --------------------------------------------------------------------------------------------------------------
# CSV paths
# --------------------------------------------------------------------------------------------------------------
def _read_xy_csv(file: _FilePath) -> tuple[np.ndarray, np.ndarray]:
    where = str(file)
    limit = MAX_CSV_BYTES

    def too_large(size: int | None) -> str:
        """The message for a file over the bound (``size`` [bytes]; None: it grew while read)."""
        amount = f"{size / 2**20:.0f} MiB" if size is not None else f"more than {limit / 2**20:.0f} MiB"
        return f"{amount}; a path CSV is read up to {limit // 2**20} MiB"

    reader = None
    with open_binary(file, where, max_bytes=limit, expected="a path CSV file", too_large=too_large) as raw:
        try:
            handle = io.TextIOWrapper(raw, encoding="utf-8-sig", newline="")
            reader = csv.reader(handle)
            return _parse_xy_rows(reader, file)
        except UnicodeDecodeError as exc:
            raise InputError(f"cannot read the file as UTF-8 text ({exc.reason})", where=where) from None
        except OSError as exc:
            raise InputError(f"cannot read it: {exc.strerror or type(exc).__name__}", where=where) from None
        except csv.Error as exc:
            line = f"{file}:{reader.line_num}" if reader is not None else where
            raise InputError(f"not a CSV line: {exc}", where=line) from None


def _parse_xy_rows(reader, file: _FilePath) -> tuple[np.ndarray, np.ndarray]:
    header = None
    columns: tuple[int, int] = (0, 1)
    xs: list[float] = []
    ys: list[float] = []
    last_line = 0
    total = 0.0
    low, high = CSV_SPACING_M
    for row in reader:
        line_no = reader.line_num
        if not row or not "".join(row).strip() or row[0].lstrip().startswith("#"):
            continue
        where = f"{file}:{line_no}"
        if header is None:
            header = [cell.strip().lower() for cell in row]
            found = []
            for names in (("x_m", "x"), ("y_m", "y")):
                index = next((header.index(n) for n in names if n in header), None)
                if index is None:
                    raise InputError(f"missing column '{names[0]}' (or '{names[1]}'); found {_columns(header)}",
                                     where=where)
                found.append(index)
            columns = (found[0], found[1])
            continue
        values = []
        for index, name in zip(columns, ("x", "y"), strict=True):
            if index >= len(row):
                raise InputError(f"missing the {name} value (expected {len(header)} columns)", where=where)
            cell = row[index].strip()
            try:
                value = float(cell)
            except ValueError:
                raise InputError(f"{name}: expected a number, got {excerpt(cell, 20)}", where=where) from None
            if not math.isfinite(value):
                raise InputError(f"{name}: expected a finite number, got {excerpt(cell, 20)}", where=where)
            if abs(value) > MAX_CSV_COORDINATE_M:
                raise InputError(f"{name}: {value:g} m is beyond +-{MAX_CSV_COORDINATE_M:g} m", where=where)
            values.append(value)
        if xs:
            if values[0] == xs[-1] and values[1] == ys[-1]:
                raise InputError(f"repeats the point of line {last_line} ({values[0]:g}, {values[1]:g})", where=where)
            step = math.hypot(values[0] - xs[-1], values[1] - ys[-1])
            if not low <= step <= high:
                raise InputError(f"{step:.4g} m from the point of line {last_line}; consecutive points must be "
                                 f"{low * 1000:g} mm to {high:g} m apart (merge or remove points)", where=where)
            total += step
            if total > MAX_LENGTH_M:
                raise InputError(f"the line is longer than {MAX_LENGTH_M:g} m by here", where=where)
        if len(xs) == MAX_CSV_POINTS:
            raise InputError(f"more than {MAX_CSV_POINTS} points", where=where)
        xs.append(values[0])
        ys.append(values[1])
        last_line = line_no
    if header is None:
        raise InputError("empty file: expected a header with columns x_m, y_m", where=str(file))
    if len(xs) < 3:
        raise InputError(f"{len(xs)} point(s); at least 3 are needed", where=str(file))
    return np.array(xs), np.array(ys)


def _columns(header: list[str]) -> str:
    """The header's columns for a message: at most three, each a short escaped excerpt (a file that is no
    path CSV, a system file or binary text, is not echoed)."""
    named = [excerpt(h, 16) for h in header[:3] if h]
    more = f" and {len(header) - 3} more" if len(header) > 3 else ""
    return f"{len(header)} column(s): {', '.join(named) or 'unnamed'}{more}"


def path_from_csv(file, *, smoothing_m: float = 0.01, align: bool = True, name: str | None = None) -> Path:
    """A path from a CSV file of points, smoothed and resampled uniformly in arc length.

    Parameters
    ----------
    file : str or os.PathLike
        CSV file with a header naming columns ``x_m`` and ``y_m`` (or ``x`` and ``y``) [m]; other columns
        are ignored; blank lines and lines starting with ``#`` are skipped.
    smoothing_m : float
        RMS distance [m] the smoothing spline may keep from the points (0: interpolate them).
    align : bool
        Move and turn the path so that it starts at the origin heading +x, as every trikedyn path does
        (the simulation starts the vehicle there). ``False`` keeps the file's coordinates.
    name : str, optional
        Path name (default: the file name).

    Returns
    -------
    Path
        No cones, no corridors.

    Raises
    ------
    InputError
        Naming the file and line: missing columns, a value that is not a finite number or lies beyond
        ``MAX_CSV_COORDINATE_M``, a point that repeats the previous one, fewer than 3 points. And the bounds:
        consecutive points closer than 1 mm or farther than 1 km apart (``CSV_SPACING_M``) are refused, not
        merged (a point 1 mm from the last says the line was sampled without moving: remove or merge such
        points, the smoothing spline cannot tell their order); more than ``MAX_CSV_POINTS`` points, a line
        longer than ``MAX_LENGTH_M`` (20 km) or a file larger than ``MAX_CSV_BYTES``. The file is read by the
        one bounded reader (:mod:`trikedyn._reading`): a folder, a pipe or a device is refused before it is
        opened; a message quotes at most a short, escaped excerpt of the file's text.

    Notes
    -----
    A parametric smoothing spline (``scipy.interpolate.splprep``, cubic, parameter the chord length,
    smoothing factor ``n * smoothing_m^2``) is fitted to the points; heading and curvature are its
    derivatives, so the curvature is continuous.
    """
    from scipy.interpolate import splev, splprep

    file = _FilePath(file)
    sigma = _number(smoothing_m, "smoothing_m", minimum=0.0)
    x, y = _read_xy_csv(file)
    chord = np.hypot(np.diff(x), np.diff(y))
    u = np.concatenate(([0.0], np.cumsum(chord)))
    k = min(3, x.size - 1)
    try:
        tck, _ = splprep([x, y], u=u, k=k, s=x.size * sigma**2, quiet=1)
    except Exception as exc:  # FITPACK's own errors are plain ValueErrors / SystemErrors with terse text
        raise InputError(f"cannot fit a smoothing spline to the points: {exc}", where=str(file)) from None
    ud = np.linspace(u[0], u[-1], int(math.ceil(u[-1] / _DENSE_DX_M)) + 1)
    dxd, dyd = splev(ud, tck, der=1)
    g = np.hypot(dxd, dyd)
    if np.any(g <= 1e-9):
        raise InputError("the smoothed line has a cusp; reduce smoothing_m or remove reversing points", where=str(file))
    sd = np.concatenate(([0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(ud))))
    s = np.linspace(0.0, sd[-1], _uniform_count(sd[-1], str(file)))
    uu = np.interp(s, sd, ud)
    px, py = splev(uu, tck)
    d1x, d1y = splev(uu, tck, der=1)
    d2x, d2y = splev(uu, tck, der=2)
    px, py = np.asarray(px), np.asarray(py)
    heading = np.unwrap(np.arctan2(d1y, d1x))
    curvature = (np.asarray(d1x) * d2y - np.asarray(d1y) * d2x) / np.hypot(d1x, d1y) ** 3
    if align:
        h0 = heading[0]
        c, sn = math.cos(h0), math.sin(h0)
        dx, dy = px - px[0], py - py[0]
        px, py = c * dx + sn * dy, -sn * dx + c * dy
        heading = heading - h0
    return Path(
        name=name or file.stem,
        x_m=px,
        y_m=py,
        s_m=s,
        heading_rad=heading,
        curvature_per_m=curvature,
        description=(
            f"from {file.name}: {x.size} points, cubic smoothing spline (RMS tolerance {sigma:g} m), "
            f"resampled every {s[1] - s[0]:.4f} m" + ("; moved to start at the origin heading +x" if align else "")
        ),
    )
