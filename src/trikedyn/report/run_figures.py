"""Figures of one run an engineer would show (``trikedyn plot RUN --kind KIND``).

Each is a pure function ``figure_<kind>(source, meta=None) -> matplotlib.figure.Figure`` of a run: a
:class:`~trikedyn.simulate.result.Result`, a run file's table (``pandas.DataFrame``) or a mapping of channel
names to arrays (``time_s`` among them); ``meta`` is the run's metadata (a Result's own when left out). The
figures are made without pyplot (matplotlib is imported inside the functions); save them with
:func:`trikedyn.report.figures.save`.

* ``time`` -- stacked time histories: speed [km/h], lateral acceleration [m/s²], yaw rate [deg/s],
  roll [deg], rollover index (Eq. 5), the judged window shaded grey;
* ``wheel-loads`` -- each wheel's vertical load [N], the lift (Fz <= 0) shaded red;
* ``plan`` -- the CG path through the lanes and cones, the vehicle's footprint at intervals;
* ``gg`` -- the g-g diagram (longitudinal against lateral acceleration [g]);
* ``roll`` -- roll angle [deg] against lateral acceleration [m/s²], with the roll gradient.

The run's channels, labels, judged window and lifts are read by :mod:`trikedyn.report.run_channels`.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import InputError, did_you_mean
from ._drawing import plain
from .run_channels import judged_window, label_of, lift_spans, need_channel, run_source, title_of, wheel_names

__all__ = ["KINDS", "MAX_FOOTPRINTS", "figure", "figure_gg", "figure_plan", "figure_roll", "figure_time",
           "figure_wheel_loads"]

G = 9.80665  # standard gravity [m/s²]
LIFT = "#d62728"
WINDOW = "0.85"

TIME_CHANNELS = ("speed_mps", "ay_mps2", "yaw_rate_radps", "roll_rad", "ri")
MAX_FOOTPRINTS = 200
"""Most footprints drawn in the plan view."""


def _shade_window(ax, window, label=None) -> None:
    if window is not None:
        ax.axvspan(*window, color=WINDOW, alpha=0.6, lw=0, zorder=0, label=label, gid="judged")


def _new(figsize):
    from matplotlib.figure import Figure

    return Figure(figsize=figsize, layout="constrained")


def _grid(ax) -> None:
    ax.grid(alpha=0.3)
    ax.tick_params(labelsize=8)


# --- the figures ------------------------------------------------------------------------------------------------

def figure_time(source, meta=None, channels: list[str] | None = None):
    """Stacked time histories: speed [km/h], lateral acceleration [m/s²], yaw rate [deg/s], roll [deg] and the
    rollover index RI (Eq. 5), or the ``channels`` named (each labelled with its unit); the judged window grey.

    Parameters
    ----------
    source : Result, pandas.DataFrame or mapping
        The run (channels in SI units, ``time_s`` [s]).
    meta : mapping, optional
        Its metadata (a Result's own by default).
    channels : list of str, optional
        The channels to draw.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.

    Raises
    ------
    InputError
        A channel asked for is not in the run.
    """
    data, meta = run_source(source, meta)
    names = list(channels) if channels else [c for c in TIME_CHANNELS if c in data]
    for name in names:
        if name not in data:
            raise InputError(f"no channel '{name}'" + did_you_mean(name, list(data)), where="run")
    if not names:
        raise InputError("the run holds none of the channels to plot", where="run")
    t, window = need_channel(data, "time_s"), judged_window(data)
    fig = _new((8.0, 1.75 * len(names) + 0.9))
    axes = np.atleast_1d(fig.subplots(len(names), 1, sharex=True))
    for ax, name in zip(axes, names, strict=True):
        label, scale = label_of(name)
        _shade_window(ax, window)
        ax.plot(t, np.asarray(data[name], dtype=float) * scale, lw=1.0)
        if name in ("ri", "ltr"):
            ax.set_ylim(-1.1, 1.1)
            for level in (-1.0, 1.0):
                ax.axhline(level, color=LIFT, ls=":", lw=0.8)
        if name.endswith("_fz_N") or name == "min_wheel_load_N":
            ax.axhline(0.0, color=LIFT, ls=":", lw=0.8)
        quantity, _, unit = label.rpartition(" [")
        ax.set_title(plain(quantity[:1].upper() + quantity[1:]), fontsize=9, loc="left", pad=2)
        ax.set_ylabel(plain(f"[{unit}"), fontsize=8)
        _grid(ax)
    axes[-1].set_xlabel("time [s]")
    note = "; grey: judged window (entry to exit gate)" if window else ""
    fig.suptitle(f"{title_of(meta)}\ntime histories{note}", fontsize=10)
    return fig


def figure_wheel_loads(source, meta=None):
    """Each wheel's vertical load [N] over time, the spans with Fz <= 0 (wheel lifted) shaded red and the
    judged window grey. The lift patches carry ``gid="lift"``.

    Parameters
    ----------
    source : Result, pandas.DataFrame or mapping
        The run (channels in SI units, ``time_s`` [s]).
    meta : mapping, optional
        Its metadata (a Result's own by default).

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    data, meta = run_source(source, meta)
    names = wheel_names(data, meta)
    if not names:
        raise InputError("not a run of trikedyn: no wheel loads ('<wheel>_fz_N')", where="run")
    t, window = need_channel(data, "time_s"), judged_window(data)
    fig = _new((8.0, 1.7 * len(names) + 1.0))
    axes = np.atleast_1d(fig.subplots(len(names), 1, sharex=True, sharey=True))
    lifted_any = False
    for ax, name in zip(axes, names, strict=True):
        fz = need_channel(data, f"{name}_fz_N")
        _shade_window(ax, window, "judged window")
        spans = lift_spans(t, fz)
        for k, (a, b) in enumerate(spans):
            width = max(b - a, float(np.median(np.diff(t))) if t.size > 1 else 0.0)
            ax.axvspan(a, a + width, color=LIFT, alpha=0.3, lw=0, zorder=1, gid="lift",
                       label="lifted (Fz ≤ 0)" if k == 0 else None)
        lifted_any |= bool(spans)
        ax.plot(t, fz, lw=1.0, color="C0", zorder=2)
        ax.axhline(0.0, color="k", lw=0.6)
        lift_s = sum(b - a for a, b in spans)
        extra = f"; lifted {len(spans)}x, {lift_s:.2f} s in all, first at {spans[0][0]:.2f} s" if spans else ""
        ax.set_title(plain(f"{name.replace('_', ' ')} wheel{extra}"), fontsize=9, loc="left", pad=2)
        ax.set_ylabel("vertical load [N]", fontsize=8)
        _grid(ax)
        if spans or (window and ax is axes[0]):
            ax.legend(fontsize=7, loc="upper right")
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"{title_of(meta)}\nwheel loads{' (a wheel lifts: red)' if lifted_any else ''}", fontsize=10)
    return fig


def _scene(source, data: dict, meta: dict):
    """The animation's :class:`~trikedyn.report.scene.Scene` of the run: a Result's own vehicle and course,
    else the course rebuilt from the metadata as ``trikedyn animate`` does (a warning when it cannot be)."""
    from .scene import Scene, scene_from

    if isinstance(source, Scene):
        return source
    if getattr(source, "params", None) is not None and hasattr(source, "states"):
        return Scene.from_result(source)
    from ..simulate.runfile import run_course, run_vehicle
    from .scene import scene_channels

    channels, names = scene_channels(data, meta)  # every refusal before the rebuilding, which may warn
    meta = {**meta, "wheels": names}
    params, _ = run_vehicle(meta, names)
    manoeuvre, note = run_course(meta, params)
    if manoeuvre is None:
        warnings.warn(f"no course drawn; {note}", stacklevel=3)
    return scene_from(channels, meta, params=params, manoeuvre=manoeuvre)


def figure_plan(source, meta=None, every_s: float = 1.0):
    """Plan view: the CG path [m] through the lanes (grey) and cones (orange, red when struck), the reference
    line dashed, and the vehicle's footprint every ``every_s`` seconds (or so many more that at most
    :data:`MAX_FOOTPRINTS` are drawn). The lateral scale is stretched (stated in the axis label, at most
    x1000) so that a lane change is visible over a course 100 m long.

    ``source`` may also be a :class:`~trikedyn.report.scene.Scene`.

    Parameters
    ----------
    source : Result, pandas.DataFrame or mapping
        The run (channels in SI units, ``time_s`` [s]). Or a :class:`~trikedyn.report.scene.Scene`.
    meta : mapping, optional
        Its metadata (a Result's own by default).
    every_s : float
        Time between footprints [s].

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.patches import Polygon

    from .animation import CONE, _box, _draw_course, _rotate
    from .scene import frame_indices

    data, meta = ({"time_s": source.time_s}, dict(meta or {})) if hasattr(source, "footprint_m") else run_source(source, meta)
    scene = _scene(source, data, meta)
    cgx, cgy = scene.cg_xy
    fig = _new((11.0, 4.2))
    ax = fig.subplots()
    _draw_course(ax, scene)
    if scene.cones_xy.shape[0] and np.isfinite(scene.cone_hit_s).any():
        hit = np.isfinite(scene.cone_hit_s)
        ax.scatter(scene.cones_xy[hit, 0], scene.cones_xy[hit, 1], marker="^", s=36, c=LIFT, edgecolors="k",
                   linewidths=0.5, zorder=4, label="cone struck")
    outline = _box(*scene.footprint_m)
    span = float(scene.time_s[-1] - scene.time_s[0])
    every_s = max(float(every_s), span / (MAX_FOOTPRINTS - 1))
    for k, i in enumerate(frame_indices(scene.time_s, every_s)):
        corners = _rotate(outline, float(scene.yaw_rad[i]), float(scene.x_m[i]), float(scene.y_m[i]))
        ax.add_patch(Polygon(corners, closed=True, fill=False, lw=0.7, ec="C0", zorder=2, gid="footprint",
                             label=f"footprint every {every_s:.3g} s" if k == 0 else None))
    ax.plot(cgx, cgy, color="k", lw=1.1, zorder=3, label="CG path")
    if scene.path_xy is not None:
        ax.plot([], [], ls="--", lw=0.6, color="0.55", label="reference line")
    if scene.cones_xy.shape[0]:
        ax.scatter([], [], marker="^", s=28, c=CONE, edgecolors="k", linewidths=0.5, label="cones")
    points = np.vstack([np.column_stack((cgx, cgy)), scene.cones_xy.reshape(-1, 2),
                        *([] if scene.path_xy is None else [scene.path_xy])])
    (x0, y0), (x1, y1) = points.min(axis=0), points.max(axis=0)
    pad_y = max(scene.footprint_m[2] * 2, 1.0)
    ax.set_xlim(x0 - 3.0, x1 + 3.0)
    ax.set_ylim(y0 - pad_y, y1 + pad_y)
    span_x, span_y = (x1 - x0) + 6.0, (y1 - y0) + 2 * pad_y
    stretch = min(max(1, round((span_x / span_y) * (3.0 / 10.0))), 1000)  # fits a 10 in x 3 in box
    ax.set_aspect(stretch, adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel(f"y [m]{f' (scale ×{stretch})' if stretch > 1 else ''}")
    _grid(ax)
    ax.legend(fontsize=7, loc="upper left", ncols=3)
    struck = int(np.isfinite(scene.cone_hit_s).sum())
    course = f"{scene.cones_xy.shape[0]} cones, {struck} struck" if scene.cones_xy.shape[0] else "no course drawn"
    fig.suptitle(f"{title_of(meta)}\nplan view ({course})", fontsize=10)
    return fig


def figure_gg(source, meta=None):
    """The g-g diagram: longitudinal against lateral acceleration [g] of the body (CG), with circles every
    0.25 g; the judged window drawn darker.

    Parameters
    ----------
    source : Result, pandas.DataFrame or mapping
        The run (channels in SI units, ``time_s`` [s]).
    meta : mapping, optional
        Its metadata (a Result's own by default).

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    data, meta = run_source(source, meta)
    ax_g, ay_g = need_channel(data, "ax_mps2") / G, need_channel(data, "ay_mps2") / G
    window = judged_window(data)
    fig = _new((6.0, 6.2))
    ax = fig.subplots()
    ax.plot(ay_g, ax_g, lw=0.7, color="0.6", label="whole run")
    if window is not None:
        inside = np.asarray(data["judged"], dtype=float) > 0.5
        ax.plot(np.where(inside, ay_g, np.nan), np.where(inside, ax_g, np.nan), lw=1.1, color="C0",
                label="judged window")
    total = np.hypot(ax_g, ay_g)
    if not np.isfinite(total).any():
        raise InputError("no sample with both accelerations (ax_mps2, ay_mps2) a number", where="run")
    reach = max(float(np.nanmax(total)), 0.25)
    top = math.ceil(reach / 0.25) * 0.25
    angle = np.linspace(0.0, 2 * math.pi, 181)
    for r in np.arange(0.25, top + 1e-9, 0.25):
        ax.plot(r * np.cos(angle), r * np.sin(angle), lw=0.5, color="0.8", zorder=0)
    k = int(np.nanargmax(total))
    ax.plot(ay_g[k], ax_g[k], "o", color=LIFT, ms=4, label=f"peak {reach:.2f} g")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.axvline(0.0, color="k", lw=0.5)
    ax.set_xlim(-top, top)
    ax.set_ylim(-top, top)
    ax.set_aspect("equal")
    ax.set_xlabel("lateral acceleration a_y [g]")
    ax.set_ylabel("longitudinal acceleration a_x [g]")
    _grid(ax)
    ax.legend(fontsize=7, loc="upper right")
    fig.suptitle(f"{title_of(meta)}\ng-g diagram (body, at the CG)", fontsize=10)
    return fig


def figure_roll(source, meta=None):
    """Roll angle [deg] against lateral acceleration [m/s²] (top axis in g), with the roll gradient
    [deg/(m/s²)] fitted over the samples with every wheel down; the samples with a wheel lifted in red.

    Parameters
    ----------
    source : Result, pandas.DataFrame or mapping
        The run (channels in SI units, ``time_s`` [s]).
    meta : mapping, optional
        Its metadata (a Result's own by default).

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    data, meta = run_source(source, meta)
    ay, roll = need_channel(data, "ay_mps2"), np.degrees(need_channel(data, "roll_rad"))
    names = wheel_names(data, meta)
    down = np.ones(ay.size, dtype=bool)
    for name in names:
        down &= np.asarray(data[f"{name}_fz_N"], dtype=float) > 0.0
    fig = _new((7.0, 5.2))
    ax = fig.subplots()
    ax.plot(ay, roll, lw=0.8, color="C0", label="run")
    if (~down).any():
        ax.plot(ay[~down], roll[~down], ".", ms=2.5, color=LIFT, label="a wheel lifted", gid="lift")
    ok = down & np.isfinite(ay) & np.isfinite(roll)
    if ok.sum() >= 3 and np.ptp(ay[ok]) > 1e-6:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a poorly conditioned fit is still the best line; no warning
            slope, offset = np.polyfit(ay[ok], roll[ok], 1)
        line = np.array([ay[ok].min(), ay[ok].max()])
        ax.plot(line, slope * line + offset, "--", color="k", lw=0.9,
                label=f"roll gradient {slope:.2f} deg/(m/s²) ({slope * G:.1f} deg/g)")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.axvline(0.0, color="k", lw=0.5)
    ax.set_xlabel("lateral acceleration [m/s²]")
    ax.set_ylabel("roll [deg]")
    top = ax.secondary_xaxis("top", functions=(lambda a: a / G, lambda g: g * G))
    top.set_xlabel("lateral acceleration [g]", fontsize=8)
    _grid(ax)
    ax.legend(fontsize=7, loc="upper left")
    fig.suptitle(f"{title_of(meta)}\nroll against lateral acceleration", fontsize=10)
    return fig


KINDS = {"time": figure_time, "wheel-loads": figure_wheel_loads, "plan": figure_plan, "gg": figure_gg,
         "roll": figure_roll}
"""The figures of a run by the name ``trikedyn plot --kind`` takes."""


def figure(kind: str, source, meta=None, **options):
    """The figure of ``kind`` (a key of :data:`KINDS`) of a run.

    Parameters
    ----------
    kind : str
        A key of :data:`KINDS`.
    source : Result, pandas.DataFrame or mapping
        The run (channels in SI units, ``time_s`` [s]).
    meta : mapping, optional
        Its metadata (a Result's own by default).
    **options
        The figure's own options (``every_s`` [s], ``channels``).

    Returns
    -------
    matplotlib.figure.Figure
        The figure.

    Raises
    ------
    InputError
        An unknown kind, or the run lacks a channel the figure needs.
    """
    if kind not in KINDS:
        raise InputError(f"expected one of {', '.join(KINDS)}, got '{kind}'", where="--kind")
    return KINDS[kind](source, meta, **options)
