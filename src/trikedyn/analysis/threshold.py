"""Threshold velocity: the highest speed at which every wheel stays on the ground through a manoeuvre.

The paper (section 3.2) defines it as "the velocity just below a velocity in which one of the wheels lost
its grip off the road, i.e. vertical force reach zero". Here: the highest constant *target* speed, to
``resolution_kmh`` (0.1 km/h), at which no wheel's vertical force reaches zero during the manoeuvre. It is
found by bracketing (rising in steps until a run fails) and bisection, assuming a single crossing.

A run fails when a wheel lifts, or when the driver loses control without any lift (a spin: the path error
grows beyond ``lost_m``, or the run diverges). Cone strikes do not define the threshold (the paper's
definition is lift-off) but are judged: ``limit`` is ``"lift-off"`` when the first failing speed lifts a
wheel with the driver still on the path, and ``"tracking"`` when the driver had already lost the path
(a cone strike or a spin) before the first lift. The speed of the first cone strike is reported too.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..driver.preview import DriverSettings
from ..errors import InputError, SimulationError
from ..model.vehicle import VehicleModel, build_model
from ..params.io import ParameterSet

__all__ = ["RunVerdict", "ThresholdResult", "judge_run", "threshold_velocity", "manoeuvre_path"]

LIFT_OFF, TRACKING = "lift-off", "tracking"


def manoeuvre_path(manoeuvre: str, params):
    """The path of ``dlc`` (ISO 3888-1) or ``slc`` (ISO 14791) for a parameter set."""
    from ..manoeuvres import paths

    if manoeuvre == "dlc":
        return paths.double_lane_change(params.body.overall_width_m)
    if manoeuvre == "slc":
        return paths.single_lane_change()
    raise InputError(f"unknown manoeuvre '{manoeuvre}'; expected dlc or slc", where="manoeuvre")


@dataclass(frozen=True)
class RunVerdict:
    """How one run at one speed went."""

    speed_kmh: float
    passed: bool
    limit: str | None  # "lift-off" or "tracking" when failed
    wheel: str | None
    time_s: float | None
    detail: str
    cone_strikes: int = 0

    def to_dict(self) -> dict:
        return asdict(self)


def judge_run(result, lost_m: float = 2.5) -> RunVerdict:
    """Pass or fail of a closed-loop run (see the module docstring), and what went wrong first."""
    speed_kmh = float(result.meta.get("target_speed_kmh", float("nan")))
    wheels = result.meta["wheels"]
    fz = np.column_stack([result[f"{w}_fz_N"] for w in wheels])
    lifted = np.nonzero((fz <= 0.0).any(axis=1))[0]
    t_lift = float(result.time_s[lifted[0]]) if lifted.size else math.inf
    strikes = result.meta.get("cone_strikes", [])
    t_strike = min((float(s["time_s"]) for s in strikes), default=math.inf)
    error = np.abs(result.channels.get("path_error_m", np.zeros(1)))
    lost = np.nonzero(error > lost_m)[0]
    t_lost = float(result.time_s[lost[0]]) if lost.size else math.inf
    if result.status != "ok" and math.isinf(t_lift):
        t_lost = min(t_lost, float(result.time_s[-1]))
    t_track = min(t_strike, t_lost)
    n = len(strikes)
    if math.isinf(t_lift) and math.isinf(t_lost):
        note = f", {n} cone strike(s) from {t_strike:.2f} s" if n else ""
        return RunVerdict(speed_kmh, True, None, None, None, "every wheel down" + note, n)
    if not math.isinf(t_lift):
        k = int(np.argmin(fz[lifted[0]]))
        limit = TRACKING if t_track < t_lift else LIFT_OFF
        lead = ""
        if limit == TRACKING:
            lead = (f"cone strike at {t_strike:.2f} s, then " if t_strike <= t_lost else f"path lost at {t_lost:.2f} s, then ")
        return RunVerdict(speed_kmh, False, limit, wheels[k], t_lift, f"{lead}{wheels[k]} lifted at {t_lift:.2f} s", n)
    why = result.status if result.status != "ok" else f"path lost (error > {lost_m:g} m) at {t_lost:.2f} s"
    return RunVerdict(speed_kmh, False, TRACKING, None, t_lost, why, n)


@dataclass(frozen=True)
class ThresholdResult:
    """The threshold velocity and what limits it."""

    threshold_speed_kmh: float | None
    limit: str | None
    limiting_wheel: str | None
    lift_time_s: float | None
    first_failure_kmh: float | None
    first_cone_strike_kmh: float | None
    detail: str
    runs: tuple[RunVerdict, ...]

    def to_dict(self, runs: bool = False) -> dict:
        out = {k: v for k, v in asdict(self).items() if k != "runs"}
        if runs:
            out["runs"] = [r.to_dict() for r in self.runs]
        out["n_runs"] = len(self.runs)
        return out


def _run(model, path, speed_kmh, driver, dt):
    from ..simulate.closed_loop import drive

    try:
        result = drive(model, path, speed_kmh, driver=driver, dt=dt)
    except SimulationError as err:
        result = getattr(err, "result", None)
        if result is None:
            raise
    result.meta["target_speed_kmh"] = speed_kmh
    return judge_run(result)


def threshold_velocity(vehicle: ParameterSet | VehicleModel, manoeuvre: str = "dlc", *, low_kmh: float = 10.0,
                       high_kmh: float = 90.0, step_kmh: float = 10.0, resolution_kmh: float = 0.1,
                       driver: DriverSettings | None = None, dt: float = 5e-3) -> ThresholdResult:
    """The threshold velocity of a vehicle in ``manoeuvre`` (``"dlc"``, ``"slc"`` or a Path).

    Parameters
    ----------
    vehicle : ParameterSet or VehicleModel
        The vehicle with its payload.
    manoeuvre : str or Path
    low_kmh, high_kmh : float
        Search range [km/h]; ``low_kmh`` should pass.
    step_kmh : float
        Bracketing step [km/h].
    resolution_kmh : float
        Bisection resolution [km/h].

    Returns
    -------
    ThresholdResult
        ``threshold_speed_kmh`` is None when even ``low_kmh`` fails, and ``high_kmh`` when nothing fails.
    """
    model = vehicle if isinstance(vehicle, VehicleModel) else build_model(vehicle)
    path = manoeuvre_path(manoeuvre, model.params) if isinstance(manoeuvre, str) else manoeuvre
    if not (0 < low_kmh < high_kmh) or step_kmh <= 0 or resolution_kmh <= 0:
        raise InputError("need 0 < low_kmh < high_kmh and positive step and resolution", where="threshold search")
    runs = []

    def attempt(v):
        verdict = _run(model, path, round(v, 6), driver, dt)
        runs.append(verdict)
        return verdict

    def first_strike():
        struck = [r.speed_kmh for r in runs if r.cone_strikes]
        return min(struck) if struck else None

    first = attempt(low_kmh)
    if not first.passed:
        return ThresholdResult(None, first.limit, first.wheel, first.time_s, low_kmh, first_strike(),
                               f"fails already at {low_kmh:g} km/h: {first.detail}", tuple(runs))
    lo, hi, failing = low_kmh, None, None
    v = low_kmh
    while v < high_kmh:
        v = min(v + step_kmh, high_kmh)
        verdict = attempt(v)
        if verdict.passed:
            lo = v
        else:
            hi, failing = v, verdict
            break
    if hi is None:
        return ThresholdResult(high_kmh, None, None, None, None, first_strike(),
                               f"no wheel lifts up to {high_kmh:g} km/h", tuple(runs))
    n_lo = round(lo / resolution_kmh)
    n_hi = round(hi / resolution_kmh)
    while n_hi - n_lo > 1:
        mid = (n_lo + n_hi) // 2
        verdict = attempt(mid * resolution_kmh)
        if verdict.passed:
            n_lo = mid
        else:
            n_hi, failing = mid, verdict
    threshold = round(n_lo * resolution_kmh, 6)
    return ThresholdResult(threshold, failing.limit, failing.wheel, failing.time_s, round(n_hi * resolution_kmh, 6),
                           first_strike(), f"at {n_hi * resolution_kmh:.1f} km/h: {failing.detail}", tuple(runs))
