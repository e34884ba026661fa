"""``trikedyn log`` (what an IMU log holds, conversion) and ``trikedyn identify`` (Eqs. 1-4, and the values a
vehicle file takes, written into it with ``--into``)."""

from __future__ import annotations

import math
import re
from datetime import date
from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from ._common import (
    ForceOpt,
    JsonOpt,
    choice,
    emit,
    save_figure,
    within,
)

log_app = typer.Typer(help="IMU logs: what a file holds, and conversion to CSV.", no_args_is_help=True)

FormatOpt = Annotated[
    str, typer.Option("--format", help="Log format (auto-detected by default): " + ", ".join(
        ["auto", "witmotion-sdk", "witmotion-pc", "witmotion-2025", "wt901sd-binary", "bwt901cl-csv", "phyphox", "csv"])
        + ", or any layout registered in trikedyn.measure.formats")
]
RateOpt = Annotated[
    float | None, typer.Option("--sample-rate", help="Sample rate [Hz] for files that store no time.")
]
SensorOpt = Annotated[int, typer.Option("--sensor", callback=within(1, 64), help="Which sensor of a multi-sensor file (1, 2, ...).")]

# The import options of a table (the csv and phyphox layouts): read_log's keyword arguments on the command line.
TimeColumnOpt = Annotated[str | None, typer.Option(
    "--time-column", help="CSV: the header of the time column (default: a column time_s, or time_ms in ms).")]
TimeUnitOpt = Annotated[str | None, typer.Option(
    "--time-unit", callback=choice("s", "ms", "us"), help="CSV: the unit of the time column: s, ms or us.")]
DelimiterOpt = Annotated[str | None, typer.Option(
    "--delimiter", callback=choice(",", ";", "tab"),
    help="CSV: the field separator, ',', ';' or 'tab' (detected by default).")]
DecimalOpt = Annotated[str | None, typer.Option(
    "--decimal", callback=choice(".", ","),
    help="CSV: the decimal mark, '.' or ',' (detected by default: ',' for 1,5-like numbers in a ';' or tab file).")]
ColumnOpt = Annotated[list[str], typer.Option(
    "--column", help="CSV: NAME=HEADER, the column of a channel (az_mps2='Acc Z'; names as in `trikedyn log info`); "
                     "repeatable.")]
UnitOpt = Annotated[list[str], typer.Option(
    "--unit", help="CSV: NAME=UNIT, a channel's unit in the file (az_mps2=g, wz_radps=deg/s); repeatable.")]


def _pairs(items: list[str], option: str) -> dict[str, str] | None:
    """``NAME=VALUE`` items as a dict (None for none)."""
    out = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise InputError(f"expected NAME=VALUE (az_mps2=AccZ), got {item!r}", where=option)
        out[name.strip()] = value.strip()
    return out or None


def read_options(fmt: str = "auto", sensor: int = 1, rate: float | None = None, time_column: str | None = None,
                 time_unit: str | None = None, delimiter: str | None = None, decimal: str | None = None,
                 column: list[str] = (), unit: list[str] = ()) -> dict:
    """The keyword arguments of :func:`trikedyn.measure.logs.read_log` (after the path) that a command's log
    options give: ``--format``, ``--sensor``, ``--sample-rate`` and the table options.

    Parameters
    ----------
    fmt : str
        Log format (``auto``: sniffed).
    sensor : int
        Sensor number in a multi-sensor file.
    rate : float, optional
        Sample rate [Hz] for a log without times.
    time_column : str, optional
        The time column of a table.
    time_unit : str, optional
        Its unit.
    delimiter : str, optional
        Field separator.
    decimal : str, optional
        Decimal mark.
    column : list of str
        ``SI=HEADER`` pairs.
    unit : list of str
        ``SI=UNIT`` pairs.

    Returns
    -------
    dict
        The keyword arguments.
    """
    return {"format": fmt, "sensor": sensor, "sample_rate_hz": rate, "time_column": time_column,
            "time_unit": time_unit, "delimiter": delimiter, "decimal": decimal,
            "columns": _pairs(list(column), "--column"), "units": _pairs(list(unit), "--unit")}


def _read(log: Path, options: dict):
    from ..measure.logs import read_log

    return read_log(log, **options)


@log_app.command("info")
def log_info(
    log: Annotated[Path, typer.Argument(help="IMU log file.")],
    fmt: FormatOpt = "auto",
    sensor: SensorOpt = 1,
    rate: RateOpt = None,
    time_column: TimeColumnOpt = None,
    time_unit: TimeUnitOpt = None,
    delimiter: DelimiterOpt = None,
    decimal: DecimalOpt = None,
    column: ColumnOpt = [],  # noqa: B006 - typer's way for a repeatable option
    unit: UnitOpt = [],  # noqa: B006
    as_json: JsonOpt = False,
):
    """Format, length, sample rate and channels of an IMU log, and what the reader did to it."""
    imu = _read(log, read_options(fmt, sensor, rate, time_column, time_unit, delimiter, decimal, column, unit))
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
    time_column: TimeColumnOpt = None,
    time_unit: TimeUnitOpt = None,
    delimiter: DelimiterOpt = None,
    decimal: DecimalOpt = None,
    column: ColumnOpt = [],  # noqa: B006
    unit: UnitOpt = [],  # noqa: B006
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Convert an IMU log to a plain CSV in SI units (never onto the log itself)."""
    from .._files import atomic_write, check_output

    check_output(out, force=force, reads=[log])
    imu = _read(log, read_options(fmt, sensor, rate, time_column, time_unit, delimiter, decimal, column, unit))
    atomic_write(out, lambda fh: imu.data.to_csv(fh, index=False), binary=False)
    emit({"wrote": str(out), "samples": len(imu.data)}, as_json, f"wrote {out} ({len(imu.data)} samples)")


# ----------------------------------------------------------------------------------------------- identify
_IDENTIFIED = re.compile(r"^trikedyn identify (?P<log>.+?) \(\d{4}-\d{2}-\d{2}\)")


def _sigma(value: float) -> str:
    """`` ± sigma`` to two significant digits, or nothing for a sigma the identification has not."""
    return f" ± {value:.2g}" if math.isfinite(value) else ""


def _quarter_car_of(into: Path, suspension: str, tyre_stiffness, unsprung_mass, sprung_mass):
    """The vehicle file's quarter car of ``suspension``: (tyre stiffness, tyre damping, unsprung mass, sprung
    mass, where the sprung mass comes from); options that contradict the file are errors."""
    from ..errors import did_you_mean
    from ..params.inplace import read_vehicle_target
    from ..params.springs import suspension_quarter_car

    params = read_vehicle_target(into)[1].params
    if suspension not in params.suspension:
        names = list(params.suspension)
        raise InputError(f"no suspension '{suspension}' in {into}{did_you_mean(suspension, names)} (it has: "
                         f"{', '.join(names)})", where="--suspension")
    try:
        car = suspension_quarter_car(params, suspension)
    except KeyError:
        raise InputError(f"no wheel of {into} uses suspension '{suspension}'", where="--suspension") from None
    for option, given, own, unit in (("--tyre-stiffness", tyre_stiffness, car.tyre_stiffness_N_per_m, "N/m"),
                                     ("--unsprung-mass", unsprung_mass, car.unsprung_mass_kg, "kg")):
        if given is not None and abs(given / own - 1.0) > 0.01:
            raise InputError(f"{given:g} {unit} is not the vehicle file's {own:g} {unit}, which the model uses; "
                             "leave it out (--into takes it from the file) or change the file first", where=option)
    if sprung_mass is not None:
        return car, sprung_mass, "--sprung-mass"
    if not car.sprung_mass_kg > 0:
        raise InputError(f"the masses and CG of {into} leave no sprung mass on '{suspension}'; give --sprung-mass",
                         where="--sprung-mass")
    return car, car.sprung_mass_kg, f"the masses and CG of {into.name}"


def _vehicle_values(result) -> dict[str, float]:
    """The values a vehicle file takes, as written (K to 1 N/m, C to 0.1 N s/m, f_n and xi to 0.001)."""
    return {"stiffness_N_per_m": float(round(result.stiffness_N_per_m)),
            "damping_Ns_per_m": round(result.damping_Ns_per_m, 1),
            "natural_frequency_hz": round(result.natural_frequency_hz, 3),
            "damping_ratio": round(result.damping_ratio, 3)}


def _sources(result, log: Path, mass_from: str) -> dict[str, str]:
    """The provenance note of each value written."""
    common = f"trikedyn identify {log} ({date.today().isoformat()})"
    fit = f"f_n {result.natural_frequency_hz:.3f}{_sigma(result.natural_frequency_std_hz)} Hz"
    xi = f"xi {result.damping_ratio:.3f}{_sigma(result.damping_ratio_std)}"
    series = (f"the tyre ({result.tyre_stiffness_N_per_m:.0f} N/m, {result.tyre_damping_Ns_per_m:g} N s/m) and "
              f"{result.unsprung_mass_kg:.1f} kg unsprung in series taken out")
    mass = f"M_s {result.sprung_mass_kg:.1f} kg ({mass_from})"
    return {"stiffness_N_per_m": f"{common}: the suspension's own spring at the wheel, {series}; {fit}, {xi}, {mass}",
            "damping_Ns_per_m": f"{common}: the suspension's own damper at the wheel, {series}; {fit}, {xi}, {mass}",
            "natural_frequency_hz": f"{common}: the body mode's undamped natural frequency, {fit} ({result.method})",
            "damping_ratio": f"{common}: the body mode's damping ratio, {xi} ({result.method})"}


def identify(
    log: Annotated[Path, typer.Argument(help="Speed-bump accelerometer record (any supported IMU log).")],
    sprung_mass: Annotated[float | None, typer.Option("--sprung-mass", callback=within(1, 5000, "kg"), help="Sprung mass on this suspension, M_s [kg] (with --into: the vehicle file's, from its masses and CG, by default).")] = None,
    axis: Annotated[str, typer.Option("--axis", help="Accelerometer axis: x, y or z.")] = "z",
    tyre_stiffness: Annotated[
        float | None, typer.Option("--tyre-stiffness", callback=within(1e3, 1e7, "N/m"), help="Tyre vertical stiffness [N/m]: K and C become the suspension's own, the tyre in series taken out (what a vehicle file takes).")
    ] = None,
    unsprung_mass: Annotated[
        float | None, typer.Option("--unsprung-mass", callback=within(0, 500, "kg"), help="Unsprung mass on the tyre [kg] (wheel with fork slider or half the swing arm), with --tyre-stiffness.")
    ] = None,
    into: Annotated[Path | None, typer.Option("--into", help="A vehicle file (.toml) to write K, C, f_n and xi into, with their provenance (with --suspension); its tyre, unsprung and sprung masses are used.")] = None,
    suspension: Annotated[str | None, typer.Option("--suspension", help="Which [suspension.NAME] of the --into file.")] = None,
    resample: Annotated[
        float | None, typer.Option("--resample-hz", help="Resample to this rate before analysis [Hz] (auto).")
    ] = None,
    fmt: FormatOpt = "auto",
    sensor: SensorOpt = 1,
    rate: RateOpt = None,
    time_column: TimeColumnOpt = None,
    time_unit: TimeUnitOpt = None,
    delimiter: DelimiterOpt = None,
    decimal: DecimalOpt = None,
    column: ColumnOpt = [],  # noqa: B006
    unit: UnitOpt = [],  # noqa: B006
    plot: Annotated[Path | None, typer.Option("--plot", help="Write the Fig. 2c-d style figure (PNG).")] = None,
    force: Annotated[bool, typer.Option("--force", help="Replace an existing --plot file, and values of the --into file that it sets with another source.")] = False,
    as_json: JsonOpt = False,
):
    """Suspension stiffness and damping from a speed-bump record (paper Eqs. 1-4), and the values a vehicle file
    takes.

    Log decrement over n cycles on both the compression and the extension crests (Eqs. 1-2), natural
    frequency from a windowed, zero-padded spectrum and a free-decay fit, K from Eq. 3 and C from Eq. 4. A
    vehicle file's K and C are the suspension's own, the tyre in series: with --tyre-stiffness the tyre is
    taken out. --into FILE --suspension NAME takes the tyre and the masses from that vehicle file and writes
    K, C, f_n and xi into its [suspension.NAME], each with its source; nothing else of the file changes.
    """
    from ..measure.suspension import identify_suspension

    if axis not in ("x", "y", "z"):
        raise InputError(f"expected x, y or z, got '{axis}'", where="--axis")
    if (into is None) != (suspension is None):
        raise InputError("--into FILE and --suspension NAME go together", where="--suspension" if into else "--into")
    if unsprung_mass is not None and tyre_stiffness is None and into is None:
        raise InputError("the unsprung mass matters only with the tyre in series: give --tyre-stiffness too",
                         where="--unsprung-mass")
    target = car = None
    if into is not None:
        from ..params.inplace import check_vehicle_target

        target = check_vehicle_target(into, reads=[log, plot])
        car, sprung_mass, mass_from = _quarter_car_of(target, suspension, tyre_stiffness, unsprung_mass, sprung_mass)
        tyre = (car.tyre_stiffness_N_per_m, car.tyre_damping_Ns_per_m, car.unsprung_mass_kg)
    elif sprung_mass is None:
        raise InputError("the sprung mass on this suspension [kg] is needed; or --into FILE --suspension NAME takes "
                         "it from a vehicle file", where="--sprung-mass")
    else:
        mass_from = "--sprung-mass"
        tyre = (tyre_stiffness, 0.0, unsprung_mass)
    if plot is not None:
        from .._files import check_output

        check_output(plot, force=force, reads=[log, into])
    imu = _read(log, read_options(fmt, sensor, rate, time_column, time_unit, delimiter, decimal, column, unit))
    result = identify_suspension(
        imu.data["time_s"].to_numpy(), imu.channel(f"a{axis}_mps2"), sprung_mass,
        tyre_stiffness_N_per_m=tyre[0], tyre_damping_Ns_per_m=tyre[1], unsprung_mass_kg=tyre[2],
        resample_hz=resample,
    )
    data = result.to_dict() | {"file": str(log), "axis": axis, "sprung_mass_from": mass_from}
    own = result.tyre_stiffness_N_per_m is not None
    if own:
        data["vehicle_values"] = _vehicle_values(result)
    if target is not None:
        data["vehicle_file"] = _write_into(target, suspension, result, log, mass_from, force)
    if plot is not None:
        save_figure(result.plot(axis=axis), plot, dpi=120)
        data["plot"] = str(plot)
    emit(data, as_json, lambda: _identify_text(data))


def _write_into(target: Path, suspension: str, result, log: Path, mass_from: str, force: bool) -> dict:
    """Write the vehicle values into ``[suspension.NAME]`` of ``target``; what was written, and the bounce the
    model's quarter car of the updated file has."""
    from ..params.inplace import read_vehicle_target, update_vehicle_file
    from ..params.springs import suspension_quarter_car

    values = _vehicle_values(result)
    if not all(math.isfinite(v) and v > 0 for v in values.values()):
        raise InputError(f"no finite positive K, C, f_n and xi to write ({values})", where=str(log))
    sources = _sources(result, log, mass_from)

    def same_log(source):
        """Whether a value's ``source`` says it was identified (``trikedyn identify``) from a log of this log's
        file name: such a value may be replaced without ``--force``."""
        match = _IDENTIFIED.match(source or "")
        return match is not None and Path(match.group("log")).name == log.name

    replaced = update_vehicle_file(target, ("suspension", suspension), {k: (v, sources[k]) for k, v in values.items()},
                                   force=force, replaceable=same_log)
    params = read_vehicle_target(target)[1].params
    car = suspension_quarter_car(params, suspension)
    f_model, xi_model = car.body_mode(result.sprung_mass_kg)
    return {"file": str(target), "suspension": suspension, "values": values, "sources": sources,
            "replaced": replaced, "model_frequency_hz": f_model, "model_damping_ratio": xi_model}


def _identify_text(data: dict) -> str:
    def sigma(key):
        """`` ± sigma`` of the entry ``key`` of ``data``, or nothing when the entry is missing or not finite."""
        value = data.get(key)
        return _sigma(value) if value is not None else ""

    lines = [
        f"natural frequency  {data['natural_frequency_hz']:.3f}{sigma('natural_frequency_std_hz')} Hz",
        f"damping ratio      {data['damping_ratio']:.3f}{sigma('damping_ratio_std')}   (log decrement "
        f"{data['log_decrement']:.3f}, {data['cycles_used']} cycles)",
        f"sprung mass        {data['sprung_mass_kg']:.1f} kg   ({data['sprung_mass_from']})",
    ]
    rigid = f"{data['equivalent_stiffness_N_per_m']:.0f} N/m and {data['equivalent_damping_Ns_per_m']:.1f} N s/m"
    if "vehicle_values" in data:
        lines.append(f"the suspension's own spring and damper, at the wheel: what a vehicle file's "
                     f"[suspension.NAME] takes (the tyre, {data['tyre_stiffness_N_per_m']:.0f} N/m, and "
                     f"{data['unsprung_mass_kg']:.1f} kg unsprung in series taken out):")
        lines += [f"  {k:<21}= {v:g}" for k, v in data["vehicle_values"].items()]
        lines.append(f"tyre included, the paper's rigid-tyre Eqs. 3-4 (not for a vehicle file): K and C = {rigid}")
    else:
        lines.append(f"tyre included, the paper's rigid-tyre Eqs. 3-4: K and C = {rigid}")
        lines.append("a vehicle file takes the suspension's own spring and damper, the tyre in series taken out: "
                     "give --tyre-stiffness (and --unsprung-mass), or --into FILE --suspension NAME, which takes them "
                     "from the file")
    into = data.get("vehicle_file")
    if into:
        replaced = f" (replaced: {', '.join(into['replaced'])})" if into["replaced"] else ""
        lines.append(f"wrote [suspension.{into['suspension']}] of {into['file']}: {', '.join(into['values'])}"
                     f"{replaced}")
        lines.append(f"its quarter car now bounces at {into['model_frequency_hz']:.3f} Hz (xi "
                     f"{into['model_damping_ratio']:.3f}) with the sprung mass above; `trikedyn vehicle check` audits it")
    lines += [f"warning: {w}" for w in data.get("warnings", [])]
    return "\n".join(lines)
