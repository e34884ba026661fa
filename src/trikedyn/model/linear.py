"""Linearisation about an equilibrium, and the vibration modes (``trikedyn modes``).

The state is reduced to the coordinates that matter for small motions: the chassis' horizontal position,
heading and the wheels' spin angles are cyclic (nothing depends on them) and are left out. The Jacobian
is taken by central differences of the compiled right-hand side; each complex pair of eigenvalues is a
mode with undamped natural frequency ``|lambda| / 2 pi`` and damping ratio ``-Re(lambda) / |lambda|``,
named after the coordinate that dominates its eigenvector (displacements scaled to metres at the wheel
or at the chassis' extremities).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .statics import Equilibrium, state_derivative
from .vehicle import VehicleModel

__all__ = ["Mode", "SingleTrack", "linearise", "modes", "single_track"]


@dataclass(frozen=True)
class Mode:
    """One vibration mode."""

    name: str
    frequency_hz: float
    damping_ratio: float
    eigenvalue: complex
    participation: dict

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "frequency_hz": self.frequency_hz,
            "damping_ratio": self.damping_ratio,
            "eigenvalue": [self.eigenvalue.real, self.eigenvalue.imag],
            "participation": self.participation,
        }


def _coordinates(model: VehicleModel):
    """Indices of the non-cyclic coordinates and their names and length scales [m per unit]."""
    tree = model.tree
    wheels = {w.wheel_body for w in tree.wheels}
    half_length = max(abs(w.x_m) for w in model.params.wheels) / 2 or 1.0
    half_track = model.params.track_m / 2
    idx = [2, 3, 4]
    names = ["bounce", "roll", "pitch"]
    scale = [1.0, half_track, half_length]
    for w in tree.wheels:
        idx.append(5 + w.spring_body)
        names.append(f"{w.name} wheel hop")
        scale.append(w.motion_ratio)
        if w.steer_body >= 0:
            idx.append(5 + w.steer_body)
            names.append("steer")
            scale.append(w.radius)
    for i in range(1, tree.n_bodies):
        if 5 + i not in idx and i not in wheels:
            idx.append(5 + i)
            names.append(tree.body_names[i])
            scale.append(1.0)
    return idx, names, np.array(scale)


def linearise(model: VehicleModel, state: np.ndarray, *, eps: float = 1e-6):
    """``A = d(dx/dt)/dx`` on the reduced state (positions, all velocities, slips), by central differences.

    Returns
    -------
    a : ndarray (m, m)
    positions : list[int]
        State indices of the reduced positions (the reduced state is these, then all velocities and slips).
    """
    n = model.n_dof
    pos, _, _ = _coordinates(model)
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


def modes(model: VehicleModel, equilibrium: Equilibrium | np.ndarray, *, min_hz: float = 0.05) -> list[Mode]:
    """Oscillatory modes about an equilibrium, sorted by frequency; each named by its dominant coordinate."""
    state = equilibrium.state if isinstance(equilibrium, Equilibrium) else equilibrium
    a, pos = linearise(model, state)
    _, names, scale = _coordinates(model)
    values, vectors = np.linalg.eig(a)
    out = []
    for k, lam in enumerate(values):
        if lam.imag <= 0:
            continue
        w = abs(lam)
        if w / (2 * np.pi) < min_hz:
            continue
        disp = np.abs(vectors[: len(pos), k]) * scale
        if disp.max() <= 0:
            continue
        share = disp / disp.sum()
        order = np.argsort(share)[::-1]
        participation = {names[i]: float(share[i]) for i in order if share[i] >= 0.05}
        out.append(Mode(names[order[0]], w / (2 * np.pi), float(-lam.real / w), complex(lam), participation))
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
        ``delta = (L / v^2 + K) a_y`` [rad]."""
        return (self.wheelbase_m / speed_mps**2 + self.understeer_gradient_rad_per_mps2) * lateral_acceleration_mps2

    @property
    def understeer_gradient_deg_per_g(self) -> float:
        return float(np.degrees(self.understeer_gradient_rad_per_mps2) * 9.80665)


def single_track(model: VehicleModel) -> SingleTrack:
    """The linear single-track model from the static wheel loads and the tyres' cornering stiffness."""
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
    stiffness = {w.name: linear_stiffnesses(t.model, t.coefficients, loads[w.name])[1]
                 for w, t in zip(model.tree.wheels, model.tyres, strict=True)}
    c_front = sum(stiffness[n] for n in front)
    c_rear = sum(v for n, v in stiffness.items() if n not in front)
    k = f_front / g / c_front - f_rear / g / c_rear
    out = SingleTrack(model.params.wheelbase_m, (f_front + f_rear) / g, f_front, f_rear, c_front, c_rear, k)
    model.cache[key] = out
    return out
