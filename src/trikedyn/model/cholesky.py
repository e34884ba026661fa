"""Cholesky solve of a symmetric positive definite system, compiled with numba, allocating nothing.

The dynamics' last step (:mod:`trikedyn.model.dynamics`): ``H du/dt = tau - C`` with the joint-space mass
matrix ``H``; a matrix that is not positive definite gives NaN, which the health watch of the time loop sees.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit

__all__ = ["cholesky_solve_into"]


@jit(inline="always")
def cholesky_solve_into(a, b, low, y, x):
    """Solve ``a x = b`` for symmetric positive definite ``a`` by Cholesky; ``x`` is NaN if ``a`` is not.

    Parameters
    ----------
    a : numpy.ndarray, shape (n, n)
        The symmetric matrix (only its lower triangle is read).
    b : numpy.ndarray, shape (n,)
        Right-hand side.
    low : numpy.ndarray, shape (n, n)
        Written with the Cholesky factor.
    y : numpy.ndarray, shape (n,)
        Scratch for the forward substitution.
    x : numpy.ndarray, shape (n,)
        Written with the solution.
    """
    n = a.shape[0]
    for j in range(n):
        d = a[j, j]
        for k in range(j):
            d -= low[j, k] * low[j, k]
        if d <= 0.0:
            for i in range(n):
                x[i] = np.nan
            return
        ljj = np.sqrt(d)
        low[j, j] = ljj
        for i in range(j + 1, n):
            s = a[i, j]
            for k in range(j):
                s -= low[i, k] * low[j, k]
            low[i, j] = s / ljj
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= low[i, k] * y[k]
        y[i] = s / low[i, i]
    for i in range(n - 1, -1, -1):
        s = y[i]
        for k in range(i + 1, n):
            s -= low[k, i] * x[k]
        x[i] = s / low[i, i]
