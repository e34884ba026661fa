"""The built-in study (the paper's Fig. 10) on our physics: the paper's three findings, pinned.

This does not tune anything to the paper: it pins what the model gives (with a tolerance for numerical
changes) and checks the paper's qualitative findings against it.
"""

import pytest

from trikedyn.paper.model_side import study_findings
from trikedyn.study.designs.runner import run_study


@pytest.fixture(scope="module")
def table(tmp_path_factory):
    return run_study("paper", tmp_path_factory.mktemp("paper-study"), workers=2, progress=False)


def test_all_fifty_scenarios_ok(table):
    """The paper's definition (lift-off) at the speed imposed (ideal speed control), each threshold driven."""
    assert len(table) == 50 and (table["status"] == "ok").all()
    assert (table.criterion == "lift-off").all() and (table.speed_control == "ideal").all()
    assert (table.driven_min_kmh > 0.97 * table.threshold_speed_kmh).all()
    assert (table.driven_max_kmh < 1.03 * table.threshold_speed_kmh).all()


def test_paper_findings_hold_on_our_model(table):
    findings = study_findings(table)
    assert findings["falls with freight"]["holds"]
    assert findings["rises with stiffness"]["holds"]
    damping = findings["damping matters less than stiffness"]
    assert damping["holds"] and damping["mean_abs_change_damping_kmh"] < 0.3 * damping["mean_abs_change_stiffness_kmh"]


@pytest.mark.parametrize(
    ("manoeuvre", "freight", "stiffness", "expected_kmh"),
    [("dlc", 0.0, 1.0, 43.8), ("dlc", 200.0, 1.0, 38.4), ("dlc", 0.0, 0.8, 41.5), ("slc", 0.0, 1.0, 74.7),
     ("slc", 200.0, 1.0, 63.7), ("slc", 0.0, 1.2, 76.7)],
)
def test_pinned_thresholds(table, manoeuvre, freight, stiffness, expected_kmh):
    row = table[(table.manoeuvre == manoeuvre) & (table.freight_kg == freight)
                & (table.stiffness_scale == stiffness) & (table.damping_scale == 1.0)]
    assert len(row) == 1
    assert row.threshold_speed_kmh.iloc[0] == pytest.approx(expected_kmh, abs=1.0)
