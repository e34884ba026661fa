"""Imported by the pool's fork server (:data:`~trikedyn.study.engine.executors.PRELOAD`): numba's compiler
context set up once, in the server, for every worker it forks.

A process's first compiled call, even one loaded from numba's cache, first builds numba's typing and target
contexts (their registries of types and functions): about 0.27 s on the reference machine, which each worker
used to pay at its first run. Calling one small cached function here builds them in the server, and a forked
worker inherits them. The call compiles nothing new after the first time (``cache=True``), and the server
still starts no thread.
"""

from __future__ import annotations

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
