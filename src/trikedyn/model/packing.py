"""The vehicle packed once into named compiled records: the one data the plant and the driver read.

A :class:`Plant` is a named tuple of plain numpy arrays that numba passes as one argument:

* the tree (``parent``, ``jtype``, ``jaxis``, ``tree_e``, ``tree_r``, ``mass``, ``h``, ``ibar``; see
  :mod:`trikedyn.model.dynamics`);
* ``wheels``: one :data:`WHEEL` record per wheel station (``p.wheels[k].radius``, ``.stiffness``,
  ``.steer_body``, ``.tyre_model``, ...);
* ``tyres``: one row of tyre coefficients per wheel, laid out by the wheel's tyre model
  (:mod:`trikedyn.tyre.interface`);
* ``vehicle``: one :data:`VEHICLE` record (``p.vehicle[0].g``, ``.max_steer``, ``.wheelbase``, ...);
* ``road``: one :data:`ROAD` record.

Compiled code reads every value by its name; the records are numpy structured arrays, so they are also
plain to inspect in Python (``model.plant.wheels["radius"]``). The per-wheel outputs of the right-hand
side are :data:`WHEEL_OUT` records. Units: SI throughout (m, kg, N, N m, rad, s).
"""

from __future__ import annotations

from collections import namedtuple
from collections.abc import Mapping

import numpy as np

__all__ = ["INPUT_NAMES", "Plant", "ROAD", "VEHICLE", "WHEEL", "WHEEL_OUT", "record", "road_record", "state_labels"]

WHEEL = np.dtype(
    [
        ("radius", "f8"),  # unloaded tyre radius [m]
        ("motion_ratio", "f8"),  # vertical wheel travel per unit suspension coordinate [m/m or m/rad]
        ("stiffness", "f8"),  # suspension rate in joint coordinates [N/m or N m/rad]
        ("damping", "f8"),  # suspension damping in joint coordinates [N s/m or N m s/rad]
        ("preload", "f8"),  # joint force carrying the design load [N or N m]
        ("bump_travel", "f8"),  # wheel travel from static to the bump stop [m]
        ("rebound_travel", "f8"),  # wheel travel from static to full extension [m]
        ("bump_stop_stiffness", "f8"),  # one-sided stop stiffness at the wheel [N/m]
        ("wheel_body", "i8"),  # body index of the wheel
        ("spring_body", "i8"),  # body index on the suspension joint
        ("steer_body", "i8"),  # body index of the steering head, -1 when not steered
        ("driven", "i8"),  # 1 when driven (open differential)
        ("braked", "i8"),  # 1 when braked
        ("steer_kp", "f8"),  # steering servo stiffness on this head [N m/rad]
        ("steer_kd", "f8"),  # steering servo damping on this head [N m s/rad]
        ("steer_y", "f8"),  # lateral position of the contact point, for the Ackermann linkage [m]
        ("tyre_model", "i8"),  # tyre model number (trikedyn.tyre.interface)
        ("vertical_stiffness", "f8"),  # tyre radial stiffness [N/m]
        ("vertical_damping", "f8"),  # tyre radial damping [N s/m]
        ("relaxation_x", "f8"),  # longitudinal relaxation length [m]
        ("relaxation_y", "f8"),  # lateral relaxation length [m]
    ],
    align=True,
)
"""One wheel station: suspension, steering servo and linkage, tyre."""

VEHICLE = np.dtype(
    [
        ("g", "f8"),  # gravity [m/s^2]
        ("max_steer", "f8"),  # steering lock about the steering axis [rad]
        ("max_steer_rate", "f8"),  # fastest steering a driver applies [rad/s]
        ("max_torque", "f8"),  # drive torque at the wheels, all driven wheels [N m]
        ("max_power", "f8"),  # drive power [W]
        ("max_brake", "f8"),  # brake torque per braked wheel [N m]
        ("aero", "f8"),  # 0.5 rho Cd A [kg/m]
        ("aero_x", "f8"),  # drag point: chassis CG x [m]
        ("aero_z", "f8"),  # drag point: chassis CG z [m]
        ("v_low", "f8"),  # slip regularisation speed [m/s]
        ("w_low", "f8"),  # rolling resistance sign smoothing [rad/s]
        ("slip_forces", "f8"),  # 1: horizontal tyre forces on; 0: off (verification)
        ("n_driven", "f8"),  # number of driven wheels
        ("n_braked", "i8"),  # number of braked wheels
        ("roll_limit", "f8"),  # roll or pitch beyond which the run stops as a rollover [rad]
        ("penetration_limit", "f8"),  # tyre deflection, per radius, beyond which the run stops [1]
        ("wheelbase", "f8"),  # front contact(s) to rear contact(s) [m]
        ("cos_rake", "f8"),  # cosine of the steering axis angle [1]
        ("ackermann", "f8"),  # Ackermann fraction of a steered pair: 0 parallel, 1 full [1]
    ],
    align=True,
)
"""Vehicle-wide values."""

ROAD = np.dtype(
    [("bump", "i8"), ("start", "f8"), ("length", "f8"), ("height", "f8"), ("y_min", "f8"), ("y_max", "f8")],
    align=True,
)
"""Road: flat (``bump = 0``) or a ``(1 - cos) / 2`` bump of ``height`` over ``start .. start + length`` along
x, across ``y_min <= |y| <= y_max`` [m]."""

WHEEL_OUT = np.dtype(
    [
        ("fx", "f8"),  # longitudinal tyre force [N]
        ("fy", "f8"),  # lateral tyre force [N]
        ("fz", "f8"),  # vertical tyre force [N]
        ("kappa", "f8"),  # transient longitudinal slip [1]
        ("alpha", "f8"),  # transient slip angle, tan(alpha) = -vy / |vx| [rad]
        ("deflection", "f8"),  # tyre deflection [m]
        ("travel", "f8"),  # suspension travel at the wheel, up positive [m]
        ("spin", "f8"),  # wheel spin rate [rad/s]
        ("vx", "f8"),  # forward speed of the wheel centre in tyre axes [m/s]
        ("mz", "f8"),  # aligning moment about the road normal [N m]
        ("camber", "f8"),  # inclination of the wheel plane, about the tyre x axis [rad]
        ("clamped", "f8"),  # bits of the tyre inputs clamped to the tyre data's validity ranges
    ],
    align=True,
)
"""What the right-hand side reports per wheel."""

INPUT_NAMES = ("steer_rad", "drive_torque_Nm", "brake_torque_Nm")
"""The inputs ``u`` of the right-hand side: steer command about the steering axis (reference, before the
linkage), total drive torque at the driven wheels, brake torque per braked wheel."""

Plant = namedtuple("Plant", "parent jtype jaxis tree_e tree_r mass h ibar wheels tyres vehicle road")
"""Everything the compiled right-hand side ``f(t, x, u, p)`` reads about the vehicle and the road."""


def record(dtype: np.dtype, values: Mapping[str, float]) -> np.ndarray:
    """One record of ``dtype`` filled by field name: every field given, none unknown.

    A record is never filled by position, so reordering the fields of :data:`WHEEL`, :data:`VEHICLE` or
    :data:`ROAD` cannot mix them up silently.

    Parameters
    ----------
    dtype : numpy.dtype
        A structured record type (:data:`WHEEL`, :data:`VEHICLE`, :data:`ROAD`).
    values : mapping of str to number
        Field name -> value, in the field's unit (see the record's comments).

    Returns
    -------
    numpy.ndarray, shape (1,)
        The record.

    Raises
    ------
    ValueError
        A field of the record not given, or a name that is not a field of it (a bug in the packing).
    """
    names = dtype.names or ()
    missing = [n for n in names if n not in values]
    unknown = sorted(set(values) - set(names))
    if missing or unknown:
        raise ValueError(f"record of {len(names)} fields: " + "; ".join(
            f"{what}: {', '.join(which)}" for what, which in (("not set", missing), ("not a field", unknown)) if which))
    out = np.zeros(1, dtype)
    for name in names:
        out[0][name] = values[name]
    return out


def road_record(bump: bool, start_m: float, length_m: float, height_m: float, y_min_m: float,
                y_max_m: float) -> np.ndarray:
    """One :data:`ROAD` record (a length-1 array).

    Parameters
    ----------
    bump : bool
        A bump (True) or a flat road.
    start_m : float
        Bump start along x [m].
    length_m : float
        Bump length along x [m].
    height_m : float
        Bump height [m].
    y_min_m, y_max_m : float
        Lateral extent of the bump [m].

    Returns
    -------
    numpy.ndarray, shape (1,), dtype ROAD
        The record.
    """
    return record(ROAD, {"bump": int(bump), "start": start_m, "length": length_m, "height": height_m,
                         "y_min": y_min_m, "y_max": y_max_m})


def state_labels(body_names, wheel_names) -> tuple[str, ...]:
    """Labels of the state ``x = (q, u, slips)`` of a tree (see :mod:`trikedyn.model.dynamics`).

    ``q``: chassis position, roll/pitch/yaw, then one joint coordinate per body after the chassis; ``u``:
    chassis angular then linear velocity in chassis axes, then the joint rates (``<body>_qd``); then per wheel the
    transient longitudinal slip and the tangent of the transient slip angle.

    Parameters
    ----------
    body_names : sequence of str
        Body names, the chassis first.
    wheel_names : sequence of str
        Wheel names.

    Returns
    -------
    tuple of str
        One label per state entry.
    """
    joints = list(body_names[1:])
    q = ["x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad", *(f"{b}_q" for b in joints)]
    u = ["wx_radps", "wy_radps", "wz_radps", "vx_mps", "vy_mps", "vz_mps", *(f"{b}_qd" for b in joints)]
    slips = [f"{w}_{s}" for w in wheel_names for s in ("kappa", "tan_alpha")]
    return (*q, *u, *slips)
