"""run(vehicle, manoeuvre): judged over the window, run-out, open-loop steer with the speed held."""

import numpy as np
import pytest

from trikedyn.analysis import metrics
from trikedyn.manoeuvres import registry
from trikedyn.simulate.closed_loop import run


def test_circle_reports_its_steady_rollover_index(reference):
    """R = 15 m at 25 km/h: the max |RI| over the window is the steady-state RI within 2 % (the driver no
    longer swerves at the end of the path)."""
    result = run(reference, "circle", speed_kmh=25.0, radius_m=15.0)
    assert result.success and result.message == "ok"
    judged = metrics.judged_mask(result)
    ri = result["ri"][judged]
    steady = float(np.mean(ri[ri.size // 2:]))
    assert abs(steady) > 0.3
    assert metrics.evaluate(result, "max_abs_ri") == pytest.approx(abs(steady), rel=0.02)
    assert metrics.summary(result)["window_complete"] is True


# speeds and options below each manoeuvre's threshold; a manoeuvre not listed is driven at 25 km/h
BELOW_THRESHOLD = {"dlc": (35.0, {}), "slc": (40.0, {}), "circle": (25.0, {"radius_m": 15.0}),
                   "steady-state-circle": (15.0, {"max_ay_mps2": 3.0, "ay_rate_mps2_per_s": 0.3})}


def _line(tmp_path):
    x = np.linspace(0.0, 100.0, 201)
    file = tmp_path / "line.csv"
    file.write_text("x_m,y_m\n" + "\n".join(f"{a:.3f},{2.0 * np.tanh((a - 50) / 8):.5f}" for a in x), encoding="utf-8")
    return str(file)


@pytest.mark.parametrize("name", [k.name for k in registry.available() if k.closed_loop])
def test_steer_in_the_run_out_stays_within_the_window_envelope(reference, name, tmp_path):
    """Every registered closed-loop manoeuvre, below its threshold: nothing happens after the exit gate
    that did not happen inside it (the driver does not run out of road)."""
    speed_kmh, options = BELOW_THRESHOLD.get(name, (25.0, {}))
    if name == "path":
        options = {"file": _line(tmp_path)}
    result = run(reference, name, speed_kmh=speed_kmh, **options)
    assert result.success
    assert not metrics.evaluate(result, "wheel_lifted")
    judged = metrics.judged_mask(result)
    after = np.zeros_like(judged)
    after[np.nonzero(judged)[0][-1] + 1:] = True
    assert after.sum() >= 20, "the run should go on past the exit gate"
    inside = result["steer_cmd_rad"][judged]
    span = inside.max() - inside.min()
    low, high = inside.min() - 0.1 * span - 1e-3, inside.max() + 0.1 * span + 1e-3
    outside = result["steer_cmd_rad"][after]
    assert outside.min() >= low and outside.max() <= high


def test_metrics_ignore_the_run_out(reference):
    """A window shorter than the run: the metrics see only the samples inside it."""
    result = run(reference, "dlc", speed_kmh=30.0)
    judged = metrics.judged_mask(result)
    assert 0 < judged.sum() < judged.size
    s = result["path_s_m"]
    assert s[judged].min() >= result.manoeuvre.window.start - 0.5 and s[judged].max() <= result.manoeuvre.window.end
    ay = np.abs(result["ay_mps2"][judged]).max()
    assert metrics.evaluate(result, "max_lateral_acceleration_mps2") == pytest.approx(ay)


def test_result_is_immutable_and_labelled(reference):
    result = run(reference, "step", speed_kmh=20.0)
    with pytest.raises(TypeError):
        result.channels["ri"] = np.zeros(3)
    with pytest.raises(ValueError):
        result["ri"][0] = 1.0
    assert result.state("x_m")[-1] == pytest.approx(result["x_m"][-1])
    assert len(result.state_names) == result.states.shape[1]
    assert "front_kappa" in result.state_names
    assert np.allclose(result.state("wz_radps"), result["yaw_rate_radps"])  # angular before linear
    # the rolling start: forward speed along the (statically pitched) chassis x axis
    assert result.state("vx_mps")[0] == pytest.approx(20.0 / 3.6 * np.cos(result.state("pitch_rad")[0]), rel=1e-9)


def test_step_steer_holds_the_speed(reference):
    """ISO 7401 step: the driver's speed control holds the speed within 0.5 km/h while the steer is open
    loop (the earlier fixed drive torque let it climb by 4 km/h)."""
    result = run(reference, "step", speed_kmh=30.0, steer_deg=4.0)
    speed = result["speed_mps"][metrics.judged_mask(result)] * 3.6
    assert np.abs(speed - 30.0).max() < 0.5
    start = result.manoeuvre.parameters["start_s"]
    steer = result["steer_cmd_rad"]
    assert np.allclose(steer[result.time_s < start], 0.0)
    assert steer[-1] == pytest.approx(np.radians(4.0))


def test_fishhook_amplitude_follows_the_reference_steer(reference):
    m = registry.build("fishhook", reference.params, 20.0, scale=2.0)
    p = m.parameters
    assert p["amplitude_deg"] == pytest.approx(2.0 * p["reference_steer_deg"])
    assert m.steer[:, 1].max() == pytest.approx(np.radians(p["amplitude_deg"]))
    assert m.steer[:, 1].min() == pytest.approx(-np.radians(p["amplitude_deg"]))


def test_a_longer_run_gets_a_longer_run_out(reference):
    """run(..., duration_s=longer): the path grows with it, so the driver still does not run out of road."""
    result = run(reference, "slc", speed_kmh=30.0, duration_s=registry.build("slc", reference.params, 30.0).duration_s + 8)
    v = 30.0 / 3.6
    assert result.manoeuvre.path.s_m[-1] > v * result.time_s[-1] + 10.0
    judged = metrics.judged_mask(result)
    after = result.time_s > result.time_s[judged][-1]
    assert np.abs(result["steer_cmd_rad"][after]).max() <= np.abs(result["steer_cmd_rad"][judged]).max()
