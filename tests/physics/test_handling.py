"""Verification ladder, rung 5: handling limits against closed forms."""

import numpy as np
import pytest

from trikedyn.errors import SimulationError
from trikedyn.model.statics import static_equilibrium
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle, mass_properties, override
from trikedyn.simulate.run import simulate
from trikedyn.tyre.interface import linear_stiffnesses
from trikedyn.units import STANDARD_GRAVITY as G

from .rigid import RIGID_GRIPPY


@pytest.mark.parametrize(("speed_mps", "steer_rad"), [(5.0, 0.03), (8.0, 0.012), (12.0, 0.006)])
def test_steady_cornering_matches_single_track_yaw_rate_gain(reference, speed_mps, steer_rad):
    """r / delta = v / (L + K_us v^2), K_us = m_f / C_f - m_r / C_r (axle loads and cornering stiffnesses
    at the static loads); delta is the road steer angle, the steer about the raked axis times cos(rake)."""
    model = build_model(reference)
    p = reference.params
    eq = static_equilibrium(model)
    stiffness = {w.name: linear_stiffnesses(t.model, t.coefficients, eq.wheel_loads_N[w.name])[1]
                 for w, t in zip(model.tree.wheels, model.tyres, strict=True)}
    c_front = stiffness["front"]
    c_rear = stiffness["rear_left"] + stiffness["rear_right"]
    m_front = eq.wheel_loads_N["front"] / G
    k_us = m_front / c_front - (model.tree.total_mass() - m_front) / c_rear
    run = simulate(model, duration_s=8.0, speed_kmh=speed_mps * 3.6, steer_rad=steer_rad, drive_torque_Nm=51.0)
    tail = run.to_pandas().loc[7.0:8.0]
    speed = tail.speed_mps.mean()
    yaw_rate = tail.yaw_rate_radps.mean()
    assert speed * yaw_rate <= 0.5  # the linear range the acceptance asks for
    road_steer = tail.steer_rad.mean() * np.cos(np.radians(p.steering.axis_angle_deg))
    linear = speed / (p.wheelbase_m + k_us * speed**2)
    assert yaw_rate / road_steer == pytest.approx(linear, rel=0.05)


def rigid_trike():
    """reference-etrike on rigid suspension and stiff, very grippy tyres, CG on the centre line, driven at
    the right rear wheel (the outer one in a left turn)."""
    base = load_vehicle("reference-etrike")
    return override(
        base,
        {
            **RIGID_GRIPPY,
            # drive the outer wheel of the left turn only: through the open differential the unloading
            # inner wheel would spin and cap the drive force before the tip-over is reached
            "wheels.rear_left.driven": False,
        },
    )


def test_quasi_static_tip_over_matches_closed_form():
    """Constant steer, speed raised slowly: the inner rear wheel lifts at a_y / g = a T / (2 h L)."""
    pset = rigid_trike()
    p = pset.params
    cg = mass_properties(p).cg_m
    a = p.wheelbase_m - cg[0]
    expected = a * p.track_m / (2 * cg[2] * p.wheelbase_m) * G
    model = build_model(pset)
    with pytest.raises(SimulationError, match="rolled over") as info:  # once lifted, it tips over
        simulate(model, duration_s=80.0, speed_kmh=7.0 * 3.6, steer_rad=lambda t: np.minimum(0.25, 0.125 * t),
                 drive_torque_Nm=lambda t: 90.0 + 1.0 * t, dt=5e-4, output_rate_hz=200.0)
    frame = info.value.result.to_pandas()
    inner = frame.rear_left_fz_N  # turning left
    lifted = frame.index[inner.to_numpy() <= 0.0]
    assert len(lifted) > 0, "the inner rear wheel never lifted"
    t_lift = lifted[0]
    # centripetal acceleration in the road plane at lift-off (steady turning: v * yaw rate)
    window = frame.loc[t_lift - 0.2 : t_lift]
    lateral = (window.speed_mps * window.yaw_rate_radps).abs().mean()
    assert lateral == pytest.approx(expected, rel=0.03)
    longitudinal = np.gradient(frame.speed_mps.to_numpy(), frame.index.to_numpy())
    assert np.abs(longitudinal[frame.index < t_lift][-200:]).max() < 0.2  # quasi-static: slow speed rise


def test_rollover_ends_with_a_clear_simulation_error(reference):
    """A top-heavy trike thrown into a sharp turn rolls over: SimulationError with time and reason."""
    top_heavy = override(reference, {"mass.cg_z_m": 1.1})
    with pytest.raises(SimulationError) as info:
        simulate(top_heavy, duration_s=10.0, speed_kmh=40.0, steer_rad=lambda t: np.minimum(0.3, 0.6 * t))
    err = info.value
    assert "rolled over" in str(err) and 0.0 < err.time_s < 10.0
    assert str(err).startswith(f"at t = {err.time_s:.4f} s")
    assert err.result.time_s[-1] <= err.time_s


def test_time_step_too_large_is_refused(reference):
    """Classical RK4 is refused at 10 ms (the spin-slip mode, ~300 rad/s); the default loop, with those pairs
    exact, at 20 ms (the rear wheel hop, ~154 rad/s, needs dt <= 16 ms)."""
    with pytest.raises(SimulationError, match="time step too large.*fastest mode"):
        simulate(reference, duration_s=1.0, speed_kmh=20.0, dt=0.01, integrator="rk4")
    simulate(reference, duration_s=1.0, speed_kmh=20.0, dt=0.01)
    with pytest.raises(SimulationError, match="time step too large"):
        simulate(reference, duration_s=1.0, speed_kmh=20.0, dt=0.02)
