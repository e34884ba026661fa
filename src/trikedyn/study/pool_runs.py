"""Many independent calls on a process pool that survives dead workers: the sampled studies
(:func:`~trikedyn.study.sample_runs.run_samples`), the loading chart and the layout optimiser.

A worker can die (a crash, or out of memory). The calls it had in flight then go to a new pool; a call on
which workers die twice is given up (the caller says how it counts); after :data:`MAX_RESTARTS` deaths the
run stops with :class:`WorkersKeptDying`, naming the calls not done. The executor is one of
:mod:`trikedyn.study.executors` (``workers=0``: in this process).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Hashable, Iterable
from concurrent.futures import FIRST_COMPLETED, wait
from concurrent.futures.process import BrokenProcessPool

__all__ = ["MAX_RESTARTS", "ResilientPool", "WorkersKeptDying"]

MAX_RESTARTS = 3
"""New process pools after a worker died, before a run gives up."""


class WorkersKeptDying(Exception):
    """Workers died more than :data:`MAX_RESTARTS` times; ``remaining`` are the keys of the calls not done."""

    def __init__(self, restarts: int, remaining: list):
        super().__init__(f"worker processes died {restarts} times (a crash, or out of memory)")
        self.restarts, self.remaining = restarts, remaining


class ResilientPool:
    """One executor of ``workers`` processes for any number of :meth:`run` calls (replaced after a death);
    :meth:`close` it when done."""

    def __init__(self, workers: int | None):
        from .executors import start_pool_server

        self.workers = workers
        self.executor = None
        self.restarts = 0
        start_pool_server(workers)  # its imports overlap the caller's set-up

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
        """
        from .executors import make_executor

        todo = deque(tasks)
        deaths: dict = {}
        while todo:
            if self.executor is None:
                self.executor = make_executor(self.workers, None, None, len(todo))
            executor, pending = self.executor, {}
            try:
                while todo or pending:
                    while todo and len(pending) < executor.window:
                        key, args = todo.popleft()
                        pending[executor.submit(fn, *args)] = (key, args)
                    for fut in wait(list(pending), timeout=1.0, return_when=FIRST_COMPLETED).done:
                        value = fut.result()  # a dead worker raises here, its call still pending
                        on_result(pending.pop(fut)[0], value)
            except BrokenProcessPool:
                self.close(abandon=True)
                self.restarts += 1
                for key, args in reversed(list(pending.values())):
                    deaths[key] = deaths.get(key, 0) + 1
                    if deaths[key] >= 2:
                        on_death(key)
                    else:
                        todo.appendleft((key, args))
                if self.restarts > MAX_RESTARTS:
                    raise WorkersKeptDying(self.restarts, [key for key, _ in todo]) from None
            except BaseException:
                self.close(abandon=True)
                raise

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
