"""The executors a study runs on: in this process, a local process pool, or a Dask cluster.

Each offers the same small interface to :mod:`trikedyn.study.runner`'s loop: ``label`` (for the summary and
the ``runs`` table), ``window`` (how many scenarios to keep in flight), ``submit(fn, *args, key=)`` ->
future, ``wait(futures, timeout)`` -> the done ones, ``result(fut)``, ``cancel(fut)`` (True if it never
started), ``abandon()`` (a second Ctrl-C: stop now) and ``close()``. :func:`make_executor` picks one from
the run's options; :func:`check_executor` checks those options before anything is written.

Pool workers are spawned (safe with numba), ignore SIGINT (the main process decides) and exit on their own
when the main process dies.
"""

from __future__ import annotations

import os
import signal
import threading
import time
from concurrent.futures import FIRST_COMPLETED, CancelledError, Future

from ..errors import InputError

__all__ = ["check_executor", "make_executor", "one_line"]


def one_line(exc: BaseException) -> str:
    """An exception as one line: ``TypeName: message`` with the whitespace collapsed."""
    return f"{type(exc).__name__}: {' '.join(str(exc).split())}"


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
                raise InputError(f"cannot connect to the Dask scheduler: {one_line(exc)}", where=scheduler) from None
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


def check_executor(workers, dask_local, scheduler) -> None:
    """At most one executor, and whole numbers of workers."""
    chosen = [name for name, v in (("workers", workers), ("dask_local", dask_local), ("scheduler", scheduler))
              if v is not None]
    if len(chosen) > 1:
        raise InputError(f"choose one executor, got {' and '.join(chosen)}", where="executor")
    for name, value, least in (("workers", workers, 0), ("dask_local", dask_local, 1)):
        if value is not None and (isinstance(value, bool) or int(value) != value or value < least):
            raise InputError(f"expected a whole number of workers >= {least}, got {value!r}", where=name)


def make_executor(workers, dask_local, scheduler, n_todo: int):
    check_executor(workers, dask_local, scheduler)
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
