"""``trikedyn uncertainty``: the threshold velocity (or any study metric, ``--metric``) as a distribution
(median, 5-95 %) from the uncertain inputs."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ._bounds import SEARCH_DEFAULTS, search_bound
from ._common import (
    CriterionOpt,
    DaskLocalOpt,
    ForceOpt,
    JsonOpt,
    ManoeuvreOpt,
    OptionOpt,
    SchedulerOpt,
    SpeedControlOpt,
    VehicleArg,
    WorkersOpt,
    emit,
    manoeuvre_options,
    readable,
    within,
)
from ._sampled import (
    MetricOpt,
    MetricOptionOpt,
    ProgressLine,
    check_executor,
    check_resume,
    metric_options,
    start_output,
    start_pool_server,
    write_results,
)

JSON_FILE, SAMPLES_FILE, FIGURE_FILE, PLAN_FILE = ("uncertainty.json", "uncertainty-samples.csv", "uncertainty.png",
                                                   "uncertainty-plan.json")


def _plan(pset, search, inputs, samples, seed, fraction) -> dict:
    """What makes the samples of a run: a resumed run must have the same."""
    return {"vehicle": pset.name, "manoeuvre": search.manoeuvre, "options": search.options,
            "resolution_kmh": search.resolution_kmh, "high_kmh": search.high_kmh, "criterion": search.criterion,
            "speed_control": search.speed_control, "sampling": "latin-hypercube",
            "samples": samples, "seed": seed, "fraction": fraction,
            "inputs": [[i.name, i.distribution, i.factor.low, i.factor.high, i.std] for i in inputs],
            **({"metric": search.metric, "metric_options": search.metric_options} if search.metric != "threshold" else {})}


def _fmt(value, shown: str = ".1f") -> str:
    return "-" if value is None else format(value, shown)


def _text(result) -> str:
    d = result.to_dict()
    d |= result.statistics()  # by the threshold's names, whatever the metric
    ref = result.reference_threshold_speed_kmh
    normal = [i for i in result.inputs if i.distribution == "normal"]
    uniform = [i for i in result.inputs if i.distribution != "normal"]
    origins = {k: sum(i.factor.range_from == k for i in uniform) for k in ("declared", "fraction", "narrowed")}
    what, unit = d["metric"].replace("_", " "), d["unit"]
    shown = ".1f" if d["metric"] == "threshold" else ".4g"
    lines = [
        f"{result.vehicle} on {result.manoeuvre}: {what} {'none' if ref is None else f'{ref:{shown}} {unit}'} as given",
        f"{len(result.inputs)} uncertain inputs ({len(uniform)} uniform over their range, "
        f"{len(normal)} normal from measured sigmas, truncated at +/-3 sigma); Latin hypercube, {result.samples} "
        f"samples, {d['failed']} failed",
        f"  median {_fmt(d['median_kmh'], shown)} {unit}, 5-95 % {_fmt(d['p05_kmh'], shown)} .. "
        f"{_fmt(d['p95_kmh'], shown)} {unit}, mean {_fmt(d['mean_kmh'], shown)}{'' if d['metric'] == 'threshold' else ' ' + unit}, std {_fmt(d['std_kmh'], shown)} "
        f"{unit} (n={d['n']})",
    ]
    if d["metric"] == "threshold":
        lines.append(f"  threshold: the {result.search.criterion} criterion, {result.search.speed_control} speed control")
    if d["at_search_limit"]:
        lines.append(f"  {d['at_search_limit']} samples reached the top of the search ({result.search.high_kmh:g} km/h; "
                     "raise it with --high)")
    if uniform:
        lines.append(f"  uniform: {origins['declared']} over the range declared in the vehicle file, "
                     f"{origins['fraction']} over +/-{result.fraction:.0%} of their value (none declared)"
                     + (f", {origins['narrowed']} narrowed to rigid bodies (the inertias)" if origins["narrowed"] else ""))
    from ..study.designs.sample_runs import limits_line

    regimes = limits_line(result.limits, ": the distribution has a part of each")
    if regimes:
        lines.append(f"  {regimes}")
    for i in normal:
        lines.append(f"  {i.name}: normal, mean {readable(i.factor.value)}, std {readable(i.std)}  "
                     f"[{i.source or '--std'}]")
    for note in result.notes:
        lines.append(f"  note: {note}")
    for row in d["failures"]:
        lines.append(f"  failed ({row['samples']}): {row['error']}")
    return "\n".join(lines)


def _far_from_measured(pset, measured, stds) -> list[str]:
    """A note for each measured sigma used about a vehicle value more than 3 sigma from what was measured."""
    from ..study.designs.factors import numeric_parameters

    values = numeric_parameters(pset)
    notes = []
    for m in measured:
        value = values.get(m.path)
        if m.path in stds or value is None or abs(value - m.measured) <= 3 * m.std:
            continue
        notes.append(f"{m.path}: the vehicle's {readable(value)} is {abs(value - m.measured) / m.std:.0f} sigma from "
                     f"the measured {readable(m.measured)}; its sigma is sampled about the vehicle's value (update "
                     "the vehicle file if the measurement is of this vehicle)")
    return notes


def _identification_files(items: list[str]) -> list[Path]:
    """Every file an ``--identification [NAME=]FILE`` may read: the name with and without ``NAME=``, and for a
    folder the JSON files in it (more rather than fewer: they are only kept from being written onto)."""
    found = []
    for item in items:
        for name in sorted({item.strip(), item.partition("=")[2].strip()} - {""}):
            path = Path(name)
            found.append(path)
            if path.is_dir():
                found += sorted(path.glob("*.json"))
    return found


def uncertainty_cmd(
    vehicle: VehicleArg,
    manoeuvre: ManoeuvreOpt = "dlc",
    option: OptionOpt = [],  # noqa: B006
    samples: Annotated[int, typer.Option("--samples", callback=within(2, 100_000), help="Latin-hypercube samples (threshold searches).")] = 64,
    parameter: Annotated[list[str], typer.Option("--parameter", "-p", help="Assumed values varied uniformly over their range: dotted paths or design knobs, repeatable or comma-separated. Default: every assumed value that can vary.")] = [],  # noqa: B006
    std: Annotated[list[str], typer.Option("--std", help="A measured value PATH=SIGMA [its unit] (mass.cg_z_m=0.01): normal about the vehicle's value, truncated at +/-3 sigma; repeatable. Wins over --weighing and --identification.")] = [],  # noqa: B006
    weighing: Annotated[Path | None, typer.Option("--weighing", help="A weighing file (as `trikedyn cg weigh` reads): the sigmas of the CG's x and y (level weighing) and z (tilted weighings), normal about the vehicle's CG.")] = None,
    identification: Annotated[list[str], typer.Option("--identification", help="[SUSPENSION=]FILE: the JSON of `trikedyn identify --json` (or a folder holding it): the sigmas of that suspension's stiffness and damping, propagated from those of f_n and xi; the name is needed when the vehicle has more than one suspension (front=id.json); repeatable.")] = [],  # noqa: B006
    fraction: Annotated[float, typer.Option("--fraction", callback=within(0, 0.9, above=True), help="Each assumed value varies over value x (1 -/+ fraction) unless the vehicle file declares its range [-].")] = 0.2,
    resolution: Annotated[float, typer.Option("--resolution", callback=search_bound("resolution_kmh"), help="Resolution of each threshold search [km/h].")] = SEARCH_DEFAULTS["resolution_kmh"],
    high: Annotated[float, typer.Option("--high", callback=search_bound("high_kmh"), help="Highest speed searched [km/h]; a sample that passes it counts as this speed.")] = SEARCH_DEFAULTS["high_kmh"],
    seed: Annotated[int, typer.Option("--seed", callback=within(0, 2**32 - 1), help="Seed of the sampling.")] = 1,
    criterion: CriterionOpt = SEARCH_DEFAULTS["criterion"],
    speed_control: SpeedControlOpt = SEARCH_DEFAULTS["speed_control"],
    metric: MetricOpt = "threshold",
    metric_option: MetricOptionOpt = [],  # noqa: B006
    workers: WorkersOpt = None,
    dask_local: DaskLocalOpt = None,
    scheduler: SchedulerOpt = None,
    out: Annotated[Path | None, typer.Option("--out", help="Folder for uncertainty.json, the samples (CSV, written as they finish) and the histogram (PNG).")] = None,
    resume: Annotated[bool, typer.Option("--resume", help="Continue an interrupted run in --out: samples in its CSV are not run again.")] = False,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Uncertainty of the threshold velocity (or of any study metric, --metric): median and 5-95 % interval over the assumed and measured values."""
    from ..params import load_vehicle
    from ..study.designs import uncertainty as ua

    stds = ua.parse_std(std)
    check_executor(workers, dask_local, scheduler)
    start_pool_server(workers, dask_local, scheduler)  # the workers' imports overlap the reference search's
    check_resume(out, resume, force)
    options = manoeuvre_options(manoeuvre, option)
    pset = load_vehicle(vehicle)
    measured = ua.measured_stds(pset, weighing, identification)
    sigmas = {m.path: m.std for m in measured} | stds
    sources = {m.path: m.source for m in measured} | dict.fromkeys(stds, "--std")
    inputs, excluded = ua.build_inputs(pset, parameter, sigmas, fraction, sources)
    search = ua.Search(manoeuvre, options, resolution, high_kmh=high, criterion=criterion,
                       speed_control=speed_control, metric=metric, metric_options=metric_options(metric_option))
    plan = json.loads(json.dumps(_plan(pset, search, inputs, int(samples), seed, fraction)))
    log = None
    if out is not None:
        reads = [vehicle, manoeuvre, options.get("file"), weighing, *_identification_files(identification)]
        start_output(out, plan, PLAN_FILE, kind="an uncertainty", resume=resume, force=force, reads=reads,
                     writes=[JSON_FILE, SAMPLES_FILE, FIGURE_FILE])
        log = ua.SampleLog(out / SAMPLES_FILE, [i.factor for i in inputs], 1, search.metric)
    result = ua.run_uncertainty(pset, search, inputs, samples=int(samples), seed=seed, fraction=fraction,
                                excluded=excluded, workers=workers, dask_local=dask_local, scheduler=scheduler, log=log, resume=resume,
                                progress=ProgressLine("uncertainty"))
    result.measured, result.notes = list(measured), _far_from_measured(pset, measured, stds)
    data = result.to_dict()
    if out is not None:
        write_results(out, data, result.plot(), FIGURE_FILE, JSON_FILE, samples=str(out / SAMPLES_FILE))
    emit(data, as_json, lambda: _text(result) + (f"\nwrote {', '.join(data['files'].values())}" if out else ""))
