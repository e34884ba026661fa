"""The full Magic Formula over arrays of inputs, for users and plots (ISO signs: :mod:`trikedyn.tyre.pac2002`).

:func:`forces` and :func:`pure_forces` broadcast their inputs together, pack the tyre when given a
:class:`~trikedyn.tyre.tir.TyreProperties` (:func:`~trikedyn.tyre.pac2002_pack.pack`) and evaluate the compiled
kernels (:func:`~trikedyn.tyre.pac2002.mf_forces_into`) element by element.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .pac2002 import LONGVL, mf_forces_into
from .pac2002_pack import pack

__all__ = ["TyreForces", "forces", "pure_forces"]


class TyreForces(NamedTuple):
    """Forces [N] and moments [N m] (ISO axes), arrays of the broadcast input shape, and the clamp mask."""

    fx: np.ndarray
    fy: np.ndarray
    mz: np.ndarray
    mx: np.ndarray
    my: np.ndarray
    clamped: np.ndarray


def forces(tir, fz, kappa=0.0, alpha=0.0, gamma=0.0, vcx=None, *, side=None, combined=True) -> TyreForces:
    """Tyre forces and moments over arrays of inputs (for users and plots; ISO signs, see the module).

    Parameters
    ----------
    tir : TyreProperties or numpy.ndarray
        The tyre, or its packed vector (:func:`pack`; ``side`` is then ignored).
    fz : array_like
        Vertical load [N].
    kappa, alpha, gamma : array_like
        Longitudinal slip [1], slip angle [rad], inclination [rad]; broadcast together with ``fz``.
    vcx : array_like, optional
        Forward speed [m/s]; default the file's ``LONGVL``.
    side : {'left', 'right', None}
        Mounting side (see :func:`~trikedyn.tyre.pac2002_pack.pack`).
    combined : bool
        Combined slip (default) or pure slip (each force of its own slip only).

    Returns
    -------
    TyreForces
    """
    c = tir if isinstance(tir, np.ndarray) else pack(tir, side)
    if vcx is None:
        vcx = c[LONGVL]
    arrays = np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in (fz, kappa, alpha, gamma, vcx)))
    shape = arrays[0].shape
    flat = [np.ascontiguousarray(v).ravel() for v in arrays]
    out = np.empty((5, flat[0].size))
    mask = np.empty(flat[0].size, dtype=np.int64)
    mf_forces_into(*flat, c, bool(combined), out, mask)
    return TyreForces(*(row.reshape(shape) for row in out), mask.reshape(shape))


def pure_forces(tir, fz, kappa=0.0, alpha=0.0, gamma=0.0, vcx=None, *, side=None) -> TyreForces:
    """:func:`forces` in pure slip: ``Fx0(kappa)``, ``Fy0(alpha)``, ``Mz0(alpha)`` (4.E9), (4.E19), (4.E31).

    Parameters
    ----------
    tir : TyreProperties or numpy.ndarray
        The tyre, or its packed vector (``side`` is then ignored).
    fz : array_like
        Vertical load [N].
    kappa, alpha, gamma : array_like
        Longitudinal slip (dimensionless), slip angle [rad], inclination [rad].
    vcx : array_like, optional
        Forward speed [m/s]; default the file's ``LONGVL``.
    side : {'left', 'right', None}
        Mounting side (see :func:`~trikedyn.tyre.pac2002_pack.pack`).

    Returns
    -------
    TyreForces
        Forces [N], moments [N m] and clamp masks, shaped as the broadcast inputs.
    """
    return forces(tir, fz, kappa, alpha, gamma, vcx, side=side, combined=False)
