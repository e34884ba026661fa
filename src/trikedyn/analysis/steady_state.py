"""ISO 4138 steady-state circular driving, constant radius: the handling diagram, its gradients and shape.

Pure array algorithm (NumPy), no vehicle model; SI signals in ISO 8855 axes (a left turn has positive
lateral acceleration and steer). The standard's text was not at hand: the definitions are the commonly
published ones (SAE J266; ISO 4138 as summarised in the literature), stated by the function. The result
is a frozen dataclass; ``to_dict()`` gives JSON-safe plain values (None for NaN). Bad input raises
:class:`~trikedyn.errors.InputError`, a :class:`ValueError`. The shape of the steer curve (gradients by
band, neutral steer, limit behaviour) is :mod:`trikedyn.analysis.steer_shape`'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..units import STANDARD_GRAVITY as G
from ._series import PlainResult, as_values, positive
from .steer_shape import BAND_WIDTH_MPS2, LIMIT_BAND_MPS2, NEUTRAL_TOLERANCE_DEG_PER_G, SteerShape, steer_shape

__all__ = ["HandlingDiagram", "handling_diagram"]

FIT_LIMIT_G = 0.2  # default upper bound of the linear-range fit [g] ...
FIT_LIMIT_FRACTION = 0.4  # ... or this fraction of the largest a_y reached, whichever is smaller
MIN_FIT_POINTS = 10  # fewest samples of the linear-range fit


@dataclass(frozen=True, eq=False)
class HandlingDiagram(PlainResult):
    """ISO 4138 constant-radius handling diagram, folded to a left turn.

    Attributes
    ----------
    understeer_gradient_deg_per_g, sideslip_gradient_deg_per_g, roll_gradient_deg_per_g : float
        Slopes of road-wheel steer, sideslip and roll against ``a_y / g`` in the linear range [deg/g].
    steer_intercept_deg, sideslip_intercept_deg, roll_intercept_deg, ackermann_steer_deg : float
        The fitted lines at ``a_y = 0`` (the steer one should be the Ackermann steer); ``L / R`` [deg].
    max_lateral_acceleration_mps2 : float
        Largest lateral acceleration of the record [m/s^2].
    fit_start_mps2, fit_limit_mps2 : float
        The linear range: the lowest lateral acceleration fitted and the upper bound of the fit [m/s^2].
    n_fit, turn_direction : int
        Number of samples fitted; the sign the record was folded with (+1 left turn, -1 right).
    ay_bins_mps2, steer_deg, sideslip_deg, roll_deg : ndarray
        The diagram: per non-empty lateral-acceleration bin, the means of a_y [m/s^2] and of road-wheel
        steer, sideslip and roll [deg].
    shape : SteerShape
        The steer curve's shape beyond the linear range: understeer gradient by band, neutral-steer
        lateral acceleration, limit behaviour (:func:`~trikedyn.analysis.steer_shape.steer_shape`).
    """

    understeer_gradient_deg_per_g: float
    sideslip_gradient_deg_per_g: float
    roll_gradient_deg_per_g: float
    steer_intercept_deg: float
    sideslip_intercept_deg: float
    roll_intercept_deg: float
    ackermann_steer_deg: float
    max_lateral_acceleration_mps2: float
    fit_start_mps2: float
    fit_limit_mps2: float
    n_fit: int
    turn_direction: int
    ay_bins_mps2: np.ndarray
    steer_deg: np.ndarray
    sideslip_deg: np.ndarray
    roll_deg: np.ndarray
    shape: SteerShape

    def plot(self):
        """Road-wheel steer, sideslip and roll [deg] against lateral acceleration [m/s^2]: binned means, the
        linear-range fits (dashed, their range shaded); on the steer, the gradient by band (coloured by
        behaviour), the neutral-steer point (star) and the stretch that gives the limit behaviour; returns
        the Figure.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 9), gridspec_kw={"height_ratios": [2, 1, 1]})
        a = np.array([self.fit_start_mps2, self.fit_limit_mps2])
        rows = [("road-wheel steer", self.steer_deg, self.steer_intercept_deg, self.understeer_gradient_deg_per_g),
                ("sideslip", self.sideslip_deg, self.sideslip_intercept_deg, self.sideslip_gradient_deg_per_g),
                ("roll", self.roll_deg, self.roll_intercept_deg, self.roll_gradient_deg_per_g)]
        for ax, (name, y, c0, k) in zip(axes, rows, strict=True):
            ax.axvspan(*a, color="0.85", alpha=0.6, lw=0,
                       label=f"linear range {a[0]:.2f}-{a[1]:.2f} m/s²")
            ax.plot(self.ay_bins_mps2, y, "o-", color="k", ms=3, lw=1.0, label="binned mean")
            ax.plot(a, c0 + k * a / G, "--", color="tab:red", lw=1.4, label=f"linear-range fit: {k:+.3g} deg/g")
            ax.set_ylabel(f"{name} [deg]")
            ax.grid(alpha=0.3)
        self.shape.mark(axes[0])
        axes[0].axhline(self.ackermann_steer_deg, color="0.5", lw=0.8, ls=":")
        axes[0].legend(fontsize=7, loc="lower left")
        for ax in axes[1:]:
            ax.legend(fontsize=7, loc="best")
        axes[-1].set_xlabel("lateral acceleration [m/s²] (folded to a left turn)")
        fig.tight_layout()
        return fig


def handling_diagram(lateral_acceleration_mps2, road_steer_rad, sideslip_rad, roll_rad, *, radius_m,
                     wheelbase_m, fit_limit_mps2=None, n_bins=20, band_width_mps2=BAND_WIDTH_MPS2,
                     limit_band_mps2=LIMIT_BAND_MPS2,
                     neutral_tolerance_deg_per_g=NEUTRAL_TOLERANCE_DEG_PER_G) -> HandlingDiagram:
    """ISO 4138 steady-state circular driving, constant-radius method: gradients, shape and diagram.

    The samples are quasi-steady states on a circle of constant radius, the speed rising slowly. As the
    Ackermann steer ``L / R`` is then constant, the slope of road-wheel steer against lateral acceleration
    *is* the understeer gradient ``d delta / d(a_y / g)`` [deg/g] (positive: understeer); the sideslip
    (at the CG) and roll gradients are the slopes of those angles likewise.

    *Folding.* A record holds one turn direction, ``sign(mean a_y)``; every channel is multiplied by it,
    so a right turn gives the gradients of the mirrored left turn. A record whose folded a_y goes below
    -25 % of its maximum mixes both directions and is refused: analyse each direction separately.
    *Linear range.* Least-squares straight lines through the samples with folded ``|a_y| <=
    fit_limit_mps2``, by default ``min(0.2 g, 0.4 max a_y)``; at least 10 samples spanning a quarter of
    that range are needed. *Shape.* The understeer gradient by band of lateral acceleration, the
    neutral-steer lateral acceleration (the peak of the steer curve) and the limit behaviour, by
    :func:`~trikedyn.analysis.steer_shape.steer_shape`. *Diagram.* Means over ``n_bins`` equal bins of the
    folded a_y.

    Parameters
    ----------
    lateral_acceleration_mps2 : array_like
        Lateral acceleration [m/s^2].
    road_steer_rad, sideslip_rad, roll_rad : array_like
        Road-wheel steer, CG sideslip and body roll angles [rad], one per a_y sample.
    radius_m, wheelbase_m : float
        Radius of the circle and wheelbase [m].
    fit_limit_mps2 : float, optional
        Upper bound of the fitted lateral accelerations [m/s^2].
    n_bins : int
        Number of bins of the diagram (empty ones are dropped).
    band_width_mps2, limit_band_mps2, neutral_tolerance_deg_per_g : float
        Width of the gradient bands [m/s^2]; the last stretch of a_y that gives the limit behaviour
        [m/s^2]; gradients within +- this are neutral [deg/g] (see :func:`~trikedyn.analysis.steer_shape.steer_shape`).

    Returns
    -------
    HandlingDiagram
        Gradients [deg/g], intercepts [deg], the binned diagram and the shape.
    """
    n = np.size(lateral_acceleration_mps2)
    ay = as_values(lateral_acceleration_mps2, n, "lateral_acceleration_mps2")
    chans = [as_values(x, n, w) for x, w in ((road_steer_rad, "road_steer_rad"), (sideslip_rad, "sideslip_rad"),
                                             (roll_rad, "roll_rad"))]
    radius, wheelbase = positive(radius_m, "radius_m"), positive(wheelbase_m, "wheelbase_m")
    direction = 1 if ay.mean() >= 0 else -1
    a = direction * ay
    deg = [np.degrees(direction * x) for x in chans]
    a_max = float(a.max())
    if a_max <= 0 or a.min() < -0.25 * a_max:
        raise InputError("the record mixes left and right turns (or has no lateral acceleration); analyse "
                         "each turn direction separately", "lateral_acceleration_mps2")
    limit = (min(FIT_LIMIT_G * G, FIT_LIMIT_FRACTION * a_max) if fit_limit_mps2 is None
             else positive(fit_limit_mps2, "fit_limit_mps2"))
    sel = np.abs(a) <= limit
    span = float(np.ptp(a[sel])) if sel.any() else 0.0
    if sel.sum() < MIN_FIT_POINTS or span < 0.25 * limit:
        raise InputError(f"only {int(sel.sum())} samples spanning {span:.3g} m/s^2 with |a_y| <= {limit:.3g} "
                         f"m/s^2; the linear-range fit needs at least {MIN_FIT_POINTS} samples spanning a "
                         "quarter of that range: start the run slower or raise fit_limit_mps2",
                         "lateral_acceleration_mps2")
    fits = [np.polyfit(a[sel] / G, d[sel], 1) for d in deg]
    shape = steer_shape(a, deg[0], band_width_mps2=band_width_mps2, limit_band_mps2=limit_band_mps2,
                        neutral_tolerance_deg_per_g=neutral_tolerance_deg_per_g)
    nb = int(n_bins)
    which = np.clip(np.digitize(a, np.linspace(a.min(), a_max, nb + 1)) - 1, 0, nb - 1)
    counts = np.bincount(which, minlength=nb)

    def binned(x):
        """Means of ``x`` over the non-empty bins."""
        return (np.bincount(which, weights=x, minlength=nb) / np.maximum(counts, 1))[counts > 0]

    return HandlingDiagram(
        understeer_gradient_deg_per_g=float(fits[0][0]), sideslip_gradient_deg_per_g=float(fits[1][0]),
        roll_gradient_deg_per_g=float(fits[2][0]), steer_intercept_deg=float(fits[0][1]),
        sideslip_intercept_deg=float(fits[1][1]), roll_intercept_deg=float(fits[2][1]),
        ackermann_steer_deg=math.degrees(wheelbase / radius), max_lateral_acceleration_mps2=a_max,
        fit_start_mps2=float(a[sel].min()), fit_limit_mps2=float(limit), n_fit=int(sel.sum()),
        turn_direction=direction, ay_bins_mps2=binned(a), steer_deg=binned(deg[0]), sideslip_deg=binned(deg[1]),
        roll_deg=binned(deg[2]), shape=shape)
