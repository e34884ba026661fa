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

And the server stays quiet when its client vanishes (:class:`QuietWhenTheClientVanishes`): a main process
interrupted (Ctrl-C, SIGTERM) while it asks the server for a worker leaves the server reading an empty socket,
and :mod:`multiprocessing.forkserver` lets that ``EOFError`` end the server with a traceback on the terminal
the command shares with it, after the command's own one line.
"""

from __future__ import annotations

import gc
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
    """A :data:`sys.excepthook` that prints nothing for an exception that says the other end of a connection
    is gone (``EOFError``, ``ConnectionError``), and a traceback for any other, as Python's own hook.

    Parameters
    ----------
    previous : callable
        The hook it stands in front of.
    """

    def __init__(self, previous=sys.__excepthook__):
        self.previous = previous

    def __call__(self, kind, value, tb):
        """Handle an uncaught exception: quiet for a vanished client, else ``previous``'s traceback."""
        if isinstance(kind, type) and issubclass(kind, (EOFError, ConnectionError)):
            return
        try:
            self.previous(kind, value, tb)
        except Exception:  # noqa: BLE001 - a hook must not raise
            traceback.print_exception(kind, value, tb)


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
    return isinstance(sys.excepthook, QuietWhenTheClientVanishes)


numba_ready()
if in_the_fork_server():
    sys.excepthook = QuietWhenTheClientVanishes(sys.excepthook)
gc.freeze()
