"""Threshold velocity: the search, its verdicts and the CLI."""

import json

import pytest

from trikedyn.analysis.threshold import threshold_velocity
from trikedyn.cli import main
from trikedyn.params import load_vehicle, with_freight


@pytest.fixture(scope="module")
def slc_threshold():
    """The paper's SLC threshold: lift-off, at the speed imposed (its own 5 kW drive stops at 55 km/h)."""
    return threshold_velocity(load_vehicle("reference-etrike"), "slc", resolution_kmh=0.1, criterion="lift-off",
                              speed_control="ideal")


def test_threshold_is_bracketed_to_the_resolution(slc_threshold):
    result = slc_threshold
    assert result.limit == "lift-off" and result.limiting_wheel in ("rear_left", "rear_right")
    assert result.first_failure_kmh == pytest.approx(result.threshold_speed_kmh + 0.1)
    passed = [r.speed_kmh for r in result.runs if r.passed]
    failed = [r.speed_kmh for r in result.runs if not r.passed]
    assert max(passed) == pytest.approx(result.threshold_speed_kmh)
    assert min(failed) == pytest.approx(result.first_failure_kmh)
    assert result.lift_time_s > 0


def test_freight_lowers_the_threshold(slc_threshold):
    laden = threshold_velocity(with_freight(load_vehicle("reference-etrike"), 200.0), "slc", resolution_kmh=0.5,
                               criterion="lift-off", speed_control="ideal")
    assert laden.threshold_speed_kmh < slc_threshold.threshold_speed_kmh - 5.0


def test_threshold_command_json(capsys):
    code = main(["threshold", "reference-etrike", "--manoeuvre", "slc", "--payload", "100", "--resolution", "1",
                 "--speed-control", "ideal", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0
    for key in ("threshold_speed_kmh", "limit", "limiting_wheel", "lift_time_s"):
        assert key in data
    assert data["limit"] in ("lift-off", "cone strike", "path lost", "spin") and data["threshold_speed_kmh"] > 30
    assert data["criterion"] == "course" and data["speed_control"] == "ideal"


def test_threshold_command_rejects_unknown_manoeuvre(capsys):
    assert main(["threshold", "reference-etrike", "--manoeuvre", "zigzag"]) == 2
    assert "--manoeuvre" in capsys.readouterr().err
