"""Linearisation about an equilibrium or steady rolling, and the vibration modes (``trikedyn modes``).

The state is reduced to the coordinates that matter for small motions: the chassis' horizontal position,
heading and the wheels' spin angles are cyclic (nothing depends on them) and are left out; every velocity
(the wheels' spin rates included) and the tyres' transient slips are kept. The Jacobian is taken by
central differences of the compiled right-hand side; each complex pair of eigenvalues is a mode with
undamped natural frequency ``|lambda| / 2 pi`` and damping ratio ``-Re(lambda) / |lambda|``, named after
what carries its kinetic energy (body bounce, pitch, roll, yaw, each wheel's hop, steer, ...; see
:mod:`trikedyn.model.modal_names`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .modal_names import assign_names, energy_shares, modal_coordinates
from .statics import Equilibrium, rolling_state, state_derivative
from .vehicle import VehicleModel

__all__ = ["Mode", "SingleTrack", "linearise", "modes", "single_track"]


@dataclass(frozen=True)
class Mode:
    """One vibration mode.

    Attributes
    ----------
    name : str
        What moves (see :mod:`trikedyn.model.modal_names`).
    frequency_hz : float
        Undamped natural frequency ``|lambda| / 2 pi`` [Hz].
    damping_ratio : float
        ``-Re(lambda) / |lambda|`` [1].
    eigenvalue : complex
        ``lambda`` [1/s].
    participation : dict
        Share of the mode's kinetic energy [1] per motion, largest first.
    """

    name: str
    frequency_hz: float
    damping_ratio: float
    eigenvalue: complex
    participation: dict

    def to_dict(self) -> dict:
        """The mode as a JSON-ready dict.

        Returns
        -------
        dict
            ``name``, ``frequency_hz`` [Hz], ``damping_ratio`` (dimensionless), ``eigenvalue`` as [real, imag]
            [1/s] and ``participation``.
        """
        return {
            "name": self.name,
            "frequency_hz": self.frequency_hz,
            "damping_ratio": self.damping_ratio,
            "eigenvalue": [self.eigenvalue.real, self.eigenvalue.imag],
            "participation": self.participation,
        }


def _positions(model: VehicleModel) -> list[int]:
    """State indices of the non-cyclic coordinates: chassis height, roll, pitch, and every joint that is
    not a wheel's spin."""
    wheels = {w.wheel_body for w in model.tree.wheels}
    return [2, 3, 4] + [5 + i for i in range(1, model.tree.n_bodies) if i not in wheels]


def linearise(model: VehicleModel, state: np.ndarray, *, eps: float = 1e-6):
    """``A = d(dx/dt)/dx`` on the reduced state (positions, all velocities, slips), by central differences.

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    state : numpy.ndarray, shape (n_states,)
        The state to linearise about (e.g. an equilibrium, or rolling).
    eps : float
        Relative central-difference step, dimensionless (scaled by ``max(1, |x_j|)``).

    Returns
    -------
    a : ndarray (m, m)
    positions : list[int]
        State indices of the reduced positions (the reduced state is these, then all velocities and slips).
    """
    n = model.n_dof
    pos = _positions(model)
    keep = pos + list(range(n, model.n_states))
    m = len(keep)
    a = np.empty((m, m))
    for j, col in enumerate(keep):
        step = eps * max(1.0, abs(state[col]))
        xp = state.copy()
        xm = state.copy()
        xp[col] += step
        xm[col] -= step
        a[:, j] = (state_derivative(model, xp)[0][keep] - state_derivative(model, xm)[0][keep]) / (2 * step)
    return a, pos


def modes(model: VehicleModel, equilibrium: Equilibrium | np.ndarray, *, speed_mps: float = 0.0,
          min_hz: float = 0.05) -> list[Mode]:
    """Oscillatory modes about an equilibrium (or a state), sorted by frequency, named by what moves.

    Parameters
    ----------
    model : VehicleModel
    equilibrium : Equilibrium or ndarray
        The static equilibrium, or the full state to linearise about.
    speed_mps : float
        With an :class:`Equilibrium`: linearise about steady straight rolling at this speed [m/s]
        (:func:`~trikedyn.model.statics.rolling_state`); 0 is standstill.
    min_hz : float
        Modes below this undamped natural frequency [Hz] are left out.

    Returns
    -------
    list of Mode
        ``participation``: each motion's share of the mode's kinetic energy [1] (those of 5 % or more,
        largest first); ``name``: see :func:`~trikedyn.model.modal_names.assign_names`.
    """
    if isinstance(equilibrium, Equilibrium):
        state = rolling_state(model, equilibrium, speed_mps) if speed_mps else equilibrium.state
    else:
        state = np.asarray(equilibrium, dtype=float)
    a, pos = linearise(model, state)
    coords = modal_coordinates(model, state)
    values, vectors = np.linalg.eig(a)
    n = model.n_dof
    found, rows = [], []
    for k, lam in enumerate(values):
        w = abs(lam)
        if lam.imag <= 0 or w / (2 * np.pi) < min_hz:
            continue
        share = energy_shares(coords, vectors[len(pos) : len(pos) + n, k])
        if share.sum() <= 0:
            continue
        found.append(lam)
        rows.append(share)
    if not found:
        return []
    names = assign_names(np.array(rows), coords.groups, coords.unique)
    out = []
    for lam, share, name in zip(found, rows, names, strict=True):
        w = abs(lam)
        order = np.argsort(-share, kind="stable")
        participation = {coords.groups[i]: float(share[i]) for i in order if share[i] >= 0.05}
        out.append(Mode(name, w / (2 * np.pi), float(-lam.real / w), complex(lam), participation))
    return sorted(out, key=lambda md: md.frequency_hz)


@dataclass(frozen=True)
class SingleTrack:
    """The linear single-track (bicycle) model of a vehicle at its static loads.

    Attributes
    ----------
    wheelbase_m : float
    mass_kg : float
    front_load_N, rear_load_N : float
        Static axle loads [N].
    front_cornering_stiffness_N_per_rad, rear_cornering_stiffness_N_per_rad : float
        Axle cornering stiffnesses at those loads (sum over the axle's tyres) [N/rad].
    understeer_gradient_rad_per_mps2 : float
        ``K = m_f / C_f - m_r / C_r`` [rad / (m/s^2)] (axle masses ``m = F_z / g``).
    """

    wheelbase_m: float
    mass_kg: float
    front_load_N: float
    rear_load_N: float
    front_cornering_stiffness_N_per_rad: float
    rear_cornering_stiffness_N_per_rad: float
    understeer_gradient_rad_per_mps2: float

    def road_steer_rad(self, speed_mps: float, lateral_acceleration_mps2: float) -> float:
        """Steady-state road-wheel steer angle for a lateral acceleration at a speed:
        ``delta = (L / v^2 + K) a_y`` [rad].

        Parameters
        ----------
        speed_mps : float
            Forward speed [m/s].
        lateral_acceleration_mps2 : float
            Steady lateral acceleration [m/s^2].

        Returns
        -------
        float
            Road-wheel steer angle [rad].
        """
        return (self.wheelbase_m / speed_mps**2 + self.understeer_gradient_rad_per_mps2) * lateral_acceleration_mps2

    @property
    def understeer_gradient_deg_per_g(self) -> float:
        """The understeer gradient ``K`` in [deg/g] (positive: understeer)."""
        return float(np.degrees(self.understeer_gradient_rad_per_mps2) * 9.80665)


def single_track(model: VehicleModel) -> SingleTrack:
    """The linear single-track model from the static wheel loads and the tyres' cornering stiffness.

    Parameters
    ----------
    model : VehicleModel
        The vehicle (its static equilibrium on a flat road gives the axle loads).

    Returns
    -------
    SingleTrack
        Wheelbase [m], mass [kg], axle loads [N], axle cornering stiffnesses [N/rad] and the understeer
        gradient ``K = F_f / (g C_f) - F_r / (g C_r)`` [rad/(m/s^2)]; cached on the model.
    """
    from ..tyre.interface import linear_stiffnesses
    from .statics import static_equilibrium

    key = ("single_track",)
    if key in model.cache:
        return model.cache[key]
    eq = static_equilibrium(model.on_flat_road())
    g = model.gravity
    front = [w.name for w in model.tree.wheels if model.params.wheel(w.name).x_m > 0.5 * model.params.wheelbase_m]
    loads = eq.wheel_loads_N
    f_front = sum(loads[n] for n in front)
    f_rear = sum(v for n, v in loads.items() if n not in front)
    stiffness = {w.name: linear_stiffnesses(t.name or t.model, t.coefficients, loads[w.name])[1]
                 for w, t in zip(model.tree.wheels, model.tyres, strict=True)}
    c_front = sum(stiffness[n] for n in front)
    c_rear = sum(v for n, v in stiffness.items() if n not in front)
    k = f_front / g / c_front - f_rear / g / c_rear
    out = SingleTrack(model.params.wheelbase_m, (f_front + f_rear) / g, f_front, f_rear, c_front, c_rear, k)
    model.cache[key] = out
    return out
