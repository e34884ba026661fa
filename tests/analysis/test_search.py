"""The margin-guided threshold search (trikedyn.analysis.search): the same answer as bisection, in fewer runs.

Synthetic margins test the search's logic (certificate, edges of the range, flat and steep sides); real
runs test the margin table; and every scenario of the paper's study compares the search with bisection.
"""

import math
import statistics

import numpy as np
import pytest

from trikedyn.analysis.search import Grid, Probe, margin_search, margin_table, seed_speed
from trikedyn.analysis.threshold import manoeuvre_builder, threshold_velocity
from trikedyn.params import override, scale_suspension, with_freight
from trikedyn.simulate.closed_loop import run


def _synthetic(margin, static=1500.0):
    """A probe whose margin table is the one entry ``margin(v)`` [N] (negative: failed), and its log."""
    speeds = []

    def probe(v):
        speeds.append(v)
        m = float(margin(v))
        return Probe(v, m > 0, np.array([[m]]), np.array([static]))

    return probe, speeds


def _truth(margin, grid):
    """The certified pair by brute force: the last passing index and the first failing one."""
    passing = [k for k in range(grid.last + 1) if margin(grid.speed(k)) > 0]
    failing = [k for k in range(grid.last + 1) if margin(grid.speed(k)) <= 0]
    return (max(passing) if passing else None), (min(failing) if failing else None)


def _shape(crossing_kmh, power, negative_scale):
    """Margin ``1500 (1 - (v / crossing)^(2 power))`` [N]: falling like ``v^2`` for ``power`` 1, more
    steeply near the crossing above 1; times ``negative_scale`` beyond it (a kinked signed extension)."""

    def margin(v):
        m = 1500.0 * (1.0 - (v / crossing_kmh) ** (2 * power))
        return m if m > 0 else negative_scale * m

    return margin


@pytest.mark.parametrize("negative_scale", [0.05, 1.0, 8.0])
@pytest.mark.parametrize("power", [0.7, 1.0, 2.0])
def test_certifies_the_same_pair_as_brute_force(power, negative_scale):
    grid = Grid(10.0, 90.0, 0.1)
    runs = []
    for crossing in np.linspace(31.23, 84.61, 9):
        margin = _shape(crossing, power, negative_scale)
        probe, speeds = _synthetic(margin)
        out = margin_search(probe, grid, seed_kmh=crossing / 0.75)
        assert (out.passed, out.failed) == _truth(margin, grid)
        assert out.passed in [grid.index_below(s) for s in speeds]  # certified by runs made
        assert grid.speed(out.failed) in speeds
        runs.append(len(speeds))
    assert max(runs) <= 12


def test_a_smooth_margin_needs_few_runs():
    grid = Grid(10.0, 90.0, 0.1)
    runs = []
    for crossing in np.linspace(35.17, 80.93, 15):
        probe, speeds = _synthetic(_shape(crossing, 1.3, 2.0))
        margin_search(probe, grid, seed_kmh=crossing / 0.75)
        runs.append(len(speeds))
    assert statistics.median(runs) <= 5


def test_edges_of_the_range():
    grid = Grid(10.0, 90.0, 0.1)
    probe, speeds = _synthetic(lambda v: 1000.0 - 0.01 * v * v)  # never fails
    out = margin_search(probe, grid, seed_kmh=60.0)
    assert (out.passed, out.failed) == (grid.last, None) and speeds[-1] == 90.0
    probe, speeds = _synthetic(lambda v: -10.0 * v)  # fails everywhere
    out = margin_search(probe, grid, seed_kmh=60.0)
    assert (out.passed, out.failed) == (None, 0) and 10.0 in speeds
    probe, speeds = _synthetic(_shape(47.77, 1.0, 1.0))  # no seed: rises by the step first
    out = margin_search(probe, grid)
    assert speeds[0] == 20.0 and grid.speed(out.passed) == 47.7 and grid.speed(out.failed) == 47.8


def test_failures_without_a_margin_still_bracket():
    """A run that fails without a lift (lost path) has no negative margin: bisection-like steps find it."""
    grid = Grid(10.0, 90.0, 0.5)
    speeds = []

    def probe(v):
        speeds.append(v)
        return Probe(v, v < 52.3, np.array([[2000.0 - 0.1 * v]]) if v < 52.3 else None, np.array([2000.0]))

    out = margin_search(probe, grid, seed_kmh=40.0)
    assert grid.speed(out.passed) == 52.0 and grid.speed(out.failed) == 52.5


def test_grid_anchored_at_low_and_ending_at_high():
    grid = Grid(5.0, 20.2, 0.5)
    assert grid.speed(0) == 5.0 and grid.speed(3) == 6.5 and grid.speed(grid.last) == 20.2
    assert grid.index_below(6.74) == 3 and grid.index_below(4.9) == -1


# ------------------------------------------------------------------------------------------------------------
# the margin of real runs
# ------------------------------------------------------------------------------------------------------------
def test_margin_table_is_signed_across_the_threshold(reference):
    """Below the threshold every entry is a load; above it the lifting wheel's entry is negative, small
    just above and larger further up, and later entries are unknown."""
    from trikedyn.analysis.criteria import judge_run

    signed = {}
    for v in (70.0, 74.7, 74.8, 76.0):  # ideal speed control: the speed asked for is driven
        result = run(reference, "slc", speed_kmh=v, speed_control="ideal")
        verdict = judge_run(result, speed_kmh=v, criterion="lift-off")
        table, static = margin_table(result, fail_time_s=verdict.time_s, lift_wheel=verdict.wheel)
        assert table.shape == (3, 25) and np.all(static > 1000.0)
        if verdict.passed:
            assert np.isfinite(table).all() and (table > 0).all()
            assert np.nanmin(table) == pytest.approx(verdict.min_wheel_load_N)
        else:
            assert np.isnan(table).any() and np.nanmin(table) < 0
        signed[v] = float(np.nanmin(table))
    assert signed[70.0] > signed[74.7] > 0 > signed[74.8] > signed[76.0] > -1500.0


def test_criterion_rows_cross_zero_where_their_reason_fails(reference):
    """The course rows of the margin: the speed's band, the path corridor, the spin limit and the cone clearance,
    each positive while held and negative beyond its failure, with their values at v = 0 as anchors."""
    from trikedyn.analysis.margins import criterion_rows, run_margins
    from trikedyn.analysis.verdict import Judging, judge

    rules = Judging()
    clean = run(reference, "dlc", speed_kmh=35.0)
    rows, anchors = criterion_rows(clean, judge(clean, rules), "course", rules)
    assert rows.shape == (4, 25) and np.all(np.nan_to_num(rows, nan=1.0) > 0)
    assert anchors[:3].tolist() == [rules.speed_band_kmh, rules.lost_m, rules.spin_deg] and np.isnan(anchors[3])
    struck = run(reference, "dlc", speed_kmh=45.0)
    verdict = judge(struck, rules)
    assert verdict.reason("cone strike") is not None
    rows, _ = criterion_rows(struck, verdict, "course", rules)
    assert np.nanmin(rows[3]) < 0 < np.nanmin(rows[0])
    assert criterion_rows(struck, verdict, "lift-off", rules)[0].shape == (3, 25)  # no cone row
    fast = run(reference, "slc", speed_kmh=70.0)  # beyond the drive's top speed
    table, anchors, margin = run_margins(fast, judge(fast, rules), "lift-off", rules)
    assert table.shape == (6, 25) and np.nanmin(table[3]) < 0 < margin


def test_seed_is_the_static_tip_over_speed_in_the_tightest_curve(reference):
    dlc = manoeuvre_builder("dlc")(reference.params, 40.0)
    slc = manoeuvre_builder("slc")(reference.params, 40.0)
    assert 40.0 < seed_speed(reference.params, dlc) < seed_speed(reference.params, slc) < 150.0
    assert seed_speed(reference.params, manoeuvre_builder("fishhook")(reference.params, 40.0)) > 0


def test_result_reports_its_runs(reference):
    result = threshold_velocity(reference, "slc", resolution_kmh=0.5)
    assert result.method == "margin" and result.n_runs == len(result.runs) == len(result.speeds_kmh)
    data = result.to_dict(runs=True)
    assert data["method"] == "margin" and data["speeds_kmh"] == list(result.speeds_kmh)
    assert set(result.to_dict()) == {"threshold_speed_kmh", "limit", "limiting_wheel", "lift_time_s",
                                     "first_failure_kmh", "first_cone_strike_kmh", "detail", "n_runs", "criterion",
                                     "speed_control", "top_speed_kmh", "entry_speed_kmh", "window_speed_kmh",
                                     "course_speed_kmh", "lift_off_speed_kmh", "failure_time_s"}
    with pytest.raises(Exception, match="method"):
        threshold_velocity(reference, "slc", method="golden")


# ------------------------------------------------------------------------------------------------------------
# the paper's study: margin search against bisection
# ------------------------------------------------------------------------------------------------------------
def _paper_vehicles():
    from trikedyn.study.scenarios import expand
    from trikedyn.study.spec import load_spec

    spec = load_spec("paper")
    base = spec.load_vehicle()
    for s in expand(spec):
        pset = scale_suspension(base, stiffness=s["stiffness_scale"], damping=s["damping_scale"])
        if s["overrides"]:
            pset = override(pset, s["overrides"])
        yield s, with_freight(pset, s["freight_kg"])


@pytest.mark.slow
@pytest.mark.parametrize("criterion", ["lift-off", "course"])
def test_margin_search_equals_bisection_on_the_paper_study(criterion, paper_searches):
    """Every scenario of ``trikedyn study paper`` (50, ideal speed control as the spec says), under each
    criterion: the same threshold, limit, wheel and lift time as bisection, certified by runs at the threshold
    and 0.1 km/h above it; a median of <= 6 runs under the course criterion (measured: 5.0), <= 7 under lift-off
    (6.5: the single lane change at the speeds imposed takes 7, its margin beyond a lift being erratic; bisection
    takes 12)."""
    runs, mismatches = [], []
    for s, (new, old) in paper_searches[criterion].items():
        fields = ("threshold_speed_kmh", "first_failure_kmh", "limit", "limiting_wheel", "lift_time_s")
        if any(getattr(new, f) != getattr(old, f) for f in fields):
            mismatches.append((s, new.threshold_speed_kmh, old.threshold_speed_kmh))
        assert new.threshold_speed_kmh in new.speeds_kmh and new.first_failure_kmh in new.speeds_kmh
        assert math.isclose(new.first_failure_kmh - new.threshold_speed_kmh, 0.1, abs_tol=1e-9)
        runs.append(new.n_runs)
    assert not mismatches
    assert len(runs) == 50 and statistics.median(runs) <= (6 if criterion == "course" else 7)


@pytest.mark.slow
def test_the_course_threshold_is_at_most_the_lift_off_one_on_the_paper_study(paper_searches):
    """On every paper scenario: course <= lift-off, and the course threshold's passing run struck no cone."""
    for s, (course, _) in paper_searches["course"].items():
        lift = paper_searches["lift-off"][s][0]
        assert course.threshold_speed_kmh <= lift.threshold_speed_kmh, s
        passing = next(r for r in course.runs if r.speed_kmh == course.threshold_speed_kmh)
        assert passing.passed and passing.cone_strikes == 0 and passing.verdict == "pass", s


@pytest.fixture(scope="module")
def paper_searches():
    """Margin search and bisection on every paper scenario, under each criterion."""
    from trikedyn.model.vehicle import build_model

    out = {"lift-off": {}, "course": {}}
    for s, pset in _paper_vehicles():
        model = build_model(pset)
        search = dict(low_kmh=s["low_kmh"], high_kmh=s["high_kmh"], step_kmh=s["step_kmh"],
                      resolution_kmh=s["resolution_kmh"], speed_control=s["speed_control"])
        key = (s["manoeuvre"], s["stiffness_scale"], s["damping_scale"], s["freight_kg"])
        for criterion in out:
            out[criterion][key] = (threshold_velocity(model, s["manoeuvre"], criterion=criterion, **search),
                                   threshold_velocity(model, s["manoeuvre"], method="bisection", criterion=criterion,
                                                      **search))
    return out
