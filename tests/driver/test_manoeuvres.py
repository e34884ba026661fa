"""Issue 4: the driver through the ISO manoeuvres, the rollover index, the emulated IMU, comparison."""

import numpy as np
import pytest

from trikedyn.analysis import metrics
from trikedyn.analysis.compare import compare, load_table
from trikedyn.driver.preview import DriverSettings
from trikedyn.manoeuvres import paths
from trikedyn.measure.logs import write_log
from trikedyn.params import load_vehicle
from trikedyn.simulate.closed_loop import drive
from trikedyn.units import STANDARD_GRAVITY as G


@pytest.fixture(scope="module")
def trike():
    return load_vehicle("reference-etrike")


@pytest.mark.parametrize("speed_kmh", [20.0, 30.0, 40.0])
@pytest.mark.parametrize("manoeuvre", ["dlc", "slc"])
def test_reference_trike_completes_the_lane_changes(trike, manoeuvre, speed_kmh):
    """ISO 3888-1 (lanes from the 1.25 m width) and ISO 14791 without a cone strike, every wheel down."""
    path = paths.double_lane_change(trike.params.body.overall_width_m) if manoeuvre == "dlc" else paths.single_lane_change()
    run = drive(trike, path, speed_kmh)
    summary = metrics.summary(run)
    assert summary["status"] == "ok"
    assert summary["cone_strikes"] == 0, metrics.cone_strikes(run)
    assert not summary["wheel_lifted"] and summary["min_wheel_load_N"] > 200.0
    assert summary["min_speed_kmh"] > speed_kmh - 2.0 and summary["max_speed_kmh"] < speed_kmh + 2.0
    # the run really reached the end of the path
    assert run["x_m"][-1] > path.x_m[-1] - 12.0
    # Eq. 5 within [-1, 1] while every wheel touches the road
    assert summary["max_abs_ri_all_wheels_down"] <= 1.0


def test_double_lane_change_at_50_kmh_lifts_a_wheel(trike):
    """Why the DLC is not driven faster: at 50 km/h a rear wheel lifts (lift-off, not the driver)."""
    run = drive(trike, paths.double_lane_change(trike.params.body.overall_width_m), 50.0)
    summary = metrics.summary(run)
    assert summary["wheel_lifted"] and summary["min_wheel_load_N"] == 0.0
    assert summary["max_abs_ri"] == pytest.approx(1.0)


def test_emulated_sensor_on_a_steady_circle(trike):
    """On a steady circle the sensor's lateral specific force is v^2/R cos(roll) + g sin(roll) within 2 %."""
    run = drive(trike, paths.circle(20.0, laps=1.5), 25.0)
    frame = run.to_pandas().loc[8.0:]
    p = trike.params.sensor
    yaw = frame.yaw_rad.to_numpy()
    sx = frame.x_m.to_numpy() + p.x_m * np.cos(yaw) - p.y_m * np.sin(yaw)
    sy = frame.y_m.to_numpy() + p.x_m * np.sin(yaw) + p.y_m * np.cos(yaw)
    # least-squares circle through the sensor's path
    a = np.column_stack([2 * sx, 2 * sy, np.ones_like(sx)])
    cx, cy, c = np.linalg.lstsq(a, sx**2 + sy**2, rcond=None)[0]
    radius = np.sqrt(c + cx**2 + cy**2)
    t = frame.index.to_numpy()
    speed = np.hypot(np.gradient(sx, t), np.gradient(sy, t))
    roll = frame.roll_rad.to_numpy()
    expected = speed**2 / radius * np.cos(roll) + G * np.sin(roll)
    measured = frame.imu_ay_mps2.to_numpy()
    assert 2.0 < expected.mean() < 4.0
    assert measured.mean() == pytest.approx(expected.mean(), rel=0.02)


def test_comparison_with_a_synthetic_measured_log(trike, tmp_path):
    """A 'measured' run with other driver gains, sampled at 10 Hz with noise, shifted by 0.3 s and written
    as a WitMotion SDK file, against the nominal run: the offset is found within one sample."""
    path = paths.double_lane_change(trike.params.body.overall_width_m)
    nominal = drive(trike, path, 30.0)
    other = drive(trike, path, 30.0, driver=DriverSettings(preview_time_s=0.4, reaction_delay_s=0.1))
    log = other.imu_log(10.0, noise_std=0.05, gyro_noise_std=0.005, bias=(0.1, -0.05, 0.2), seed=1)
    log = log[log.time_s >= 0.3].copy()
    log["time_s"] -= 0.3  # the logger started 0.3 s late: its time 0 is the run's 0.3 s
    written = write_log(log, tmp_path / "measured.txt", "witmotion-sdk")
    measured, kind = load_table(written)
    assert kind == "witmotion-sdk"
    simulated = nominal.imu_log()
    result = compare(measured, simulated, channels=["ay_mps2", "wz_radps"])
    assert result.offset_s == pytest.approx(0.3, abs=0.1)
    assert result["wz_radps"].correlation > 0.9
    same = compare(simulated, simulated, channels=["ay_mps2", "wz_radps"])
    assert same.offset_s == 0.0
    assert all(c.rmse == 0.0 and c.peak_error == 0.0 for c in same.channels)


def test_speed_controller_follows_a_linear_profile(trike):
    """The paper drove its double lane change with the throttle held, the speed rising about linearly."""
    from trikedyn.manoeuvres import speed

    profile = speed.linear(25.0, 35.0, 20.0)
    run = drive(trike, paths.double_lane_change(1.25), profile, duration_s=18.0)
    frame = run.to_pandas().loc[2.0:]
    target = profile.at(frame.index.to_numpy()) * 3.6
    assert np.abs(frame.speed_mps.to_numpy() * 3.6 - target).max() < 1.0
    assert metrics.summary(run)["cone_strikes"] == 0
