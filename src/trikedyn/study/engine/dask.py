"""The Dask executor (:class:`DaskExecutor`): calls submitted through a ``dask.distributed`` client, on a new
``LocalCluster`` (``dask_local=N``) or on an existing scheduler (``scheduler="tcp://host:port"``); shutting it
down closes the client (and the cluster it started). A lost scheduler (killed, its host gone) cancels every task
the client had: each call in flight then fails with :class:`SchedulerLost`, and so does every later ``submit``,
at once, so that the caller stops and says so instead of waiting for futures that never end (the client's
own ``get_executor()`` left them running forever, and printed a traceback for each).

:func:`~trikedyn.study.engine.executors.make_executor` makes one from a run's options; ``dask`` is imported only
when one is made.
"""

from __future__ import annotations

import logging
import threading
from concurrent.futures import Executor, Future, InvalidStateError

from ...errors import InputError
from .loop import one_line

__all__ = ["RESULT_TIMEOUT_S", "DaskExecutor", "SchedulerLost"]


RESULT_TIMEOUT_S = 60.0
"""Longest wait for a finished task's value to reach the client [s] (a scheduler lost meanwhile)."""


class SchedulerLost(RuntimeError):
    """The Dask scheduler was lost: the calls in flight on it are not done, and no more can be submitted."""


_DASK_LOGGERS = ("distributed.client", "distributed.batched", "distributed.core", "tornado.application")
"""Loggers that report a lost scheduler again and again (reconnection attempts, a line per task): quiet once
:class:`DaskExecutor` has said it in one line."""


class DaskExecutor(Executor):
    """Calls on a ``dask.distributed`` client, on a new ``LocalCluster`` of ``n_workers`` single-threaded
    processes or on the scheduler at ``scheduler``; ``shutdown`` closes the client and the cluster it started.

    Each call is a task (``Client.submit``, ``pure=False``) whose :class:`~concurrent.futures.Future` counts as
    started from its submission and is settled from the task's own callback: its value, its exception, or
    :class:`SchedulerLost` when the task was cancelled under us (the client cancels every task when it loses
    the scheduler). From then on :meth:`submit` raises :class:`SchedulerLost`, and the client's reports of
    the loss (reconnection attempts, one line per task) are quieted until :meth:`shutdown`.
    """

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
        self.address = f"at {scheduler}" if scheduler else "of the local cluster"
        self.window = max(sum(self._client.nthreads().values()), 1) + 1
        self.lost: str | None = None
        self._quieted: dict = {}
        self._pending: set = set()
        self._lock = threading.Lock()
        self._closed = False

    def _lose(self) -> str:
        """Note the scheduler as lost (once) and quiet the client's own reports of it; the reason."""
        with self._lock:
            if self.lost is None:
                self.lost = f"the Dask scheduler {self.address} was lost"
                for name in _DASK_LOGGERS:
                    log = logging.getLogger(name)
                    self._quieted[name] = log.level
                    log.setLevel(logging.CRITICAL + 1)
            return self.lost

    def _settle(self, fut: Future, task) -> None:
        """Give ``fut`` the outcome of the Dask ``task`` (called in the client's callback thread)."""
        try:
            if task.status == "finished":
                outcome, value = "result", task.result(timeout=RESULT_TIMEOUT_S)
            elif task.status == "cancelled":
                outcome, value = "exception", SchedulerLost(self._lose())
            else:
                outcome, value = "exception", task.exception()
        except (OSError, TimeoutError):  # the value could not be fetched: the connection is gone
            outcome, value = "exception", SchedulerLost(self._lose())
        except Exception as exc:  # noqa: BLE001 - fetching the outcome failed: the call failed
            outcome, value = "exception", exc
        try:
            fut.set_result(value) if outcome == "result" else fut.set_exception(value)
        except InvalidStateError:  # settled already
            pass
        self._pending.discard(fut)

    def submit(self, fn, /, *args, **kwargs) -> Future:
        """Submit ``fn(*args, **kwargs)`` as a task; a started :class:`~concurrent.futures.Future`.

        Parameters
        ----------
        fn : callable
            The function (picklable).
        *args, **kwargs
            Its arguments.

        Returns
        -------
        concurrent.futures.Future
            Its future, counted as started.

        Raises
        ------
        SchedulerLost
            The scheduler was lost (a task came back cancelled, or the client is not connected).
        RuntimeError
            After :meth:`shutdown`.
        """
        if self._closed:
            raise RuntimeError("cannot schedule new futures after shutdown")
        if self.lost is None and self._client.status != "running":
            self._lose()
        if self.lost is not None:
            raise SchedulerLost(self.lost)
        fut: Future = Future()
        fut.set_running_or_notify_cancel()  # Dask does not say when a task starts: count it as started
        self._pending.add(fut)
        task = self._client.submit(fn, *args, pure=False, **kwargs)
        task.add_done_callback(lambda done: self._settle(fut, done))
        return fut

    def shutdown(self, wait=True, *, cancel_futures=False):
        """Close the client (and the cluster it started); ``wait`` (without ``cancel_futures``): once the tasks
        submitted are done. After a lost scheduler the client is closed without waiting for it.

        Parameters
        ----------
        wait : bool
            Wait for the tasks submitted (unless the scheduler is lost).
        cancel_futures : bool
            Do not wait for them.
        """
        if self._closed:
            return
        self._closed = True
        try:
            if wait and not cancel_futures and self.lost is None:
                from concurrent.futures import wait as wait_calls

                wait_calls(list(self._pending))
            if self.lost is not None:
                self._client.close(timeout=5)
            else:
                self._client.close()
            if self._cluster is not None:
                self._cluster.close()
        except (OSError, TimeoutError, RuntimeError):
            if self.lost is None:
                raise
        finally:
            for name, level in self._quieted.items():
                logging.getLogger(name).setLevel(level)
