"""``trikedyn loading-chart``: the safe speed for operators over freight mass and freight position (or any study
metric over them, ``--metric``: then there is no safe speed).

With ``--out``, each cell is logged (``loading-chart-cells.csv``) as it finishes, beside the run's plan
(``loading-chart-plan.json``); ``--resume`` continues a run that was killed or interrupted: the cells logged
are not run again (:class:`trikedyn.study.designs.loading.CellLog`)."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
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
    write_results,
)

JSON_FILE, CSV_FILE, FIGURE_FILE = "loading-chart.json", "loading-chart.csv", "loading-chart.png"
CELLS_FILE, PLAN_FILE = "loading-chart-cells.csv", "loading-chart-plan.json"


def _numbers(text: str | None, option: str) -> list[float] | None:
    """A comma-separated list of finite numbers (None: the default grid)."""
    if text is None:
        return None
    values = []
    for part in text.split(","):
        try:
            value = float(part)
        except ValueError:
            raise InputError(f"expected comma-separated numbers, got {part.strip()!r}", where=option) from None
        if not math.isfinite(value):
            raise InputError(f"expected finite numbers, got {part.strip()!r}", where=option)
        values.append(value)
    return values


def loading_chart_cmd(
    vehicle: VehicleArg,
    manoeuvre: ManoeuvreOpt = "dlc",
    option: OptionOpt = [],  # noqa: B006
    masses: Annotated[str | None, typer.Option("--masses", help="Freight masses [kg], comma-separated (default 0,50,100,150,200).")] = None,
    x: Annotated[str | None, typer.Option("--x", help="Fore-aft positions of the freight [m, vehicle axes], comma-separated (default: the vehicle's freight site and +/-0.2 m).")] = None,
    z: Annotated[str | None, typer.Option("--z", help="Heights of the freight [m], comma-separated (default: the freight site and +0.2, +0.4 m).")] = None,
    margin_kmh: Annotated[float | None, typer.Option("--margin-kmh", callback=within(0, 200, "km/h"), help="Safe speed = threshold - this [km/h], not below 0 (default 5).")] = None,
    margin_fraction: Annotated[float | None, typer.Option("--margin-fraction", callback=within(0, 0.99), help="Or: safe speed = threshold x (1 - this) [-].")] = None,
    resolution: Annotated[float, typer.Option("--resolution", callback=search_bound("resolution_kmh"), help="Resolution of each threshold search [km/h].")] = SEARCH_DEFAULTS["resolution_kmh"],
    high: Annotated[float, typer.Option("--high", callback=search_bound("high_kmh"), help="Highest speed searched [km/h] (raise it for slc).")] = SEARCH_DEFAULTS["high_kmh"],
    criterion: CriterionOpt = SEARCH_DEFAULTS["criterion"],
    speed_control: SpeedControlOpt = SEARCH_DEFAULTS["speed_control"],
    metric: MetricOpt = "threshold",
    metric_option: MetricOptionOpt = [],  # noqa: B006
    workers: WorkersOpt = None,
    dask_local: DaskLocalOpt = None,
    scheduler: SchedulerOpt = None,
    out: Annotated[Path | None, typer.Option("--out", help="Folder for loading-chart.json, .csv and .png (a printable figure), and the cells as they finish (loading-chart-cells.csv).")] = None,
    resume: Annotated[bool, typer.Option("--resume", help="Continue an interrupted run in --out: cells in its log are not run again.")] = False,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """The safe speed (threshold velocity less a stated margin) over freight mass and freight position; with --metric, that metric in each cell and no safe speed."""
    from ..params import load_vehicle
    from ..study.designs import loading as lc
    from ..study.designs.search import Search

    if margin_kmh is not None and margin_fraction is not None:
        raise InputError("give --margin-kmh or --margin-fraction, not both", where="--margin-fraction")
    grid = [_numbers(masses, "--masses"), _numbers(x, "--x"), _numbers(z, "--z")]
    if grid[0] is not None and any(m < 0 for m in grid[0]):
        raise InputError("freight masses must be >= 0 kg", where="--masses")
    check_executor(workers, dask_local, scheduler)
    check_resume(out, resume, force)
    options = manoeuvre_options(manoeuvre, option)
    pset = load_vehicle(vehicle)
    search = Search(manoeuvre, options, resolution, high_kmh=high, criterion=criterion, speed_control=speed_control,
                    metric=metric, metric_options=metric_options(metric_option)).on_course_of(pset)
    if search.metric != "threshold" and (margin_kmh is not None or margin_fraction is not None):
        raise InputError("a margin applies to the threshold only: a chart of another metric has no safe speed",
                         where="--margin-kmh" if margin_kmh is not None else "--margin-fraction")
    log = None
    if out is not None:
        masses_kg, x_m, z_m = lc.grid_cells(pset, *grid)
        plan = json.loads(json.dumps({"vehicle": pset.name, **search.to_dict(), "masses_kg": masses_kg, "x_m": x_m,
                                      "z_m": z_m}))
        start_output(out, plan, PLAN_FILE, kind="a loading-chart", resume=resume, force=force,
                     reads=[vehicle, manoeuvre, options.get("file")],
                     writes=[JSON_FILE, CSV_FILE, FIGURE_FILE, CELLS_FILE])
        log = lc.CellLog(out / CELLS_FILE, search.metric)
    chart = lc.run_loading_chart(pset, search, *grid,
                                 margin_kmh=lc.DEFAULT_MARGIN_KMH if margin_kmh is None else margin_kmh,
                                 margin_fraction=margin_fraction, workers=workers, dask_local=dask_local, scheduler=scheduler, log=log, resume=resume,
                                 progress=ProgressLine("loading-chart", "cells", every_s=3.0))
    data = chart.to_dict()
    if out is not None:
        from .._files import atomic_write

        atomic_write(out / CSV_FILE, lambda fh: csv.writer(fh).writerows(chart.rows()), binary=False)
        write_results(out, data, chart.plot(), FIGURE_FILE, JSON_FILE, dpi=150, csv=str(out / CSV_FILE),
                      cells=str(out / CELLS_FILE))

    def shown() -> str:
        """The text output: the chart's table, and the files written when there is an output folder."""
        lines = [chart.table()]
        if out is not None:
            lines.append(f"wrote {', '.join(data['files'].values())}")
        return "\n".join(lines)

    emit(data, as_json, shown)
