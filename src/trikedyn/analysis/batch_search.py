"""A threshold search that tries several speeds at once: one lockstep batch a round.

The margin search (:mod:`trikedyn.analysis.search`) chooses one run at a time from the runs before it.
Here each round is a batch of ``lanes`` speeds (run together by :mod:`trikedyn.simulate.batch`), chosen from
every run made so far:

- **first round**: ``lanes`` speeds spread evenly over ``FIRST_SPREAD`` of the static tip-over speed in the
  manoeuvre's tightest curve (:func:`~trikedyn.analysis.search.seed_speed`; the paper's lane-change
  thresholds lie at 0.68-0.82 of it); without one, ``lanes`` speeds ``step_kmh`` apart from ``low_kmh``;
- **later rounds**: ``DENSE`` of the lanes on the grid speeds nearest the margin's predicted crossing
  (:func:`~trikedyn.analysis.search.predicted_crossing`), the others spread evenly over the bracket, so
  that a round certifies the answer when the estimate is good and shrinks the bracket ``lanes``-fold when it
  is not; while nothing has failed, the spread goes up from the highest pass (``step_kmh`` apart, beyond
  the estimate); while nothing has passed, down from the lowest failure (by factors of ``DOWN``).

The answer is certified as the other searches': a passing grid speed with a failing one a grid step above
it (the lowest failure and the highest pass below it), a failing ``low_kmh`` or a passing ``high_kmh``;
where the crossing is single, the same threshold. A search costs more runs than the margin search's (it
guesses before it knows) in fewer rounds.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from .search import DOWN, NEG_WEIGHT, Grid, Probe, SearchOutcome, predicted_crossing

__all__ = ["DENSE", "FIRST_SPREAD", "LANES", "batch_margin_search"]

LANES = 4
"""Speeds a round tries by default."""

FIRST_SPREAD = (0.6, 0.88)
"""The first round's speeds, as fractions of the static tip-over speed in the tightest curve [-]."""

DENSE = 0.5
"""Fraction of a round's lanes on the grid speeds nearest the predicted crossing [-]."""


def _spread(first: int, last: int, count: int) -> list[int]:
    """``count`` grid indices spread evenly over ``first..last`` (inclusive), ends included when they fit."""
    if count <= 0 or last < first:
        return []
    if last - first + 1 <= count:
        return list(range(first, last + 1))
    return sorted({int(round(v)) for v in np.linspace(first, last, count + 2)[1:-1]})


def _round(grid: Grid, lo: int, hi: int, z: float | None, lanes: int, step: int) -> list[int]:
    """The grid indices of the next round, strictly inside the bracket ``(lo, hi)`` (``-1``, ``last + 1``:
    open), at most ``lanes`` of them."""
    inside = list(range(lo + 1, hi))
    if len(inside) <= lanes:
        return inside
    near: list[int] = []
    if z is not None:
        kz = min(max(grid.index_below(z), lo + 1), hi - 1)
        dense = max(1, int(round(DENSE * lanes)))
        start = min(max(kz - (dense - 1) // 2, lo + 1), hi - dense)
        near = list(range(start, start + dense))
    rest = lanes - len(near)
    if hi > grid.last:  # nothing failed: rise from the highest pass, beyond the estimate
        base = max(near) if near else lo
        far = [min(base + step * (i + 1), grid.last) for i in range(rest)]
    elif lo < 0:  # nothing passed: fall from the lowest failure
        top = min(near) if near else hi
        far = [max(grid.index_below(DOWN ** (i + 1) * grid.speed(top)), 0) for i in range(rest)]
    else:
        far = _spread(lo + 1, hi - 1, rest + len(near))
        far = [k for k in far if k not in near][:rest]
    chosen = sorted({k for k in near + far if lo < k < hi})
    return chosen[:lanes]


def batch_margin_search(probe_many: Callable[[Sequence[float]], list[Probe]], grid: Grid, *,
                        seed_kmh: float | None = None, step_kmh: float = 10.0, lanes: int = LANES) -> SearchOutcome:
    """Find a passing grid speed with a failing one a grid step above it, ``lanes`` runs a round.

    Parameters
    ----------
    probe_many : callable
        ``probe_many(speeds_kmh) -> list of Probe``: runs the manoeuvre at those speeds (one batch).
    grid : Grid
        The speeds [km/h] that may be tried and reported.
    seed_kmh : float, optional
        The static tip-over speed in the manoeuvre's tightest curve [km/h]
        (:func:`~trikedyn.analysis.search.seed_speed`).
    step_kmh : float
        Spacing [km/h] of the speeds tried while nothing has failed, and of the first round without a seed.
    lanes : int
        Speeds a round (>= 1).

    Returns
    -------
    SearchOutcome
        The certified pair; ``estimates`` holds the predicted crossing [km/h] before each round.
    """
    last = grid.last
    lanes = max(1, int(lanes))
    step = max(1, round(step_kmh / grid.resolution_kmh))
    if seed_kmh is not None and np.isfinite(seed_kmh) and seed_kmh > 0:
        first = [grid.index_below(f * seed_kmh) for f in np.linspace(*FIRST_SPREAD, lanes)]
    else:
        first = [step * (i + 1) for i in range(lanes)]
    ks = sorted({min(max(k, 0), last) for k in first})
    probes: list[Probe] = []
    outcome: dict[int, bool] = {}
    estimates: list[float | None] = [None]
    lo, hi = -1, last + 1
    while True:
        for k, probe in zip(ks, probe_many([grid.speed(k) for k in ks]), strict=True):
            probes.append(probe)
            outcome[k] = probe.passed
        hi = min([k for k, ok in outcome.items() if not ok], default=last + 1)
        lo = max([k for k, ok in outcome.items() if ok and k < hi], default=-1)
        if hi - lo <= 1:
            break
        z = predicted_crossing(probes, NEG_WEIGHT)
        estimates.append(z)
        ks = [k for k in _round(grid, lo, hi, z, lanes, step) if k not in outcome]
        if not ks:  # cannot happen: the bracket's inside holds an untried index
            ks = [(lo + hi) // 2]
    return SearchOutcome(lo if lo >= 0 else None, hi if hi <= last else None, tuple(estimates))
