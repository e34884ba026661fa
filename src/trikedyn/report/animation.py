"""Animations of a run: the trike driving through the cones (plan view, or in 3d) or seen from behind (rear
view).

Pure drawing. A :class:`~trikedyn.report.scene.Scene` (trajectory, wheel loads, outline, course) is made
from a :class:`~trikedyn.simulate.result.Result` or from a run file's channels
(:func:`~trikedyn.report.scene.scene_from`); :func:`animate` writes it as a GIF (Pillow, no external
program), an HTML page with a JavaScript player, or an MP4 (needs ffmpeg). matplotlib is imported inside the functions.

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
from pathlib import Path

import numpy as np

from ..errors import InputError
from ._drawing import CONE, LIFTED, load_bars, plain
from .scene import Scene, check_frames, frame_indices

__all__ = ["CONE", "FORMATS", "LIFTED", "VIEWS", "animate", "ffmpeg_available"]

VIEWS = ("plan", "rear", "3d")
FORMATS = (".gif", ".html", ".mp4")
FIGSIZE_IN = (6.0, 4.0)
FOLLOW_HALF_SPAN_M = (11.0, 7.0)  # half the plan view's window along x and y [m], centred ahead of the vehicle
TYRE_WIDTH_M = 0.2


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
        :class:`~trikedyn.report.scene.Scene` made by :func:`~trikedyn.report.scene.scene_from`.
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
        Unknown view or format, fps or every_s out of range, more than
        :data:`~trikedyn.report.scene.MAX_FRAMES` frames (counted before any is drawn), MP4 without ffmpeg.
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
