"""Static equilibrium and steady straight running, found by a solver; linearisation and modes.

Every simulation starts from an equilibrium, never from a guessed state that rings. At rest the unknowns
are the chassis height, roll and pitch and every joint that is not a wheel's spin (steer, fork,
swing arms); the residuals are the accelerations of those coordinates with all velocities zero.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import root

from ..errors import SimulationError
from .rhs import f_with_outputs
from .vehicle import VehicleModel

__all__ = ["Equilibrium", "rolling_state", "state_derivative", "static_equilibrium"]


def state_derivative(model: VehicleModel, x: np.ndarray, t: float = 0.0, inputs: np.ndarray | None = None):
    """``dx/dt`` and the per-wheel outputs (:data:`~trikedyn.model.packing.WHEEL_OUT`) at one state.

    ``inputs``: the inputs ``(steer [rad], drive [N m], brake [N m])``; zero by default.

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    x : array_like
        State (``model.state_names``).
    t : float
        Time [s].
    inputs : array_like, shape (3,), optional
        Steer [rad], drive torque [N m], brake torque [N m].

    Returns
    -------
    xdot : numpy.ndarray
        ``dx/dt``.
    wout : numpy.ndarray, dtype WHEEL_OUT
        The per-wheel outputs (loads [N], forces, slips).
    """
    u = np.zeros(3) if inputs is None else np.array(inputs, dtype=float).reshape(3)
    # a writable C-contiguous copy: a read-only or strided state would be another type to numba, so another
    # compilation of the whole right-hand side
    return f_with_outputs(t, np.array(x, dtype=float, order="C"), u, model.plant)


def _free_joints(model: VehicleModel) -> list[int]:
    wheels = {w.wheel_body for w in model.tree.wheels}
    return [5 + i for i in range(1, model.tree.n_bodies) if i not in wheels]


@dataclass(frozen=True)
class Equilibrium:
    """A static equilibrium: the state, the wheel loads [N] and the solver's residual."""

    state: np.ndarray
    wheel_loads_N: dict
    residual: float


def static_equilibrium(model: VehicleModel, *, tol: float = 1e-10) -> Equilibrium:
    """The vehicle at rest on flat ground: solve for height, roll, pitch and the joint deflections.

    Parameters
    ----------
    model : VehicleModel
        The vehicle (on its road; flat ground is assumed at rest).
    tol : float
        Solver tolerance on the residual, in the generalised forces' units [N, N m].

    Returns
    -------
    Equilibrium
        The state, the wheel loads [N] and the residual; cached on the model.

    Raises
    ------
    SimulationError
        When the solver finds no equilibrium (e.g. the vehicle cannot stand).
    """
    key = ("static_equilibrium", tol)
    if key not in model.cache:
        model.cache[key] = _solve_static(model, tol)
    return model.cache[key]


def _solve_static(model: VehicleModel, tol: float) -> Equilibrium:
    n = model.n_dof
    joints = _free_joints(model)
    unknown = [2, 3, 4, *joints]
    residual_rows = [n + 0, n + 1, n + 5, *(n + j for j in joints)]
    radius = float(np.mean([w.radius for w in model.tree.wheels]))
    load = model.tree.total_mass() * 9.81 / len(model.tree.wheels)
    guess = np.zeros(len(unknown))
    guess[0] = -load / float(np.mean(model.wheels["vertical_stiffness"]))

    def residual(p):
        """The accelerations that vanish at rest (roll and pitch [rad/s^2], vertical [m/s^2], free joints') of the
        state whose chassis height [m], roll, pitch [rad] and free joints are ``p``, the rest 0."""
        x = np.zeros(model.n_states)
        x[unknown] = p
        xdot, _ = state_derivative(model, x)
        return xdot[residual_rows]

    sol = root(residual, guess, method="hybr", options={"xtol": 1e-13})
    x = np.zeros(model.n_states)
    x[unknown] = sol.x
    xdot, wout = state_derivative(model, x)
    res = float(np.abs(xdot[n : 2 * n]).max())
    if not sol.success and res > tol * 1e3 or res > 1e-6:
        raise SimulationError(f"no static equilibrium found ({sol.message}; residual {res:.2e} m/s^2)", 0.0)
    if x[2] < -radius:
        raise SimulationError("static equilibrium has the chassis below the road", 0.0)
    loads = {w.name: float(wout[k]["fz"]) for k, w in enumerate(model.tree.wheels)}
    return Equilibrium(x, loads, res)


def rolling_state(model: VehicleModel, equilibrium: Equilibrium, speed_mps: float, heading_rad: float = 0.0):
    """The equilibrium state rolling straight ahead at ``speed_mps``: chassis velocity, wheel spins
    ``v / R_e`` (effective radius at the static deflection) and the transient slips at their steady
    rolling values (zero slip angle; the small longitudinal slip of rolling resistance settles within
    a few relaxation lengths).

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    equilibrium : Equilibrium
        Its static equilibrium (:func:`static_equilibrium`).
    speed_mps : float
        Forward speed [m/s].
    heading_rad : float
        Yaw angle [rad].

    Returns
    -------
    numpy.ndarray
        The state.
    """
    n = model.n_dof
    x = equilibrium.state.copy()
    x[5] = heading_rad
    _, wout = state_derivative(model, x)
    pitch = x[4]
    x[n + 3] = speed_mps * np.cos(pitch)
    x[n + 5] = speed_mps * np.sin(pitch)
    for k, w in enumerate(model.tree.wheels):
        r_eff = w.radius - wout[k]["deflection"] / 3.0
        x[n + 5 + w.wheel_body] = speed_mps / r_eff
    return x
