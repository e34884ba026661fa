"""What an animation draws, and when: the :class:`Scene` of a run (trajectory, wheel loads, outline, course),
made from a :class:`~trikedyn.simulate.result.Result` or from a run file's channels (:func:`scene_from`, after
:func:`scene_channels` checks them), and the frames picked from its samples (:func:`check_frames`,
:func:`frame_indices`).

Pure data, no drawing: :mod:`trikedyn.report.animation` draws a scene, and the run figures draw its snapshots.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError

__all__ = ["MAX_FRAMES", "Scene", "check_frames", "frame_indices", "scene_channels", "scene_from"]


MAX_FRAMES = 2000
"""Most frames of one animation: a few minutes to draw, a few hundred MB of GIF frames in memory; a longer run
takes a larger time between frames (``--every-s``)."""
@dataclass(frozen=True)
class Scene:
    """What an animation draws.

    Attributes
    ----------
    time_s, x_m, y_m, yaw_rad, roll_rad, speed_mps, steer_rad : numpy.ndarray
        Time [s]; chassis reference point (rear-axle centre) [m]; yaw and roll [rad]; speed [m/s]; steer
        angle [rad] (drawn as the steered wheels' angle).
    loads_N : dict of str to numpy.ndarray
        Vertical load of each wheel [N].
    wheels : dict of str to tuple
        Each wheel's ``(x_m, y_m, radius_m, steered)`` in chassis axes [m].
    footprint_m : tuple of float
        ``(x_rear, x_front, half_width)``: the body's plan rectangle about the reference point [m].
    cg_m : tuple of float
        CG ``(x, y, z)`` in chassis axes [m] (the trail follows it).
    path_xy : numpy.ndarray or None
        ``(n, 2)`` reference line [m].
    cones_xy : numpy.ndarray
        ``(k, 2)`` cone positions [m].
    corridors : tuple
        Lane sections ``(x_start, x_end, y_min, y_max)`` [m].
    cone_hit_s : numpy.ndarray
        Time each cone is first struck [s] (inf: never).
    title : str
    pitch_rad : numpy.ndarray or None
        Pitch [rad], positive nose down (the 3d view); None: level.
    """

    time_s: np.ndarray
    x_m: np.ndarray
    y_m: np.ndarray
    yaw_rad: np.ndarray
    roll_rad: np.ndarray
    speed_mps: np.ndarray
    steer_rad: np.ndarray
    loads_N: dict
    wheels: dict
    footprint_m: tuple
    cg_m: tuple = (0.0, 0.0, 0.5)
    path_xy: np.ndarray | None = None
    cones_xy: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    corridors: tuple = ()
    cone_hit_s: np.ndarray = field(default_factory=lambda: np.zeros(0))
    title: str = ""
    pitch_rad: np.ndarray | None = None

    @classmethod
    def from_result(cls, result) -> Scene:
        """The scene of a run held in memory (its manoeuvre and vehicle come with it).

        Parameters
        ----------
        result : Result
            A run that carries its vehicle and manoeuvre.

        Returns
        -------
        Scene
            The scene.

        Raises
        ------
        InputError
            When the run does not carry its vehicle.
        """
        if result.params is None:
            raise InputError("the run does not carry its vehicle (result.params)", where="result")
        channels = {"time_s": result.time_s, **dict(result.channels)}
        return scene_from(channels, result.meta, manoeuvre=result.manoeuvre, params=result.params)

    @property
    def cg_xy(self) -> tuple[np.ndarray, np.ndarray]:
        """Plan-view position of the CG [m]."""
        cx, cy = self.cg_m[0], self.cg_m[1]
        c, s = np.cos(self.yaw_rad), np.sin(self.yaw_rad)
        return self.x_m + cx * c - cy * s, self.y_m + cx * s + cy * c


def scene_channels(channels: Mapping, meta: Mapping, where: str = "run") -> tuple[dict, list[str]]:
    """The channels an animation draws, checked before anything is rebuilt from the run: ``time_s`` (at least
    2 samples), ``x_m``, ``y_m``, ``yaw_rad``, ``speed_mps`` and each wheel's ``<wheel>_fz_N`` as finite
    floats; ``roll_rad``, ``pitch_rad`` and ``steer_rad`` too when recorded (0 otherwise).

    Parameters
    ----------
    channels : mapping of str to array_like
        The run's channels (SI units).
    meta : mapping
        The run's metadata (``wheels``).
    where : str
        Names the run in errors.

    Returns
    -------
    channels : dict of str to numpy.ndarray
    wheels : list of str
        The wheels: ``meta["wheels"]`` when the run has each one's load, else every ``<wheel>_fz_N`` channel.

    Raises
    ------
    InputError
        A channel missing, not numbers, not finite or of another length than the time; fewer than 2 samples;
        no wheel loads.
    """
    if "time_s" not in channels:
        raise InputError("not a run of trikedyn: no channel 'time_s'", where=where)
    try:
        n = len(channels["time_s"])
    except TypeError:
        raise InputError("channel 'time_s' is not a sequence of times", where=where) from None
    if n < 2:
        raise InputError("fewer than 2 samples; nothing to animate", where=where)

    def channel(name, default=None):
        """The channel ``name`` as finite floats (``default`` throughout when it is not recorded)."""
        if name not in channels:
            if default is not None:
                return np.full(n, default)
            raise InputError(f"not a run of trikedyn: no channel '{name}'", where=where)
        try:
            values = np.asarray(channels[name], dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"channel '{name}' holds values that are not numbers", where=where) from None
        if values.shape != (n,):
            raise InputError(f"channel '{name}' has {values.size} values for {n} times", where=where)
        if not np.all(np.isfinite(values)):
            raise InputError(f"channel '{name}' holds NaN or infinite values", where=where)
        return values

    out = {name: channel(name) for name in ("time_s", "x_m", "y_m", "yaw_rad", "speed_mps")}
    out |= {name: channel(name, 0.0) for name in ("roll_rad", "pitch_rad", "steer_rad")}
    listed = meta.get("wheels")
    names = [str(w) for w in listed] if isinstance(listed, list | tuple) and listed and all(
        f"{w}_fz_N" in channels for w in listed) else [str(c)[: -len("_fz_N")] for c in channels
                                                         if str(c).endswith("_fz_N")]
    if not names:
        raise InputError("not a run of trikedyn: no wheel loads ('<wheel>_fz_N')", where=where)
    out |= {f"{w}_fz_N": channel(f"{w}_fz_N") for w in names}
    return out, names


def scene_from(channels: Mapping, meta: Mapping, *, params, manoeuvre=None, where: str = "run") -> Scene:
    """A :class:`Scene` from a run's channels and metadata.

    Parameters
    ----------
    channels : mapping of str to array_like
        ``time_s`` [s], ``x_m``, ``y_m`` [m], ``yaw_rad``, ``speed_mps`` [m/s], and per wheel
        ``<wheel>_fz_N`` [N]; ``roll_rad``, ``pitch_rad`` and ``steer_rad`` [rad] if recorded
        (:func:`scene_channels`).
    meta : mapping
        The run's metadata: ``wheels``, ``vehicle``, ``manoeuvre`` (each optional; for the title).
    params : VehicleParameters
        The vehicle (or an object with the same attributes): ``wheels`` (``name``, ``x_m``, ``y_m``,
        ``radius_m``, ``steered``), ``wheelbase_m``, ``body.overall_length_m`` and ``overall_width_m``,
        ``mass.cg_x_m``, ``cg_y_m`` and ``cg_z_m`` [m].
    manoeuvre : Manoeuvre, optional
        Its path gives the reference line, lanes and cones.
    where : str
        Names the run in errors.

    Returns
    -------
    Scene
        The scene.

    Raises
    ------
    InputError
        A channel the animation needs is missing or not finite, there are fewer than 2 samples, or the vehicle
        has none of the run's wheels.
    """
    data, names = scene_channels(channels, meta, where)
    t = data["time_s"]
    loads = {n: data[f"{n}_fz_N"] for n in names}
    overhang = max(params.body.overall_length_m - params.wheelbase_m, 0.0) / 2  # as closed_loop.footprint
    footprint = (-overhang, params.wheelbase_m + overhang, params.body.overall_width_m / 2)
    wheels = {w.name: (w.x_m, w.y_m, w.radius_m, w.steered) for w in params.wheels if w.name in loads}
    if not wheels:
        raise InputError(f"the vehicle has none of the run's wheels ({', '.join(names)})", where=where)
    cg = (params.mass.cg_x_m, params.mass.cg_y_m, params.mass.cg_z_m)
    path = getattr(manoeuvre, "path", None)
    x, y, yaw = data["x_m"], data["y_m"], data["yaw_rad"]
    from ..manoeuvres.judging import cone_strikes  # the judge's own test: the footprint touches the cone

    hits = np.full(0 if path is None else path.cones.shape[0], np.inf)
    for strike in [] if path is None else cone_strikes(path, t, x, y, yaw, footprint):
        hits[strike["cone"]] = strike["time_s"]
    title = " - ".join(str(v) for v in (meta.get("vehicle"), getattr(manoeuvre, "title", None)
                                       or meta.get("manoeuvre")) if v)
    return Scene(t, x, y, yaw, data["roll_rad"], data["speed_mps"], data["steer_rad"], loads,
                 wheels, footprint, cg,
                 None if path is None else np.column_stack((path.x_m, path.y_m)),
                 np.zeros((0, 2)) if path is None else np.asarray(path.cones, dtype=float),
                 tuple((c.x_start_m, c.x_end_m, c.y_min_m, c.y_max_m) for c in getattr(path, "corridors", ())),
                 hits, title, data["pitch_rad"])


def check_frames(time_s, every_s: float, max_frames: int = MAX_FRAMES) -> int:
    """The number of frames ``t0, t0 + every_s, ...`` over ``time_s`` [s], counted before any is made.

    Parameters
    ----------
    time_s : array_like
        Sample times [s].
    every_s : float
        Time between frames [s].
    max_frames : int
        Largest number of frames.

    Returns
    -------
    int
        The number of frames.

    Raises
    ------
    InputError
        More than ``max_frames`` (``where="every_s"``), saying the time between frames that fits.
    """
    t = np.asarray(time_s, dtype=float)
    span = float(t[-1] - t[0]) if t.size else 0.0
    wanted = math.floor(span / every_s + 1e-9) + 1 if math.isfinite(span / every_s) else math.inf
    if wanted > max_frames:
        fits = span / (max_frames - 1)
        raise InputError(f"{span:.6g} s of run every {every_s:g} s is {wanted:.6g} frames, more than the "
                         f"{max_frames} drawn; take a time between frames of at least {_up(fits)} s",
                         where="every_s")
    return int(wanted)


def _up(x: float) -> str:
    """``x`` rounded up to 3 significant digits, as text."""
    if x <= 0:
        return "0"
    scale = 10 ** (math.floor(math.log10(x)) - 2)
    return f"{math.ceil(x / scale - 1e-9) * scale:.6g}"


def frame_indices(time_s, every_s: float, max_frames: int = MAX_FRAMES) -> np.ndarray:
    """Sample indices nearest to ``t0, t0 + every_s, ...`` up to the end of the run (the last one included).

    Parameters
    ----------
    time_s : array_like
        Sample times [s].
    every_s : float
        Time between frames [s].
    max_frames : int
        Largest number of frames.

    Returns
    -------
    numpy.ndarray of int
        Sample indices.

    Raises
    ------
    InputError
        More than ``max_frames`` times asked for (:func:`check_frames`).
    """
    check_frames(time_s, every_s, max_frames)
    t = np.asarray(time_s, dtype=float)
    wanted = np.arange(t[0], t[-1] + 1e-9, every_s)
    idx = np.clip(np.searchsorted(t, wanted), 0, t.size - 1)
    earlier = np.clip(idx - 1, 0, t.size - 1)
    idx = np.where(np.abs(t[earlier] - wanted) <= np.abs(t[idx] - wanted), earlier, idx)
    return np.unique(np.append(idx, t.size - 1))
