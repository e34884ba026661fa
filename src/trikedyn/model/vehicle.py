"""A vehicle ready for the compiled loop: its tree and every force parameter packed once, by name.

:func:`build_model` turns a parameter set into a :class:`VehicleModel`: the multibody tree
(:mod:`trikedyn.model.topology`), and the :class:`~trikedyn.model.packing.Plant` the compiled right-hand
side ``f(t, x, u, p)`` (:mod:`trikedyn.model.rhs`) and the driver read: named records per wheel, per tyre,
for the vehicle and the road (:mod:`trikedyn.model.packing`). Nothing in the time loop is a Python object.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..params.io import ParameterSet
from ..params.ops import static_wheel_loads
from ..params.schema import VehicleParameters
from ..tyre.interface import COEFFS_WIDTH, TyreSetup, tyre_setup
from ..units import STANDARD_GRAVITY
from .packing import VEHICLE, WHEEL, Plant, record, road_record, state_labels
from .topology import Tree, build_tree

__all__ = ["IDEAL_LIMIT", "Road", "VehicleModel", "build_model", "flat_road", "speed_bump"]

IDEAL_LIMIT = 1e9
"""Torque [N m] and power [W] limit of the ideal drive and brakes (:meth:`VehicleModel.with_ideal_drive`):
never reached."""


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

    def record(self) -> np.ndarray:
        """The compiled :data:`~trikedyn.model.packing.ROAD` record (a length-1 array).

        Returns
        -------
        numpy.ndarray, shape (1,), dtype ROAD
            The record.
        """
        return road_record(self.kind != "flat", self.start_m, self.length_m, self.height_m, *self.lateral_m)


def flat_road() -> Road:
    """A flat road at z = 0.

    Returns
    -------
    Road
        The flat road.
    """
    return Road()


def speed_bump(start_m: float, length_m: float = 0.9, height_m: float = 0.06,
               lateral_m: tuple[float, float] = (0.0, 1e9)) -> Road:
    """A speed bump (defaults: 0.9 m long, 60 mm high, a common road hump) starting at ``start_m``.

    Parameters
    ----------
    start_m : float
        Where the bump starts along x [m].
    length_m : float
        Bump length along x [m].
    height_m : float
        Bump height [m].
    lateral_m : tuple of float
        Lateral extent (y_min, y_max) [m]; everywhere by default.

    Returns
    -------
    Road
        The road.
    """
    return Road("bump", start_m, length_m, height_m, tuple(lateral_m))


@dataclass(frozen=True)
class VehicleModel:
    """One vehicle for the compiled loop. Build with :func:`build_model`.

    Attributes
    ----------
    params : VehicleParameters
    tree : Tree
        The multibody tree and its wheel stations.
    plant : Plant
        What the compiled right-hand side reads: ``f(t, x, u, model.plant)``.
    tyres : tuple of TyreSetup
        Each wheel's tyre, as built.
    steer_inertia : float
        Inertia of the first steered assembly about its steering axis [kg m^2].
    cache : dict
        Results that depend only on the model (static equilibrium, stability limit), kept across runs.
    """

    params: VehicleParameters
    tree: Tree
    plant: Plant
    tyres: tuple[TyreSetup, ...]
    steer_inertia: float
    cache: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def n_dof(self) -> int:
        """Degrees of freedom of the tree (13 for the paper's topology)."""
        return self.tree.n_dof

    @property
    def n_states(self) -> int:
        """Coordinates, velocities and two transient slips per wheel."""
        return 2 * self.tree.n_dof + 2 * len(self.tree.wheels)

    @property
    def wheel_names(self) -> tuple[str, ...]:
        """The wheels' names, in the tree's order."""
        return tuple(w.name for w in self.tree.wheels)

    @property
    def state_names(self) -> tuple[str, ...]:
        """Labels of the state vector (:func:`~trikedyn.model.packing.state_labels`)."""
        return state_labels(self.tree.body_names, self.wheel_names)

    @property
    def wheels(self) -> np.ndarray:
        """The :data:`~trikedyn.model.packing.WHEEL` records."""
        return self.plant.wheels

    @property
    def vehicle(self):
        """The :data:`~trikedyn.model.packing.VEHICLE` record."""
        return self.plant.vehicle[0]

    @property
    def gravity(self) -> float:
        """g [m/s^2]."""
        return float(self.plant.vehicle[0]["g"])

    @property
    def flat(self) -> bool:
        """True on a flat road."""
        return int(self.plant.road[0]["bump"]) == 0

    def with_road(self, road: Road) -> VehicleModel:
        """This model on another road (its cache emptied: the equilibrium depends on the road).

        Parameters
        ----------
        road : Road
            The road.

        Returns
        -------
        VehicleModel
            The copy.
        """
        return replace(self, plant=self.plant._replace(road=road.record()), cache={})

    def on_flat_road(self) -> VehicleModel:
        """This model on a flat road (itself if its road is flat, keeping its cache).

        Returns
        -------
        VehicleModel
            The model on flat ground.
        """
        return self if self.flat else self.with_road(flat_road())

    def with_ideal_drive(self) -> VehicleModel:
        """This model with a drive and brakes that have no torque or power limit (the ideal speed control).

        The speed controller's demand then reaches the wheels whatever it is, as a multibody package's
        kinematic drive imposes the speed; the tyres still carry it (their grip is the only limit). The
        cache is shared: what it holds (equilibrium, stability limits) does not depend on the limits.

        Returns
        -------
        VehicleModel
            The copy.
        """
        vehicle = self.plant.vehicle.copy()
        vehicle["max_torque"] = IDEAL_LIMIT
        vehicle["max_power"] = IDEAL_LIMIT
        vehicle["max_brake"] = IDEAL_LIMIT
        return replace(self, plant=self.plant._replace(vehicle=vehicle), cache=self.cache)

    def variant(self, *, slip_forces: bool | None = None, damping: bool | None = None,
                gravity: float | None = None, drag: bool | None = None) -> VehicleModel:
        """A copy with model parts switched off, for verification (energy, momentum).

        ``damping=False`` removes the suspension and tyre dampers and the steering servos' damping;
        ``slip_forces=False`` the tyres' horizontal forces and rolling resistance; ``drag=False`` the
        aerodynamic drag; ``gravity`` sets g [m/s^2].

        Parameters
        ----------
        slip_forces : bool, optional
            Keep (True) or remove (False) the tyres' horizontal forces; unchanged when None.
        damping : bool, optional
            False removes the dampers; unchanged otherwise.
        gravity : float, optional
            Gravity [m/s^2]; unchanged when None.
        drag : bool, optional
            False removes the aerodynamic drag; unchanged otherwise.

        Returns
        -------
        VehicleModel
            The copy, with an empty cache.
        """
        wheels = self.plant.wheels.copy()
        vehicle = self.plant.vehicle.copy()
        if slip_forces is not None:
            vehicle["slip_forces"] = 1.0 if slip_forces else 0.0
        if damping is False:
            wheels["damping"] = 0.0
            wheels["vertical_damping"] = 0.0
            wheels["steer_kd"] = 0.0
        if gravity is not None:
            vehicle["g"] = gravity
        if drag is False:
            vehicle["aero"] = 0.0
        return replace(self, plant=self.plant._replace(wheels=wheels, vehicle=vehicle), cache={})


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
        Tyre slip and rolling-resistance regularisation speeds [m/s] and [rad/s]
        (:mod:`trikedyn.tyre.magic_formula`).

    Returns
    -------
    VehicleModel
        The compiled records, the tree, the tyre setups and a cache.
    """
    params = vehicle.params if isinstance(vehicle, ParameterSet) else vehicle
    tree = build_tree(params)
    nw = len(tree.wheels)
    loads = static_wheel_loads(params, STANDARD_GRAVITY)
    omega = 2.0 * np.pi * params.steering.servo_bandwidth_hz
    zeta = params.steering.servo_damping_ratio
    wheels = np.zeros(nw, WHEEL)
    tyres = np.zeros((nw, COEFFS_WIDTH))
    setups = []
    inertias = []
    for k, w in enumerate(tree.wheels):
        spec = params.wheel(w.name)
        setup = tyre_setup(params, spec, loads[w.name])
        setups.append(setup)
        tyres[k] = setup.coefficients
        inertia = _steer_axis_inertia(tree, w.steer_body) if w.steer_body >= 0 else 0.0
        if w.steer_body >= 0:
            inertias.append(inertia)
        wheels[k] = record(WHEEL, {
            "radius": w.radius, "motion_ratio": w.motion_ratio, "stiffness": w.stiffness, "damping": w.damping,
            "preload": w.preload, "bump_travel": w.bump_travel, "rebound_travel": w.rebound_travel,
            "bump_stop_stiffness": w.bump_stop_stiffness, "wheel_body": w.wheel_body, "spring_body": w.spring_body,
            "steer_body": w.steer_body, "driven": int(w.driven), "braked": int(w.braked),
            "steer_kp": inertia * omega**2, "steer_kd": 2.0 * zeta * inertia * omega,
            "steer_y": spec.y_m if w.steer_body >= 0 else 0.0, "tyre_model": setup.model,
            "vertical_stiffness": setup.vertical_stiffness_N_per_m, "vertical_damping": setup.vertical_damping_Ns_per_m,
            "relaxation_x": setup.relaxation_x_m, "relaxation_y": setup.relaxation_y_m,
        })[0]
    veh = record(VEHICLE, {
        "g": STANDARD_GRAVITY,
        "max_steer": np.radians(params.steering.max_angle_deg),
        "max_steer_rate": np.radians(params.steering.max_rate_deg_per_s),
        "max_torque": params.drive.max_drive_torque_Nm,
        "max_power": params.drive.max_power_W,
        "max_brake": params.drive.max_brake_torque_Nm,
        "aero": 0.5 * params.aero.air_density_kg_per_m3 * params.aero.drag_coefficient * params.aero.frontal_area_m2,
        "aero_x": tree.chassis_cg[0],
        "aero_z": tree.chassis_cg[2],
        "v_low": v_low_mps,
        "w_low": w_low_radps,
        "slip_forces": 1.0,
        "n_driven": max(1, sum(w.driven for w in tree.wheels)),
        "n_braked": sum(w.braked for w in tree.wheels),
        "roll_limit": np.radians(60.0),
        "penetration_limit": 0.5,
        "wheelbase": params.wheelbase_m,
        "cos_rake": np.cos(params.steering_axis_angle_rad),
        "ackermann": params.steering.ackermann_fraction,
    })
    plant = Plant(*tree.arrays(), wheels, tyres, veh, (road or flat_road()).record())
    return VehicleModel(params, tree, plant, tuple(setups), inertias[0] if inertias else 1.0)
