"""The handling tests on the model: ISO 4138 against the single-track model, ISO 7401 step against it."""

import json

import numpy as np
import pytest

from trikedyn.analysis import metrics
from trikedyn.analysis.handling_tests import (
    _why_it_ended,
    braking_in_turn_test,
    steady_state_test,
    steer_at_nominal_radius,
    step_steer_test,
)
from trikedyn.cli import main
from trikedyn.model.linear import single_track
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle, override, save_vehicle


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


def measured_peak(test):
    """Where the measured steer curve peaks, two ways apart from the shape's: the argmax of the diagram's
    binned means (the curve the figure draws, 20 bins), and the maximum of a degree-6 polynomial through
    the samples themselves [m/s^2]."""
    d = test.diagram
    binned = float(d.ay_bins_mps2[np.argmax(d.steer_deg)])
    r = test.result
    _, _, end = _why_it_ended(r, r.params, r.manoeuvre.parameters["max_ay_mps2"])
    keep = metrics.judged_mask(r) & (np.arange(r.time_s.size) <= end)
    ay = np.asarray(r["ay_mps2"])[keep]
    steer = np.degrees(steer_at_nominal_radius(r, r.params, test.radius_m))[keep]
    grid = np.linspace(ay.min(), ay.max(), 2001)
    poly = float(grid[np.argmax(np.polyval(np.polyfit(ay, steer, 6), grid))])
    return binned, poly


def test_handling_diagram_of_the_reference_trike(steady):
    """The reference trike understeers a little at low a_y and turns to oversteer before its limit (the
    delta layout's known tendency: its two-wheel axle carries all the roll-moment load transfer): the
    steer peaks near 3.6 m/s^2 and the limit behaviour is oversteer. It rolls out of the turn."""
    d = steady.diagram
    assert d.understeer_gradient_deg_per_g > 0 and d.roll_gradient_deg_per_g > 0
    ay, steer = np.asarray(d.ay_bins_mps2), np.asarray(d.steer_deg)
    high = ay > 0.35 * 9.80665
    assert np.polyfit(ay[high], steer[high], 1)[0] < 0  # steer falls with a_y: oversteer
    assert steady.limit in ("lift-off", "driver limit", "steering lock", "speed not reached", "end of test")
    assert steady.max_lateral_acceleration_mps2 > 3.0
    shape = d.shape
    assert shape.limit_behaviour == "oversteer" and shape.neutral_steer == "peak"
    for peak in measured_peak(steady):
        assert shape.neutral_steer_lateral_acceleration_mps2 == pytest.approx(peak, abs=0.3)
    assert shape.bands[0].behaviour == "understeer" and shape.bands[-1].behaviour == "oversteer"
    # the first band is the linear range, as fitted over bins rather than samples
    assert shape.bands[0].gradient_deg_per_g == pytest.approx(d.understeer_gradient_deg_per_g, abs=0.05)


def test_a_rear_heavy_trike_turns_oversteer(tmp_path, capsys):
    """Acceptance (issue 20): the reference trike with its CG moved back to 35 % of the wheelbase from the
    rear axle (from 42.7 %) understeers hardly at all at low a_y and turns oversteer at about 2.3 m/s^2,
    like the issue's 300 kg trike: `handling` says ``limit_behaviour: oversteer`` and puts the
    neutral-steer lateral acceleration within 0.3 m/s^2 of where the measured steer curve peaks."""
    rear_heavy = override(load_vehicle("reference-etrike"), {"cg_x_fraction": 0.35})
    test = steady_state_test(rear_heavy, radius_m=20.0)
    shape = test.diagram.shape
    assert shape.limit_behaviour == "oversteer" and shape.limit_gradient_deg_per_g < -1.0
    assert shape.neutral_steer == "peak"
    for peak in measured_peak(test):
        assert shape.neutral_steer_lateral_acceleration_mps2 == pytest.approx(peak, abs=0.3)
    assert 1.8 < shape.neutral_steer_lateral_acceleration_mps2 < 2.8
    # the command, on the vehicle written to a file: the text says so, and the JSON
    path = save_vehicle(rear_heavy, tmp_path / "rear-heavy.toml")
    assert main(["handling", str(path), "--radius", "20"]) == 0
    text = capsys.readouterr().out
    assert "limit behaviour       oversteer" in text
    assert f"neutral steer at a_y  {shape.neutral_steer_lateral_acceleration_mps2:.2f} m/s^2" in text
    assert "linear range: fitted over 0.87-1.96 m/s^2" in text and "3.00- 4.00 m/s^2" in text
    assert main(["handling", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["limit_behaviour"] == "oversteer"
    assert data["neutral_steer_lateral_acceleration_mps2"] == pytest.approx(
        shape.neutral_steer_lateral_acceleration_mps2)
    assert [b["behaviour"] for b in data["steer_bands"]][-1] == "oversteer"


def test_the_tadpole_understeers_at_its_limit():
    """reference-tadpole (the pair steers and takes the load transfer): oversteer at low a_y, then the steer
    rises ever faster to the lift-off: limit understeer, no neutral-steer point below it."""
    test = steady_state_test(load_vehicle("reference-tadpole"), radius_m=20.0)
    shape = test.diagram.shape
    assert shape.limit_behaviour == "understeer" and shape.limit_gradient_deg_per_g > 5.0
    assert shape.neutral_steer == "not reached"
    assert shape.bands[0].behaviour == "oversteer" and shape.bands[-1].behaviour == "understeer"
    json.dumps(test.to_dict(), allow_nan=False)  # NaN neutral steer becomes None


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
                "max_lateral_acceleration_mps2", "limit", "fit_start_mps2", "fit_limit_mps2", "steer_bands",
                "neutral_steer_lateral_acceleration_mps2", "neutral_steer", "limit_behaviour",
                "limit_gradient_deg_per_g", "limit_low_mps2", "limit_high_mps2"):
        assert key in data
    assert data["limit_behaviour"] in ("understeer", "neutral", "oversteer")
    assert {"low_mps2", "high_mps2", "gradient_deg_per_g", "behaviour"} <= set(data["steer_bands"][0])
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
