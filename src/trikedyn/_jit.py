"""The one place where trikedyn's compiled functions get their numba options.

``jit`` is ``numba.njit`` with ``cache=True`` and IEEE arithmetic: no fast-math flags at all. With
contraction into fused multiply-adds and reassociation (used until issue 25), the rounding of a function
depended on where LLVM inlined it: the lockstep batch loop and the scalar loop, or a loop compiled afresh and
the same loop loaded from the cache, differed by 1e-8 N on a wheel load and by 1.4e-5 on a lane that tips
over, so the same run did not give the same answer twice. Without the flags every compile of a function
rounds alike, and the batch equals the scalar loop bit for bit; the single-run speed is unchanged within the
benchmark's noise (``make bench``). ``error_model="numpy"``: a division by zero gives inf or NaN (which the
health watch catches) instead of a Python exception, so divisions need no branch.
"""

from __future__ import annotations

from numba import njit

__all__ = ["FASTMATH", "jit"]

FASTMATH: set[str] = set()  # no fast-math flag: see the module's docstring


def jit(func=None, **options):
    """``numba.njit(cache=True, fastmath=FASTMATH, error_model="numpy")``, usable with or without arguments."""
    options = {"cache": True, "fastmath": FASTMATH, "error_model": "numpy", **options}
    if func is None:
        return lambda f: njit(**options)(f)
    return njit(**options)(func)
