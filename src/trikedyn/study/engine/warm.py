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
"""

from __future__ import annotations

import gc

from ..._jit import jit

__all__ = ["numba_ready"]


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


numba_ready()
gc.freeze()
