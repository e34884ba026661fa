"""The sections of a vehicle parameter set (:mod:`trikedyn.params.schema`): mass, steering, suspension,
wheels, tyre, drive, aero, points, payload, components and body, each validated on its own with units in its
keys' names, a physical range for every number (a quantity that must be positive says so first, ``gt=0``,
then has a least physical value) and no unknown keys. Checks across sections are the whole vehicle's
(:class:`~trikedyn.params.schema.VehicleParameters`).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, field_validator, model_validator

__all__ = ["AeroSpec", "BodySpec", "ComponentSpec", "DriveSpec", "MassSpec", "PayloadItemSpec", "PointSpec",
           "SteeringSpec", "SuspensionSpec", "TyreSpec", "WheelSpec"]


class _Spec(BaseModel):
    """Base of every schema section: frozen, unknown keys rejected."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True, allow_inf_nan=False)


def _at_least(minimum: float, unit: str) -> AfterValidator:
    """The least physical value of a quantity that must be > 0 (which the field's ``gt=0`` checks first).

    Each field has a range an engineer would accept for a three-wheeled vehicle (its lower bound here, its
    upper bound in ``le=``): wide enough for a 10 kg recumbent trike and a 5 t cargo one, narrow enough that
    no derived quantity (frequencies, sags, tip-over accelerations) divides by a vanishing number.
    """

    def check(value: float) -> float:
        """``value`` unchanged if it is at least ``minimum`` (in ``unit``), else ValueError."""
        if value < minimum:
            raise ValueError(f"input should be at least {minimum:g}{' ' + unit if unit else ''} (got {value:g})")
        return value

    check.minimum = minimum  # the bound, for whoever inspects the schema (documentation, tests)
    return AfterValidator(check)


def _positive(minimum: float, unit: str):
    """A float that is > 0 (pydantic's own message) and at least ``minimum`` (a physical value)."""
    return Annotated[float, _at_least(minimum, unit)]


class MassSpec(_Spec):
    """Masses, centre of gravity and inertia of the vehicle with its driver, without freight."""

    curb_kg: _positive(10.0, "kg") = Field(gt=0, le=5000, description="vehicle as weighed, wheels included, no driver [kg]")
    body_kg: _positive(5.0, "kg") | None = Field(
        default=None, gt=0, le=5000, description="curb mass less the wheels (paper's M_B) [kg]"
    )
    driver_kg: float = Field(default=0.0, ge=0, le=300, description="driver aboard [kg]")
    cg_x_m: float = Field(ge=-5, le=10, description="CG of vehicle + driver, ahead of the rear axle [m]")
    cg_y_m: float = Field(ge=-2, le=2, description="CG of vehicle + driver, left of the centre line [m]")
    cg_z_m: _positive(0.05, "m") = Field(gt=0, le=3, description="CG of vehicle + driver, above the ground [m]")
    roll_inertia_kgm2: _positive(0.1, "kg m^2") = Field(gt=0, le=1e5, description="Ixx of vehicle + driver about the CG")
    pitch_inertia_kgm2: _positive(0.1, "kg m^2") = Field(gt=0, le=1e5, description="Iyy of vehicle + driver about the CG")
    yaw_inertia_kgm2: _positive(0.1, "kg m^2") = Field(gt=0, le=1e5, description="Izz of vehicle + driver about the CG")
    roll_yaw_product_kgm2: float = Field(default=0.0, ge=-1e4, le=1e4, description="Ixz = int x z dm")
    roll_pitch_product_kgm2: float = Field(default=0.0, ge=-1e4, le=1e4, description="Ixy = int x y dm")
    pitch_yaw_product_kgm2: float = Field(default=0.0, ge=-1e4, le=1e4, description="Iyz = int y z dm")

    @property
    def total_kg(self) -> float:
        """Vehicle plus driver, ready to drive, without payload [kg]."""
        return self.curb_kg + self.driver_kg

    @property
    def cg_m(self) -> tuple[float, float, float]:
        """Centre of gravity (x, y, z) [m]."""
        return (self.cg_x_m, self.cg_y_m, self.cg_z_m)

    @property
    def inertia_tensor_kgm2(self) -> list[list[float]]:
        """Inertia tensor about the CG [kg m^2]; off-diagonals are minus the products of inertia."""
        ixy, ixz, iyz = self.roll_pitch_product_kgm2, self.roll_yaw_product_kgm2, self.pitch_yaw_product_kgm2
        return [
            [self.roll_inertia_kgm2, -ixy, -ixz],
            [-ixy, self.pitch_inertia_kgm2, -iyz],
            [-ixz, -iyz, self.yaw_inertia_kgm2],
        ]

    @model_validator(mode="after")
    def _realisable_inertia(self):
        ixx, iyy, izz = self.roll_inertia_kgm2, self.pitch_inertia_kgm2, self.yaw_inertia_kgm2
        if ixx + iyy < izz or iyy + izz < ixx or ixx + izz < iyy:
            raise ValueError(
                f"inertias ({ixx:g}, {iyy:g}, {izz:g}) kg m^2 break the triangle inequality "
                "(no rigid body has them)"
            )
        return self

    @model_validator(mode="after")
    def _body_below_curb(self):
        if self.body_kg is not None and self.body_kg >= self.curb_kg:
            raise ValueError(f"body_kg ({self.body_kg:g}) must be less than curb_kg ({self.curb_kg:g})")
        return self


class SteeringSpec(_Spec):
    """Steering head: the revolute about the inclined steering axis, driven by a servo."""

    axis_angle_deg: float = Field(ge=0, le=45, description="steering axis behind the vertical (rake) [deg]")
    trail_m: float = Field(ge=-0.2, le=0.4, description="mechanical trail on the ground [m]")
    head_mass_kg: _positive(0.1, "kg") = Field(gt=0, le=100, description="bars, upper fork, lamp: turns with the steer")
    head_inertia_kgm2: _positive(0.001, "kg m^2") = Field(gt=0, le=50, description="head inertia about the steering axis")
    max_angle_deg: _positive(5.0, "deg") = Field(gt=0, le=80, description="steering lock [deg]")
    max_rate_deg_per_s: _positive(10.0, "deg/s") = Field(gt=0, le=2000, description="fastest steering a driver applies")
    servo_bandwidth_hz: _positive(0.5, "Hz") = Field(
        gt=0, le=50, description="steering servo natural frequency on the steered inertia [Hz]"
    )
    servo_damping_ratio: _positive(0.05, "") = Field(gt=0, le=3, description="steering servo damping ratio")
    ackermann_fraction: float = Field(
        default=1.0, ge=0, le=1.5,
        description="of a steered pair: 0 parallel steer, 1 full Ackermann (inner wheel steers more) [1]",
    )
    handlebar_ratio: _positive(0.1, "") = Field(
        default=1.0, gt=0, le=30, description="handlebar angle per road-wheel steer angle [deg/deg]"
    )


class SuspensionSpec(_Spec):
    """One suspension type: its own spring and damper as wheel rates (at the wheel, vertical), not the tyre's.

    The model adds the wheel's tyre in series (:mod:`trikedyn.params.springs`; a tyre-inclusive K makes it too soft);
    the measured body mode (optional: Table 1) is audited by ``trikedyn vehicle check`` (Eqs. 3-4, tyre in series).
    """

    kind: Literal["telescopic", "swing_arm"]
    stiffness_N_per_m: _positive(100.0, "N/m") = Field(gt=0, le=1e7, description="the suspension's own spring as a wheel rate K, the tyre in series not included [N/m]")
    damping_Ns_per_m: float = Field(ge=0, le=1e5, description="the suspension's own damper as a wheel rate C, the tyre not included [N s/m]")
    natural_frequency_hz: _positive(0.1, "Hz") | None = Field(default=None, gt=0, le=50, description="measured f_n of the body mode, spring and tyre together (bump test) [Hz]")
    damping_ratio: float | None = Field(default=None, ge=0, lt=1, description="measured damping ratio of the body mode")
    moving_mass_kg: float = Field(ge=0, le=200, description="fork slider or swing arm, wheel excluded [kg]")
    moving_inertia_kgm2: float = Field(
        default=0.0, ge=0, le=50, description="swing arm inertia about its pivot [kg m^2]"
    )
    arm_length_m: _positive(0.05, "m") | None = Field(default=None, gt=0, le=2, description="swing arm pivot to axle [m]")
    pivot_height_m: _positive(0.01, "m") | None = Field(default=None, gt=0, le=2, description="swing arm pivot height [m]")
    bump_travel_m: _positive(0.005, "m") = Field(gt=0, le=0.5, description="travel from static to the bump stop [m]")
    rebound_travel_m: _positive(0.005, "m") = Field(gt=0, le=0.5, description="travel from static to full extension [m]")
    bump_stop_stiffness_N_per_m: _positive(1000.0, "N/m") = Field(gt=0, le=1e8, description="one-sided stop stiffness [N/m]")

    @model_validator(mode="after")
    def _swing_arm_geometry(self):
        if self.kind == "swing_arm" and (self.arm_length_m is None or self.pivot_height_m is None):
            raise ValueError("a swing_arm suspension needs arm_length_m and pivot_height_m")
        if self.kind == "telescopic" and (self.arm_length_m is not None or self.pivot_height_m is not None):
            raise ValueError("arm_length_m and pivot_height_m apply to kind = 'swing_arm' only")
        return self


class WheelSpec(_Spec):
    """One wheel station: the wheel centre's position at static ride height and its suspension."""

    name: str = Field(pattern=r"^[a-z][a-z0-9_]*$", max_length=40, description="front, rear_left, rear_right (delta); front_left, front_right, rear (tadpole)")
    x_m: float = Field(ge=-5, le=10, description="contact point ahead of the rear axle [m]")
    y_m: float = Field(ge=-2, le=2, description="contact point left of the centre line [m]")
    suspension: str = Field(max_length=40, description="name of an entry of [suspension]")
    radius_m: float = Field(gt=0.05, le=1.0, description="unloaded tyre radius [m]")
    mass_kg: _positive(0.2, "kg") = Field(gt=0, le=100, description="wheel with tyre, hub and brake disc [kg]")
    spin_inertia_kgm2: _positive(0.001, "kg m^2") = Field(gt=0, le=20, description="inertia about the axle [kg m^2]")
    steered: bool = False
    driven: bool = False
    braked: bool = True
    tyre_file: str | None = Field(
        default=None, min_length=1, max_length=1000,
        description="Adams/MF-Tyre .tir property file for this wheel, relative to the vehicle file, in its folder "
        "or below it; None: the [tyre] section's similarity model",
    )

    @field_validator("tyre_file")
    @classmethod
    def _tir_name(cls, value):
        if value is None:
            return value
        if any(ord(c) < 32 for c in value):
            raise ValueError("a file name with a control character")
        if not value.lower().endswith(".tir"):
            raise ValueError(f"expected a .tir tyre property file, got '{value[-60:]}'")
        return value


class TyreSpec(_Spec):
    """Tyre: vertical spring-damper and a Magic Formula (Pacejka) with load dependence.

    Peak friction ``mu = mu0 * (1 + load_sensitivity * dfz)`` with ``dfz = (Fz - Fz0) / Fz0``;
    cornering stiffness ``C_alpha = cornering_stiffness_factor * Fz0 * sin(2 atan(Fz / (cornering_stiffness_load_factor * Fz0)))``;
    longitudinal slip stiffness ``C_kappa = slip_stiffness_factor * Fz``.
    """

    vertical_stiffness_N_per_m: _positive(1000.0, "N/m") = Field(gt=0, le=1e7, description="tyre vertical stiffness kz, in series with the suspension's spring (paper: 200 kN/m)")
    vertical_damping_Ns_per_m: float = Field(ge=0, le=1e4, description="tyre vertical damping cz, in series with the suspension's damper (paper: 75 N s/m)")
    nominal_load_N: _positive(10.0, "N") = Field(gt=0, le=1e5, description="Fz0 of the Magic Formula [N]")
    mu_x: _positive(0.05, "") = Field(gt=0, le=3, description="longitudinal peak friction at Fz0")
    mu_y: _positive(0.05, "") = Field(gt=0, le=3, description="lateral peak friction at Fz0")
    load_sensitivity: float = Field(ge=-1, le=0.5, description="d mu / d dfz (negative: mu falls with load)")
    shape_x: float = Field(gt=1, le=2, description="Magic Formula C, longitudinal")
    shape_y: float = Field(gt=1, le=2, description="Magic Formula C, lateral")
    curvature_x: float = Field(ge=-5, le=1, description="Magic Formula E, longitudinal")
    curvature_y: float = Field(ge=-5, le=1, description="Magic Formula E, lateral")
    slip_stiffness_factor: _positive(1.0, "") = Field(gt=0, le=100, description="C_kappa / Fz [1]")
    cornering_stiffness_factor: _positive(1.0, "1/rad") = Field(gt=0, le=100, description="pKy1: C_alpha / Fz0 at peak [1/rad]")
    cornering_stiffness_load_factor: _positive(0.1, "") = Field(gt=0, le=10, description="pKy2: load of peak C_alpha / Fz0")
    rolling_resistance: float = Field(ge=0, le=0.2, description="rolling resistance coefficient")
    relaxation_length_x_m: _positive(0.01, "m") = Field(gt=0, le=3, description="longitudinal slip relaxation length [m]")
    relaxation_length_y_m: _positive(0.01, "m") = Field(gt=0, le=3, description="lateral slip relaxation length [m]")


class DriveSpec(_Spec):
    """Drive to the driven wheels through an open differential, and brakes."""

    max_drive_torque_Nm: _positive(1.0, "N m") = Field(gt=0, le=1e4, description="at the wheels, all driven wheels [N m]")
    max_power_W: _positive(10.0, "W") = Field(gt=0, le=1e6, description="at the wheels [W]")
    max_brake_torque_Nm: _positive(1.0, "N m") = Field(gt=0, le=1e4, description="per braked wheel [N m]")
    differential: Literal["open"] = "open"


class AeroSpec(_Spec):
    """Aerodynamic drag 0.5 rho Cd A v^2."""

    drag_coefficient: float = Field(ge=0, le=3)
    frontal_area_m2: float = Field(ge=0, le=20)
    air_density_kg_per_m3: _positive(0.5, "kg/m^3") = Field(default=1.2, gt=0, le=2)


class PointSpec(_Spec):
    """A point in vehicle axes [m] (sensor position, freight site)."""

    x_m: float = Field(ge=-5, le=10)
    y_m: float = Field(ge=-2, le=2)
    z_m: float = Field(ge=-1, le=5)


class PayloadItemSpec(_Spec):
    """A payload item: a point mass (no size) or a uniform box, added to the vehicle or removed from it.

    Payload is kept apart from ``[mass]`` so that the springs' preload stays that of the vehicle as built
    (a laden vehicle sinks on its springs) and the payload can be listed, changed and taken off again.
    """

    name: str = Field(min_length=1, max_length=100)
    mass_kg: float = Field(ge=0, le=5000)
    x_m: float = Field(ge=-5, le=10)
    y_m: float = Field(ge=-2, le=2)
    z_m: float = Field(ge=-1, le=5)
    length_m: float = Field(default=0.0, ge=0, le=15, description="box edge along x [m]; 0 for a point")
    width_m: float = Field(default=0.0, ge=0, le=5, description="box edge along y [m]")
    height_m: float = Field(default=0.0, ge=0, le=5, description="box edge along z [m]")
    removed: bool = Field(default=False, description="true: this mass is taken off the vehicle")


class ComponentSpec(_Spec):
    """A movable mass inside the vehicle (battery, motor controller, motor ...): a point or a uniform box.

    Components are *part of* ``[mass]``, not added to it: the vehicle's mass, CG and inertia stay those of
    ``[mass]``, and the rest of the body is whatever ``[mass]`` holds besides the components. A component
    says where that part of the mass is, so that a design knob (:mod:`trikedyn.params.knobs`) can move or
    re-weigh it and change the vehicle's mass, CG and inertia by parallel-axis composition. The driver is
    ``mass.driver_kg``, not a component.
    """

    name: str = Field(pattern=r"^[a-z][a-z0-9_]*$", max_length=40,
                      description="how knobs name it (component.NAME.x_m ...): lower case, digits, underscores")
    description: str | None = Field(default=None, min_length=1, max_length=500, description="what it is")
    mass_kg: float = Field(ge=0, le=2000, description="its mass, part of the vehicle's mass [kg]")
    x_m: float = Field(ge=-5, le=10, description="its centre, ahead of the rear axle [m]")
    y_m: float = Field(ge=-2, le=2, description="its centre, left of the centre line [m]")
    z_m: float = Field(ge=-1, le=5, description="its centre, above the ground [m]")
    length_m: float = Field(default=0.0, ge=0, le=15, description="box edge along x; 0 for a point [m]")
    width_m: float = Field(default=0.0, ge=0, le=5, description="box edge along y [m]")
    height_m: float = Field(default=0.0, ge=0, le=5, description="box edge along z [m]")


class BodySpec(_Spec):
    """Overall body dimensions (for lane widths and plots)."""

    overall_width_m: _positive(0.3, "m") = Field(gt=0, le=5)
    overall_length_m: _positive(0.5, "m") = Field(gt=0, le=15)
