"""The multibody tree of a trike, built from its parameter set (the paper's topology, section 2.3).

Delta layout (13 DOF): chassis (floating base, 6 DOF: driver, battery, cargo included); front: steering
head (revolute about the inclined steering axis), fork slider (prismatic along it, the telescopic
suspension) and front wheel (revolute, spin); rear: per side a trailing swing arm (revolute to the
chassis) and its wheel (revolute, spin). The layout is data: each wheel station is built from its
``WheelSpec`` and ``SuspensionSpec`` (steered + telescopic, or unsteered + swing arm), so a tadpole trike
needs a parameter set, not new code.

Design configuration (all joint coordinates zero): chassis frame = vehicle axes, wheel centres at
``(x_m, y_m, radius_m)``, springs at their static length (their preload carries the static load of the
vehicle *without* payload: a laden vehicle sinks on its springs). Assumed geometry of the parts, beyond
the parameter set (small effects, documented here):

* steering head CG on the steering axis, 0.80 m above the ground; its inertia is ``head_inertia_kgm2``
  about every axis through its CG;
* fork slider CG 0.15 m up the steering axis from the wheel centre; a 0.5 m rod;
* swing arm CG midway between pivot and axle; ``moving_inertia_kgm2`` about the pivot;
* wheel: spin inertia ``spin_inertia_kgm2``, half of it about the transverse axes (thin disc).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ParameterError
from ..mechanics import MassProperties, combine
from ..params.ops import mass_properties, static_wheel_loads, unsprung_mass
from ..params.schema import VehicleParameters
from ..units import STANDARD_GRAVITY
from .dynamics import JOINT_FREE, JOINT_PRISMATIC, JOINT_REVOLUTE, JOINT_ROTOR

__all__ = ["Tree", "WheelStation", "build_tree"]

HEAD_CG_HEIGHT_M = 0.80
SLIDER_CG_OFFSET_M = 0.15
SLIDER_LENGTH_M = 0.5


@dataclass(frozen=True)
class WheelStation:
    """Where a wheel sits in the tree and how its suspension acts.

    Attributes
    ----------
    name : str
        Wheel name.
    wheel_body, spring_body, steer_body : int
        Body indices of the wheel, of the body on the suspension joint, and of the steering head (-1).
    motion_ratio : float
        Vertical wheel travel per unit suspension coordinate at design [m/m or m/rad].
    stiffness, damping : float
        Suspension rates in joint coordinates: wheel rate times the motion ratio squared.
    preload : float
        Joint force [N or N m] that carries the static load at design.
    """

    name: str
    wheel_body: int
    spring_body: int
    steer_body: int
    radius: float
    motion_ratio: float
    stiffness: float
    damping: float
    preload: float
    bump_travel: float
    rebound_travel: float
    bump_stop_stiffness: float
    driven: bool
    braked: bool


@dataclass(frozen=True)
class Tree:
    """A rigid-body tree as arrays for the compiled dynamics (see :mod:`trikedyn.model.dynamics`)."""

    body_names: tuple[str, ...]
    parent: np.ndarray
    jtype: np.ndarray
    jaxis: np.ndarray
    tree_e: np.ndarray
    tree_r: np.ndarray
    mass: np.ndarray
    h: np.ndarray
    ibar: np.ndarray
    wheels: tuple[WheelStation, ...] = field(default=())
    chassis_cg: np.ndarray = field(default_factory=lambda: np.zeros(3))

    @property
    def n_bodies(self) -> int:
        """Number of bodies, the chassis included."""
        return len(self.body_names)

    @property
    def n_dof(self) -> int:
        """Degrees of freedom: 6 for the chassis plus one per joint (``n_bodies + 5``)."""
        return self.n_bodies + 5

    def arrays(self):
        """The tuple of arrays the compiled functions take after ``q, u, ...``.

        Returns
        -------
        tuple of numpy.ndarray
            ``(parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar)`` (see :mod:`trikedyn.model.dynamics`).
        """
        return (self.parent, self.jtype, self.jaxis, self.tree_e, self.tree_r, self.mass, self.h, self.ibar)

    def total_mass(self) -> float:
        """Total mass of the tree [kg].

        Returns
        -------
        float
            The sum of the body masses [kg].
        """
        return float(self.mass.sum())


class _Builder:
    def __init__(self):
        self.names, self.parent, self.jtype, self.jaxis = [], [], [], []
        self.tree_e, self.tree_r, self.inertia = [], [], []

    def add(self, name, parent, jtype, axis, tree_e, tree_r, inertia: MassProperties):
        """Add a body; ``inertia`` is given in the body's own frame (CG and tensor)."""
        self.names.append(name)
        self.parent.append(parent)
        self.jtype.append(jtype)
        self.jaxis.append(np.asarray(axis, dtype=float))
        self.tree_e.append(np.asarray(tree_e, dtype=float))
        self.tree_r.append(np.asarray(tree_r, dtype=float))
        self.inertia.append(inertia)
        return len(self.names) - 1

    def design_pose(self, i):
        """World (= chassis at design) rotation body->world and origin of body ``i`` at q = 0."""
        if i == 0:
            return np.eye(3), np.zeros(3)
        rp, pp = self.design_pose(self.parent[i])
        return rp @ self.tree_e[i].T, pp + rp @ self.tree_r[i]

    def in_chassis(self, i) -> MassProperties:
        """Body ``i``'s inertia expressed in chassis (vehicle) axes at design."""
        rot, origin = self.design_pose(i)
        mp = self.inertia[i]
        return MassProperties(mp.mass_kg, origin + rot @ mp.cg_m, rot @ mp.inertia_kgm2 @ rot.T)


def _rod_or_point(mass, cg, inertia_diag):
    return MassProperties(mass, cg, np.diag(inertia_diag))


def build_tree(params: VehicleParameters, g: float = STANDARD_GRAVITY) -> Tree:
    """Build the multibody tree of a parameter set (layout from its wheels; see the module docstring).

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    g : float
        Gravity [m/s^2] (the design loads that set the springs' preload).

    Returns
    -------
    Tree
        Bodies, joints, inertias and the wheel stations.
    """
    b = _Builder()
    b.add("chassis", -1, JOINT_FREE, np.zeros(3), np.eye(3), np.zeros(3), MassProperties(0.0, np.zeros(3)))
    design_loads = static_wheel_loads(params.model_copy(update={"payload": ()}), g)
    stations = []
    eps = params.steering_axis_angle_rad
    for w in params.wheels:
        susp = params.suspension[w.suspension]
        radius = w.radius_m
        wheel_inertia = _rod_or_point(
            w.mass_kg, np.zeros(3), (w.spin_inertia_kgm2 / 2, w.spin_inertia_kgm2, w.spin_inertia_kgm2 / 2)
        )
        sprung_load = design_loads[w.name] - unsprung_mass(params, w.name) * g
        if w.steered and susp.kind == "telescopic":
            axis = np.array([-np.sin(eps), 0.0, np.cos(eps)])
            ground = np.array([w.x_m + params.steering.trail_m, w.y_m, 0.0])
            centre = np.array([w.x_m, w.y_m, radius])
            foot = ground + ((centre - ground) @ axis) * axis
            head_e = np.array([[np.cos(eps), 0.0, np.sin(eps)], [0.0, 1.0, 0.0], list(axis)])
            up = (HEAD_CG_HEIGHT_M - foot[2]) / np.cos(eps)
            ih = params.steering.head_inertia_kgm2
            head = b.add(
                f"{w.name}_steering_head", 0, JOINT_REVOLUTE, (0, 0, 1), head_e, foot,
                _rod_or_point(params.steering.head_mass_kg, (0.0, 0.0, up), (ih, ih, ih)),
            )
            m_s = susp.moving_mass_kg
            offset = head_e @ (centre - foot)
            slider = b.add(
                f"{w.name}_fork_slider", head, JOINT_PRISMATIC, (0, 0, 1), np.eye(3), np.zeros(3),
                _rod_or_point(
                    m_s, offset + (0.0, 0.0, SLIDER_CG_OFFSET_M),
                    (m_s * SLIDER_LENGTH_M**2 / 12, m_s * SLIDER_LENGTH_M**2 / 12, m_s * 0.002),
                ),
            )
            wheel = b.add(f"{w.name}_wheel", slider, JOINT_ROTOR, (0, 1, 0), np.eye(3), offset, wheel_inertia)
            ratio = float(np.cos(eps))
            # the axial spring carries the axial component of the vertical sprung load
            stations.append((w, wheel, slider, head, ratio, sprung_load * ratio))
        elif not w.steered and susp.kind == "swing_arm":
            drop = radius - susp.pivot_height_m
            if abs(drop) >= susp.arm_length_m:
                raise ParameterError(
                    f"swing arm of {susp.arm_length_m} m cannot reach from a pivot {susp.pivot_height_m} m high "
                    f"to an axle {radius} m high",
                    where=f"suspension.{w.suspension}",
                )
            lx = float(np.sqrt(susp.arm_length_m**2 - drop**2))
            pivot = np.array([w.x_m + lx, w.y_m, susp.pivot_height_m])
            half = susp.arm_length_m / 2
            i_cg = max(susp.moving_inertia_kgm2 - susp.moving_mass_kg * half**2, 1e-6)
            arm = b.add(
                f"{w.name}_swing_arm", 0, JOINT_REVOLUTE, (0, 1, 0), np.eye(3), pivot,
                _rod_or_point(susp.moving_mass_kg, (-lx / 2, 0.0, drop / 2), (i_cg * 0.05, i_cg, i_cg)),
            )
            wheel = b.add(f"{w.name}_wheel", arm, JOINT_ROTOR, (0, 1, 0), np.eye(3), (-lx, 0.0, drop), wheel_inertia)
            # torque about the pivot that carries the sprung load at the axle: load * lever (lx)
            # minus the moment of the arm's own weight is carried as part of the unsprung share
            stations.append((w, wheel, arm, -1, lx, sprung_load * lx))
        else:
            raise ParameterError(
                f"wheel '{w.name}': a {'steered' if w.steered else 'fixed'} wheel on a '{susp.kind}' "
                "suspension is not modelled (steered wheels use 'telescopic', fixed ones 'swing_arm')",
                where=f"wheels[{w.name}]",
            )

    # the chassis is what remains of the whole vehicle (payload included) once the parts are taken off
    parts = combine([b.in_chassis(i) for i in range(1, len(b.names))])
    whole = mass_properties(params)
    chassis = whole - parts
    if chassis.mass_kg <= 0 or np.any(np.linalg.eigvalsh(chassis.inertia_kgm2) <= 0):
        raise ParameterError(
            f"the parts (wheels, fork, arms, head: {parts.mass_kg:.1f} kg) leave no physical chassis in "
            f"{whole.mass_kg:.1f} kg with the given inertia", where="mass"
        )
    b.inertia[0] = chassis

    nb = len(b.names)
    mass = np.array([mp.mass_kg for mp in b.inertia])
    hvec = np.array([mp.mass_kg * mp.cg_m for mp in b.inertia])
    ibar = np.array(
        [mp.inertia_kgm2 + mp.mass_kg * (mp.cg_m @ mp.cg_m * np.eye(3) - np.outer(mp.cg_m, mp.cg_m)) for mp in b.inertia]
    )
    wheel_stations = tuple(
        WheelStation(
            name=w.name, wheel_body=wb, spring_body=sb, steer_body=hb, radius=w.radius_m, motion_ratio=mr,
            stiffness=params.suspension[w.suspension].stiffness_N_per_m * mr**2,
            damping=params.suspension[w.suspension].damping_Ns_per_m * mr**2,
            preload=pre,
            bump_travel=params.suspension[w.suspension].bump_travel_m,
            rebound_travel=params.suspension[w.suspension].rebound_travel_m,
            bump_stop_stiffness=params.suspension[w.suspension].bump_stop_stiffness_N_per_m,
            driven=w.driven, braked=w.braked,
        )
        for (w, wb, sb, hb, mr, pre) in stations
    )
    return Tree(
        body_names=tuple(b.names),
        parent=np.array(b.parent, dtype=np.int64),
        jtype=np.array(b.jtype, dtype=np.int64),
        jaxis=np.array(b.jaxis).reshape(nb, 3),
        tree_e=np.array(b.tree_e).reshape(nb, 3, 3),
        tree_r=np.array(b.tree_r).reshape(nb, 3),
        mass=mass,
        h=hvec,
        ibar=ibar,
        wheels=wheel_stations,
        chassis_cg=chassis.cg_m,
    )
