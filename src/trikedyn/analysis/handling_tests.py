"""The handling tests engineers run first, on the model: drive the registered manoeuvre, then reduce it.

- :func:`steady_state_test`: ISO 4138 constant radius, slowly rising speed -> handling diagram, understeer,
  roll and sideslip gradients [deg/g], the understeer gradient by band of lateral acceleration, the
  neutral-steer lateral acceleration and the limit behaviour, the lateral acceleration at the end and why
  the test ended;
- :func:`step_steer_test`: ISO 7401 step steer, speed held -> yaw-rate and lateral-acceleration gains,
  response times, overshoot;
- :func:`frequency_response_test`: ISO 7401 sine sweep -> yaw-rate and lateral-acceleration gain and phase;
- :func:`braking_in_turn_test`: ISO 7975 -> path deviation, yaw-rate change, wheel loads.

The reductions are the pure functions of :mod:`trikedyn.analysis.handling`, :mod:`~trikedyn.analysis.steady_state`
and :mod:`~trikedyn.analysis.steer_shape`; the road-wheel steer angle is
the steer about the raked axis times ``cos(rake)``; sideslip is that of the CG, ``atan(v_y / v_x)``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..model.vehicle import VehicleModel, build_model
from ..registry import Registry
from ..simulate.closed_loop import run
from . import handling, metrics, steady_state

__all__ = ["REDUCERS", "Figures", "SteadyStateTest", "braking_in_turn_test", "frequency_response_test", "manoeuvre_figures",
           "reduces", "steady_state_test", "step_steer_test"]

LOST_PATH_M = 1.0
"""Path error of the CG beyond which the driver is taken to have lost the circle [m]."""


def _model(vehicle) -> VehicleModel:
    return vehicle if isinstance(vehicle, VehicleModel) else build_model(vehicle)


def road_steer(result, params) -> np.ndarray:
    """Road-wheel steer angle [rad]: the steer joint angle times the cosine of the steering axis angle."""
    return np.asarray(result["steer_rad"]) * math.cos(math.radians(params.steering.axis_angle_deg))


def sideslip(result) -> np.ndarray:
    """Sideslip angle of the CG [rad]."""
    return np.arctan2(result["vy_mps"], np.maximum(np.abs(result["vx_mps"]), 1e-6))


def steer_at_nominal_radius(result, params, radius_m: float) -> np.ndarray:
    """Road-wheel steer [rad] corrected for the driver's small departures from the nominal radius.

    The driver holds the circle only to a few centimetres, and the radius it actually drives drifts as the
    speed rises; the kinematic steer ``L_e / R`` drifts with it and would bias the gradient (by about
    0.1 deg/g on reference-etrike). The measured path curvature ``r / v`` replaces ``1 / R``:
    ``delta_c = delta - L (r / v - 1 / R)`` (``L`` the wheelbase: the front contact lies below the wheel
    centre, the trail behind the steering axis' ground point). At constant radius this is the steer itself.
    """
    speed = np.maximum(np.asarray(result["speed_mps"]), 0.1)
    curvature = np.asarray(result["yaw_rate_radps"]) / speed
    sign = 1.0 if result.manoeuvre is None or result.manoeuvre.parameters.get("direction", "left") == "left" else -1.0
    return road_steer(result, params) - params.wheelbase_m * (curvature - sign / radius_m)


@dataclass(frozen=True)
class SteadyStateTest:
    """ISO 4138 on the model: the diagram (with its shape: gradient by band, neutral steer, limit behaviour),
    the end of the test (``limit``, ``limit_detail``, the largest lateral acceleration [m/s^2]) and the run."""

    diagram: steady_state.HandlingDiagram
    radius_m: float
    limit: str
    limit_detail: str
    max_lateral_acceleration_mps2: float
    result: object = field(repr=False, default=None)

    def to_dict(self) -> dict:
        """JSON-safe figures: the linear-range gradients [deg/g] (``understeer_gradient_deg_per_g`` is the
        fit over ``fit_start_mps2``-``fit_limit_mps2``), the shape (``steer_bands``, the neutral-steer
        lateral acceleration, ``limit_behaviour``: see :class:`~trikedyn.analysis.steer_shape.SteerShape`),
        the end of the test (``limit``, ``limit_detail``) and the binned ``diagram``.

        Returns
        -------
        dict
            The figures, JSON-safe.
        """
        d = self.diagram.to_dict()
        keys = ("understeer_gradient_deg_per_g", "roll_gradient_deg_per_g", "sideslip_gradient_deg_per_g",
                "ackermann_steer_deg", "steer_intercept_deg", "fit_start_mps2", "fit_limit_mps2")
        shape = {k: v for k, v in d["shape"].items() if k not in ("bands", "curve_ay_mps2", "curve_steer_deg")}
        return {**{k: d[k] for k in keys}, "steer_bands": d["shape"]["bands"], **shape, "radius_m": self.radius_m,
                "max_lateral_acceleration_mps2": self.max_lateral_acceleration_mps2,
                "limit": self.limit, "limit_detail": self.limit_detail,
                "diagram": {k: d[k] for k in ("ay_bins_mps2", "steer_deg", "sideslip_deg", "roll_deg")}}

    def describe(self, name: str = "") -> str:
        """In words, a line a figure: the linear-range understeer gradient and its range, the gradient by band,
        the neutral-steer lateral acceleration, the limit behaviour, the roll and sideslip gradients, and the
        end of the test; ``name`` (the vehicle's) heads it.

        Parameters
        ----------
        name : str
            The vehicle's name for the heading (none when empty).

        Returns
        -------
        str
            The lines, joined.
        """
        d, shape = self.diagram, self.diagram.shape
        lines = [f"{name + ': ' if name else ''}ISO 4138 constant radius {self.radius_m:g} m",
                 f"understeer gradient   {d.understeer_gradient_deg_per_g:+.3f} deg/g (linear range: fitted over "
                 f"{d.fit_start_mps2:.2f}-{d.fit_limit_mps2:.2f} m/s^2)",
                 f"  by band of a_y      (bands {shape.band_width_mps2:g} m/s^2 wide; neutral within "
                 f"+-{shape.neutral_tolerance_deg_per_g:g} deg/g)"]
        lines += [f"    {b.low_mps2:5.2f}-{b.high_mps2:5.2f} m/s^2  {b.gradient_deg_per_g:+7.3f} deg/g  {b.behaviour}"
                  for b in shape.bands]
        if shape.neutral_steer == "peak":
            neutral = (f"{shape.neutral_steer_lateral_acceleration_mps2:.2f} m/s^2 (the steer curve's peak, "
                       f"{shape.neutral_steer_deg:.3f} deg; oversteer beyond)")
        elif shape.neutral_steer == "falls from the start":
            neutral = f"none: the steer falls from the start of the test ({shape.bands[0].low_mps2:.2f} m/s^2)"
        else:
            neutral = f"not reached: no peak of the steer up to {d.max_lateral_acceleration_mps2:.2f} m/s^2"
        lines += [f"neutral steer at a_y  {neutral}",
                  f"limit behaviour       {shape.limit_behaviour} ({shape.limit_gradient_deg_per_g:+.3f} deg/g over "
                  f"the last {shape.limit_high_mps2 - shape.limit_low_mps2:.2f} m/s^2: {shape.limit_low_mps2:.2f}-"
                  f"{shape.limit_high_mps2:.2f} m/s^2)",
                  f"roll gradient         {d.roll_gradient_deg_per_g:+.3f} deg/g (linear range)",
                  f"sideslip gradient     {d.sideslip_gradient_deg_per_g:+.3f} deg/g (linear range)",
                  f"ends at a_y           {self.max_lateral_acceleration_mps2:.2f} m/s^2: {self.limit} "
                  f"({self.limit_detail})"]
        return "\n".join(lines)

    def plot(self):
        """The handling diagram (steer, sideslip, roll against lateral acceleration): the linear range, the
        gradient by band, the neutral-steer point and the limit behaviour marked, and the end of the test.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        fig = self.diagram.plot()
        for ax in fig.axes:
            ax.axvline(self.max_lateral_acceleration_mps2, color="0.4", lw=0.8, ls=":")
        fig.suptitle(f"ISO 4138 handling diagram, R = {self.radius_m:g} m; ends at "
                     f"{self.max_lateral_acceleration_mps2:.2f} m/s² ({self.limit})\nlimit behaviour: "
                     f"{self.diagram.shape.limit_behaviour}", fontsize=10)
        fig.tight_layout(rect=(0, 0, 1, 0.95))
        return fig


def _why_it_ended(result, params, ay_target_end: float) -> tuple[str, str, int]:
    """The limit of a steady-state run and the index of its last valid sample."""
    judged = metrics.judged_mask(result)
    idx = np.nonzero(judged)[0]
    end = int(idx[-1]) if idx.size else result.time_s.size - 1
    candidates = []
    lift = metrics.first_lift(result)
    if lift is not None:
        candidates.append((lift.time_s, "lift-off", f"{lift.wheel} lifted at {lift.time_s:.2f} s"))
    if "path_error_m" in result.channels:
        lost = np.nonzero((np.abs(result["path_error_m"]) > LOST_PATH_M) & judged)[0]
        if lost.size:
            t = float(result.time_s[lost[0]])
            candidates.append((t, "driver limit", f"the circle was lost (path error > {LOST_PATH_M:g} m) at {t:.2f} s"))
    lock = math.radians(params.steering.max_angle_deg)
    locked = np.nonzero((np.abs(result["steer_cmd_rad"]) >= 0.999 * lock) & judged)[0]
    if locked.size:
        t = float(result.time_s[locked[0]])
        candidates.append((t, "steering lock", f"the steer reached its lock at {t:.2f} s"))
    if not result.success:
        t = float(result.time_s[-1])
        candidates.append((t, "lift-off" if lift else "driver limit", result.message))
    if candidates:
        t, limit, detail = min(candidates)
        end = min(end, int(np.searchsorted(result.time_s, t)) - 1)
        return limit, detail, max(end, 0)
    speed = np.asarray(result["speed_mps"])
    target = result.manoeuvre.speed.at(result.time_s)
    if speed[end] < target[end] - 0.5:
        return "speed not reached", (f"the speed fell {3.6 * (target[end] - speed[end]):.1f} km/h short of the "
                                     "target (drive torque or power)"), end
    return "end of test", f"the target lateral acceleration {ay_target_end:g} m/s^2 was reached", end


def steady_state_test(vehicle, *, radius_m: float = 20.0, start_speed_kmh: float = 15.0,
                      ay_rate_mps2_per_s: float = 0.1, max_ay_mps2: float = 9.0, direction: str = "left",
                      fit_limit_mps2: float | None = None, dt: float | None = None) -> SteadyStateTest:
    """ISO 4138 steady-state circular driving at constant radius, the speed raised slowly.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleModel
        The vehicle with its payload.
    radius_m : float
        Circle radius [m].
    start_speed_kmh : float
        Speed at the start [km/h]. Below about 12 km/h the low-speed terms of the tyre model (slip
        regularisation, rolling resistance) bend the diagram; 15 km/h on a 20 m circle starts at 0.09 g.
    ay_rate_mps2_per_s : float
        Rise of ``v^2 / R`` per second [m/s^2/s]: slow enough to be quasi-steady.
    max_ay_mps2 : float
        Where the rise stops [m/s^2] (a wheel lift, the driver or the drive normally ends it first).
    fit_limit_mps2 : float, optional
        Upper end of the linear-range fit [m/s^2] (see :func:`~trikedyn.analysis.steady_state.handling_diagram`).
    direction : {"left", "right"}
        Turn direction.
    dt : float, optional
        Time step [s]; automatic by default.

    Returns
    -------
    SteadyStateTest
        ``limit`` is ``"lift-off"``, ``"driver limit"`` (the circle was lost), ``"steering lock"``, ``"speed
        not reached"`` (drive torque or power) or ``"end of test"``.
    """
    result = run(_model(vehicle), "steady-state-circle", speed_kmh=start_speed_kmh, dt=dt, radius_m=radius_m,
                 ay_rate_mps2_per_s=ay_rate_mps2_per_s, max_ay_mps2=max_ay_mps2, direction=direction)
    return reduce_steady_state(result, fit_limit_mps2=fit_limit_mps2)


REDUCERS: Registry[Callable] = Registry("handling reducer", group="trikedyn.handling_reducers", where="manoeuvre")
"""Manoeuvre name -> ``fn(result)`` giving the test's own figures (plug-ins: ``trikedyn.handling_reducers``)."""


def reduces(name: str, *, replace: bool = False):
    """Decorator: ``fn(result) -> object with to_dict()`` gives the figures of manoeuvre ``name`` (a manoeuvre
    with a reducer already raises ValueError unless ``replace=True``).

    Parameters
    ----------
    name : str
        The manoeuvre's registered name.
    replace : bool
        Replace an existing reducer.

    Returns
    -------
    callable
        The decorator.
    """

    def decorate(fn):
        """Register ``fn`` as the reducer of ``name``; returns it unchanged."""
        REDUCERS.register(name, fn, replace=replace)
        return fn

    return decorate


def manoeuvre_figures(result) -> dict | None:
    """The test's own figures for a run of a manoeuvre that has them (JSON-safe), else None.

    Parameters
    ----------
    result : Result
        A run.

    Returns
    -------
    dict or None
        The reducer's figures, JSON-safe.
    """
    man = result.manoeuvre
    if man is None or man.name not in REDUCERS or not metrics.judged_mask(result).any():
        return None
    return REDUCERS.get(man.name)(result).to_dict()


@reduces("steady-state-circle")
def reduce_steady_state(result, *, fit_limit_mps2: float | None = None) -> SteadyStateTest:
    """ISO 4138 figures of a ``steady-state-circle`` run (see :func:`steady_state_test`)."""
    params = result.params
    p = result.manoeuvre.parameters
    radius_m = p["radius_m"]
    limit, detail, end = _why_it_ended(result, params, p["max_ay_mps2"])
    keep = metrics.judged_mask(result).copy()
    keep[end + 1:] = False
    ay = np.asarray(result["ay_mps2"])
    steer = steer_at_nominal_radius(result, params, radius_m)
    diagram = steady_state.handling_diagram(ay[keep], steer[keep], sideslip(result)[keep],
                                        np.asarray(result["roll_rad"])[keep], radius_m=radius_m,
                                        wheelbase_m=params.wheelbase_m, fit_limit_mps2=fit_limit_mps2)
    return SteadyStateTest(diagram, radius_m, limit, detail, float(np.abs(ay[keep]).max()), result)


@dataclass(frozen=True)
class Figures:
    """A test's figures by name (each with ``to_dict()``, or a plain value)."""

    values: dict

    def __getitem__(self, key):
        return self.values[key]

    def to_dict(self) -> dict:
        """Each figure's ``to_dict()``, or the plain value.

        Returns
        -------
        dict
            Figure name -> its JSON-safe value.
        """
        return {k: (v.to_dict() if hasattr(v, "to_dict") else v) for k, v in self.values.items()}


@reduces("step")
def reduce_step(result) -> Figures:
    """ISO 7401 step figures: yaw-rate and lateral-acceleration responses against the road-wheel steer
    [rad], and the speed drift [km/h] over the window."""
    params = result.params
    judged = metrics.judged_mask(result)
    start = result.manoeuvre.parameters["start_s"]
    use = result.time_s >= start - 0.5
    steer = road_steer(result, params)[use]
    t = result.time_s[use]
    target = float(result.manoeuvre.speed.speed_mps[0] * 3.6)
    return Figures({
        "yaw_rate": handling.step_response(t, steer, np.asarray(result["yaw_rate_radps"])[use], steer_start_s=start),
        "lateral_acceleration": handling.step_response(t, steer, np.asarray(result["ay_mps2"])[use],
                                                       steer_start_s=start),
        "speed_drift_kmh": float(np.abs(np.asarray(result["speed_mps"])[judged] * 3.6 - target).max()),
    })


@reduces("sweep")
def reduce_sweep(result) -> Figures:
    """ISO 7401 frequency response: yaw-rate and lateral-acceleration gain and phase against the road-wheel
    steer, over the sweep's band."""
    params = result.params
    judged = metrics.judged_mask(result)
    t = result.time_s[judged]
    steer = road_steer(result, params)[judged]
    p = result.manoeuvre.parameters
    band = {"f_min_hz": p["f_start_hz"], "f_max_hz": p["f_end_hz"]}
    return Figures({
        "yaw_rate": handling.frequency_response(t, steer, np.asarray(result["yaw_rate_radps"])[judged], **band),
        "lateral_acceleration": handling.frequency_response(t, steer, np.asarray(result["ay_mps2"])[judged], **band),
    })


@reduces("braking-in-turn")
def reduce_braking_in_turn(result) -> Figures:
    """ISO 7975 figures: path deviation, yaw-rate change, deceleration, and the least wheel loads [N]."""
    from ..simulate.closed_loop import cg_track

    params = result.params
    p = result.manoeuvre.parameters
    cx, cy = cg_track(params, np.asarray(result["x_m"]), np.asarray(result["y_m"]), np.asarray(result["yaw_rad"]))
    braking = handling.braking_in_turn(result.time_s, cx, cy, np.asarray(result["yaw_rate_radps"]),
                                       np.asarray(result["speed_mps"]), np.asarray(result["ay_mps2"]),
                                       brake_start_s=p["brake_start_s"],
                                       circle_centre_xy=(p["centre_x_m"], p["centre_y_m"]), radius_m=p["radius_m"])
    judged = metrics.judged_mask(result)
    loads = {w: float(np.asarray(result[f"{w}_fz_N"])[judged].min()) for w in result.meta["wheels"]}
    return Figures({"braking": braking, "min_wheel_loads_N": loads})


def step_steer_test(vehicle, speed_kmh: float, *, steer_deg: float = 2.0, hold_s: float = 4.0, dt: float | None = None):
    """ISO 7401 step steer with the speed held: yaw-rate and lateral-acceleration step responses.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleModel
        The vehicle with its payload.
    speed_kmh : float
        Target speed [km/h].
    steer_deg : float
        Steer step about the steering axis [deg].
    hold_s : float
        Hold time after the ramp [s].
    dt : float, optional
        Time step [s]; automatic by default.

    Returns
    -------
    dict
        ``yaw_rate`` and ``lateral_acceleration``: :class:`~trikedyn.analysis.handling.StepResponse` figures
        against the road-wheel steer [rad]; ``speed_drift_kmh`` (largest departure from the target in the
        window); ``result``.
    """
    result = run(_model(vehicle), "step", speed_kmh=speed_kmh, dt=dt, steer_deg=steer_deg, hold_s=hold_s)
    return {**reduce_step(result).values, "result": result}


def frequency_response_test(vehicle, speed_kmh: float, *, amplitude_deg: float = 1.0, f_start_hz: float = 0.2,
                            f_end_hz: float = 3.0, sweep_s: float = 30.0, dt: float | None = None):
    """ISO 7401 frequency response from a sine sweep: gain and phase of yaw rate and lateral acceleration
    against the road-wheel steer.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleModel
        The vehicle with its payload.
    speed_kmh : float
        Target speed [km/h].
    amplitude_deg : float
        Steer amplitude about the steering axis [deg].
    f_start_hz, f_end_hz : float
        Sweep start and end frequencies [Hz].
    sweep_s : float
        Sweep duration [s].
    dt : float, optional
        Time step [s]; automatic by default.

    Returns
    -------
    dict
        ``yaw_rate`` and ``lateral_acceleration`` :class:`~trikedyn.analysis.handling.FrequencyResponse` figures and ``result``.
    """
    result = run(_model(vehicle), "sweep", speed_kmh=speed_kmh, dt=dt, amplitude_deg=amplitude_deg,
                 f_start_hz=f_start_hz, f_end_hz=f_end_hz, sweep_s=sweep_s)
    return {**reduce_sweep(result).values, "result": result}


def braking_in_turn_test(vehicle, speed_kmh: float, *, radius_m: float = 20.0, deceleration_mps2: float = 3.0,
                         dt: float | None = None):
    """ISO 7975 braking in a turn: path deviation, yaw-rate change and wheel loads while braking.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleModel
        The vehicle with its payload.
    speed_kmh : float
        Target speed [km/h].
    radius_m : float
        Circle radius [m].
    deceleration_mps2 : float
        Braking deceleration [m/s^2].
    dt : float, optional
        Time step [s]; automatic by default.

    Returns
    -------
    dict
        The :func:`~trikedyn.analysis.handling.braking_in_turn` figures and ``result`` (the run).
    """
    result = run(_model(vehicle), "braking-in-turn", speed_kmh=speed_kmh, dt=dt, radius_m=radius_m,
                 deceleration_mps2=deceleration_mps2)
    return {**reduce_braking_in_turn(result).values, "result": result}
