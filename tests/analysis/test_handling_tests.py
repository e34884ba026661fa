"""The handling tests on the model: ISO 4138 against the single-track model, ISO 7401 step against it."""

import json

import numpy as np
import pytest

from trikedyn.analysis.handling_tests import braking_in_turn_test, steady_state_test, step_steer_test
from trikedyn.cli import main
from trikedyn.model.linear import single_track
from trikedyn.model.vehicle import build_model
from trikedyn.params import override


@pytest.fixture(scope="module")
def model(reference):
    return build_model(reference)


@pytest.fixture(scope="module")
def steady(model):
    return steady_state_test(model, radius_m=20.0)


def test_understeer_gradient_matches_the_single_track_model(reference):
    """A test vehicle with what the single-track model leaves out taken away (CG on the centre line, no drag,
    no rolling resistance), the speed raised slowly: below 0.1 g the understeer gradient is within 5 % of
    m_f / C_f - m_r / C_r at the static loads (measured: -0.5 %), and the steer at zero lateral acceleration
    is the kinematic steer L / R."""
    test_vehicle = build_model(override(reference, {"mass.cg_y_m": 0.0, "aero.drag_coefficient": 0.0,
                                                    "tyre.rolling_resistance": 0.0}))
    test = steady_state_test(test_vehicle, radius_m=20.0, start_speed_kmh=11.0, ay_rate_mps2_per_s=0.03,
                             max_ay_mps2=1.5, fit_limit_mps2=0.1 * 9.80665)
    linear = single_track(test_vehicle).understeer_gradient_deg_per_g
    assert test.diagram.understeer_gradient_deg_per_g == pytest.approx(linear, rel=0.05)
    p = test_vehicle.params
    kinematic = np.degrees(p.wheelbase_m / 20.0)
    assert test.diagram.steer_intercept_deg == pytest.approx(kinematic, rel=0.01)


def test_handling_diagram_of_the_reference_trike(steady):
    """The reference trike understeers a little at low a_y and turns to oversteer before it lifts a wheel
    (the delta layout's known tendency); it rolls out of the turn."""
    d = steady.diagram
    assert d.understeer_gradient_deg_per_g > 0 and d.roll_gradient_deg_per_g > 0
    ay, steer = np.asarray(d.ay_bins_mps2), np.asarray(d.steer_deg)
    high = ay > 0.35 * 9.80665
    assert np.polyfit(ay[high], steer[high], 1)[0] < 0  # steer falls with a_y: oversteer
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


def test_simulate_reports_each_tests_own_figures(capsys):
    """`simulate` on a handling manoeuvre adds that test's figures (ISO 7401 step, sweep; ISO 7975)."""
    assert main(["simulate", "reference-etrike", "--manoeuvre", "step", "-o", "steer_deg=2", "--speed", "25",
                 "--json"]) == 0
    step = json.loads(capsys.readouterr().out)["figures"]
    assert step["yaw_rate"]["steady_state_gain"] > 0 and step["speed_drift_kmh"] < 0.5
    assert 0 < step["yaw_rate"]["response_time_s"] < step["yaw_rate"]["peak_response_time_s"]
    assert main(["simulate", "reference-etrike", "--manoeuvre", "sweep", "--speed", "25", "--json"]) == 0
    sweep = json.loads(capsys.readouterr().out)["figures"]["yaw_rate"]
    gain = np.asarray(sweep["gain"])
    assert len(gain) >= 5 and gain[0] == pytest.approx(step["yaw_rate"]["steady_state_gain"], rel=0.05)
    assert main(["simulate", "reference-etrike", "--manoeuvre", "braking-in-turn", "--speed", "25", "--json"]) == 0
    braking = json.loads(capsys.readouterr().out)["figures"]
    assert braking["braking"]["mean_deceleration_mps2"] > 1.0
