"""The vehicle parameter schema: validated, with units in the names, bounds and no unknown keys.

A parameter set describes one vehicle in trikedyn's axes (ISO 8855: x forward, y left, z up; origin on
the ground below the centre of the rear axle: the two-wheel axle of a delta trike, the single rear wheel's
axle of a tadpole, so that x is measured forward from the rear wheel(s) in both). The wheel layout is data: a list of wheels, each with
its position, its suspension (by name) and whether it is steered, driven and braked, so that a tadpole
trike is a different parameter set, not different code.

Masses follow the paper's bookkeeping (section 2.1): ``curb_kg`` is the vehicle as weighed (the paper's
total mass M = 508 kg), ``driver_kg`` the driver aboard, and the centre of gravity and the inertia
tensor are those of vehicle plus driver, ready to drive, without freight. The model splits that whole
into its bodies (chassis, steering head, fork slider, swing arms, wheels), so the chassis' own mass
and CG are derived, never entered twice.
The optional ``[[components]]`` (battery, motor controller, motor ...) say where parts of that
mass are; they are inside ``[mass]``, not added to it, and the design knobs
(:mod:`trikedyn.params.knobs`) move or re-weigh them with the vehicle's CG and inertia following.

Every number is finite and has a physical range, not just a sign: a quantity that must be positive says
so first (``gt=0``) and then has a least physical value (spring stiffness 100 N/m .. 1e7 N/m, curb mass
10 .. 5000 kg, wheel mass 0.2 .. 100 kg, ...; see each field). Across fields: the three contact points span
a triangle (each at least :data:`MIN_SUPPORT_M` from the line through the other two), and payload leaves
at least :data:`MIN_MASS_KG` with its CG at least :data:`MIN_CG_HEIGHT_M` above the ground. Within these
ranges the audit and the derived quantities never divide by zero or overflow.

An assumed value may declare the range it is uncertain over (what ``trikedyn sensitivity`` and ``trikedyn
uncertainty`` vary it over; without one they take ``value * (1 -/+ 0.2)``, the ``--fraction``). The ranges
sit in ``[ranges.SECTION]`` tables, each written right after the section it is about, keyed as that section
is: ``[ranges.mass]`` after ``[mass]``, ``[ranges.suspension.front]`` after ``[suspension.front]``,
``[ranges.wheels.front]`` after the front ``[[wheels]]`` entry, ``[ranges.components.battery]`` after the
battery; a design knob (``track_m``, ``wheelbase_m``, ``cg_height_m``) goes in ``[ranges]`` itself. A range
is ``[low, high]`` in the value's unit or ``{ rel = f }`` for ``value * (1 -/+ f)``::

    [tyre]
    mu_y = { value = 0.85, assumed = "dry asphalt" }

    [ranges.tyre]
    mu_y = [0.6, 1.0]  # damp to dry asphalt

Dotted keys in one ``[ranges]`` table (``tyre.mu_y = [0.6, 1.0]``) are the same thing. The schema checks the
form (two finite numbers, low < high; ``0 < rel < 1``); the sensitivity and uncertainty commands check that
each key names a number of the vehicle (or a design knob) and that low < value < high, naming the file and
the key (``trikedyn.study.designs.factors.declared_ranges``). A value moved by a study or an override may leave its
range: the range describes the vehicle as written.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, field_validator, model_validator

from .ranges import MAX_RANGES, RangeSpec, RelativeRange, flat_ranges
from .sections import (
    AeroSpec,
    BodySpec,
    ComponentSpec,
    DriveSpec,
    MassSpec,
    PayloadItemSpec,
    PointSpec,
    SteeringSpec,
    SuspensionSpec,
    TyreSpec,
    WheelSpec,
    _Spec,
)

__all__ = [
    "AeroSpec",
    "BodySpec",
    "ComponentSpec",
    "DriveSpec",
    "MassSpec",
    "PayloadItemSpec",
    "PointSpec",
    "RelativeRange",
    "SteeringSpec",
    "SuspensionSpec",
    "TyreSpec",
    "VehicleParameters",
    "WheelSpec",
]


MIN_SUPPORT_M = 0.1
"""Least distance of each wheel's contact point from the line through the other two [m]."""

MIN_MASS_KG = 10.0
"""Least mass of the vehicle with its payload [kg]."""

MIN_CG_HEIGHT_M = 0.01
"""Least height of the CG with payload above the ground [m]."""


class VehicleParameters(_Spec):
    """A whole vehicle. Load with :func:`trikedyn.params.load_vehicle`."""

    name: str = Field(min_length=1, max_length=100)
    description: str = Field(min_length=1, max_length=2000)
    source: str = Field(min_length=1, max_length=2000)
    layout: Literal["delta", "tadpole"]
    mass: MassSpec
    body: BodySpec
    steering: SteeringSpec
    suspension: dict[str, SuspensionSpec] = Field(min_length=1, max_length=3)
    wheels: tuple[WheelSpec, ...] = Field(min_length=3, max_length=3)
    tyre: TyreSpec
    drive: DriveSpec
    aero: AeroSpec
    sensor: PointSpec
    freight: PointSpec = Field(description="where freight goes (the paper's back trunk)")
    payload: tuple[PayloadItemSpec, ...] = Field(default=(), max_length=1000)
    components: tuple[ComponentSpec, ...] = Field(
        default=(), max_length=100,
        description="movable masses inside the body mass (part of [mass], not added to it)",
    )
    ranges: dict[str, RangeSpec] = Field(
        default_factory=dict, max_length=MAX_RANGES, exclude_if=lambda ranges: not ranges,
        description=("the range an assumed value is uncertain over, for the sensitivity and uncertainty commands "
                     "(else value x (1 -/+ 0.2)): [low, high] in its unit, or { rel = f } for value x (1 -/+ f); "
                     "in [ranges.SECTION] tables next to the values (key as in the section: [ranges.mass] "
                     "cg_z_m = [0.36, 0.42]; [ranges.wheels.front] radius_m = ...), or dotted keys in [ranges]; "
                     "a design knob (track_m, wheelbase_m, cg_height_m) in [ranges] itself"),
    )

    @field_validator("ranges", mode="before")
    @classmethod
    def _flatten_ranges(cls, ranges):
        return flat_ranges(ranges)

    @field_validator("wheels")
    @classmethod
    def _unique_wheel_names(cls, wheels):
        names = [w.name for w in wheels]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"wheel names must be unique; repeated: {', '.join(sorted(dup))}")
        return wheels

    @model_validator(mode="after")
    def _consistent_layout(self):
        for w in self.wheels:
            if w.suspension not in self.suspension:
                from ..errors import close_match

                hint = close_match(w.suspension, self.suspension)
                tip = f" (did you mean '{hint}'?)" if hint is not None else ""
                raise ValueError(
                    f"wheel '{w.name}' names suspension '{w.suspension}', which is not defined{tip}; "
                    f"defined: {', '.join(self.suspension)}"
                )
        steered = [w for w in self.wheels if w.steered]
        expected = 1 if self.layout == "delta" else 2
        if len(steered) != expected:
            raise ValueError(f"a {self.layout} layout has {expected} steered wheel(s), found {len(steered)}")
        if not any(w.driven for w in self.wheels):
            raise ValueError("at least one wheel must be driven")
        fixed = [w for w in self.wheels if not w.steered]
        if self.layout == "delta":
            front, rear = steered[0], fixed
            if any(abs(w.x_m) > 1e-9 for w in rear):
                raise ValueError("the rear axle is the x origin: both rear wheels need x_m = 0")
            if front.x_m <= 0:
                raise ValueError("the front wheel must be ahead of the rear axle (x_m > 0)")
            if not rear[0].y_m * rear[1].y_m < 0:
                raise ValueError("the two rear wheels must be on opposite sides (y_m of opposite signs)")
        else:  # tadpole: the origin is on the ground below the single rear wheel's axle
            rear, front = fixed[0], steered
            if abs(rear.x_m) > 1e-9:
                raise ValueError(
                    f"the rear wheel's axle is the x origin of a tadpole: wheel '{rear.name}' needs x_m = 0"
                )
            if any(w.x_m <= 0 for w in front):
                raise ValueError("both front (steered) wheels must be ahead of the rear wheel (x_m > 0)")
            if not front[0].y_m * front[1].y_m < 0:
                raise ValueError("the two front wheels must be on opposite sides (y_m of opposite signs)")
        return self

    @field_validator("wheels")
    @classmethod
    def _support_triangle(cls, wheels):
        """The contact points span a triangle: each at least MIN_SUPPORT_M from the line through the others."""
        pts = [(w.x_m, w.y_m) for w in wheels]
        (ax, ay), (bx, by), (cx, cy) = pts
        twice_area = abs((bx - ax) * (cy - ay) - (by - ay) * (cx - ax))
        for i, w in enumerate(wheels):
            (px, py), (qx, qy) = pts[(i + 1) % 3], pts[(i + 2) % 3]
            height = twice_area / max(math.hypot(qx - px, qy - py), 1e-12)
            if height < MIN_SUPPORT_M:
                raise ValueError(
                    f"wheel '{w.name}' is {height:.3f} m from the line through the other two contact points; "
                    f"the wheels must span a triangle at least {MIN_SUPPORT_M:g} m high"
                )
        return wheels

    @field_validator("payload")
    @classmethod
    def _payload_leaves_a_vehicle(cls, payload, info):
        """Payload taken off leaves at least MIN_MASS_KG, and the CG stays above the ground."""
        base = info.data.get("mass")
        if base is None:  # the mass section has its own error
            return payload
        mass, moment = base.total_kg, base.total_kg * base.cg_z_m
        for item in payload:
            sign = -1.0 if item.removed else 1.0
            mass += sign * item.mass_kg
            moment += sign * item.mass_kg * item.z_m
        if mass < MIN_MASS_KG:
            removed = sum(i.mass_kg for i in payload if i.removed)
            raise ValueError(
                f"cannot remove {removed:g} kg from {mass + removed:g} kg (at least {MIN_MASS_KG:g} kg must remain)"
            )
        if moment / mass < MIN_CG_HEIGHT_M:
            raise ValueError(
                f"puts the CG {moment / mass:.3f} m above the ground; it must stay at least {MIN_CG_HEIGHT_M:g} m"
            )
        return payload

    @field_validator("components")
    @classmethod
    def _components_inside_the_body(cls, components, info):
        """Names unique; the components weigh less than the body (``body_kg``, else curb less wheels)."""
        names = [c.name for c in components]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"component names must be unique; repeated: {', '.join(dup)}")
        mass, wheels = info.data.get("mass"), info.data.get("wheels")
        if not components or mass is None or (mass.body_kg is None and wheels is None):
            return components  # those sections have their own error
        body = mass.body_kg if mass.body_kg is not None else mass.curb_kg - sum(w.mass_kg for w in wheels)
        total = sum(c.mass_kg for c in components)
        if total >= body:
            raise ValueError(
                f"the components weigh {total:g} kg, not less than the body mass {body:g} kg they are part of"
            )
        return components

    # ---- derived geometry -------------------------------------------------------------------------
    def wheel(self, name: str) -> WheelSpec:
        """The wheel called ``name``.

        Parameters
        ----------
        name : str
            A wheel name.

        Returns
        -------
        WheelSpec
            The wheel.

        Raises
        ------
        KeyError
            When there is none.
        """
        for w in self.wheels:
            if w.name == name:
                return w
        raise KeyError(name)

    @property
    def wheelbase_m(self) -> float:
        """Front axle to rear axle [m]: the steered wheels' mean x less the fixed wheels' mean x (delta: the
        front wheel's x; tadpole: the front pair's mean x, the rear wheel being at x = 0)."""
        front = [w.x_m for w in self.wheels if w.steered]
        rear = [w.x_m for w in self.wheels if not w.steered]
        return abs(sum(front) / len(front) - sum(rear) / len(rear))

    @property
    def track_m(self) -> float:
        """Track of the two-wheel axle: rear for a delta, front for a tadpole [m]."""
        pair = [w for w in self.wheels if w.steered == (self.layout == "tadpole")]
        return abs(pair[0].y_m - pair[1].y_m)

    @property
    def steering_axis_angle_rad(self) -> float:
        """Steering axis rake [rad]."""
        return math.radians(self.steering.axis_angle_deg)
