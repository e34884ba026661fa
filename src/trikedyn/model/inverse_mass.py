"""Entries of the inverse mass matrix ``H^-1`` from a factor of ``H``, without forming ``H^-1``.

The exponential integrator (:mod:`trikedyn.simulate.exponential`) needs ``(H^-1)_ss`` of each wheel's spin
joint once per step: from the Cholesky factor of the generic kernels (:func:`inverse_mass_diagonal`) or from
the leaves-first ``H = L^T D L`` of the generated ones (:func:`ltdl_inverse_diagonal`, Featherstone, *Rigid
Body Dynamics Algorithms*, 2008, section 6.5), which touches only the joint and its ancestors.
"""

from __future__ import annotations

from .._jit import jit

__all__ = ["dof_parent", "inverse_mass_diagonal", "ltdl_inverse_diagonal"]


@jit(inline="always")
def inverse_mass_diagonal(low, s, y):
    """``(H^-1)_ss`` from the Cholesky factor ``low`` of ``H``: ``|L^-1 e_s|^2`` (``y``: scratch, length n).

    Parameters
    ----------
    low : numpy.ndarray, shape (n, n)
        Lower Cholesky factor of the mass matrix.
    s : int
        The diagonal entry wanted.
    y : numpy.ndarray, shape (n,)
        Scratch.

    Returns
    -------
    float
        ``(H^-1)_ss`` [1/kg or 1/(kg m^2)].
    """
    n = low.shape[0]
    y[s] = 1.0 / low[s, s]
    total = y[s] * y[s]
    for i in range(s + 1, n):
        acc = 0.0
        for k in range(s, i):
            acc -= low[i, k] * y[k]
        y[i] = acc / low[i, i]
        total += y[i] * y[i]
    return total


@jit(inline="always")
def dof_parent(parent, k):
    """The parent of degree of freedom ``k`` in the tree expanded to one joint per degree of freedom: the
    base's six form a chain (-1 above the first), a joint's parent is its parent body's joint (the base's
    last for the base).

    Parameters
    ----------
    parent : ndarray of int
        Each body's parent body (the packed tree's parent array; the base is body 0 or 1 as packed).
    k : int
        The degree of freedom (0-5 the base's, then one per joint).

    Returns
    -------
    int
        The parent degree of freedom, -1 above the first.
    """
    if k < 6:
        return k - 1
    pb = parent[k - 5]
    return 5 + pb if pb > 0 else 5


@jit(inline="always")
def ltdl_inverse_diagonal(factor, parent, s, z):
    """``(H^-1)_ss`` from the leaves-first factorisation ``H = L^T D L``: ``sum_i z_i^2 / D_i`` with
    ``L^T z = e_s``, nonzero only on ``s`` and its ancestors (``z``: scratch, length n).

    Parameters
    ----------
    factor : numpy.ndarray, shape (n, n)
        ``D`` on the diagonal, ``L_ij`` at each ``j`` an ancestor of ``i`` (other entries are not read).
    parent : numpy.ndarray of int, shape (nb,)
        The tree's parent bodies.
    s : int
        The diagonal entry wanted.
    z : numpy.ndarray, shape (n,)
        Scratch.

    Returns
    -------
    float
        ``(H^-1)_ss`` [1/kg or 1/(kg m^2)].
    """
    i = s
    while i != -1:
        z[i] = 0.0
        i = dof_parent(parent, i)
    z[s] = 1.0
    total = 0.0
    i = s
    while i != -1:
        zi = z[i]
        j = dof_parent(parent, i)
        while j != -1:
            z[j] -= factor[i, j] * zi
            j = dof_parent(parent, j)
        total += zi * zi / factor[i, i]
        i = dof_parent(parent, i)
    return total
