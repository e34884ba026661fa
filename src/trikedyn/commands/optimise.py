"""``trikedyn optimise``: move components (and the track or wheelbase) within bounds to raise the threshold velocity
(or to maximise, or with ``--minimise`` minimise, any study metric: ``--metric``)."""

from __future__ import annotations

import hashlib
import json
import re
from dataclasses import replace
from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from ._bounds import search_bound
from ._common import (
    CriterionOpt,
    DaskLocalOpt,
    ForceOpt,
    JsonOpt,
    OptionOpt,
    SchedulerOpt,
    SpeedControlOpt,
    VehicleArg,
    WorkersOpt,
    absolute_csv,
    emit,
    manoeuvre_options,
    within,
)
from ._sampled import (
    MetricOptionOpt,
    ProgressLine,
    check_executor,
    check_resume,
    metric_options,
    start_output,
    write_results,
)

JSON_FILE, LOG_FILE, FIGURE_FILE, PLAN_FILE = ("optimise.json", "optimise-evaluations.csv", "optimise.png",
                                               "optimise-plan.json")


def _file_name(name: str) -> str:
    """A vehicle file name from a vehicle's name (which is free text)."""
    stem = re.sub(r"[^A-Za-z0-9._-]+", "-", name).strip(".-") or "vehicle"
    return f"{stem[:80]}-optimised.toml"


def _plan(pset, spec, searches, minimise: bool = False) -> dict:
    """What makes a run's evaluations: a resumed run must have the same."""
    digest = hashlib.sha256(pset.params.model_dump_json().encode()).hexdigest()[:16]
    return json.loads(json.dumps({
        "vehicle": pset.name, "vehicle_digest": digest,
        "spec": {k: v for k, v in spec.to_dict().items() if k not in ("origin", "description")},
        "searches": [s.to_dict() for s in searches], **({"minimise": True} if minimise else {})}))


def _check_command(file: Path, manoeuvre: str, options: dict, payload_kg: float) -> str:
    parts = ["trikedyn", "threshold", str(file), "--manoeuvre", manoeuvre]
    for key, value in options.items():
        parts += ["-o", f"{key}={value}"]
    if payload_kg:
        parts += ["--payload", f"{payload_kg:g}"]
    import shlex

    return " ".join(shlex.quote(p) for p in parts)


def optimise_cmd(
    vehicle: VehicleArg,
    spec: Annotated[str, typer.Option("--spec", help="An optimise spec: a built-in name (battery-layout) or a .toml file with [optimise] knobs = { \"component.battery.x_m\" = [low, high], ... }.")],
    manoeuvre: Annotated[list[str], typer.Option("--manoeuvre", callback=absolute_csv, help="A registered manoeuvre (dlc, slc, ...) or a path .csv file; repeat it to maximise the worst threshold over several. Default: the spec's manoeuvres.")] = [],  # noqa: B006
    option: OptionOpt = [],  # noqa: B006
    maxiter: Annotated[int | None, typer.Option("--maxiter", callback=within(0, 1000), help="Generations after the first (default: the spec's).")] = None,
    popsize: Annotated[int | None, typer.Option("--popsize", callback=within(1, 100), help="Population = popsize x number of knobs, at least 5 (default: the spec's).")] = None,
    seed: Annotated[int | None, typer.Option("--seed", callback=within(0, 2**32 - 1), help="Seed of differential evolution (default: the spec's).")] = None,
    resolution: Annotated[float | None, typer.Option("--resolution", callback=search_bound("resolution_kmh"), help="Resolution of each threshold search [km/h] (default: the spec's, 0.1).")] = None,
    high: Annotated[float | None, typer.Option("--high", callback=search_bound("high_kmh"), help="Highest speed searched [km/h] (default: the spec's, 90; raise it for slc).")] = None,
    criterion: Annotated[str | None, CriterionOpt.__metadata__[0]] = None,
    speed_control: Annotated[str | None, SpeedControlOpt.__metadata__[0]] = None,
    metric: Annotated[str, typer.Option("--metric", help="The objective: a registered study metric (threshold, tilt_angle, understeer_gradient, peak_ri, min_wheel_load ...), maximised (its worst over the manoeuvres), or minimised with --minimise. Default: the threshold velocity. Its value is named by it: best_value, reference_value ... in the JSON (with metric and unit), worst_METRIC and METRIC_MANOEUVRE columns in the log.")] = "threshold",
    metric_option: MetricOptionOpt = [],  # noqa: B006
    minimise: Annotated[bool, typer.Option("--minimise", help="Minimise the --metric instead of maximising it (a metric where smaller is better, such as peak_ri); the worst over several manoeuvres is then the highest. Not for the threshold.")] = False,
    workers: WorkersOpt = None,
    dask_local: DaskLocalOpt = None,
    scheduler: SchedulerOpt = None,
    out: Annotated[Path, typer.Option("--out", help="Folder for the optimised vehicle (TOML), optimise.json, the evaluations (CSV, written as they finish) and the figure (PNG).")] = Path("optimise-output"),
    resume: Annotated[bool, typer.Option("--resume", help="Continue an interrupted run in --out: layouts in its CSV are not searched again.")] = False,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Layout optimiser: move the spec's components (and track or wheelbase) within its bounds to maximise the
    threshold velocity (the worst over several manoeuvres), or another --metric (maximised, or with --minimise
    minimised), by differential evolution; writes the optimised vehicle file."""
    import time

    from ..params import load_vehicle, save_vehicle
    from ..study.designs import optimise as opt
    from ..study.designs.named import by_metric

    start = time.perf_counter()
    check_executor(workers, dask_local, scheduler)
    check_resume(out, resume, force)
    the_spec = opt.load_optimise_spec(spec)
    changes = {k: v for k, v in (("maxiter", maxiter), ("popsize", popsize), ("seed", seed),
                                 ("resolution_kmh", resolution), ("high_kmh", high), ("criterion", criterion),
                                 ("speed_control", speed_control)) if v is not None}
    if manoeuvre:
        if len(set(manoeuvre)) != len(manoeuvre):
            raise InputError("a manoeuvre is given twice", where="--manoeuvre")
        changes["manoeuvres"] = tuple(manoeuvre)
    the_spec = replace(the_spec, **changes)
    if option and len(the_spec.manoeuvres) > 1:
        raise InputError("options (-o) apply to one manoeuvre; give a single --manoeuvre", where="--option")
    searches = tuple(opt.Search(m, manoeuvre_options(m, option), the_spec.resolution_kmh, high_kmh=the_spec.high_kmh,
                                criterion=the_spec.criterion, speed_control=the_spec.speed_control, metric=metric,
                                metric_options=metric_options(metric_option))
                     for m in the_spec.manoeuvres)
    if minimise and metric == "threshold":
        raise InputError("the threshold velocity is maximised; --minimise needs another --metric", where="--minimise")
    pset = load_vehicle(vehicle)
    the_spec.check(pset)
    searches = tuple(s.on_course_of(pset) for s in searches)  # every layout meets the reference's course
    vehicle_file = out / _file_name(pset.name)
    reads = [vehicle, spec, *the_spec.manoeuvres, *(s.options.get("file") for s in searches)]
    start_output(out, _plan(pset, the_spec, searches, minimise), PLAN_FILE, kind="an optimise", resume=resume, force=force,
                 reads=reads, writes=[JSON_FILE, LOG_FILE, FIGURE_FILE, vehicle_file.name])
    log = opt.EvaluationLog(out / LOG_FILE, the_spec.names, the_spec.manoeuvres, metric)
    result = opt.run_optimise(pset, the_spec, searches, workers=workers, dask_local=dask_local, scheduler=scheduler, log=log, resume=resume,
                              progress=ProgressLine("optimise", "evaluations", every_s=5.0), minimise=minimise)
    save_vehicle(result.vehicle, vehicle_file)
    # the file as written, searched on its own: what `trikedyn threshold FILE` gives
    written, error = opt.evaluate_layout(load_vehicle(vehicle_file), {}, searches, the_spec.payload_kg)
    data = result.to_dict()
    data["vehicle_file"] = str(vehicle_file)
    data.update(by_metric({"vehicle_file_thresholds_kmh": dict(zip(result.manoeuvres, written, strict=True))}, metric))
    data["vehicle_file_verified"] = tuple(written) == tuple(result.best.thresholds)
    if not data["vehicle_file_verified"]:
        import warnings

        unit = searches[0].unit
        verb = "searches to" if metric == "threshold" else f"measures (its {metric})"
        warnings.warn(f"the written vehicle file {verb} {written} {unit}, the optimiser found "
                      f"{result.best.thresholds} {unit}{f' ({error})' if error else ''}", RuntimeWarning, stacklevel=1)
    # `trikedyn threshold` gives the threshold again; another metric has no such command
    data["check"] = [_check_command(vehicle_file, s.manoeuvre, dict(s.options), the_spec.payload_kg) for s in searches
                     if metric == "threshold"]
    data["wall_time_s"] = time.perf_counter() - start
    files = write_results(out, data, result.plot(), FIGURE_FILE, JSON_FILE, dpi=120, vehicle=str(vehicle_file),
                          evaluations=str(out / LOG_FILE))

    def shown() -> str:
        """The text output: the result's table, the commands that check the thresholds, and the files written."""
        lines = [result.table()]
        lines += [f"  check: {c}" for c in data["check"]]
        lines.append(f"wrote {', '.join(files.values())}")
        return "\n".join(lines)

    emit(data, as_json, shown)
