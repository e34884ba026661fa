"""Verification ladder, rung 3: energy and momentum invariants of the full model."""

import numpy as np
import pytest

from trikedyn.model.statics import rolling_state, static_equilibrium
from trikedyn.model.vehicle import build_model
from trikedyn.simulate.integrator import OPEN_LOOP, STATUS_OK, rk4_loop

from .energy import kinetic_energy, momenta, potential_energy


@pytest.fixture(scope="module")
def conservative(reference):
    """Dampers, tyre slip forces, drive and drag off: only springs, gravity and inertia remain."""
    return build_model(reference).variant(damping=False, slip_forces=False, drag=False)


def test_energy_conserved_bouncing_and_rolling(conservative):
    model = conservative
    n = model.n_dof
    eq = static_equilibrium(model)
    x0 = rolling_state(model, eq, 5.0)
    x0[2] += 0.01  # dropped from 10 mm: bounce, with roll and pitch
    x0[n + 0] = 0.05  # roll rate
    x0[n + 1] = -0.04  # pitch rate
    x0[n + 5 + 1] = 0.3  # steer rate
    energy0 = kinetic_energy(model, x0) + potential_energy(model, x0)
    scale = kinetic_energy(model, x0)
    times, states, _, _, _, status, rec, _ = rk4_loop(x0, 0.0, 2.5e-4, 40000, 400, np.zeros((1, 4)), *OPEN_LOOP, model.plant,
                                                       True, 0.0)
    assert status == STATUS_OK and times[rec - 1] == pytest.approx(10.0)
    energy = np.array([kinetic_energy(model, x) + potential_energy(model, x) for x in states[:rec]])
    drift = np.abs(energy - energy0).max() / scale
    assert drift < 1e-6, drift
    # it really moved: the vehicle rolled 50 m and the suspension worked
    assert states[rec - 1][0] > 45.0
    assert np.ptp(states[:rec, 2]) > 0.005


def test_momentum_conserved_in_free_flight(conservative):
    model = conservative.variant(gravity=0.0)
    n = model.n_dof
    rng = np.random.default_rng(5)
    x0 = np.zeros(model.n_states)
    x0[2] = 20.0  # far above the road: no contact during the run
    x0[3:6] = (0.1, -0.05, 0.3)
    x0[6:n] = rng.uniform(-0.03, 0.03, n - 6)
    x0[n : 2 * n] = rng.normal(0.0, 1.0, n)
    lin0, ang0 = momenta(model, x0)
    times, states, _, _, _, status, rec, _ = rk4_loop(x0, 0.0, 2.5e-4, 8000, 400, np.zeros((1, 4)), *OPEN_LOOP, model.plant,
                                                       True, 0.0)
    assert status == STATUS_OK
    for x in states[:rec]:
        lin, ang = momenta(model, x)
        assert np.abs(lin - lin0).max() <= 1e-8 * np.abs(lin0).max()
        assert np.abs(ang - ang0).max() <= 1e-8 * np.abs(ang0).max()
