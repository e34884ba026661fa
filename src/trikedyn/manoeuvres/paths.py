"""Manoeuvre geometry: reference lines, cones and lane corridors.

A :class:`Path` is what the driver model follows: a reference line sampled uniformly in arc length (every
``ds <= 0.05 m``) as plain float64 arrays, with its heading and curvature, plus the cones and the lane
corridors that judge the run. Axes are ISO 8855 (x forward, y left). Every path starts at the origin,
heading +x, with a straight run-in, and ends with a straight run-out (:func:`circle` excepted: it ends on
the circle).

Manoeuvres
----------
- :func:`double_lane_change`: ISO 3888-1 double lane change (default) or ISO 3888-2 obstacle avoidance;
- :func:`single_lane_change`: ISO 14791 single lane change (one sine period of lateral acceleration);
- :func:`circle`: ISO 4138 steady-state circular driving, constant radius;
- :func:`straight`;
- :func:`path_from_csv`: a measured or designed line from a CSV file, smoothed and resampled.

Judging a run
-------------
:func:`cone_strikes` and :func:`corridor_violations` take the vehicle trajectory (a reference point and the
yaw angle at each sample) and the vehicle's footprint rectangle.

The standards prescribe cones, not a line to drive: the reference lines here are our choice and each
function's docstring says which. All functions are pure; arrays are returned C-contiguous.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path as _FilePath

import numpy as np

from ..errors import InputError

__all__ = [
    "CONE_RADIUS_M",
    "DS_MAX_M",
    "Corridor",
    "Path",
    "circle",
    "cone_strikes",
    "corridor_violations",
    "double_lane_change",
    "path_from_csv",
    "single_lane_change",
    "straight",
]

DS_MAX_M = 0.05
"""Largest spacing of the reference-line points [m]."""

CONE_RADIUS_M = 0.15
"""Radius of a cone's base circle [m] (our choice; the standards ask for cones at least 500 mm high)."""

MAX_LENGTH_M = 20_000.0
"""Longest reference line [m] (20 km: over 30 min at 40 km/h; 400 000 points at DS_MAX_M)."""

MAX_CSV_POINTS = 1_000_000
"""Most points of a path CSV."""

CSV_SPACING_M = (0.001, 1000.0)
"""Least and largest distance between consecutive points of a path CSV [m]."""

MAX_CSV_COORDINATE_M = 1e7
"""Largest magnitude of a path CSV coordinate [m] (UTM northings reach 1e7 m; beyond, float64 rounds the
millimetre)."""

MAX_CSV_BYTES = 256 * 2**20
"""Largest path CSV read [bytes]."""

_DENSE_DX_M = 0.005  # spacing of the dense grid used to integrate arc length [m]


# --------------------------------------------------------------------------------------------------------------
# data classes
# --------------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Corridor:
    """A straight lane section the vehicle must stay within: ``x_start_m <= x <= x_end_m``, ``y_min_m <= y <= y_max_m``.

    Parameters
    ----------
    x_start_m, x_end_m : float
        Longitudinal extent of the section [m].
    y_min_m, y_max_m : float
        Right and left lane limits [m] (y left positive).
    name : str
        The section's name, e.g. ``"section 3"``.
    """

    x_start_m: float
    x_end_m: float
    y_min_m: float
    y_max_m: float
    name: str = ""

    def __post_init__(self):
        values = (self.x_start_m, self.x_end_m, self.y_min_m, self.y_max_m)
        if not all(math.isfinite(v) for v in values):
            raise InputError(f"corridor limits must be finite numbers, got {values}", where=f"corridor '{self.name}'")
        if self.x_end_m <= self.x_start_m or self.y_max_m <= self.y_min_m:
            raise InputError("expected x_start_m < x_end_m and y_min_m < y_max_m", where=f"corridor '{self.name}'")

    @property
    def width_m(self) -> float:
        """Lane width [m]."""
        return self.y_max_m - self.y_min_m

    @property
    def length_m(self) -> float:
        """Section length [m]."""
        return self.x_end_m - self.x_start_m

    @property
    def centre_y_m(self) -> float:
        """Lateral position of the lane centre [m]."""
        return 0.5 * (self.y_min_m + self.y_max_m)

    def to_dict(self) -> dict:
        """JSON-safe dict of the corridor."""
        return {
            "name": self.name,
            "x_start_m": float(self.x_start_m),
            "x_end_m": float(self.x_end_m),
            "y_min_m": float(self.y_min_m),
            "y_max_m": float(self.y_max_m),
            "width_m": float(self.width_m),
        }


def _array(value, name: str) -> np.ndarray:
    out = np.ascontiguousarray(value, dtype=np.float64)
    if out.ndim != 1:
        raise InputError(f"expected a 1-D array, got shape {out.shape}", where=name)
    if not np.all(np.isfinite(out)):
        raise InputError("contains NaN or infinite values", where=name)
    return out


@dataclass(frozen=True, eq=False)
class Path:
    """A reference line with its cones and lane corridors.

    Parameters
    ----------
    name : str
        Short name of the manoeuvre.
    x_m, y_m : numpy.ndarray
        Reference-line points [m], uniformly spaced in arc length, ``ds <= 0.05 m``.
    s_m : numpy.ndarray
        Arc length from the first point [m].
    heading_rad : numpy.ndarray
        Tangent direction [rad], continuous (unwrapped: a full circle ends at ``2 pi``).
    curvature_per_m : numpy.ndarray
        Signed curvature [1/m], positive turning left.
    cones : numpy.ndarray
        ``(k, 2)`` cone positions (x, y) [m]; ``(0, 2)`` when none.
    corridors : tuple of Corridor
        The lane sections the vehicle must stay within.
    description : str
        The standard and clause followed, and the choices made where it leaves one.

    Notes
    -----
    The arrays are float64 and C-contiguous, ready for compiled code (:meth:`as_array` stacks them in the
    driver's column order). Treat them as read-only: they are not copied when a path is shared.
    """

    name: str
    x_m: np.ndarray
    y_m: np.ndarray
    s_m: np.ndarray
    heading_rad: np.ndarray
    curvature_per_m: np.ndarray
    cones: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    corridors: tuple = ()
    description: str = ""

    def __post_init__(self):
        for key in ("x_m", "y_m", "s_m", "heading_rad", "curvature_per_m"):
            object.__setattr__(self, key, _array(getattr(self, key), f"path.{key}"))
        n = self.x_m.size
        if n < 2:
            raise InputError(f"a path needs at least 2 points, got {n}", where="path.x_m")
        for key in ("y_m", "s_m", "heading_rad", "curvature_per_m"):
            if getattr(self, key).size != n:
                raise InputError(f"has {getattr(self, key).size} values, x_m has {n}", where=f"path.{key}")
        if np.any(np.diff(self.s_m) <= 0.0):
            raise InputError("arc length must increase strictly", where="path.s_m")
        cones = (
            np.ascontiguousarray(self.cones, dtype=np.float64).reshape(-1, 2)
            if np.size(self.cones)
            else np.zeros((0, 2))
        )
        if not np.all(np.isfinite(cones)):
            raise InputError("contains NaN or infinite values", where="path.cones")
        object.__setattr__(self, "cones", cones)
        corridors = tuple(self.corridors)
        for c in corridors:
            if not isinstance(c, Corridor):
                raise InputError(f"expected Corridor objects, got {type(c).__name__}", where="path.corridors")
        object.__setattr__(self, "corridors", corridors)

    # ---- summary -------------------------------------------------------------------------------------------
    @property
    def length_m(self) -> float:
        """Length of the reference line [m]."""
        return float(self.s_m[-1] - self.s_m[0])

    @property
    def ds_m(self) -> float:
        """Spacing of the points in arc length [m]."""
        return float(self.s_m[1] - self.s_m[0])

    def as_array(self) -> np.ndarray:
        """The line as one ``(n, 5)`` float64 C-contiguous array: x, y, s, heading, curvature.

        The column order is the driver's (``trikedyn.driver.preview.PATH_COLUMNS``).
        """
        return np.ascontiguousarray(
            np.column_stack((self.x_m, self.y_m, self.s_m, self.heading_rad, self.curvature_per_m))
        )

    def to_dict(self) -> dict:
        """JSON-safe summary: name, length, point spacing, cone count, corridors, description."""
        return {
            "name": self.name,
            "length_m": self.length_m,
            "n_points": int(self.x_m.size),
            "ds_m": self.ds_m,
            "x_end_m": float(self.x_m[-1]),
            "y_end_m": float(self.y_m[-1]),
            "cones": int(self.cones.shape[0]),
            "corridors": [c.to_dict() for c in self.corridors],
            "description": self.description,
        }

    # ---- projection ----------------------------------------------------------------------------------------
    @cached_property
    def _tree(self):
        from scipy.spatial import cKDTree

        return cKDTree(np.column_stack((self.x_m, self.y_m)))

    def project(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """Arc length of the nearest point of the line and signed lateral offset, for arrays of points.

        Parameters
        ----------
        x, y : array_like
            Points [m] (any matching shapes).

        Returns
        -------
        s_m : numpy.ndarray
            Arc length of the foot of the perpendicular on the line [m].
        offset_m : numpy.ndarray
            Signed distance from the line [m], positive to the left of the direction of travel.

        Notes
        -----
        The nearest point sample (a k-d tree) is refined on its two adjacent segments (straight chords).
        The offset is then exact to the chord's sagitta, ``ds^2 / (8 R)`` (6e-6 m at R = 50 m); the arc
        length to ``|offset| ds / (2 R)`` (4 mm for a point 3 m off a 20 m circle). Beyond the ends the foot is clamped to the
        end point and the offset is the component normal to the end segment. Where the line passes a
        place twice (several laps of a circle) the nearer pass wins, and either may be returned.
        """
        px, py = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        shape = px.shape
        px = px.ravel()
        py = py.ravel()
        _, i = self._tree.query(np.column_stack((px, py)))
        s, off = self._foot(np.asarray(i, dtype=np.int64), px, py)
        return s.reshape(shape), off.reshape(shape)

    def track(self, x, y, *, back: int = 40, ahead: int = 400) -> tuple[np.ndarray, np.ndarray]:
        """Like :meth:`project`, for the successive positions of a vehicle driving along the line.

        The nearest point is searched near the previous one (``back`` points behind, ``ahead`` points
        ahead), so the arc length grows lap after lap on a line that passes a place twice (a circle driven
        several times), where :meth:`project` may return either pass.
        """
        px = np.asarray(x, dtype=np.float64).ravel()
        py = np.asarray(y, dtype=np.float64).ravel()
        n = self.x_m.size
        idx = np.empty(px.size, dtype=np.int64)
        j = 0
        for k in range(px.size):
            lo, hi = max(j - back, 0), min(j + ahead, n)
            d2 = (self.x_m[lo:hi] - px[k]) ** 2 + (self.y_m[lo:hi] - py[k]) ** 2
            j = lo + int(np.argmin(d2))
            idx[k] = j
        return self._foot(idx, px, py)

    def _foot(self, i: np.ndarray, px: np.ndarray, py: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Refine the nearest points ``i`` on their two adjacent segments: arc length and signed offset."""
        n = self.x_m.size
        best_s = np.empty_like(px)
        best_off = np.empty_like(px)
        best_d2 = np.full_like(px, np.inf)
        for a in (np.maximum(i - 1, 0), np.minimum(i, n - 2)):
            b = a + 1
            ex = self.x_m[b] - self.x_m[a]
            ey = self.y_m[b] - self.y_m[a]
            seg = np.hypot(ex, ey)
            ux, uy = ex / seg, ey / seg
            rx, ry = px - self.x_m[a], py - self.y_m[a]
            along = rx * ux + ry * uy
            t = np.clip(along / seg, 0.0, 1.0)
            d2 = (rx - t * ex) ** 2 + (ry - t * ey) ** 2
            better = d2 < best_d2
            best_d2 = np.where(better, d2, best_d2)
            best_s = np.where(better, self.s_m[a] + t * (self.s_m[b] - self.s_m[a]), best_s)
            best_off = np.where(better, ux * ry - uy * rx, best_off)
        return best_s, best_off


# --------------------------------------------------------------------------------------------------------------
# construction helpers
# --------------------------------------------------------------------------------------------------------------
def _number(value, where: str, *, positive: bool = False, minimum: float | None = None) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise InputError(f"expected a number, got {value!r}", where=where)
    value = float(value)
    if not math.isfinite(value):
        raise InputError(f"expected a finite number, got {value!r}", where=where)
    if positive and value <= 0.0:
        raise InputError(f"must be > 0, got {value:g}", where=where)
    if minimum is not None and value < minimum:
        raise InputError(f"must be >= {minimum:g}, got {value:g}", where=where)
    return value


def _direction(direction, where: str = "direction") -> float:
    if direction not in ("left", "right"):
        raise InputError(f"expected 'left' or 'right', got {direction!r}", where=where)
    return 1.0 if direction == "left" else -1.0


def _uniform_count(length_m: float, where: str = "path") -> int:
    """Number of points so that the spacing is at most DS_MAX_M, for a line of at most MAX_LENGTH_M."""
    _check_length(length_m, where)
    return int(math.ceil(length_m / DS_MAX_M - 1e-9)) + 1


def _check_length(length_m: float, where: str) -> None:
    if not length_m <= MAX_LENGTH_M:
        raise InputError(f"the line would be {length_m:.4g} m long; at most {MAX_LENGTH_M:g} m", where=where)


def _sine_blend(t):
    """One sine period of second derivative: b(t) = t - sin(2 pi t) / (2 pi) on [0, 1], and b', b''.

    b(0) = 0, b(1) = 1; b' and b'' vanish at both ends, so a line built from it has continuous heading and
    curvature. ``t`` is clipped to [0, 1] (constant outside).
    """
    t = np.clip(t, 0.0, 1.0)
    w = 2.0 * np.pi * t
    return t - np.sin(w) / (2.0 * np.pi), 1.0 - np.cos(w), 2.0 * np.pi * np.sin(w)


def _lateral_profile(x, y_start: float, transitions):
    """y(x), y'(x), y''(x) of a line made of constant-y stretches joined by sine blends.

    ``transitions`` is a sequence of ``(x_from, x_to, y_to)`` in increasing x, non-overlapping.
    """
    y = np.full_like(x, y_start)
    dy = np.zeros_like(x)
    ddy = np.zeros_like(x)
    level = y_start
    for x_from, x_to, y_to in transitions:
        span = x_to - x_from
        delta = y_to - level
        b, db, ddb = _sine_blend((x - x_from) / span)
        y += delta * b
        dy += delta * db / span
        ddy += delta * ddb / span**2
        level = y_to
    return y, dy, ddy


def _from_graph(profile, x_end: float, **meta) -> Path:
    """A path y = f(x) for 0 <= x <= x_end, resampled uniformly in arc length.

    ``profile(x)`` returns y, y', y'' (exact derivatives). Arc length is integrated on a dense grid
    (trapezoid, dx = 5 mm); the uniform points are located on it and then evaluated exactly, so positions,
    heading and curvature are those of the analytic line.
    """
    _check_length(x_end, meta.get("name", "path"))
    xd = np.linspace(0.0, x_end, int(math.ceil(x_end / _DENSE_DX_M)) + 1)
    _, dyd, _ = profile(xd)
    g = np.hypot(1.0, dyd)
    sd = np.concatenate(([0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(xd))))
    s = np.linspace(0.0, sd[-1], _uniform_count(sd[-1]))
    x = np.interp(s, sd, xd)
    y, dy, ddy = profile(x)
    return Path(
        x_m=x,
        y_m=y,
        s_m=s,
        heading_rad=np.arctan(dy),
        curvature_per_m=ddy / (1.0 + dy * dy) ** 1.5,
        **meta,
    )


def _lane_cones(corridor: Corridor, xs) -> list[tuple[float, float]]:
    """Cones on both limits of a lane at the given x, their base circles tangent to the lane limits."""
    r = CONE_RADIUS_M
    return [(float(x), corridor.y_max_m + r) for x in xs] + [(float(x), corridor.y_min_m - r) for x in xs]


def _mirror(corridor: Corridor, sign: float) -> Corridor:
    if sign > 0:
        return corridor
    return Corridor(corridor.x_start_m, corridor.x_end_m, -corridor.y_max_m, -corridor.y_min_m, corridor.name)


# --------------------------------------------------------------------------------------------------------------
# ISO 3888 double lane change
# --------------------------------------------------------------------------------------------------------------
_ISO3888 = ("ISO 3888-1", "ISO 3888-2")


def _iso3888_track(w: float, standard: str):
    """Section lengths [m] and lanes (section names, x_from, x_to, y_min, y_max) for a left-first track.

    x from the start of section 1; y = 0 on the centre of section 1.
    """
    if standard == "ISO 3888-1":
        lengths = (15.0, 30.0, 25.0, 25.0, 15.0, 15.0)
        a = 1.1 * w + 0.25  # section 1
        b = 1.2 * w + 0.25  # section 3
        c = 1.3 * w + 0.25  # sections 5 and 6
        y3_min = -0.5 * a + 3.5  # lane offset 3.5 m between the right-hand limits of sections 1 and 3
    else:  # ISO 3888-2
        lengths = (12.0, 13.5, 11.0, 12.5, 12.0)
        a = 1.1 * w + 0.25
        b = w + 1.0
        c = max(1.3 * w + 0.25, 3.0)
        y3_min = 0.5 * a + 1.0  # lane offset 1 m: gap between the left limit of section 1 and the right of section 3
    edges = np.concatenate(([0.0], np.cumsum(lengths)))
    lanes = [
        (("section 1",), edges[0], edges[1], -0.5 * a, 0.5 * a),
        (("section 3",), edges[2], edges[3], y3_min, y3_min + b),
        # exit lane: its right-hand limit continues that of section 1
        (
            ("section 5", "section 6") if len(lengths) == 6 else ("section 5",),
            edges[4],
            edges[-1],
            -0.5 * a,
            -0.5 * a + c,
        ),
    ]
    return lengths, edges, lanes


def double_lane_change(
    vehicle_width_m: float,
    *,
    run_in_m: float = 30.0,
    run_out_m: float = 30.0,
    standard: str = "ISO 3888-1",
    direction: str = "left",
) -> Path:
    """Double lane change track: ISO 3888-1 (default) or ISO 3888-2, cones, lanes and a reference line.

    Parameters
    ----------
    vehicle_width_m : float
        Vehicle width w [m] (the paper's e-trike: 1.25 m). The lane widths are functions of it.
    run_in_m : float
        Straight approach before section 1 [m]; section 1 starts at ``x = run_in_m``.
    run_out_m : float
        Straight after the last section, on the exit-lane centre [m].
    standard : {"ISO 3888-1", "ISO 3888-2"}
        ISO 3888-1 double lane change (the paper's test) or ISO 3888-2 obstacle avoidance.
    direction : {"left", "right"}
        Side of the first lane change (the paper's: left).

    Returns
    -------
    Path
        With one corridor per lane section and the cones.

    Notes
    -----
    **ISO 3888-1** (Passenger cars -- Test track for a severe lane-change manoeuvre -- Part 1: Double
    lane-change), Table 1, as Project Chrono's ISO 3888 helper implements it and other public models cite
    it from the 1999 edition (we could not read the standard's text; we assume the 2018 edition the paper
    cites kept the track):

    ========  ==========  ==================  =====================================
    section   length [m]  lane width [m]      lateral position
    ========  ==========  ==================  =====================================
    1         15          1.1 w + 0.25        reference lane
    2         30          --                  --
    3         25          1.2 w + 0.25        lane offset 3.5 m
    4         25          --                  --
    5         15          1.3 w + 0.25        right-hand limit in line with section 1
    6         15          1.3 w + 0.25        as section 5
    ========  ==========  ==================  =====================================

    Total 125 m. For w = 1.25 m the lanes are 1.625, 1.75 and 1.875 m wide; for w = 2 m, 2.45, 2.65 and
    2.85 m. *Choice*: the standard gives a "lane offset" of 3.5 m; we measure it between the right-hand
    lane limits of sections 1 and 3 (same-side cone lines), so the lane centres are 3.5 + 0.05 w m apart
    (3.5625 m for the e-trike). Project Chrono measures it from the centre of section 1 to the right-hand
    limit of section 3 (centres 3.5 + (1.2 w + 0.25)/2 apart, 4.375 m for the e-trike), and simple models
    take it centre to centre; a reading of the standard's Figure 1 settles it.

    **ISO 3888-2** (Part 2: Obstacle avoidance, 2011), clause 4.1 and Table 1, as Project Chrono and other
    public tracks implement it: sections of 12, 13.5, 11, 12.5 and 12 m (total 61 m, as 4.1 states); lanes 1.1 w + 0.25 (section 1), w + 1 (section 3, its
    right-hand limit 1 m left of the left-hand limit of section 1) and 1.3 w + 0.25 but not less than 3 m
    (section 5, right-hand limit in line with section 1). *Uncertain*: public implementations disagree on
    section 5 (Project Chrono: 3 m; others: 1.3 w + 0.25 capped at 3 m); we take "not less than 3 m".

    **Cones**: at the start, the middle and the end of each lane (sections 1, 3 and the exit lane: for
    ISO 3888-1 sections 5 and 6 together), on both limits, as Project Chrono and other public tracks
    place them. ISO 3888-2 clause 4.2 puts the lane limits tangent to the cones' base circles; we do the
    same for both parts, so cone centres lie ``CONE_RADIUS_M`` outside the corridor edges.

    **Reference line** (the standards prescribe the cones, not a line): the lane centres, joined across
    the free sections 2 and 4 by a sine blend -- the lateral position ``y = y0 + D (u - sin(2 pi u)/(2 pi))``,
    ``u`` the fraction of the free section -- which is the ISO 14791 lane-change shape. Heading and
    curvature are continuous (the curvature rate jumps at the ends of a blend); the line is straight and
    centred in every lane section, so a vehicle on it keeps ``(lane width - w) / 2`` to each limit.
    """
    w = _number(vehicle_width_m, "vehicle_width_m", positive=True)
    if w > 5.0:
        raise InputError(f"expected a vehicle width in metres (<= 5), got {w:g}", where="vehicle_width_m")
    run_in = _number(run_in_m, "run_in_m", minimum=0.0)
    run_out = _number(run_out_m, "run_out_m", minimum=0.0)
    if standard not in _ISO3888:
        raise InputError(f"expected one of {', '.join(_ISO3888)}, got {standard!r}", where="standard")
    sign = _direction(direction)

    lengths, edges, lanes = _iso3888_track(w, standard)
    corridors: list[Corridor] = []
    cones: list[tuple[float, float]] = []
    centres = []
    for names, x_from, x_to, y_min, y_max in lanes:
        x_from += run_in
        x_to += run_in
        lane = Corridor(x_from, x_to, y_min, y_max, " + ".join(names))
        cones += _lane_cones(lane, (x_from, 0.5 * (x_from + x_to), x_to))
        centres.append(lane.centre_y_m)
        cut = x_from
        for k, name in enumerate(names):  # one corridor per section
            x_cut = x_to if k == len(names) - 1 else cut + (x_to - x_from) / len(names)
            corridors.append(Corridor(cut, x_cut, y_min, y_max, name))
            cut = x_cut
    e = edges + run_in
    transitions = ((e[1], e[2], centres[1]), (e[3], e[4], centres[2]))
    x_end = e[-1] + run_out

    def profile(x):
        y, dy, ddy = _lateral_profile(x, centres[0], transitions)
        return sign * y, sign * dy, sign * ddy

    cones_xy = np.array(cones)
    cones_xy[:, 1] *= sign
    lane_text = ", ".join(f"{c.name} {c.width_m:.3f} m" for c in corridors)
    return _from_graph(
        profile,
        x_end,
        name=f"{standard} {'double lane change' if standard == 'ISO 3888-1' else 'obstacle avoidance'}",
        cones=cones_xy,
        corridors=tuple(_mirror(c, sign) for c in corridors),
        description=(
            f"{standard} (Table 1) track for vehicle width {w:g} m, first change to the {direction}: "
            f"sections {', '.join(f'{v:g}' for v in lengths)} m (total {sum(lengths):g} m) from x = {run_in:g} m; "
            f"lanes {lane_text}. "
            + (
                "Lane offset 3.5 m taken between the right-hand limits of sections 1 and 3 (our reading). "
                if standard == "ISO 3888-1"
                else "Section 5 width: 1.3 w + 0.25 m, not less than 3 m (our reading; sources differ). "
            )
            + "Cones at the start, middle and end of each lane, tangent to the lane limits. Reference line: "
            "lane centres joined by sine blends (one sine period of curvature) across the free sections; "
            f"run-in {run_in:g} m, run-out {run_out:g} m."
        ),
    )


# --------------------------------------------------------------------------------------------------------------
# ISO 14791 single lane change
# --------------------------------------------------------------------------------------------------------------
def single_lane_change(
    *,
    lateral_offset_m: float = 3.5,
    length_m: float = 50.0,
    run_in_m: float = 30.0,
    run_out_m: float = 30.0,
    lane_width_m: float = 3.5,
) -> Path:
    """Single lane change (ISO 14791:2000): one full sine period of lateral acceleration.

    Parameters
    ----------
    lateral_offset_m : float
        Lateral displacement A of the lane change [m], positive to the left (the paper's: left).
    length_m : float
        Longitudinal length L of the lane change [m].
    run_in_m, run_out_m : float
        Straights before and after it [m]; the change starts at ``x = run_in_m``.
    lane_width_m : float
        Width of the start and the target lane [m] (corridors and cones).

    Returns
    -------
    Path
        Corridors "start lane" (the run-in) and "target lane" (the run-out), cones at their ends.

    Notes
    -----
    ISO 14791 (Road vehicles -- Heavy commercial vehicle combinations and articulated buses -- Lateral
    stability test methods) drives the single lane change along a path whose lateral acceleration is one
    full sine period. Over the change, with ``x' = x - run_in_m``::

        y(x') = A (x'/L - sin(2 pi x'/L) / (2 pi))
        a_y   = v^2 y'' = (2 pi A v^2 / L^2) sin(2 pi x'/L)   (small slope, constant speed)

    so the peak lateral acceleration is ``2 pi A v^2 / L^2`` and its frequency ``v / L``. The path's exact
    curvature, which this function returns, is ``y'' / (1 + y'^2)^1.5``; at the peak the slope is A/L, so
    it falls short of ``y''`` by about ``1.5 (A/L)^2``: under 1 % for L > 12 A (0.7 % with the defaults).

    *Choices* (the standard's text was not available to us; it is written for heavy vehicles and sets the
    test by speed and lateral-acceleration frequency): the offset defaults to 3.5 m (one road lane) and the
    length to 50 m, so that the peak lateral acceleration, 0.0088 v^2, is moderate at the e-trike's test
    speeds (0.6 m/s^2 at 30 km/h, 1.7 m/s^2 at 50 km/h). Shorten ``length_m`` for a sharper change
    (``L = v / f`` for a lateral-acceleration frequency ``f``). Lanes of 3.5 m by default.
    """
    a = _number(lateral_offset_m, "lateral_offset_m")
    if a == 0.0:
        raise InputError("must not be 0 (positive: to the left, negative: to the right)", where="lateral_offset_m")
    span = _number(length_m, "length_m", positive=True)
    run_in = _number(run_in_m, "run_in_m", minimum=0.0)
    run_out = _number(run_out_m, "run_out_m", minimum=0.0)
    width = _number(lane_width_m, "lane_width_m", positive=True)
    x0, x1 = run_in, run_in + span
    x_end = x1 + run_out
    corridors = []
    cones: list[tuple[float, float]] = []
    if run_in > 0.0:
        lane = Corridor(0.0, x0, -0.5 * width, 0.5 * width, "start lane")
        corridors.append(lane)
        cones += _lane_cones(lane, (0.0, x0))
    if run_out > 0.0:
        lane = Corridor(x1, x_end, a - 0.5 * width, a + 0.5 * width, "target lane")
        corridors.append(lane)
        cones += _lane_cones(lane, (x1, x_end))

    def profile(x):
        return _lateral_profile(x, 0.0, ((x0, x1, a),))

    return _from_graph(
        profile,
        x_end,
        name="ISO 14791 single lane change",
        cones=np.array(cones) if cones else np.zeros((0, 2)),
        corridors=tuple(corridors),
        description=(
            f"ISO 14791:2000 single lane change: lateral offset {a:g} m over {span:g} m from x = {run_in:g} m, "
            "y = A (x'/L - sin(2 pi x'/L)/(2 pi)): one sine period of lateral acceleration, peak "
            f"2 pi A v^2/L^2 = {2 * math.pi * abs(a) / span**2:.4g} v^2 m/s^2. Offset and length are our choices "
            f"(not taken from the standard's text). Lanes {width:g} m wide: start lane over the run-in, target "
            f"lane over the run-out ({run_out:g} m), cones at their ends tangent to the lane limits."
        ),
    )


# --------------------------------------------------------------------------------------------------------------
# ISO 4138 circle, straight
# --------------------------------------------------------------------------------------------------------------
def circle(radius_m: float, *, laps: float = 1.0, run_in_m: float = 10.0, direction: str = "left") -> Path:
    """Constant-radius circle (ISO 4138 steady-state circular driving, constant-radius method).

    Parameters
    ----------
    radius_m : float
        Radius of the reference line [m].
    laps : float
        Number of laps (fractions allowed).
    run_in_m : float
        Straight along +x before the circle [m]; the circle is tangent to it at ``x = run_in_m``.
    direction : {"left", "right"}
        Turning direction (left: counter-clockwise seen from above, centre at ``(run_in_m, +R)``).

    Returns
    -------
    Path
        No cones, no corridors.

    Notes
    -----
    ISO 4138 (Passenger cars -- Steady-state circular driving behaviour -- Open-loop test methods) leaves
    the radius to the tester (a large radius such as 100 m is usual for cars; a trike's lower speeds suit
    a smaller one). The curvature steps from 0 to 1/R where the run-in meets the circle; the driver's
    preview smooths the entry. The heading keeps growing over the laps (it is not wrapped).
    """
    r = _number(radius_m, "radius_m", positive=True, minimum=1.0)
    n_laps = _number(laps, "laps", positive=True)
    run_in = _number(run_in_m, "run_in_m", minimum=0.0)
    sign = _direction(direction)
    total = run_in + 2.0 * math.pi * r * n_laps
    if not total <= MAX_LENGTH_M:
        raise InputError(f"run_in_m {run_in:g} m + {n_laps:g} lap(s) of radius {r:g} m make {total:.4g} m; at "
                         f"most {MAX_LENGTH_M:g} m", where="circle")
    s = np.linspace(0.0, total, _uniform_count(total, "circle"))
    phi = np.clip(s - run_in, 0.0, None) / r
    on_circle = s > run_in
    x = np.where(on_circle, run_in + r * np.sin(phi), s)
    y = sign * r * (1.0 - np.cos(phi))
    return Path(
        name=f"ISO 4138 circle R = {r:g} m",
        x_m=x,
        y_m=y,
        s_m=s,
        heading_rad=sign * phi,
        curvature_per_m=np.where(on_circle, sign / r, 0.0),
        description=(
            f"ISO 4138 constant-radius circle, R = {r:g} m, {n_laps:g} lap(s) to the {direction}, "
            f"after a {run_in:g} m straight run-in (curvature steps to 1/R at the entry)."
        ),
    )


def straight(length_m: float) -> Path:
    """A straight line along +x from the origin.

    Parameters
    ----------
    length_m : float
        Length [m].
    """
    length = _number(length_m, "length_m", positive=True)
    s = np.linspace(0.0, length, _uniform_count(length, "length_m"))
    zero = np.zeros_like(s)
    return Path(
        name="straight",
        x_m=s.copy(),
        y_m=zero,
        s_m=s,
        heading_rad=zero.copy(),
        curvature_per_m=zero.copy(),
        description=f"straight line along +x, {length:g} m",
    )


# --------------------------------------------------------------------------------------------------------------
# CSV paths
# --------------------------------------------------------------------------------------------------------------
def _read_xy_csv(file: _FilePath) -> tuple[np.ndarray, np.ndarray]:
    try:
        if not file.is_file():
            raise InputError("no such file", where=str(file))
        size = file.stat().st_size
    except (OSError, ValueError) as exc:
        raise InputError(f"cannot read it: {getattr(exc, 'strerror', None) or exc}", where=str(file)) from None
    if size > MAX_CSV_BYTES:
        raise InputError(f"{size / 2**20:.0f} MiB; a path CSV is read up to {MAX_CSV_BYTES // 2**20} MiB", where=str(file))
    reader = None
    try:
        with file.open(encoding="utf-8-sig", newline="") as handle:
            reader = csv.reader(handle)
            return _parse_xy_rows(reader, file)
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the file as UTF-8 text: {exc}", where=str(file)) from None
    except csv.Error as exc:
        where = f"{file}:{reader.line_num}" if reader is not None else str(file)
        raise InputError(f"not a CSV line: {exc}", where=where) from None


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
                    shown = ", ".join(h[:40] for h in header[:20]) or "none"
                    raise InputError(f"missing column '{names[0]}' (or '{names[1]}'); found {shown}", where=where)
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
                raise InputError(f"{name}: expected a number, got {cell[:40]!r}", where=where) from None
            if not math.isfinite(value):
                raise InputError(f"{name}: expected a finite number, got {cell[:40]!r}", where=where)
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
        longer than ``MAX_LENGTH_M`` (20 km) or a file larger than ``MAX_CSV_BYTES``.

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


# --------------------------------------------------------------------------------------------------------------
# judging a run
# --------------------------------------------------------------------------------------------------------------
def _trajectory(time_s, x_m, y_m, yaw_rad):
    arrays = []
    for value, name in ((time_s, "time_s"), (x_m, "x_m"), (y_m, "y_m"), (yaw_rad, "yaw_rad")):
        arrays.append(_array(value, name))
    n = arrays[0].size
    for arr, name in zip(arrays[1:], ("x_m", "y_m", "yaw_rad"), strict=True):
        if arr.size != n:
            raise InputError(f"has {arr.size} samples, time_s has {n}", where=name)
    return arrays


def _footprint(footprint):
    try:
        x_rear, x_front, half_width = (float(v) for v in footprint)
    except (TypeError, ValueError):
        raise InputError(
            f"expected (x_rear_m, x_front_m, half_width_m), got {footprint!r}", where="footprint"
        ) from None
    if not (math.isfinite(x_rear) and math.isfinite(x_front) and math.isfinite(half_width)):
        raise InputError("values must be finite", where="footprint")
    if x_front <= x_rear or half_width <= 0.0:
        raise InputError(f"expected x_rear_m < x_front_m and half_width_m > 0, got {footprint!r}", where="footprint")
    return x_rear, x_front, half_width


def cone_strikes(
    path: Path, time_s, x_m, y_m, yaw_rad, footprint, *, cone_radius_m: float = CONE_RADIUS_M
) -> list[dict]:
    """Cones the vehicle footprint touches, each once, with the time of first contact.

    Parameters
    ----------
    path : Path
        The manoeuvre (its ``cones``).
    time_s, x_m, y_m, yaw_rad : array_like
        Trajectory samples: time [s], position of the vehicle reference point [m] and yaw angle [rad].
    footprint : tuple of float
        ``(x_rear_m, x_front_m, half_width_m)``: the vehicle's plan rectangle in its own axes relative to the
        reference point [m] (e.g. ``(-0.6, 2.4, 0.625)`` for a reference point on the rear axle).
    cone_radius_m : float
        Radius of a cone's base circle [m].

    Returns
    -------
    list of dict
        ``{"cone": index, "x_m": ..., "y_m": ..., "time_s": ...}`` ordered by time.

    Notes
    -----
    A cone is struck at a sample when its base circle overlaps the rectangle (distance from the cone
    centre to the rectangle <= radius). Contact between samples is not interpolated: sample finely
    (0.01 s is 0.2 m at 72 km/h).
    """
    t, x, y, yaw = _trajectory(time_s, x_m, y_m, yaw_rad)
    x_rear, x_front, half_width = _footprint(footprint)
    r = _number(cone_radius_m, "cone_radius_m", minimum=0.0)
    cones = path.cones
    if cones.shape[0] == 0 or t.size == 0:
        return []
    c, s = np.cos(yaw), np.sin(yaw)
    first = np.full(cones.shape[0], -1, dtype=np.int64)
    chunk = max(1, 2_000_000 // cones.shape[0])
    for start in range(0, t.size, chunk):
        sl = slice(start, start + chunk)
        dx = cones[None, :, 0] - x[sl, None]
        dy = cones[None, :, 1] - y[sl, None]
        bx = c[sl, None] * dx + s[sl, None] * dy  # cone centre in vehicle axes
        by = -s[sl, None] * dx + c[sl, None] * dy
        ex = bx - np.clip(bx, x_rear, x_front)
        ey = by - np.clip(by, -half_width, half_width)
        hit = ex * ex + ey * ey <= r * r
        new = hit.any(axis=0) & (first < 0)
        if np.any(new):
            first[new] = start + np.argmax(hit[:, new], axis=0)
        if np.all(first >= 0):
            break
    struck = np.flatnonzero(first >= 0)
    order = struck[np.argsort(first[struck], kind="stable")]
    return [
        {"cone": int(k), "x_m": float(cones[k, 0]), "y_m": float(cones[k, 1]), "time_s": float(t[first[k]])}
        for k in order
    ]


def corridor_violations(path: Path, time_s, x_m, y_m, yaw_rad, footprint) -> list[dict]:
    """Episodes in which a footprint corner leaves the lane section it is in.

    Parameters
    ----------
    path : Path
        The manoeuvre (its ``corridors``).
    time_s, x_m, y_m, yaw_rad : array_like
        Trajectory samples: time [s], position of the vehicle reference point [m] and yaw angle [rad].
    footprint : tuple of float
        ``(x_rear_m, x_front_m, half_width_m)`` in vehicle axes relative to the reference point [m].

    Returns
    -------
    list of dict
        One entry per corridor and run of consecutive violating samples, ordered by start time:
        ``{"corridor": index, "name", "side": "left"|"right", "time_start_s", "time_end_s",
        "time_worst_s", "worst_excursion_m", "samples"}``; the excursion is how far the worst corner is
        beyond the lane limit [m].

    Notes
    -----
    A corner is judged against a corridor when its x lies within the corridor's x range. The corners
    bound the rectangle's lateral extent, so a straight lane limit is crossed first by a corner.
    """
    t, x, y, yaw = _trajectory(time_s, x_m, y_m, yaw_rad)
    x_rear, x_front, half_width = _footprint(footprint)
    if not path.corridors or t.size == 0:
        return []
    bx = np.array([x_front, x_front, x_rear, x_rear])
    by = np.array([half_width, -half_width, half_width, -half_width])
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    cx = x[:, None] + c * bx - s * by
    cy = y[:, None] + s * bx + c * by
    out = []
    for index, lane in enumerate(path.corridors):
        within = (cx >= lane.x_start_m) & (cx <= lane.x_end_m)
        left = np.where(within, cy - lane.y_max_m, -np.inf)
        right = np.where(within, lane.y_min_m - cy, -np.inf)
        excess = np.maximum(left.max(axis=1), right.max(axis=1))
        bad = excess > 0.0
        if not np.any(bad):
            continue
        edges = np.diff(np.concatenate(([0], bad.astype(np.int8), [0])))
        for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True):
            worst = a + int(np.argmax(excess[a:b]))
            out.append(
                {
                    "corridor": index,
                    "name": lane.name,
                    "side": "left" if left[worst].max() >= right[worst].max() else "right",
                    "time_start_s": float(t[a]),
                    "time_end_s": float(t[b - 1]),
                    "time_worst_s": float(t[worst]),
                    "worst_excursion_m": float(excess[worst]),
                    "samples": int(b - a),
                }
            )
    out.sort(key=lambda v: (v["time_start_s"], v["corridor"]))
    return out
