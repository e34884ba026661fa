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
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping

import numpy as np

from ..errors import InputError, did_you_mean
from ._drawing import plain

__all__ = ["KINDS", "figure", "figure_gg", "figure_plan", "figure_roll", "figure_time", "figure_wheel_loads",
           "MAX_FOOTPRINTS", "lift_spans", "title_of"]

G = 9.80665  # standard gravity [m/s²]
LIFT = "#d62728"
WINDOW = "0.85"

# channel -> (label with unit, scale from the stored SI value)
LABELS = {
    "speed_mps": ("speed [km/h]", 3.6),
    "vx_mps": ("longitudinal velocity [km/h]", 3.6),
    "vy_mps": ("lateral velocity [m/s]", 1.0),
    "ax_mps2": ("longitudinal acceleration [m/s²]", 1.0),
    "ay_mps2": ("lateral acceleration [m/s²]", 1.0),
    "az_mps2": ("vertical acceleration [m/s²]", 1.0),
    "imu_ay_mps2": ("lateral acceleration, seat sensor [m/s²]", 1.0),
    "imu_ax_mps2": ("longitudinal acceleration, seat sensor [m/s²]", 1.0),
    "yaw_rate_radps": ("yaw rate [deg/s]", math.degrees(1.0)),
    "roll_rate_radps": ("roll rate [deg/s]", math.degrees(1.0)),
    "pitch_rate_radps": ("pitch rate [deg/s]", math.degrees(1.0)),
    "imu_wz_radps": ("yaw rate, seat sensor [deg/s]", math.degrees(1.0)),
    "roll_rad": ("roll [deg]", math.degrees(1.0)),
    "pitch_rad": ("pitch [deg]", math.degrees(1.0)),
    "yaw_rad": ("yaw [deg]", math.degrees(1.0)),
    "steer_rad": ("steer angle [deg]", math.degrees(1.0)),
    "steer_cmd_rad": ("steer command [deg]", math.degrees(1.0)),
    "ri": ("rollover index RI (Eq. 5) [-]", 1.0),
    "ltr": ("load transfer ratio [-]", 1.0),
    "min_wheel_load_N": ("least wheel load [N]", 1.0),
    "path_error_m": ("path error [m]", 1.0),
    "x_m": ("x [m]", 1.0),
    "y_m": ("y [m]", 1.0),
}
# unit suffix of a channel name -> (unit shown, scale)
SUFFIXES = (("_radps", "deg/s", math.degrees(1.0)), ("_rad", "deg", math.degrees(1.0)), ("_mps2", "m/s²", 1.0),
            ("_mps", "m/s", 1.0), ("_Nm", "N·m", 1.0), ("_N", "N", 1.0), ("_m", "m", 1.0), ("_s", "s", 1.0),
            ("_kmh", "km/h", 1.0))
TIME_CHANNELS = ("speed_mps", "ay_mps2", "yaw_rate_radps", "roll_rad", "ri")
MAX_FOOTPRINTS = 200
"""Most footprints drawn in the plan view."""


def label_of(name: str) -> tuple[str, float]:
    """A channel's axis label with its unit, and the factor from its stored (SI) value to the value shown."""
    if name in LABELS:
        return LABELS[name]
    for suffix, unit, scale in SUFFIXES:
        if name.endswith(suffix):
            words = name[: -len(suffix)].replace("_", " ")
            words = words.replace(" fz", " vertical load").replace(" fy", " lateral force").replace(" fx", " longitudinal force")
            return f"{words} [{unit}]", scale
    return f"{name.replace('_', ' ')} [-]", 1.0


# --- the run as channels and metadata -------------------------------------------------------------------------

def _source(source, meta) -> tuple[dict, dict]:
    """``(channels, meta)`` of a Result, a DataFrame or a mapping; channels hold ``time_s``. A table or a mapping
    is checked as a run file is (:func:`trikedyn.simulate.runcheck.check_run_table`: numbers, finite increasing
    time, ...), and so is metadata that does not come with a Result (:func:`~trikedyn.simulate.runcheck.check_meta`)."""
    from ..simulate.runcheck import check_meta, check_run_table

    if hasattr(source, "time_s") and hasattr(source, "channels") and not isinstance(source, Mapping):
        channels = {"time_s": np.asarray(source.time_s, dtype=float), **dict(source.channels)}
        return channels, dict(source.meta or {}) if meta is None else check_meta(meta, "meta")
    if isinstance(source, Mapping):
        import pandas as pd

        try:
            source = pd.DataFrame({str(k): np.asarray(v).reshape(-1) for k, v in source.items()})
        except (TypeError, ValueError) as exc:
            raise InputError(f"the channels are not one table ({' '.join(str(exc).split())[:120]})",
                             where="run") from None
    if not (hasattr(source, "columns") and hasattr(source, "attrs")):
        raise InputError(f"expected a run (Result, table or channels), got {type(source).__name__}", where="run")
    table = check_run_table(source, "run")
    meta = check_meta(table.attrs if meta is None else meta, "meta")
    return {c: table[c].to_numpy() for c in table.columns}, meta


def _need(channels: dict, name: str) -> np.ndarray:
    if name not in channels:
        raise InputError(f"not a run of trikedyn: no channel '{name}'", where="run")
    return np.asarray(channels[name], dtype=float)


def _wheels(channels: dict, meta: dict) -> list[str]:
    names = meta.get("wheels")
    if isinstance(names, list | tuple) and names and all(f"{n}_fz_N" in channels for n in names):
        return [str(n) for n in names]
    return [c[: -len("_fz_N")] for c in channels if str(c).endswith("_fz_N")]


def title_of(meta: Mapping) -> str:
    """``vehicle - manoeuvre at N km/h (payload P kg)`` from a run's metadata (what it holds of these).

    Parameters
    ----------
    meta : mapping
        A run's metadata.

    Returns
    -------
    str
        The title.
    """
    summary = meta.get("summary") if isinstance(meta.get("summary"), Mapping) else {}
    vehicle = meta.get("vehicle") or summary.get("vehicle")
    manoeuvre = meta.get("manoeuvre") or summary.get("manoeuvre") or meta.get("manoeuvre_name")
    speed = meta.get("target_speed_kmh") or summary.get("speed_kmh")
    payload = summary.get("payload_kg") or meta.get("payload_kg")
    text = " - ".join(str(v) for v in (vehicle, manoeuvre) if v) or "run"
    if speed:
        text += f" at {float(speed):g} km/h"
    if payload:
        text += f" (payload {float(payload):g} kg)"
    return plain(text)


def _window(channels: dict) -> tuple[float, float] | None:
    """The judged window (entry to exit gate) as ``(t_start, t_end)`` [s], or None."""
    if "judged" not in channels:
        return None
    inside = np.nonzero(np.asarray(channels["judged"], dtype=float) > 0.5)[0]
    if not inside.size:
        return None
    t = np.asarray(channels["time_s"], dtype=float)
    return float(t[inside[0]]), float(t[inside[-1]])


def _shade_window(ax, window, label=None) -> None:
    if window is not None:
        ax.axvspan(*window, color=WINDOW, alpha=0.6, lw=0, zorder=0, label=label, gid="judged")


def lift_spans(time_s, fz_N) -> list[tuple[float, float]]:
    """The spans of time ``(t_start, t_end)`` [s] in which a wheel's vertical load is zero or less (lifted).

    Parameters
    ----------
    time_s : array_like
        Times [s].
    fz_N : array_like
        Vertical load of one wheel [N].

    Returns
    -------
    list of tuple of float
        ``(t_start, t_end)`` [s] per span.
    """
    t = np.asarray(time_s, dtype=float)
    off = np.asarray(fz_N, dtype=float) <= 0.0
    if not off.any():
        return []
    edges = np.diff(np.concatenate(([0], off.astype(int), [0])))
    starts, ends = np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0] - 1
    return [(float(t[a]), float(t[b])) for a, b in zip(starts, ends, strict=True)]


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
    data, meta = _source(source, meta)
    names = list(channels) if channels else [c for c in TIME_CHANNELS if c in data]
    for name in names:
        if name not in data:
            raise InputError(f"no channel '{name}'" + did_you_mean(name, list(data)), where="run")
    if not names:
        raise InputError("the run holds none of the channels to plot", where="run")
    t, window = _need(data, "time_s"), _window(data)
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
    data, meta = _source(source, meta)
    names = _wheels(data, meta)
    if not names:
        raise InputError("not a run of trikedyn: no wheel loads ('<wheel>_fz_N')", where="run")
    t, window = _need(data, "time_s"), _window(data)
    fig = _new((8.0, 1.7 * len(names) + 1.0))
    axes = np.atleast_1d(fig.subplots(len(names), 1, sharex=True, sharey=True))
    lifted_any = False
    for ax, name in zip(axes, names, strict=True):
        fz = _need(data, f"{name}_fz_N")
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
    """The animation's :class:`~trikedyn.report.animation.Scene` of the run: a Result's own vehicle and course,
    else the course rebuilt from the metadata as ``trikedyn animate`` does (a warning when it cannot be)."""
    from .animation import Scene, scene_from

    if isinstance(source, Scene):
        return source
    if getattr(source, "params", None) is not None and hasattr(source, "states"):
        return Scene.from_result(source)
    from ..simulate.runfile import run_course, run_vehicle
    from .animation import scene_channels

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

    ``source`` may also be a :class:`~trikedyn.report.animation.Scene`.

    Parameters
    ----------
    source : Result, pandas.DataFrame or mapping
        The run (channels in SI units, ``time_s`` [s]). Or a :class:`~trikedyn.report.animation.Scene`.
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

    from .animation import CONE, _box, _draw_course, _rotate, frame_indices

    data, meta = ({"time_s": source.time_s}, dict(meta or {})) if hasattr(source, "footprint_m") else _source(source, meta)
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
    data, meta = _source(source, meta)
    ax_g, ay_g = _need(data, "ax_mps2") / G, _need(data, "ay_mps2") / G
    window = _window(data)
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
    data, meta = _source(source, meta)
    ay, roll = _need(data, "ay_mps2"), np.degrees(_need(data, "roll_rad"))
    names = _wheels(data, meta)
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
