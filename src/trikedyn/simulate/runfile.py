"""Run files: a run saved as a table (``.parquet`` or ``.csv``) with a ``.json`` sidecar, and its vehicle and
course rebuilt from them.

``trikedyn simulate --out run.parquet`` writes every channel (:meth:`Result.to_pandas`) and, beside it,
``run.json``: the run's metadata (vehicle name, wheels, time step, manoeuvre name and target speed, footprint,
speed control), its summary (the verdict and the figures of :func:`trikedyn.analysis.metrics.summary`), the
manoeuvre as built (``manoeuvre_spec``, its path CSV named relative to the run's folder when it lies there) and
the **vehicle as driven** (``vehicle_params``: every parameter, payload included), so that a run can be drawn
again with its own vehicle and course wherever it is read (``trikedyn plot``, ``trikedyn animate``, the
report).

Reading back is checked once, where it is read: :mod:`trikedyn.simulate.runcheck` (:func:`read_run`, ...)
and :mod:`trikedyn.simulate.runmeta` (:func:`run_meta`, ...); imported here too.

Rebuilding (:func:`run_vehicle`, :func:`run_course`): the vehicle is the one recorded; for a file from
before the vehicle was recorded (or a recorded one that does not have the run's wheels), the preset of its
name when that preset's outline matches the recorded footprint, else a stand-in made from the footprint (the
courses of the lane changes depend on the vehicle's width only). The cones are not stored: the course is
rebuilt with :func:`trikedyn.manoeuvres.registry.build` from the manoeuvre's name, options and target speed;
a path CSV the record names is a file named in a file, so it follows the rule of
:func:`trikedyn._reading.named_file` (relative to the run's folder, in it or below it).
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from types import SimpleNamespace

from ..errors import InputError
from .runcheck import (  # noqa: F401  (the reading API, importable from here as before)
    MAX_ABS_VALUE,
    MAX_RUN_BYTES,
    MAX_RUN_COLUMNS,
    MAX_RUN_ROWS,
    MAX_RUN_S,
    RUN_SUFFIXES,
    RunFile,
    check_run_table,
    read_run,
    read_run_table,
)
from .runmeta import MAX_SIDECAR_BYTES, MAX_WHEELS, READ_FROM, check_meta, run_meta  # noqa: F401  (as before)

__all__ = ["MAX_ABS_VALUE", "MAX_RUN_BYTES", "MAX_RUN_COLUMNS", "MAX_RUN_ROWS", "MAX_RUN_S", "MAX_SIDECAR_BYTES",
           "MAX_WHEELS", "READ_FROM", "RUN_SUFFIXES", "RunFile", "check_meta", "check_run_file", "check_run_table",
           "footprint_of", "read_run", "read_run_table", "run_course", "run_meta", "run_vehicle", "stand_in",
           "write_run"]

WHEEL_RADIUS_M = 0.27
"""Drawn radius of a wheel of a stand-in vehicle [m]."""


def check_run_file(out: Path, force: bool, reads=()) -> None:
    """A run file name (``.parquet`` or ``.csv``) and the ``.json`` beside it, checked before the run: neither
    is a file the command reads, an existing one is replaced only with ``force``.

    Parameters
    ----------
    out : Path
        The run file to write.
    force : bool
        Replace existing files.
    reads : iterable of Path
        Files the command reads (never written).
    """
    from .._files import check_output

    if out.suffix not in (".parquet", ".csv"):
        raise InputError("expected a .parquet or .csv file name", where=str(out))
    check_output(out, force=force, reads=reads)
    check_output(out.with_suffix(".json"), force=force, reads=reads)


def write_run(result, out: Path, summary: dict) -> None:
    """Write a run: its channels to ``out`` (``.parquet`` or ``.csv``) and its metadata, ``summary``, manoeuvre and
    vehicle to the ``.json`` beside it, each atomically.

    Parameters
    ----------
    result : Result
        The run.
    out : Path
        The table file.
    summary : dict
        Its metrics, stored in the sidecar.
    """
    from .._files import atomic_write
    from .._json import finite, json_default

    frame = result.to_pandas().reset_index()
    if out.suffix == ".parquet":
        atomic_write(out, lambda fh: frame.to_parquet(fh, index=False))
    else:
        atomic_write(out, lambda fh: frame.to_csv(fh, index=False), binary=False)
    meta = {k: v for k, v in result.meta.items() if k != "driver"} | {"summary": summary}
    if result.manoeuvre is not None:
        meta["manoeuvre_spec"] = _relative_file(result.manoeuvre.to_dict(), out)
    if result.params is not None and hasattr(result.params, "model_dump"):
        meta["vehicle_params"] = result.params.model_dump(mode="json")
    text = json.dumps(finite(meta)[0], indent=2, default=json_default, allow_nan=False)
    atomic_write(out.with_suffix(".json"), lambda fh: fh.write(text), binary=False)


def _relative_file(spec: dict, out: Path) -> dict:
    """The manoeuvre's record with its path CSV (``parameters.file``) named relative to the run's folder when it
    lies in it or below (the rule a file named in a file is read by); as given otherwise."""
    params = spec.get("parameters")
    file = params.get("file") if isinstance(params, dict) else None
    if isinstance(file, str):
        try:
            rel = Path(file).resolve().relative_to(Path(out).resolve().parent)
        except (OSError, ValueError, RuntimeError):
            return spec
        return {**spec, "parameters": {**params, "file": rel.as_posix()}}
    return spec


# ------------------------------------------------------------------------------------------------------------
# rebuilding a run's vehicle and course
# ------------------------------------------------------------------------------------------------------------
def footprint_of(meta: dict) -> tuple[float, float, float] | None:
    """The recorded ``(x_rear, x_front, half_width)`` [m] of the vehicle's outline, or None.

    Parameters
    ----------
    meta : dict
        The run's metadata.

    Returns
    -------
    tuple of float or None
        The footprint [m], None when absent or invalid.
    """
    try:
        values = tuple(float(v) for v in meta.get("footprint_m") or ())
    except (TypeError, ValueError):
        return None
    ok = len(values) == 3 and all(math.isfinite(v) for v in values) and values[0] < values[1] and values[2] > 0
    return values if ok else None


def stand_in(names: list[str], footprint) -> SimpleNamespace:
    """A vehicle made from the run file alone: outline from the footprint, wheels placed by their names (front
    ones at the wheelbase, left and right ones near the sides), CG on the centre line (approximate). Enough to
    draw it and to lay out a course that depends on the width only.

    Parameters
    ----------
    names : list of str
        Wheel names.
    footprint : tuple of float or None
        ``(x_rear, x_front, half_width)`` [m]; a typical trike's when None.

    Returns
    -------
    types.SimpleNamespace
        Duck-typed vehicle parameters (wheels, wheelbase [m], body, mass).
    """
    x_rear, x_front, half = footprint if footprint is not None else (-0.6, 2.4, 0.625)
    base = x_front + x_rear  # equal overhangs (trikedyn.simulate.closed_loop.footprint)
    wheels = [SimpleNamespace(name=n, x_m=base if "front" in n else 0.0, radius_m=WHEEL_RADIUS_M, steered="front" in n,
                              y_m=0.85 * half if "left" in n else -0.85 * half if "right" in n else 0.0) for n in names]
    return SimpleNamespace(name="stand-in", wheels=wheels, wheelbase_m=base,
                           body=SimpleNamespace(overall_width_m=2 * half, overall_length_m=x_front - x_rear),
                           mass=SimpleNamespace(cg_x_m=0.4 * base, cg_y_m=0.0, cg_z_m=0.5))


def run_vehicle(meta: dict, names: list[str]):
    """The vehicle a run drove, and how it was found (a note): the one recorded in its sidecar (when it has the
    run's wheels); else the preset of its name if that preset's outline matches the recorded footprint; else a
    :func:`stand_in`.

    Parameters
    ----------
    meta : dict
        The run's metadata.
    names : list of str
        The run's wheel names.

    Returns
    -------
    params : VehicleParameters or SimpleNamespace
        The vehicle.
    note : str
        How it was found.
    """
    from ..params import list_presets, load_vehicle
    from ..params.schema import VehicleParameters

    recorded = meta.get("vehicle_params")
    if isinstance(recorded, dict):
        try:
            params = VehicleParameters.model_validate(recorded)
            theirs = sorted(w.name for w in params.wheels)
            if theirs != sorted(names):
                raise ValueError(f"its wheels ({', '.join(theirs)}) are not the run's ({', '.join(names)})")
            return params, f"the vehicle recorded with the run ('{params.name}')"
        except (ValueError, TypeError, InputError) as exc:  # e.g. its .tir file has gone
            first = " ".join(str(exc).split())[:200]
            warnings.warn(f"the run's recorded vehicle could not be rebuilt ({first}); using its name or outline",
                          stacklevel=2)
    name, footprint = meta.get("vehicle"), footprint_of(meta)
    if isinstance(name, str) and name in list_presets():
        params = load_vehicle(name).params
        overhang = max(params.body.overall_length_m - params.wheelbase_m, 0.0) / 2
        mine = (-overhang, params.wheelbase_m + overhang, params.body.overall_width_m / 2)
        if sorted(w.name for w in params.wheels) == sorted(names) and (
                footprint is None or all(abs(a - b) < 1e-6 for a, b in zip(mine, footprint, strict=True))):
            return params, f"preset '{name}'"
    return stand_in(names, footprint), "a stand-in vehicle from the run's footprint (wheels placed approximately)"


def run_course(meta: dict, params, run=None):
    """The manoeuvre rebuilt from a run's record (name, options, target speed) for ``params``, or None; and a
    note saying how (or why not). The record's name and options travel as a
    :class:`~trikedyn.manoeuvres.spec.ManoeuvreSpec`, checked against the manoeuvre's option table as any other.

    Parameters
    ----------
    meta : dict
        The run's metadata (:func:`check_meta`).
    params : VehicleParameters or SimpleNamespace
        The vehicle (:func:`run_vehicle`).
    run : str or Path, optional
        The run file (default: the one :func:`run_meta` read the metadata for). A path CSV the record names
        (``manoeuvre_spec.parameters.file``) is a file named in a file: relative to the run's folder, in it or
        below it (:func:`trikedyn._reading.named_file`); without a run file it is not read.

    Returns
    -------
    manoeuvre : Manoeuvre or None
        The rebuilt manoeuvre.
    note : str
        How it was rebuilt, or why not.
    """
    from ..manoeuvres.registry import get
    from ..manoeuvres.spec import ManoeuvreSpec

    spec = meta.get("manoeuvre_spec") if isinstance(meta.get("manoeuvre_spec"), dict) else {}
    name = meta.get("manoeuvre_name") or spec.get("name")
    speed = meta.get("target_speed_kmh") or (meta.get("summary") or {}).get("speed_kmh")
    if not name or not speed:
        return None, "none: the run file names no manoeuvre and speed"
    run = run if run is not None else meta.get(READ_FROM)
    try:
        kind = get(str(name))
        if isinstance(params, SimpleNamespace) and not kind.closed_loop:
            return None, f"none: '{name}' steers open loop (no course to draw) and the run's vehicle is not recorded"
        declared = {o.name for o in kind.options}
        options = {k: v for k, v in (spec.get("parameters") or {}).items() if k in declared}
        if "file" in options:
            options["file"] = _named_path_csv(options["file"], run)
        manoeuvre = ManoeuvreSpec(str(name), options).build(params, float(speed))
    except (InputError, AttributeError, KeyError, TypeError, ValueError, ArithmeticError) as exc:
        return None, f"none: '{name}' could not be rebuilt ({' '.join(str(exc).split())[:300]})"
    told = ", ".join(f"{k}={v}" for k, v in options.items())
    return manoeuvre, f"'{name}' rebuilt at {float(speed):g} km/h" + (f" with {told}" if told else "")


def _named_path_csv(name, run) -> str:
    """A path CSV named in a run's record, by the rule for files named in files (relative to the run's folder)."""
    from .._reading import named_file

    if run is None:
        raise InputError("its path CSV is named relative to the run file, which is not known here",
                         where="manoeuvre_spec.parameters.file")
    return str(named_file(name, Path(run).parent, expected="a path .csv", where="manoeuvre_spec.parameters.file",
                          place="the run file's folder", suffixes=(".csv",)).path)
