"""``trikedyn log`` (what an IMU log holds, conversion) and ``trikedyn identify`` (Eqs. 1-4)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from ._common import (
    ForceOpt,
    JsonOpt,
    emit,
    save_figure,
    within,
)

log_app = typer.Typer(help="IMU logs: what a file holds, and conversion to CSV.", no_args_is_help=True)

FormatOpt = Annotated[
    str, typer.Option("--format", help="Log format (auto-detected by default): " + ", ".join(
        ["auto", "witmotion-sdk", "witmotion-pc", "witmotion-2025", "wt901sd-binary", "bwt901cl-csv", "csv"]) + ", or any layout registered in trikedyn.measure.formats")
]
RateOpt = Annotated[
    float | None, typer.Option("--sample-rate", help="Sample rate [Hz] for files that store no time.")
]
SensorOpt = Annotated[int, typer.Option("--sensor", callback=within(1, 64), help="Which sensor of a multi-sensor file (1, 2, ...).")]


def _read(log: Path, fmt: str, sensor: int, rate: float | None):
    from ..measure.logs import read_log

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
    emit(summary, as_json, "\n".join(lines))


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
    from .._files import atomic_write, check_output

    check_output(out, force=force, reads=[log])
    imu = _read(log, fmt, sensor, rate)
    atomic_write(out, lambda fh: imu.data.to_csv(fh, index=False), binary=False)
    emit({"wrote": str(out), "samples": len(imu.data)}, as_json, f"wrote {out} ({len(imu.data)} samples)")


def identify(
    log: Annotated[Path, typer.Argument(help="Speed-bump accelerometer record (any supported IMU log).")],
    sprung_mass: Annotated[float, typer.Option("--sprung-mass", callback=within(1, 5000, "kg"), help="Sprung mass on this suspension, M_s [kg].")],
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
    from ..measure.suspension import identify_suspension

    if axis not in ("x", "y", "z"):
        raise InputError(f"expected x, y or z, got '{axis}'", where="--axis")
    if plot is not None:
        from .._files import check_output

        check_output(plot, force=force, reads=[log])
    imu = _read(log, fmt, sensor, rate)
    result = identify_suspension(
        imu.data["time_s"].to_numpy(), imu.channel(f"a{axis}_mps2"), sprung_mass,
        tyre_stiffness_N_per_m=tyre_stiffness, resample_hz=resample,
    )
    data = result.to_dict() | {"file": str(log), "axis": axis}
    if plot is not None:
        save_figure(result.plot(axis=axis), plot, dpi=120)
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
    emit(data, as_json, text)
