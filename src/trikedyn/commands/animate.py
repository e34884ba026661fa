"""``trikedyn animate``: a run file as an animation (the trike through the cones, or its roll from behind).

A run file (``trikedyn simulate --out run.parquet``, or ``.csv``) is read back and checked, with its vehicle
and course, as :mod:`trikedyn.simulate.runfile` reads and rebuilds them. A course that cannot be rebuilt (a
path CSV gone, an unknown manoeuvre) leaves the animation without cones, with a warning. At most
:data:`trikedyn.report.scene.MAX_FRAMES` frames are drawn (counted before any is).
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


def load_run(run: Path, every_s: float | None = None):
    """A run file as a :class:`~trikedyn.report.scene.Scene`, and notes on how its vehicle and course
    were found.

    Everything that can refuse the run is checked before the vehicle and the course are rebuilt (which may
    warn): the file and its metadata (:func:`trikedyn.simulate.runcheck.read_run`), the channels drawn
    (:func:`trikedyn.report.scene.scene_channels`) and, given ``every_s``, the number of frames
    (:func:`trikedyn.report.scene.check_frames`). So a refusal is one line, never after a warning.

    Parameters
    ----------
    run : Path
        The run file (.parquet or .csv).
    every_s : float, optional
        Time between frames [s], checked against the frame limit when given.

    Returns
    -------
    scene : Scene
        The scene.
    notes : dict of str to str
        How the ``vehicle`` and the ``course`` were found.

    Raises
    ------
    InputError
        The file is missing, is not a run file (suffix, columns, values, metadata), cannot be read, or would
        take more than :data:`~trikedyn.report.scene.MAX_FRAMES` frames.
    """
    from ..report.scene import check_frames, scene_channels, scene_from
    from ..simulate.runcheck import read_run
    from ..simulate.runfile import run_course, run_vehicle

    where = str(run)
    found = read_run(run)
    table, meta = found.table, dict(found.meta)
    channels, names = scene_channels({c: table[c].to_numpy() for c in table.columns}, meta, where)
    if every_s is not None:
        check_frames(channels["time_s"], every_s)
    meta["wheels"] = names
    params, vehicle_note = run_vehicle(meta, names)
    manoeuvre, course_note = run_course(meta, params, run)
    if manoeuvre is None:
        warnings.warn(f"{where}: no course drawn; {course_note}", stacklevel=2)
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
                                           "between frames [s] (0.1 s at 10 fps plays in real time); at most "
                                           "2000 frames are drawn, a longer run needs a larger time.")] = 0.1,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Animate a run: the trike (body outline, wheels shaded by their load, red when lifted) through the cones
    with time and speed, seen from behind rolling with its wheel loads as bars, or in 3d. GIF by default."""
    from .._files import check_output
    from .._reading import file_problem
    from ..report.animation import FORMATS, VIEWS, animate, ffmpeg_available

    if view not in VIEWS:
        raise InputError(f"expected one of {', '.join(VIEWS)}, got '{view}'", where="--view")
    target = out if out is not None else run.with_suffix(".gif")
    if target.suffix.lower() not in FORMATS:
        raise InputError(f"expected a {', '.join(FORMATS)} file name", where=str(target))
    if target.suffix.lower() == ".mp4" and not ffmpeg_available():
        raise InputError("writing .mp4 needs ffmpeg, which is not installed; write a .gif or .html instead",
                         where=str(target))
    problem = file_problem(run)
    if problem is not None:  # before the output checks: a missing run is the first thing to say
        what = "file not found" if problem == "no such file" else problem
        raise InputError(f"{what}; expected a run file written by `trikedyn simulate --out`", where=str(run))
    check_output(target, force=force, reads=[run, run.with_suffix(".json")], option="--out")
    scene, notes = load_run(run, every_s)
    frames = animate(scene, target, view=view, fps=fps, every_s=every_s)
    duration = float(scene.time_s[-1] - scene.time_s[0])
    data = {"wrote": str(target), "view": view, "frames": frames, "fps": fps, "every_s": every_s,
            "run_duration_s": duration, "cones": int(scene.cones_xy.shape[0]),
            "cones_struck": int((scene.cone_hit_s < math.inf).sum()), **notes}
    emit(data, as_json, f"wrote {target}: {frames} frames ({view} view, {duration:.1f} s of run), "
                        f"{data['cones']} cones; course: {notes['course']}")
