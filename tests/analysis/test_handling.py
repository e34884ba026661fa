"""Tests of trikedyn.analysis.handling on synthetic signals with known answers (no vehicle model)."""

from __future__ import annotations

import json
import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
from scipy import signal

from trikedyn.analysis.handling import (
    braking_in_turn,
    frequency_response,
    handling_diagram,
    sine_sweep,
    step_response,
)
from trikedyn.errors import InputError

G = 9.80665


# ------------------------------------------------------------------------------ handling diagram
L, R = 1.6, 20.0
K_STEER, K_BETA, K_ROLL = 2.5, -3.0, 4.0  # deg/g
BETA0 = math.degrees(0.7 / R)  # kinematic sideslip of the CG 0.7 m ahead of the rear axle [deg]


def circle_run(direction=1, ay_max=0.45 * G, n=1000, tail=False, seed=0):
    """Constant-radius run: a_y rising with v^2, steer = L/R + K a_y/g, noise on every channel."""
    rng = np.random.default_rng(seed)
    a = ay_max * np.linspace(0.02, 1.0, n) ** 2  # a_y = v^2 / R with the speed rising linearly
    extra = np.where(a > 0.25 * G, 40.0 * (a / G - 0.25) ** 2, 0.0) if tail else 0.0  # limit understeer
    steer = math.degrees(L / R) + K_STEER * a / G + extra
    beta = BETA0 + K_BETA * a / G - 2 * extra
    roll = K_ROLL * a / G + 0.5 * extra
    noise = lambda: rng.normal(0, 0.005, n)  # noqa: E731  [deg]
    ay = a + rng.normal(0, 0.002 * G, n)
    return (direction * ay, direction * np.radians(steer + noise()), direction * np.radians(beta + noise()),
            direction * np.radians(roll + noise()))


@pytest.mark.parametrize("direction", [1, -1])
def test_handling_diagram_recovers_linear_gradients(direction):
    ay, steer, beta, roll = circle_run(direction)
    d = handling_diagram(ay, steer, beta, roll, radius_m=R, wheelbase_m=L)
    assert d.turn_direction == direction
    assert d.understeer_gradient_deg_per_g == pytest.approx(K_STEER, rel=0.01)
    assert d.sideslip_gradient_deg_per_g == pytest.approx(K_BETA, rel=0.01)
    assert d.roll_gradient_deg_per_g == pytest.approx(K_ROLL, rel=0.01)
    assert d.ackermann_steer_deg == pytest.approx(math.degrees(L / R))
    assert d.steer_intercept_deg == pytest.approx(d.ackermann_steer_deg, abs=0.01)
    assert d.sideslip_intercept_deg == pytest.approx(BETA0, abs=0.01)
    assert d.fit_limit_mps2 == pytest.approx(min(0.2 * G, 0.4 * d.max_lateral_acceleration_mps2))
    assert d.max_lateral_acceleration_mps2 == pytest.approx(0.45 * G, rel=0.03)
    # the binned diagram is folded to a left turn and follows the lines
    assert np.all(np.diff(d.ay_bins_mps2) > 0) and d.ay_bins_mps2[0] < 0.01 * G
    assert np.allclose(d.steer_deg, math.degrees(L / R) + K_STEER * d.ay_bins_mps2 / G, atol=0.05)
    assert np.allclose(d.roll_deg, K_ROLL * d.ay_bins_mps2 / G, atol=0.05)
    out = json.loads(json.dumps(d.to_dict(), allow_nan=False))
    assert out["turn_direction"] == direction and len(out["steer_deg"]) == d.steer_deg.size


def test_handling_diagram_nonlinear_tail_does_not_bias_the_gradient():
    ay, steer, beta, roll = circle_run(tail=True)
    d = handling_diagram(ay, steer, beta, roll, radius_m=R, wheelbase_m=L)
    assert d.understeer_gradient_deg_per_g == pytest.approx(K_STEER, rel=0.01)
    assert d.sideslip_gradient_deg_per_g == pytest.approx(K_BETA, rel=0.01)
    # the tail is there: a fit over the whole record would be biased, and the diagram shows it
    whole = handling_diagram(ay, steer, beta, roll, radius_m=R, wheelbase_m=L, fit_limit_mps2=0.45 * G)
    assert whole.understeer_gradient_deg_per_g > 1.1 * K_STEER
    assert d.steer_deg[-1] > math.degrees(L / R) + K_STEER * 0.45 + 0.5


def test_handling_diagram_needs_low_acceleration_points():
    ay, steer, beta, roll = circle_run()
    high = ay > 0.25 * G  # the run starts above the fit range
    with pytest.raises(ValueError, match="linear-range fit needs"):
        handling_diagram(ay[high], steer[high], beta[high], roll[high], radius_m=R, wheelbase_m=L)
    low = np.flatnonzero(ay < 0.15 * G)
    few = np.r_[low[np.linspace(0, low.size - 1, 6).astype(int)], np.flatnonzero(ay > 0.25 * G)]
    with pytest.raises(ValueError, match="only 6 samples"):
        handling_diagram(ay[few], steer[few], beta[few], roll[few], radius_m=R, wheelbase_m=L)


def test_handling_diagram_bad_input():
    ay, steer, beta, roll = circle_run()
    with pytest.raises(InputError, match="mixes left and right"):
        handling_diagram(np.r_[ay, -ay], np.r_[steer, -steer], np.r_[beta, -beta], np.r_[roll, -roll],
                         radius_m=R, wheelbase_m=L)
    with pytest.raises(InputError, match="road_steer_rad"):
        handling_diagram(ay, steer[:-1], beta, roll, radius_m=R, wheelbase_m=L)
    with pytest.raises(InputError, match="radius_m"):
        handling_diagram(ay, steer, beta, roll, radius_m=0.0, wheelbase_m=L)


def test_handling_diagram_plot():
    d = handling_diagram(*circle_run(), radius_m=R, wheelbase_m=L)
    fig = d.plot()
    assert len(fig.axes) == 3 and all("[deg]" in ax.get_ylabel() for ax in fig.axes)
    assert "[m/s²]" in fig.axes[-1].get_xlabel()
    assert any(line.get_linestyle() == "--" for line in fig.axes[0].lines)
    plt.close(fig)


# ------------------------------------------------------------------------------ step response
WN, ZETA, GAIN = 2 * math.pi * 1.5, 0.4, 3.0
DT = 0.002
T_STEP = 1.0


def second_order(t, steer):
    sys = ([GAIN * WN**2], [1.0, 2 * ZETA * WN, WN**2])
    return signal.lsim(sys, steer, t)[1]


def ramped_step(t, ramp_s, amplitude=0.05):
    return amplitude * np.clip((t - T_STEP) / ramp_s, 0.0, 1.0)


def ramped_step_second_order(t, ramp_s):
    """Closed form: the response of the unit-gain 2nd-order system to a unit step ramped over ``ramp_s``."""
    wd, s = WN * math.sqrt(1 - ZETA**2), ZETA * WN

    def ramp(u):  # unit-ramp response
        u = np.maximum(u, 0.0)
        return u - 2 * ZETA / WN + np.exp(-s * u) * (2 * ZETA / WN * np.cos(wd * u)
                                                      + (2 * ZETA**2 - 1) / wd * np.sin(wd * u))

    return (ramp(t - T_STEP) - ramp(t - T_STEP - ramp_s)) / ramp_s


def test_ramped_step_closed_form_is_right():
    t = np.arange(0, 6, 1e-3)
    exact = ramped_step_second_order(t, 0.15)
    assert np.allclose(second_order(t, ramped_step(t, 0.15, 1.0)) / GAIN, exact, atol=1e-5)


@pytest.mark.parametrize("amplitude", [0.05, -0.05])
def test_step_response_of_second_order_system(amplitude):
    t = np.arange(0, 6, DT)
    wd = WN * math.sqrt(1 - ZETA**2)
    # (near-)ideal step: the textbook overshoot and peak time
    steer = ramped_step(t, DT, amplitude)
    s = step_response(t, steer, second_order(t, steer))
    assert s.overshoot == pytest.approx(math.exp(-math.pi * ZETA / math.sqrt(1 - ZETA**2)), rel=0.02)
    assert s.steady_state_gain == pytest.approx(GAIN, rel=0.005)
    assert s.peak_response_time_s == pytest.approx(math.pi / wd, abs=2 * DT)
    assert s.steady_state_value == pytest.approx(GAIN * amplitude, rel=0.005)
    assert s.peak_value == pytest.approx(GAIN * amplitude * (1 + s.overshoot), rel=1e-6)
    # the ISO 7401 ramp of 0.15 s filters the peak: about 8 % less overshoot than the ideal step.
    # Compared with the closed-form response to that ramped step.
    steer = ramped_step(t, 0.15, amplitude)
    s = step_response(t, steer, second_order(t, steer), steer_start_s=0.5)
    fine = np.arange(T_STEP, 4.0, 1e-5)
    exact = ramped_step_second_order(fine, 0.15)
    k = int(np.argmax(exact))
    t50 = T_STEP + 0.075
    assert s.steer_50_time_s == pytest.approx(t50, abs=1e-9)
    assert s.overshoot == pytest.approx(exact[k] - 1, rel=0.02)
    assert s.overshoot < 0.95 * math.exp(-math.pi * ZETA / math.sqrt(1 - ZETA**2))
    assert s.steady_state_gain == pytest.approx(GAIN, rel=0.005)
    assert s.peak_response_time_s == pytest.approx(fine[k] - t50, abs=2 * DT)
    assert s.response_time_s == pytest.approx(fine[np.argmax(exact >= 0.9)] - t50, abs=1e-3)
    assert s.rise_time_s == pytest.approx(fine[np.argmax(exact >= 0.9)] - fine[np.argmax(exact >= 0.1)], abs=1e-3)
    assert json.loads(json.dumps(s.to_dict(), allow_nan=False))["overshoot"] == pytest.approx(s.overshoot)


def test_step_response_negative_step_gives_the_same_figures():
    t = np.arange(0, 6, DT)
    up, down = (ramped_step(t, 0.15, a) for a in (0.05, -0.05))
    a, b = step_response(t, up, second_order(t, up)), step_response(t, down, second_order(t, down))
    for name in ("steady_state_gain", "steer_50_time_s", "response_time_s", "rise_time_s", "peak_response_time_s",
                 "overshoot"):
        assert getattr(b, name) == pytest.approx(getattr(a, name), rel=1e-9, abs=1e-12), name
    assert b.steady_state_value == pytest.approx(-a.steady_state_value) and b.peak_value == pytest.approx(-a.peak_value)
    # a channel of opposite sign (negative gain) too
    c = step_response(t, up, -second_order(t, up))
    assert c.steady_state_gain == pytest.approx(-GAIN, rel=0.005) and c.overshoot == pytest.approx(a.overshoot)


def test_step_response_first_order_lag_response_time():
    tau, ramp_s = 0.25, 0.15
    t = np.arange(0, 5, 0.001)
    steer = ramped_step(t, ramp_s)
    response = signal.lsim(([2.0], [tau, 1.0]), steer, t)[1]
    s = step_response(t, steer, response)
    # after the ramp, y = 1 - (tau / T_r)(e^(T_r / tau) - 1) e^(-(t - t_step) / tau)
    t90 = tau * math.log(10 * tau / ramp_s * (math.exp(ramp_s / tau) - 1))
    assert s.response_time_s == pytest.approx(t90 - ramp_s / 2, abs=1e-3)
    assert s.overshoot == 0.0 and math.isnan(s.peak_response_time_s)
    assert s.to_dict()["peak_response_time_s"] is None
    assert s.steady_state_gain == pytest.approx(2.0, rel=0.005)


def test_step_response_with_noise_and_offset():
    rng = np.random.default_rng(1)
    t = np.arange(0, 6, 0.01)
    steer = 0.01 + ramped_step(t, 0.15)  # steer offset before the step
    clean = second_order(t, steer - 0.01) + 0.2  # response offset
    s = step_response(t, steer + rng.normal(0, 1e-4, t.size), clean + rng.normal(0, 1e-3, t.size),
                      steer_start_s=0.9, steady_window_s=(4.5, 6.0))
    assert s.steady_state_gain == pytest.approx(GAIN, rel=0.01)
    assert s.steady_state_value == pytest.approx(0.2 + 0.05 * GAIN, rel=0.01)


def test_step_response_refuses_steer_without_step():
    t = np.arange(0, 5, 0.01)
    with pytest.raises(ValueError, match="no step"):
        step_response(t, np.full(t.size, 0.05), np.full(t.size, 0.1))
    pulse = 0.05 * ((t > 1) & (t < 2))  # a pulse returns to zero: no step
    with pytest.raises(ValueError, match="no step"):
        step_response(t, pulse, second_order(t, pulse))
    steer = ramped_step(t, 0.15)
    with pytest.raises(ValueError, match="steady window"):
        step_response(t, steer, second_order(t, steer), steady_window_s=4.5)


# ------------------------------------------------------------------------------ frequency response
FS = 100.0


def check_against(fr, h, f_lo, f_hi):
    """Gain within 3 % and phase within 3 deg of ``h`` over the whole band reported, which covers at
    least [f_lo, f_hi]."""
    f = fr.frequency_hz
    assert f[0] <= f_lo and f[-1] >= f_hi, (f[0], f[-1])
    exact = h(f)
    np.testing.assert_allclose(fr.gain, np.abs(exact), rtol=0.03)
    np.testing.assert_allclose(fr.phase_deg, np.degrees(np.angle(exact)), atol=3.0)


def h_second(f):
    s = 2j * np.pi * f
    return GAIN * WN**2 / (s**2 + 2 * ZETA * WN * s + WN**2)


def test_sine_sweep_shape():
    t = np.arange(0, 70, 1 / FS)
    x = sine_sweep(t, 0.02, 0.2, 4.0, 60.0, 5.0)
    assert np.all(x[t < 5.0] == 0) and np.all(x[t > 65.0] == 0) and np.abs(x).max() <= 0.02
    assert abs(x[np.argmin(np.abs(t - 5.0))]) < 1e-12 and abs(x[np.argmin(np.abs(t - 65.0))]) < 1e-6
    assert np.abs(x[(t > 30) & (t < 40)]).max() == pytest.approx(0.02, rel=1e-3)
    # instantaneous frequency halfway: 1 / (2 x the interval between the zero crossings about it)
    for method, f_mid in (("linear", 2.1), ("logarithmic", math.sqrt(0.2 * 4.0))):
        x = sine_sweep(t, 1.0, 0.2, 4.0, 60.0, 5.0, method=method)
        i = np.flatnonzero(np.diff(np.sign(x)) != 0)
        crossings = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
        k = np.searchsorted(crossings, 35.0)
        assert 1 / (2 * (crossings[k] - crossings[k - 1])) == pytest.approx(f_mid, rel=0.01)
    with pytest.raises(InputError, match="method"):
        sine_sweep(t, 1.0, 0.2, 4.0, 60.0, 5.0, method="cubic")


@pytest.mark.parametrize(("method", "f_lo", "f_hi"), [
    ("linear", 0.2 + 3.8 * 5 / 60, 4.0 - 3.8 * 5 / 60),  # the sweep at full amplitude, between the 5-s tapers
    ("logarithmic", 0.2 * 20 ** (5 / 60), 0.2 * 20 ** (55 / 60)),
])
def test_frequency_response_from_sweep(method, f_lo, f_hi):
    rng = np.random.default_rng(2)
    t = np.arange(0, 75, 1 / FS)
    steer = sine_sweep(t, 0.02, 0.2, 4.0, 60.0, 5.0, method=method)
    response = second_order(t, steer) + rng.normal(0, 0.0005, t.size)
    fr = frequency_response(t, steer, response)
    check_against(fr, h_second, f_lo, f_hi)
    assert fr.gain_at(1.5) == pytest.approx(abs(h_second(1.5)), rel=0.03)
    assert fr.phase_at(1.5) == pytest.approx(-90.0, abs=3.0)
    assert fr.frequency_hz[-1] < 6.0  # nothing reported far beyond the swept band
    with pytest.raises(InputError, match="outside the band"):
        fr.gain_at(20.0)


def test_frequency_response_from_random_steer_first_order():
    rng = np.random.default_rng(3)
    t = np.arange(0, 300, 1 / FS)
    sos = signal.butter(4, 8.0, fs=FS, output="sos")
    steer = signal.sosfiltfilt(sos, rng.normal(0, 0.02, t.size))
    tau = 0.08
    response = signal.lsim(([1.5], [tau, 1.0]), steer, t)[1] + rng.normal(0, 0.0005, t.size)
    fr = frequency_response(t, steer, response, f_max_hz=5.0)
    check_against(fr, lambda f: 1.5 / (1 + 2j * np.pi * f * tau), 0.1, 5.0)
    assert fr.frequency_hz[-1] <= 5.0
    np.testing.assert_allclose(fr.gain_at([0.5, 2.0]), np.abs(1.5 / (1 + 2j * np.pi * np.array([0.5, 2.0]) * tau)),
                               rtol=0.03)
    out = json.loads(json.dumps(fr.to_dict(), allow_nan=False))
    assert len(out["gain"]) == fr.gain.size and out["nperseg"] == 1000


def test_frequency_response_random_steer_second_order_and_plot():
    rng = np.random.default_rng(4)
    t = np.arange(0, 300, 1 / FS)
    steer = signal.sosfiltfilt(signal.butter(4, 8.0, fs=FS, output="sos"), rng.normal(0, 0.02, t.size))
    fr = frequency_response(t, steer, second_order(t, steer) + rng.normal(0, 0.0005, t.size), f_max_hz=5.0)
    check_against(fr, h_second, 0.1, 5.0)
    fig = fr.plot()
    assert fig.axes[0].get_xscale() == "log" and "phase [deg]" in fig.axes[1].get_ylabel()
    plt.close(fig)


def test_frequency_response_bad_input():
    t = np.arange(0, 20, 0.01)
    with pytest.raises(InputError, match="no frequency"):
        frequency_response(t, np.zeros(t.size), np.zeros(t.size))
    t_bad = t.copy()
    t_bad[100:] += 0.005
    x = np.sin(t)
    with pytest.raises(InputError, match="not uniform"):
        frequency_response(t_bad, x, x)


# ------------------------------------------------------------------------------ braking in a turn
R1, V0, DECEL, T0 = 40.0, 15.0, 4.0, 2.0


def braking_run(r_after=R1, direction=1, dt=0.005, t_end=5.0):
    """Steady circle (centre (0, dir R1)) until T0, then braking at DECEL on a circle of radius
    ``r_after`` tangent inside the first at the brake point (the same circle if ``r_after == R1``)."""
    t = np.arange(0, t_end + dt / 2, dt)
    tb = np.clip(t - T0, 0, None)
    v = V0 - DECEL * tb
    s_after = V0 * tb - 0.5 * DECEL * tb**2  # arc length since brake start
    theta0 = V0 * np.minimum(t, T0) / R1  # angle swept on the first circle
    # the brake point P and the unit vector e0 from the first centre to it, then the second circle
    th_b = V0 * T0 / R1
    e0 = np.array([math.sin(th_b), -math.cos(th_b)])
    c2 = (R1 - r_after) * e0  # relative to the first centre
    phi = th_b + s_after / r_after
    x = np.where(t <= T0, R1 * np.sin(theta0), c2[0] + r_after * np.sin(phi))
    y_rel = np.where(t <= T0, -R1 * np.cos(theta0), c2[1] - r_after * np.cos(phi))  # relative to the centre
    y = R1 + y_rel
    wz = np.where(t <= T0, V0 / R1, v / r_after)
    ay = v * wz
    return t, x, direction * y, direction * wz, v, direction * ay


@pytest.mark.parametrize("direction", [1, -1])
def test_braking_on_the_circle_keeps_the_path(direction):
    t, x, y, wz, v, ay = braking_run(direction=direction)
    b = braking_in_turn(t, x, y, wz, v, ay, brake_start_s=T0, circle_centre_xy=(0.0, direction * R1), radius_m=R1)
    assert abs(b.path_deviation_m) < 1e-9 and abs(b.path_deviation_max_m) < 1e-9
    assert b.yaw_rate_ratio == pytest.approx((V0 - DECEL) / V0, rel=1e-9)
    assert b.lateral_acceleration_ratio == pytest.approx(((V0 - DECEL) / V0) ** 2, rel=1e-9)
    assert abs(b.yaw_rate_excess_radps) < 1e-12 and abs(b.yaw_rate_excess_max_radps) < 1e-12
    assert b.mean_deceleration_mps2 == pytest.approx(DECEL, rel=1e-9)
    assert b.speed_initial_mps == pytest.approx(V0)
    assert b.yaw_rate_initial_radps == pytest.approx(direction * V0 / R1)
    assert json.loads(json.dumps(b.to_dict(), allow_nan=False))["yaw_rate_ratio"] == pytest.approx(b.yaw_rate_ratio)


@pytest.mark.parametrize("direction", [1, -1])
def test_braking_turning_in_gives_negative_deviation(direction):
    r2 = 30.0
    t, x, y, wz, v, ay = braking_run(r_after=r2, direction=direction)
    b = braking_in_turn(t, x, y, wz, v, ay, brake_start_s=T0, circle_centre_xy=(0.0, direction * R1), radius_m=R1)

    def deviation(tb):  # radial distance of the point on the inner circle from the first circle
        phi = (V0 * tb - 0.5 * DECEL * tb**2) / r2
        return math.sqrt((R1 - r2) ** 2 + 2 * (R1 - r2) * r2 * math.cos(phi) + r2**2) - R1

    # the size expected: for small angles d = -(1/r2 - 1/R1) s^2 / 2, s the arc length since t0
    assert deviation(1.0) == pytest.approx(-0.5 * (1 / r2 - 1 / R1) * 13.0**2, rel=0.05)
    assert b.path_deviation_m == pytest.approx(deviation(1.0), abs=1e-6)
    assert b.path_deviation_m < -0.5
    assert b.path_deviation_max_m == pytest.approx(deviation(3.0), abs=1e-6)  # grows until the record ends
    v1 = V0 - DECEL
    assert b.yaw_rate_excess_radps == pytest.approx(v1 / r2 - v1 / R1, rel=1e-9)
    assert b.yaw_rate_ratio == pytest.approx((v1 / r2) / (V0 / R1), rel=1e-9)
    assert b.mean_deceleration_mps2 == pytest.approx(DECEL, rel=1e-9)
    assert b.yaw_rate_excess_max_radps == pytest.approx(V0 / r2 - V0 / R1, rel=1e-2)


def test_braking_in_turn_bad_input():
    t, x, y, wz, v, ay = braking_run()
    with pytest.raises(InputError, match="within the record"):
        braking_in_turn(t, x, y, wz, v, ay, brake_start_s=4.5, circle_centre_xy=(0, R1), radius_m=R1)
    with pytest.raises(InputError, match="not turning"):
        braking_in_turn(t, x, y, 0 * wz, v, ay, brake_start_s=T0, circle_centre_xy=(0, R1), radius_m=R1)
    with pytest.raises(InputError, match="speed_mps"):
        braking_in_turn(t, x, y, wz, v[:-1], ay, brake_start_s=T0, circle_centre_xy=(0, R1), radius_m=R1)
