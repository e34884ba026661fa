"""Tilt-table test: the largest static tilt angle of the vehicle on a platform tilted about its x axis.

Type approval asks for a maximum stable tilt angle (e.g. Japan's safety standard: 35 deg, 30 deg for
slow vehicles). The vehicle stands on a table that is tilted quasi-statically about the vehicle's
longitudinal (x) axis; the wheels are kept from sliding sideways (a lip, or high friction); the tilt angle
is the table angle at which the first wheel on the high side lifts (its vertical force reaches zero).
``side`` names the side that goes *down*, the direction the vehicle would tip to: tilting to the left,
a delta trike tips about the line from the front contact to the rear left contact and its rear *right*
wheel lifts. A CG left of the centre line makes the left tilt angle the smaller one.

Method
------
The full compliant model (:mod:`trikedyn.model`: springs with preload, bump stops, tyre vertical
stiffness, the steering servo) is put in quasi-static equilibrium at each table angle. The table is the
model's flat road, and tilting it is rotating gravity in the road frame, ``g (0, +-sin(theta),
-cos(theta))``. Generalised forces at zero velocity: the model's own forces without gravity (springs,
stops, servo, tyre normal forces) as ``H du/dt`` from the compiled right-hand side
(:func:`~trikedyn.model.statics.state_derivative` with gravity and tyre slip forces off, ``H`` from
:func:`~trikedyn.model.dynamics.crba`); rotated gravity and the table's tangential forces by recursive
Newton-Euler (:func:`~trikedyn.model.dynamics.rnea` with that gravity vector, the contact forces as
external forces on the wheels): exact, with no numerical Jacobian of contact points.

Tangential forces are Lagrange multipliers of lateral (table y) pins: the front contact's y and the mean y
of the rear pair (generally: of each group of contacts at one x) are held at their level values, each
multiplier shared equally by its group. The two rear lateral forces are statically indeterminate (same x,
same line of action); equal shares are their least-norm split, consistent with leaving the pair's
relative lateral motion (a track change, second order in the roll) free. Gravity has no x component on a
table tilted about x, so no longitudinal force is needed and none is applied: chassis x is fixed (a gauge)
and the wheels' spin equations are left out (parking brakes react any spin torque). Pinning every contact
in x and y with stiff springs was tried and rejected: with locked wheels it set up large self-equilibrated
longitudinal forces (the raked fork and the swing arms move their contacts in x as they deflect) that
jacked the suspension and hid most of the body roll; a real tyre's compliance relaxes such forces.

Unknowns (chassis y, z, roll, pitch, yaw, every joint but the wheel spins, the multipliers) are found by
Newton's method with least-squares steps on a forward-difference Jacobian (one row, the table-x force
balance, is identically zero), continuing from the previous angle in steps of :data:`STEP_DEG`. Past the
lift the tyres are made to hold the wheel down (``Fz = kz d`` also for ``d < 0``): identical to the model
up to the lift, and the lowest wheel load stays a smooth function of the angle through zero, so the lift
is bracketed and found by Brent's method to :data:`XTOL_DEG`. The rigid figure is the closed form per
support-triangle edge of :func:`trikedyn.params.audit.tip_over_thresholds` (``tan(theta) = d_y / h``,
``d_y`` the CG's lateral distance to the tip axis, ``h`` its height; ``a T / (2 h L)`` for a centred CG),
payload included.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..errors import InputError, SimulationError
from ..model.dynamics import crba, rnea
from ..model.kinematics import joint_transforms, world_transforms
from ..model.statics import state_derivative, static_equilibrium
from ..model.vehicle import VehicleModel, build_model
from ..params.audit import tip_over_thresholds
from ..params.io import ParameterSet
from ..params.schema import VehicleParameters

__all__ = ["TiltResult", "TiltSide", "rigid_tilt_angles", "tilt_table"]

SIDES = ("left", "right")
STEP_DEG = 2.0
"""Table angle step of the continuation [deg]."""
XTOL_DEG = 1e-4
"""Tolerance of the lift angle [deg]."""
MAX_DEG = 89.0


def _json(value):
    """Plain JSON types: floats (None when not finite), lists, dicts with string keys."""
    if isinstance(value, dict):
        return {str(k): _json(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_json(v) for v in value]
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    return value.item() if isinstance(value, np.generic) else value


@dataclass(frozen=True)
class TiltSide:
    """The tilt test toward one side.

    Attributes
    ----------
    side : {"left", "right"}
        The side that goes down.
    tilt_angle_deg : float
        Table angle at which the first wheel lifts [deg].
    first_lifting_wheel : str
    rigid_tilt_angle_deg : float
        The rigid closed form about the same tip axis [deg].
    tip_axis : str
        The support-triangle edge the vehicle tips about, e.g. ``"front-rear_left"``.
    body_roll_deg : float
        Chassis roll relative to the table at the lift, toward the downhill side positive [deg].
    cg_shift_m : float
        Downhill shift of the whole vehicle's CG at the lift from where it stands on the level table
        [m] (body roll, spring and tyre deflections).
    angles_deg : tuple of float
        Table angles of the load table, up to and including the lift [deg].
    wheel_loads_N : dict
        Wheel name -> vertical (table-normal) load at each of ``angles_deg`` [N].
    """

    side: str
    tilt_angle_deg: float
    first_lifting_wheel: str
    rigid_tilt_angle_deg: float
    tip_axis: str
    body_roll_deg: float
    cg_shift_m: float
    angles_deg: tuple
    wheel_loads_N: dict

    def to_dict(self) -> dict:
        """JSON-safe (plain floats; None for non-finite values).

        Returns
        -------
        dict
            The side (angles [deg], loads [N]).
        """
        return _json(asdict(self))


@dataclass(frozen=True)
class TiltResult:
    """Result of :func:`tilt_table`: the limiting side and the details per side tested.

    Attributes
    ----------
    tilt_angle_deg : float
        The smaller tilt angle of the sides tested [deg].
    side : {"left", "right"}
        The side that limits (the side that goes down).
    first_lifting_wheel : str
        The wheel that lifts first on that side.
    rigid_tilt_angle_deg : float
        The rigid closed form for that side [deg].
    sides : dict
        ``"left"`` / ``"right"`` -> :class:`TiltSide`, for each side tested.
    require_deg : float or None
        The required angle [deg], if one was given.
    passes : bool or None
        ``tilt_angle_deg >= require_deg``; None without a requirement.
    vehicle : str
    mass_kg : float
        Total mass, payload included [kg].
    """

    tilt_angle_deg: float
    side: str
    first_lifting_wheel: str
    rigid_tilt_angle_deg: float
    sides: dict = field(default_factory=dict)
    require_deg: float | None = None
    passes: bool | None = None
    vehicle: str = ""
    mass_kg: float = 0.0

    def to_dict(self) -> dict:
        """JSON-safe (plain floats; None for non-finite values); ``sides`` with each side's details.

        Returns
        -------
        dict
            The result (angles [deg], loads [N]).
        """
        return _json(asdict(self))

    def plot(self):
        """Wheel loads [N] against table angle [deg], one axis per side, the lift and the rigid angle
        (dashed) marked; returns a :class:`matplotlib.figure.Figure`.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from matplotlib.figure import Figure

        sides = [self.sides[s] for s in SIDES if s in self.sides]
        fig = Figure(figsize=(6.5 * len(sides), 4.2))
        axes = fig.subplots(1, len(sides), squeeze=False)[0]
        for ax, s in zip(axes, sides, strict=True):
            for wheel, loads in s.wheel_loads_N.items():
                ax.plot(s.angles_deg, loads, marker=".", label=wheel)
            ax.axvline(s.tilt_angle_deg, color="k", lw=1.0)
            ax.plot([s.tilt_angle_deg], [0.0], "kx", ms=9)
            label = f"{s.first_lifting_wheel} lifts\n{s.tilt_angle_deg:.2f} deg"
            ax.annotate(label, (s.tilt_angle_deg, 0.0), xytext=(-8, 12), textcoords="offset points", ha="right")
            ax.axvline(
                s.rigid_tilt_angle_deg, color="k", ls="--", lw=1.0, label=f"rigid {s.rigid_tilt_angle_deg:.2f} deg"
            )
            if self.require_deg is not None:
                ax.axvline(
                    self.require_deg, color="tab:red", ls=":", lw=1.0, label=f"required {self.require_deg:g} deg"
                )
            ax.set_title(f"tilt to the {s.side}")
            ax.set_xlabel("table angle [deg]")
            ax.set_ylabel("wheel load [N]")
            ax.set_ylim(bottom=min(0.0, ax.get_ylim()[0]))
            ax.grid(alpha=0.3)
            ax.legend(fontsize="small")
        fig.suptitle(f"{self.vehicle}: tilt table, {self.mass_kg:.0f} kg")
        fig.tight_layout()
        return fig


def rigid_tilt_angles(params) -> dict:
    """Rigid-vehicle tilt angle per side: ``side -> (angle [deg], tip axis, lifting wheel)``.

    From :func:`trikedyn.params.audit.tip_over_thresholds` (total CG, payload included): a vehicle on a
    table tilted by ``theta`` about x feels ``g sin(theta)`` laterally and ``g cos(theta)`` normally, so it
    tips about an edge when ``tan(theta) = d_y / h``.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.

    Returns
    -------
    dict
        ``side -> (angle [deg], tip axis, lifting wheel)``.
    """
    names = [w.name for w in params.wheels]
    out = {}
    for edge in tip_over_thresholds(params):
        if not edge["lateral"] or edge["tips_toward"] not in SIDES:
            continue
        on_axis = edge["edge"].split("-")
        lifting = next(n for n in names if n not in on_axis)
        angle = math.degrees(math.atan(edge["acceleration_g"]))
        side = edge["tips_toward"]
        if side not in out or angle < out[side][0]:
            out[side] = (angle, edge["edge"], lifting)
    return out


class _Table:
    """The quasi-static equilibrium problem of one vehicle on the tilting table (see the module docstring)."""

    def __init__(self, model: VehicleModel):
        self.model = model.on_flat_road()
        self.q0 = static_equilibrium(self.model).state[: self.model.n_dof].copy()
        self.bare = self.model.variant(gravity=0.0, slip_forces=False)
        tree = self.model.tree
        self.n = tree.n_dof
        self.arrays = tree.arrays()
        self.wheels = tree.wheels
        spin = {w.wheel_body for w in self.wheels}
        joints = [5 + b for b in range(1, tree.n_bodies) if b not in spin]
        self.coords = [1, 2, 3, 4, 5, *joints]  # chassis x is the gauge
        self.rows = [0, 1, 2, 3, 4, 5, *joints]
        groups: dict[float, list[int]] = {}  # contacts at one x (to the mm) share a lateral pin
        for k, w in enumerate(self.model.params.wheels):
            groups.setdefault(round(w.x_m, 3), []).append(k)
        self.groups = list(groups.values())
        self.kz = np.array(self.model.wheels["vertical_stiffness"], dtype=float)
        self.g = self.model.gravity
        self.tol = 1e-8 * tree.total_mass() * self.g
        cs = self._contacts(self.q0)[0]
        self.y0 = np.array([np.mean([cs[k][1] for k in gr]) for gr in self.groups])
        self.steps = np.array([1e-7] * len(self.coords) + [1.0] * len(self.groups))
        self.start = np.concatenate([self.q0[self.coords], np.zeros(len(self.groups))])
        self.cg0 = self._cg(self.q0)

    def _frames(self, q):
        e, r = joint_transforms(q, *self.arrays[:5])
        return world_transforms(self.arrays[0], e, r)

    def _contacts(self, q):
        """Contact points in the table frame and centre -> contact vectors, as the compiled tyre finds them."""
        ew, pw = self._frames(q)
        points, arms = [], []
        for w in self.wheels:
            axle = ew[w.wheel_body][1]
            down = np.array([0.0, 0.0, 1.0]) - axle[2] * axle
            arm = -w.radius * down / np.linalg.norm(down)
            points.append(pw[w.wheel_body] + arm)
            arms.append(arm)
        return points, arms, ew

    def _cg(self, q):
        ew, pw = self._frames(q)
        tree = self.model.tree
        points = pw + np.einsum("bji,bj->bi", ew, tree.h / tree.mass[:, None])
        return tree.mass @ points / tree.total_mass()

    def state(self, s):
        """The generalised coordinates [m, rad] of a solution ``s``: its first entries in the solved coordinates,
        the others (chassis x, wheel spins) at the level-table equilibrium."""
        q = self.q0.copy()
        q[self.coords] = s[: len(self.coords)]
        return q

    def residual(self, s, gravity):
        """Generalised-force residual [N, N m] and pin residuals (scaled to N), signed wheel loads [N]."""
        q = self.state(s)
        lam = 1e3 * s[len(self.coords) :]  # lateral pin forces [N]
        x = np.zeros(self.model.n_states)
        x[: self.n] = q
        xdot, wout = state_derivative(self.bare, x)
        own = crba(q, *self.arrays) @ xdot[self.n : 2 * self.n]
        loads = self.kz * wout["deflection"]
        points, arms, ew = self._contacts(q)
        fext = np.zeros((self.model.tree.n_bodies, 6))
        pins = np.empty(len(self.groups))
        for gi, group in enumerate(self.groups):
            pins[gi] = 1e5 * (np.mean([points[k][1] for k in group]) - self.y0[gi])
            for k in group:
                force = np.array([0.0, lam[gi] / len(group), min(loads[k], 0.0)])  # lifted: held down
                body = self.wheels[k].wheel_body
                fext[body, :3] = ew[body] @ np.cross(arms[k], force)
                fext[body, 3:] = ew[body] @ force
        zero = np.zeros(self.n)
        total = own - rnea(q, zero, zero, fext, gravity, *self.arrays)
        return np.concatenate([total[self.rows], pins]), loads

    def solve(self, angle_deg, sign, s):
        """Equilibrium at a table angle from a nearby solution ``s``: (solution, signed loads) or None."""
        theta = math.radians(angle_deg)
        gravity = self.g * np.array([0.0, sign * math.sin(theta), -math.cos(theta)])
        s = s.copy()
        for _ in range(30):
            res, loads = self.residual(s, gravity)
            if not np.all(np.isfinite(res)):
                return None
            if np.abs(res).max() < self.tol:
                return s, loads
            jac = np.empty((res.size, s.size))
            for j, h in enumerate(self.steps):
                shifted = s.copy()
                shifted[j] += h
                jac[:, j] = (self.residual(shifted, gravity)[0] - res) / h
            s = s + np.linalg.lstsq(jac, -res, rcond=None)[0]
        return None


def _tilt_side(table: _Table, side: str, rigid) -> TiltSide:
    sign = 1.0 if side == "left" else -1.0
    names = [w.name for w in table.wheels]
    found = table.solve(0.0, sign, table.start)
    if found is None or found[1].min() <= 0:
        raise SimulationError("the vehicle does not stand on the level table", 0.0)
    angles, rows = [0.0], [found[1]]
    lower, s_lower, step = 0.0, found[0], STEP_DEG
    while True:
        if lower >= MAX_DEG:
            raise SimulationError(f"no wheel lifts up to {MAX_DEG:g} deg of tilt to the {side}")
        angle = min(lower + step, MAX_DEG)
        found = table.solve(angle, sign, s_lower)
        if found is None:
            step /= 2
            if step < 1e-3:
                raise SimulationError(f"no equilibrium found at {angle:.3f} deg of tilt to the {side}")
            continue
        if found[1].min() <= 0.0:
            upper = angle
            break
        lower, s_lower = angle, found[0]
        angles.append(angle)
        rows.append(found[1])

    def lowest(a):
        """The lowest signed wheel load [N] at a tilt of ``a`` [deg], solved from the last standing angle: its root
        is the lift-off angle."""
        hit = table.solve(a, sign, s_lower)
        if hit is None:
            raise SimulationError(f"no equilibrium found at {a:.4f} deg of tilt to the {side}")
        return float(hit[1].min())

    lift = brentq(lowest, lower, upper, xtol=XTOL_DEG)
    s, loads = table.solve(lift, sign, s_lower)
    q = table.state(s)
    wheel = names[int(np.argmin(loads))]
    angles.append(lift)
    rows.append(np.maximum(loads, 0.0))
    cg = table._cg(q)
    return TiltSide(
        side=side,
        tilt_angle_deg=float(lift),
        first_lifting_wheel=wheel,
        rigid_tilt_angle_deg=float(rigid[0]),
        tip_axis=rigid[1],
        body_roll_deg=float(-sign * math.degrees(q[3])),
        cg_shift_m=float(sign * (cg[1] - table.cg0[1])),
        angles_deg=tuple(float(a) for a in angles),
        wheel_loads_N={n: tuple(float(r[k]) for r in rows) for k, n in enumerate(names)},
    )


def tilt_table(vehicle, *, side: str = "both", require_deg: float | None = None) -> TiltResult:
    """The tilt-table test of a vehicle on its compliant model (see the module docstring).

    Parameters
    ----------
    vehicle : ParameterSet, VehicleParameters or VehicleModel
        The vehicle, payload included (apply it first with :func:`trikedyn.params.with_freight`).
    side : {"both", "left", "right"}
        The side that goes down; ``"both"`` tests both and reports the smaller angle.
    require_deg : float, optional
        Required tilt angle [deg] (e.g. 35); sets ``passes``.

    Returns
    -------
    TiltResult

    Raises
    ------
    InputError
        For an unknown ``side`` or a ``require_deg`` outside (0, 90).
    SimulationError
        When the vehicle cannot stand on the level table, or no equilibrium is found on the way.
    """
    if side not in ("both", *SIDES):
        raise InputError(f"expected left, right or both, got '{side}'", where="side")
    if require_deg is not None and not (math.isfinite(require_deg) and 0.0 < require_deg < 90.0):
        raise InputError(f"expected an angle between 0 and 90 deg, got {require_deg!r}", where="require_deg")
    if isinstance(vehicle, VehicleModel):
        model = vehicle
    elif isinstance(vehicle, ParameterSet | VehicleParameters):
        model = build_model(vehicle)
    else:
        raise InputError(f"expected a ParameterSet or a VehicleModel, got {type(vehicle).__name__}", where="vehicle")
    rigid = rigid_tilt_angles(model.params)
    table = _Table(model)
    wanted = SIDES if side == "both" else (side,)
    sides = {s: _tilt_side(table, s, rigid[s]) for s in wanted}
    limit = min(sides.values(), key=lambda r: r.tilt_angle_deg)
    return TiltResult(
        tilt_angle_deg=limit.tilt_angle_deg,
        side=limit.side,
        first_lifting_wheel=limit.first_lifting_wheel,
        rigid_tilt_angle_deg=limit.rigid_tilt_angle_deg,
        sides=sides,
        require_deg=None if require_deg is None else float(require_deg),
        passes=None if require_deg is None else bool(limit.tilt_angle_deg >= require_deg),
        vehicle=model.params.name,
        mass_kg=model.tree.total_mass(),
    )
