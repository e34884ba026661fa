"""The handling tests on the model: ISO 4138 against the single-track model, ISO 7401 step against it."""

import json

import numpy as np
import pytest

from trikedyn.analysis.handling_tests import braking_in_turn_test, steady_state_test, step_steer_test
from trikedyn.cli import main
from trikedyn.model.linear import single_track
from trikedyn.model.vehicle import build_model


@pytest.fixture(scope="module")
def model(reference):
    return build_model(reference)


@pytest.fixture(scope="module")
def steady(model):
    return steady_state_test(model, radius_m=20.0)


def test_understeer_gradient_matches_the_single_track_model(model, steady):
    """At low lateral acceleration the gradient is within 5 % of m_f / C_f - m_r / C_r at the static loads;
    the steer at zero lateral acceleration is the Ackermann steer L / R (with the trail, L + trail)."""
    linear = single_track(model).understeer_gradient_deg_per_g
    assert steady.diagram.understeer_gradient_deg_per_g == pytest.approx(linear, rel=0.05)
    assert steady.diagram.steer_intercept_deg == pytest.approx(steady.diagram.ackermann_steer_deg, rel=0.01)
    assert steady.diagram.roll_gradient_deg_per_g > 0  # rolls out of the turn
    assert steady.limit in ("lift-off", "driver limit", "steering lock", "speed not reached", "end of test")
    assert steady.max_lateral_acceleration_mps2 > 3.0


def test_step_steer_gain_matches_the_handling_diagram(model, steady):
    """ISO 7401 step at 25 km/h: the steady yaw-rate gain is that of the diagram at the same speed (2 %);
    the speed is held within 0.5 km/h."""
    v = 25.0 / 3.6
    d = steady.diagram
    a_y = v * v / steady.radius_m
    delta = np.radians(d.steer_intercept_deg + d.understeer_gradient_deg_per_g * a_y / 9.80665)
    diagram_gain = (v / steady.radius_m) / delta
    step = step_steer_test(model, 25.0, steer_deg=2.0)
    assert step["yaw_rate"].steady_state_gain == pytest.approx(diagram_gain, rel=0.02)
    assert step["speed_drift_kmh"] < 0.5
    assert 0.0 < step["yaw_rate"].response_time_s < 1.0


def test_braking_in_a_turn_reports_deviation_and_loads(model):
    out = braking_in_turn_test(model, 25.0)
    figures = out["braking"].to_dict()
    assert figures["mean_deceleration_mps2"] > 1.0
    assert abs(figures["path_deviation_m"]) < 1.0
    assert all(v > 0 for v in out["min_wheel_loads_N"].values())


def test_handling_command(capsys, tmp_path):
    plot = tmp_path / "diagram.png"
    code = main(["handling", "reference-etrike", "--radius", "20", "--plot", str(plot), "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and plot.stat().st_size > 10_000
    for key in ("understeer_gradient_deg_per_g", "roll_gradient_deg_per_g", "sideslip_gradient_deg_per_g",
                "max_lateral_acceleration_mps2", "limit"):
        assert key in data
    assert main(["handling", "reference-etrike", "--radius", "-3"]) == 2
    assert "--radius" in capsys.readouterr().err
