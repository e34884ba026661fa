"""Many independent calls on one executor that survives dead workers: how the sampled designs (sensitivity
and uncertainty samples, the loading chart's cells, the optimiser's generations) run on the engine.

:class:`ResilientPool` runs its calls through the one scheduling loop (:func:`~trikedyn.study.engine.loop.drive`)
on the executor a run's options choose (:func:`~trikedyn.study.engine.executors.make_executor`: in this
process, a process pool, a local Dask cluster or a Dask scheduler). A worker can die (a crash, or out of
memory): the calls it had in flight then go to a new executor; a call on which workers die twice is given up
(the caller says how it counts); after :data:`MAX_RESTARTS` deaths the run stops with
:class:`WorkersKeptDying`, naming the calls not done. A lost Dask scheduler is not retried: the run stops
with :class:`SchedulerGone` (the caller keeps what finished, and a re-run with ``--resume`` goes on).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Hashable, Iterable

from .executors import make_executor, start_pool_server
from .loop import StopSignal, drive

__all__ = ["MAX_RESTARTS", "ExecutorLost", "ResilientPool", "SchedulerGone", "WorkersKeptDying"]

MAX_RESTARTS = 3
"""New executors after a worker died, before a run gives up."""


class ExecutorLost(Exception):
    """The run's executor was lost for good; ``remaining`` are the keys of the calls not done."""

    def __init__(self, message: str, remaining: list):
        super().__init__(message)
        self.remaining = remaining


class WorkersKeptDying(ExecutorLost):
    """Workers died more than :data:`MAX_RESTARTS` times; ``remaining`` are the keys of the calls not done."""

    def __init__(self, restarts: int, remaining: list):
        super().__init__(f"worker processes died {restarts} times (a crash, or out of memory)", remaining)
        self.restarts = restarts


class SchedulerGone(ExecutorLost):
    """The Dask scheduler was lost (:class:`~trikedyn.study.engine.dask.SchedulerLost`); ``remaining`` are
    the keys of the calls not done."""


class ResilientPool:
    """One executor for any number of :meth:`run` calls (replaced after a worker's death); :meth:`close` it
    when done.

    Parameters
    ----------
    workers : int, optional
        Processes of a local pool (all cores when None; 0: in this process).
    dask_local : int, optional
        Workers of a new local Dask cluster instead.
    scheduler : str, optional
        Address of a Dask scheduler instead (``tcp://host:port``).
    stop : StopSignal, optional
        The stop flag the loop polls (else a Ctrl-C is Python's KeyboardInterrupt, and abandons the calls).
    """

    def __init__(self, workers: int | None, dask_local: int | None = None, scheduler: str | None = None,
                 stop: StopSignal | None = None):
        self.workers, self.dask_local, self.scheduler, self.stop = workers, dask_local, scheduler, stop
        self.executor = None
        self.restarts = 0
        start_pool_server(workers, dask_local, scheduler)  # its imports overlap the caller's set-up

    @property
    def label(self) -> str | None:
        """The current executor's label (None before the first call)."""
        return None if self.executor is None else self.executor.label

    def run(self, fn: Callable, tasks: Iterable[tuple[Hashable, tuple]], on_result: Callable,
            on_death: Callable) -> None:
        """``fn(*args)`` for each ``(key, args)`` of ``tasks``: ``on_result(key, value)`` as each finishes,
        ``on_death(key)`` for a call on which workers died twice.

        Parameters
        ----------
        fn : callable
            The function, picklable.
        tasks : iterable of (key, args)
            The calls.
        on_result : callable
            ``on_result(key, value)``.
        on_death : callable
            ``on_death(key)``.

        Raises
        ------
        WorkersKeptDying
            After more than :data:`MAX_RESTARTS` deaths in this pool's life.
        SchedulerGone
            The Dask scheduler was lost.
        """
        todo = deque(tasks)
        deaths: dict = {}
        while todo:
            if self.executor is None:
                self.executor = make_executor(self.workers, self.dask_local, self.scheduler, len(todo))
            try:
                lost = drive(self.executor, fn, list(todo), on_result, stop=self.stop)
            except BaseException:
                self.close(abandon=True)
                raise
            todo.clear()
            if not lost:
                break
            gone = getattr(self.executor, "lost", None)
            self.close(abandon=True)
            if gone:
                raise SchedulerGone(gone, [item.key for item in lost])
            self.restarts += 1
            for item in [*(i for i in lost if i.submitted), *(i for i in lost if not i.submitted)]:
                if item.submitted:  # in flight when its worker died
                    deaths[item.key] = deaths.get(item.key, 0) + 1
                    if deaths[item.key] >= 2:
                        on_death(item.key)
                        continue
                todo.append((item.key, item.args))
            if self.restarts > MAX_RESTARTS:
                raise WorkersKeptDying(self.restarts, [key for key, _ in todo])

    def close(self, abandon: bool = False) -> None:
        """Shut the executor down; ``abandon``: now, the calls in flight lost (a dead worker, Ctrl-C).

        Parameters
        ----------
        abandon : bool
            Shut down now, losing the calls in flight.
        """
        if self.executor is not None:
            executor, self.executor = self.executor, None
            executor.shutdown(wait=not abandon, cancel_futures=True)
