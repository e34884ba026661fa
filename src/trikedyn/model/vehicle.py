"""A vehicle ready for the compiled loop: its tree and every force parameter packed in plain arrays.

:func:`build_model` turns a parameter set into a :class:`VehicleModel` (tree arrays, per-wheel arrays,
tyre coefficients, scalars and the road). The compiled right-hand side
(:mod:`trikedyn.model.rhs`) reads those arrays by the index constants defined here, so nothing in the
time loop is a Python object.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..params.io import ParameterSet
from ..params.schema import VehicleParameters
from ..tyre.magic_formula import tyre_coefficients
from ..units import STANDARD_GRAVITY
from .topology import Tree, build_tree

__all__ = ["Road", "VehicleModel", "build_model", "flat_road", "speed_bump"]

# per-wheel float parameters
WF_RADIUS, WF_MR, WF_K, WF_C, WF_PRELOAD, WF_BUMP, WF_REBOUND, WF_KSTOP = range(8)
N_WF = 8
# per-wheel integer parameters
WI_WHEEL, WI_SPRING, WI_STEER, WI_DRIVEN, WI_BRAKED = range(5)
N_WI = 5
# scalars
(
    S_G,
    S_STEER_KP,
    S_STEER_KD,
    S_MAX_STEER,
    S_MAX_TORQUE,
    S_MAX_POWER,
    S_MAX_BRAKE,
    S_AERO,
    S_AERO_X,
    S_AERO_Z,
    S_V_LOW,
    S_W_LOW,
    S_SLIP_FORCES,
    S_N_DRIVEN,
    S_ROLL_LIMIT,
    S_PENETRATION_LIMIT,
    S_SIGMA_X,
    S_SIGMA_Y,
) = range(18)
N_S = 18
# road
R_KIND, R_X0, R_LENGTH, R_HEIGHT, R_YMIN, R_YMAX = range(6)
ROAD_FLAT, ROAD_BUMP = 0.0, 1.0


@dataclass(frozen=True)
class Road:
    """Road height profile: flat, or a ``(1 - cos) / 2`` speed bump across the road.

    Attributes
    ----------
    kind : {"flat", "bump"}
    start_m, length_m, height_m : float
        Where the bump starts along x [m], its length [m] and its height [m].
    lateral_m : (float, float)
        The bump covers ``lateral_m[0] <= |y| <= lateral_m[1]`` [m]: the whole road by default; a narrow
        central cushion, or two side cushions, let one axle cross it alone.
    """

    kind: str = "flat"
    start_m: float = 0.0
    length_m: float = 1.0
    height_m: float = 0.0
    lateral_m: tuple[float, float] = (0.0, 1e9)

    def array(self) -> np.ndarray:
        kind = ROAD_FLAT if self.kind == "flat" else ROAD_BUMP
        return np.array([kind, self.start_m, self.length_m, self.height_m, *self.lateral_m])


def flat_road() -> Road:
    """A flat road at z = 0."""
    return Road()


def speed_bump(start_m: float, length_m: float = 0.9, height_m: float = 0.06,
               lateral_m: tuple[float, float] = (0.0, 1e9)) -> Road:
    """A speed bump (defaults: 0.9 m long, 60 mm high, a common road hump) starting at ``start_m``."""
    return Road("bump", start_m, length_m, height_m, tuple(lateral_m))


@dataclass(frozen=True)
class VehicleModel:
    """Arrays of one vehicle for the compiled loop. Build with :func:`build_model`."""

    params: VehicleParameters
    tree: Tree
    wheel_f: np.ndarray
    wheel_i: np.ndarray
    tyre: np.ndarray
    scalars: np.ndarray
    road: np.ndarray
    steer_inertia: float
    cache: dict = field(default_factory=dict, compare=False, repr=False)
    """Results that depend only on the model (static equilibrium, stability limit), kept across runs."""

    @property
    def n_dof(self) -> int:
        return self.tree.n_dof

    @property
    def n_states(self) -> int:
        """Coordinates, velocities and two transient slips per wheel."""
        return 2 * self.tree.n_dof + 2 * len(self.tree.wheels)

    @property
    def wheel_names(self) -> tuple[str, ...]:
        return tuple(w.name for w in self.tree.wheels)

    def arrays(self):
        """Everything the compiled right-hand side takes after ``t, x, inputs``."""
        return (*self.tree.arrays(), self.wheel_f, self.wheel_i, self.tyre, self.scalars, self.road)

    def with_road(self, road: Road) -> VehicleModel:
        return replace(self, road=road.array(), cache={})

    def on_flat_road(self) -> VehicleModel:
        """This model on a flat road (itself if its road is flat, keeping its cache)."""
        return self if self.road[R_KIND] == ROAD_FLAT else self.with_road(flat_road())

    def variant(self, *, slip_forces: bool | None = None, damping: bool | None = None,
                gravity: float | None = None, drag: bool | None = None) -> VehicleModel:
        """A copy with model parts switched off, for verification (energy, momentum).

        ``damping=False`` removes the suspension and tyre dampers and the steering servo's damping;
        ``slip_forces=False`` the tyres' horizontal forces and rolling resistance; ``drag=False`` the
        aerodynamic drag; ``gravity`` sets g [m/s^2].
        """
        scalars = self.scalars.copy()
        wheel_f = self.wheel_f.copy()
        tyre = self.tyre.copy()
        if slip_forces is not None:
            scalars[S_SLIP_FORCES] = 1.0 if slip_forces else 0.0
        if damping is False:
            wheel_f[:, WF_C] = 0.0
            tyre[1] = 0.0  # CZ
            scalars[S_STEER_KD] = 0.0
        if gravity is not None:
            scalars[S_G] = gravity
        if drag is False:
            scalars[S_AERO] = 0.0
        return replace(self, scalars=scalars, wheel_f=wheel_f, tyre=tyre, cache={})


def _steer_axis_inertia(tree: Tree, steer_body: int) -> float:
    """Inertia of the steered assembly (head, slider, wheel) about the steering axis at design [kg m^2]."""
    axis = tree.jaxis[steer_body]
    total = 0.0
    # bodies in the steered subtree, expressed in the head frame (fixed transforms at q = 0)
    frames = {steer_body: (np.eye(3), np.zeros(3))}
    for i in range(steer_body, tree.n_bodies):
        if i != steer_body and int(tree.parent[i]) not in frames:
            continue
        if i != steer_body:
            ep, rp = frames[int(tree.parent[i])]
            e = tree.tree_e[i] @ ep
            r = rp + ep.T @ tree.tree_r[i]
            frames[i] = (e, r)
        e, r = frames[i]
        m = tree.mass[i]
        c = r + e.T @ (tree.h[i] / m)
        ic = tree.ibar[i] - m * (tree.h[i] / m @ (tree.h[i] / m) * np.eye(3) - np.outer(tree.h[i] / m, tree.h[i] / m))
        ic_head = e.T @ ic @ e
        d = c - (c @ axis) * axis
        total += axis @ ic_head @ axis + m * d @ d
    return float(total)


def build_model(vehicle: ParameterSet | VehicleParameters, *, road: Road | None = None,
                v_low_mps: float = 1.0, w_low_radps: float = 1.0) -> VehicleModel:
    """Pack a parameter set into a :class:`VehicleModel`.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleParameters
        The vehicle (payload included).
    road : Road, optional
        Flat by default.
    v_low_mps, w_low_radps : float
        Tyre slip and rolling-resistance regularisation (:mod:`trikedyn.tyre.magic_formula`).
    """
    params = vehicle.params if isinstance(vehicle, ParameterSet) else vehicle
    tree = build_tree(params)
    nw = len(tree.wheels)
    wheel_f = np.zeros((nw, N_WF))
    wheel_i = np.zeros((nw, N_WI), dtype=np.int64)
    for k, w in enumerate(tree.wheels):
        wheel_f[k] = (w.radius, w.motion_ratio, w.stiffness, w.damping, w.preload, w.bump_travel,
                      w.rebound_travel, w.bump_stop_stiffness)
        wheel_i[k] = (w.wheel_body, w.spring_body, w.steer_body, int(w.driven), int(w.braked))
    steer_bodies = [w.steer_body for w in tree.wheels if w.steer_body >= 0]
    inertia = _steer_axis_inertia(tree, steer_bodies[0]) if steer_bodies else 1.0
    omega = 2.0 * np.pi * params.steering.servo_bandwidth_hz
    scalars = np.zeros(N_S)
    scalars[S_G] = STANDARD_GRAVITY
    scalars[S_STEER_KP] = inertia * omega**2
    scalars[S_STEER_KD] = 2.0 * params.steering.servo_damping_ratio * inertia * omega
    scalars[S_MAX_STEER] = np.radians(params.steering.max_angle_deg)
    scalars[S_MAX_TORQUE] = params.drive.max_drive_torque_Nm
    scalars[S_MAX_POWER] = params.drive.max_power_W
    scalars[S_MAX_BRAKE] = params.drive.max_brake_torque_Nm
    scalars[S_AERO] = 0.5 * params.aero.air_density_kg_per_m3 * params.aero.drag_coefficient * params.aero.frontal_area_m2
    scalars[S_AERO_X] = tree.chassis_cg[0]
    scalars[S_AERO_Z] = tree.chassis_cg[2]
    scalars[S_V_LOW] = v_low_mps
    scalars[S_W_LOW] = w_low_radps
    scalars[S_SLIP_FORCES] = 1.0
    scalars[S_N_DRIVEN] = max(1, sum(w.driven for w in tree.wheels))
    scalars[S_ROLL_LIMIT] = np.radians(60.0)
    scalars[S_PENETRATION_LIMIT] = 0.5
    scalars[S_SIGMA_X] = params.tyre.relaxation_length_x_m
    scalars[S_SIGMA_Y] = params.tyre.relaxation_length_y_m
    return VehicleModel(params, tree, wheel_f, wheel_i, tyre_coefficients(params.tyre), scalars,
                        (road or flat_road()).array(), inertia)
