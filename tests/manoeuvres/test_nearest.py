"""Path.track's compiled nearest-point search and foot refinement (``manoeuvres/_nearest.py``) against plain
references to the last bit: the windowed search as the float loop it was, the feet as the array expressions they
were."""

import numpy as np
import pytest

from trikedyn.manoeuvres import circle, double_lane_change, single_lane_change
from trikedyn.manoeuvres._nearest import feet, track_indices


def _reference_indices(xm, ym, px, py, back, ahead):
    """The first of the nearest points in the window, by the float comparison (NaN and inf never win; with
    nothing finite the window's first point)."""
    out = np.empty(px.size, dtype=np.int64)
    j = 0
    for k in range(px.size):
        lo, hi = max(j - back, 0), min(j + ahead, xm.size)
        d2 = (xm[lo:hi] - px[k]) ** 2 + (ym[lo:hi] - py[k]) ** 2
        finite = d2 < np.inf
        best = int(np.flatnonzero(d2 == d2[finite].min())[0]) if finite.any() else 0
        j = lo + best
        out[k] = j
    return out


def _reference_feet(path, i, px, py):
    """The numpy refinement of ``Path._foot`` until it was compiled."""
    n = path.x_m.size
    best_s = np.full_like(px, np.nan)
    best_off = np.full_like(px, np.nan)
    best_d2 = np.full_like(px, np.inf)
    for a in (np.maximum(i - 1, 0), np.minimum(i, n - 2)):
        b = a + 1
        ex = path.x_m[b] - path.x_m[a]
        ey = path.y_m[b] - path.y_m[a]
        seg = np.hypot(ex, ey)
        ux, uy = ex / seg, ey / seg
        rx, ry = px - path.x_m[a], py - path.y_m[a]
        along = rx * ux + ry * uy
        t = np.clip(along / seg, 0.0, 1.0)
        d2 = (rx - t * ex) ** 2 + (ry - t * ey) ** 2
        better = d2 < best_d2
        best_d2 = np.where(better, d2, best_d2)
        best_s = np.where(better, path.s_m[a] + t * (path.s_m[b] - path.s_m[a]), best_s)
        best_off = np.where(better, ux * ry - uy * rx, best_off)
    return best_s, best_off


def test_the_windowed_search_equals_the_float_loop_on_random_lines():
    """Rounded coordinates make ties; NaN and inf positions and line points, empty windows."""
    rng = np.random.default_rng(3)
    for _ in range(400):
        n = int(rng.integers(1, 60))
        xm, ym = np.round(rng.normal(size=n), 1), np.round(rng.normal(size=n), 1)
        px, py = np.round(rng.normal(size=40), 1), np.round(rng.normal(size=40), 1)
        px[rng.random(40) < 0.1] = np.nan
        py[rng.random(40) < 0.05] = np.inf
        xm[rng.random(n) < 0.1] = np.nan
        back, ahead = int(rng.integers(0, 5)), int(rng.integers(0, 20))
        np.testing.assert_array_equal(track_indices(xm, ym, px, py, back, ahead),
                                      _reference_indices(xm, ym, px, py, back, ahead))


@pytest.mark.parametrize("path", [double_lane_change(1.25), single_lane_change(), circle(20.0, laps=2.0)],
                         ids=["dlc", "slc", "circle"])
def test_track_equals_the_references_along_a_wandering_drive(path):
    rng = np.random.default_rng(5)
    m = 1800
    i = np.linspace(0, path.x_m.size - 1, m).astype(int)
    off = 1.5 * np.sin(np.linspace(0, 9, m) + rng.uniform(0, 6)) + rng.normal(0, 0.01, m)
    px = path.x_m[i] - off * np.sin(path.heading_rad[i])
    py = path.y_m[i] + off * np.cos(path.heading_rad[i])
    idx = track_indices(path.x_m, path.y_m, px, py, 40, 400)
    np.testing.assert_array_equal(idx, _reference_indices(path.x_m, path.y_m, px, py, 40, 400))
    s, offset = path.track(px, py)
    ref_s, ref_off = _reference_feet(path, idx, px, py)
    np.testing.assert_array_equal(s, ref_s, strict=True)
    np.testing.assert_array_equal(offset, ref_off, strict=True)
    assert np.all(np.diff(s) > -0.05)  # progress along the line, lap after lap on the circle
    ends = np.array([0, path.x_m.size - 1, path.x_m.size - 2, 1])  # the clamped end segments
    got = feet(path.x_m, path.y_m, path.s_m, ends, px[:4] + 100.0, py[:4])
    for a, b in zip(got, _reference_feet(path, ends, px[:4] + 100.0, py[:4]), strict=True):
        np.testing.assert_array_equal(a, b, strict=True)
