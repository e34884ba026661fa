"""Run files: a run saved as a table (``.parquet`` or ``.csv``) with a ``.json`` sidecar, and rebuilt from them.

``trikedyn simulate --out run.parquet`` writes every channel (:meth:`Result.to_pandas`) and, beside it,
``run.json``: the run's metadata (vehicle name, wheels, time step, manoeuvre name and target speed, footprint,
speed control), its summary (the verdict and the figures of :func:`trikedyn.analysis.metrics.summary`), the
manoeuvre as built (``manoeuvre_spec``) and the **vehicle as driven** (``vehicle_params``: every parameter,
payload included), so that a run can be drawn again with its own vehicle and course wherever it is read
(``trikedyn plot``, ``trikedyn animate``, the report).

Reading back (:func:`run_meta`, :func:`run_vehicle`, :func:`run_course`): the vehicle is the one recorded;
for a file from before the vehicle was recorded, the preset of its name when that preset's outline matches the
recorded footprint, else a stand-in made from the footprint (the courses of the lane changes depend on the
vehicle's width only). The cones are not stored: the course is rebuilt with
:func:`trikedyn.manoeuvres.registry.build` from the manoeuvre's name, options and target speed.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from types import SimpleNamespace

from ..errors import InputError

__all__ = ["MAX_SIDECAR_BYTES", "check_run_file", "footprint_of", "run_course", "run_meta", "run_vehicle", "stand_in",
           "write_run"]

WHEEL_RADIUS_M = 0.27
"""Drawn radius of a wheel of a stand-in vehicle [m]."""
MAX_SIDECAR_BYTES = 16 * 2**20
"""Largest ``.json`` sidecar read [bytes]: a run's is a few kB; a bigger one is not read (and said so)."""


def check_run_file(out: Path, force: bool, reads=()) -> None:
    """A run file name (``.parquet`` or ``.csv``) and the ``.json`` beside it, checked before the run: neither
    is a file the command reads, an existing one is replaced only with ``force``."""
    from .._files import check_output

    if out.suffix not in (".parquet", ".csv"):
        raise InputError("expected a .parquet or .csv file name", where=str(out))
    check_output(out, force=force, reads=reads)
    check_output(out.with_suffix(".json"), force=force, reads=reads)


def write_run(result, out: Path, summary: dict) -> None:
    """Write a run: its channels to ``out`` (``.parquet`` or ``.csv``) and its metadata, ``summary``, manoeuvre and
    vehicle to the ``.json`` beside it, each atomically."""
    from .._files import atomic_write
    from .._json import finite, json_default

    frame = result.to_pandas().reset_index()
    if out.suffix == ".parquet":
        atomic_write(out, lambda fh: frame.to_parquet(fh, index=False))
    else:
        atomic_write(out, lambda fh: frame.to_csv(fh, index=False), binary=False)
    meta = {k: v for k, v in result.meta.items() if k != "driver"} | {"summary": summary}
    if result.manoeuvre is not None:
        meta["manoeuvre_spec"] = result.manoeuvre.to_dict()
    if result.params is not None and hasattr(result.params, "model_dump"):
        meta["vehicle_params"] = result.params.model_dump(mode="json")
    text = json.dumps(finite(meta)[0], indent=2, default=json_default, allow_nan=False)
    atomic_write(out.with_suffix(".json"), lambda fh: fh.write(text), binary=False)


def run_meta(run: Path, attrs: dict) -> dict:
    """A run's metadata: the table's own (Parquet) metadata ``attrs``, completed by the ``.json`` beside it (a
    sidecar that cannot be read, or over :data:`MAX_SIDECAR_BYTES`, is left out with a warning)."""
    meta = dict(attrs)
    side = Path(run).with_suffix(".json")
    if side.is_file():
        try:
            if side.stat().st_size > MAX_SIDECAR_BYTES:
                raise ValueError(f"over {MAX_SIDECAR_BYTES // 2**20} MiB")
            found = json.loads(side.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            warnings.warn(f"{side}: not read ({type(exc).__name__}: {exc}); going on without it", stacklevel=2)
        else:
            meta = {**found, **meta} if isinstance(found, dict) else meta
    return meta


def footprint_of(meta: dict) -> tuple[float, float, float] | None:
    """The recorded ``(x_rear, x_front, half_width)`` [m] of the vehicle's outline, or None."""
    try:
        values = tuple(float(v) for v in meta.get("footprint_m") or ())
    except (TypeError, ValueError):
        return None
    ok = len(values) == 3 and all(math.isfinite(v) for v in values) and values[0] < values[1] and values[2] > 0
    return values if ok else None


def stand_in(names: list[str], footprint) -> SimpleNamespace:
    """A vehicle made from the run file alone: outline from the footprint, wheels placed by their names (front
    ones at the wheelbase, left and right ones near the sides), CG on the centre line (approximate). Enough to
    draw it and to lay out a course that depends on the width only."""
    x_rear, x_front, half = footprint if footprint is not None else (-0.6, 2.4, 0.625)
    base = x_front + x_rear  # equal overhangs (trikedyn.simulate.closed_loop.footprint)
    wheels = [SimpleNamespace(name=n, x_m=base if "front" in n else 0.0, radius_m=WHEEL_RADIUS_M, steered="front" in n,
                              y_m=0.85 * half if "left" in n else -0.85 * half if "right" in n else 0.0) for n in names]
    return SimpleNamespace(name="stand-in", wheels=wheels, wheelbase_m=base,
                           body=SimpleNamespace(overall_width_m=2 * half, overall_length_m=x_front - x_rear),
                           mass=SimpleNamespace(cg_x_m=0.4 * base, cg_y_m=0.0, cg_z_m=0.5))


def run_vehicle(meta: dict, names: list[str]):
    """The vehicle a run drove, and how it was found (a note): the one recorded in its sidecar; else the preset
    of its name if that preset's outline matches the recorded footprint; else a :func:`stand_in`."""
    from ..params import list_presets, load_vehicle
    from ..params.schema import VehicleParameters

    recorded = meta.get("vehicle_params")
    if isinstance(recorded, dict):
        try:
            params = VehicleParameters.model_validate(recorded)
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
        if footprint is None or all(abs(a - b) < 1e-6 for a, b in zip(mine, footprint, strict=True)):
            return params, f"preset '{name}'"
    return stand_in(names, footprint), "a stand-in vehicle from the run's footprint (wheels placed approximately)"


def run_course(meta: dict, params):
    """The manoeuvre rebuilt from a run's record (name, options, target speed) for ``params``, or None; and a
    note saying how (or why not)."""
    from ..manoeuvres.registry import build, get

    spec = meta.get("manoeuvre_spec") if isinstance(meta.get("manoeuvre_spec"), dict) else {}
    name = meta.get("manoeuvre_name") or spec.get("name")
    speed = meta.get("target_speed_kmh") or (meta.get("summary") or {}).get("speed_kmh")
    if not name or not speed:
        return None, "none: the run file names no manoeuvre and speed"
    try:
        kind = get(str(name))
        if isinstance(params, SimpleNamespace) and not kind.closed_loop:
            return None, f"none: '{name}' steers open loop (no course to draw) and the run's vehicle is not recorded"
        declared = {o.name for o in kind.options}
        options = {k: v for k, v in (spec.get("parameters") or {}).items() if k in declared}
        manoeuvre = build(str(name), params, float(speed), **options)
    except (InputError, AttributeError, KeyError, TypeError, ValueError) as exc:
        return None, f"none: '{name}' could not be rebuilt ({exc})"
    told = ", ".join(f"{k}={v}" for k, v in options.items())
    return manoeuvre, f"'{name}' rebuilt at {float(speed):g} km/h" + (f" with {told}" if told else "")
