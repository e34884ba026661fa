"""The similarity tyre over a batch's lanes: every lane's forces at once, in a loop LLVM vectorises.

:func:`similarity_forces_lanes` is the similarity branch of :func:`~trikedyn.tyre.interface.tyre_forces`
(:func:`~trikedyn.tyre.magic_formula.combined_forces` and
:func:`~trikedyn.tyre.magic_formula.rolling_resistance_moment`) written for ``B`` lanes side by side: each input
and output a row of ``B`` numbers, each coefficient a row over the lanes (lanes may carry different tyres of the
same model; the peak frictions and stiffness factors are written out on the coefficient rows, because calling
:func:`~trikedyn.tyre.magic_formula.peak_friction` and its neighbours on a lane's strided coefficient vector keeps
the loop scalar: 156 against 52 ns a lane), the branches computed both ways and selected, and the arctangents,
the sine and the hyperbolic tangent those of :mod:`trikedyn.model.lane_math` (within 1-2 ulp of the C library's,
which a loop that calls them cannot vectorise). It gives the scalar function's forces within 3.3e-16 of the peak force
(``tests/tyre/test_lanes.py`` asks 1e-15) and takes 52 ns a lane over 8 lanes against 120 ns a scalar call
(``python benchmarks/lane_math.py``). It is a piece of the tyres and springs over lanes, which the lockstep batch
still evaluates lane by lane: wired in alone, between passes over the lanes that store and reload each wheel's
contact, it gained nothing, and its 1-2 ulp left a lane that rolls over 3e-9 from its scalar run
(``docs/physics.md``, *Speed*, *Lanes that round differently*).
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from ..model.lane_math import arctan, sincos, tanh
from .magic_formula import (
    CORNERING_STIFFNESS_FACTOR,
    CORNERING_STIFFNESS_LOAD_FACTOR,
    CURVATURE_X,
    CURVATURE_Y,
    FZ0,
    LOAD_SENSITIVITY,
    MU_FLOOR_FRACTION,
    MU_X,
    MU_Y,
    RHO_LINEAR,
    ROLLING_RESISTANCE,
    SHAPE_X,
    SHAPE_Y,
    SLIP_STIFFNESS_FACTOR,
    U_PEAK_X,
    U_PEAK_Y,
)

__all__ = ["similarity_forces_lanes"]


@jit(inline="always")
def _curve(u, shape, curvature):
    """:func:`~trikedyn.tyre.magic_formula.magic_formula_curve` by the branch-free functions."""
    return sincos(shape * arctan(u - curvature * (u - arctan(u))))[0]


@jit
def similarity_forces_lanes(coeffs, kappa, alpha, fz, spin, r_eff, w_low, fx, fy, my):
    """The similarity tyre's ``F_x``, ``F_y`` and rolling-resistance moment of every lane.

    Parameters
    ----------
    coeffs : numpy.ndarray, shape (n_coeffs, B)
        Each lane's coefficient vector (:mod:`trikedyn.tyre.magic_formula`), one row a coefficient.
    kappa, alpha : numpy.ndarray, shape (B,)
        Longitudinal slip [1] and slip angle [rad] of each lane.
    fz : numpy.ndarray, shape (B,)
        Vertical load [N]; a lane with ``fz <= 0`` gets no force.
    spin : numpy.ndarray, shape (B,)
        Wheel spin rate [rad/s].
    r_eff : numpy.ndarray, shape (B,)
        Effective rolling radius [m] (the moment's arm).
    w_low : numpy.ndarray, shape (B,)
        Spin rate smoothing the rolling resistance's sign [rad/s], each lane's.
    fx, fy, my : numpy.ndarray, shape (B,)
        Written with the forces [N] and the moment about the spin axis [N m].
    """
    for j in range(kappa.shape[0]):
        contact = fz[j] > 0.0
        fz0 = coeffs[FZ0, j]
        load = fz[j] if contact else fz0  # a load the arithmetic takes; the lane's forces are zeroed below
        scale = max(1.0 + coeffs[LOAD_SENSITIVITY, j] * (load - fz0) / fz0, MU_FLOOR_FRACTION)
        mu_x, mu_y = coeffs[MU_X, j] * scale, coeffs[MU_Y, j] * scale
        cx, cy = coeffs[SHAPE_X, j], coeffs[SHAPE_Y, j]
        ux, uy = coeffs[U_PEAK_X, j], coeffs[U_PEAK_Y, j]
        bx = coeffs[SLIP_STIFFNESS_FACTOR, j] / (cx * mu_x)
        ratio = load / (coeffs[CORNERING_STIFFNESS_LOAD_FACTOR, j] * fz0)
        c_alpha = coeffs[CORNERING_STIFFNESS_FACTOR, j] * fz0 * (2.0 * ratio / (1.0 + ratio * ratio))
        by = c_alpha / (cy * mu_y * load)
        kn = bx * kappa[j] / ux
        an = by * alpha[j] / uy
        rho = np.sqrt(kn * kn + an * an)
        linear = rho < RHO_LINEAR
        r = 1.0 if linear else rho  # the curves at a harmless argument where the zero-slip limit is taken
        gx = cx * ux if linear else _curve(r * ux, cx, coeffs[CURVATURE_X, j]) / r
        gy = cy * uy if linear else _curve(r * uy, cy, coeffs[CURVATURE_Y, j]) / r
        moment = -coeffs[ROLLING_RESISTANCE, j] * load * r_eff[j] * tanh(spin[j] / w_low[j])
        fx[j] = mu_x * load * (kn * gx) if contact else 0.0
        fy[j] = mu_y * load * (an * gy) if contact else 0.0
        my[j] = moment if contact else 0.0
