"""Threshold velocity: the highest speed at which every wheel stays on the ground through a manoeuvre.

The paper (section 3.2) defines it as "the velocity just below a velocity in which one of the wheels lost
its grip off the road, i.e. vertical force reach zero". Here: the highest constant *target* speed, to
``resolution_kmh`` (0.1 km/h), at which no wheel's vertical force reaches zero during the manoeuvre.

Two searches, both assuming a single crossing and both certifying their answer by a passing run at the
threshold and a failing run one resolution above it (so they agree wherever the crossing is single):

- ``method="margin"`` (default, :mod:`trikedyn.analysis.search`): the runs are chosen by a continuous
  margin (the minimum wheel load, per wheel and stretch of the window, extended below zero beyond a lift),
  extrapolated to its zero by secant and regula-falsi steps in ``v^2``; the first run is placed from the
  static tip-over speed in the manoeuvre's tightest curve. About 5 runs a search (the paper's study: a
  median of 5, from 12).
- ``method="bisection"``: bracketing (rising from ``low_kmh`` in ``step_kmh`` steps until a run fails),
  then bisection to the resolution.

A run fails when a wheel lifts, or when the driver loses control without any lift (a spin: the path error
grows beyond ``lost_m``, or the run diverges). Cone strikes do not define the threshold (the paper's
definition is lift-off) but are judged: ``limit`` is ``"lift-off"`` when the first failing speed lifts a
wheel with the driver still on the path, and ``"tracking"`` when the driver had already lost the path
(a cone strike or a spin) before the first lift. The speed of the first cone strike is reported too.

Any registered manoeuvre can be searched (closed-loop paths and open-loop steer inputs alike) and a path
from a CSV file; each run is judged up to the manoeuvre's exit gate (:mod:`trikedyn.analysis.metrics`),
never in the run-out beyond it, where the driver is no longer being tested.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace

import numpy as np

from ..driver.preview import DriverSettings
from ..errors import InputError
from ..model.vehicle import VehicleModel, build_model
from ..params.io import ParameterSet
from .search import Grid, Probe, margin_search, margin_table, seed_speed

__all__ = ["RunVerdict", "ThresholdResult", "judge_run", "threshold_velocity", "manoeuvre_builder"]

LIFT_OFF, TRACKING = "lift-off", "tracking"


def manoeuvre_builder(manoeuvre, options: dict | None = None):
    """``speed_kmh -> Manoeuvre`` for a registered name, a path ``.csv`` file or a bare
    :class:`~trikedyn.manoeuvres.paths.Path` (judged over its whole length); the name is checked now."""
    from ..manoeuvres.base import Manoeuvre
    from ..manoeuvres.paths import Path

    options = dict(options or {})
    if isinstance(manoeuvre, Path):
        from ..manoeuvres import speed as speeds
        from ..manoeuvres.base import whole_path

        return lambda params, v: whole_path(manoeuvre, speeds.constant(v, 1.0))
    if isinstance(manoeuvre, Manoeuvre):
        raise InputError("give the manoeuvre by name: a threshold search builds it at each speed", where="manoeuvre")
    from ..manoeuvres import registry

    name = str(manoeuvre)
    if not name.lower().endswith(".csv"):
        registry.get(name)  # unknown names fail before any run
    return lambda params, v: registry.build(name, params, v, **options)


@dataclass(frozen=True)
class RunVerdict:
    """How one run at one speed went.

    ``speed_kmh`` [km/h]; ``limit`` is ``"lift-off"`` or ``"tracking"`` when it failed, with the wheel and
    time [s] of the first lift (or of the lost path); ``min_wheel_load_N`` [N] is the smallest wheel load
    up to the exit gate; ``margin_N`` [N] the signed margin the search steers by (the smallest entry of
    :func:`trikedyn.analysis.search.margin_table`: negative when a wheel lifted, None when unknown).
    """

    speed_kmh: float
    passed: bool
    limit: str | None  # "lift-off" or "tracking" when failed
    wheel: str | None
    time_s: float | None
    detail: str
    cone_strikes: int = 0
    min_wheel_load_N: float | None = None
    margin_N: float | None = None

    def to_dict(self) -> dict:
        return asdict(self)


def judge_run(result, lost_m: float = 2.5, speed_kmh: float | None = None) -> RunVerdict:
    """Pass or fail of a run (see the module docstring), and what went wrong first.

    Judged up to the exit gate: a lift in the run-in counts, nothing in the run-out does. A run that
    stopped early (rollover, divergence) fails.
    """
    from .metrics import cone_strikes, first_lift, judged_mask, until_exit

    speed_kmh = float(result.meta.get("target_speed_kmh", float("nan")) if speed_kmh is None else speed_kmh)
    lift = first_lift(result, from_start=True)
    t_lift = lift.time_s if lift is not None else math.inf
    strikes = cone_strikes(result)
    t_strike = min((float(s["time_s"]) for s in strikes), default=math.inf)
    scope = until_exit(result) if judged_mask(result).any() else np.ones(result.time_s.size, dtype=bool)
    if "path_error_m" in result.channels and result.manoeuvre is not None and result.manoeuvre.closed_loop:
        lost = np.nonzero((np.abs(result["path_error_m"]) > lost_m) & scope)[0]
    else:
        lost = np.zeros(0, dtype=int)
    t_lost = float(result.time_s[lost[0]]) if lost.size else math.inf
    if result.status != "ok" and math.isinf(t_lift):
        t_lost = min(t_lost, float(result.time_s[-1]))
    fz = np.column_stack([result[f"{w}_fz_N"] for w in result.meta["wheels"]])[scope]
    min_load = float(fz.min()) if fz.size else None
    t_track = min(t_strike, t_lost)
    n = len(strikes)
    if math.isinf(t_lift) and math.isinf(t_lost):
        note = f", {n} cone strike(s) from {t_strike:.2f} s" if n else ""
        return RunVerdict(speed_kmh, True, None, None, None, "every wheel down" + note, n, min_load)
    if not math.isinf(t_lift):
        limit = TRACKING if t_track < t_lift else LIFT_OFF
        lead = ""
        if limit == TRACKING:
            lead = (f"cone strike at {t_strike:.2f} s, then " if t_strike <= t_lost else f"path lost at {t_lost:.2f} s, then ")
        return RunVerdict(speed_kmh, False, limit, lift.wheel, t_lift, f"{lead}{lift.wheel} lifted at {t_lift:.2f} s", n,
                          min_load)
    why = result.status if result.status != "ok" else f"path lost (error > {lost_m:g} m) at {t_lost:.2f} s"
    return RunVerdict(speed_kmh, False, TRACKING, None, t_lost, why, n, min_load)


@dataclass(frozen=True)
class ThresholdResult:
    """The threshold velocity and what limits it.

    Attributes
    ----------
    threshold_speed_kmh : float or None
        The highest grid speed [km/h] with every wheel down (certified by a run), None when ``low_kmh``
        fails already.
    limit, limiting_wheel, lift_time_s
        At ``first_failure_kmh`` (one resolution above the threshold): ``"lift-off"`` or ``"tracking"``,
        the wheel that lifted first and when [s].
    first_failure_kmh : float or None
        The failing speed [km/h] that certifies the threshold.
    first_cone_strike_kmh : float or None
        The lowest speed [km/h] among the runs made at which a cone was struck (it depends on the speeds
        the search tried).
    detail : str
    runs : tuple of RunVerdict
        Every run, in the order made.
    method : str
        ``"margin"`` or ``"bisection"``.
    """

    threshold_speed_kmh: float | None
    limit: str | None
    limiting_wheel: str | None
    lift_time_s: float | None
    first_failure_kmh: float | None
    first_cone_strike_kmh: float | None
    detail: str
    runs: tuple[RunVerdict, ...]
    method: str = "margin"

    @property
    def n_runs(self) -> int:
        """Runs made by the search."""
        return len(self.runs)

    @property
    def speeds_kmh(self) -> tuple[float, ...]:
        """The speeds tried [km/h], in order."""
        return tuple(r.speed_kmh for r in self.runs)

    def to_dict(self, runs: bool = False) -> dict:
        """The result's fields and ``n_runs``; with ``runs``, also ``method``, ``speeds_kmh`` and every run."""
        out = {k: v for k, v in asdict(self).items() if k not in ("runs", "method")}
        if runs:
            out["method"] = self.method
            out["speeds_kmh"] = list(self.speeds_kmh)
            out["runs"] = [r.to_dict() for r in self.runs]
        out["n_runs"] = self.n_runs
        return out


def _measure(model, build, speed_kmh, driver, dt):
    """Run the manoeuvre at ``speed_kmh`` [km/h]: the verdict, and the run as the margin search sees it."""
    from ..simulate.closed_loop import run

    result = run(model, build(model.params, speed_kmh), driver=driver, dt=dt)
    verdict = judge_run(result, speed_kmh=speed_kmh)
    margins, static = margin_table(result, fail_time_s=verdict.time_s, lift_wheel=verdict.wheel)
    probe = Probe(speed_kmh, verdict.passed, margins, static)
    return replace(verdict, margin_N=probe.margin_N), probe


METHODS = ("margin", "bisection")


def threshold_velocity(vehicle: ParameterSet | VehicleModel, manoeuvre="dlc", *, options: dict | None = None,
                       low_kmh: float = 10.0, high_kmh: float = 90.0, step_kmh: float = 10.0,
                       resolution_kmh: float = 0.1, driver: DriverSettings | None = None,
                       dt: float | None = None, method: str = "margin") -> ThresholdResult:
    """The threshold velocity of a vehicle in a manoeuvre.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleModel
        The vehicle with its payload.
    manoeuvre : str or Path
        A registered manoeuvre's name (``trikedyn manoeuvres``), a path ``.csv`` file, or a bare Path.
    options : dict, optional
        The manoeuvre's options.
    low_kmh, high_kmh : float
        Search range [km/h]; ``low_kmh`` should pass.
    step_kmh : float
        Bracketing step [km/h] (``"bisection"``; the margin search rises by it only when the margin gives
        no estimate).
    resolution_kmh : float
        Resolution [km/h]: the threshold is ``low_kmh`` plus a whole number of it (or ``high_kmh``).
    driver : DriverSettings, optional
        The driver's parameters; defaults otherwise.
    dt : float, optional
        Time step [s]; by default the loop's automatic step (:func:`~trikedyn.simulate.run.automatic_step`),
        the same for every run of the search (the stability limit is found once per model).
    method : {"margin", "bisection"}
        ``"margin"`` (default): runs chosen by the continuous margin (:mod:`trikedyn.analysis.search`);
        ``"bisection"``: bracketing from ``low_kmh`` in ``step_kmh`` steps, then bisection. Both certify
        the answer by a pass at the threshold and a fail one resolution above it.

    Returns
    -------
    ThresholdResult
        ``threshold_speed_kmh`` is None when even ``low_kmh`` fails, and ``high_kmh`` when nothing fails;
        ``runs`` in the order they were made (``n_runs``, ``speeds_kmh``).
    """
    model = vehicle if isinstance(vehicle, VehicleModel) else build_model(vehicle)
    build = manoeuvre_builder(manoeuvre, options)
    values = (low_kmh, high_kmh, step_kmh, resolution_kmh)
    if not all(math.isfinite(v) for v in values) or not (0 < low_kmh < high_kmh) or step_kmh <= 0 \
            or resolution_kmh <= 0:
        raise InputError("need finite 0 < low_kmh < high_kmh and positive step and resolution",
                         where="threshold search")
    if method not in METHODS:
        raise InputError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}", where="threshold search")
    runs: list[RunVerdict] = []

    def measure(v):
        verdict, probe = _measure(model, build, round(v, 6), driver, dt)
        runs.append(verdict)
        return verdict, probe

    if method == "bisection":
        return _bisection(lambda v: measure(v)[0], runs, low_kmh, high_kmh, step_kmh, resolution_kmh)
    grid = Grid(low_kmh, high_kmh, resolution_kmh)
    try:
        seed = seed_speed(model.params, build(model.params, 0.5 * (low_kmh + high_kmh)))
    except InputError:
        seed = None
    outcome = margin_search(lambda v: measure(v)[1], grid, seed_kmh=seed, step_kmh=step_kmh)
    by_speed = {r.speed_kmh: r for r in runs}
    if outcome.passed is None:
        failing = by_speed[grid.speed(0)]
        return ThresholdResult(None, failing.limit, failing.wheel, failing.time_s, failing.speed_kmh,
                               _first_strike(runs), f"fails already at {failing.speed_kmh:g} km/h: {failing.detail}",
                               tuple(runs), method)
    threshold = grid.speed(outcome.passed)
    if outcome.failed is None:
        return ThresholdResult(threshold, None, None, None, None, _first_strike(runs),
                               f"no wheel lifts up to {threshold:g} km/h", tuple(runs), method)
    failing = by_speed[grid.speed(outcome.failed)]
    return ThresholdResult(threshold, failing.limit, failing.wheel, failing.time_s, failing.speed_kmh,
                           _first_strike(runs), f"at {failing.speed_kmh:.1f} km/h: {failing.detail}", tuple(runs),
                           method)


def _first_strike(runs) -> float | None:
    struck = [r.speed_kmh for r in runs if r.cone_strikes]
    return min(struck) if struck else None


def _bisection(attempt, runs, low_kmh, high_kmh, step_kmh, resolution_kmh) -> ThresholdResult:
    """The search before the margin: bracketing from ``low_kmh`` in ``step_kmh`` steps, then bisection."""
    first = attempt(low_kmh)
    if not first.passed:
        return ThresholdResult(None, first.limit, first.wheel, first.time_s, low_kmh, _first_strike(runs),
                               f"fails already at {low_kmh:g} km/h: {first.detail}", tuple(runs), "bisection")
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
        return ThresholdResult(high_kmh, None, None, None, None, _first_strike(runs),
                               f"no wheel lifts up to {high_kmh:g} km/h", tuple(runs), "bisection")
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
                           _first_strike(runs), f"at {n_hi * resolution_kmh:.1f} km/h: {failing.detail}", tuple(runs),
                           "bisection")
