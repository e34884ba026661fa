"""Animations of a run: the trike driving through the cones (plan view, or in 3d) or seen from behind (rear
view).

Pure drawing. A :class:`Scene` (trajectory, wheel loads, outline, course) is made from a
:class:`~trikedyn.simulate.result.Result` or from a run file's channels (:func:`scene_from`);
:func:`animate` writes it as a GIF (Pillow, no external program), an HTML page with a JavaScript player,
or an MP4 (needs ffmpeg). matplotlib is imported inside the functions.

- **plan**: a view that follows the vehicle (22 m x 14 m) under a strip with the whole course; the body
  outline, the three wheels (shaded by their vertical load, red when lifted), the trail of the CG, the
  cones (red once struck), bars of the wheel loads, time [s] and speed [km/h];
- **rear**: the body seen from behind, rolled by its roll angle, and the wheel loads as bars;
- **3d**: the body as a box rolled and pitched by the run's angles, the wheels as discs shaded by their load,
  cones and lanes on the ground, seen by a camera that follows the vehicle
  (:mod:`trikedyn.report.animation_3d`).
"""

from __future__ import annotations

import html
import math
import shutil
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ._drawing import CONE, LIFTED, load_bars, plain

__all__ = ["CONE", "FORMATS", "LIFTED", "MAX_FRAMES", "VIEWS", "Scene", "animate", "check_frames", "ffmpeg_available",
           "frame_indices", "scene_channels", "scene_from"]

VIEWS = ("plan", "rear", "3d")
FORMATS = (".gif", ".html", ".mp4")
MAX_FRAMES = 2000
"""Most frames of one animation: a few minutes to draw, a few hundred MB of GIF frames in memory; a longer run
takes a larger time between frames (``--every-s``)."""
FIGSIZE_IN = (6.0, 4.0)
FOLLOW_HALF_SPAN_M = (11.0, 7.0)  # half the plan view's window along x and y [m], centred ahead of the vehicle
TYRE_WIDTH_M = 0.2


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


def ffmpeg_available() -> bool:
    """True when matplotlib can write MP4 (an ``ffmpeg`` program is installed).

    Returns
    -------
    bool
        Whether MP4 can be written.
    """
    from matplotlib import animation

    return bool(animation.writers.is_available("ffmpeg"))


def _rotate(points, angle, dx=0.0, dy=0.0):
    c, s = math.cos(angle), math.sin(angle)
    p = np.asarray(points, dtype=float)
    return np.column_stack((dx + c * p[:, 0] - s * p[:, 1], dy + s * p[:, 0] + c * p[:, 1]))


def _box(x0, x1, half):
    return np.array([(x0, -half), (x1, -half), (x1, half), (x0, half)])


def _axes(ax, xlabel, ylabel, title=None):
    """Equal scales, small labels; returns the text box for time, speed, ..."""
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(xlabel, fontsize=7)
    ax.set_ylabel(ylabel, fontsize=7)
    ax.tick_params(labelsize=7)
    if title is not None:
        ax.set_title(title, fontsize=8, pad=2)
    return ax.text(0.01, 0.97, "", transform=ax.transAxes, va="top", fontsize=8, family="monospace", zorder=6,
                   bbox={"fc": "white", "ec": "0.6", "alpha": 0.85, "pad": 2})


def _draw_course(ax, scene, small=False):
    """Lanes (grey), reference line (dashed) and cones (orange triangles); returns the cones' artist."""
    from matplotlib.patches import Rectangle

    for x0, x1, y0, y1 in scene.corridors:
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color="0.9", lw=0, zorder=0))
    if scene.path_xy is not None:
        ax.plot(scene.path_xy[:, 0], scene.path_xy[:, 1], ls="--", lw=0.6, color="0.55", zorder=1)
    if scene.cones_xy.shape[0]:
        return ax.scatter(scene.cones_xy[:, 0], scene.cones_xy[:, 1], marker="^", s=6 if small else 28, c=CONE,
                          edgecolors="k", linewidths=0.3 if small else 0.5, zorder=3)
    return None


def _plan(fig, scene):
    """The plan view: the whole course above, a window following the vehicle below; returns ``update(i)``."""
    from matplotlib.patches import Polygon, Rectangle

    grid = fig.add_gridspec(2, 2, height_ratios=(1.0, 4.2), width_ratios=(5.0, 1.0), hspace=0.32, wspace=0.25,
                            left=0.09, right=0.93, top=0.93, bottom=0.1)
    over, ax, side = fig.add_subplot(grid[0, :]), fig.add_subplot(grid[1, 0]), fig.add_subplot(grid[1, 1])
    cgx, cgy = scene.cg_xy
    _draw_course(over, scene, small=True)
    over.plot(cgx, cgy, lw=0.6, color="0.3")
    points = np.vstack([np.column_stack((cgx, cgy)), *([] if scene.path_xy is None else [scene.path_xy])])
    (x0, y0), (x1, y1) = points.min(axis=0) - 2.0, points.max(axis=0) + 2.0
    over.set(xlim=(x0, x1), ylim=(y0, y1))
    over.tick_params(labelsize=6)
    over.set_title(plain(scene.title or "run"), fontsize=8, pad=2)
    dot, = over.plot([], [], "o", ms=4, color="k", zorder=5)
    half_x, half_y = FOLLOW_HALF_SPAN_M
    window = over.add_patch(Rectangle((0, 0), 2 * half_x, 2 * half_y, fill=False, lw=0.6, color="k"))

    cones = _draw_course(ax, scene)
    trail, = ax.plot([], [], lw=1.2, color="#2ca02c", zorder=2)
    outline = _box(*scene.footprint_m)
    body = ax.add_patch(Polygon(outline, closed=True, fc="#c7c7c7", ec="k", lw=0.8, alpha=0.85, zorder=4))
    tyres = {n: ax.add_patch(Polygon(np.zeros((4, 2)), closed=True, ec="k", lw=0.5, zorder=5)) for n in scene.wheels}
    text = _axes(ax, "x [m]", "y [m]")
    ax.grid(alpha=0.25)
    bars, colour = load_bars(side, scene, list(range(len(scene.loads_N))), 0.7)
    side.yaxis.tick_right()
    side.set_title("Fz [kN]", fontsize=7, pad=2)

    def update(i):
        """Draw sample ``i``."""
        t, x, y, yaw = scene.time_s[i], scene.x_m[i], scene.y_m[i], scene.yaw_rad[i]
        body.set_xy(_rotate(outline, yaw, x, y))
        lifted = []
        for name, (wx, wy, radius, steered) in scene.wheels.items():
            local = _rotate(_box(-radius, radius, TYRE_WIDTH_M / 2), scene.steer_rad[i] if steered else 0.0, wx, wy)
            tyres[name].set_xy(_rotate(local, yaw, x, y))
            fz = float(scene.loads_N[name][i])
            tyres[name].set_facecolor(colour(fz))
            lifted += [name] if fz <= 0.0 else []
        bars(i)
        trail.set_data(cgx[: i + 1], cgy[: i + 1])
        if cones is not None:
            cones.set_facecolors([LIFTED if hit <= t else CONE for hit in scene.cone_hit_s])
        cx, cy = x + 0.35 * half_x * math.cos(yaw), y + 0.35 * half_x * math.sin(yaw)  # a little ahead
        ax.set_xlim(cx - half_x, cx + half_x)
        ax.set_ylim(cy - half_y, cy + half_y)
        window.set_xy((cx - half_x, cy - half_y))
        dot.set_data([cgx[i]], [cgy[i]])
        lines = [f"t = {t:6.2f} s", f"v = {3.6 * scene.speed_mps[i]:6.1f} km/h"]
        lines += [f"cones struck {int(np.sum(scene.cone_hit_s <= t))}"] if scene.cones_xy.shape[0] else []
        lines += [plain(f"LIFT: {', '.join(lifted)}")] if lifted else []
        text.set_text("\n".join(lines))
        text.get_bbox_patch().set_edgecolor(LIFTED if lifted else "0.6")

    return update


def _rear(fig, scene):
    """The rear view: the body rolled by its roll angle above, the wheel loads below; returns ``update(i)``."""
    from matplotlib.patches import Polygon, Rectangle

    grid = fig.add_gridspec(2, 1, height_ratios=(3.0, 1.3), hspace=0.35, left=0.1, right=0.97, top=0.92, bottom=0.1)
    ax, low = fig.add_subplot(grid[0]), fig.add_subplot(grid[1])
    half = scene.footprint_m[2]
    pivot = max(w[2] for w in scene.wheels.values())  # roll drawn about a line at axle height
    height = max(2.0 * scene.cg_m[2], pivot + 1.0)
    # body outline in (y [m], z - pivot [m]); seen from behind, the vehicle's left (+y) is on the left (h = -y)
    outline = np.array([(half, 0.0), (-half, 0.0), (-half, height - pivot), (half, height - pivot)])
    for _, wy, r, _ in scene.wheels.values():
        ax.add_patch(Rectangle((-wy - TYRE_WIDTH_M / 2, 0.0), TYRE_WIDTH_M, 2 * r, color="0.2",
                               alpha=0.35 if abs(wy) < 1e-6 else 1.0, zorder=1))
    ax.axhline(0.0, color="0.4", lw=1.0)
    body = ax.add_patch(Polygon(np.zeros((4, 2)), closed=True, fc="#c7c7c7", ec="k", lw=1.0, alpha=0.9, zorder=2))
    cg, = ax.plot([], [], "o", ms=5, color="k", zorder=3)
    text = _axes(ax, "<- left   lateral [m]   right ->  (seen from behind)", "height [m]", plain(scene.title or "run"))
    ax.set_xlim(-half - 0.6, half + 0.6)
    ax.set_ylim(-0.1, height + 0.35)
    positions = [-w[1] for w in scene.wheels.values()]
    if len(set(np.round(positions, 3))) < len(positions):
        positions = list(np.linspace(-half, half, len(positions)))
    bars, _ = load_bars(low, scene, positions, 0.25)
    low.set_xlim(ax.get_xlim())
    low.set_title("wheel loads Fz [kN] (red: lifted)", fontsize=7, pad=2)

    def update(i):
        """Draw sample ``i``."""
        phi = float(scene.roll_rad[i])  # about x forward: y' = y cos - z sin, z' = y sin + z cos
        turned = _rotate(outline, phi, 0.0, pivot)
        body.set_xy(np.column_stack((-turned[:, 0], turned[:, 1])))
        g = _rotate(np.array([[scene.cg_m[1], scene.cg_m[2] - pivot]]), phi, 0.0, pivot)[0]
        cg.set_data([-g[0]], [g[1]])
        bars(i)
        lifted = [n for n, fz in scene.loads_N.items() if fz[i] <= 0.0]
        lines = [f"t = {scene.time_s[i]:6.2f} s   v = {3.6 * scene.speed_mps[i]:5.1f} km/h",
                 f"roll = {math.degrees(phi):+5.2f} deg"]
        lines += [plain(f"LIFT: {', '.join(lifted)}")] if lifted else []
        text.set_text("\n".join(lines))

    return update


def _writer(suffix: str, fps: int):
    """A matplotlib movie writer for ``suffix``: GIF frames kept as 64-colour palette images (a quarter of
    Pillow's memory), HTML with the frames embedded as PNG, MP4 by ffmpeg."""
    from matplotlib import animation

    if suffix == ".html":
        return animation.HTMLWriter(fps=fps, embed_frames=True, default_mode="once", embed_limit=1000.0)
    if suffix == ".mp4":
        return animation.FFMpegWriter(fps=fps)
    from PIL import Image

    class SmallGif(animation.PillowWriter):
        """Pillow's GIF writer keeping each frame as a 64-colour palette image."""

        def grab_frame(self, **savefig_kwargs):
            """Grab the frame and quantise it."""
            super().grab_frame(**savefig_kwargs)
            self._frames[-1] = self._frames[-1].convert("RGB").quantize(64, method=Image.Quantize.FASTOCTREE)

    return SmallGif(fps=fps)


def animate(result, path, view: str = "plan", fps: int = 10, every_s: float = 0.1, dpi: int = 100) -> int:
    """Write an animation of a run.

    Parameters
    ----------
    result : Result or Scene
        The run (:class:`~trikedyn.simulate.result.Result`, with its manoeuvre for the cones), or a
        :class:`Scene` made by :func:`scene_from`.
    path : str or Path
        Output file: ``.gif`` (Pillow), ``.html`` (a page with a JavaScript player) or ``.mp4`` (needs
        ffmpeg). Written atomically; an existing file is replaced.
    view : {"plan", "rear", "3d"}
        The trike through the cones seen from above, the body's roll and the wheel loads from behind, or the
        trike rolling and pitching through the cones in 3d, seen by a camera that follows it.
    fps : int
        Frames per second of the animation [1/s].
    every_s : float
        Simulated time between frames [s] (``every_s * fps = 1`` plays in real time).
    dpi : int
        Resolution [dots per inch] of the 6 x 4 in figure.

    Returns
    -------
    int
        Number of frames written.

    Raises
    ------
    InputError
        Unknown view or format, fps or every_s out of range, more than :data:`MAX_FRAMES` frames (counted
        before any is drawn), MP4 without ffmpeg.
    """
    from .._files import atomic_write

    path = Path(path)
    suffix = path.suffix.lower()
    if view not in VIEWS:
        raise InputError(f"expected one of {', '.join(VIEWS)}, got {view!r}", where="view")
    if suffix not in FORMATS:
        raise InputError(f"expected a {', '.join(FORMATS)} file name", where=str(path))
    if not (isinstance(fps, int | np.integer) and 1 <= fps <= 60):
        raise InputError(f"must be a whole number from 1 to 60 frames/s, got {fps!r}", where="fps")
    if not (math.isfinite(every_s) and 0.001 <= every_s <= 60.0):
        raise InputError(f"must be >= 0.001 and <= 60 s, got {every_s!r}", where="every_s")
    if suffix == ".mp4" and not ffmpeg_available():
        raise InputError("writing .mp4 needs ffmpeg, which is not installed; write a .gif or .html instead",
                         where=str(path))
    if not isinstance(result, Scene):
        check_frames(result.time_s, every_s)  # before the scene is made
    scene = result if isinstance(result, Scene) else Scene.from_result(result)
    frames = frame_indices(scene.time_s, every_s)
    from matplotlib.figure import Figure  # no pyplot: the user's backend and figures are left alone

    fig = Figure(figsize=FIGSIZE_IN, dpi=dpi, facecolor="white")
    if view == "3d":
        from .animation_3d import draw_3d as draw
    else:
        draw = _plan if view == "plan" else _rear
    update = draw(fig, scene)
    writer = _writer(suffix, fps)
    with tempfile.TemporaryDirectory(prefix="trikedyn-anim-") as folder:
        scratch = Path(folder) / f"animation{suffix}"
        with writer.saving(fig, scratch, dpi):  # one draw per frame (FuncAnimation would draw twice)
            for i in frames:
                update(int(i))
                writer.grab_frame()
        if suffix == ".html":  # the writer's player is a fragment: make it a page
            page = (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>'
                    f"{html.escape(scene.title or 'trikedyn run')}</title></head>\n<body>\n"
                    f"{scratch.read_text(encoding='utf-8')}\n</body></html>\n")
            atomic_write(path, lambda fh: fh.write(page), binary=False)
        else:
            with scratch.open("rb") as source:
                atomic_write(path, lambda fh: shutil.copyfileobj(source, fh))
    return int(frames.size)
