"""``trikedyn animate``: a run file as an animation (the trike through the cones, or its roll from behind).

A run file (``trikedyn simulate --out run.parquet``, or ``.csv``) is read back with its vehicle and course
as :mod:`trikedyn.simulate.runfile` rebuilds them. A course that cannot be rebuilt (a path CSV gone, an
unknown manoeuvre) leaves the animation without cones, with a warning.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from ._common import ForceOpt, JsonOpt, emit, within

__all__ = ["animate_cmd", "load_run"]

RUN_SUFFIXES = (".parquet", ".pq", ".csv")


def load_run(run: Path):
    """A run file as a :class:`~trikedyn.report.animation.Scene`, and notes on how its course was rebuilt.

    Raises
    ------
    InputError
        The file is missing, is not a run file (suffix, columns), or cannot be read.
    """
    from ..analysis.compare import load_table
    from ..report.animation import scene_from
    from ..simulate.runfile import run_course, run_meta, run_vehicle

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
    meta = run_meta(run, frame.attrs)
    names = meta.get("wheels")
    if not (isinstance(names, list) and names and all(f"{n}_fz_N" in frame.columns for n in names)):
        names = [c[: -len("_fz_N")] for c in frame.columns if str(c).endswith("_fz_N")]
    if not names:
        raise InputError("not a run of trikedyn: no wheel loads ('<wheel>_fz_N')", where=where)
    meta["wheels"] = names
    params, vehicle_note = run_vehicle(meta, names)
    manoeuvre, course_note = run_course(meta, params)
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
