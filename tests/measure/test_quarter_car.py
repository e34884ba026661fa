"""Tests of trikedyn.measure.quarter_car: the two-mass quarter car used as the identification reference."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import eigh

from trikedyn.errors import InputError
from trikedyn.measure.quarter_car import quarter_car_free_decay, quarter_car_matrices, quarter_car_modes
from trikedyn.units import STANDARD_GRAVITY

MS, MU, K, C, KT, CT = 200.0, 25.0, 40e3, 1500.0, 200e3, 75.0


def _state_matrix(ms, mu, k, c, kt, ct):
    m, cm, km = quarter_car_matrices(ms, mu, k, c, kt, ct)
    return np.block([[np.zeros((2, 2)), np.eye(2)], [-np.linalg.solve(m, km), -np.linalg.solve(m, cm)]])


def test_matrices():
    m, c, k = quarter_car_matrices(MS, MU, K, C, KT, CT)
    np.testing.assert_array_equal(m, [[200.0, 0.0], [0.0, 25.0]])
    np.testing.assert_array_equal(c, [[1500.0, -1500.0], [-1500.0, 1575.0]])
    np.testing.assert_array_equal(k, [[40e3, -40e3], [-40e3, 240e3]])


def test_undamped_modes_are_the_generalised_eigenvalues():
    modes = quarter_car_modes(MS, MU, K, 0.0, KT)
    m, _, k = quarter_car_matrices(MS, MU, K, 0.0, KT)
    expected = np.sqrt(eigh(k, m, eigvals_only=True)) / (2 * np.pi)
    np.testing.assert_allclose(modes.natural_frequency_hz, expected, rtol=1e-10)
    np.testing.assert_allclose(modes.damping_ratio, 0.0, atol=1e-10)


def test_rigid_tyre_and_light_wheel_give_the_single_mass_oscillator():
    # K_t -> infinity, m -> 0: body mode f = sqrt(K/M)/2pi = sqrt(200)/2pi = 2.2508 Hz, xi = C/(2 sqrt(K M))
    # = 1500 / (2 sqrt(8e6)) = 0.26517.
    modes = quarter_car_modes(MS, 1e-3, K, C, 1e12)
    assert modes.sprung_frequency_hz == pytest.approx(2.250791, rel=1e-5)
    assert modes.sprung_damping_ratio == pytest.approx(0.265165, rel=1e-5)


def test_modes_sorted_body_first_and_overdamped_wheel_pair():
    modes = quarter_car_modes(240.0, 20.0, 80e3, 6119.0, KT)
    assert modes.sprung_frequency_hz < modes.unsprung_frequency_hz
    assert modes.sprung_damping_ratio == pytest.approx(0.400, abs=1e-3)
    assert modes.unsprung_damping_ratio > 1.0  # two real eigenvalues
    lam = np.linalg.eigvals(_state_matrix(240.0, 20.0, 80e3, 6119.0, KT, 0.0))
    np.testing.assert_allclose(np.sort_complex(modes.eigenvalues), np.sort_complex(lam), rtol=1e-9)


def test_release_matches_adaptive_integration_and_initial_value():
    a_mat = _state_matrix(MS, MU, K, C, KT, CT)
    x0 = np.array([0.02, 0.02 * K / (K + KT), 0.0, 0.0])
    t, a = quarter_car_free_decay(MS, MU, K, C, KT, CT, duration_s=3.0, sample_rate_hz=100.0,
                                  initial_displacement_m=0.02, event_time_s=0.5)
    sol = solve_ivp(lambda _, x: a_mat @ x, (0.5, 3.0), x0, t_eval=t[t >= 0.5], rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(a[t >= 0.5], (a_mat @ sol.y)[2], atol=1e-8)
    np.testing.assert_array_equal(a[t < 0.5], 0.0)  # held
    # Released from the quasi-static position: a = -K_eq x0 / M_s, K_eq = 40e3*200e3/240e3 = 33333 N/m
    assert a[50] == pytest.approx(-33333.33 * 0.02 / 200.0, rel=1e-6)


def test_bump_matches_adaptive_integration():
    h, length, v, t0 = 0.05, 0.5, 1.389, 0.3
    a_mat = _state_matrix(MS, MU, K, C, KT, CT)
    om = 2 * np.pi * v / length

    def rhs(t, x):
        on = t0 <= t <= t0 + length / v
        zr = h / 2 * (1 - np.cos(om * (t - t0))) if on else 0.0
        zr_dot = h / 2 * om * np.sin(om * (t - t0)) if on else 0.0
        dx = a_mat @ x
        dx[3] += (KT * zr + CT * zr_dot) / MU
        return dx

    t, a = quarter_car_free_decay(MS, MU, K, C, KT, CT, duration_s=2.0, sample_rate_hz=100.0,
                                  bump=(h, length, v), event_time_s=t0)
    sol = solve_ivp(rhs, (0.0, 2.0), np.zeros(4), t_eval=t, rtol=1e-10, atol=1e-12, max_step=2e-3)
    np.testing.assert_allclose(a, (a_mat @ sol.y)[2], atol=1e-6 * np.abs(a).max())


def test_gravity_bias_noise_and_seed():
    # Held throughout: it reads g + bias + noise.
    kw = {"duration_s": 20.0, "sample_rate_hz": 100.0, "initial_displacement_m": 0.01, "event_time_s": 20.0,
          "noise_std_mps2": 0.1, "bias_mps2": 0.3, "include_gravity": True}
    t, a = quarter_car_free_decay(MS, MU, K, C, KT, seed=1, **kw)
    assert len(t) == 2000 and t[1] - t[0] == pytest.approx(0.01)
    assert a.mean() == pytest.approx(STANDARD_GRAVITY + 0.3, abs=0.01)
    assert a.std() == pytest.approx(0.1, rel=0.05)
    np.testing.assert_array_equal(a, quarter_car_free_decay(MS, MU, K, C, KT, seed=1, **kw)[1])


def test_bad_input():
    with pytest.raises(InputError) as err:
        quarter_car_matrices(-1.0, MU, K, C, KT)
    assert err.value.where == "sprung_mass"
    with pytest.raises(InputError, match="exactly one"):
        quarter_car_free_decay(MS, MU, K, C, KT, duration_s=1.0, sample_rate_hz=10.0)
    with pytest.raises(InputError, match="exactly one"):
        quarter_car_free_decay(MS, MU, K, C, KT, duration_s=1.0, sample_rate_hz=10.0,
                               initial_displacement_m=0.01, bump=(0.05, 0.5, 1.0))
