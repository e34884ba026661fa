"""Verification ladder, rung 3: mass matrix and dynamics against MuJoCo at random states."""

import numpy as np
import pytest

from trikedyn.model.dynamics import crba, forward_dynamics, rnea
from trikedyn.model.topology import build_tree

from .mujoco_oracle import accelerations, mass_matrix, model_and_data, set_state, velocity_map

G = np.array([0.0, 0.0, -9.80665])


def random_state(rng, n):
    q = np.zeros(n)
    q[:3] = rng.normal(0, 1, 3)
    q[3:6] = rng.uniform(-0.6, 0.6, 3)  # roll, pitch, yaw
    q[6:] = rng.uniform(-0.5, 0.5, n - 6)
    u = rng.normal(0, 2.0, n)
    return q, u


@pytest.fixture(scope="module")
def tree(reference):
    return build_tree(reference.params)


def test_mass_matrix_equals_mujoco_at_50_states(tree):
    model, data = model_and_data(tree)
    rng = np.random.default_rng(1)
    n = tree.n_dof
    for _ in range(50):
        q, u = random_state(rng, n)
        set_state(model, data, q, u)
        t = velocity_map(q, n)
        expected = t.T @ mass_matrix(model, data) @ t
        ours = crba(q, *tree.arrays())
        scale = np.abs(expected).max()
        assert np.abs(ours - expected).max() <= 1e-8 * scale
        assert np.allclose(ours, ours.T, rtol=0, atol=1e-12 * scale)
        assert np.linalg.eigvalsh(ours).min() > 0


def test_accelerations_equal_mujoco_at_50_states(tree):
    """Same state, same applied generalised forces: same accelerations (bias forces included)."""
    model, data = model_and_data(tree, tuple(G))
    rng = np.random.default_rng(2)
    n = tree.n_dof
    fext = np.zeros((tree.n_bodies, 6))
    for _ in range(50):
        q, u = random_state(rng, n)
        qfrc = rng.normal(0, 200.0, n)
        set_state(model, data, q, u)
        expected = accelerations(model, data, q, u, qfrc)
        tau = velocity_map(q, n).T @ qfrc
        ours = forward_dynamics(q, u, tau, fext, G, *tree.arrays())
        assert np.abs(ours - expected).max() <= 1e-8 * max(np.abs(expected).max(), 1.0)


def test_bias_forces_equal_mujoco(tree):
    """C(q, u) from our RNEA equals MuJoCo's bias mapped into our coordinates: C = T^T (c_mj + M dT/dt u)."""
    model, data = model_and_data(tree, tuple(G))
    rng = np.random.default_rng(3)
    n = tree.n_dof
    fext = np.zeros((tree.n_bodies, 6))
    for _ in range(50):
        q, u = random_state(rng, n)
        set_state(model, data, q, u)
        m = mass_matrix(model, data)
        bias_mj = data.qfrc_bias.copy()
        t = velocity_map(q, n)
        # dT/dt u: only the block R v changes: d(R)/dt v = R (w x v)
        tdot_u = np.zeros(n)
        tdot_u[:3] = t[:3, 3:6] @ np.cross(u[:3], u[3:6])
        expected = t.T @ (bias_mj + m @ tdot_u)
        ours = rnea(q, u, np.zeros(n), fext, G, *tree.arrays())
        assert np.abs(ours - expected).max() <= 1e-8 * max(np.abs(expected).max(), 1.0)
