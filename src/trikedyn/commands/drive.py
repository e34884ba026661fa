"""``trikedyn modes``, ``manoeuvres``, ``simulate``, ``plot`` and ``compare``: the model, driven and looked at."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from ._common import (
    BandKmhOpt,
    BandPercentOpt,
    ForceOpt,
    FreightAliasOpt,
    JsonOpt,
    ManoeuvreOpt,
    OptionOpt,
    PayloadOpt,
    SpeedControlOpt,
    VehicleArg,
    emit,
    judging,
    key_values,
    manoeuvre_options,
    payload_kg,
    save_figure,
    within,
)


def modes_cmd(
    vehicle: VehicleArg,
    payload: PayloadOpt = 0.0,
    freight: FreightAliasOpt = None,
    speed: Annotated[float, typer.Option("--speed", callback=within(0, 400, "km/h"),
                                         help="Rolling straight ahead at this speed [km/h] (0: at rest).")] = 0.0,
    as_json: JsonOpt = False,
):
    """Static equilibrium, and the vibration modes of the linearised model about it, at rest or rolling
    straight ahead (--speed), named by what carries their kinetic energy."""
    from ..model.linear import modes
    from ..model.statics import static_equilibrium
    from ..model.vehicle import build_model
    from ..params import load_vehicle, with_freight
    from ..units import kmh_to_mps

    freight = payload_kg(payload, freight)
    model = build_model(with_freight(load_vehicle(vehicle), freight))
    eq = static_equilibrium(model)
    found = modes(model, eq, speed_mps=kmh_to_mps(speed))
    data = {
        "vehicle": model.params.name,
        "freight_kg": freight,
        "payload_kg": freight,
        "speed_kmh": speed,
        "static_wheel_loads_N": eq.wheel_loads_N,
        "modes": [m.to_dict() for m in found],
    }
    lines = [f"{model.params.name}: static wheel loads " + ", ".join(f"{k} {v:.0f} N" for k, v in eq.wheel_loads_N.items())]
    where = "at rest" if speed == 0 else f"rolling straight ahead at {speed:g} km/h"
    lines.append(f"modes {where}; participation: share of each mode's kinetic energy")
    width = max([24, *(len(m.name) + 2 for m in found)])
    lines += [f"{'mode':<{width}}{'f [Hz]':>9}{'zeta':>8}   participation"]
    for m in found:
        share = ", ".join(f"{k} {v:.0%}" for k, v in list(m.participation.items())[:3])
        lines.append(f"{m.name:<{width}}{m.frequency_hz:>9.3f}{m.damping_ratio:>8.3f}   {share}")
    emit(data, as_json, "\n".join(lines))


def manoeuvres_cmd(as_json: JsonOpt = False):
    """List the registered manoeuvres and their options (units in the option names)."""
    from ..manoeuvres.registry import available

    kinds = [k.to_dict() for k in available()]
    lines = []
    for k in kinds:
        lines.append(f"{k['name']:<20} {k['title']} ({'closed loop' if k['closed_loop'] else 'open-loop steer'})")
        lines.append(f"{'':<20} {k['summary']}")
        for o in k["options"]:
            unit = f" [{o['unit']}]" if o["unit"] else ""
            lines.append(f"{'':<22}-o {o['name']}={o['default']}{unit}: {o['help']}")
    lines.append("a path .csv file is driven as the 'path' manoeuvre (columns x_m, y_m)")
    emit(kinds, as_json, "\n".join(lines))


def simulate_cmd(
    vehicle: VehicleArg,
    manoeuvre: ManoeuvreOpt = "dlc",
    speed: Annotated[float, typer.Option("--speed", callback=within(0, 400, "km/h", above=True), help="Target speed [km/h].")] = 30.0,
    payload: PayloadOpt = 0.0,
    freight: FreightAliasOpt = None,
    option: OptionOpt = [],  # noqa: B006
    radius: Annotated[float | None, typer.Option("--radius", callback=within(1, 10_000, "m"), help="Circle radius [m] (same as -o radius_m=...).")] = None,
    steer_deg: Annotated[float | None, typer.Option("--steer-deg", callback=within(-90, 90, "deg"), help="Step steer angle about the steering axis [deg] "
                                                    "(same as -o steer_deg=...).")] = None,
    duration: Annotated[float | None, typer.Option("--duration", callback=within(0, 3600, "s", above=True), help="Simulated time [s] (default: the manoeuvre's).")] = None,
    out: Annotated[Path | None, typer.Option("--out", help="Write the run (.parquet or .csv; a .json summary beside it).")] = None,
    speed_control: SpeedControlOpt = "driver",
    band_percent: BandPercentOpt = 3.0,
    band_kmh: BandKmhOpt = 1.0,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Drive a manoeuvre and say how the vehicle did: the verdict (pass, lift-off, cone strike, path lost, spin,
    speed not held), the speed actually driven, and the figures over the judged window (RI, wheel loads, ...)."""
    payload = payload_kg(payload, freight)
    import numpy as np

    from ..analysis.metrics import summary
    from ..params import load_vehicle, with_freight
    from ..simulate.closed_loop import run

    if not np.isfinite(speed) or speed <= 0:
        raise InputError(f"must be > 0 km/h, got {speed!r}", where="--speed")
    if duration is not None and (not np.isfinite(duration) or duration <= 0):
        raise InputError(f"must be > 0 s, got {duration!r}", where="--duration")
    options = manoeuvre_options(manoeuvre, option, radius_m=radius, steer_deg=steer_deg)
    if out is not None:
        from ..simulate.runfile import check_run_file

        check_run_file(out, force, reads=[vehicle, manoeuvre, options.get("file")])
    rules = judging(band_percent, band_kmh)
    pset = with_freight(load_vehicle(vehicle), payload)
    result = run(pset, manoeuvre, speed_kmh=speed, duration_s=duration, speed_control=speed_control, **options)
    data = summary(result, rules) | {"vehicle": pset.name, "payload_kg": payload, "speed_kmh": speed,
                                     "speed_control": speed_control}
    if not result.success:
        data["failure"] = result.message
    elif duration is None:
        from ..analysis.handling_tests import manoeuvre_figures

        try:  # the test's own figures (ISO 7401 step, sweep, ISO 7975, ISO 4138)
            figures = manoeuvre_figures(result)
        except InputError as exc:  # the run is fine; its reduction is not possible (say why)
            data["figures_error"] = str(exc)
        else:
            if figures is not None:
                data["figures"] = figures
    if out is not None:
        from ..simulate.runfile import write_run

        write_run(result, out, data)
        data["out"] = str(out)
    emit(data, as_json, lambda: "\n".join(_verdict_lines(data) + key_values(
        {k: v for k, v in data.items() if k not in ("passed", "verdict", "reasons")})))


def _verdict_lines(data: dict) -> list[str]:
    """The verdict first, in words: what went wrong and when, and the speed driven against the target."""
    head = "PASS" if data["passed"] else f"FAIL: {data['verdict']}"
    lines = [f"{head}  ({data['manoeuvre']}, target {data['speed_kmh']:g} km/h, {data['speed_control']} speed control)"]
    lines += [f"  {r['detail']}" for r in data["reasons"]]
    w = data.get("window_speed_kmh")
    if w is not None and data.get("entry_speed_kmh") is not None:
        band = f" (band +/- {data['speed_band_kmh']:.1f} km/h)" if data.get("speed_band_kmh") is not None else ""
        lines.append(f"  driven {data['entry_speed_kmh']:.1f} km/h at the entry gate, {w['min']:.1f}-{w['max']:.1f} "
                     f"km/h (mean {w['mean']:.1f}) in the window{band}")
    return lines + [""]


def plot_cmd(
    run: Annotated[Path, typer.Argument(help="A run file written by `trikedyn simulate --out`.")],
    out: Annotated[Path | None, typer.Option("--out", help="PNG to write (default: beside the run, RUN.png for "
                                             "the time histories, RUN-KIND.png for the others).")] = None,
    kind: Annotated[str, typer.Option("--kind", help="time: speed [km/h], lateral acceleration, yaw rate, roll "
                                      "and RI over time; wheel-loads: each wheel's load [N], lift shaded; plan: "
                                      "the path through the cones with the footprint; gg: g-g diagram; roll: "
                                      "roll [deg] against lateral acceleration.")] = "time",
    channels: Annotated[str | None, typer.Option(help="Comma-separated channels for --kind time (default: speed, "
                                                 "lateral acceleration, yaw rate, roll, RI).")] = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Figures of a run with titles and units: time histories (like the paper's Figs. 7-9), wheel loads, plan
    view through the cones, g-g diagram, roll against lateral acceleration."""
    from .._files import check_output
    from ..report.run_figures import KINDS, figure

    if kind not in KINDS:
        raise InputError(f"expected one of {', '.join(KINDS)}, got '{kind}'", where="--kind")
    names = [c.strip() for c in channels.split(",") if c.strip()] if channels else None
    if names and kind != "time":
        raise InputError("--channels applies to --kind time only", where="--channels")
    target = out or (run.with_suffix(".png") if kind == "time" else run.with_name(f"{run.stem}-{kind}.png"))
    check_output(target, force=force, reads=[run, run.with_suffix(".json")])
    from ..analysis.compare import load_table
    from ..simulate.runfile import run_meta

    frame, _ = load_table(run)
    meta = run_meta(run, frame.attrs)
    options = {"channels": names} if names else {}
    try:
        fig = figure(kind, frame, meta, **options)
    except InputError as exc:
        raise InputError(exc.reason, where=str(run)) from None
    save_figure(fig, target, dpi=110)
    time_s = frame["time_s"].to_numpy(dtype=float)
    data = {"wrote": str(target), "kind": kind, "samples": int(time_s.size),
            "duration_s": float(time_s[-1] - time_s[0]) if time_s.size else 0.0}
    if kind == "time":
        data["channels"] = names or [c for c in ("speed_mps", "ay_mps2", "yaw_rate_radps", "roll_rad", "ri")
                                     if c in frame.columns]
    emit(data, as_json, f"wrote {target}")


def compare_cmd(
    log: Annotated[Path, typer.Argument(help="Measured IMU log (any supported format) or a run file.")],
    run: Annotated[Path, typer.Argument(help="Simulated run file (or another log).")],
    channels: Annotated[str, typer.Option(help="Channels to compare (the paper compares lateral acceleration and yaw rate).")] = "ay_mps2,wz_radps",
    max_offset: Annotated[float, typer.Option("--max-offset", callback=within(0, 600, "s", above=True), help="Largest time offset searched [s].")] = 5.0,
    plot: Annotated[Path | None, typer.Option("--plot", help="Write measured over simulated (PNG), like Figs. 7-8.")] = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Compare a measured log with a simulation: time offset by cross-correlation, RMSE, NRMSE, peak error."""
    from ..analysis.compare import compare, load_table

    if plot is not None:
        from .._files import check_output

        check_output(plot, force=force, reads=[log, run])

    measured = _imu_view(load_table(log)[0])
    simulated = _imu_view(load_table(run)[0])
    names = [c.strip() for c in channels.split(",") if c.strip()]
    result = compare(measured, simulated, channels=names, max_offset_s=max_offset)
    data = result.to_dict()
    if plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        save_figure(result.plot(), plot, dpi=110)
        data["plot"] = str(plot)
    lines = [f"time offset {data['offset_s']:+.3f} s (measured time + offset = simulated time)"]
    for name, m in data["channels"].items():
        lines.append(f"{name:<12} RMSE {m['rmse']:.4f}  NRMSE {m['nrmse']:.3f}  peak {m['peak_error']:.4f}  r {m['correlation']:.3f}")
    emit(data, as_json, "\n".join(lines))


def _imu_view(frame):
    """A run table seen as an IMU log: its emulated sensor channels under the log names."""
    renamed = {c: c[len("imu_"):] for c in frame.columns if c.startswith("imu_")}
    if not renamed:
        return frame
    keep = ["time_s", *renamed]
    return frame[keep].rename(columns=renamed)
