"""The ``trikedyn`` command: a thin command map over the Python API.

Every command has ``--help`` and ``--json``. A user's mistake (file, field, value) prints one line,
``trikedyn: error: WHERE: WHAT``, and exits with code 2; nothing else is printed.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from . import __version__
from .errors import InputError

app = typer.Typer(
    name="trikedyn",
    help="Stability analysis of three-wheeled vehicles: measure, model, drive, judge, study.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    add_completion=False,
)
vehicle_app = typer.Typer(help="Vehicle parameter sets: list, show, check, export.", no_args_is_help=True)
cg_app = typer.Typer(help="Centre of gravity: from wheel weighings, and with payload.", no_args_is_help=True)
app.add_typer(vehicle_app, name="vehicle")
app.add_typer(cg_app, name="cg")

def _within(low: float, high: float, unit: str = "", *, above: bool = False):
    """Typer callback: the option's value must be finite and within ``[low, high]`` (``(low, high]`` with
    ``above``); None passes (an option left out)."""

    def check(ctx: typer.Context, param: typer.CallbackParam, value):
        if value is None or ctx.resilient_parsing:
            return value
        name = max(param.opts, key=len) if param.opts else param.name
        number = float(value)
        ok = math.isfinite(number) and (number > low if above else number >= low) and number <= high
        if not ok:
            bound = f"{'>' if above else '>='} {low:g} and <= {high:g}"
            raise InputError(f"must be {bound}{' ' + unit if unit else ''}, got {value!r}", where=name)
        return value

    return check


JsonOpt = Annotated[bool, typer.Option("--json", help="Print machine-readable JSON instead of text.")]
ForceOpt = Annotated[bool, typer.Option("--force", help="Replace output files that exist already.")]
VehicleArg = Annotated[str, typer.Argument(help="Preset name (see `trikedyn vehicle list`) or a .toml file.")]


_WARNINGS: list[str] = []
"""Warnings raised while a command runs (printed as one line each, and listed under ``warnings`` in JSON)."""


def _emit(data, as_json: bool, text=None) -> None:
    """Print a command's result: JSON (always valid: non-finite numbers become null, with a warning), or
    ``text`` (a string, or a function of nothing that makes it: text is only formatted when asked for)."""
    if as_json:
        clean, bad = _finite(data)
        if isinstance(clean, dict) and (bad or _WARNINGS):
            notes = [*_WARNINGS, *(f"{p or 'value'}: non-finite number replaced by null" for p in bad)]
            clean = {**clean, "warnings": [*clean.get("warnings", []), *notes]}
        typer.echo(json.dumps(clean, indent=2, default=_json_default, allow_nan=False))
    elif text is not None:
        typer.echo(text() if callable(text) else text)
    else:
        typer.echo(json.dumps(_finite(data)[0], indent=2, default=_json_default, allow_nan=False))


def _json_default(obj):
    import numpy as np

    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def _finite(node, path: str = ""):
    """``node`` with every non-finite float replaced by None, and the paths where that happened."""
    import math

    if isinstance(node, dict):
        out, bad = {}, []
        for key, value in node.items():
            out[key], sub = _finite(value, f"{path}.{key}" if path else str(key))
            bad += sub
        return out, bad
    if isinstance(node, list | tuple):
        out, bad = [], []
        for i, value in enumerate(node):
            item, sub = _finite(value, f"{path}[{i}]")
            out.append(item)
            bad += sub
        return out, bad
    if hasattr(node, "tolist") and not isinstance(node, str):  # numpy arrays and scalars
        return _finite(node.tolist(), path)
    if isinstance(node, float) and not math.isfinite(node):
        return None, [path]
    return node, []


def _version(value: bool):
    if value:
        typer.echo(f"trikedyn {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Show the version and exit.")
    ] = False,
):
    """trikedyn: how fast can a three-wheeler safely go, and why."""


# ------------------------------------------------------------------------------------------------
# vehicle
# ------------------------------------------------------------------------------------------------
@vehicle_app.command("list")
def vehicle_list(as_json: JsonOpt = False):
    """List the parameter sets shipped with trikedyn."""
    from .params import list_presets, load_vehicle

    rows = [{"name": n, "description": load_vehicle(n).params.description} for n in list_presets()]
    _emit(rows, as_json, "\n".join(f"{r['name']:<24} {r['description']}" for r in rows))


@vehicle_app.command("show")
def vehicle_show(vehicle: VehicleArg, as_json: JsonOpt = False):
    """Show every value of a parameter set, marking assumed values (*) and their reasons."""
    from .params import load_vehicle

    pset = load_vehicle(vehicle)
    data = pset.params.model_dump(mode="json", exclude_none=True)
    if as_json:
        _emit({"origin": pset.origin, "parameters": data, "notes": pset.notes}, True)
        return
    lines = [f"{pset.name}: {pset.params.description}", f"source: {pset.params.source}", ""]
    for path, value in _flatten(data):
        note = pset.notes.get(path, {})
        mark = "*" if "assumed" in note else " "
        lines.append(f"{mark} {path:<48} {value}")
    assumed = pset.assumed()
    lines += ["", f"* assumed ({len(assumed)} values):"]
    lines += [f"  {k}: {v}" for k, v in assumed.items()]
    typer.echo("\n".join(lines))


def _flatten(node, prefix=""):
    if isinstance(node, dict):
        for key, value in node.items():
            yield from _flatten(value, f"{prefix}.{key}" if prefix else key)
    elif isinstance(node, list) and node and all(isinstance(i, dict) for i in node):
        for i, item in enumerate(node):
            label = item.get("name", str(i))
            yield from _flatten({k: v for k, v in item.items() if k != "name"}, f"{prefix}.{label}")
    else:
        yield prefix, node


@vehicle_app.command("check")
def vehicle_check(vehicle: VehicleArg, as_json: JsonOpt = False):
    """Audit a parameter set for consistency (Eqs. 3-4, CG against loads, support triangle, ...).

    Exits 0 even when it finds inconsistencies: they are findings to read, not errors.
    """
    from .params import audit, load_vehicle

    pset = load_vehicle(vehicle)
    findings = audit(pset)
    if as_json:
        _emit({"vehicle": pset.name, "findings": [f.to_dict() for f in findings]}, True)
        return
    width = max(len(f.level) for f in findings)
    lines = [f"{pset.name} ({pset.origin})"] + [f"{f.level.upper():<{width}}  {f.topic}: {f.message}" for f in findings]
    bad = sum(f.level == "inconsistent" for f in findings)
    lines.append(f"{len(findings)} findings, {bad} inconsistent")
    typer.echo("\n".join(lines))


@vehicle_app.command("export")
def vehicle_export(
    vehicle: VehicleArg, file: Annotated[Path, typer.Argument(help="TOML file to write.")], force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Write a parameter set to a TOML file (with its notes) to start your own vehicle from."""
    from ._files import atomic_write_path, check_output
    from .params import load_vehicle, save_vehicle

    check_output(file, force=force, reads=[vehicle])
    pset = load_vehicle(vehicle)
    atomic_write_path(file, lambda tmp: save_vehicle(pset, tmp))
    _emit({"wrote": str(file)}, as_json, f"wrote {file}")


# ------------------------------------------------------------------------------------------------
# cg
# ------------------------------------------------------------------------------------------------
@cg_app.command("weigh")
def cg_weigh(file: Annotated[Path, typer.Argument(help="Weighing record (TOML); see the docs.")], as_json: JsonOpt = False):
    """Mass and CG from wheel weighings: x, y level; z from raised-axle weighings (least squares)."""
    from .measure.weighing import load_weighing, reduce_weighing

    result = reduce_weighing(load_weighing(file), where=str(file)).to_dict()
    text = (
        f"mass {result['mass_kg']:.2f} ± {result['mass_std_kg']:.2f} kg\n"
        f"cg x {result['cg_x_m'] * 1000:.1f} ± {result['cg_x_std_m'] * 1000:.1f} mm\n"
        f"cg y {result['cg_y_m'] * 1000:.1f} ± {result['cg_y_std_m'] * 1000:.1f} mm"
    )
    if "cg_z_m" in result:
        text += f"\ncg z {result['cg_z_m'] * 1000:.1f} ± {result['cg_z_std_m'] * 1000:.1f} mm"
    _emit(result, as_json, text)


def _floats(text: str, n: int, option: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != n:
        raise InputError(f"expected {n} comma-separated numbers, got '{text}'", where=option)
    return values


@cg_app.command("payload")
def cg_payload(
    vehicle: VehicleArg,
    freight: Annotated[float, typer.Option(callback=_within(0, 2000, "kg"), help="The paper's freight [kg] at the vehicle's freight site.")] = 0.0,
    point: Annotated[list[str], typer.Option(help="Point mass 'KG,X,Y,Z' [kg, m]; repeatable.")] = [],  # noqa: B006
    box: Annotated[list[str], typer.Option(help="Box 'KG,X,Y,Z,LX,LY,LZ' [kg, m]; repeatable.")] = [],  # noqa: B006
    remove: Annotated[bool, typer.Option(help="Take the payload off instead of adding it.")] = False,
    as_json: JsonOpt = False,
):
    """Mass, CG and inertia of a vehicle with a payload added (or removed)."""
    from .measure.cg import Box, Payload, PointMass
    from .params import freight as paper_freight
    from .params import load_vehicle, mass_properties, with_payload

    pset = load_vehicle(vehicle)
    items = list(paper_freight(pset.params, freight).items) if freight else []
    for i, spec in enumerate(point):
        m, x, y, z = _floats(spec, 4, f"--point #{i + 1}")
        items.append(PointMass(m, (x, y, z), name=f"--point #{i + 1}"))
    for i, spec in enumerate(box):
        m, x, y, z, lx, ly, lz = _floats(spec, 7, f"--box #{i + 1}")
        items.append(Box(m, (x, y, z), (lx, ly, lz), name=f"--box #{i + 1}"))
    mp = mass_properties(with_payload(pset, Payload("cli", tuple(items)), remove=remove).params)
    base = pset.params.mass.total_kg
    data = {"total_kg": mp.mass_kg, "payload_kg": mp.mass_kg - base, "cg_m": mp.cg_m, "inertia_kgm2": mp.inertia_kgm2}
    i = mp.inertia_kgm2
    text = (
        f"total {mp.mass_kg:.2f} kg (payload {mp.mass_kg - base:+.2f} kg)\n"
        f"cg ({mp.cg_m[0] * 1000:.1f}, {mp.cg_m[1] * 1000:.1f}, {mp.cg_m[2] * 1000:.1f}) mm\n"
        f"Ixx {i[0, 0]:.1f}  Iyy {i[1, 1]:.1f}  Izz {i[2, 2]:.1f} kg m^2"
    )
    _emit(data, as_json, text)


@cg_app.command("freight-table")
def cg_freight_table(
    vehicle: Annotated[str, typer.Argument(help="Preset name or .toml file.")] = "reference-etrike",
    masses: Annotated[str, typer.Option(help="Freight masses [kg], comma-separated.")] = "0,50,100,150,200",
    as_json: JsonOpt = False,
):
    """CG against freight mass, like the paper's Table 3."""
    from .params import load_vehicle, mass_properties, with_freight

    pset = load_vehicle(vehicle)
    rows = []
    for text in masses.split(","):
        m = _floats(text, 1, "--masses")[0]
        cg = mass_properties(with_freight(pset, m).params).cg_m
        rows.append({"freight_kg": m, "cg_x_m": cg[0], "cg_y_m": cg[1], "cg_z_m": cg[2]})
    text = "freight_kg   x_mm    y_mm    z_mm\n" + "\n".join(
        f"{r['freight_kg']:>10.1f} {r['cg_x_m'] * 1e3:7.1f} {r['cg_y_m'] * 1e3:7.1f} {r['cg_z_m'] * 1e3:7.1f}" for r in rows
    )
    _emit(rows, as_json, text)


# ------------------------------------------------------------------------------------------------
# logs and suspension identification
# ------------------------------------------------------------------------------------------------
log_app = typer.Typer(help="IMU logs: what a file holds, and conversion to CSV.", no_args_is_help=True)
app.add_typer(log_app, name="log")

FormatOpt = Annotated[
    str, typer.Option("--format", help="Log format (auto-detected by default): " + ", ".join(
        ["auto", "witmotion-sdk", "witmotion-pc", "witmotion-2025", "wt901sd-binary", "bwt901cl-csv", "csv"]))
]
RateOpt = Annotated[
    float | None, typer.Option("--sample-rate", help="Sample rate [Hz] for files that store no time.")
]
SensorOpt = Annotated[int, typer.Option("--sensor", callback=_within(1, 64), help="Which sensor of a multi-sensor file (1, 2, ...).")]


def _read(log: Path, fmt: str, sensor: int, rate: float | None):
    from .measure.logs import read_log

    return read_log(log, fmt, sensor=sensor, sample_rate_hz=rate)


@log_app.command("info")
def log_info(
    log: Annotated[Path, typer.Argument(help="IMU log file.")],
    fmt: FormatOpt = "auto",
    sensor: SensorOpt = 1,
    rate: RateOpt = None,
    as_json: JsonOpt = False,
):
    """Format, length, sample rate and channels of an IMU log, and what the reader did to it."""
    imu = _read(log, fmt, sensor, rate)
    data = imu.data
    summary = {
        "file": str(log),
        "format": imu.format,
        "samples": len(data),
        "duration_s": float(data["time_s"].iloc[-1]) if len(data) else 0.0,
        "sample_rate_hz": imu.sample_rate_hz,
        "channels": {
            c: {"original": imu.original_columns.get(c, c), "mean": float(data[c].mean()), "std": float(data[c].std())}
            for c in data.columns
            if c != "time_s" and data[c].dtype.kind == "f"
        },
        "notes": list(imu.notes),
    }
    lines = [
        f"{log}: {imu.format}, {summary['samples']} samples over {summary['duration_s']:.2f} s "
        f"({summary['sample_rate_hz']:.2f} Hz)"
    ]
    lines += [f"  {c:<18} mean {v['mean']:>10.4f}  std {v['std']:>9.4f}   ({v['original']})" for c, v in summary["channels"].items()]
    lines += [f"  note: {n}" for n in imu.notes]
    _emit(summary, as_json, "\n".join(lines))


@log_app.command("convert")
def log_convert(
    log: Annotated[Path, typer.Argument(help="IMU log file.")],
    out: Annotated[Path, typer.Argument(help="Output CSV (SI units, time in s from the start).")],
    fmt: FormatOpt = "auto",
    sensor: SensorOpt = 1,
    rate: RateOpt = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Convert an IMU log to a plain CSV in SI units (never onto the log itself)."""
    from ._files import atomic_write_path, check_output

    check_output(out, force=force, reads=[log])
    imu = _read(log, fmt, sensor, rate)
    atomic_write_path(out, lambda tmp: imu.data.to_csv(tmp, index=False))
    _emit({"wrote": str(out), "samples": len(imu.data)}, as_json, f"wrote {out} ({len(imu.data)} samples)")


@app.command("identify")
def identify(
    log: Annotated[Path, typer.Argument(help="Speed-bump accelerometer record (any supported IMU log).")],
    sprung_mass: Annotated[float, typer.Option("--sprung-mass", callback=_within(1, 5000, "kg"), help="Sprung mass on this suspension, M_s [kg].")],
    axis: Annotated[str, typer.Option("--axis", help="Accelerometer axis: x, y or z.")] = "z",
    tyre_stiffness: Annotated[
        float | None, typer.Option("--tyre-stiffness", help="Tyre stiffness [N/m]: correct K for the tyre in series.")
    ] = None,
    resample: Annotated[
        float | None, typer.Option("--resample-hz", help="Resample to this rate before analysis [Hz] (auto).")
    ] = None,
    fmt: FormatOpt = "auto",
    sensor: SensorOpt = 1,
    rate: RateOpt = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Write the Fig. 2c-d style figure (PNG).")] = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Suspension stiffness and damping from a speed-bump record (paper Eqs. 1-4).

    Log decrement over n cycles on both the compression and the extension crests (Eqs. 1-2), natural
    frequency from a windowed, zero-padded spectrum, K from Eq. 3 and C from Eq. 4.
    """
    from .measure.suspension import identify_suspension

    if axis not in ("x", "y", "z"):
        raise InputError(f"expected x, y or z, got '{axis}'", where="--axis")
    if plot is not None:
        from ._files import check_output

        check_output(plot, force=force, reads=[log])
    imu = _read(log, fmt, sensor, rate)
    result = identify_suspension(
        imu.data["time_s"].to_numpy(), imu.channel(f"a{axis}_mps2"), sprung_mass,
        tyre_stiffness_N_per_m=tyre_stiffness, resample_hz=resample,
    )
    data = result.to_dict() | {"file": str(log), "axis": axis}
    if plot is not None:
        _save_figure(result.plot(), plot, dpi=120)
        data["plot"] = str(plot)
    text = lambda: "\n".join(  # noqa: E731 - formatted only when text is asked for
        [
            f"natural frequency  {data['natural_frequency_hz']:.3f} Hz",
            f"damping ratio      {data['damping_ratio']:.3f}   (log decrement {data['log_decrement']:.3f}, "
            f"{data['cycles_used']} cycles)",
            f"stiffness K        {data['stiffness_N_per_m']:.0f} N/m   (Eq. 3)",
            f"damping C          {data['damping_Ns_per_m']:.1f} N s/m   (Eq. 4)",
        ]
        + [f"warning: {w}" for w in data.get("warnings", [])]
    )
    _emit(data, as_json, text)


@app.command("modes")
def modes_cmd(
    vehicle: VehicleArg,
    freight: Annotated[float, typer.Option(callback=_within(0, 2000, "kg"), help="The paper's freight aboard [kg].")] = 0.0,
    as_json: JsonOpt = False,
):
    """Static equilibrium, and the vibration modes of the linearised model about it."""
    from .model.linear import modes
    from .model.statics import static_equilibrium
    from .model.vehicle import build_model
    from .params import load_vehicle, with_freight

    model = build_model(with_freight(load_vehicle(vehicle), freight))
    eq = static_equilibrium(model)
    found = modes(model, eq)
    data = {
        "vehicle": model.params.name,
        "freight_kg": freight,
        "static_wheel_loads_N": eq.wheel_loads_N,
        "modes": [m.to_dict() for m in found],
    }
    lines = [f"{model.params.name}: static wheel loads " + ", ".join(f"{k} {v:.0f} N" for k, v in eq.wheel_loads_N.items())]
    lines += [f"{'mode':<24}{'f [Hz]':>9}{'zeta':>8}   participation"]
    for m in found:
        share = ", ".join(f"{k} {v:.0%}" for k, v in list(m.participation.items())[:3])
        lines.append(f"{m.name:<24}{m.frequency_hz:>9.3f}{m.damping_ratio:>8.3f}   {share}")
    _emit(data, as_json, "\n".join(lines))


OptionOpt = Annotated[
    list[str], typer.Option("--option", "-o", help="A manoeuvre option KEY=VALUE (see `trikedyn manoeuvres`); repeatable.")
]
ManoeuvreOpt = Annotated[
    str, typer.Option("--manoeuvre", help="A registered manoeuvre (see `trikedyn manoeuvres`: dlc, slc, circle, step, "
                      "fishhook, ...) or a path .csv file.")
]


def _manoeuvre_options(manoeuvre: str, pairs: list[str], **legacy) -> dict:
    """``-o KEY=VALUE`` pairs, plus the older shortcuts (``--radius``, ``--steer-deg``) where the manoeuvre
    takes that option."""
    from .manoeuvres.registry import get, parse_options

    options = parse_options(pairs)
    if manoeuvre.lower().endswith(".csv"):
        return options
    try:
        kind = get(manoeuvre)
    except InputError as exc:
        raise InputError(exc.reason, where="--manoeuvre") from None
    for key, value in legacy.items():
        if value is not None and key not in options and any(o.name == key for o in kind.options):
            options[key] = value
    return options


@app.command("manoeuvres")
def manoeuvres_cmd(as_json: JsonOpt = False):
    """List the registered manoeuvres and their options (units in the option names)."""
    from .manoeuvres.registry import available

    kinds = [k.to_dict() for k in available()]
    lines = []
    for k in kinds:
        lines.append(f"{k['name']:<20} {k['title']} ({'closed loop' if k['closed_loop'] else 'open-loop steer'})")
        lines.append(f"{'':<20} {k['summary']}")
        for o in k["options"]:
            unit = f" [{o['unit']}]" if o["unit"] else ""
            lines.append(f"{'':<22}-o {o['name']}={o['default']}{unit}: {o['help']}")
    lines.append("a path .csv file is driven as the 'path' manoeuvre (columns x_m, y_m)")
    _emit(kinds, as_json, "\n".join(lines))


def _check_run_file(out: Path, force: bool, reads=()) -> None:
    """A run file name (``.parquet`` or ``.csv``) and the ``.json`` beside it, checked before the run."""
    from ._files import check_output

    if out.suffix not in (".parquet", ".csv"):
        raise InputError("expected a .parquet or .csv file name", where=str(out))
    check_output(out, force=force, reads=reads)
    check_output(out.with_suffix(".json"), force=force, reads=reads)


def _write_run(result, out: Path, summary: dict) -> None:
    from ._files import atomic_write_path

    frame = result.to_pandas().reset_index()
    if out.suffix == ".parquet":
        atomic_write_path(out, lambda tmp: frame.to_parquet(tmp, index=False))
    else:
        atomic_write_path(out, lambda tmp: frame.to_csv(tmp, index=False))
    meta = {k: v for k, v in result.meta.items() if k != "driver"} | {"summary": summary}
    if result.manoeuvre is not None:
        meta["manoeuvre_spec"] = result.manoeuvre.to_dict()
    text = json.dumps(_finite(meta)[0], indent=2, default=_json_default, allow_nan=False)
    atomic_write_path(out.with_suffix(".json"), lambda tmp: tmp.write_text(text, encoding="utf-8"))


def _save_figure(fig, path: Path, dpi: int = 110) -> None:
    """Save a matplotlib figure atomically and close it."""
    import matplotlib.pyplot as plt

    from ._files import atomic_write_path

    try:
        atomic_write_path(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format=path.suffix.lstrip(".").lower() or "png"))
    except ValueError as exc:  # an unknown image format
        raise InputError(f"cannot write this kind of figure: {exc}", where=str(path)) from None
    finally:
        plt.close(fig)


@app.command("simulate")
def simulate_cmd(
    vehicle: VehicleArg,
    manoeuvre: ManoeuvreOpt = "dlc",
    speed: Annotated[float, typer.Option("--speed", callback=_within(0, 400, "km/h", above=True), help="Target speed [km/h].")] = 30.0,
    payload: Annotated[float, typer.Option("--payload", callback=_within(0, 2000, "kg"), help="The paper's freight aboard [kg].")] = 0.0,
    option: OptionOpt = [],  # noqa: B006
    radius: Annotated[float | None, typer.Option("--radius", callback=_within(1, 10_000, "m"), help="Circle radius [m] (same as -o radius_m=...).")] = None,
    steer_deg: Annotated[float | None, typer.Option("--steer-deg", callback=_within(-90, 90, "deg"), help="Step steer angle about the steering axis [deg] "
                                                    "(same as -o steer_deg=...).")] = None,
    duration: Annotated[float | None, typer.Option("--duration", callback=_within(0, 3600, "s", above=True), help="Simulated time [s] (default: the manoeuvre's).")] = None,
    out: Annotated[Path | None, typer.Option("--out", help="Write the run (.parquet or .csv; a .json summary beside it).")] = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Drive a manoeuvre and report how it went over its judged window (cone strikes, RI, wheel loads, ...)."""
    import numpy as np

    from .analysis.metrics import summary
    from .params import load_vehicle, with_freight
    from .simulate.closed_loop import run

    if not np.isfinite(speed) or speed <= 0:
        raise InputError(f"must be > 0 km/h, got {speed!r}", where="--speed")
    if duration is not None and (not np.isfinite(duration) or duration <= 0):
        raise InputError(f"must be > 0 s, got {duration!r}", where="--duration")
    options = _manoeuvre_options(manoeuvre, option, radius_m=radius, steer_deg=steer_deg)
    if out is not None:
        _check_run_file(out, force, reads=[vehicle, manoeuvre, options.get("file")])
    pset = with_freight(load_vehicle(vehicle), payload)
    result = run(pset, manoeuvre, speed_kmh=speed, duration_s=duration, **options)
    data = summary(result) | {"vehicle": pset.name, "payload_kg": payload, "speed_kmh": speed}
    if not result.success:
        data["failure"] = result.message
    elif duration is None:
        from .analysis.handling_tests import manoeuvre_figures

        try:  # the test's own figures (ISO 7401 step, sweep, ISO 7975, ISO 4138)
            figures = manoeuvre_figures(result)
        except InputError as exc:  # the run is fine; its reduction is not possible (say why)
            data["figures_error"] = str(exc)
        else:
            if figures is not None:
                data["figures"] = figures
    if out is not None:
        _write_run(result, out, data)
        data["out"] = str(out)
    _emit(data, as_json, lambda: "\n".join(f"{k:<32} {v}" for k, v in data.items()))


@app.command("plot")
def plot_cmd(
    run: Annotated[Path, typer.Argument(help="A run file written by `trikedyn simulate --out`.")],
    out: Annotated[Path | None, typer.Option("--out", help="PNG to write (default: beside the run).")] = None,
    channels: Annotated[str, typer.Option(help="Comma-separated channels to plot.")] = "speed_mps,ay_mps2,yaw_rate_radps,ri,min_wheel_load_N",
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Time histories of a run (like the paper's Figs. 7-9)."""
    from ._files import check_output

    target = out or run.with_suffix(".png")
    check_output(target, force=force, reads=[run])
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .analysis.compare import load_table

    frame, kind = load_table(run)
    names = [c.strip() for c in channels.split(",") if c.strip()]
    missing = [c for c in names if c not in frame.columns]
    if missing:
        from difflib import get_close_matches

        hint = get_close_matches(missing[0], list(frame.columns), n=1)
        raise InputError(f"no channel '{missing[0]}'" + (f"; did you mean '{hint[0]}'?" if hint else ""), where=str(run))
    fig, axes = plt.subplots(len(names), 1, sharex=True, figsize=(7, 1.8 * len(names)))
    for ax, name in zip(np.atleast_1d(axes), names, strict=False):
        ax.plot(frame["time_s"], frame[name])
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[-1].set_xlabel("time [s]")
    fig.tight_layout()
    _save_figure(fig, target, dpi=110)
    _emit({"wrote": str(target), "channels": names}, as_json, f"wrote {target}")


@app.command("compare")
def compare_cmd(
    log: Annotated[Path, typer.Argument(help="Measured IMU log (any supported format) or a run file.")],
    run: Annotated[Path, typer.Argument(help="Simulated run file (or another log).")],
    channels: Annotated[str, typer.Option(help="Channels to compare (the paper compares lateral acceleration and yaw rate).")] = "ay_mps2,wz_radps",
    max_offset: Annotated[float, typer.Option("--max-offset", callback=_within(0, 600, "s", above=True), help="Largest time offset searched [s].")] = 5.0,
    plot: Annotated[Path | None, typer.Option("--plot", help="Write measured over simulated (PNG), like Figs. 7-8.")] = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Compare a measured log with a simulation: time offset by cross-correlation, RMSE, NRMSE, peak error."""
    from .analysis.compare import compare, load_table

    if plot is not None:
        from ._files import check_output

        check_output(plot, force=force, reads=[log, run])

    measured = _imu_view(load_table(log)[0])
    simulated = _imu_view(load_table(run)[0])
    names = [c.strip() for c in channels.split(",") if c.strip()]
    result = compare(measured, simulated, channels=names, max_offset_s=max_offset)
    data = result.to_dict()
    if plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        _save_figure(result.plot(), plot, dpi=110)
        data["plot"] = str(plot)
    lines = [f"time offset {data['offset_s']:+.3f} s (measured time + offset = simulated time)"]
    for name, m in data["channels"].items():
        lines.append(f"{name:<12} RMSE {m['rmse']:.4f}  NRMSE {m['nrmse']:.3f}  peak {m['peak_error']:.4f}  r {m['correlation']:.3f}")
    _emit(data, as_json, "\n".join(lines))


def _imu_view(frame):
    """A run table seen as an IMU log: its emulated sensor channels under the log names."""
    renamed = {c: c[len("imu_"):] for c in frame.columns if c.startswith("imu_")}
    if not renamed:
        return frame
    keep = ["time_s", *renamed]
    return frame[keep].rename(columns=renamed)


@app.command("threshold")
def threshold_cmd(
    vehicle: VehicleArg,
    manoeuvre: ManoeuvreOpt = "dlc",
    payload: Annotated[float, typer.Option("--payload", callback=_within(0, 2000, "kg"), help="The paper's freight aboard [kg].")] = 0.0,
    option: OptionOpt = [],  # noqa: B006
    stiffness: Annotated[float, typer.Option("--stiffness-scale", callback=_within(0, 100, above=True), help="Suspension stiffness factor (Table 2).")] = 1.0,
    damping: Annotated[float, typer.Option("--damping-scale", callback=_within(0, 100, above=True), help="Suspension damping factor (Table 2).")] = 1.0,
    low: Annotated[float, typer.Option("--low", callback=_within(0, 400, "km/h", above=True), help="Lowest speed searched [km/h].")] = 10.0,
    high: Annotated[float, typer.Option("--high", callback=_within(0, 400, "km/h", above=True), help="Highest speed searched [km/h].")] = 90.0,
    resolution: Annotated[float, typer.Option("--resolution", callback=_within(0.001, 50, "km/h"), help="Resolution [km/h].")] = 0.1,
    as_json: JsonOpt = False,
):
    """Threshold velocity: the highest speed with every wheel on the ground through the manoeuvre."""
    from .analysis.threshold import threshold_velocity
    from .params import load_vehicle, scale_suspension, with_freight

    options = _manoeuvre_options(manoeuvre, option)
    pset = with_freight(scale_suspension(load_vehicle(vehicle), stiffness=stiffness, damping=damping), payload)
    result = threshold_velocity(pset, manoeuvre, options=options, low_kmh=low, high_kmh=high, resolution_kmh=resolution)
    data = result.to_dict(runs=True) | {"vehicle": pset.name, "manoeuvre": manoeuvre, "options": options,
                                        "payload_kg": payload, "stiffness_scale": stiffness, "damping_scale": damping}
    if result.threshold_speed_kmh is None:
        headline = f"no threshold: {result.detail}"
    else:
        headline = f"threshold velocity {result.threshold_speed_kmh:.1f} km/h ({result.limit or 'no limit found'})"
    lines = [headline, f"  {result.detail}"]
    if result.first_cone_strike_kmh is not None:
        lines.append(f"  first cone strike seen at {result.first_cone_strike_kmh:.1f} km/h")
    lines.append(f"  {len(result.runs)} runs")
    _emit(data, as_json, "\n".join(lines))


@app.command("handling")
def handling_cmd(
    vehicle: VehicleArg,
    radius: Annotated[float, typer.Option("--radius", callback=_within(1, 1000, "m"), help="Circle radius [m].")] = 20.0,
    payload: Annotated[float, typer.Option("--payload", callback=_within(0, 2000, "kg"), help="The paper's freight aboard [kg].")] = 0.0,
    start_speed: Annotated[float, typer.Option("--start-speed", callback=_within(0, 200, "km/h", above=True), help="Speed at the start [km/h].")] = 15.0,
    plot: Annotated[Path | None, typer.Option("--plot", help="Write the handling diagram (PNG).")] = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """ISO 4138 steady-state circular driving: handling diagram, understeer, roll and sideslip gradients [deg/g]."""
    import numpy as np

    from .analysis.handling_tests import steady_state_test
    from .params import load_vehicle, with_freight

    for value, where in ((radius, "--radius"), (start_speed, "--start-speed")):
        if not np.isfinite(value) or value <= 0:
            raise InputError(f"must be > 0, got {value!r}", where=where)
    if plot is not None:
        from ._files import check_output

        check_output(plot, force=force, reads=[vehicle])
    pset = with_freight(load_vehicle(vehicle), payload)
    test = steady_state_test(pset, radius_m=radius, start_speed_kmh=start_speed)
    data = test.to_dict() | {"vehicle": pset.name, "payload_kg": payload}
    if plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        _save_figure(test.plot(), plot, dpi=120)
        data["plot"] = str(plot)
    text = lambda: "\n".join([  # noqa: E731
        f"{pset.name}: ISO 4138 constant radius {radius:g} m",
        f"understeer gradient   {data['understeer_gradient_deg_per_g']:+.3f} deg/g",
        f"roll gradient         {data['roll_gradient_deg_per_g']:+.3f} deg/g",
        f"sideslip gradient     {data['sideslip_gradient_deg_per_g']:+.3f} deg/g",
        f"ends at a_y           {data['max_lateral_acceleration_mps2']:.2f} m/s^2: {data['limit']} ({data['limit_detail']})",
    ])
    _emit(data, as_json, text)


@app.command("study")
def study_cmd(
    spec: Annotated[str, typer.Argument(help="Study spec (TOML file), or 'paper' for the built-in Fig. 10 study.")],
    workers: Annotated[int | None, typer.Option("--workers", callback=_within(0, 256), help="Processes on this machine (default: all cores).")] = None,
    dask_local: Annotated[int | None, typer.Option("--dask-local", callback=_within(1, 256), help="Run on a local Dask cluster of N workers.")] = None,
    scheduler: Annotated[str | None, typer.Option("--scheduler", help="Dask scheduler address (tcp://host:port).")] = None,
    out: Annotated[Path, typer.Option("--out", help="Output folder (its store makes a re-run resume).")] = Path("study-output"),
    dry_run: Annotated[bool, typer.Option("--dry-run", help="Check the spec and count its scenarios; run nothing.")] = False,
    max_scenarios: Annotated[int, typer.Option("--max-scenarios", callback=_within(1, 1e9), help="Refuse a spec with more scenarios than this.")] = 10_000,
    as_json: JsonOpt = False,
):
    """Parametric study of the threshold velocity: parallel, resumable, CSV and Parquet tables."""
    if dry_run:
        from .study import count_scenarios, load_spec

        loaded = load_spec(spec)
        count, exact = count_scenarios(loaded)
        if count > max_scenarios:
            raise InputError(f"the spec expands to {'up to ' if not exact else ''}{count:,} scenarios, more than the "
                             f"limit {max_scenarios:,}; pass --max-scenarios {count} to run it", where=str(spec))
        data = {"study": loaded.name, "vehicle": loaded.vehicle, "manoeuvres": list(loaded.manoeuvres),
                "scenarios": count, "exact": exact, "groups": [g.name for g in loaded.groups]}
        _emit(data, as_json, lambda: (f"study '{loaded.name}': {count} scenarios on {loaded.vehicle} "
                                      f"({', '.join(loaded.manoeuvres)}); nothing run"))
        return
    from .study.runner import study_command

    study_command(spec, workers, dask_local, scheduler, out, as_json, max_scenarios=max_scenarios)


@app.command("reproduce")
def reproduce_cmd(
    out: Annotated[Path, typer.Option("--out", help="Output folder (created; a non-empty one needs --force).")] = Path(
        "trikedyn-output"
    ),
    no_figures: Annotated[bool, typer.Option("--no-figures", help="Skip the PNG figures and the report.")] = False,
    no_study: Annotated[bool, typer.Option("--no-study", help="Skip the parametric study (Fig. 10).")] = False,
    workers: Annotated[int | None, typer.Option("--workers", help="Processes for the study (default 2).")] = 2,
    force: Annotated[bool, typer.Option("--force", help="Write into a folder that holds files (they are replaced).")] = False,
    as_json: JsonOpt = False,
):
    """The reference paper's workflow on the built-in reference vehicle: tables, figures, verdicts, report.html."""
    from ._files import check_output_folder
    from .reproduce import reproduce

    if workers is not None and not 1 <= workers <= 256:
        raise InputError(f"expected 1 to 256 processes, got {workers}", where="--workers")
    check_output_folder(out, force=force)
    summary = reproduce(out, figures=not no_figures, study=not no_study, workers=workers)
    text = "\n".join(
        [f"wrote {len(summary['files'])} files to {out}"]
        + [f"- {s['verdict'].upper()}: {s['paper']}" for s in summary["statements"]]
        + [f"see {out / 'summary.md'}"]
    )
    _emit({k: summary[k] for k in ("out_dir", "statements", "files")}, as_json, text)


@app.command("tilt")
def tilt_cmd(
    vehicle: VehicleArg,
    payload: Annotated[float, typer.Option("--payload", callback=_within(0, 2000, "kg"), help="The paper's freight aboard \\[kg].")] = 0.0,
    side: Annotated[str, typer.Option("--side", help="The side that goes down: left, right or both.")] = "both",
    require_deg: Annotated[
        float | None, typer.Option("--require-deg", help="Required tilt angle \\[deg] (e.g. 35): pass or fail.")
    ] = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Write wheel loads \\[N] against table angle \\[deg] (PNG).")] = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Tilt-table test: the table angle at which the first wheel lifts, on the compliant model."""
    from .analysis.tilt import tilt_table
    from .params import load_vehicle, with_freight

    if side not in ("left", "right", "both"):
        raise InputError(f"expected left, right or both, got '{side}'", where="--side")
    if not np.isfinite(payload) or payload < 0:
        raise InputError(f"must be >= 0 kg, got {payload!r}", where="--payload")
    if require_deg is not None and not (np.isfinite(require_deg) and 0.0 < require_deg < 90.0):
        raise InputError(f"expected an angle between 0 and 90 deg, got {require_deg!r}", where="--require-deg")
    if plot is not None:
        from ._files import check_output

        check_output(plot, force=force, reads=[vehicle])
    pset = with_freight(load_vehicle(vehicle), payload)
    result = tilt_table(pset, side=side, require_deg=require_deg)
    data = result.to_dict() | {"payload_kg": payload}
    if plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        _save_figure(result.plot(), plot, dpi=110)
        data["plot"] = str(plot)
    lines = [
        f"tilt angle {result.tilt_angle_deg:.1f} deg ({result.side}; {result.first_lifting_wheel} lifts first); "
        f"rigid {result.rigid_tilt_angle_deg:.1f} deg"
    ]
    for s in result.sides.values():
        lines.append(
            f"  {s.side:<6} {s.tilt_angle_deg:6.2f} deg  {s.first_lifting_wheel} lifts, body roll {s.body_roll_deg:.1f} deg; "
            f"rigid {s.rigid_tilt_angle_deg:.2f} deg about {s.tip_axis}"
        )
    if result.passes is not None:
        lines.append(f"  required {result.require_deg:g} deg: {'passes' if result.passes else 'FAILS'}")
    if plot is not None:
        lines.append(f"  wrote {plot}")
    _emit(data, as_json, "\n".join(lines))


# ------------------------------------------------------------------------------------------------
def _fail(message: str, as_json: bool, where: str | None = None) -> int:
    """One line on stderr (and, under --json, a JSON object on stdout); exit code 2."""
    line = " ".join(message.split())
    typer.echo(f"trikedyn: error: {line}", err=True)
    if as_json:
        typer.echo(json.dumps({"error": line, "where": where}, allow_nan=False))
    return 2


def _show_warning(message, category, filename, lineno, file=None, line=None):  # noqa: ARG001
    text = " ".join(str(message).split())
    _WARNINGS.append(text)
    typer.echo(f"trikedyn: warning: {category.__name__}: {text}", err=True)


def main(argv: list[str] | None = None) -> int:
    """Entry point: the one error boundary of the command line.

    A user's mistake or environment (a bad file, field or value; a file that cannot be written; a
    simulation that cannot start or that fails) prints one line ``trikedyn: error: WHERE: WHAT`` on stderr
    and exits with code 2; with ``--json`` the same error is also a JSON object ``{"error", "where"}`` on
    stdout. Warnings print as one line each. A genuine bug keeps its traceback (exit code 1).
    """
    import warnings

    args = list(sys.argv[1:] if argv is None else argv)
    as_json = "--json" in args
    _WARNINGS.clear()
    from .errors import SimulationError

    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = _show_warning
        try:
            result = app(args=args, prog_name="trikedyn", standalone_mode=False)
        except InputError as exc:
            return _fail(str(exc), as_json, exc.where)
        except SimulationError as exc:
            return _fail(f"simulation: {exc}", as_json, "simulation")
        except OSError as exc:
            from ._files import describe_os_error

            where = exc.filename if exc.filename is not None else "file system"
            return _fail(f"{where}: {describe_os_error(exc)}", as_json, str(where))
        except MemoryError:
            return _fail("input: too large to process in memory", as_json, "input")
        except KeyboardInterrupt:
            typer.echo("trikedyn: interrupted", err=True)
            return 130
        except SystemExit as exc:
            return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except Exception as exc:  # click's usage errors (unknown option, missing argument) and Exit
            if hasattr(exc, "format_message") and hasattr(exc, "exit_code"):
                ctx = getattr(exc, "ctx", None)
                where = ctx.command_path if ctx is not None else "trikedyn"
                return _fail(f"{where}: {exc.format_message()}", as_json, where)
            if type(exc).__name__ == "Abort":
                typer.echo("trikedyn: aborted", err=True)
                return 130
            if hasattr(exc, "exit_code") and type(exc).__name__ == "Exit":
                return int(exc.exit_code)
            raise
    return result if isinstance(result, int) else 0


def _console():  # pragma: no cover - console-script shim
    sys.exit(main())
