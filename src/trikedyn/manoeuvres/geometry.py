"""Path geometry: the :class:`Path` the driver follows (reference line, cones, lane corridors), and the
helpers that build lines from analytic profiles (sine blends, arc-length resampling).

Axes are ISO 8855 (x forward, y left). Every line starts at the origin heading +x; arrays are float64 and
C-contiguous, ready for compiled code.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..errors import InputError

__all__ = ["CONE_RADIUS_M", "DS_MAX_M", "MAX_LENGTH_M", "Corridor", "Path"]

DS_MAX_M = 0.05
"""Largest spacing of the reference-line points [m]."""

CONE_RADIUS_M = 0.15
"""Radius of a cone's base circle [m] (our choice; the standards ask for cones at least 500 mm high)."""

MAX_LENGTH_M = 20_000.0
"""Longest reference line [m] (20 km: over 30 min at 40 km/h; 400 000 points at DS_MAX_M)."""

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
        """JSON-safe dict of the corridor.

        Returns
        -------
        dict
            Name, x range [m], y range [m] and width [m].
        """
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

        Returns
        -------
        numpy.ndarray, shape (n, 5)
            Columns x [m], y [m], s [m], heading [rad], curvature [1/m].
        """
        return np.ascontiguousarray(
            np.column_stack((self.x_m, self.y_m, self.s_m, self.heading_rad, self.curvature_per_m))
        )

    def to_dict(self) -> dict:
        """JSON-safe summary: name, length, point spacing, cone count, corridors, description.

        Returns
        -------
        dict
            The summary (lengths [m]).
        """
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

        Parameters
        ----------
        x, y : array_like
            Successive positions [m].
        back, ahead : int
            Search span behind and ahead of the previous nearest point, in path points.

        Returns
        -------
        s_m : numpy.ndarray
            Arc length of each position's foot on the line [m].
        offset_m : numpy.ndarray
            Signed distance from the line [m], positive to the left.
        """
        px = np.asarray(x, dtype=np.float64).ravel()
        py = np.asarray(y, dtype=np.float64).ravel()
        from ._nearest import track_indices

        idx = track_indices(np.ascontiguousarray(self.x_m, dtype=np.float64),
                            np.ascontiguousarray(self.y_m, dtype=np.float64), px, py, int(back), int(ahead))
        return self._foot(idx, px, py)

    def _foot(self, i: np.ndarray, px: np.ndarray, py: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Refine the nearest points ``i`` on their two adjacent segments: arc length and signed offset
        (:func:`~trikedyn.manoeuvres._nearest.feet`)."""
        from ._nearest import feet

        return feet(np.ascontiguousarray(self.x_m, dtype=np.float64), np.ascontiguousarray(self.y_m, dtype=np.float64),
                    np.ascontiguousarray(self.s_m, dtype=np.float64), np.ascontiguousarray(i, dtype=np.int64),
                    np.ascontiguousarray(px, dtype=np.float64), np.ascontiguousarray(py, dtype=np.float64))


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
        y[x >= x_to] += delta  # past the blend: the whole step (b = 1, b' = b'' = 0)
        inside = (x > x_from) & (x < x_to)  # before it: nothing (b = b' = b'' = 0)
        b, db, ddb = _sine_blend((x[inside] - x_from) / span)
        y[inside] += delta * b
        dy[inside] += delta * db / span
        ddy[inside] += delta * ddb / span**2
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
