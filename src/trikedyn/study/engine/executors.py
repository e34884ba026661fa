"""The executors a study runs on, each a :class:`concurrent.futures.Executor`.

- :class:`InlineExecutor`: one call after the other in this process, at ``submit`` (``workers=0``:
  debugging; a study whose scenarios are all stored);
- :class:`ProcessPool`: a :class:`~concurrent.futures.ProcessPoolExecutor` whose workers ignore SIGINT (the
  main process decides) and exit on their own when the main process dies;
  ``shutdown(wait=False, cancel_futures=True)`` also stops the workers in flight (a second Ctrl-C). Its
  workers fork from a fork server that imported the simulation once (:data:`PRELOAD`), where the platform
  has one (Linux, macOS), so that a worker starts in milliseconds, not the second an import takes; else
  they are spawned. Neither forks a process that has threads (numba's LLVM, the main's import thread);
- :class:`~trikedyn.study.engine.dask.DaskExecutor` (in :mod:`trikedyn.study.engine.dask`): calls submitted
  through a ``dask.distributed`` client, on a new ``LocalCluster`` (``dask_local=N``) or on an existing
  scheduler (``scheduler="tcp://host:port"``); a lost scheduler fails the calls in flight, and every later
  ``submit``, with :class:`~trikedyn.study.engine.dask.SchedulerLost`.

Callers use the standard API only (``submit``, :func:`concurrent.futures.wait` with ``FIRST_COMPLETED``,
``Future.cancel``, ``shutdown``); each executor also says ``label`` (for summaries and the store's ``runs``
table) and ``window`` (how many calls to keep in flight: enough to keep every worker busy). A future that
has started cannot be cancelled: ``cancel()`` returns False and the call finishes. Dask does not tell the
client when a task starts, so a Dask future counts as started from its submission.

:func:`make_executor` picks one from a run's options; :func:`check_executor` checks the options before
anything is written.
"""

from __future__ import annotations

import os
import signal
import threading
import time
from concurrent.futures import Executor, Future, ProcessPoolExecutor

from ...errors import InputError
from .loop import one_line  # noqa: F401  (re-exported: where the callers find it)

__all__ = ["PRELOAD", "InlineExecutor", "ProcessPool", "check_executor",
           "make_executor", "one_line", "start_pool_server", "wait_for_exit", "worker_count"]

PRELOAD = ("trikedyn.analysis.threshold", "trikedyn.study.designs.runner", "trikedyn.study.metrics",
           "trikedyn.study.engine.warm")
"""What the fork server imports before it forks the pool's workers: the simulation (numba, scipy, the model),
the study's worker functions, and numba's compiler contexts set up (:mod:`trikedyn.study.engine.warm`)."""


def wait_for_exit(pid: int, timeout_s: float | None = None) -> bool:
    """Return when process ``pid`` has ended, or after ``timeout_s``.

    A spawned worker's parent is the main process: orphaned, it is adopted by another. A worker from the
    fork server is the server's child, and the server outlives the main process while a worker does (each
    worker holds the server's "alive" pipe): it waits on a pidfd of the main process (Linux), else polls its
    pid (every 0.5 s, or 0.02 s with a timeout).

    Parameters
    ----------
    pid : int
        The process.
    timeout_s : float, optional
        The longest wait [s]; None: until it ends.

    Returns
    -------
    bool
        True once it has ended; False when it still runs after ``timeout_s``.
    """
    deadline = None if timeout_s is None else time.monotonic() + timeout_s
    poll = 0.5 if timeout_s is None else 0.02

    def another_poll() -> bool:
        """Sleep one poll; False when the deadline has passed instead."""
        if deadline is not None and time.monotonic() >= deadline:
            return False
        time.sleep(poll)
        return True

    if os.getppid() == pid:
        while os.getppid() == pid:
            if not another_poll():
                return False
        return True
    try:
        handle = os.pidfd_open(pid)
    except ProcessLookupError:
        return True
    except (AttributeError, OSError):  # no pidfd (macOS, an old kernel)
        while True:
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                return True
            except PermissionError:  # alive, or its pid taken by another user's process
                pass
            if not another_poll():
                return False
    import select

    try:
        ready, _, _ = select.select([handle], [], [], timeout_s)  # readable once the process has ended
    finally:
        os.close(handle)
    return bool(ready)


def _watch_main(main_pid: int) -> None:
    wait_for_exit(main_pid)
    os._exit(1)  # the main process died (SIGKILL): nobody will collect our work


def _pool_worker_init(main_pid: int) -> None:
    """Pool worker start-up: ignore SIGINT (the main process decides), exit when the main process dies."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=_watch_main, args=(main_pid,), daemon=True).start()


class InlineExecutor(Executor):
    """Calls run at ``submit``, one after the other, in this process; the future comes back done."""

    window = 1

    def __init__(self, label: str = "in-process (serial)"):
        self.label = label
        self._shutdown = False

    def submit(self, fn, /, *args, **kwargs) -> Future:
        """Call ``fn(*args, **kwargs)`` now, in this process.

        Parameters
        ----------
        fn : callable
            The function.
        *args, **kwargs
            Its arguments.

        Returns
        -------
        concurrent.futures.Future
            A finished future (its result or exception).

        Raises
        ------
        RuntimeError
            After shutdown.
        """
        if self._shutdown:
            raise RuntimeError("cannot schedule new futures after shutdown")
        fut: Future = Future()
        fut.set_running_or_notify_cancel()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # noqa: BLE001 - the future carries it, as a pool's would
            if isinstance(exc, KeyboardInterrupt | SystemExit):
                raise
            fut.set_exception(exc)
        return fut

    def shutdown(self, wait=True, *, cancel_futures=False):
        """Refuse further calls.

        Parameters
        ----------
        wait : bool
            Wait for the calls in flight.
        cancel_futures : bool
            Cancel the calls not started. (nothing is ever in flight.)
        """
        self._shutdown = True


_fork_server_failed = False


def pool_context():
    """The start method of the pool's workers: the fork server where the platform has one, started now if it
    is not running (it imports :data:`PRELOAD`, about a second, in its own process); else, or when it cannot
    start (no socket for it in the temporary folder), spawn."""
    global _fork_server_failed
    import multiprocessing

    if not _fork_server_failed and "forkserver" in multiprocessing.get_all_start_methods():
        from multiprocessing import forkserver

        context = multiprocessing.get_context("forkserver")
        context.set_forkserver_preload(list(PRELOAD))  # read when the server starts
        try:
            forkserver.ensure_running()
            return context
        except OSError:
            _fork_server_failed = True
    return multiprocessing.get_context("spawn")


def _chooses_pool(workers, dask_local, scheduler) -> bool:
    """Whether a run's options ask for the local process pool (when it has anything to do)."""
    return workers != 0 and dask_local is None and scheduler is None


def start_pool_server(workers=None, dask_local=None, scheduler=None) -> None:
    """Start the pool's fork server now if the run's options ask for the pool (:func:`make_executor`), so
    that its imports overlap the caller's set-up (reading the spec and the vehicle) rather than follow the
    pool's first call.

    Parameters
    ----------
    workers : int, optional
        Worker processes (all cores when None; 0: in this process).
    dask_local : int, optional
        Workers of a local Dask cluster.
    scheduler : str, optional
        Address of a Dask scheduler.
    """
    if _chooses_pool(workers, dask_local, scheduler):
        pool_context()


class ProcessPool(ProcessPoolExecutor):
    """A local process pool: workers from the fork server (or spawned), that ignore SIGINT and die with the
    main process."""

    def __init__(self, workers: int):
        super().__init__(max_workers=workers, mp_context=pool_context(), initializer=_pool_worker_init,
                         initargs=(os.getpid(),))
        self.workers = workers
        self.label = f"process pool ({workers} worker{'s' if workers != 1 else ''})"
        self.window = workers + 1

    def shutdown(self, wait=True, *, cancel_futures=False):
        """As :meth:`ProcessPoolExecutor.shutdown`; ``wait=False, cancel_futures=True`` also terminates the
        workers (the calls in flight are lost): what a second Ctrl-C asks.

        Parameters
        ----------
        wait : bool
            Wait for the calls in flight.
        cancel_futures : bool
            Cancel the calls not started.
        """
        processes = list((getattr(self, "_processes", None) or {}).values())
        super().shutdown(wait=wait, cancel_futures=cancel_futures)
        if not wait and cancel_futures:
            for proc in processes:  # our own workers, by their handles
                if proc.is_alive():
                    proc.terminate()
            for proc in processes:
                proc.join(timeout=2.0)


def check_executor(workers, dask_local, scheduler) -> None:
    """At most one executor, and whole numbers of workers.

    Parameters
    ----------
    workers : int, optional
        Worker processes (0: in this process).
    dask_local : int, optional
        Workers of a local Dask cluster.
    scheduler : str, optional
        Address of a Dask scheduler.

    Raises
    ------
    InputError
        Two executors chosen, or a count that is not a whole number in range.
    """
    chosen = [name for name, v in (("workers", workers), ("dask_local", dask_local), ("scheduler", scheduler))
              if v is not None]
    if len(chosen) > 1:
        raise InputError(f"choose one executor, got {' and '.join(chosen)}", where="executor")
    for name, value, least in (("workers", workers, 0), ("dask_local", dask_local, 1)):
        if value is not None and (isinstance(value, bool) or int(value) != value or value < least):
            raise InputError(f"expected a whole number of workers >= {least}, got {value!r}", where=name)


def worker_count(workers, dask_local, scheduler) -> int | None:
    """How many workers a run's options ask for, as a run's summary records it: ``workers`` (all cores when
    None), or the local Dask cluster's; None on a scheduler (its workers may come and go).

    Parameters
    ----------
    workers : int, optional
        Worker processes (all cores when None; 0: in this process).
    dask_local : int, optional
        Workers of a local Dask cluster.
    scheduler : str, optional
        Address of a Dask scheduler.

    Returns
    -------
    int or None
        The count.
    """
    if scheduler is not None:
        return None
    if dask_local is not None:
        return int(dask_local)
    return int(workers) if workers is not None else (os.cpu_count() or 1)


NOTHING_TO_DO = "no executor: every scenario was stored already"
"""The executor label of a run that had nothing to compute."""


def make_executor(workers, dask_local, scheduler, n_todo: int) -> Executor:
    """The executor for a run's options (at most one of ``workers``, ``dask_local``, ``scheduler``) and
    ``n_todo`` calls: in this process when there is nothing to do or ``workers=0``; a :class:`ProcessPool` of
    ``workers`` (all cores by default, no more than ``n_todo``); or a :class:`DaskExecutor`.

    Parameters
    ----------
    workers : int, optional
        Worker processes (all cores when None; 0: in this process).
    dask_local : int, optional
        Workers of a local Dask cluster.
    scheduler : str, optional
        Address of a Dask scheduler.
    n_todo : int
        Calls to make.

    Returns
    -------
    concurrent.futures.Executor
        The executor.
    """
    check_executor(workers, dask_local, scheduler)
    if n_todo == 0:
        return InlineExecutor(NOTHING_TO_DO)
    if not _chooses_pool(workers, dask_local, scheduler):
        from .dask import DaskExecutor

        if scheduler is not None:
            return DaskExecutor(scheduler=scheduler)
        if dask_local is not None:
            return DaskExecutor(n_workers=int(dask_local))
        return InlineExecutor()
    return ProcessPool(min(int(workers or os.cpu_count() or 1), n_todo))
