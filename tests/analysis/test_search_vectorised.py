"""The vectorised estimate (trikedyn.analysis.search.predicted_crossing) equals the per-entry original bit for bit.

``predicted_crossing``, ``_neighbourhood`` and ``_crossing`` below are verbatim copies of the entry-by-entry
implementation the vectorised one replaced (commit 07260dd): on random probe sets (NaN entries, all-negative,
all-positive and mixed tables, ties in speed, probes without a table or with a table of another shape, static
loads absent, zero or negative, weights other than 1, 1 to 8 probes, 2 to 4 wheels, 1 to 60 stretches) the new
function returns the same float, or None, as the copy.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from trikedyn.analysis import search
from trikedyn.analysis.search import SPAN, Probe


# ------------------------------------------------------------------------------------------------------------
# the reference: a verbatim copy of the original implementation
# ------------------------------------------------------------------------------------------------------------
def predicted_crossing(probes: list[Probe], weight: float = 1.0) -> float | None:
    """Lowest predicted zero of the margin table's entries [km/h] (see the module docstring), or None.

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
    best = math.inf
    for w in range(shape[0]):
        for b in range(shape[1]):
            m = table[:, w, b]
            z = _crossing(v2, m, None if static is None else float(static[w]), weight)
            if z is not None:
                best = min(best, z)
    return math.sqrt(best) if math.isfinite(best) and best > 0 else None


def _neighbourhood(table: np.ndarray, span: int) -> np.ndarray:
    """Each entry replaced by the minimum over ``span`` stretches each side (same wheel): a dip that moves
    a little along the manoeuvre from one speed to the next stays in every entry that saw it. Unknown
    (NaN) when a neighbour is unknown, unless a known neighbour is already negative."""
    if span <= 0:
        return table
    n = table.shape[-1]
    out = np.empty_like(table)
    for b in range(n):
        part = table[..., max(0, b - span): b + span + 1]
        low = np.where(np.isfinite(part), part, np.inf).min(axis=-1)
        unknown = ~np.isfinite(part).all(axis=-1) & ~(low <= 0)
        out[..., b] = np.where(unknown | ~np.isfinite(low), np.nan, low)
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


# ------------------------------------------------------------------------------------------------------------
# random probe sets
# ------------------------------------------------------------------------------------------------------------
def _same(new, old):
    """Equal to the last bit (both floats) or both None."""
    if old is None or new is None:
        return old is None and new is None
    return type(new) is type(old) and (new == old or (math.isnan(new) and math.isnan(old)))


def _table(rng, speeds, shape, kind):
    """A margin table [N] per speed [km/h] of the given kind, (runs, wheels, stretches)."""
    runs = len(speeds)
    v = np.asarray(speeds, dtype=float)[:, None, None]
    if kind == "positive":
        t = rng.uniform(1.0, 2000.0, (runs, *shape))
    elif kind == "negative":
        t = -rng.uniform(0.0, 800.0, (runs, *shape))
    elif kind == "noise":
        t = rng.normal(0.0, 500.0, (runs, *shape))
    elif kind == "integers":  # exact zeros and ties among entries
        t = rng.integers(-3, 4, (runs, *shape)).astype(float) * 100.0
    else:  # falling with speed through zero at a crossing of its own per entry, steeper beyond it
        crossing = rng.uniform(20.0, 90.0, shape)
        base = rng.uniform(200.0, 2000.0, shape)
        t = base * (1.0 - (v / crossing) ** (2 * rng.uniform(0.7, 2.0)))
        t = np.where(t > 0, t, rng.uniform(0.05, 8.0) * t) + rng.normal(0.0, rng.choice([0.0, 5.0, 50.0]), t.shape)
    if rng.random() < 0.5:  # unknown entries: scattered, and after a lift (the rest of a failing run)
        t[rng.random(t.shape) < rng.choice([0.05, 0.3, 0.8])] = np.nan
    if rng.random() < 0.3:
        for r in range(runs):
            if rng.random() < 0.5:
                t[r, :, rng.integers(0, shape[1]):] = np.nan
    if rng.random() < 0.1:
        t[rng.random(t.shape) < 0.05] = rng.choice([np.inf, -np.inf])
    if rng.random() < 0.1:
        t[rng.random(t.shape) < 0.2] = 0.0
    return t


def _probes(rng):
    """1 to 8 probes of one random kind (see the module docstring)."""
    n = int(rng.integers(1, 9))
    wheels, stretches = int(rng.integers(2, 5)), int(rng.integers(1, 61))
    if rng.random() < 0.3:  # ties in speed
        speeds = list(rng.choice([30.0, 41.5, 52.25, 60.0], n))
    else:
        speeds = list(np.round(rng.uniform(5.0, 95.0, n), int(rng.integers(1, 7))))
    if rng.random() < 0.05:
        speeds[0] = 0.0
    kind = rng.choice(["positive", "negative", "noise", "integers", "falling", "falling", "falling"])
    table = _table(rng, speeds, (wheels, stretches), kind)
    probes = []
    for r, v in enumerate(speeds):
        margins = table[r]
        u = rng.random()
        if u < 0.1:
            margins = None
        elif u < 0.2:  # another shape: left out, unless it is the first usable one
            margins = rng.normal(0.0, 500.0, (wheels, max(1, stretches + int(rng.integers(-3, 4)))))
        static = None
        w = rng.random()
        if w < 0.5:
            static = rng.uniform(100.0, 3000.0, wheels)
        elif w < 0.65:
            static = rng.choice([0.0, -250.0, np.nan, 1000.0], wheels)
        passed = bool(margins is not None and np.nanmin(np.where(np.isfinite(margins), margins, np.inf)) > 0)
        probes.append(Probe(float(v), passed, margins, static))
    rng.shuffle(probes)  # the estimate sorts them by speed
    weight = float(rng.choice([1.0, 0.5, 0.25, 2.0, 4.0, rng.uniform(0.01, 5.0)]))
    return probes, weight


@pytest.mark.parametrize("seed", range(8))
def test_equals_the_original_on_random_probe_sets(seed):
    rng = np.random.default_rng(20261202 + seed)
    found = 0
    for _ in range(500):
        probes, weight = _probes(rng)
        old = predicted_crossing(probes, weight)
        new = search.predicted_crossing(probes, weight)
        assert _same(new, old), (old, new, weight, probes)
        found += old is not None
    assert 0 < found < 500  # both outcomes are exercised


@pytest.mark.parametrize("seed", range(3))
def test_every_entry_equals_the_original(seed):
    """Entry by entry (not only the lowest): each predicted zero of _crossings is _crossing's (NaN: None)."""
    rng = np.random.default_rng(seed)
    for _ in range(300):
        probes, weight = _probes(rng)
        usable = [p for p in probes if p.margins is not None]
        if not usable:
            continue
        usable = [p for p in usable if p.margins.shape == usable[0].margins.shape]
        order = sorted(usable, key=lambda p: p.speed_kmh)
        v2 = np.array([p.speed_kmh for p in order]) ** 2
        table = _neighbourhood(np.stack([p.margins for p in order]), SPAN)
        runs, wheels, stretches = table.shape
        static = next((p.static_N for p in order if p.static_N is not None), None)
        anchor = None if static is None else np.repeat(np.asarray(static, dtype=float), stretches)
        z = search._crossings(v2, table.reshape(runs, -1), anchor, weight)
        for e in range(wheels * stretches):
            w, b = divmod(e, stretches)
            old = _crossing(v2, table[:, w, b], None if static is None else float(static[w]), weight)
            assert (math.isnan(z[e]) and old is None) or z[e] == old, (e, z[e], old)


def test_equals_the_original_along_searches():
    """The probe sets a search meets: each prefix of a sequence of runs, at each Illinois weight."""
    rng = np.random.default_rng(7)
    for _ in range(100):
        probes, _ = _probes(rng)
        for k in range(1, len(probes) + 1):
            for weight in (0.125, 0.5, 1.0, 2.0):
                assert _same(search.predicted_crossing(probes[:k], weight), predicted_crossing(probes[:k], weight))


def test_edge_cases():
    one = np.array([[800.0, -10.0, np.nan]] * 2)
    cases = [
        [],
        [Probe(40.0, True)],
        [Probe(40.0, True, one)],
        [Probe(40.0, True, one, np.array([1500.0, 1400.0]))],
        [Probe(40.0, False, -one, np.array([1500.0, 1400.0]))],
        [Probe(40.0, False, -np.abs(one), np.array([0.0, -1.0]))],
        [Probe(40.0, True, np.full((2, 3), np.nan), np.array([1500.0, 1400.0]))],
        [Probe(40.0, True, np.full((2, 3), 500.0)), Probe(50.0, True, np.full((2, 3), 400.0))],
        [Probe(40.0, True, np.full((2, 3), 500.0)), Probe(40.0, True, np.full((2, 3), 400.0))],
        [Probe(50.0, False, np.full((2, 3), -5.0)), Probe(40.0, True, np.full((2, 3), 400.0))],
        [Probe(40.0, True, np.zeros((2, 0)), np.array([1.0, 1.0]))],
        [Probe(40.0, True, np.ones((2, 1)) * 3.0, np.array([1.0, 1.0])), Probe(0.0, True, np.ones((2, 1)))],
    ]
    for probes in cases:
        for weight in (0.5, 1.0, 3.0):
            assert _same(search.predicted_crossing(probes, weight), predicted_crossing(probes, weight))


@pytest.mark.parametrize("dtype", [np.float32, np.int64])
def test_tables_of_other_types_equal_the_original(dtype):
    """float32 or integer tables take the entry-by-entry path: the same answer as before there too."""
    rng = np.random.default_rng(3)
    for _ in range(200):
        probes, weight = _probes(rng)
        probes = [Probe(p.speed_kmh, p.passed, None if p.margins is None else
                        np.nan_to_num(p.margins, nan=-1.0, posinf=5.0, neginf=-5.0).astype(dtype), p.static_N)
                  for p in probes]
        with np.errstate(all="ignore"):
            assert _same(search.predicted_crossing(probes, weight), predicted_crossing(probes, weight))


@pytest.mark.parametrize("span", [0, 1, 2, 3, 70])
def test_neighbourhood_equals_the_original(span):
    rng = np.random.default_rng(span)
    for _ in range(300):
        shape = (int(rng.integers(1, 9)), int(rng.integers(1, 5)), int(rng.integers(1, 61)))
        t = rng.normal(0.0, 500.0, shape)
        t[rng.random(shape) < rng.choice([0.0, 0.1, 0.5])] = np.nan
        t[rng.random(shape) < 0.02] = np.inf
        new, old = search._neighbourhood(t, span), _neighbourhood(t, span)
        assert new.dtype == old.dtype and np.array_equal(new, old, equal_nan=True)


@st.composite
def _probe_sets(draw):
    n = draw(st.integers(1, 8))
    wheels, stretches = draw(st.integers(2, 4)), draw(st.integers(1, 60))
    margin = st.one_of(st.floats(-2000.0, 2000.0, allow_nan=False), st.just(0.0), st.just(math.nan))
    probes = []
    for _ in range(n):
        speed = draw(st.sampled_from([20.0, 35.5, 50.0]) | st.floats(0.0, 120.0))
        margins = None
        if draw(st.booleans()) or not probes:
            cells = draw(st.lists(margin, min_size=wheels * stretches, max_size=wheels * stretches))
            margins = np.array(cells).reshape(wheels, stretches)
        static = draw(st.none() | st.lists(st.floats(-500.0, 3000.0), min_size=wheels, max_size=wheels))
        probes.append(Probe(speed, draw(st.booleans()), margins, None if static is None else np.array(static)))
    return probes, draw(st.floats(0.01, 8.0))


@settings(max_examples=200, derandomize=True, deadline=None)
@given(_probe_sets())
def test_equals_the_original_hypothesis(case):
    probes, weight = case
    assert _same(search.predicted_crossing(probes, weight), predicted_crossing(probes, weight))
