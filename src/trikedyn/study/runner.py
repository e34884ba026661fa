"""Run a study: every scenario's threshold search, in parallel, into the resumable result store.

Executors (the same function, the same results, to the last digit):

- a local process pool (default; ``workers`` processes, spawn context, which is safe with numba);
- ``workers=0``: one scenario after the other in this process (debugging);
- ``dask_local=N``: a ``dask.distributed.LocalCluster`` of N single-threaded worker processes;
- ``scheduler="tcp://host:port"``: an existing Dask cluster (its workers need the same trikedyn).

The main process keeps at most a few scenarios more in flight than there are workers, writes each result
to the store as it completes (:mod:`trikedyn.study.store`) and shows a progress bar on stderr.

Interruption: the first SIGINT (Ctrl-C) or SIGTERM stops submitting, lets the scenarios in flight finish
and be stored, then raises :class:`StudyInterrupted` (the CLI exits with code 130 and says how many
scenarios are stored); a second one abandons the scenarios in flight. A SIGKILL at any moment leaves the
store consistent. Re-running the same spec into the same folder resumes: stored scenarios are not
recomputed. Pool workers ignore SIGINT (the main process decides) and exit on their own when the main
process dies.

A scenario that fails (any exception: an invalid override, a simulation error) is stored as a row with
``status = "error"`` and its error text, and the study goes on. A worker that dies (crash, out of memory)
loses its scenario: it is not stored, the study finishes the others and raises :class:`StudyIncomplete`;
a re-run retries it.
"""

from __future__ import annotations

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
from concurrent.futures import FIRST_COMPLETED, CancelledError, Future
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError, TrikedynError
from .spec import SCENARIO_KEYS, StudySpec, expand, load_spec
from .store import RESULT_KEYS, StudyStore

__all__ = ["StudyIncomplete", "StudyInterrupted", "main", "run_scenario", "run_study", "study_command"]


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
def _one_line(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {' '.join(str(exc).split())}"


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
# executors
# ------------------------------------------------------------------------------------------------
def _watch_parent(parent: int) -> None:
    while True:
        time.sleep(0.5)
        if os.getppid() != parent:  # the main process died (SIGKILL): nobody will collect our work
            os._exit(1)


def _pool_worker_init() -> None:
    """Pool worker start-up: ignore SIGINT (the main process decides), exit when the main process dies."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=_watch_parent, args=(os.getppid(),), daemon=True).start()


class _Inline:
    """Scenarios one after the other in this process."""

    label = "in-process (serial)"
    window = 1

    def close(self):
        return None

    def submit(self, fn, *args, key=None) -> Future:
        fut: Future = Future()
        fut.set_result(fn(*args))
        return fut

    def wait(self, futures, timeout):
        return [f for f in futures if f.done()]

    def result(self, fut):
        return fut.result()

    def cancel(self, fut) -> bool:
        return False

    def abandon(self):
        return None


class _Pool:
    """A local ``ProcessPoolExecutor`` (spawn context)."""

    def __init__(self, workers: int):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        self.workers = workers
        self.label = f"process pool ({workers} worker{'s' if workers != 1 else ''})"
        self.window = workers + 1
        self._pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"),
                                         initializer=_pool_worker_init)

    def close(self):
        self._pool.shutdown(wait=True, cancel_futures=True)

    def submit(self, fn, *args, key=None):
        return self._pool.submit(fn, *args)

    def wait(self, futures, timeout):
        from concurrent.futures import wait

        return wait(futures, timeout=timeout, return_when=FIRST_COMPLETED).done

    def result(self, fut):
        return fut.result()

    def cancel(self, fut) -> bool:
        return fut.cancel()

    def abandon(self):
        """Stop the workers now (a second Ctrl-C): the scenarios in flight are lost, nothing is stored."""
        processes = list((getattr(self._pool, "_processes", None) or {}).values())
        self._pool.shutdown(wait=False, cancel_futures=True)
        for proc in processes:  # our own workers, by their handles
            if proc.is_alive():
                proc.terminate()
        for proc in processes:
            proc.join(timeout=2.0)


class _Dask:
    """A ``dask.distributed`` client: on a new ``LocalCluster`` or on an existing scheduler."""

    def __init__(self, n_workers: int | None = None, scheduler: str | None = None):
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError:
            raise InputError("needs dask: pip install 'trikedyn[dask]'",
                             where="--scheduler" if scheduler else "--dask-local") from None
        self._cluster = None
        if scheduler is None:
            self._cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                                         dashboard_address=None)
            self._client = Client(self._cluster)
            self.label = f"dask LocalCluster ({n_workers} worker{'s' if n_workers != 1 else ''})"
        else:
            try:
                self._client = Client(scheduler, timeout="20s")
            except (OSError, TimeoutError) as exc:
                raise InputError(f"cannot connect to the Dask scheduler: {_one_line(exc)}", where=scheduler) from None
            self.label = f"dask cluster at {scheduler}"
        threads = sum(self._client.nthreads().values())
        self.window = max(threads, 1) + 1

    def close(self):
        self._client.close()
        if self._cluster is not None:
            self._cluster.close()

    def submit(self, fn, *args, key=None):
        return self._client.submit(fn, *args, key=key, pure=False)

    def wait(self, futures, timeout):
        from dask.distributed import wait

        try:
            return wait(futures, timeout=timeout, return_when="FIRST_COMPLETED").done
        except TimeoutError:
            return [f for f in futures if f.done()]

    def result(self, fut):
        if fut.cancelled():
            raise CancelledError()
        return fut.result()

    def cancel(self, fut) -> bool:
        return False  # Dask does not say whether a task started: the few in flight are let finish

    def abandon(self):
        return None  # close() releases the tasks in flight


def _check_executor(workers, dask_local, scheduler) -> None:
    """At most one executor, and whole numbers of workers."""
    chosen = [name for name, v in (("workers", workers), ("dask_local", dask_local), ("scheduler", scheduler))
              if v is not None]
    if len(chosen) > 1:
        raise InputError(f"choose one executor, got {' and '.join(chosen)}", where="executor")
    for name, value, least in (("workers", workers, 0), ("dask_local", dask_local, 1)):
        if value is not None and (isinstance(value, bool) or int(value) != value or value < least):
            raise InputError(f"expected a whole number of workers >= {least}, got {value!r}", where=name)


def _executor(workers, dask_local, scheduler, n_todo: int):
    _check_executor(workers, dask_local, scheduler)
    if n_todo == 0:
        idle = _Inline()
        idle.label = "none (every scenario stored already)"
        return idle
    if scheduler is not None:
        return _Dask(scheduler=scheduler)
    if dask_local is not None:
        return _Dask(n_workers=int(dask_local))
    if workers is None:
        workers = os.cpu_count() or 1
    if workers == 0:
        return _Inline()
    return _Pool(min(int(workers), n_todo))


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


def _run(spec, out_dir, *, workers=None, dask_local=None, scheduler=None, progress=True) -> _Outcome:
    started = time.perf_counter()
    _check_executor(workers, dask_local, scheduler)
    spec = load_spec(spec)
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
        backend = _executor(workers, dask_local, scheduler, len(todo))
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
              dask_local: int | None = None, scheduler: str | None = None, progress: bool = True):
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

    Returns
    -------
    pandas.DataFrame
        The spec's stored scenarios in spec order (see :meth:`StudyStore.to_pandas`); identical, value for
        value, whichever executor ran them. Use a ``if __name__ == "__main__":`` guard in scripts: the
        process pool spawns fresh interpreters.

    Raises
    ------
    InputError
        Bad spec, two executors chosen, the folder held by another study or another run.
    StudyInterrupted
        SIGINT/SIGTERM: the finished scenarios are stored; re-run to resume.
    StudyIncomplete
        Workers died; the other scenarios are stored; re-run to retry the lost ones.
    """
    outcome = _run(spec, out_dir, workers=workers, dask_local=dask_local, scheduler=scheduler, progress=progress)
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


def study_command(spec_path, workers=None, dask_local=None, scheduler=None, out=None, as_json=False) -> dict:
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

    Returns
    -------
    dict
        The summary. On SIGINT/SIGTERM the summary (JSON) or a message (stderr) is printed and
        ``SystemExit(130)`` raised; on lost workers, ``SystemExit(1)``. ``InputError`` propagates (exit 2).
    """
    spec = load_spec(spec_path)
    out = Path(out) if out is not None else Path(f"study-{spec.name}")
    outcome = _run(spec, out, workers=workers, dask_local=dask_local, scheduler=scheduler, progress=True)
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
    """``python -m trikedyn.study.runner SPEC [--out DIR] [--workers N | --dask-local N | --scheduler URL]``."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m trikedyn.study.runner", description="Run or resume a study.")
    parser.add_argument("spec", help="built-in study name (paper) or a study .toml file")
    parser.add_argument("--out", default=None, help="output folder (default: study-<name>)")
    parser.add_argument("--workers", type=int, default=None, help="local processes (0: in this process)")
    parser.add_argument("--dask-local", type=int, default=None, help="workers of a new Dask LocalCluster")
    parser.add_argument("--scheduler", default=None, help="address of an existing Dask scheduler")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")
    args = parser.parse_args(argv)
    try:
        study_command(args.spec, args.workers, args.dask_local, args.scheduler, args.out, args.json)
    except InputError as exc:
        print(f"trikedyn: error: {exc}", file=sys.stderr)
        return 2
    except SystemExit as exc:
        return int(exc.code or 0)
    return 0


if __name__ == "__main__":
    from trikedyn.study.runner import main as _main  # the importable module, so workers unpickle its functions

    sys.exit(_main())
