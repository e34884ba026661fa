"""Run a study: every scenario's threshold search, in parallel, into the resumable result store.

Executors (:mod:`trikedyn.study.executors`; the same function, the same results, to the last digit):

- a local process pool (default; ``workers`` processes, spawn context, which is safe with numba);
- ``workers=0``: one scenario after the other in this process (debugging);
- ``dask_local=N``: a ``dask.distributed.LocalCluster`` of N single-threaded worker processes;
- ``scheduler="tcp://host:port"``: an existing Dask cluster (its workers need the same trikedyn).

Bounded: before anything is expanded or written, the spec's scenarios are counted from its axis lengths
(:func:`~trikedyn.study.spec.count_scenarios`); more than ``max_scenarios`` (10,000 by default; the
paper's study has 50) is an :class:`~trikedyn.errors.InputError` naming the spec file, so a few lines of
TOML with seven ten-value axes (10^7 scenarios) are refused at once instead of filling the memory.

The main process keeps at most a few scenarios more in flight than there are workers, writes each result
to the store as it completes (:mod:`trikedyn.study.store`) and shows a progress bar on stderr.

Interruption: the first SIGINT (Ctrl-C) or SIGTERM stops submitting, lets the scenarios in flight finish
and be stored, then raises :class:`StudyInterrupted` (the CLI exits with code 130 and says how many
scenarios are stored); a second one abandons the scenarios in flight. A SIGKILL at any moment leaves the
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
import json
import os
import signal
import socket
import sys
import threading
import time
import traceback
import uuid
from collections import deque
from concurrent.futures import CancelledError
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError, TrikedynError
from .executors import check_executor, make_executor
from .executors import one_line as _one_line
from .spec import SCENARIO_KEYS, StudySpec, count_scenarios, expand, load_spec
from .store import RESULT_KEYS, StudyStore

__all__ = ["MAX_SCENARIOS", "StudyIncomplete", "StudyInterrupted", "main", "run_scenario", "run_study",
           "study_command"]

MAX_SCENARIOS = 10_000
"""Default limit on a study's scenarios (:func:`run_study`'s ``max_scenarios``)."""


class StudyInterrupted(KeyboardInterrupt):
    """A study run stopped by SIGINT/SIGTERM; what finished is stored and a re-run resumes.

    Attributes
    ----------
    summary : dict
        As :func:`study_command` reports it (``out``, ``scenarios`` counts, ``wall_time_s``, ...).
    """

    def __init__(self, message: str, summary: dict):
        super().__init__(message)
        self.summary = summary


class StudyIncomplete(TrikedynError):
    """Some scenarios were lost to dead workers (not to their own errors); a re-run retries them."""

    def __init__(self, message: str, summary: dict):
        super().__init__(message)
        self.summary = summary


# ------------------------------------------------------------------------------------------------
# one scenario
# ------------------------------------------------------------------------------------------------
def run_scenario(scenario: dict, vehicle=None, run_token: str | None = None) -> dict:
    """Compute one scenario's threshold velocity; never raises for the scenario's own failure.

    The vehicle is built as: load (or take ``vehicle``), ``scale_suspension``, ``override``,
    ``with_freight``; then :func:`~trikedyn.analysis.threshold.threshold_velocity` runs.

    Parameters
    ----------
    scenario : dict
        One of :func:`trikedyn.study.spec.expand`'s scenarios.
    vehicle : ParameterSet, optional
        The study's base vehicle (the runner loads it once and ships it). If None, ``scenario["vehicle"]``
        is loaded: a preset name, or a path valid from the working folder.
    run_token : str, optional
        The run's token, kept in the row.

    Returns
    -------
    dict
        Flat: the scenario's fields, ``status`` (``"ok"`` or ``"error"``), the threshold result's keys
        (``threshold_speed_kmh`` [km/h], ``limit``, ``limiting_wheel``, ``lift_time_s`` [s],
        ``first_failure_kmh``, ``first_cone_strike_kmh`` [km/h], ``detail``, ``n_runs``; None on error),
        ``error`` (one line, or None), ``traceback``, ``wall_time_s`` [s], ``worker`` (host:pid),
        ``run_token`` and ``finished_at`` [s since the epoch].
    """
    start = time.perf_counter()
    row = {k: scenario[k] for k in SCENARIO_KEYS}
    try:
        from ..analysis.threshold import threshold_velocity
        from ..params import load_vehicle, override, scale_suspension, with_freight

        pset = vehicle if vehicle is not None else load_vehicle(scenario["vehicle"])
        pset = scale_suspension(pset, stiffness=scenario["stiffness_scale"], damping=scenario["damping_scale"])
        if scenario["overrides"]:
            pset = override(pset, scenario["overrides"])
        pset = with_freight(pset, scenario["freight_kg"])
        result = threshold_velocity(pset, scenario["manoeuvre"], low_kmh=scenario["low_kmh"],
                                    high_kmh=scenario["high_kmh"], step_kmh=scenario["step_kmh"],
                                    resolution_kmh=scenario["resolution_kmh"])
        row.update(status="ok", **result.to_dict(), error=None, traceback=None)
    except Exception as exc:  # the scenario's own failure is a result, not a crash
        row.update(status="error", **dict.fromkeys(RESULT_KEYS), error=_one_line(exc),
                   traceback=traceback.format_exc())
    row.update(wall_time_s=time.perf_counter() - start, worker=f"{socket.gethostname()}:{os.getpid()}",
               run_token=run_token, finished_at=time.time())
    return row


# ------------------------------------------------------------------------------------------------
# the loop
# ------------------------------------------------------------------------------------------------
class _StopSignal:
    """First SIGINT/SIGTERM: ask to stop after the scenarios in flight; second: KeyboardInterrupt now."""

    def __init__(self):
        self.requested: str | None = None
        self._previous: dict = {}

    def _handler(self, signum, frame):
        if self.requested is not None:
            raise KeyboardInterrupt
        self.requested = signal.Signals(signum).name
        print(f"\n{self.requested}: stopping after the scenarios in flight (again to abandon them)",
              file=sys.stderr, flush=True)

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous[sig] = signal.signal(sig, self._handler)
        return self

    def __exit__(self, *exc):
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)


@dataclass
class _Outcome:
    summary: dict
    frame: object = None
    lost: list = field(default_factory=list)


def _progress_bar(total: int, initial: int, progress: bool):
    from tqdm import tqdm

    enabled = progress and sys.stderr.isatty()
    return tqdm(total=total, initial=initial, disable=not enabled, file=sys.stderr, unit="scenario",
                desc="study", dynamic_ncols=True)


def _check_limit(max_scenarios) -> None:
    if max_scenarios is None:
        return
    if isinstance(max_scenarios, bool) or not isinstance(max_scenarios, int | float) or max_scenarios < 1 \
            or int(max_scenarios) != max_scenarios:
        raise InputError(f"expected a whole number of scenarios >= 1, got {max_scenarios!r}", where="max_scenarios")


def _check_size(spec: StudySpec, max_scenarios) -> None:
    """Refuse a spec with more than ``max_scenarios`` scenarios, counted without expanding it."""
    if max_scenarios is None:
        return
    n, exact = count_scenarios(spec)
    if n > max_scenarios:
        size = f"{n:,} scenarios" if exact else f"up to {n:,} scenarios"
        raise InputError(f"the spec expands to {size}, more than the limit {int(max_scenarios):,}; "
                         f"pass --max-scenarios {n} to run it", where=spec.origin)


def _run(spec, out_dir, *, workers=None, dask_local=None, scheduler=None, progress=True,
         max_scenarios=MAX_SCENARIOS) -> _Outcome:
    started = time.perf_counter()
    check_executor(workers, dask_local, scheduler)
    _check_limit(max_scenarios)
    spec = load_spec(spec)
    _check_size(spec, max_scenarios)
    scenarios = expand(spec)
    order = [s["scenario_id"] for s in scenarios]
    token = uuid.uuid4().hex[:12]
    with StudyStore(out_dir, spec.name, lock=True) as store:
        done = store.done_ids() & set(order)
        todo = deque(s for s in scenarios if s["scenario_id"] not in done)
        n_skipped = len(done)
        base = spec.load_vehicle() if todo else None
        counts = {"computed": 0}
        lost: list[tuple[str, str]] = []
        outcome = "completed"
        backend = make_executor(workers, dask_local, scheduler, len(todo))
        store.begin_run(token, len(todo), backend.label)
        bar = _progress_bar(len(scenarios), len(done), progress)
        stop = _StopSignal()
        running: dict = {}
        broken = False

        def collect(fut):
            scenario = running.pop(fut)
            try:
                row = backend.result(fut)
            except CancelledError:
                return
            except Exception as exc:  # the worker died, not the scenario
                lost.append((scenario["scenario_id"], _one_line(exc)))
                return
            store.put(row)
            counts["computed"] += 1
            bar.update(1)

        try:
            with stop:
                while todo or running:
                    if stop.requested:
                        todo.clear()
                        for fut in list(running):
                            if backend.cancel(fut):
                                running.pop(fut)
                    while todo and len(running) < backend.window and not stop.requested:
                        scenario = todo.popleft()
                        try:
                            fut = backend.submit(run_scenario, scenario, base, token,
                                                 key=f"trikedyn-{token}-{scenario['scenario_id']}")
                        except RuntimeError as exc:  # BrokenProcessPool, a closed client
                            lost.append((scenario["scenario_id"], _one_line(exc)))
                            broken = True
                            break
                        running[fut] = scenario
                        if fut.done():
                            collect(fut)
                    if broken:  # what is not submitted is lost for this run
                        lost.extend((s["scenario_id"], "not run: executor broken") for s in todo)
                        todo.clear()
                    if running:
                        for fut in list(backend.wait(list(running), timeout=0.25)):
                            collect(fut)
        except KeyboardInterrupt:  # a second signal: abandon the scenarios in flight
            backend.abandon()
            outcome = "interrupted"
        except Exception:  # not the scenarios' own failures (those are rows): say so, then let it through
            with contextlib.suppress(Exception):
                store.end_run(token, "failed")
            raise
        finally:
            bar.close()
            backend.close()
        if stop.requested:
            outcome = "interrupted"
        elif lost and outcome != "interrupted":
            outcome = "incomplete"
        store.end_run(token, outcome)

        stored = store.done_ids() & set(order)
        n_failed = sum(r["status"] == "error" for r in store.rows() if r["scenario_id"] in stored)
        files = store.export(order) if len(stored) == len(order) else {}
        summary = {
            "study": spec.name,
            "out": str(Path(out_dir)),
            "database": str(store.path),
            "executor": backend.label,
            "outcome": outcome,
            "scenarios": {"total": len(order), "done": len(stored), "failed": n_failed,
                          "computed": counts["computed"], "skipped": n_skipped, "lost": len(lost)},
            "wall_time_s": round(time.perf_counter() - started, 3),
            "table": str(files["csv"]) if files else None,
            "parquet": str(files["parquet"]) if files else None,
            "run_token": token,
        }
        frame = store.to_pandas(order)
    return _Outcome(summary, frame, lost)


def run_study(spec: str | Path | StudySpec, out_dir: str | Path, *, workers: int | None = None,
              dask_local: int | None = None, scheduler: str | None = None, progress: bool = True,
              max_scenarios: int | None = MAX_SCENARIOS):
    """Run (or resume) a study into ``out_dir`` and return its results table.

    Parameters
    ----------
    spec : str, path or StudySpec
        A built-in study name (``"paper"``), a study TOML file, or a loaded spec.
    out_dir : path
        Output folder: ``study.sqlite`` (the store), and once every scenario is stored, ``results.csv``
        and ``results.parquet``. Re-running into the same folder computes only the missing scenarios.
    workers : int, optional
        Processes of the local pool; ``os.cpu_count()`` by default; 0 runs in this process.
    dask_local : int, optional
        Run on a new Dask ``LocalCluster`` of this many single-threaded workers instead.
    scheduler : str, optional
        Run on an existing Dask cluster, e.g. ``"tcp://host:8786"``, instead.
    progress : bool
        Progress bar on stderr (only when stderr is a terminal).
    max_scenarios : int or None
        Refuse a spec with more scenarios than this (counted from its axes before anything is expanded or
        written; an upper bound in the rare spec whose groups overlap too much to count exactly); None for
        no limit.

    Returns
    -------
    pandas.DataFrame
        The spec's stored scenarios in spec order (see :meth:`StudyStore.to_pandas`); identical, value for
        value, whichever executor ran them. Use a ``if __name__ == "__main__":`` guard in scripts: the
        process pool spawns fresh interpreters.

    Raises
    ------
    InputError
        Bad spec, more scenarios than ``max_scenarios``, two executors chosen, an output folder that cannot
        be created or written, a symbolic link where the study keeps a file, the folder held by another
        study or another run.
    StudyInterrupted
        SIGINT/SIGTERM: the finished scenarios are stored; re-run to resume.
    StudyIncomplete
        Workers died; the other scenarios are stored; re-run to retry the lost ones.
    """
    outcome = _run(spec, out_dir, workers=workers, dask_local=dask_local, scheduler=scheduler, progress=progress,
                   max_scenarios=max_scenarios)
    _raise_unfinished(outcome)
    return outcome.frame


def _raise_unfinished(outcome: _Outcome) -> None:
    s = outcome.summary
    n = s["scenarios"]
    if s["outcome"] == "interrupted":
        raise StudyInterrupted(
            f"interrupted: {n['done']} of {n['total']} scenarios stored in {s['database']}; run the same command "
            f"again to resume (stored scenarios are not recomputed)", s)
    if s["outcome"] == "incomplete":
        first = outcome.lost[0][1] if outcome.lost else "unknown"
        raise StudyIncomplete(
            f"{n['lost']} scenario(s) not finished (worker lost: {first}); {n['done']} of {n['total']} stored in "
            f"{s['database']}; run again to retry them", s)


def _summary_text(s: dict) -> str:
    n = s["scenarios"]
    lines = [
        f"study '{s['study']}': {n['done']} of {n['total']} scenarios stored ({n['failed']} failed); "
        f"{n['computed']} computed in this run, {n['skipped']} already stored",
        f"wall time {s['wall_time_s']:.1f} s on {s['executor']}",
    ]
    if s["table"]:
        lines.append(f"table: {s['table']} (and {Path(s['parquet']).name})")
    return "\n".join(lines)


def study_command(spec_path, workers=None, dask_local=None, scheduler=None, out=None, as_json=False,
                  max_scenarios: int | None = MAX_SCENARIOS) -> dict:
    """The ``trikedyn study`` command: run or resume a study and print a summary.

    Parameters
    ----------
    spec_path : str or path
        A built-in study name (``paper``) or a study TOML file.
    workers, dask_local, scheduler
        The executor (see :func:`run_study`); at most one.
    out : path, optional
        Output folder; ``study-<name>`` in the working folder by default.
    as_json : bool
        Print JSON (``study``, ``out``, ``scenarios`` {total, done, failed, computed, skipped, lost},
        ``wall_time_s``, ``table``, ...) instead of text.
    max_scenarios : int or None
        ``--max-scenarios``: refuse a spec with more scenarios (see :func:`run_study`); None for no limit.

    Returns
    -------
    dict
        The summary. On SIGINT/SIGTERM the summary (JSON) or a message (stderr) is printed and
        ``SystemExit(130)`` raised; on lost workers, ``SystemExit(1)``. ``InputError`` propagates (exit 2).
    """
    spec = load_spec(spec_path)
    out = Path(out) if out is not None else Path(f"study-{spec.name}")
    outcome = _run(spec, out, workers=workers, dask_local=dask_local, scheduler=scheduler, progress=True,
                   max_scenarios=max_scenarios)
    summary = outcome.summary
    print(json.dumps(summary, indent=2) if as_json else _summary_text(summary), flush=True)
    try:
        _raise_unfinished(outcome)
    except StudyInterrupted as exc:
        print(f"trikedyn: {exc}", file=sys.stderr, flush=True)
        raise SystemExit(130) from None
    except StudyIncomplete as exc:
        print(f"trikedyn: {exc}", file=sys.stderr, flush=True)
        raise SystemExit(1) from None
    return summary


def main(argv: list[str] | None = None) -> int:
    """``python -m trikedyn.study.runner SPEC [--out DIR] [--workers N | --dask-local N | --scheduler URL]
    [--max-scenarios N]``."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m trikedyn.study.runner", description="Run or resume a study.")
    parser.add_argument("spec", help="built-in study name (paper) or a study .toml file")
    parser.add_argument("--out", default=None, help="output folder (default: study-<name>)")
    parser.add_argument("--workers", type=int, default=None, help="local processes (0: in this process)")
    parser.add_argument("--dask-local", type=int, default=None, help="workers of a new Dask LocalCluster")
    parser.add_argument("--scheduler", default=None, help="address of an existing Dask scheduler")
    parser.add_argument("--max-scenarios", type=int, default=MAX_SCENARIOS,
                        help=f"refuse a spec with more scenarios than this (default {MAX_SCENARIOS})")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")
    args = parser.parse_args(argv)
    try:
        study_command(args.spec, args.workers, args.dask_local, args.scheduler, args.out, args.json,
                      max_scenarios=args.max_scenarios)
    except InputError as exc:
        print(f"trikedyn: error: {exc}", file=sys.stderr)
        return 2
    except SystemExit as exc:
        return int(exc.code or 0)
    return 0


if __name__ == "__main__":
    from trikedyn.study.runner import main as _main  # the importable module, so workers unpickle its functions

    sys.exit(_main())
