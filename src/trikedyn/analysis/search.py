"""Where a threshold search looks next: a continuous margin, extrapolated to zero, certified on a grid.

The pass/fail verdict of a run is a step in speed; the smallest wheel load behind it is not. Every run
yields a **margin table** (:func:`margin_table`): the minimum vertical force [N] of each wheel in each of
``BINS`` stretches of the judged window (by distance along the path for a closed-loop manoeuvre, by time
otherwise; the run-in before the entry gate is one more stretch). An entry falls smoothly with speed
while the dip it holds stays in its stretch (each entry is read as the minimum over its neighbours too,
so that a dip moving a little with speed stays in view), even where the overall minimum jumps from one
dip to another, as when a later, steeper dip overtakes an earlier, shallower one.

**Signed extension.** A run that lifts a wheel keeps the entries before the lift; the lifting wheel's
stretch gets the depth its load would have dipped to below zero, ``F' T / 4`` [N] (``F'`` the rate of fall
through zero [N/s], ``T`` the time the wheel stayed up: the depth of a parabolic dip of that slope and
width, :func:`_virtual_dip`); later entries are unknown. The margin is thus continuous through zero at
the threshold and negative above it, so that regula-falsi steps work across it.

**Estimate** (:func:`predicted_crossing`). Each entry's zero is predicted in ``v^2`` (the load an axle
transfers grows with the lateral acceleration, ``v^2`` times the path's curvature): by the straight line
through its two highest passing speeds, or through its static load at ``v = 0`` and the one passing speed
known; with a failing speed above that line's zero, by the secant (regula falsi) from the highest pass
to the failure's negative value, weighted by ``NEG_WEIGHT`` (the load falls more steeply beyond the lift
than before it) and Illinois-corrected (the weight doubles after two failures in a row, halves after two
passes). With failures only, by the secant from the static load. The estimate is the lowest predicted
zero.

**Search** (:func:`margin_search`). The first run is at ``SEED_FRACTION`` of the static tip-over speed in
the manoeuvre's tightest curve (:func:`seed_speed`: the rigid vehicle's tip-over lateral acceleration of
:func:`trikedyn.params.audit.tip_over_thresholds` over the largest curvature in the window). While no
run has failed, the next goes to the estimate, only ``FIRST_STEP`` of the way after the first run (its
line from ``v = 0`` reaches far); while none has passed, to the estimate but ``DOWN`` of the failing speed
at most. Once bracketed, the next run is at the grid speed below the estimate (after a pass) or nearest to
it (after a failure), inside the bracket; halfway across at least when two runs in a row crept up on the
crossing from the same side (by less than ``1 / CRAWL`` of the bracket), and bisection when the bracket
stops halving. The paper's 50 scenarios take a median of 5 runs (4 to 9), bisection 12.

The estimate only chooses where to look: the answer is certified like a bisection's, by a passing run at a
grid speed and a failing run one grid step above it (or a failing ``low_kmh``, or a passing ``high_kmh``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .margins import BINS, margin_table

__all__ = ["BINS", "SEED_FRACTION", "Grid", "Probe", "SearchOutcome", "margin_search", "margin_table",
           "predicted_crossing", "seed_speed"]

SEED_FRACTION = 0.7
"""First speed tried, as a fraction of the static tip-over speed in the manoeuvre's tightest curve [-]
(the paper's e-trike: thresholds at 0.68-0.82 of it in the lane changes)."""

FIRST_STEP = 0.6
"""Fraction of the way to the first estimate (a line from the static load, which overshoots) [-]."""

FAR_KMH = 1.5
"""The first step is shortened only when the estimate is farther than this above the first run [km/h]."""

DOWN = 0.9
"""While nothing has passed, each run is at this fraction of the lowest failing speed at most [-]."""

NEG_WEIGHT = 0.5
"""Initial weight of a failure's negative margin in the secant [-]."""

CRAWL = 8
"""Two runs in a row on the same side that moved less than 1/CRAWL of the bracket: the next goes at least
halfway across it."""

SPAN = 1
"""Neighbouring stretches (each side) an entry of the margin table also covers."""


@dataclass(frozen=True)
class Grid:
    """The speeds a search may report: ``low_kmh + k * resolution_kmh``, the last one ``high_kmh`` [km/h]."""

    low_kmh: float
    high_kmh: float
    resolution_kmh: float

    @property
    def last(self) -> int:
        """Index of ``high_kmh``."""
        return max(1, math.ceil((self.high_kmh - self.low_kmh) / self.resolution_kmh - 1e-9))

    def speed(self, k: int) -> float:
        """Speed of index ``k`` [km/h], rounded to 1e-6 km/h.

        Parameters
        ----------
        k : int
            Grid index.

        Returns
        -------
        float
            Speed [km/h].
        """
        if k >= self.last:
            return round(self.high_kmh, 6)
        return round(self.low_kmh + k * self.resolution_kmh, 6)

    def index_below(self, speed_kmh: float) -> int:
        """Highest index at or below ``speed_kmh`` (may be -1 or beyond ``last``).

        Parameters
        ----------
        speed_kmh : float
            Speed [km/h].

        Returns
        -------
        int
            The index.
        """
        return math.floor((speed_kmh - self.low_kmh) / self.resolution_kmh + 1e-9)


@dataclass(frozen=True)
class Probe:
    """One run as the search sees it: its verdict, its margin table [N] (wheels x stretches; NaN unknown)
    and the wheels' static loads [N], or None when the run gave no loads."""

    speed_kmh: float
    passed: bool
    margins: np.ndarray | None = None
    static_N: np.ndarray | None = None

    @property
    def margin_N(self) -> float | None:
        """The signed margin [N]: the smallest entry of the table (negative when a wheel lifted)."""
        if self.margins is None or not np.isfinite(self.margins).any():
            return None
        return float(np.nanmin(self.margins))


@dataclass(frozen=True)
class SearchOutcome:
    """Indices of the certified pair: ``passed`` (None when ``low_kmh`` fails) and ``failed`` (None when
    ``high_kmh`` passes), and the estimates [km/h] made before each probe (None: none possible)."""

    passed: int | None
    failed: int | None
    estimates: tuple[float | None, ...]


# ------------------------------------------------------------------------------------------------------------
# the first guess
# ------------------------------------------------------------------------------------------------------------
def seed_speed(params, manoeuvre) -> float | None:
    """The static tip-over speed in the manoeuvre's tightest curve [km/h], or None when it has none.

    ``v = sqrt(a_tip / kappa_max)``: ``a_tip`` the smallest lateral acceleration that tips the rigid
    vehicle about an edge of its support triangle [m/s^2], ``kappa_max`` the largest |curvature| of the
    path inside the judged window [1/m] (open loop: the largest steer angle over the wheelbase).

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    manoeuvre : Manoeuvre
        The manoeuvre (its path or steer).

    Returns
    -------
    float or None
        Speed [km/h].
    """
    from ..params.audit import tip_over_thresholds

    edges = [e for e in tip_over_thresholds(params) if e["lateral"] and e["acceleration_g"] > 0]
    if not edges:
        return None
    a_tip = min(e["acceleration_g"] for e in edges) * 9.80665
    kappa = 0.0
    if manoeuvre.steer is not None:
        kappa = float(np.abs(manoeuvre.steer[:, 1]).max()) / max(float(params.wheelbase_m), 1e-3)
    elif manoeuvre.path is not None:
        path, w = manoeuvre.path, manoeuvre.window
        inside = (path.s_m >= w.start) & (path.s_m <= w.end) if w.kind == "distance" else np.ones(path.s_m.size, bool)
        if inside.any():
            kappa = float(np.abs(path.curvature_per_m[inside]).max())
    if not (kappa > 0 and math.isfinite(kappa)):
        return None
    return math.sqrt(a_tip / kappa) * 3.6


# ------------------------------------------------------------------------------------------------------------
# the estimate
# ------------------------------------------------------------------------------------------------------------
def predicted_crossing(probes: list[Probe], weight: float = 1.0) -> float | None:
    """Lowest predicted zero of the margin table's entries [km/h] (see the module docstring), or None.

    All entries are predicted at once (:func:`_crossings`); each gets the value the per-entry rule
    :func:`_crossing` gives it, to the last bit (a table that is not of float64 goes entry by entry).

    Parameters
    ----------
    probes : list of Probe
        The runs so far.
    weight : float
        Weight of the nearest runs in the fit, dimensionless.

    Returns
    -------
    float or None
        Speed [km/h].
    """
    usable = [p for p in probes if p.margins is not None]
    if not usable:
        return None
    shape = usable[0].margins.shape
    usable = [p for p in usable if p.margins.shape == shape]
    order = sorted(usable, key=lambda p: p.speed_kmh)
    v2 = np.array([p.speed_kmh for p in order]) ** 2
    table = _neighbourhood(np.stack([p.margins for p in order]), SPAN)  # (runs, wheels, stretches)
    static = next((p.static_N for p in order if p.static_N is not None), None)
    if table.dtype != np.float64 or table.ndim != 3 or v2.dtype != np.float64:
        best = math.inf
        for w in range(shape[0]):
            for b in range(shape[1]):
                z = _crossing(v2, table[:, w, b], None if static is None else float(static[w]), weight)
                if z is not None:
                    best = min(best, z)
        return math.sqrt(best) if math.isfinite(best) and best > 0 else None
    runs, wheels, stretches = table.shape
    if static is None or not stretches:
        anchor = None
    else:  # each wheel's static load [N], once per stretch
        anchor = np.repeat(np.array([float(static[w]) for w in range(wheels)]), stretches)
    z = _crossings(v2, table.reshape(runs, wheels * stretches), anchor, weight)
    z = z[z < math.inf]  # None (NaN) and +inf never lower the minimum
    best = z.min() if z.size else math.inf
    return math.sqrt(best) if math.isfinite(best) and best > 0 else None


def _neighbourhood(table: np.ndarray, span: int) -> np.ndarray:
    """Each entry replaced by the minimum over ``span`` stretches each side (same wheel): a dip that moves
    a little along the manoeuvre from one speed to the next stays in every entry that saw it. Unknown
    (NaN) when a neighbour is unknown, unless a known neighbour is already negative."""
    if span <= 0:
        return table
    finite = np.isfinite(table)
    values = np.where(finite, table, np.inf)
    low, known = values.copy(), finite.copy()
    for k in range(1, min(span, table.shape[-1] - 1) + 1):  # the neighbours k stretches before and after
        np.minimum(low[..., k:], values[..., :-k], out=low[..., k:])
        np.minimum(low[..., :-k], values[..., k:], out=low[..., :-k])
        known[..., k:] &= finite[..., :-k]
        known[..., :-k] &= finite[..., k:]
    out = np.empty_like(table)
    out[...] = np.where(~known & ~(low <= 0) | ~np.isfinite(low), np.nan, low)
    return out


def _crossing(v2: np.ndarray, m: np.ndarray, static: float | None, weight: float) -> float | None:
    """Predicted ``v^2`` [km^2/h^2] at which one entry reaches zero, from its values ``m`` [N] at ``v2``
    (ascending; NaN unknown), its static load [N] and the weight of negative values."""
    known = np.isfinite(m)
    pos = np.nonzero(known & (m > 0))[0]
    anchor = static is not None and static > 0
    if not pos.size:  # failures only: the secant from the static load at v = 0
        neg = np.nonzero(known)[0]
        if not neg.size or not anchor:
            return None
        return v2[neg[0]] * static / (static - weight * m[neg[0]])
    vb, mb = v2[pos[-1]], m[pos[-1]]
    line = None
    if pos.size >= 2:
        va, ma = v2[pos[-2]], m[pos[-2]]
    elif anchor and vb > 0:
        va, ma = 0.0, static
    else:
        va, ma = vb, mb
    if ma > mb and vb > va:  # falling: the line through the two highest passes
        line = vb + mb * (vb - va) / (ma - mb)
    neg = np.nonzero(known & (m <= 0) & (v2 > vb))[0]
    if not neg.size:
        return line
    vc, mc = v2[neg[0]], weight * m[neg[0]]
    if pos.size >= 2 and line is not None and line < vc:  # two passes foresee it before the failure
        return line
    return vb + mb * (vc - vb) / (mb - mc)  # regula falsi to the nearest failure


def _crossings(v2: np.ndarray, m: np.ndarray, static: np.ndarray | None, weight: float) -> np.ndarray:
    """:func:`_crossing` of every entry at once: ``m`` [N] is (runs, entries) of float64, ``static`` [N]
    one load per entry or None; NaN where :func:`_crossing` gives None. Each branch is taken where
    :func:`_crossing` takes it, with the same operations in the same order."""
    runs, entries = m.shape
    cols = np.arange(entries)
    known = np.isfinite(m)
    passing = known & (m > 0)
    count = np.cumsum(passing, axis=0)
    npos = count[-1]
    ib = np.argmax(passing & (count == npos), axis=0)  # the highest pass (where there is one)
    ia = np.argmax(passing & (count == npos - 1), axis=0)  # the one below it (where there are two)
    anchor = np.zeros(entries, bool) if static is None else static > 0
    s = np.zeros(entries) if static is None else static
    z = np.full(entries, np.nan)
    with np.errstate(all="ignore"):  # every branch is evaluated on every entry; only its own are kept
        # failures only: the secant from the static load at v = 0
        first = np.argmax(known, axis=0)
        only = (npos == 0) & known[first, cols] & anchor
        mf = m[first, cols]
        z[only] = (v2[first] * s / (s - weight * mf))[only]
        # the line through the two highest passes, or from the static load, where it falls
        vb, mb = v2[ib], m[ib, cols]
        two = npos >= 2
        from_static = ~two & anchor & (vb > 0)
        va = np.where(two, v2[ia], np.where(from_static, 0.0, vb))
        ma = np.where(two, m[ia, cols], np.where(from_static, s, mb))
        falling = (ma > mb) & (vb > va)
        line = vb + mb * (vb - va) / (ma - mb)
        # the nearest failure above the highest pass
        failing = known & (m <= 0) & (v2[:, None] > vb)
        ic = np.argmax(failing, axis=0)
        fails = failing[ic, cols]
        vc, mc = v2[ic], weight * m[ic, cols]
        secant = vb + mb * (vc - vb) / (mb - mc)
        some = npos > 0
        use_line = some & falling & (~fails | two & (line < vc))
        z[use_line] = line[use_line]
        use_secant = some & fails & ~(two & falling & (line < vc))
        z[use_secant] = secant[use_secant]
    return z


# ------------------------------------------------------------------------------------------------------------
# the search
# ------------------------------------------------------------------------------------------------------------
def margin_search(probe: Callable[[float], Probe], grid: Grid, *, seed_kmh: float | None = None,
                  step_kmh: float = 10.0) -> SearchOutcome:
    """Find a passing grid speed with a failing one a grid step above it, guided by the margin.

    Parameters
    ----------
    probe : callable
        ``probe(speed_kmh) -> Probe``: runs the manoeuvre at that speed.
    grid : Grid
        The speeds [km/h] that may be tried and reported.
    seed_kmh : float, optional
        The static tip-over speed in the manoeuvre's tightest curve [km/h] (:func:`seed_speed`); the first
        run is at ``SEED_FRACTION`` of it. Without it the first run is at ``low_kmh + step_kmh``.
    step_kmh : float
        Rise [km/h] when the margin gives no estimate and nothing has failed yet.

    Returns
    -------
    SearchOutcome
    """
    last = grid.last
    step = max(1, round(step_kmh / grid.resolution_kmh))
    probes: list[Probe] = []
    estimates: list[float | None] = [None]
    lo, hi = -1, last + 1  # highest index known to pass, lowest known to fail (-1, last + 1: none yet)
    widths: list[int] = []
    weight = NEG_WEIGHT
    tried: list[int] = []
    if seed_kmh is not None and math.isfinite(seed_kmh) and seed_kmh > 0:
        k = min(max(grid.index_below(SEED_FRACTION * seed_kmh), 0), last)
    else:
        k = min(step, last)
    tried.append(k)
    while True:
        result = probe(grid.speed(k))
        if probes and lo >= 0 and hi <= last and result.passed == probes[-1].passed:
            weight = weight / 2 if result.passed else weight * 2  # Illinois: the side kept twice weighs less
        probes.append(result)
        if result.passed:
            lo = k
        else:
            hi = k
        if hi - lo <= 1:
            break
        z = predicted_crossing(probes, weight)
        estimates.append(z)
        if lo >= 0 and hi <= last:
            widths.append(hi - lo)
        if lo < 0:  # nothing has passed yet: down to the estimate, by DOWN at least
            k = grid.index_below(DOWN * grid.speed(hi))
            if z is not None:
                k = min(k, grid.index_below(z))
        elif len(widths) >= 3 and widths[-1] > widths[-3] / 2:
            k = (lo + hi) // 2  # the estimate is not closing the bracket: bisect
        elif z is None:
            k = min(lo + step, last) if hi > last else (lo + hi) // 2
        else:
            if hi > last and len(probes) == 1 and z - grid.speed(lo) > FAR_KMH:
                z = grid.speed(lo) + FIRST_STEP * (z - grid.speed(lo))
            # below the estimate after a pass; nearest to it after a failure (the secant to a failure's
            # steeper negative side falls short)
            k = grid.index_below(z if result.passed else z + 0.5 * grid.resolution_kmh)
            if lo >= 0 and hi <= last and probes[-2].passed == result.passed \
                    and CRAWL * abs(tried[-1] - tried[-2]) < hi - lo:
                # creeping up on the crossing from one side in a wide bracket: at least halfway across
                middle = (lo + hi) // 2
                k = max(k, middle) if result.passed else min(k, middle)
        k = min(max(k, lo + 1), hi - 1)
        tried.append(k)
    return SearchOutcome(lo if lo >= 0 else None, hi if hi <= last else None, tuple(estimates))
