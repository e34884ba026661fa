"""The one place where trikedyn's compiled functions get their numba options.

``jit`` is ``numba.njit`` with ``cache=True`` and a *safe* subset of fast-math: contraction into fused
multiply-adds, reassociation, reciprocal approximation and no signed zeros, so LLVM can vectorise the small
dense loops of the dynamics; but not ``nnan``/``ninf``, so NaN and infinity keep their meaning and the
health watch still sees a diverging state. ``error_model="numpy"``: a division by zero gives inf or NaN
(which the health watch catches) instead of a Python exception, so divisions need no branch.
"""

from __future__ import annotations

from numba import njit

__all__ = ["FASTMATH", "jit"]

FASTMATH = {"contract", "reassoc", "arcp", "nsz", "afn"}


def jit(func=None, **options):
    """``numba.njit(cache=True, fastmath=FASTMATH)``, usable with or without arguments."""
    options = {"cache": True, "fastmath": FASTMATH, "error_model": "numpy", **options}
    if func is None:
        return lambda f: njit(**options)(f)
    return njit(**options)(func)
