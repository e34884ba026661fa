"""Run a study: every scenario's metric (the threshold velocity by default), in parallel, into the resumable
result store; the runner returns data and prints nothing (the ``trikedyn study`` command, in
:mod:`trikedyn.commands.studies`, prints).

Executors (:mod:`trikedyn.study.engine.executors`, each a :class:`concurrent.futures.Executor`, driven by the
engine's one scheduling loop, :func:`trikedyn.study.engine.loop.drive`; the same function, the same results,
to the last digit):

- a local process pool (default; ``workers`` processes, from a preloaded fork server where the platform
  has one, else spawned: neither forks a process with threads, which is what makes it safe with numba);
- ``workers=0``: one scenario after the other in this process (debugging);
- ``dask_local=N``: a ``dask.distributed.LocalCluster`` of N single-threaded worker processes, through a
  client (:class:`~trikedyn.study.engine.dask.DaskExecutor`);
- ``scheduler="tcp://host:port"``: an existing Dask cluster (its workers need the same trikedyn), likewise.
  A scheduler lost mid-study (:class:`~trikedyn.study.engine.dask.SchedulerLost`) loses the scenarios in
  flight and stops the submissions: the run ends at once as :class:`StudyIncomplete`, and a re-run (on a
  new scheduler, or another executor) resumes.

Bounded: before anything is expanded or written, the spec's scenarios are counted from its axis lengths
(:func:`~trikedyn.study.scenarios.count_scenarios`); more than ``max_scenarios`` (10,000 by default; the
paper's study has 50) is an :class:`~trikedyn.errors.InputError` naming the spec file, so a few lines of
TOML with seven ten-value axes (10^7 scenarios) are refused at once instead of filling the memory.

The main process keeps at most a few scenarios more in flight than there are workers, writes each result
to the store as it completes (:mod:`trikedyn.study.engine.store`) and reports its progress to a reporter
(:mod:`trikedyn.study.engine.progress`: a bar on a terminal, a plain line every few seconds otherwise). Once every
scenario is stored it exports the table and draws the study's figures (:mod:`trikedyn.study.designs.figures`).

Interruption: the first SIGINT (Ctrl-C) stops submitting, lets the scenarios in flight finish and be
stored, then raises :class:`StudyInterrupted` (the CLI exits with code 130 and says how many scenarios are
stored); a second one, or a SIGTERM at any time (``timeout``, ``kill``: a scenario that hangs must not keep
the process alive), abandons the scenarios in flight (``shutdown(wait=False, cancel_futures=True)``: the
pool's workers are stopped; the CLI exits with code 143 after a SIGTERM). A SIGKILL at any moment leaves the
store consistent. Re-running the same spec into the same folder resumes: stored scenarios are not
recomputed. Pool workers ignore SIGINT (the main process decides) and exit on their own when the main
process dies.

Every run is recorded in the store's ``runs`` table; a run that dies without saying how it ended is marked
``killed`` by the next run into the folder, and one ended by an exception ``failed``.

A scenario that fails (any exception: an invalid override, a simulation error) is stored as a row with
``status = "error"`` and its error text, and the study goes on. A worker that dies (crash, out of memory)
loses its scenario: it is not stored, the study finishes the others and raises :class:`StudyIncomplete`;
a re-run retries it.
"""

from __future__ import annotations

import contextlib
import os
import socket
import time
import traceback
import uuid
import warnings
from collections import deque
from pathlib import Path

from ...errors import InputError
from ..engine.background import import_in_background
from ..engine.executors import InlineExecutor, check_executor, make_executor, start_pool_server
from ..engine.executors import one_line as _one_line
from ..engine.loop import StopSignal, drive
from ..engine.store import RESULT_KEYS, StudyStore
from ..scenarios import SCENARIO_KEYS, expand
from ..spec import StudySpec, load_spec
from .study_run import (  # noqa: F401  (re-exported: the module is the grid study's entry point)
    STUDY_FILES,
    StudyIncomplete,
    StudyInterrupted,
    StudyRun,
    _check_limit,
    _check_size,
    check_study_folder,
)

__all__ = ["MAX_SCENARIOS", "STUDY_FILES", "StudyIncomplete", "StudyInterrupted", "StudyRun", "check_study_folder",
           "execute_study", "run_scenario", "run_study"]

MAX_SCENARIOS = 10_000
"""Default limit on a study's scenarios (:func:`run_study`'s ``max_scenarios``)."""


# ------------------------------------------------------------------------------------------------
# one scenario
# ------------------------------------------------------------------------------------------------
def run_scenario(scenario: dict, vehicle=None, run_token: str | None = None) -> dict:
    """Compute one scenario's metric; never raises for the scenario's own failure.

    The vehicle is built as: load (or take ``vehicle``), then the scenario's
    :class:`~trikedyn.params.variant.Variant` (``scale_suspension``, ``override``, ``with_freight``); then the scenario's metric (:mod:`trikedyn.study.metrics`; the threshold velocity,
    :func:`~trikedyn.analysis.threshold.threshold_velocity`, by default) runs.

    Parameters
    ----------
    scenario : dict
        One of :func:`trikedyn.study.scenarios.expand`'s scenarios.
    vehicle : ParameterSet, optional
        The study's base vehicle (the runner loads it once and ships it). If None, ``scenario["vehicle"]``
        is loaded: a preset name, or a path valid from the working folder.
    run_token : str, optional
        The run's token, kept in the row.

    Returns
    -------
    dict
        Flat: the scenario's fields, ``status`` (``"ok"`` or ``"error"``), ``value`` (the metric's number)
        and ``unit``, the threshold result's keys (``threshold_speed_kmh`` [km/h], ``limit``,
        ``limiting_wheel``, ``lift_time_s`` [s], ``first_failure_kmh``, ``first_cone_strike_kmh`` [km/h],
        ``detail``, ``n_runs``; None on error and, but ``detail``, for the other metrics), ``error`` (one
        line, or None), ``traceback``, ``wall_time_s`` [s], ``worker`` (host:pid), ``run_token`` and
        ``finished_at`` [s since the epoch].
    """
    start = time.perf_counter()
    row = {k: scenario.get(k) for k in SCENARIO_KEYS}
    name = scenario.get("metric") or "threshold"
    try:
        from ...params import load_vehicle
        from ...params.variant import Variant
        from ..metrics import get

        metric = get(name)
        pset = vehicle if vehicle is not None else load_vehicle(scenario["vehicle"])
        pset = Variant.from_dict(scenario).apply(pset)  # scale, override, freight
        result = metric.fn(pset, scenario, **(scenario.get("metric_options") or {}))
        row.update({"status": "ok", **dict.fromkeys(RESULT_KEYS), "unit": metric.unit, **result, "error": None,
                    "traceback": None})
    except Exception as exc:  # the scenario's own failure is a result, not a crash
        from .sample_runs import raise_interrupt

        raise_interrupt(exc)  # a Ctrl-C that landed in compiled code is an interrupt, not a failed scenario
        row.update(status="error", **dict.fromkeys(RESULT_KEYS), error=_one_line(exc),
                   traceback=traceback.format_exc())
    row.update(wall_time_s=time.perf_counter() - start, worker=f"{socket.gethostname()}:{os.getpid()}",
               run_token=run_token, finished_at=time.time())
    return row


def execute_study(spec: str | Path | StudySpec, out_dir: str | Path, *, workers: int | None = None,
                  dask_local: int | None = None, scheduler: str | None = None, progress=True,
                  max_scenarios: int | None = MAX_SCENARIOS, figures: bool = True, force: bool = False) -> StudyRun:
    """Run (or resume) a study into ``out_dir``; an interrupted or incomplete run is returned, not raised.

    Takes the arguments of :func:`run_study`. Returns a :class:`StudyRun` (its ``raise_unfinished()`` raises
    what :func:`run_study` raises). ``InputError`` (bad spec, options, folder) is raised.

    Parameters
    ----------
    spec : str, Path or StudySpec
        A built-in name, a TOML file or a loaded spec.
    out_dir : str or Path
        The output folder.
    workers : int, optional
        Local processes (all cores by default; 0: this process).
    dask_local : int, optional
        Workers of a new local Dask cluster.
    scheduler : str, optional
        Address of an existing Dask scheduler.
    progress : bool or callable
        Progress reporting (:func:`~trikedyn.study.engine.progress.reporter`).
    max_scenarios : int or None
        Refuse a larger spec.
    figures : bool
        Draw the figures once every scenario is stored.
    force : bool
        Write into a folder holding other files.

    Returns
    -------
    StudyRun
        The run: its table, summary and how it ended.
    """
    from ..engine.progress import reporter

    started = time.perf_counter()
    check_executor(workers, dask_local, scheduler)
    start_pool_server(workers, dask_local, scheduler)
    _check_limit(max_scenarios)
    spec = load_spec(spec)
    _check_size(spec, max_scenarios)
    check_study_folder(out_dir, spec, force)
    scenarios = expand(spec)
    order = [s["scenario_id"] for s in scenarios]
    token = uuid.uuid4().hex[:12]
    report = reporter(progress)
    with StudyStore(out_dir, spec.name, lock=True) as store:
        done = store.done_ids() & set(order)
        todo = deque(s for s in scenarios if s["scenario_id"] not in done)
        n_skipped = len(done)
        base = spec.load_vehicle() if todo else None
        n_done = len(done)
        computed = 0
        lost: list[tuple[str, str]] = []
        outcome = "completed"
        executor = make_executor(workers, dask_local, scheduler, len(todo))
        if workers != 0 and todo:  # the export's and figures' libraries load while the workers compute
            import_in_background("pandas", "pyarrow.parquet", *(("matplotlib.figure",) if figures else ()))
        store.begin_run(token, len(todo), executor.label)
        stop = StopSignal(getattr(report, "note", None), inline=isinstance(executor, InlineExecutor))
        abandoned = False

        def collect(scenario_id, row):
            """Store a finished scenario's ``row``, count it and report progress."""
            nonlocal n_done, computed
            store.put(row)
            computed += 1
            n_done += 1
            if report is not None:
                report(n_done, len(order))

        try:
            with stop:  # the first progress line once a signal is ours: a Ctrl-C on seeing it stops the study
                if report is not None:
                    report(n_done, len(order))
                dropped = drive(executor, run_scenario, [(s["scenario_id"], (s, base, token)) for s in todo], collect,
                                stop=stop)
                lost.extend((item.key, item.why) for item in dropped)
        except KeyboardInterrupt:  # a second signal: the loop abandoned the scenarios in flight
            abandoned = True
            outcome = "interrupted"
        except Exception:  # not the scenarios' own failures (those are rows): say so, then let it through
            with contextlib.suppress(Exception):
                store.end_run(token, "failed")
            raise
        finally:
            if report is not None and hasattr(report, "close"):
                report.close()
            if not abandoned:  # every call collected: the idle workers exit while the results are exported
                executor.shutdown(wait=False)
        if stop.requested:
            outcome = "interrupted"
        elif lost and outcome != "interrupted":
            outcome = "incomplete"
        store.end_run(token, outcome)

        stored = store.done_ids() & set(order)
        n_failed = sum(r["status"] == "error" for r in store.rows() if r["scenario_id"] in stored)
        files = store.export(order) if len(stored) == len(order) else {}
        frame = store.to_pandas(order)
        database = store.path
    drawn = _figures(frame, Path(out_dir), spec.name) if files and figures else []
    summary = {
        "study": spec.name,
        "out": str(Path(out_dir)),
        "database": str(database),
        "executor": executor.label,
        "outcome": outcome,
        "scenarios": {"total": len(order), "done": len(stored), "failed": n_failed, "computed": computed,
                      "skipped": n_skipped, "lost": len(lost)},
        "metrics": list(dict.fromkeys(s["metric_label"] for s in scenarios)),
        "criterion": spec.criterion,
        "speed_control": spec.speed_control,
        "wall_time_s": round(time.perf_counter() - started, 3),
        "table": str(files["csv"]) if files else None,
        "parquet": str(files["parquet"]) if files else None,
        "figures": [str(p) for p in drawn],
        "run_token": token,
    }
    return StudyRun(summary, frame, lost, stop.requested)


def _figures(frame, out_dir: Path, title: str) -> list[Path]:
    """The study's figures; a figure that cannot be drawn is a warning, not a lost study."""
    from .figures import study_figures

    try:
        return study_figures(frame, out_dir, title=title)
    except InputError:
        raise
    except Exception as exc:  # the results are stored and exported: do not fail the run for a plot
        warnings.warn(f"the study's figures were not drawn: {_one_line(exc)}", RuntimeWarning, stacklevel=3)
        return []


def run_study(spec: str | Path | StudySpec, out_dir: str | Path, *, workers: int | None = None,
              dask_local: int | None = None, scheduler: str | None = None, progress=True,
              max_scenarios: int | None = MAX_SCENARIOS, figures: bool = True, force: bool = False):
    """Run (or resume) a study into ``out_dir`` and return its results table.

    Parameters
    ----------
    spec : str, path or StudySpec
        A built-in study name (``"paper"``), a study TOML file, or a loaded spec.
    out_dir : path
        Output folder: ``study.sqlite`` (the store), and once every scenario is stored, ``results.csv``,
        ``results.parquet`` and the figures (``fig_*.png``, :mod:`trikedyn.study.designs.figures`). Re-running into
        the same folder computes only the missing scenarios.
    workers : int, optional
        Processes of the local pool; ``os.cpu_count()`` by default; 0 runs in this process.
    dask_local : int, optional
        Run on a new Dask ``LocalCluster`` of this many single-threaded workers instead.
    scheduler : str, optional
        Run on an existing Dask cluster, e.g. ``"tcp://host:8786"``, instead.
    progress : bool or callable
        True: a progress bar on stderr when it is a terminal, else a line every few seconds
        (:mod:`trikedyn.study.engine.progress`); False: silent; a callable ``(done, total)`` is called instead.
    max_scenarios : int or None
        Refuse a spec with more scenarios than this (counted from its axes before anything is expanded or
        written; an upper bound in the rare spec whose groups overlap too much to count exactly); None for
        no limit.
    figures : bool
        Draw the study's figures once every scenario is stored.
    force : bool
        Write into an existing folder that holds other files but no study (its ``results.csv``,
        ``results.parquet`` and ``fig_*.png`` are replaced; :func:`check_study_folder`). A folder with a
        ``study.sqlite`` needs no ``force``: the run resumes it.

    Returns
    -------
    pandas.DataFrame
        The spec's stored scenarios in spec order (see :meth:`StudyStore.to_pandas`); identical, value for
        value, whichever executor ran them. Use a ``if __name__ == "__main__":`` guard in scripts: each
        worker of the process pool imports the script again.

    Raises
    ------
    InputError
        Bad spec, more scenarios than ``max_scenarios``, two executors chosen, an output folder that cannot
        be created or written, a symbolic link where the study keeps a file, the folder held by another
        study or another run, an existing folder with other files but no study (without ``force``), an
        output that is one of the study's inputs.
    StudyInterrupted
        SIGINT/SIGTERM: the finished scenarios are stored; re-run to resume.
    StudyIncomplete
        Workers died; the other scenarios are stored; re-run to retry the lost ones.
    """
    result = execute_study(spec, out_dir, workers=workers, dask_local=dask_local, scheduler=scheduler,
                           progress=progress, max_scenarios=max_scenarios, figures=figures, force=force)
    result.raise_unfinished()
    return result.table
