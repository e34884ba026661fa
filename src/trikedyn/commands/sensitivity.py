"""``trikedyn sensitivity``: which assumed values the threshold velocity depends on (Morris or Sobol)."""

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

JSON_FILE, SAMPLES_FILE, FIGURE_FILE, PLAN_FILE = ("sensitivity.json", "sensitivity-samples.csv", "sensitivity.png",
                                                   "sensitivity-plan.json")
def _plan(pset, search, factors, method, samples, seed, fraction) -> dict:
    """What makes the samples of a run: a resumed run must have the same."""
    return {"vehicle": pset.name, "manoeuvre": search.manoeuvre, "options": search.options,
            "resolution_kmh": search.resolution_kmh, "high_kmh": search.high_kmh, "criterion": search.criterion,
            "speed_control": search.speed_control, "method": method, "samples": samples, "seed": seed,
            "fraction": fraction, "factors": [[f.name, f.low, f.high] for f in factors],
            **({"metric": search.metric, "metric_options": search.metric_options} if search.metric != "threshold" else {})}


def _table(result) -> str:
    data = result.to_dict()
    ref = result.reference_threshold_speed_kmh
    what, unit = data["metric"].replace("_", " "), data["unit"]
    shown = ".1f" if data["metric"] == "threshold" else ".4g"
    group = "trajectories" if result.method == "morris" else "base samples"
    lines = [
        f"{result.vehicle} on {result.manoeuvre}: {what} {'none' if ref is None else f'{ref:{shown}} {unit}'} as given",
        f"{result.method}: {len(result.factors)} factors ({_origins(result)}); "
        f"{result.samples} {group}, {result.n_runs} runs, {result.failed} failed"
        + (f" ({result.dropped} {group} left out)" if result.dropped else ""),
    ]
    if data["metric"] == "threshold":
        lines.append(f"  threshold: the {result.search.criterion} criterion, {result.search.speed_control} speed control")
    if result.at_search_limit:
        lines.append(f"  {result.at_search_limit} runs reached the top of the search ({result.search.high_kmh:g} km/h; "
                     "raise it with --high)")
    from ..study.designs.sample_runs import limits_line

    regimes = limits_line(result.limits, ", each with its own sensitivities: the indices mix them, and factors "
                                         "whose intervals overlap can change places with --seed")
    if regimes:
        lines.append(f"  {regimes}")
    width = max(len(r["parameter"]) for r in result.indices) + 2
    by_name = {f.name: f for f in result.factors}
    if result.method == "morris":
        lines.append(f"{'rank':<5}{'parameter':<{width}}{f'mu* [{unit}]':>11}{'+/-':>7}{'sigma':>8}   range")
        keys = ("mu_star", "mu_star_conf", "sigma")
    else:
        lines.append(f"{'rank':<5}{'parameter':<{width}}{'ST':>8}{'+/-':>7}{'S1':>8}{'+/-':>7}   range")
        keys = ("ST", "ST_conf", "S1", "S1_conf")
    for rank, row in enumerate(result.indices, 1):
        f = by_name[row["parameter"]]
        cells = "".join(f"{_num(row[k]):>{11 if (k == 'mu_star') else 8 if k in ('ST', 'S1', 'sigma') else 7}}"
                        for k in keys)
        origin = {"declared": "declared", "narrowed": "narrowed"}.get(f.range_from, f"+/-{result.fraction:.0%}")
        lines.append(f"{rank:<5}{row['parameter']:<{width}}{cells}   {readable(f.low)} .. {readable(f.high)} ({origin})")
    from ..study.designs.sensitivity import unsettled_places

    for first, last in unsettled_places(result.indices):
        lines.append(f"places {first}-{last}: their 95 % intervals overlap, so their order is not settled by these "
                     "samples (more --samples, or compare another --seed)")
    if result.excluded:
        lines.append(f"left out: {len(result.excluded)} assumed values (see --json 'excluded')")
    return "\n".join(lines)


def _origins(result) -> str:
    """Where the factors' ranges come from, in words: declared in the vehicle file, or the default fraction."""
    count = {k: sum(f.range_from == k for f in result.factors) for k in ("declared", "fraction", "narrowed")}
    parts = [f"{count['declared']} over the range declared in the vehicle file",
             f"{count['fraction']} over +/-{result.fraction:.0%} of their value (none declared)"]
    if count["narrowed"]:
        parts.append(f"{count['narrowed']} narrowed so that every combination is a rigid body")
    return ", ".join(parts)


def _num(value: float) -> str:
    return "-" if value != value else f"{value:.3f}"


def sensitivity_cmd(
    vehicle: VehicleArg,
    manoeuvre: ManoeuvreOpt = "dlc",
    option: OptionOpt = [],  # noqa: B006
    method: Annotated[str, typer.Option("--method", help="morris (screening: mu*, sigma) or sobol (S1, ST).")] = "morris",
    samples: Annotated[int | None, typer.Option("--samples", callback=within(2, 100_000), help="Morris trajectories (default 10) or Sobol base samples, a power of 2 (default 64); runs: N x (k+1) or N x (k+2) for k factors.")] = None,
    parameter: Annotated[list[str], typer.Option("--parameter", "-p", help="Vary only these: dotted paths as in `trikedyn vehicle show` (measured ones too) or design knobs (track_m, wheelbase_m, cg_height_m, component.battery.z_m ...); repeatable or comma-separated. Default: every assumed value that can vary.")] = [],  # noqa: B006
    fraction: Annotated[float, typer.Option("--fraction", callback=within(0, 0.9, above=True), help="Each factor varies over value x (1 -/+ fraction) unless the vehicle file declares its range [-].")] = 0.2,
    resolution: Annotated[float, typer.Option("--resolution", callback=search_bound("resolution_kmh"), help="Resolution of each threshold search [km/h].")] = SEARCH_DEFAULTS["resolution_kmh"],
    high: Annotated[float, typer.Option("--high", callback=search_bound("high_kmh"), help="Highest speed searched [km/h]; a sample that passes it counts as this speed (raise it for slc).")] = SEARCH_DEFAULTS["high_kmh"],
    seed: Annotated[int, typer.Option("--seed", callback=within(0, 2**32 - 1), help="Seed of the sampling and of the confidence intervals.")] = 1,
    criterion: CriterionOpt = SEARCH_DEFAULTS["criterion"],
    speed_control: SpeedControlOpt = SEARCH_DEFAULTS["speed_control"],
    metric: MetricOpt = "threshold",
    metric_option: MetricOptionOpt = [],  # noqa: B006
    workers: WorkersOpt = None,
    dask_local: DaskLocalOpt = None,
    scheduler: SchedulerOpt = None,
    out: Annotated[Path | None, typer.Option("--out", help="Folder for sensitivity.json, the samples (CSV, written as they finish) and the figure (PNG).")] = None,
    resume: Annotated[bool, typer.Option("--resume", help="Continue an interrupted run in --out: samples in its CSV are not run again.")] = False,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Sensitivity of the threshold velocity (or of any study metric, --metric) to the vehicle's assumed values (SALib: Morris or Sobol)."""
    from ..params import load_vehicle
    from ..study.designs import sensitivity as sa

    sa.check_method(method)
    check_executor(workers, dask_local, scheduler)
    start_pool_server(workers, dask_local, scheduler)  # the workers' imports overlap the reference search's
    check_resume(out, resume, force)
    options = manoeuvre_options(manoeuvre, option)
    pset = load_vehicle(vehicle)
    if parameter:
        factors, excluded = sa.select_factors(pset, parameter, fraction), {}
    else:
        factors, excluded = sa.candidate_factors(pset, fraction)
    n = sa.DEFAULT_SAMPLES[method] if samples is None else int(samples)
    search = sa.Search(manoeuvre, options, resolution, high_kmh=high, criterion=criterion,
                       speed_control=speed_control, metric=metric, metric_options=metric_options(metric_option))
    sa.sample(sa.problem(factors), method, n, seed)  # a bad --samples fails before anything is written
    plan = json.loads(json.dumps(_plan(pset, search, factors, method, n, seed, fraction)))
    log = None
    if out is not None:
        start_output(out, plan, PLAN_FILE, kind="a sensitivity", resume=resume, force=force,
                     reads=[vehicle, manoeuvre, options.get("file")], writes=[JSON_FILE, SAMPLES_FILE, FIGURE_FILE])
        log = sa.SampleLog(out / SAMPLES_FILE, factors, sa.group_size(method, len(factors)), search.metric)
    result = sa.run_sensitivity(pset, search, factors, method=method, samples=n, seed=seed, fraction=fraction,
                                excluded=excluded, workers=workers, dask_local=dask_local, scheduler=scheduler, log=log, resume=resume, progress=ProgressLine("sensitivity"),
                                figures=out is not None)
    data = result.to_dict()
    if out is not None:
        write_results(out, data, result.plot(), FIGURE_FILE, JSON_FILE, samples=str(out / SAMPLES_FILE))
    emit(data, as_json, lambda: _table(result) + (f"\nwrote {', '.join(data['files'].values())}" if out else ""))
