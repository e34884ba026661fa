"""The one scheduling loop every design runs its evaluations through, on any executor of
:mod:`trikedyn.study.engine.executors`.

:func:`drive` keeps up to the executor's ``window`` calls in flight (``submit``), collects each as it
finishes (``wait(FIRST_COMPLETED)``, polling every 0.25 s) and hands its value to the caller at once (who
stores or logs it, so that a kill loses nothing finished). What it survives, and says back as *lost* calls
rather than raising:

- a call whose future fails (a worker died: ``BrokenProcessPool``; a Dask worker killed too often:
  ``KilledWorker``): that call is lost, the others go on;
- an executor that refuses new calls (a broken pool, a closed client: ``RuntimeError`` at ``submit``): the
  calls not yet submitted are lost, the ones in flight are still collected;
- a lost Dask scheduler (the executor's ``lost`` is set): the calls in flight never end, so they are lost at
  once, and the calls not submitted too (:class:`~trikedyn.study.engine.dask.SchedulerLost`).

Stopping is the caller's :class:`StopSignal` (or none: a KeyboardInterrupt then comes from Python's own
handler): its first SIGINT stops submitting and cancels the calls not started, the ones in flight are
collected; a second SIGINT or a SIGTERM sets ``abandon`` and the loop raises KeyboardInterrupt at its next
turn. On a KeyboardInterrupt the executor is shut down at once (``wait=False, cancel_futures=True``: a
pool's workers are stopped) and the interrupt goes on; on any other exception, once the calls in flight have
ended. On a normal return the executor is left open (the caller may drive it again: an optimiser's next
generation).
"""

from __future__ import annotations

import signal
import threading
from collections import deque
from collections.abc import Callable, Hashable, Iterable
from concurrent.futures import FIRST_COMPLETED, CancelledError, Executor, wait
from typing import NamedTuple

__all__ = ["POLL_S", "Lost", "StopSignal", "drive", "one_line"]


def one_line(exc: BaseException) -> str:
    """An exception as one line: ``TypeName: message`` with the whitespace collapsed.

    Parameters
    ----------
    exc : BaseException
        The exception.

    Returns
    -------
    str
        The line.
    """
    return f"{type(exc).__name__}: {' '.join(str(exc).split())}"


class Lost(NamedTuple):
    """A call :func:`drive` could not finish: its ``key`` and ``args``, ``why`` (one line) and whether it was
    ``submitted`` (in flight when its worker, pool or scheduler was lost) or never sent."""

    key: Hashable
    args: tuple
    why: str
    submitted: bool

POLL_S = 0.25
"""How often the loop looks at its stop flag while it waits for calls to finish [s]."""


class StopSignal:
    """First SIGINT: ask to stop after the calls in flight; a second one, or SIGTERM: abandon them.

    :attr:`requested` is the name of the last signal seen (None: none); :attr:`abandon` is set by an abandoning
    signal, and the loop, which polls every :data:`POLL_S`, raises KeyboardInterrupt at its next turn. Only with
    ``inline`` (the calls run in this thread, the loop not polling while one runs) does the handler raise
    KeyboardInterrupt itself: raised from a handler at any point of the main thread, it can land in the middle
    of an import while another thread imports (the table's libraries load in a thread while the workers
    compute) and leave both waiting on each other's import lock for ever.

    Parameters
    ----------
    note : callable, optional
        ``note(text)``: told when the first SIGINT asks to stop.
    inline : bool
        The calls run in this thread (an in-process executor).
    """

    def __init__(self, note=None, inline: bool = False):
        self.requested: str | None = None
        self.abandon = False
        self._previous: dict = {}
        self._note = note
        self._inline = inline

    def _handler(self, signum, frame):
        again, self.requested = self.requested is not None, signal.Signals(signum).name
        if again or signum != signal.SIGINT:
            self.abandon = True
            if self._inline:
                raise KeyboardInterrupt
            return
        if self._note is not None:
            self._note(f"{self.requested}: stopping after the scenarios in flight (again to abandon them)")

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous[sig] = signal.signal(sig, self._handler)
        return self

    def __exit__(self, *exc):
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)
        self._previous.clear()


def drive(executor: Executor, fn: Callable, tasks: Iterable[tuple[Hashable, tuple]], on_result: Callable, *,
          stop: StopSignal | None = None) -> list[Lost]:
    """Call ``fn(*args)`` for each ``(key, args)`` of ``tasks`` on ``executor``: ``on_result(key, value)`` in
    this thread as each call finishes; the calls lost (see the module's notes) come back.

    Parameters
    ----------
    executor : concurrent.futures.Executor
        One of :mod:`trikedyn.study.engine.executors` (its ``window``: the calls kept in flight; ``lost``: a
        Dask scheduler's loss).
    fn : callable
        The function (picklable for a process pool or Dask).
    tasks : iterable of (key, args)
        The calls, submitted in this order.
    on_result : callable
        ``on_result(key, value)``.
    stop : StopSignal, optional
        The stop flag (entered by the caller).

    Returns
    -------
    list of Lost
        The calls lost (a dead worker, a broken executor, a lost scheduler). Calls
        cancelled by a stop request are neither done nor lost.

    Raises
    ------
    KeyboardInterrupt
        An abandoning signal (:attr:`StopSignal.abandon`), or Ctrl-C without a :class:`StopSignal`; the
        executor is shut down at once.
    """
    todo = deque(tasks)
    running: dict = {}
    lost: list[Lost] = []
    window = max(int(getattr(executor, "window", 1)), 1)
    try:
        while todo or running:
            if stop is not None and stop.abandon:  # raised here, where the caller can take it
                raise KeyboardInterrupt
            if stop is not None and stop.requested:
                todo.clear()
                for fut in list(running):
                    if fut.cancel():  # never started: nothing to keep
                        running.pop(fut)
            while todo and len(running) < window:
                key, args = todo.popleft()
                try:
                    fut = executor.submit(fn, *args)
                except RuntimeError as exc:  # BrokenProcessPool, a closed client, SchedulerLost
                    lost.append(Lost(key, args, one_line(exc), False))
                    lost.extend(Lost(k, a, f"not run: {one_line(exc)}", False) for k, a in todo)
                    todo.clear()
                    break
                running[fut] = (key, args)
            if running:
                finished, _ = wait(list(running), timeout=POLL_S, return_when=FIRST_COMPLETED)
                for fut in finished:
                    key, args = running.pop(fut)
                    try:
                        value = fut.result()
                    except CancelledError:
                        continue
                    except Exception as exc:  # the worker died, not the call (a call's own failure is a value)
                        lost.append(Lost(key, args, one_line(exc), True))
                        continue
                    on_result(key, value)
            why = getattr(executor, "lost", None)
            if why:  # a lost scheduler: nothing in flight ends, nothing more can be submitted
                lost.extend(Lost(k, a, why, True) for k, a in running.values())
                lost.extend(Lost(k, a, f"not run: {why}", False) for k, a in todo)
                running.clear()
                todo.clear()
    except KeyboardInterrupt:  # an abandoning signal: the calls in flight are dropped
        executor.shutdown(wait=False, cancel_futures=True)
        raise
    except BaseException:
        if running:
            executor.shutdown(wait=True, cancel_futures=True)
        raise
    return lost
