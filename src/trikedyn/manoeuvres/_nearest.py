"""The nearest-point search of :meth:`trikedyn.manoeuvres.geometry.Path.track`, compiled (imported lazily:
loading the manoeuvres does not load numba)."""

from __future__ import annotations

import numpy as np

from .._jit import jit


@jit
def track_indices(xm, ym, px, py, back, ahead):
    """Index of the line point nearest to each ``(px[k], py[k])``, searched from ``back`` points behind to
    ``ahead`` points ahead of the previous one (the first search starts at point 0)."""
    n = xm.size
    out = np.empty(px.size, dtype=np.int64)
    j = 0
    for k in range(px.size):
        lo = max(j - back, 0)
        hi = min(j + ahead, n)
        best = lo
        dbest = np.inf
        for i in range(lo, hi):
            d = (xm[i] - px[k]) ** 2 + (ym[i] - py[k]) ** 2
            if d < dbest:
                dbest = d
                best = i
        j = best
        out[k] = j
    return out
