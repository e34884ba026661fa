"""The model's straight running: its own tyre, drive, brake and resistance terms evaluated in steady straight
running, quasi-static.

The forces the compiled right-hand side (:func:`trikedyn.model.rhs.evaluate_into`) applies, taken in balance at
one speed, with no simulation. :class:`StraightRunning` (one per model: :func:`straight_running`) gives the
quasi-static :class:`State` at a speed under a drive command and a brake torque, on a grade;
:func:`~trikedyn.analysis.straight_balance.full_drive_balance` finds the speed at which the full drive
balances the resistances, and :func:`~trikedyn.analysis.straight_balance.power_takeover` the speed at which
the power limit takes over from the torque limit. Each wheel's spin balance, and the slip that balances it, is
:mod:`~trikedyn.analysis.wheel_balance`'s. The straight-line
performance (:mod:`trikedyn.analysis.performance`: top speed, acceleration, braking) is built on these.

The model, as the simulation drives it
--------------------------------------
* **Drive.** The command is clamped to ``drive.max_drive_torque_Nm`` (the total at the driven wheels), then
  to ``max_power_W / omega_mean`` (``omega_mean`` the mean spin rate of the driven wheels), and split equally
  over the driven wheels (open differential). ``power = T omega_mean`` is the power at the wheels.
* **Wheels.** Each wheel ``i`` spins under ``I_i omega_i' = tau_drive,i - tau_brake,i tanh(omega_i / w_low)
  - F_x,i R_i + M_y,i``: the tyre's longitudinal force ``F_x`` acts at the contact point, a moment arm of the
  *unloaded* radius ``R``; the rolling-resistance moment ``M_y = -f_r F_z R_e tanh(omega / w_low)`` has the
  effective rolling radius ``R_e = R - d / 3`` (``d = F_z / k_z`` the tyre deflection), which is also the
  radius of the slip, ``kappa = (omega R_e - v) / v_ref`` with ``v_ref = (v^4 + v_low^4)^(1/4)``. Both
  come from the wheel's own tyre function (:func:`trikedyn.tyre.interface.tyre_forces`): the ``[tyre]``
  section's similarity Magic Formula, or a ``.tir`` file's full Magic Formula (its ``F_x`` with offsets, its
  rolling resistance ``M_y``), with zero slip angle and camber.
* **Vehicle.** ``M a = sum F_x,i - 0.5 rho C_d A v^2 - M g sin(theta)``, ``tan(theta) = grade / 100``; ``M``
  the whole vehicle (payload and wheels). In quasi-static running each wheel keeps its slip, so
  ``omega_i' = a (1 + kappa_i v^3 / v_ref^3) / R_e,i``: the wheels' spin inertia is part of the balance.
* **Wheel loads.** The static equilibrium's loads (``model.cache``), times ``cos(theta)``, plus the
  longitudinal load transfer of a rigid vehicle on its contact points: the pitch moment of the drag at its
  point's height (the chassis CG, as in the model), of the inertia and grade force at the CG height, of the
  wheels' rolling-resistance moments and of their spin inertia, shared by the vertical, pitch and roll
  balances of the contacts (exact for three wheels).
* **Braked wheels.** A braked wheel rolls while its tyre can carry the brake torque; when it cannot (the
  rolling balance has no root short of the tyre's peak force) it locks, and stays locked (hysteresis),
  sliding with the force of its own tyre at the slip where ``tau_brake tanh(omega / w_low)`` balances that
  force (a spin of about half ``w_low``): the tyre model's value near full lock, as in the simulation.
* **Traction.** When a driven wheel's tyre cannot carry its share of the torque, the open differential gives
  each driven wheel at most what the weaker one carries (its tyre at its peak force).

The pitch and bounce of the suspension, and the slips' relaxation, are left out (quasi-static).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.statics import static_equilibrium
from ..model.vehicle import VehicleModel, build_model
from ..params.io import ParameterSet
from ..params.ops import mass_properties
from ..params.schema import VehicleParameters
from .wheel_balance import Wheel, drive_capacity, solve_slip, spin_balance

__all__ = ["State", "StraightRunning", "cache_key", "straight_running", "vehicle_model"]

@dataclass
class State:
    """One quasi-static state of straight running (:meth:`StraightRunning.state`).

    Attributes
    ----------
    a : float
        Acceleration [m/s^2], negative braking.
    torque : float
        Total drive torque at the driven wheels, as the model clamps the command [N m].
    limit : str
        What sets the drive torque: ``"command"``, ``"torque"``, ``"power"`` or ``"traction"``.
    fz, fx : numpy.ndarray
        Vertical load and longitudinal tyre force per wheel [N].
    my : numpy.ndarray
        Rolling-resistance moment per wheel [N m].
    kappa : numpy.ndarray
        Longitudinal slip per wheel [1].
    spin : numpy.ndarray
        Spin rate per wheel [rad/s].
    locked : numpy.ndarray
        Per wheel, True when it is locked (sliding).
    """

    a: float
    torque: float
    limit: str
    fz: np.ndarray
    fx: np.ndarray
    my: np.ndarray
    kappa: np.ndarray
    spin: np.ndarray
    locked: np.ndarray


class StraightRunning:
    """The model's straight running, per wheel, quasi-static (see the module docstring).

    Built once per model by :func:`straight_running`, from the packed records and the static equilibrium.

    Attributes
    ----------
    mass : float
        The whole vehicle [kg].
    cg_z : float
        Height of the CG [m].
    g : float
        [m/s^2].
    drag : float
        ``0.5 rho C_d A`` [N s^2/m^2].
    drag_z : float
        Height at which the drag acts (the chassis CG) [m].
    max_torque, max_power : float
        The drive's limits: total torque at the driven wheels [N m], power at the wheels [W].
    max_brake : float
        Brake torque on each braked wheel [N m].
    n_driven : float
        Number of driven wheels.
    v_low, w_low : float
        The model's low-speed regularisation of the slip [m/s] and of the brake and rolling resistance [rad/s].
    wheels : list of Wheel
        Per wheel (in the model's order) its name (``.name``) and packed records
        (:class:`~trikedyn.analysis.wheel_balance.Wheel`).
    static, x : numpy.ndarray
        Static load on the flat [N] and x position [m] per wheel.
    transfer : numpy.ndarray
        Change of the loads per unit pitch moment [N / (N m)].
    driven : numpy.ndarray
        Per wheel, True when it is driven.
    radius, kz, inertia : numpy.ndarray
        Unloaded radius [m], vertical stiffness [N/m] and spin inertia [kg m^2] per wheel.
    """

    def __init__(self, model: VehicleModel):
        params = model.params
        veh = model.vehicle
        eq = static_equilibrium(model)
        self.mass = float(model.tree.total_mass())
        self.cg_z = float(mass_properties(params).cg_m[2])
        self.g = float(veh["g"])
        self.drag = float(veh["aero"])
        self.drag_z = float(veh["aero_z"])
        self.max_torque = float(veh["max_torque"])
        self.max_power = float(veh["max_power"])
        self.max_brake = float(veh["max_brake"])
        self.n_driven = float(veh["n_driven"])
        self.v_low = float(veh["v_low"])
        self.w_low = float(veh["w_low"])
        self.wheels = []
        xs, ys = [], []
        for k, w in enumerate(model.tree.wheels):
            spec = params.wheel(w.name)
            rec = model.plant.wheels[k]
            self.wheels.append(Wheel(w.name, int(rec["tyre_model"]), np.ascontiguousarray(model.plant.tyres[k]),
                                     float(rec["radius"]), float(rec["vertical_stiffness"]),
                                     float(spec.spin_inertia_kgm2), bool(rec["driven"]), bool(rec["braked"]),
                                     float(eq.wheel_loads_N[w.name]), self.v_low, self.w_low))
            xs.append(spec.x_m)
            ys.append(spec.y_m)
        n = len(self.wheels)
        self.static = np.array([w.static_load for w in self.wheels])
        self.x = np.array(xs)
        # loads' change for a pitch moment: vertical, pitch and roll balances of the contacts (least norm)
        support = np.vstack([np.ones(n), self.x, np.array(ys)])
        self.transfer = np.linalg.pinv(support)[:, 1]
        self.driven = np.array([w.driven for w in self.wheels])
        self.radius = np.array([w.radius for w in self.wheels])
        self.kz = np.array([w.kz for w in self.wheels])
        self.inertia = np.array([w.inertia for w in self.wheels])

    # -- the vehicle --------------------------------------------------------------------------------------
    def state(self, v, drive, brake, sin_t, cos_t, locked=None, start=None) -> State:
        """The quasi-static state at speed ``v`` [m/s] under a drive command [N m] and a brake torque per
        braked wheel [N m], on a grade ``(sin, cos)``; ``locked`` per wheel (kept from a previous state),
        ``start`` a nearby state to start the iteration from.

        Parameters
        ----------
        v : float
            Speed [m/s].
        drive : float
            Drive command [N m].
        brake : float
            Brake torque per braked wheel [N m].
        sin_t, cos_t : float
            Sine and cosine of the grade angle, dimensionless.
        locked : numpy.ndarray of bool, optional
            Locked wheels.
        start : State, optional
            A nearby state to start from.

        Returns
        -------
        State
            Loads [N], forces [N], slips, acceleration [m/s^2] and the limit.
        """
        n = len(self.wheels)
        v_ref = (v**4 + self.v_low**4) ** 0.25
        locked = np.zeros(n, bool) if locked is None else locked.copy()
        kappa = np.zeros(n) if start is None else start.kappa.copy()
        fz = self.static * cos_t if start is None else start.fz.copy()
        my = np.zeros(n) if start is None else start.my.copy()
        a = 0.0 if start is None else start.a
        fx, spin = np.zeros(n), np.zeros(n)
        aero = self.drag * v * v
        torque, limit = 0.0, ""
        previous = None
        for _ in range(200):
            r_eff = self.radius - fz / self.kz / 3.0
            spin_rate = a * (1.0 + kappa * (v / v_ref) ** 3) / r_eff
            pitch = (-aero * self.drag_z - self.mass * (a + self.g * sin_t) * self.cg_z + my.sum()
                     - (self.inertia * spin_rate).sum())
            fz = np.maximum(self.static * cos_t + self.transfer * pitch, 0.0)
            r_eff = self.radius - fz / self.kz / 3.0
            # the drive command, clamped as the model clamps it
            torque = min(max(drive, -self.max_torque), self.max_torque)
            limit = "torque" if torque >= self.max_torque else "command"
            if self.driven.any():
                mean_spin = float(np.abs((v + kappa * v_ref) / r_eff)[self.driven].mean())
                if abs(torque) * mean_spin > self.max_power:
                    torque = math.copysign(self.max_power / mean_spin, torque)
                    limit = "power"
            new_kappa = np.zeros(n)
            peak = None
            for k, w in enumerate(self.wheels):
                tau_d = torque / self.n_driven if w.driven else 0.0
                tau_b = brake if w.braked else 0.0
                root, lock = solve_slip(w, v, v_ref, fz[k], a, tau_d, tau_b, locked[k], kappa[k])
                if root is None:  # a driven wheel's tyre cannot carry the torque
                    if not tau_d > 0.0:
                        raise RuntimeError(f"no rolling balance for the {w.name} wheel at {v:g} m/s")  # a bug
                    most, at = drive_capacity(w, v, v_ref, fz[k], a)
                    peak = most if peak is None else min(peak, most)
                    root = at
                locked[k] = lock
                new_kappa[k] = root
            if peak is not None:
                # traction: the open differential gives each driven wheel the same torque, at most what the
                # weaker one carries (its tyre at the peak); the other one rolls with that torque
                torque = min(torque, peak * self.n_driven)
                limit = "traction"
                for k, w in enumerate(self.wheels):
                    if w.driven:
                        root, _ = solve_slip(w, v, v_ref, fz[k], a, torque / self.n_driven, 0.0, False,
                                                    kappa[k])
                        if root is not None:
                            new_kappa[k] = root
            for k, w in enumerate(self.wheels):
                tau_d = torque / self.n_driven if w.driven else 0.0
                tau_b = brake if w.braked else 0.0
                _, fx[k], my[k], spin[k] = spin_balance(w, new_kappa[k], v, v_ref, fz[k], a, tau_d, tau_b)
            a_new = (fx.sum() - aero - self.mass * self.g * sin_t) / self.mass
            # np.allclose(new_kappa, kappa, rtol=1e-8, atol=1e-11) for finite slips, without its 50 us
            done = abs(a_new - a) < 1e-9 * (1.0 + abs(a_new)) and bool(
                np.all(np.abs(new_kappa - kappa) <= 1e-11 + 1e-8 * np.abs(kappa)))
            # the acceleration is a fixed point a = A(a) (the wheels' inertia and the load transfer): secant steps
            residual = a - a_new
            if previous is not None and residual != previous[1]:
                a_next = a - residual * (a - previous[0]) / (residual - previous[1])
            else:
                a_next = a_new
            previous = (a, residual)
            a, kappa = (a_new if done else a_next), new_kappa
            if done:
                break
        return State(a, torque, limit, fz, fx.copy(), my.copy(), kappa, spin.copy(), locked)


def vehicle_model(vehicle) -> VehicleModel:
    """The vehicle as a model on a flat road.

    Parameters
    ----------
    vehicle : ParameterSet, VehicleParameters or VehicleModel
        A model (its flat-road variant is taken) or a parameter set (a model is built from it).

    Returns
    -------
    VehicleModel

    Raises
    ------
    InputError
        For anything else.
    """
    if isinstance(vehicle, VehicleModel):
        return vehicle.on_flat_road()
    if isinstance(vehicle, ParameterSet | VehicleParameters):
        return build_model(vehicle)
    raise InputError(f"expected a ParameterSet, VehicleParameters or VehicleModel, got {type(vehicle).__name__}",
                     where="vehicle")


def cache_key(model: VehicleModel, *what) -> tuple:
    """A cache key of the straight-line results (in ``model.cache``), ``what`` naming the result: they depend
    on the drive's limits, which variants of a model that share its cache (``with_ideal_drive``) change, so
    the packed records are part of the key.

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    *what
        What the result is.

    Returns
    -------
    tuple
        The key.
    """
    plant = model.plant
    return ("performance", plant.vehicle.tobytes(), plant.wheels.tobytes(), plant.tyres.tobytes(), *what)


def straight_running(model: VehicleModel) -> StraightRunning:
    """The model's :class:`StraightRunning`, built once and kept in ``model.cache``.

    Parameters
    ----------
    model : VehicleModel
        The vehicle.

    Returns
    -------
    StraightRunning
        Cached.
    """
    key = cache_key(model)
    if key not in model.cache:
        model.cache[key] = StraightRunning(model)
    return model.cache[key]

