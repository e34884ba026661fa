"""The shape of a handling diagram's steer curve: gradients by band, the neutral-steer point, the limit.

One slope does not describe a curve that bends. On a constant-radius test (ISO 4138) the slope of the
road-wheel steer against ``a_y / g`` is the understeer gradient *at that lateral acceleration*; a delta
trike, whose two-wheel axle carries all the roll-moment load transfer, typically understeers a little at
low ``a_y`` and turns to oversteer before its limit: its steer curve rises, peaks and falls. This module
reads that shape from the quasi-steady samples of such a test:

- the **steer curve**: means of the road-wheel steer over bins of lateral acceleration (0.1 m/s^2 wide),
  each bin weighted alike however long the test dwelt there;
- the **understeer gradient by band**: straight lines through the curve over bands of lateral acceleration
  1 m/s^2 wide, edges at whole m/s^2 (0-1, 1-2, ...), clipped to the record; a band at either end covering
  less than half a band width is merged into its neighbour;
- the **neutral-steer lateral acceleration**: where the steer stops rising, i.e. the first peak of the
  curve (smoothed by local quadratics over +-0.3 m/s^2): its highest point before it first falls by at
  least 0.01 deg of road-wheel steer, more than 0.2 m/s^2 above the record's start (a curve that falls
  from its start may have peaked below the record); beyond it the trike oversteers;
- the **limit behaviour**: the gradient over the last 0.5 m/s^2 of the record: ``understeer`` above
  +0.25 deg/g, ``oversteer`` below -0.25 deg/g, else ``neutral``.

Inputs are folded to a left turn as :func:`~trikedyn.analysis.steady_state.handling_diagram` folds them
(``sign(mean a_y)``). Everything here is a pure function over arrays; :class:`SteerShape` only holds the
figures and draws them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..units import STANDARD_GRAVITY as G
from ._series import PlainResult, as_values, positive

__all__ = ["BEHAVIOURS", "NEUTRAL_STEER", "SteerBand", "SteerShape", "band_gradients", "behaviour", "first_peak", "line_fit",
           "local_quadratic", "steer_curve", "steer_shape"]

BIN_MPS2 = 0.1  # width of the steer curve's bins [m/s^2] (at most a tenth of the record's a_y range)
MIN_BIN_SAMPLES = 3  # fewest samples of a bin kept in the steer curve
BAND_WIDTH_MPS2 = 1.0  # width of the gradient bands [m/s^2], edges at its multiples
SMOOTH_HALF_WIDTH_MPS2 = 0.3  # half-width of the local quadratics that smooth the curve for its peak [m/s^2]
PEAK_DROP_DEG = 0.01  # fall after a peak that makes it one [deg of road-wheel steer]
START_CLEAR_MPS2 = 0.2  # least distance of a peak from the record's start [m/s^2]
LIMIT_BAND_MPS2 = 0.5  # the last stretch of a_y whose gradient is the limit behaviour [m/s^2]
NEUTRAL_TOLERANCE_DEG_PER_G = 0.25  # |gradient| up to which a band or the limit is called neutral [deg/g]
BEHAVIOURS = ("understeer", "neutral", "oversteer")
"""The values of :attr:`SteerShape.limit_behaviour` and :attr:`SteerBand.behaviour`."""
NEUTRAL_STEER = ("peak", "not reached", "falls from the start")
"""The values of :attr:`SteerShape.neutral_steer`."""


def steer_curve(lateral_acceleration_mps2, road_steer_deg, *, bin_mps2=BIN_MPS2,
                min_samples=MIN_BIN_SAMPLES) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The measured steer curve: means over bins of lateral acceleration.

    Parameters
    ----------
    lateral_acceleration_mps2, road_steer_deg : ndarray
        Quasi-steady samples of lateral acceleration [m/s^2] (one turn direction, positive) and road-wheel
        steer [deg].
    bin_mps2 : float
        Bin width [m/s^2]; bins start at the smallest ``a_y``.
    min_samples : int
        Bins with fewer samples are left out.

    Returns
    -------
    a_mps2, steer_deg, counts : ndarray
        Per kept bin, in rising ``a_y``: the mean lateral acceleration [m/s^2], the mean steer [deg] and the
        number of samples.
    """
    a, s = np.asarray(lateral_acceleration_mps2, float), np.asarray(road_steer_deg, float)
    which = np.floor((a - a.min()) / bin_mps2).astype(int)
    counts = np.bincount(which)
    keep = counts >= min_samples
    with np.errstate(invalid="ignore"):
        a_b = np.bincount(which, weights=a) / counts
        s_b = np.bincount(which, weights=s) / counts
    return a_b[keep], s_b[keep], counts[keep]


def line_fit(a_mps2, steer_deg) -> tuple[float, float]:
    """Least-squares line through the points: (gradient [deg/g], steer at ``a_y = 0`` [deg]); NaNs with
    fewer than two distinct points.

    Parameters
    ----------
    a_mps2 : array_like
        Lateral accelerations [m/s^2].
    steer_deg : array_like
        Steer angles [deg].

    Returns
    -------
    gradient : float
        [deg/g].
    intercept : float
        Steer at zero lateral acceleration [deg].
    """
    a, s = np.asarray(a_mps2, float), np.asarray(steer_deg, float)
    if a.size < 2 or np.ptp(a) <= 0:
        return math.nan, math.nan
    slope, intercept = np.polyfit(a, s, 1)
    return float(slope * G), float(intercept)


def behaviour(gradient_deg_per_g: float, tolerance_deg_per_g: float = NEUTRAL_TOLERANCE_DEG_PER_G) -> str:
    """``"understeer"`` above ``+tolerance``, ``"oversteer"`` below ``-tolerance``, else ``"neutral"``
    (also for NaN: no gradient, no verdict either way).

    Parameters
    ----------
    gradient_deg_per_g : float
        Understeer gradient [deg/g].
    tolerance_deg_per_g : float
        Neutral band half-width [deg/g].

    Returns
    -------
    str
        The behaviour.
    """
    if gradient_deg_per_g > tolerance_deg_per_g:
        return "understeer"
    if gradient_deg_per_g < -tolerance_deg_per_g:
        return "oversteer"
    return "neutral"


def band_gradients(a_mps2, steer_deg, *, band_width_mps2=BAND_WIDTH_MPS2, a_range_mps2=None
                   ) -> list[tuple[float, float, float, float]]:
    """Understeer gradients by band of lateral acceleration, from a steer curve.

    Bands are ``[k w, (k + 1) w)`` for whole ``k`` (``w = band_width_mps2``), clipped to the curve's range;
    a band at either end spanning less than ``w / 2`` (or holding fewer than 3 points) is merged into its
    neighbour. With a quadratic curve and evenly spread points, a band's gradient is the curve's slope at
    the band's middle.

    Parameters
    ----------
    a_mps2, steer_deg : ndarray
        The steer curve (:func:`steer_curve`): lateral acceleration [m/s^2], rising; road-wheel steer [deg].
    band_width_mps2 : float
        Band width [m/s^2].
    a_range_mps2 : (float, float), optional
        The record's lowest and highest lateral acceleration [m/s^2], which clip the first and last band;
        by default the curve's first and last points.

    Returns
    -------
    list of (low_mps2, high_mps2, gradient_deg_per_g, intercept_deg)
        Per band, in rising ``a_y``: its ends (whole multiples of the width, or the record's ends) [m/s^2],
        the gradient [deg/g] and the line's steer at ``a_y = 0`` [deg].
    """
    a, s = np.asarray(a_mps2, float), np.asarray(steer_deg, float)
    w = positive(band_width_mps2, "band_width_mps2")
    k = np.floor(a / w + 1e-9).astype(int)
    groups = [np.flatnonzero(k == j) for j in np.unique(k)]

    step = float(np.median(np.diff(a))) if a.size > 1 else 0.0  # each point stands for a bin this wide

    def short(idx):
        """Whether a band's points cover less than half a band width (or are fewer than 3)."""
        return idx.size < 3 or np.ptp(a[idx]) + step < 0.5 * w

    while len(groups) > 1 and short(groups[0]):
        groups[:2] = [np.r_[groups[0], groups[1]]]
    while len(groups) > 1 and short(groups[-1]):
        groups[-2:] = [np.r_[groups[-2], groups[-1]]]
    lower, upper = (a[0], a[-1]) if a_range_mps2 is None else (float(v) for v in a_range_mps2)
    out = []
    for idx in groups:
        gradient, intercept = line_fit(a[idx], s[idx])
        out.append((max(float(k[idx[0]] * w), lower), min(float((k[idx[-1]] + 1) * w), upper), gradient, intercept))
    return out


def local_quadratic(a_mps2, steer_deg, *, half_width_mps2=SMOOTH_HALF_WIDTH_MPS2) -> np.ndarray:
    """The curve smoothed: at each point, the value of the least-squares quadratic through the points within
    ``half_width_mps2`` of it (a Savitzky-Golay filter for unevenly spaced points) [deg].

    Parameters
    ----------
    a_mps2 : array_like
        Lateral accelerations [m/s^2].
    steer_deg : array_like
        Steer angles [deg].
    half_width_mps2 : float
        Neighbourhood half-width [m/s^2].

    Returns
    -------
    numpy.ndarray
        The smoothed steer [deg].
    """
    a, s = np.asarray(a_mps2, float), np.asarray(steer_deg, float)
    out = s.copy()
    for i, ai in enumerate(a):
        near = np.abs(a - ai) <= half_width_mps2
        if near.sum() >= 4:
            out[i] = np.polyval(np.polyfit(a[near] - ai, s[near], 2), 0.0)
    return out


def first_peak(a_mps2, steer_deg, *, drop_deg=PEAK_DROP_DEG,
               clear_mps2=START_CLEAR_MPS2) -> tuple[int | None, str]:
    """The first peak of a (smoothed) steer curve, with hysteresis: the highest point before the curve first
    falls by at least ``drop_deg`` below it, if it lies more than ``clear_mps2`` above the curve's first
    ``a_y`` (a peak nearer the start may lie below the record: the curve *falls from the start*); after
    such a fall, the next peak counts once the curve has risen by ``drop_deg`` from its lowest point.

    Parameters
    ----------
    a_mps2, steer_deg : ndarray
        The curve: lateral acceleration [m/s^2], rising; steer [deg].
    drop_deg : float
        Fall (and rise, after a fall) that make a peak [deg].
    clear_mps2 : float
        Least distance of a peak from the curve's start [m/s^2].

    Returns
    -------
    index, status : int or None, str
        The peak's index and ``"peak"``; or None and ``"falls from the start"`` (it fell from its start and
        never rose by ``drop_deg`` again) or ``"not reached"`` (it rises at its end, or stays within
        ``drop_deg`` throughout).
    """
    a, s = np.asarray(a_mps2, float), np.asarray(steer_deg, float)
    rising, low, high = True, 0, 0
    for k in range(1, s.size):
        if rising:
            if s[k] > s[high]:
                high = k
            elif s[k] <= s[high] - drop_deg:
                if a[high] - a[0] > clear_mps2:
                    return high, "peak"
                rising, low = False, k
        elif s[k] < s[low]:
            low = k
        elif s[k] >= s[low] + drop_deg:
            rising, high = True, k
    return None, "not reached" if rising else "falls from the start"


def _vertex(a, s, i, half_width):
    """Where a parabola through the points within ``half_width`` of point ``i`` peaks, if it does there."""
    near = np.abs(a - a[i]) <= half_width
    if near.sum() >= 4:
        c2, c1, _ = np.polyfit(a[near] - a[i], s[near], 2)
        if c2 < 0 and abs(-c1 / (2 * c2)) <= half_width:
            return float(a[i] - c1 / (2 * c2))
    return float(a[i])


@dataclass(frozen=True)
class SteerBand(PlainResult):
    """The understeer gradient over one band of lateral acceleration.

    Attributes
    ----------
    low_mps2, high_mps2 : float
        The band of lateral acceleration [m/s^2]: whole multiples of the band width, or the record's ends.
    gradient_deg_per_g : float
        Slope of road-wheel steer against ``a_y / g`` over the band [deg/g] (positive: understeer).
    intercept_deg : float
        The band's line at ``a_y = 0`` [deg].
    behaviour : str
        ``"understeer"``, ``"neutral"`` or ``"oversteer"`` (:func:`behaviour`).
    """

    low_mps2: float
    high_mps2: float
    gradient_deg_per_g: float
    intercept_deg: float
    behaviour: str


_COLOURS = {"understeer": "tab:blue", "neutral": "tab:green", "oversteer": "tab:orange"}


@dataclass(frozen=True, eq=False)
class SteerShape(PlainResult):
    """The shape of a steer curve, as defined in :func:`steer_shape`.

    Attributes
    ----------
    bands : tuple of SteerBand
        Understeer gradient by band of lateral acceleration, in rising ``a_y``.
    neutral_steer_lateral_acceleration_mps2, neutral_steer_deg : float
        Where the steer stops rising (the peak of the steer curve) [m/s^2] and the steer there [deg]; NaN
        when there is no peak.
    neutral_steer : str
        ``"peak"`` (found), ``"not reached"`` (the steer still rises at the end of the record, or stays
        within ``peak_drop_deg`` throughout) or ``"falls from the start"`` (the steer never rises: oversteer
        from the lowest ``a_y`` of the record).
    limit_behaviour : str
        ``"understeer"``, ``"neutral"`` or ``"oversteer"``: the sign of the gradient over the last stretch of
        the record (within the tolerance).
    limit_gradient_deg_per_g, limit_low_mps2, limit_high_mps2 : float
        That gradient [deg/g] and the stretch it is fitted over [m/s^2].
    band_width_mps2, neutral_tolerance_deg_per_g : float
        Settings: the bands' width [m/s^2]; the tolerance of ``"neutral"`` [deg/g].
    curve_ay_mps2, curve_steer_deg : ndarray
        The measured steer curve (:func:`steer_curve`) [m/s^2, deg].
    """

    bands: tuple[SteerBand, ...]
    neutral_steer_lateral_acceleration_mps2: float
    neutral_steer_deg: float
    neutral_steer: str
    limit_behaviour: str
    limit_gradient_deg_per_g: float
    limit_low_mps2: float
    limit_high_mps2: float
    band_width_mps2: float
    neutral_tolerance_deg_per_g: float
    curve_ay_mps2: np.ndarray
    curve_steer_deg: np.ndarray

    def mark(self, ax) -> None:
        """Draw the bands' lines (coloured by behaviour) and the neutral-steer point on a steer [deg]
        against lateral acceleration [m/s^2] axes.

        Parameters
        ----------
        ax : matplotlib.axes.Axes
            Axes of steer [deg] against lateral acceleration [m/s^2].
        """
        seen = set()
        for band in self.bands:
            a = np.array([band.low_mps2, band.high_mps2])
            label = None if band.behaviour in seen else f"band gradient: {band.behaviour}"
            seen.add(band.behaviour)
            ax.plot(a, band.intercept_deg + band.gradient_deg_per_g * a / G, "-", lw=2.2, alpha=0.75,
                    color=_COLOURS[band.behaviour], label=label)
        if self.neutral_steer == "peak":
            a0 = self.neutral_steer_lateral_acceleration_mps2
            ax.plot([a0], [self.neutral_steer_deg], "*", ms=13, color="tab:red", zorder=5,
                    label=f"neutral steer: {a0:.2f} m/s²")
            ax.axvline(a0, color="tab:red", lw=0.8, ls=":")
        ax.axvspan(self.limit_low_mps2, self.limit_high_mps2, color=_COLOURS[self.limit_behaviour], alpha=0.12,
                   label=f"limit: {self.limit_behaviour} ({self.limit_gradient_deg_per_g:+.2f} deg/g)")


def steer_shape(lateral_acceleration_mps2, road_steer_deg, *, band_width_mps2=BAND_WIDTH_MPS2,
                limit_band_mps2=LIMIT_BAND_MPS2, neutral_tolerance_deg_per_g=NEUTRAL_TOLERANCE_DEG_PER_G,
                bin_mps2=BIN_MPS2, peak_drop_deg=PEAK_DROP_DEG) -> SteerShape:
    """The shape of the steer curve of a constant-radius test: gradients by band, neutral steer, the limit.

    Steps (the module's docstring gives the reasons): (1) fold to a left turn; (2) the steer curve, means
    over bins ``min(bin_mps2, range / 10)`` wide (:func:`steer_curve`); (3) straight lines through it by
    band (:func:`band_gradients`); (4) the first peak of the curve smoothed by local quadratics over
    +-0.3 m/s^2 (:func:`local_quadratic`, :func:`first_peak`), refined to the vertex of a parabola through
    the unsmoothed curve within 0.3 m/s^2 of it: the neutral-steer lateral acceleration; (5) the limit
    gradient, a line through the curve's points in the last ``min(limit_band_mps2, range / 4)`` of
    lateral acceleration below the largest one, and its :func:`behaviour`.

    Parameters
    ----------
    lateral_acceleration_mps2 : array_like
        Lateral acceleration of quasi-steady samples [m/s^2], one turn direction.
    road_steer_deg : array_like
        Road-wheel steer [deg], one per sample (at constant radius, or corrected to it).
    band_width_mps2, limit_band_mps2 : float
        Width of the gradient bands; length of the last stretch that gives the limit behaviour [m/s^2].
    neutral_tolerance_deg_per_g : float
        Gradients within +- this are neutral [deg/g].
    bin_mps2 : float
        Bin width of the steer curve [m/s^2].
    peak_drop_deg : float
        Rise before and fall after a peak that make it one [deg].

    Returns
    -------
    SteerShape
        Bands, neutral steer and limit behaviour.

    Raises
    ------
    InputError
        Mismatched or non-finite arrays, a record that mixes turn directions, or a steer curve of fewer
        than 5 bins.
    """
    n = np.size(lateral_acceleration_mps2)
    ay = as_values(lateral_acceleration_mps2, n, "lateral_acceleration_mps2")
    steer = as_values(road_steer_deg, n, "road_steer_deg")
    for value, where in ((band_width_mps2, "band_width_mps2"), (limit_band_mps2, "limit_band_mps2"),
                         (bin_mps2, "bin_mps2"), (peak_drop_deg, "peak_drop_deg")):
        positive(value, where)
    tolerance = float(neutral_tolerance_deg_per_g)
    if not (math.isfinite(tolerance) and tolerance >= 0):
        raise InputError(f"must be a finite number >= 0, got {tolerance}", "neutral_tolerance_deg_per_g")
    direction = 1.0 if ay.mean() >= 0 else -1.0
    a, s = direction * ay, direction * steer
    a_max = float(a.max())
    if a_max <= 0 or a.min() < -0.25 * a_max:
        raise InputError("the record mixes left and right turns (or has no lateral acceleration); analyse "
                         "each turn direction separately", "lateral_acceleration_mps2")
    span = a_max - float(a.min())
    a_c, s_c, _ = steer_curve(a, s, bin_mps2=min(bin_mps2, span / 10) if span > 0 else bin_mps2)
    if a_c.size < 5:
        raise InputError(f"the steer curve has {a_c.size} bins of at least {MIN_BIN_SAMPLES} samples; it needs 5: "
                         "a longer record or a wider range of lateral acceleration", "lateral_acceleration_mps2")
    bands = tuple(SteerBand(lo, hi, k, c, behaviour(k, tolerance)) for lo, hi, k, c in
                  band_gradients(a_c, s_c, band_width_mps2=band_width_mps2, a_range_mps2=(a.min(), a_max)))
    peak, status = first_peak(a_c, local_quadratic(a_c, s_c), drop_deg=peak_drop_deg)
    if peak is None:
        a0 = s0 = math.nan
    else:
        a0 = _vertex(a_c, s_c, peak, SMOOTH_HALF_WIDTH_MPS2)
        near = np.abs(a_c - a0) <= SMOOTH_HALF_WIDTH_MPS2
        s0 = float(np.polyval(np.polyfit(a_c[near], s_c[near], 2), a0)) if near.sum() >= 4 else float(s_c[peak])
    limit_low = a_max - min(limit_band_mps2, span / 4)
    last = a_c >= limit_low
    if last.sum() < 3:
        last = np.arange(a_c.size) >= a_c.size - 3
    k_limit, _ = line_fit(a_c[last], s_c[last])
    return SteerShape(
        bands=bands, neutral_steer_lateral_acceleration_mps2=float(a0), neutral_steer_deg=float(s0),
        neutral_steer=status, limit_behaviour=behaviour(k_limit, tolerance), limit_gradient_deg_per_g=k_limit,
        limit_low_mps2=float(min(limit_low, a_c[last].min())), limit_high_mps2=a_max,
        band_width_mps2=float(band_width_mps2), neutral_tolerance_deg_per_g=tolerance,
        curve_ay_mps2=a_c, curve_steer_deg=s_c)
