"""The manoeuvre: what the vehicle is asked to do, and where it is judged.

A :class:`Manoeuvre` is one of two kinds:

- **closed loop**: a :class:`~trikedyn.manoeuvres.paths.Path` the driver model follows at a target speed
  profile (ISO 3888-1, ISO 14791, ISO 4138, a path from a CSV file, ...);
- **open loop**: a steer command against time (ISO 7401 step, a sine sweep, a fishhook), with the speed
  held by the driver's speed controller; optionally the driver follows a path first and then holds the
  steering still (ISO 7975 braking in a turn: ``steer_hold_s``).

Every manoeuvre carries its **judged window** (:class:`Window`): where the test is scored, from the entry
gate to the exit gate (distance along the path for closed-loop tests, time for open-loop ones). A
closed-loop path goes on beyond the exit gate (its **run-out**, see :func:`with_run_out`) so that the
driver never runs out of road: the run is simulated a little past the exit, and nothing outside the
window is judged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError
from .paths import DS_MAX_M, Path
from .speed import SpeedProfile

__all__ = ["Manoeuvre", "Window", "check_duration", "path_manoeuvre", "time_to_cover", "whole_path", "with_run_out"]

MAX_DURATION_S = 3600.0
"""Longest manoeuvre accepted [s] (a longer one is almost certainly a unit mistake)."""

SPEED_JUDGED = ("window", "entry", "none")
"""Where a manoeuvre's target speed is held (:attr:`Manoeuvre.speed_judged`)."""

AFTER_EXIT_S = 1.0
"""Simulated time beyond the moment the vehicle is due at the exit gate [s] (a slower vehicle still
reaches it; the steer command in the run-out is checked by the tests)."""


@dataclass(frozen=True)
class Window:
    """Where a run is judged.

    Parameters
    ----------
    kind : {"distance", "time"}
        ``"distance"``: arc length of the path at the vehicle's CG [m]; ``"time"``: time [s].
    start, end : float
        Entry and exit gates [m or s].
    """

    kind: str
    start: float
    end: float

    def __post_init__(self):
        if self.kind not in ("distance", "time"):
            raise InputError(f"expected 'distance' or 'time', got {self.kind!r}", where="window.kind")
        if not (math.isfinite(self.start) and math.isfinite(self.end)) or self.end <= self.start:
            raise InputError(f"needs finite start < end, got {self.start!r}, {self.end!r}", where="window")

    def to_dict(self) -> dict:
        """The window as a JSON-safe dict.

        Returns
        -------
        dict
            ``kind``, ``start``, ``end`` and their ``unit`` (``m`` for a distance window, ``s`` for a time window).
        """
        return {"kind": self.kind, "start": self.start, "end": self.end,
                "unit": "m" if self.kind == "distance" else "s"}


@dataclass(frozen=True, eq=False)
class Manoeuvre:
    """A test for the vehicle: a path or open-loop steering, a target speed, a judged window.

    Parameters
    ----------
    name : str
        The registry name (``dlc``, ``slc``, ``circle``, ...).
    title : str
        Human-readable name with its standard.
    speed : SpeedProfile
        Target speed of the driver's speed controller.
    duration_s : float
        Simulated time [s].
    window : Window
        Where the run is judged.
    path : Path, optional
        The line the driver follows (closed loop), run-out included. Open-loop manoeuvres may give one to
        judge the path error, or none.
    steer : numpy.ndarray, optional
        ``(n, 2)`` open-loop steer command table: time [s], angle about the steering axis [rad], positive
        left. When given, the driver does not steer (open loop).
    steer_hold_s : float, optional
        From this time on the driver holds the steering still (the command it had then).
    parameters : dict
        The options it was built with (JSON-safe), for the record.
    description : str
        What the test is and the choices made.
    speed_judged : {"window", "entry", "none"}
        Where a run must hold its target speed (:mod:`trikedyn.analysis.verdict`, ``speed not held``):
        through the whole window (the lane changes, driven at a constant speed), only at the entry gate (an
        open-loop steer whose standard takes the speed at the start of the steer: ISO 7401, the fishhook;
        what the steer does to the speed afterwards is part of the test), or nowhere.
    """

    name: str
    title: str
    speed: SpeedProfile
    duration_s: float
    window: Window
    path: Path | None = None
    steer: np.ndarray | None = None
    steer_hold_s: float | None = None
    parameters: dict = field(default_factory=dict)
    description: str = ""
    speed_judged: str = "window"

    def __post_init__(self):
        if self.path is None and self.steer is None:
            raise InputError("a manoeuvre needs a path (closed loop) or a steer table (open loop)", where=self.name)
        if not (math.isfinite(self.duration_s) and 0 < self.duration_s <= MAX_DURATION_S):
            raise InputError(f"duration must be > 0 and <= {MAX_DURATION_S:g} s, got {self.duration_s!r}",
                             where=self.name)
        if self.steer is not None:
            table = np.ascontiguousarray(self.steer, dtype=np.float64)
            if table.ndim != 2 or table.shape[1] != 2 or table.shape[0] < 1 or not np.all(np.isfinite(table)):
                raise InputError("steer must be finite (time, angle) rows", where=f"{self.name}.steer")
            if table.shape[0] > 1 and np.any(np.diff(table[:, 0]) <= 0):
                raise InputError("steer times must increase", where=f"{self.name}.steer")
            object.__setattr__(self, "steer", table)
        if self.speed_judged not in SPEED_JUDGED:
            raise InputError(f"expected one of {', '.join(SPEED_JUDGED)}, got {self.speed_judged!r}",
                             where=f"{self.name}.speed_judged")
        if self.window.kind == "distance" and self.path is None:
            raise InputError("a distance window needs a path", where=f"{self.name}.window")

    @property
    def closed_loop(self) -> bool:
        """True when the driver steers along the path."""
        return self.steer is None

    def lasting(self, duration_s: float) -> Manoeuvre:
        """The same manoeuvre simulated for ``duration_s`` [s]; a longer run gets a longer run-out, so the
        driver still never reaches the end of the path.

        Parameters
        ----------
        duration_s : float
            Simulated time [s], > 0 and at most ``MAX_DURATION_S``.

        Returns
        -------
        Manoeuvre
            The copy.

        Raises
        ------
        InputError
            On a duration out of range.
        """
        duration = check_duration(self.name, float(duration_s))
        path = self.path
        if path is not None and duration > self.duration_s:
            path = with_run_out(path, (duration - self.duration_s) * float(self.speed.speed_mps.max()))
        return replace(self, duration_s=duration, path=path)

    def at_speed(self, speed: SpeedProfile) -> Manoeuvre:
        """The same closed-loop manoeuvre (distance window) driven at another target speed profile.

        Parameters
        ----------
        speed : SpeedProfile
            The new target speed profile (time [s], speed [m/s]).

        Returns
        -------
        Manoeuvre
            The manoeuvre rebuilt with the same gates and parameters.

        Raises
        ------
        InputError
            For a manoeuvre judged over time (open loop).
        """
        if self.window.kind != "distance":
            raise InputError("only a manoeuvre judged over distance can change its speed profile", where=self.name)
        return path_manoeuvre(self.name, self.title, self.path, speed, entry_m=self.window.start,
                              exit_m=self.window.end, parameters=self.parameters, description=self.description,
                              speed_judged=self.speed_judged)

    def to_dict(self) -> dict:
        """JSON-safe summary.

        Returns
        -------
        dict
            Name, title, loop, duration [s], window, speed, path, steer hold [s], parameters, description.
        """
        return {
            "name": self.name,
            "title": self.title,
            "closed_loop": self.closed_loop,
            "duration_s": self.duration_s,
            "window": self.window.to_dict(),
            "speed": self.speed.to_dict(),
            "path": None if self.path is None else self.path.to_dict(),
            "steer_hold_s": self.steer_hold_s,
            "parameters": dict(self.parameters),
            "description": self.description,
            "speed_judged": self.speed_judged,
        }


def check_duration(name: str, seconds: float) -> float:
    """``seconds`` if it is a duration a manoeuvre may last (before any array of that length is made).

    Parameters
    ----------
    name : str
        The manoeuvre, for the error's location.
    seconds : float
        The duration [s].

    Returns
    -------
    float
        ``seconds`` [s].

    Raises
    ------
    InputError
        If not finite, not positive or over ``MAX_DURATION_S``.
    """
    if not (math.isfinite(seconds) and 0 < seconds <= MAX_DURATION_S):
        raise InputError(f"duration must be > 0 and <= {MAX_DURATION_S:g} s, got {seconds:g} s", where=name)
    return seconds


def time_to_cover(speed: SpeedProfile, distance_m: float) -> float:
    """Time [s] at which a vehicle at exactly the target speed has covered ``distance_m`` [m].

    Beyond the profile's end the last speed holds.

    Parameters
    ----------
    speed : SpeedProfile
        Target speed profile (time [s], speed [m/s]).
    distance_m : float
        Distance [m].

    Returns
    -------
    float
        Time [s].

    Raises
    ------
    InputError
        When the profile ends at zero speed short of the distance.
    """
    t, v = speed.time_s, speed.speed_mps
    covered = np.concatenate(([0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))))
    if distance_m <= covered[-1]:
        return float(np.interp(distance_m, covered, t))
    if v[-1] <= 0:
        raise InputError("the target speed ends at 0 before the manoeuvre is covered", where="speed")
    return float(t[-1] + (distance_m - covered[-1]) / v[-1])


def with_run_out(path: Path, length_m: float) -> Path:
    """``path`` continued beyond its end by ``length_m`` [m] with its end curvature.

    A straight end goes on straight; a circle goes on round the circle. The points keep the path's spacing.

    Parameters
    ----------
    path : Path
        The line.
    length_m : float
        Length to add [m]; nothing for <= 0.

    Returns
    -------
    Path
        The longer line (``path`` itself when nothing is added).
    """
    if length_m <= 0:
        return path
    ds = min(path.ds_m, DS_MAX_M)
    n = int(math.ceil(length_m / ds))
    s_add = ds * np.arange(1, n + 1)
    kappa = float(path.curvature_per_m[-1])
    h0 = float(path.heading_rad[-1])
    x0, y0 = float(path.x_m[-1]), float(path.y_m[-1])
    if abs(kappa) < 1e-9:
        heading = np.full(n, h0)
        x = x0 + s_add * math.cos(h0)
        y = y0 + s_add * math.sin(h0)
    else:
        heading = h0 + kappa * s_add
        x = x0 + (np.sin(heading) - math.sin(h0)) / kappa
        y = y0 - (np.cos(heading) - math.cos(h0)) / kappa
    return Path(
        name=path.name,
        x_m=np.concatenate((path.x_m, x)),
        y_m=np.concatenate((path.y_m, y)),
        s_m=np.concatenate((path.s_m, path.s_m[-1] + s_add)),
        heading_rad=np.concatenate((path.heading_rad, heading)),
        curvature_per_m=np.concatenate((path.curvature_per_m, np.full(n, kappa))),
        cones=path.cones,
        corridors=path.corridors,
        description=path.description + f" Run-out: the line goes on {length_m:.0f} m beyond its end.",
    )


def path_manoeuvre(name: str, title: str, path: Path, speed: SpeedProfile, *, entry_m: float, exit_m: float,
                   parameters: dict | None = None, description: str = "", preview_s: float = 2.0,
                   speed_judged: str = "window") -> Manoeuvre:
    """A closed-loop manoeuvre on ``path`` judged from ``entry_m`` to ``exit_m`` (arc length of the CG).

    The run lasts until the vehicle, at its target speed, is due ``AFTER_EXIT_S`` past the exit gate; the
    path is extended (:func:`with_run_out`) far enough that the driver's preview never reaches its end.

    Parameters
    ----------
    name : str
        Registered name.
    title : str
        Human title.
    path : Path
        The reference line.
    speed : SpeedProfile
        Target speed profile (time [s], speed [m/s]).
    entry_m, exit_m : float
        Gates along the path (arc length) [m].
    parameters : dict, optional
        The options it was built with.
    description : str
        Standard and choices, for the report.
    preview_s : float
        Driver preview time the run-out must cover [s].
    speed_judged : str
        Where the speed is judged (``"window"`` or ``"entry"``).

    Returns
    -------
    Manoeuvre
        The closed-loop manoeuvre.

    Raises
    ------
    InputError
        When the gates are not on the path.
    """
    if not (0.0 <= entry_m < exit_m <= path.s_m[-1] + 1e-9):
        raise InputError(f"gates {entry_m:g} .. {exit_m:g} m must lie on the path (0 .. {path.s_m[-1]:g} m)",
                         where=name)
    duration = check_duration(name, time_to_cover(speed, exit_m) + AFTER_EXIT_S)
    v_max = float(speed.speed_mps.max())
    needed = exit_m + v_max * (AFTER_EXIT_S + preview_s) + 10.0  # CG ahead of the start, preview, margin
    full = with_run_out(path, max(0.0, needed - float(path.s_m[-1])))
    return Manoeuvre(name=name, title=title, speed=speed, duration_s=duration, window=Window("distance", entry_m, exit_m),
                     path=full, parameters=dict(parameters or {}), description=description, speed_judged=speed_judged)


def whole_path(path: Path, speed: SpeedProfile) -> Manoeuvre:
    """A bare :class:`~trikedyn.manoeuvres.paths.Path` as a manoeuvre judged over its whole length.

    Parameters
    ----------
    path : Path
        The reference line.
    speed : SpeedProfile
        Target speed profile (time [s], speed [m/s]).

    Returns
    -------
    Manoeuvre
        Gates at the path's start and end.
    """
    return path_manoeuvre(path.name, path.name, path, speed, entry_m=0.0, exit_m=float(path.s_m[-1]),
                          description=path.description)
