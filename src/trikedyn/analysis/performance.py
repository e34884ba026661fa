"""Straight-line performance: top speed (on the flat or a grade), acceleration 0-30 km/h, braking from 30 km/h.

Everything here is the model's own straight running, quasi-static: the forces the compiled right-hand side
(:func:`trikedyn.model.rhs.evaluate_into`) applies, taken in balance at each speed, with no simulation.

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

Top speed (:func:`top_speed`)
-----------------------------
The speed at which the acceleration at full drive is zero (Brent's method on the quasi-static
acceleration, from a closed-form first guess). ``limit`` names the term that holds the drive torque there:
``"power"``, ``"torque"``, or ``"traction"`` (the weaker driven wheel is at its tyre's peak force, and the
open differential gives the other no more torque: what a traction control would hold; without one the
simulated wheel spins up and the power limit takes its torque). At the top speed the balance reads
``sum tau_i / R_i = F_rolling + F_aero + F_grade`` with ``F_rolling = sum f_r F_z,i R_e,i / R_i``. Three
words say the vehicle has no top speed:

* ``"cannot climb"`` (``"cannot move"`` on the flat or downhill), top speed 0: at :data:`CRAWL_KMH` the full
  drive does not overcome the grade and the rolling resistance. Slower balances are reported so too: below
  a few km/h the model's low-speed regularisation (slip over ``v_low``, rolling resistance smoothed over
  ``w_low``) rules, and the vehicle at best creeps.
* ``"runs away downhill"`` (``"no balance"`` on the flat or uphill), top speed None: no speed up to
  :data:`MAX_SPEED_KMH` balances drive, drag and slope (a vehicle without drag on a slope that pulls
  harder than its rolling resistance).

Downhill the top speed is the finite balance of drive and slope against the drag (reference-etrike: 74.5 km/h
at -5 %, 180.5 km/h at -50 %); ``detail`` says when the slope alone pulls harder than the rolling resistance
(the vehicle would coast downhill). The model has no motor speed limit: the drive gives its full power at
any speed.

Verified (``tests/analysis/test_performance.py``): reference-etrike's top speed is 54.87 km/h, 0.49 % below
the hand power balance ``P = (M g C_rr + rho C_d A v^2 / 2) v`` (55.14 km/h). The difference is the model's
own, not an approximation here: the driven wheels' slip (0.5 %) and the force arm ``R`` against their rolling
radius ``R_e`` (1.0 %) take 1.5 % of the power at the road. Simulated full-drive runs of 150 s
(:func:`trikedyn.simulate.run.simulate`) settle 0.001 % above it (reference-tadpole: 0.003 % below; the
residual is the rigid load transfer and the drag along the slightly pitched chassis axis). The grade is
checked by the closed form only (the simulated road is flat): with the same two losses by hand within 0.3 %.

Acceleration (:func:`acceleration`) and braking (:func:`braking`)
-----------------------------------------------------------------
Integrated over speed, ``t = int dv / a(v)``, ``s = int v dv / a(v)``, with the quasi-static acceleration
at full drive (torque, power and traction limits, the wheels' inertia and load transfer) or with
``max_brake_torque_Nm`` on every braked wheel. A braked wheel rolls while its tyre can carry the brake
torque; when it cannot (the rolling balance has no root short of the tyre's peak force) it locks, and stays
locked (hysteresis), sliding with the force of its own tyre at the slip where ``tau_brake tanh(omega /
w_low)`` balances that force (a spin of about half ``w_low``): the tyre model's value near full lock, as in
the simulation. The pitch and bounce of the suspension, and the slips' relaxation, are left out
(quasi-static). Against open-loop simulations on reference-etrike: acceleration 3 -> 30 km/h 0.02 % in time,
0.03 % in distance (at the default 10 ms step); braking from 30 km/h to :data:`STOP_KMH` 0.3 % in distance
and 0.5 % in time, both rear wheels locked from the start (at a 1 ms step: at the default 10 ms the brake's
``tanh(omega / w_low)``, stiff for a wheel near lock, makes the simulated wheels chatter; the residual is the
suspension's pitch overshoot at the brake's onset). reference-tadpole: 0.13 % and 0.2 % (its front pair
locks); on a PAC2002 ``.tir`` tyre at every wheel 0.13 % and 0.7 %.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ..errors import InputError
from ..model.statics import static_equilibrium
from ..model.vehicle import VehicleModel, build_model
from ..params.io import ParameterSet
from ..params.ops import mass_properties
from ..params.schema import VehicleParameters
from ..tyre.interface import tyre_forces

__all__ = ["CRAWL_KMH", "MAX_GRADE_PERCENT", "MAX_SPEED_KMH", "Acceleration", "Braking", "Performance", "TopSpeed",
           "acceleration", "braking", "performance", "top_speed"]

CRAWL_KMH = 5.0
"""Slowest top speed reported [km/h]: a slower balance (or none) is ``"cannot climb"`` / ``"cannot move"``."""
MAX_SPEED_KMH = 400.0
"""Fastest top speed searched [km/h]; no balance below it is ``"runs away downhill"`` (``"no balance"``)."""
MAX_GRADE_PERCENT = 100.0
"""Steepest grade the functions take, up or down [%] (45 deg)."""
STOP_KMH = 0.5
"""Braking stops here [km/h]: distance and time are to this speed."""

_DRIVING_SLIPS = (1e-5, 1e-4, 3e-4, 1e-3, 3e-3, 0.01, 0.02, 0.035, 0.05, 0.07, 0.1, 0.13, 0.17, 0.22, 0.3, 0.4,
                  0.55, 0.75, 1.0)
"""Slips scanned, from zero outwards, for the root of a wheel's spin balance [1]."""
_LOCKED_SPINS = (0.0, 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0, 8.0, 13.0, 20.0, 35.0, 60.0)
"""Spin rates scanned, in ``w_low``, from a locked wheel upwards for its sliding root [1]."""


def _plain(value):
    """JSON-ready: floats (None when not finite), lists, dicts with string keys."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    return value.item() if isinstance(value, np.generic) else value


# ------------------------------------------------------------------------------------------------------------
# results
# ------------------------------------------------------------------------------------------------------------
class _Result:
    def to_dict(self) -> dict:
        """Plain JSON types (non-finite numbers as None)."""
        return _plain(dict(self.__dict__))


@dataclass(frozen=True)
class TopSpeed(_Result):
    """The highest steady speed at full drive, and what holds it there.

    Attributes
    ----------
    top_speed_kmh : float or None
        [km/h]; 0 when the vehicle cannot climb (or move), None when nothing balances the drive (it runs
        away downhill).
    limit : str
        ``"power"``, ``"torque"``, ``"traction"``, ``"cannot climb"``, ``"cannot move"``,
        ``"runs away downhill"`` or ``"no balance"``.
    grade_percent : float
        Road grade [%], ``tan(theta) = grade / 100``; negative downhill.
    drive_torque_Nm : float
        Total drive torque at the driven wheels [N m] (at the top speed; at :data:`CRAWL_KMH` when it cannot
        move).
    power_W : float
        Drive power at the wheels, torque times the driven wheels' mean spin rate [W].
    drive_force_N : float
        Drive torque over the wheel radius, ``sum tau_i / R_i`` [N].
    rolling_resistance_N : float
        ``sum f_r F_z,i R_e,i / R_i``: the tyres' rolling-resistance moments as a force at the road [N].
    aero_drag_N : float
        ``0.5 rho C_d A v^2`` [N].
    grade_resistance_N : float
        ``M g sin(theta)`` [N], negative downhill.
    wheel_loads_N : dict
        Vertical load per wheel [N].
    slips : dict
        Longitudinal slip per wheel [1].
    detail : str
        The result in words.
    """

    top_speed_kmh: float | None
    limit: str
    grade_percent: float
    drive_torque_Nm: float
    power_W: float
    drive_force_N: float
    rolling_resistance_N: float
    aero_drag_N: float
    grade_resistance_N: float
    wheel_loads_N: dict = field(default_factory=dict)
    slips: dict = field(default_factory=dict)
    detail: str = ""


@dataclass(frozen=True)
class Acceleration(_Result):
    """Acceleration at full drive from one speed to another.

    Attributes
    ----------
    from_kmh, to_kmh : float
        [km/h].
    time_s : float or None
        Time taken [s]; None when the vehicle does not reach ``to_kmh`` (its top speed is lower).
    distance_m : float or None
        Distance covered [m].
    grade_percent : float
        [%].
    power_limited_from_kmh : float or None
        Speed above which the power, not the torque, limits the drive [km/h] (None: not in the range).
    traction_limited : bool
        True when a driven wheel was at its tyre's peak force somewhere in the range.
    detail : str
    """

    from_kmh: float
    to_kmh: float
    time_s: float | None
    distance_m: float | None
    grade_percent: float
    power_limited_from_kmh: float | None
    traction_limited: bool
    detail: str = ""


@dataclass(frozen=True)
class Braking(_Result):
    """Braking with the full brake torque on every braked wheel, from a speed to rest.

    Attributes
    ----------
    from_kmh : float
        [km/h].
    distance_m : float or None
        Distance to slow to :data:`STOP_KMH` [m]; None when the brakes cannot (a steep downhill grade).
    time_s : float or None
        Time to slow to :data:`STOP_KMH` [s].
    mean_deceleration_mps2 : float or None
        ``v0^2 / (2 s)`` [m/s^2].
    grade_percent : float
        [%].
    locked_wheels : dict
        Each wheel that locks, and the speed at which it locks [km/h].
    detail : str
    """

    from_kmh: float
    distance_m: float | None
    time_s: float | None
    mean_deceleration_mps2: float | None
    grade_percent: float
    locked_wheels: dict = field(default_factory=dict)
    detail: str = ""


@dataclass(frozen=True)
class Performance:
    """Top speed, acceleration and braking of one vehicle on one grade (:func:`performance`)."""

    vehicle: str
    mass_kg: float
    grade_percent: float
    top_speed: TopSpeed
    acceleration: Acceleration
    braking: Braking

    def to_dict(self) -> dict:
        """Plain JSON types: the top speed's figures at the top level (``top_speed_kmh``, ``limit``, ...), the
        acceleration and braking as their own objects."""
        return {"vehicle": self.vehicle, "mass_kg": float(self.mass_kg), "grade_percent": float(self.grade_percent),
                **self.top_speed.to_dict(), "acceleration": self.acceleration.to_dict(),
                "braking": self.braking.to_dict()}


# ------------------------------------------------------------------------------------------------------------
# the quasi-static straight-line model
# ------------------------------------------------------------------------------------------------------------
@dataclass
class _Wheel:
    name: str
    model: int
    coeffs: np.ndarray
    radius: float
    kz: float
    inertia: float
    driven: bool
    braked: bool
    static_load: float


@dataclass
class _State:
    """One quasi-static state: acceleration [m/s^2], the drive torque and the per-wheel values."""

    a: float
    torque: float
    limit: str
    fz: np.ndarray
    fx: np.ndarray
    my: np.ndarray
    kappa: np.ndarray
    spin: np.ndarray
    locked: np.ndarray


class _Straight:
    """The model's straight running, per wheel, quasi-static (see the module docstring)."""

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
            self.wheels.append(_Wheel(w.name, int(rec["tyre_model"]), np.ascontiguousarray(model.plant.tyres[k]),
                                      float(rec["radius"]), float(rec["vertical_stiffness"]),
                                      float(spec.spin_inertia_kgm2), bool(rec["driven"]), bool(rec["braked"]),
                                      float(eq.wheel_loads_N[w.name])))
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

    # -- one wheel ------------------------------------------------------------------------------------------
    def _wheel(self, w: _Wheel, kappa, v, v_ref, fz, a, tau_drive, tau_brake):
        """Residual of the spin balance ``I omega' - (...)`` with its sign flipped, and the tyre's values."""
        r_eff = w.radius - fz / w.kz / 3.0
        spin = (v + kappa * v_ref) / r_eff
        if fz > 0.0:
            fx, _, _, _, my, _ = tyre_forces(w.model, w.coeffs, kappa, 0.0, 0.0, fz, v, v_ref, spin, r_eff,
                                             self.v_low, self.w_low)
        else:
            fx, my = 0.0, 0.0
        spin_rate = a * (1.0 + kappa * (v / v_ref) ** 3) / r_eff
        g = tau_drive - tau_brake * math.tanh(spin / self.w_low) - fx * w.radius + my - w.inertia * spin_rate
        return g, fx, my, spin

    def _root(self, w, lo, hi, args):
        return brentq(lambda k: self._wheel(w, k, *args)[0], lo, hi, xtol=1e-13, rtol=1e-12)

    def _solve_wheel(self, w, v, v_ref, fz, a, tau_drive, tau_brake, locked, guess):
        """The wheel's slip: the root of its spin balance it reaches from rolling (or, locked, from lock).

        Returns the slip and whether the wheel is locked; None when no root exists (a driven wheel whose
        tyre cannot carry the torque).
        """
        args = (v, v_ref, fz, a, tau_drive, tau_brake)
        lock = -v / v_ref  # slip of a wheel that does not turn
        if locked:
            prev, g_prev = lock, self._wheel(w, lock, *args)[0]
            for s in _LOCKED_SPINS[1:]:
                k = lock + s * self.w_low * (w.radius - fz / w.kz / 3.0) / v_ref
                if k >= 0.0:
                    k = 0.0
                g = self._wheel(w, k, *args)[0]
                if g_prev > 0.0 >= g:
                    return self._root(w, prev, k, args), True
                if k == 0.0:
                    break
                prev, g_prev = k, g
            locked = False  # no sliding root: the wheel rolls again
        # warm start: secant steps from the previous slip, kept when they settle on a stable root nearby
        if guess is not None and guess != 0.0:
            found = self._secant(w, guess, args)
            if found is not None:
                return found, False
        g0 = self._wheel(w, 0.0, *args)[0]
        if g0 == 0.0:
            return 0.0, False
        sign = 1.0 if g0 > 0.0 else -1.0  # the slip moves toward the side the balance pushes it
        prev = 0.0
        for s in _DRIVING_SLIPS:
            k = sign * s
            if sign < 0.0 and tau_brake > 0.0 and k <= lock:  # a braked wheel stops turning, it does not reverse
                k = lock
            g = self._wheel(w, k, *args)[0]
            if g * g0 <= 0.0:
                root = self._root(w, min(prev, k), max(prev, k), args)
                return root, self._beyond_peak(w, root, args)
            if k == lock:
                break
            prev = k
        return None, False

    def _secant(self, w, guess, args):
        """The root of the spin balance near ``guess`` by secant steps, or None (not settled, too far, or an
        unstable root: the balance must fall with the slip there)."""
        k0, k1 = guess, guess * (1.0 + 1e-4)
        g0, g1 = self._wheel(w, k0, *args)[0], self._wheel(w, k1, *args)[0]
        reach = 0.2 * abs(guess) + 1e-6
        for _ in range(10):
            if g1 == g0:
                return None
            slope = (g1 - g0) / (k1 - k0)
            if not slope < 0.0:
                return None
            k2 = k1 - g1 / slope
            if abs(k2 - guess) > reach or k2 * guess <= 0.0:
                return None
            if abs(k2 - k1) <= 1e-13 + 1e-10 * abs(k2):
                return k2
            k0, g0, k1, g1 = k1, g1, k2, self._wheel(w, k2, *args)[0]
        return None

    def _beyond_peak(self, w, kappa, args):
        """True when the tyre's force falls with more slip at ``kappa`` (the wheel slides: locked)."""
        if kappa >= 0.0:
            return False
        d = max(1e-7, 1e-4 * abs(kappa))
        return abs(self._wheel(w, kappa - d, *args)[1]) < abs(self._wheel(w, kappa, *args)[1])

    def _capacity(self, w, v, v_ref, fz, a):
        """Largest torque a driven wheel's tyre carries in rolling, and the slip there."""
        def carried(k):
            """Drive torque [N m] the wheel carries in rolling at slip ``k``: ``F_x R - M_y + I omega'``."""
            return -self._wheel(w, k, v, v_ref, fz, a, 0.0, 0.0)[0]

        values = [carried(s) for s in _DRIVING_SLIPS]
        i = int(np.argmax(values))
        lo = _DRIVING_SLIPS[max(i - 1, 0)]
        hi = _DRIVING_SLIPS[min(i + 1, len(_DRIVING_SLIPS) - 1)]
        best = minimize_scalar(lambda k: -carried(k), bounds=(lo, hi), method="bounded", options={"xatol": 1e-9})
        k = float(best.x) if -best.fun > values[i] else _DRIVING_SLIPS[i]
        return max(-best.fun, values[i]), k

    # -- the vehicle --------------------------------------------------------------------------------------
    def state(self, v, drive, brake, sin_t, cos_t, locked=None, start=None) -> _State:
        """The quasi-static state at speed ``v`` [m/s] under a drive command [N m] and a brake torque per
        braked wheel [N m], on a grade ``(sin, cos)``; ``locked`` per wheel (kept from a previous state),
        ``start`` a nearby state to start the iteration from."""
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
                root, lock = self._solve_wheel(w, v, v_ref, fz[k], a, tau_d, tau_b, locked[k], kappa[k])
                if root is None:  # a driven wheel's tyre cannot carry the torque
                    if not tau_d > 0.0:
                        raise RuntimeError(f"no rolling balance for the {w.name} wheel at {v:g} m/s")  # a bug
                    most, at = self._capacity(w, v, v_ref, fz[k], a)
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
                        root, _ = self._solve_wheel(w, v, v_ref, fz[k], a, torque / self.n_driven, 0.0, False,
                                                    kappa[k])
                        if root is not None:
                            new_kappa[k] = root
            for k, w in enumerate(self.wheels):
                tau_d = torque / self.n_driven if w.driven else 0.0
                tau_b = brake if w.braked else 0.0
                _, fx[k], my[k], spin[k] = self._wheel(w, new_kappa[k], v, v_ref, fz[k], a, tau_d, tau_b)
            a_new = (fx.sum() - aero - self.mass * self.g * sin_t) / self.mass
            done = abs(a_new - a) < 1e-9 * (1.0 + abs(a_new)) and np.allclose(new_kappa, kappa, rtol=1e-8,
                                                                           atol=1e-11)
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
        return _State(a, torque, limit, fz, fx.copy(), my.copy(), kappa, spin.copy(), locked)


def _model(vehicle) -> VehicleModel:
    if isinstance(vehicle, VehicleModel):
        return vehicle.on_flat_road()
    if isinstance(vehicle, ParameterSet | VehicleParameters):
        return build_model(vehicle)
    raise InputError(f"expected a ParameterSet, VehicleParameters or VehicleModel, got {type(vehicle).__name__}",
                     where="vehicle")


def _key(model: VehicleModel, *what) -> tuple:
    """A cache key of this module's results: they depend on the drive's limits, which variants of a model
    that share its cache (``with_ideal_drive``) change, so the packed records are part of the key."""
    plant = model.plant
    return ("performance", plant.vehicle.tobytes(), plant.wheels.tobytes(), plant.tyres.tobytes(), *what)


def _straight(model: VehicleModel) -> _Straight:
    key = _key(model)
    if key not in model.cache:
        model.cache[key] = _Straight(model)
    return model.cache[key]


def _grade(grade_percent: float) -> tuple[float, float]:
    grade = float(grade_percent)
    if not (math.isfinite(grade) and abs(grade) <= MAX_GRADE_PERCENT):
        raise InputError(f"must be within -{MAX_GRADE_PERCENT:g} .. {MAX_GRADE_PERCENT:g} %, got {grade_percent!r}",
                         where="grade_percent")
    theta = math.atan(grade / 100.0)
    return math.sin(theta), math.cos(theta)


def _speed(value: float, where: str, low: float = 0.0) -> float:
    speed = float(value)
    if not (math.isfinite(speed) and low <= speed <= MAX_SPEED_KMH):
        raise InputError(f"must be within {low:g} .. {MAX_SPEED_KMH:g} km/h, got {value!r}", where=where)
    return speed


def _where(grade: float) -> str:
    return "on the flat" if grade == 0.0 else f"{'up' if grade > 0 else 'down'} a {abs(grade):g} % grade"


# ------------------------------------------------------------------------------------------------------------
# top speed
# ------------------------------------------------------------------------------------------------------------
def _closed_form_speed(straight: _Straight, crawling: _State, sin_t: float, fastest: float) -> float:
    """Top speed [m/s] of ``min(T_max, P / omega) / R = F_rolling + M g sin + k v^2`` with the rolling
    resistance at crawling speed, no slip and ``omega = v / R``: the search's first guess."""
    radius = float(np.mean(straight.radius[straight.driven])) if straight.driven.any() else float(
        np.mean(straight.radius))
    resist = float(np.sum(-crawling.my / straight.radius)) + straight.mass * straight.g * sin_t

    def net(v):
        """Drive less resistance [N] at ``v`` [m/s]."""
        return min(straight.max_torque / radius, straight.max_power / v) - resist - straight.drag * v * v

    if net(fastest) > 0.0:
        return fastest
    low = 1e-3
    return brentq(net, low, fastest) if net(low) > 0.0 else low


def _top_speed(straight: _Straight, grade: float) -> TopSpeed:
    sin_t, cos_t = _grade(grade)
    full, fastest = straight.max_torque, MAX_SPEED_KMH / 3.6
    states = {}  # speed [m/s] -> quasi-static state at full drive

    def accel(v):
        """Acceleration [m/s^2] at full drive at ``v`` [m/s], from the nearest state found so far."""
        if v not in states:
            near = min(states, key=lambda u: abs(u - v)) if states else None
            states[v] = straight.state(v, full, 0.0, sin_t, cos_t, start=None if near is None else states[near])
        return states[v].a

    crawl = CRAWL_KMH / 3.6
    v_top, limit = None, ""
    if accel(crawl) <= 0.0:
        v_top, limit = 0.0, "cannot climb" if grade > 0 else "cannot move"
        at = crawl
    else:
        # a first guess from the closed form with the rolling resistance at crawling speed, then a bracket
        guess = _closed_form_speed(straight, states[crawl], sin_t, fastest)
        lo, hi = max(crawl, 0.99 * guess), min(fastest, 1.01 * guess)
        while accel(lo) <= 0.0 and lo > crawl:
            lo, hi = max(crawl, lo - 2.0 * (hi - lo)), lo
        while accel(hi) > 0.0 and hi < fastest:
            lo, hi = hi, min(fastest, hi + 2.0 * (hi - lo))
        if accel(hi) > 0.0:
            limit = "runs away downhill" if grade < 0.0 else "no balance"
            at = hi
        else:
            v_top = brentq(accel, lo, hi, xtol=1e-8, rtol=1e-11)
            at = v_top
    accel(at)
    s, radii = states[at], straight.radius
    shares = np.where(straight.driven, s.torque / straight.n_driven, 0.0)
    mean_spin = float(np.abs(s.spin[straight.driven]).mean()) if straight.driven.any() else 0.0
    power = s.torque * mean_spin
    rolling = float(np.sum(-s.my / radii))
    aero = straight.drag * at * at
    slope = straight.mass * straight.g * sin_t
    if limit == "":
        limit = s.limit
    names = [w.name for w in straight.wheels]
    where = _where(grade)
    pull = f"{-slope:.0f} N downhill pull"
    if v_top is None:
        detail = (f"{limit} {where}: no speed up to {MAX_SPEED_KMH:g} km/h balances the drive"
                  + (f" and the {pull}" if slope < 0.0 else "") + f" against {rolling:.0f} N rolling resistance and "
                  f"the drag")
    elif v_top == 0.0:
        against = f"{rolling:.0f} N rolling" + (f" + {slope:.0f} N grade" if slope > 0.0 else "")
        detail = (f"{limit} {where}: at {CRAWL_KMH:g} km/h the full drive ({s.torque:.0f} N m, {_limit_word(s.limit)})"
                  f" gives {float(np.sum(shares / radii)):.0f} N against {against}")
    else:
        against = f"{rolling:.0f} N rolling + {aero:.0f} N aero" + (f" + {slope:.0f} N grade" if slope > 0.0 else "")
        detail = f"{limit}-limited: {power / 1000:.1f} kW at the wheels against {against}"
        if slope < 0.0:
            detail += f", with {pull}"
    if slope < 0.0 and -slope > rolling:
        detail += "; the slope alone pulls harder than the rolling resistance: it would coast downhill"
    return TopSpeed(
        top_speed_kmh=None if v_top is None else float(v_top * 3.6),
        limit=limit,
        grade_percent=float(grade),
        drive_torque_Nm=float(s.torque),
        power_W=float(power),
        drive_force_N=float(np.sum(shares / radii)),
        rolling_resistance_N=rolling,
        aero_drag_N=float(aero),
        grade_resistance_N=float(slope),
        wheel_loads_N={n: float(f) for n, f in zip(names, s.fz, strict=True)},
        slips={n: float(k) for n, k in zip(names, s.kappa, strict=True)},
        detail=detail,
    )


def _limit_word(limit: str) -> str:
    """The limit as an adjective: ``"power"`` -> ``"power-limited"``; other words unchanged."""
    return f"{limit}-limited" if limit in ("power", "torque", "traction") else limit


def top_speed(vehicle, grade_percent: float = 0.0) -> TopSpeed:
    """The vehicle's top speed at full drive on the flat or on a grade, and what limits it.

    Quasi-static, no simulation: about 5 ms for a parameter set (the model built and its static equilibrium
    solved), 3 ms for a :class:`~trikedyn.model.vehicle.VehicleModel` whose equilibrium is known (kept in
    ``model.cache``, with this function's setup and results); the first call in a process also loads the
    compiled tyre function and right-hand side from numba's cache (about 0.3 s). See the module docstring for
    the model and its verification (a simulated full-drive run settles within 0.001 % of it).

    Parameters
    ----------
    vehicle : ParameterSet, VehicleParameters or VehicleModel
        The vehicle with its payload (:func:`trikedyn.params.with_freight`).
    grade_percent : float
        Road grade [%], ``tan(theta) = grade / 100``, within +-:data:`MAX_GRADE_PERCENT`; negative downhill.

    Returns
    -------
    TopSpeed
        ``top_speed_kmh`` [km/h] and ``limit`` (``"power"``, ``"torque"``, ``"traction"``; ``"cannot climb"``
        / ``"cannot move"`` with 0 km/h; ``"runs away downhill"`` / ``"no balance"`` with None), the
        resistances at that speed [N] and the drive power [W].

    Raises
    ------
    InputError
        For a grade out of range or not a number.
    """
    _grade(grade_percent)
    model = _model(vehicle)
    key = _key(model, "top_speed", float(grade_percent))
    if key not in model.cache:
        model.cache[key] = _top_speed(_straight(model), float(grade_percent))
    return model.cache[key]


# ------------------------------------------------------------------------------------------------------------
# acceleration and braking
# ------------------------------------------------------------------------------------------------------------
def _integrate(speeds, accels):
    """Time [s] and distance [m] over a speed grid with the accelerations there (trapezoidal rule)."""
    speeds, accels = np.asarray(speeds), np.asarray(accels)
    dv = np.diff(speeds)
    inv = 1.0 / accels
    time = float(np.sum(0.5 * (inv[1:] + inv[:-1]) * dv))
    distance = float(np.sum(0.5 * (speeds[1:] * inv[1:] + speeds[:-1] * inv[:-1]) * dv))
    return time, distance


def acceleration(vehicle, to_kmh: float = 30.0, *, from_kmh: float = 0.0, grade_percent: float = 0.0,
                 points: int = 160) -> Acceleration:
    """Time and distance to accelerate at full drive from ``from_kmh`` to ``to_kmh``.

    ``t = int dv / a(v)``, ``s = int v dv / a(v)`` over ``points`` speeds (denser at the start), with the
    quasi-static acceleration at full drive: torque, power and traction limits, resistances, the wheels'
    spin inertia and the load transfer (module docstring). Against an open-loop simulation at full drive from
    3 km/h (``tests/analysis/test_performance.py``): 0.02 % in time, 0.03 % in distance.

    Parameters
    ----------
    vehicle : ParameterSet, VehicleParameters or VehicleModel
    to_kmh, from_kmh : float
        End and start speeds [km/h], ``0 <= from_kmh < to_kmh``.
    grade_percent : float
        Road grade [%].
    points : int
        Speeds of the quadrature.

    Returns
    -------
    Acceleration
        ``time_s`` [s] and ``distance_m`` [m] (None when the top speed is below ``to_kmh``).
    """
    to_kmh, from_kmh = _speed(to_kmh, "to_kmh"), _speed(from_kmh, "from_kmh")
    if not from_kmh < to_kmh:
        raise InputError(f"must be below to_kmh ({to_kmh:g} km/h), got {from_kmh:g}", where="from_kmh")
    sin_t, cos_t = _grade(grade_percent)
    model = _model(vehicle)
    straight = _straight(model)
    v0, v1 = from_kmh / 3.6, to_kmh / 3.6
    top = top_speed(model, grade_percent)
    if top.top_speed_kmh is not None and top.top_speed_kmh <= to_kmh:
        why = (f"{top.limit} {_where(grade_percent)}" if top.top_speed_kmh == 0.0 else
               f"does not reach {to_kmh:g} km/h {_where(grade_percent)}: top speed {top.top_speed_kmh:.1f} km/h "
               f"({top.limit})")
        return Acceleration(from_kmh, to_kmh, None, None, float(grade_percent), None, False, why)
    # denser at the start, where the regularisation and the slip change fastest
    u = np.linspace(0.0, 1.0, int(points))
    speeds = v0 + (v1 - v0) * u**1.5
    accels, corner, traction, state, before = [], None, False, None, None
    for v in speeds:
        state = straight.state(v, straight.max_torque, 0.0, sin_t, cos_t, start=state)
        accels.append(state.a)
        if state.limit == "power" and corner is None:
            corner = v * 3.6 if before is None else _switch(straight, before, v, sin_t, cos_t) * 3.6
        traction |= state.limit == "traction"
        before = v
    time, distance = _integrate(speeds, accels)
    detail = (f"{from_kmh:g} -> {to_kmh:g} km/h {_where(grade_percent)} in {time:.2f} s over {distance:.1f} m"
              + (f"; power-limited from {corner:.1f} km/h" if corner is not None else "; torque-limited throughout")
              + ("; a driven wheel at its grip limit" if traction else ""))
    return Acceleration(from_kmh, to_kmh, time, distance, float(grade_percent),
                        None if corner is None else float(corner), bool(traction), detail)


def _switch(straight: _Straight, below: float, above: float, sin_t: float, cos_t: float) -> float:
    """The speed [m/s] between ``below`` (torque-limited) and ``above`` (power-limited) where the power
    takes over, to 1 mm/s."""
    while above - below > 1e-3:
        middle = 0.5 * (below + above)
        if straight.state(middle, straight.max_torque, 0.0, sin_t, cos_t).limit == "power":
            above = middle
        else:
            below = middle
    return 0.5 * (below + above)


def braking(vehicle, from_kmh: float = 30.0, *, grade_percent: float = 0.0, points: int = 200) -> Braking:
    """Distance and time to stop from ``from_kmh`` with the full brake torque on every braked wheel.

    Quasi-static over speed, ``s = int v dv / |a(v)|`` on ``points`` speeds (geometric, from ``from_kmh``
    down to :data:`STOP_KMH`; the rest of the way, a few millimetres, is left out): each braked wheel takes
    ``max_brake_torque_Nm``; its force is limited by its tyre's grip at its load (with the load transfer); a
    wheel whose tyre cannot carry the brake torque locks and slides with its tyre's force near full lock,
    and stays locked (module docstring). Against open-loop simulations from 30 km/h (at a 1 ms step: the
    default 10 ms step is too long for a wheel near lock): 0.3 % in distance, 0.5 % in time
    (``tests/analysis/test_performance.py``).

    Parameters
    ----------
    vehicle : ParameterSet, VehicleParameters or VehicleModel
    from_kmh : float
        Initial speed [km/h], above :data:`STOP_KMH`.
    grade_percent : float
        Road grade [%]; downhill lengthens the distance.
    points : int
        Speeds of the quadrature.

    Returns
    -------
    Braking
        ``distance_m`` [m] and ``time_s`` [s] to :data:`STOP_KMH` (None when the brakes cannot slow the
        vehicle to it: a steep downhill grade; the model's brakes fade below a wheel spin of ``w_low``, so on
        a slope the vehicle creeps on below that), the mean deceleration and the wheels that lock, with the
        speed at which they lock.
    """
    from_kmh = _speed(from_kmh, "from_kmh")
    if from_kmh <= STOP_KMH:
        raise InputError(f"must be > {STOP_KMH:g} km/h, got {from_kmh:g}", where="from_kmh")
    sin_t, cos_t = _grade(grade_percent)
    model = _model(vehicle)
    straight = _straight(model)
    v0 = from_kmh / 3.6
    speeds = np.geomspace(v0, STOP_KMH / 3.6, int(points))
    names = [w.name for w in straight.wheels]
    accels, locked, locked_at, state = [], None, {}, None
    for i, v in enumerate(speeds):
        state = straight.state(v, 0.0, straight.max_brake, sin_t, cos_t, locked=locked, start=state)
        locked = state.locked
        for k, name in enumerate(names):
            if locked[k] and name not in locked_at:
                locked_at[name] = from_kmh if i == 0 else float(v * 3.6)
        if state.a >= 0.0:
            if v * 3.6 < CRAWL_KMH:
                why = (f"the brakes hold the vehicle to a creep of {v * 3.6:.1f} km/h {_where(grade_percent)}, not "
                       f"to a stop (the model's brakes fade below a wheel spin of w_low = {straight.w_low:g} rad/s)")
            else:
                why = f"the brakes do not slow the vehicle below {v * 3.6:.1f} km/h {_where(grade_percent)}"
            return Braking(from_kmh, None, None, None, float(grade_percent), locked_at, why)
        accels.append(state.a)
    accels = np.array(accels)
    time, distance = _integrate(speeds[::-1], -accels[::-1])
    mean = v0**2 / (2.0 * distance)
    which = ", ".join(f"{n} at {s:.1f} km/h" for n, s in locked_at.items()) or "none"
    detail = (f"from {from_kmh:g} km/h {_where(grade_percent)}: {distance:.2f} m and {time:.2f} s to {STOP_KMH:g} km/h, "
              f"mean {mean:.2f} m/s^2; locked wheels: {which}")
    return Braking(from_kmh, distance, time, float(mean), float(grade_percent), locked_at, detail)


def performance(vehicle, grade_percent: float = 0.0, *, accelerate_to_kmh: float = 30.0,
                brake_from_kmh: float = 30.0) -> Performance:
    """Top speed, acceleration from rest to ``accelerate_to_kmh`` and braking from ``brake_from_kmh``.

    Parameters
    ----------
    vehicle : ParameterSet, VehicleParameters or VehicleModel
    grade_percent : float
        Road grade [%] for all three.
    accelerate_to_kmh, brake_from_kmh : float
        [km/h].

    Returns
    -------
    Performance
    """
    _grade(grade_percent)
    model = _model(vehicle)
    return Performance(
        vehicle=model.params.name,
        mass_kg=float(model.tree.total_mass()),
        grade_percent=float(grade_percent),
        top_speed=top_speed(model, grade_percent),
        acceleration=acceleration(model, accelerate_to_kmh, grade_percent=grade_percent),
        braking=braking(model, brake_from_kmh, grade_percent=grade_percent),
    )
