"""Imported by the pool's fork server (:data:`~trikedyn.study.engine.executors.PRELOAD`): numba's compiler
context set up once, in the server, for every worker it forks.

A process's first compiled call, even one loaded from numba's cache, first builds numba's typing and target
contexts (their registries of types and functions): about 0.27 s on the reference machine, which each worker
used to pay at its first run. Calling one small cached function here builds them in the server, and a forked
worker inherits them. The call compiles nothing new after the first time (``cache=True``), and the server
still starts no thread.

Then the server's heap (the simulation's modules and numba's contexts: about 145 000 objects the garbage
collector tracks) goes to the collector's permanent generation (:func:`gc.freeze`), as Python's documentation
advises before forking: a worker's collections never traverse it, nor touch (and copy) its pages. In one
process, the 50 searches of the paper's study with the heap frozen after their set-up took 2.42-2.73 ms of
Python a run against 2.59-2.89 (three rounds, alternated).

And the server and its workers stay quiet when their client vanishes (:class:`QuietWhenTheClientVanishes`): a
main process interrupted (Ctrl-C, SIGTERM) while it asks the server for a worker leaves the server reading an
empty socket, or a worker starting up without the semaphores the main process unlinked as it exited, and
:mod:`multiprocessing.forkserver` lets that ``EOFError`` end the server (or that ``FileNotFoundError`` the
worker) with a traceback on the terminal the command shares with them, after the command's own one line.
"""

from __future__ import annotations

import gc
import os
import sys
import traceback

from ..._jit import jit

__all__ = ["QuietWhenTheClientVanishes", "in_the_fork_server", "numba_ready"]


@jit
def _one_more(x):
    """``x + 1``: the smallest call that sets up numba's contexts."""
    return x + 1.0


def numba_ready() -> bool:
    """Set up numba's typing and target contexts in this process (a cached call).

    Returns
    -------
    bool
        True once the contexts are built.
    """
    return _one_more(1.0) == 2.0


class QuietWhenTheClientVanishes:
    """A :data:`sys.excepthook` that prints nothing for an exception that comes of the client (the main process)
    vanishing, and a traceback for any other, as Python's own hook.

    The client's end gone shows as ``EOFError`` or a ``ConnectionError``, or, in a worker still starting, as
    whatever its start-up met of the client's resources (a semaphore it unlinked as it exited: a
    ``FileNotFoundError``): any exception while the client is gone, or is gone within ``wait_s``, is quiet.

    Parameters
    ----------
    previous : callable
        The hook it stands in front of.
    client : int, optional
        The client's process id (None: only the exception's type says).
    wait_s : float
        How long an exception waits for the client to end before it is printed [s].
    """

    def __init__(self, previous=sys.__excepthook__, client: int | None = None, wait_s: float = 0.5):
        self.previous = previous
        self.client = client
        self.wait_s = wait_s

    def __call__(self, kind, value, tb):
        """Handle an uncaught exception: quiet for a vanished client, else ``previous``'s traceback."""
        if isinstance(kind, type) and issubclass(kind, (EOFError, ConnectionError)) or self.client_gone():
            return
        try:
            self.previous(kind, value, tb)
        except Exception:  # noqa: BLE001 - a hook must not raise
            traceback.print_exception(kind, value, tb)

    def client_gone(self) -> bool:
        """Whether the client has ended, or ends within ``wait_s``
        (:func:`~trikedyn.study.engine.executors.wait_for_exit`).

        Returns
        -------
        bool
            False for no client, or one still running after ``wait_s``.
        """
        from .executors import wait_for_exit

        return self.client is not None and wait_for_exit(self.client, self.wait_s)


def in_the_fork_server() -> bool:
    """Whether this code runs in a fork server's preload (:func:`multiprocessing.forkserver.main` on the stack).

    Returns
    -------
    bool
        True in the pool's fork server (and in the workers it forks, from their start).
    """
    from multiprocessing import forkserver

    frame = sys._getframe()
    while frame is not None:
        if frame.f_code is forkserver.main.__code__:
            return True
        frame = frame.f_back
    return False


numba_ready()
if in_the_fork_server():
    sys.excepthook = QuietWhenTheClientVanishes(sys.excepthook, client=os.getppid())  # the main process
gc.freeze()
