"""``trikedyn animate``: a run file as an animation (the trike through the cones, or its roll from behind).

A run file (``trikedyn simulate --out run.parquet``, or ``.csv``) keeps the channels and, in the Parquet
metadata and the ``.json`` beside it, the vehicle's name, the manoeuvre's name, options and target speed,
and the footprint. The cones are not stored: the course is rebuilt from these with
:func:`trikedyn.manoeuvres.registry.build`, for the preset of that name when its outline matches the
recorded footprint, else for a stand-in vehicle made from the footprint (the courses depend on the
vehicle's width only). A course that cannot be rebuilt (a path CSV gone, an unknown manoeuvre) leaves the
animation without cones, with a warning.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from types import SimpleNamespace
from typing import Annotated

import typer

from ..errors import InputError
from ._common import ForceOpt, JsonOpt, emit, within

__all__ = ["animate_cmd", "load_run"]

RUN_SUFFIXES = (".parquet", ".pq", ".csv")
WHEEL_RADIUS_M = 0.27  # drawn radius of a wheel when the vehicle is not known [m]


def _meta(run: Path, attrs: dict) -> dict:
    """The run's metadata: the Parquet metadata, completed by the ``.json`` summary beside the run."""
    meta = dict(attrs)
    side = run.with_suffix(".json")
    if side.is_file():
        try:
            found = json.loads(side.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            warnings.warn(f"{side}: not read ({type(exc).__name__}); animating without it", stacklevel=2)
        else:
            meta = {**found, **meta} if isinstance(found, dict) else meta
    return meta


def _footprint(meta: dict):
    """The recorded ``(x_rear, x_front, half_width)`` [m], or None."""
    try:
        values = tuple(float(v) for v in meta.get("footprint_m") or ())
    except (TypeError, ValueError):
        return None
    ok = len(values) == 3 and all(math.isfinite(v) for v in values) and values[0] < values[1] and values[2] > 0
    return values if ok else None


def _stand_in(names: list[str], footprint) -> SimpleNamespace:
    """A vehicle made from the run file alone: outline from the footprint, wheels placed by their names (front
    ones at the wheelbase, left and right ones near the sides), CG on the centre line (approximate)."""
    x_rear, x_front, half = footprint or (-0.5, 2.5, 0.625)
    base = x_front + x_rear  # equal overhangs (trikedyn.simulate.closed_loop.footprint)
    wheels = [SimpleNamespace(name=n, x_m=base if "front" in n else 0.0, radius_m=WHEEL_RADIUS_M, steered="front" in n,
                              y_m=0.85 * half if "left" in n else -0.85 * half if "right" in n else 0.0) for n in names]
    return SimpleNamespace(name="stand-in", wheels=wheels, wheelbase_m=base,
                           body=SimpleNamespace(overall_width_m=2 * half, overall_length_m=x_front - x_rear),
                           mass=SimpleNamespace(cg_x_m=0.4 * base, cg_y_m=0.0, cg_z_m=0.5))


def _vehicle(meta: dict, names: list[str]):
    """The preset the run names if its outline matches the recorded footprint; else a stand-in. And a note."""
    from ..params import list_presets, load_vehicle

    name, footprint = meta.get("vehicle"), _footprint(meta)
    if isinstance(name, str) and name in list_presets():
        params = load_vehicle(name).params
        overhang = max(params.body.overall_length_m - params.wheelbase_m, 0.0) / 2
        mine = (-overhang, params.wheelbase_m + overhang, params.body.overall_width_m / 2)
        if footprint is None or all(abs(a - b) < 1e-6 for a, b in zip(mine, footprint, strict=True)):
            return params, f"preset '{name}'"
    return _stand_in(names, footprint), "a stand-in vehicle from the run's footprint (wheels placed approximately)"


def _course(meta: dict, params):
    """The manoeuvre rebuilt from the run's record (name, options, target speed), or None; and a note."""
    from ..manoeuvres.registry import build, get

    spec = meta.get("manoeuvre_spec") if isinstance(meta.get("manoeuvre_spec"), dict) else {}
    name = meta.get("manoeuvre_name") or spec.get("name")
    speed = meta.get("target_speed_kmh") or (meta.get("summary") or {}).get("speed_kmh")
    if not name or not speed:
        return None, "none: the run file names no manoeuvre and speed"
    try:
        declared = {o.name for o in get(str(name)).options}
        options = {k: v for k, v in (spec.get("parameters") or {}).items() if k in declared}
        manoeuvre = build(str(name), params, float(speed), **options)
    except (InputError, AttributeError, KeyError, TypeError, ValueError) as exc:
        return None, f"none: '{name}' could not be rebuilt ({exc})"
    told = ", ".join(f"{k}={v}" for k, v in options.items())
    return manoeuvre, f"'{name}' rebuilt at {float(speed):g} km/h" + (f" with {told}" if told else "")


def load_run(run: Path):
    """A run file as a :class:`~trikedyn.report.animation.Scene`, and notes on how its course was rebuilt.

    Raises
    ------
    InputError
        The file is missing, is not a run file (suffix, columns), or cannot be read.
    """
    from ..analysis.compare import load_table
    from ..report.animation import scene_from

    where = str(run)
    if not run.is_file():
        raise InputError("file not found; expected a run file written by `trikedyn simulate --out`", where=where)
    if run.suffix.lower() not in RUN_SUFFIXES:
        raise InputError("expected a run file (.parquet or .csv) written by `trikedyn simulate --out`", where=where)
    frame, kind = load_table(run)
    if not kind.startswith("run-"):
        raise InputError(f"not a run file (read as a '{kind}' log)", where=where)
    missing = [c for c in ("x_m", "y_m", "yaw_rad", "speed_mps") if c not in frame.columns]
    if missing:
        raise InputError(f"not a run of trikedyn: no channel '{missing[0]}'", where=where)
    meta = _meta(run, frame.attrs)
    names = meta.get("wheels")
    if not (isinstance(names, list) and names and all(f"{n}_fz_N" in frame.columns for n in names)):
        names = [c[: -len("_fz_N")] for c in frame.columns if str(c).endswith("_fz_N")]
    if not names:
        raise InputError("not a run of trikedyn: no wheel loads ('<wheel>_fz_N')", where=where)
    meta["wheels"] = names
    params, vehicle_note = _vehicle(meta, names)
    manoeuvre, course_note = _course(meta, params)
    if manoeuvre is None:
        warnings.warn(f"{where}: no course drawn; {course_note}", stacklevel=2)
    channels = {c: frame[c].to_numpy() for c in frame.columns}
    scene = scene_from(channels, meta, params=params, manoeuvre=manoeuvre, where=where)
    return scene, {"vehicle": vehicle_note, "course": course_note}


def animate_cmd(
    run: Annotated[Path, typer.Argument(help="A run file written by `trikedyn simulate --out` (.parquet or .csv).")],
    out: Annotated[Path | None, typer.Option("--out", help="Animation to write: .gif (default: beside the run), "
                                             ".html (a page with a player) or .mp4 (needs ffmpeg).")] = None,
    view: Annotated[str, typer.Option("--view", help="plan: the trike through the cones, from above; rear: the "
                                      "body's roll and the wheel loads, from behind; 3d: the trike rolling and "
                                      "pitching through the cones, seen by a camera that follows it.")] = "plan",
    fps: Annotated[int, typer.Option("--fps", callback=within(1, 60, "frames/s"), help="Frames per second of the "
                                     "animation [1/s].")] = 10,
    every_s: Annotated[float, typer.Option("--every-s", callback=within(0.001, 60, "s"), help="Simulated time "
                                           "between frames [s] (0.1 s at 10 fps plays in real time).")] = 0.1,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Animate a run: the trike (body outline, wheels shaded by their load, red when lifted) through the cones
    with time and speed, seen from behind rolling with its wheel loads as bars, or in 3d. GIF by default."""
    from .._files import check_output
    from ..report.animation import FORMATS, VIEWS, animate, ffmpeg_available

    if view not in VIEWS:
        raise InputError(f"expected one of {', '.join(VIEWS)}, got '{view}'", where="--view")
    target = out if out is not None else run.with_suffix(".gif")
    if target.suffix.lower() not in FORMATS:
        raise InputError(f"expected a {', '.join(FORMATS)} file name", where=str(target))
    if target.suffix.lower() == ".mp4" and not ffmpeg_available():
        raise InputError("writing .mp4 needs ffmpeg, which is not installed; write a .gif or .html instead",
                         where=str(target))
    if not run.is_file():  # before the output checks: a missing run is the first thing to say
        raise InputError("file not found; expected a run file written by `trikedyn simulate --out`", where=str(run))
    check_output(target, force=force, reads=[run, run.with_suffix(".json")], option="--out")
    scene, notes = load_run(run)
    frames = animate(scene, target, view=view, fps=fps, every_s=every_s)
    duration = float(scene.time_s[-1] - scene.time_s[0])
    data = {"wrote": str(target), "view": view, "frames": frames, "fps": fps, "every_s": every_s,
            "run_duration_s": duration, "cones": int(scene.cones_xy.shape[0]),
            "cones_struck": int((scene.cone_hit_s < math.inf).sum()), **notes}
    emit(data, as_json, f"wrote {target}: {frames} frames ({view} view, {duration:.1f} s of run), "
                        f"{data['cones']} cones; course: {notes['course']}")
