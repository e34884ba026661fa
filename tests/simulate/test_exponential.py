"""The exponential step (ETDRK4 with each wheel's spin-slip pair exact): its block functions against scipy,
its stability where the spin-slip mode is hardly damped, and the automatic step."""

import numpy as np
import pytest
import scipy.linalg as sl
from numba import njit

import trikedyn as td
from trikedyn.simulate.exponential import BLOCK_WIDTH, block_functions, expm2, phi_functions


@njit
def _functions(mat, h):
    out = np.zeros((mat.shape[0], BLOCK_WIDTH))
    block_functions(mat, mat.shape[0], h, out)
    return out


def _phis(m):
    """``exp(M), phi_1(M), phi_2(M), phi_3(M)`` from the exponential of an augmented matrix."""
    z = np.zeros((8, 8))
    z[:2, :2] = m
    z[:2, 2:4] = z[2:4, 4:6] = z[4:6, 6:8] = np.eye(2)
    f = sl.expm(z)
    return f[:2, :2], f[:2, 2:4], f[:2, 4:6], f[:2, 6:8]


BLOCKS = [
    [0.0, -45000.0, 1.8, -9.8],  # the spin-slip block at walking pace: a lightly damped 285 rad/s pair
    [0.0, -33000.0, 1.8, -74.0],  # at 40 km/h
    [0.0, 0.0, 1.8, -74.0],  # a wheel off the ground: no slip stiffness
    [0.0, 0.0, 0.0, 0.0],  # nothing
    [-3.0, 1.0, 0.0, -3.0],  # a repeated eigenvalue (defective)
    [2.0, 5.0, 0.5, -1.0],  # real, distinct, one growing
    [-1e-9, 0.0, 0.0, 1e-9],  # nearly coincident
]


@pytest.mark.parametrize("block", BLOCKS)
@pytest.mark.parametrize("h", [1e-3, 1e-2])
def test_block_functions_match_scipy(block, h):
    row = _functions(np.array([block]), h)[0]
    m = h * np.array(block).reshape(2, 2)
    e_half, phi1_half, _, _ = _phis(m / 2)
    _, p1, p2, p3 = _phis(m)
    expected = [e_half, phi1_half, p1 - 3 * p2 + 4 * p3, 2 * p2 - 4 * p3, 4 * p3 - p2]
    for k, want in enumerate(expected):
        got = row[4 * k: 4 * k + 4].reshape(2, 2)
        assert np.allclose(got, want, rtol=1e-9, atol=1e-12), (k, got, want)
    assert np.allclose(np.array(expm2(*block, h)).reshape(2, 2), sl.expm(m), rtol=1e-10, atol=1e-13)


@pytest.mark.parametrize("z", [0.0, 1e-6, 0.3 + 0.2j, -0.49, 0.51, -3.0 + 2.8j, 2.0, -60.0])
def test_phi_functions_of_a_scalar(z):
    e, p1, p2, p3, p4 = phi_functions(complex(z))
    f = sl.expm(np.array([[z, 1, 0, 0, 0], [0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1], [0, 0, 0, 0, 0]],
                         dtype=complex))
    for got, want in zip((e, p1, p2, p3, p4), f[0], strict=True):
        assert abs(got - want) <= 1e-12 * max(1.0, abs(want))


def test_walking_pace_is_stable_at_the_default_step(reference):
    """At 5 km/h the spin-slip mode is hardly damped (v_ref / sigma_x ~ 10/s): the default 10 ms step follows
    classical RK4 at 1.25 ms to 0.1 mm/s (Lawson's integrating-factor RK4 with the same blocks drifted by
    76 mm/s in 8 s: its quadrature of the coupling left outside the blocks grows by 5 % a step)."""
    kw = {"duration_s": 8.0, "speed_kmh": 5.0, "drive_torque_Nm": 25.0, "steer_rad": 0.05}
    fine = td.run_open_loop(reference, dt=1.25e-3, integrator="rk4", **kw)
    ours = td.run_open_loop(reference, **kw)
    assert ours.meta["dt_s"] == 0.01
    assert np.abs(ours["vx_mps"] - fine["vx_mps"]).max() < 1e-3
    static = fine["rear_left_fz_N"][0]
    assert np.abs(ours["rear_left_fz_N"] - fine["rear_left_fz_N"]).max() < 0.005 * static


def test_a_bumpy_road_halves_the_automatic_step(reference):
    bump = td.speed_bump(3.0, length_m=0.5, height_m=0.05, lateral_m=(0.0, 0.3))
    flat = td.run_open_loop(reference, duration_s=0.5, speed_kmh=5.0)
    bumpy = td.run_open_loop(reference, duration_s=0.5, speed_kmh=5.0, road=bump)
    assert flat.meta["dt_s"] == 0.01 and bumpy.meta["dt_s"] == 0.005


def test_unknown_integrator_is_an_input_error(reference):
    with pytest.raises(td.InputError, match="unknown integrator 'euler'"):
        td.run_open_loop(reference, duration_s=0.5, speed_kmh=5.0, integrator="euler")
