"""Threshold velocity: the highest speed at which the vehicle passes a manoeuvre, by criterion.

The paper (section 3.2) defines it as "the velocity just below a velocity in which one of the wheels lost
its grip off the road, i.e. vertical force reach zero". Here: the highest constant *target* speed, to
``resolution_kmh`` (0.1 km/h), at which a run passes under a **criterion**
(:mod:`trikedyn.analysis.verdict`):

- ``"course"`` (the default): ISO 3888-1's validity: every wheel down, no cone struck, path kept, no spin,
  speed held. What an engineer can sign: a run with a cone struck is not a valid lane change, whatever
  the wheels did;
- ``"lift-off"``: the paper's definition: no wheel lifts (nor does the driver lose the vehicle, nor is the
  speed not held); cone strikes are reported, not failed;
- ``"both"``: the course threshold, and the lift-off threshold above it (``course_speed_kmh``,
  ``lift_off_speed_kmh``), from one set of runs where they overlap.

**The speed driven.** Every run is judged against the speed it actually drove: a run whose speed leaves its
band (3 % or 1 km/h) is ``speed not held``, neither a pass nor a lift, and a threshold is certified by a
run that held it (``entry_speed_kmh``, ``window_speed_kmh`` of that run beside the target). With the
driver's own speed control (``speed_control="driver"``) a search never asks for more than the vehicle can
drive: it stops at its top speed on the flat (:func:`trikedyn.analysis.performance.top_speed`); a vehicle
that passes there gets ``limit = "top speed"``. ``speed_control="ideal"`` drives with unlimited torque
(the speed a multibody package's kinematic drive imposes).

Two searches, both certifying their answer by a passing run at the threshold and a failing run one
resolution above it (so they agree wherever the crossing is single):

- ``method="margin"`` (default, :mod:`trikedyn.analysis.search`): the runs are chosen by continuous
  margins (:mod:`trikedyn.analysis.margins`: each wheel's load and, per criterion, the speed band, the path
  corridor, the spin limit and the cone clearance), extrapolated to their zero; about 5 runs a search;
- ``method="bisection"``: bracketing (rising from ``low_kmh`` in ``step_kmh`` steps until a run fails),
  then bisection to the resolution;
- ``method="batch"`` (:mod:`trikedyn.analysis.batch_search`): several speeds a round, chosen by the same
  margins and run together in one lockstep batch (:mod:`trikedyn.simulate.batch`): more runs, fewer rounds.

``limit`` names what fails one resolution above the threshold: under ``lift-off``, ``"lift-off"``,
``"tracking"`` (the driver had lost the path, struck a cone or spun before the lift) or
``"speed not held"``; under ``course``, the failing run's verdict (``"lift-off"``, ``"cone strike"``,
``"path lost"``, ``"spin"``, ``"speed not held"``); ``"top speed"`` when nothing fails up to the top speed.

Any registered manoeuvre can be searched (closed-loop paths and open-loop steer inputs alike) and a path
from a CSV file; each run is judged up to the manoeuvre's exit gate, never in the run-out beyond it.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

from ..driver.preview import DriverSettings
from ..errors import InputError
from ..model.vehicle import VehicleModel, build_model
from ..params.io import ParameterSet
from .criteria import CRITERIA, DEFAULT_CRITERION, RunVerdict, check_criterion, classify, strikes_and_load
from .search import Grid, Probe, margin_search, seed_speed
from .search_settings import SEARCH_DEFAULTS as _D
from .search_settings import SearchSettings
from .verdict import Judging, judge

__all__ = ["CRITERIA", "DEFAULT_CRITERION", "METHODS", "ThresholdResult", "manoeuvre_builder", "threshold_velocity"]

TOP_SPEED = "top speed"
METHODS = ("margin", "bisection", "batch")


def manoeuvre_builder(manoeuvre, options: dict | None = None):
    """``speed_kmh -> Manoeuvre`` for a registered name, a path ``.csv`` file or a bare
    :class:`~trikedyn.manoeuvres.paths.Path` (judged over its whole length); the name is checked now.

    Parameters
    ----------
    manoeuvre : str, Path or Manoeuvre
        A name, a ``.csv`` file or a path.
    options : dict, optional
        The manoeuvre's options.

    Returns
    -------
    callable
        ``(params, speed_kmh) -> Manoeuvre``.

    Raises
    ------
    InputError
        For an unknown name or option.
    """
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
class ThresholdResult:
    """The threshold velocity and what limits it.

    Attributes
    ----------
    threshold_speed_kmh : float or None
        The highest target speed [km/h] of the grid at which a run passes (certified by that run), None when
        ``low_kmh`` fails already.
    limit, limiting_wheel, lift_time_s
        At ``first_failure_kmh`` (one resolution above the threshold): what failed (see the module
        docstring), the wheel that lifted first and when [s] (None when no wheel lifted); ``limit`` is
        ``"top speed"`` when nothing fails up to the vehicle's top speed.
    first_failure_kmh : float or None
        The failing speed [km/h] that certifies the threshold.
    first_cone_strike_kmh : float or None
        The lowest speed [km/h] among the runs made at which a cone was struck (it depends on the speeds
        the search tried).
    detail : str
    runs : tuple of RunVerdict
        Every run, in the order made (each judged under its ``criterion``).
    method : str
        ``"margin"`` or ``"bisection"``.
    criterion : str
        ``"course"``, ``"lift-off"`` or ``"both"`` (:data:`CRITERIA`).
    speed_control : str
        ``"driver"`` or ``"ideal"`` (:data:`~trikedyn.simulate.closed_loop.SPEED_CONTROLS`).
    top_speed_kmh : float or None
        The vehicle's top speed on the flat [km/h]; the driver's searches stop there.
    entry_speed_kmh : float or None
        The speed the threshold's passing run drove at the entry gate [km/h].
    window_speed_kmh : dict or None
        Its speed over the window [km/h]: ``min``, ``mean``, ``max``.
    course_speed_kmh, lift_off_speed_kmh : float or None
        The threshold under each criterion searched (the other None).
    lift_off : ThresholdResult or None
        Under ``"both"``: the lift-off search (this result is the course one).
    failure_time_s : float or None
        When the run at ``first_failure_kmh`` failed [s] (its lift, cone strike, lost path, ...).
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
    criterion: str = DEFAULT_CRITERION
    speed_control: str = "driver"
    top_speed_kmh: float | None = None
    entry_speed_kmh: float | None = None
    window_speed_kmh: dict | None = None
    course_speed_kmh: float | None = None
    lift_off_speed_kmh: float | None = None
    lift_off: ThresholdResult | None = field(default=None, repr=False)
    failure_time_s: float | None = None

    @property
    def n_runs(self) -> int:
        """Simulations made by the search."""
        return len(self.runs)

    @property
    def speeds_kmh(self) -> tuple[float, ...]:
        """The speeds tried [km/h], in order."""
        return tuple(r.speed_kmh for r in self.runs)

    @property
    def headline(self) -> str:
        """The result in one line: ``threshold 43.2 km/h (course; driven 42.9-43.6 km/h): cone strike``."""
        if self.threshold_speed_kmh is None:
            return f"no threshold ({self.criterion}): {self.detail}"
        driven = ""
        if self.window_speed_kmh is not None:
            w = self.window_speed_kmh
            driven = f"; driven {w['min']:.1f}-{w['max']:.1f} km/h"
        line = (f"threshold {self.threshold_speed_kmh:.1f} km/h target ({self.criterion}, {self.speed_control} "
                f"speed control{driven}): {self.limit or 'no limit found'}")
        if self.lift_off is not None and self.lift_off_speed_kmh is not None:
            line += f"; lift-off {self.lift_off_speed_kmh:.1f} km/h ({self.lift_off.limit or 'no limit found'})"
        return line

    def to_dict(self, runs: bool = False) -> dict:
        """The result's fields and ``n_runs``; with ``runs``, also ``method``, ``speeds_kmh`` and every run.

        Parameters
        ----------
        runs : bool
            Include the runs.

        Returns
        -------
        dict
            JSON-ready (speeds [km/h]).
        """
        out = {k: v for k, v in asdict(self).items() if k not in ("runs", "method", "lift_off")}
        if self.lift_off is not None:
            out["lift_off"] = self.lift_off.to_dict()
        if runs:
            out["method"] = self.method
            out["speeds_kmh"] = list(self.speeds_kmh)
            out["runs"] = [r.to_dict() for r in self.runs]
        out["n_runs"] = self.n_runs
        return out


class _Runs:
    """The runs of one search (or of both criteria's searches): simulated once per target speed, each ending
    at its exit gate where the judging ends (``end_at_exit``, :func:`~trikedyn.simulate.closed_loop.exit_gate`)."""

    def __init__(self, model, build, driver, dt, speed_control, judging):
        self.model, self.build, self.driver, self.dt = model, build, driver, dt
        self.speed_control, self.judging = speed_control, judging
        self.done: dict[float, tuple] = {}
        self.order: list[RunVerdict] = []
        self.ready: dict = {}  # results run ahead in a batch, not measured yet

    def prefetch(self, speeds_kmh) -> None:
        """Run the speeds [km/h] not run yet together, in one lockstep batch (:mod:`trikedyn.simulate.batch`);
        :meth:`measure` then takes their results."""
        from ..simulate.batch import run_prepared
        from ..simulate.closed_loop import prepare_run

        todo = [v for v in dict.fromkeys(round(v, 6) for v in speeds_kmh) if v not in self.done and v not in self.ready]
        specs = [prepare_run(self.model, self.build(self.model.params, v), driver=self.driver, dt=self.dt,
                             speed_control=self.speed_control, end_at_exit=True) for v in todo]
        self.ready.update(zip(todo, run_prepared(specs, lanes=max(1, len(specs))), strict=True))

    def measure(self, speed_kmh: float, criterion: str) -> tuple[RunVerdict, Probe]:
        """The verdict under ``criterion`` of the run at ``speed_kmh`` [km/h], and its probe for the search."""
        from .margins import run_margins

        speed_kmh = round(speed_kmh, 6)
        fresh = speed_kmh not in self.done
        if fresh:
            from ..simulate.closed_loop import run

            result = self.ready.pop(speed_kmh, None)
            if result is None:
                result = run(self.model, self.build(self.model.params, speed_kmh), driver=self.driver, dt=self.dt,
                             speed_control=self.speed_control, end_at_exit=True)
            self.done[speed_kmh] = (result, judge(result, self.judging), *strikes_and_load(result), {})
        result, verdict, strikes, min_load, probes = self.done[speed_kmh]
        if criterion not in probes:
            table, anchors, margin = run_margins(result, verdict, criterion, self.judging)
            seen = replace(classify(verdict, criterion, speed_kmh, strikes, min_load), margin_N=margin)
            probes[criterion] = (seen, Probe(speed_kmh, seen.passed, table, anchors))
        seen, probe = probes[criterion]
        if fresh:
            self.order.append(seen)
        return seen, probe


def threshold_velocity(vehicle: ParameterSet | VehicleModel, manoeuvre="dlc", *, options: dict | None = None,
                       low_kmh: float = _D["low_kmh"], high_kmh: float = _D["high_kmh"],
                       step_kmh: float = _D["step_kmh"], resolution_kmh: float = _D["resolution_kmh"],
                       driver: DriverSettings | None = None,
                       dt: float | None = None, method: str = "margin", criterion: str = DEFAULT_CRITERION,
                       speed_control: str = "driver", judging: Judging | None = None) -> ThresholdResult:
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
        Search range [km/h]; ``low_kmh`` should pass. With ``speed_control="driver"`` the range ends at the
        vehicle's top speed on the flat when that is lower.
    step_kmh : float
        Bracketing step [km/h] (``"bisection"``; the margin search rises by it only when the margin gives
        no estimate).
    resolution_kmh : float
        Resolution [km/h]: the threshold is ``low_kmh`` plus a whole number of it (or the range's end).
    driver : DriverSettings, optional
        The driver's parameters; defaults otherwise.
    dt : float, optional
        Time step [s]; by default the loop's automatic step (:func:`~trikedyn.simulate.run.automatic_step`),
        the same for every run of the search.
    method : {"margin", "bisection", "batch"}
        How the runs are chosen; all certify the answer by a pass at the threshold and a fail one
        resolution above it (``"batch"``: several speeds a round, run in lockstep).
    criterion : {"course", "lift-off", "both"}
        What a run must do to pass (see the module docstring); ``"course"`` by default.
    speed_control : {"driver", "ideal"}
        The vehicle's own drive and brakes, or unlimited ones (:func:`trikedyn.simulate.closed_loop.run`).
    judging : Judging, optional
        The speed band and the path and spin limits (:class:`~trikedyn.analysis.verdict.Judging`).

    Returns
    -------
    ThresholdResult
        ``threshold_speed_kmh`` is None when even ``low_kmh`` fails; ``runs`` in the order they were made.
    """
    from ..simulate.defaults import SPEED_CONTROLS

    model = vehicle if isinstance(vehicle, VehicleModel) else build_model(vehicle)
    build = manoeuvre_builder(manoeuvre, options)
    try:  # the range by the search settings' one set of bounds (those of the commands and the specs)
        SearchSettings(low_kmh=low_kmh, high_kmh=high_kmh, step_kmh=step_kmh, resolution_kmh=resolution_kmh)
    except InputError as exc:
        raise InputError(f"{exc.where}: {exc.reason}", where="threshold search") from None
    if method not in METHODS:
        raise InputError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}", where="threshold search")
    check_criterion(criterion)
    if speed_control not in SPEED_CONTROLS:
        raise InputError(f"unknown speed control {speed_control!r}; expected one of {', '.join(SPEED_CONTROLS)}",
                         where="speed_control")
    from .performance import top_speed

    top = top_speed(model).top_speed_kmh
    runs = _Runs(model, build, driver, dt, speed_control, judging or Judging())
    context = {"criterion": criterion, "speed_control": speed_control, "top_speed_kmh": top}
    high = high_kmh
    if speed_control == "driver" and top is not None and top < high_kmh:
        if top < low_kmh + resolution_kmh:
            return ThresholdResult(None, TOP_SPEED, None, None, None, None,
                                   f"its top speed ({top:.1f} km/h) is below the speeds searched (from {low_kmh:g} km/h)",
                                   (), method, **context)
        high = round(low_kmh + math.floor((top - low_kmh) / resolution_kmh + 1e-9) * resolution_kmh, 6)
    capped = high < high_kmh
    title = _title(manoeuvre)
    grid = Grid(low_kmh, high, resolution_kmh)
    if criterion != "both":
        return _search(runs, criterion, grid, method, step_kmh, capped, title, context)
    course = _search(runs, "course", grid, method, step_kmh, capped, title, context)
    base = course.threshold_speed_kmh
    if base is None:
        lift = _search(runs, "lift-off", grid, method, step_kmh, capped, title, context)
    elif course.first_failure_kmh is None:  # clean up to the end of the range: no lift either
        lift = replace(course, criterion="lift-off", runs=(), course_speed_kmh=None, lift_off_speed_kmh=base)
    else:  # the course threshold passes lift-off too: search above it
        lift = _search(runs, "lift-off", Grid(base, high, resolution_kmh), method, step_kmh, capped, title, context)
    return replace(course, criterion="both", runs=tuple(runs.order), course_speed_kmh=base,
                   lift_off_speed_kmh=lift.threshold_speed_kmh, lift_off=lift)


def _title(manoeuvre) -> str:
    """The manoeuvre in words for a sentence: ``the ISO 14791 single lane change``."""
    from ..manoeuvres import registry

    name = str(getattr(manoeuvre, "name", manoeuvre))
    if name.lower().endswith(".csv") or not isinstance(manoeuvre, str):
        return "the path"
    try:
        return f"the {registry.get(name).title}"
    except InputError:
        return f"the {name}"


def _search(runs: _Runs, criterion: str, grid: Grid, method: str, step_kmh: float, capped: bool, title: str,
            context: dict) -> ThresholdResult:
    """One criterion's search on ``grid``; the runs it makes are kept in ``runs``."""
    made: list[RunVerdict] = []

    def measure(v):
        """The run at ``v`` [km/h] judged under this search's criterion, kept in ``made``."""
        verdict, probe = runs.measure(v, criterion)
        made.append(verdict)
        return verdict, probe

    if method == "bisection":
        passed, failed = _bisection(lambda v: measure(v)[0], grid, step_kmh)
    else:
        try:
            seed = seed_speed(runs.model.params, runs.build(runs.model.params, 0.5 * (grid.low_kmh + grid.high_kmh)))
        except InputError:
            seed = None
        if method == "batch":
            from .batch_search import batch_margin_search

            def measure_many(speeds):
                """The runs at ``speeds`` [km/h], made in one batch, as probes."""
                runs.prefetch(speeds)
                return [measure(v)[1] for v in speeds]

            outcome = batch_margin_search(measure_many, grid, seed_kmh=seed, step_kmh=step_kmh)
        else:
            outcome = margin_search(lambda v: measure(v)[1], grid, seed_kmh=seed, step_kmh=step_kmh)
        passed, failed = outcome.passed, outcome.failed
    by_speed = {r.speed_kmh: r for r in made}
    strike = min((r.speed_kmh for r in made if r.cone_strikes), default=None)
    common = {"method": method, **context, "criterion": criterion, "runs": tuple(made),
              f"{criterion.replace('-', '_')}_speed_kmh": None}
    if passed is None:
        failing = by_speed[grid.speed(0)]
        return ThresholdResult(None, failing.limit, failing.wheel, _lift_time(failing), failing.speed_kmh, strike,
                               f"fails already at {failing.speed_kmh:g} km/h: {failing.detail}",
                               failure_time_s=failing.time_s, **common)
    threshold = grid.speed(passed)
    held = by_speed[threshold]
    common.update(entry_speed_kmh=held.entry_speed_kmh, window_speed_kmh=held.window_speed_kmh)
    common[f"{criterion.replace('-', '_')}_speed_kmh"] = threshold
    if failed is None:
        top = context["top_speed_kmh"]
        if capped:
            what = "no wheel lifts in" if criterion == "lift-off" else "it drives cleanly through"
            detail = f"{what} {title} at any speed it can reach (top speed {top:.1f} km/h)"
            return ThresholdResult(threshold, TOP_SPEED, None, None, None, strike, detail, **common)
        what = "no wheel lifts" if criterion == "lift-off" else "it drives the course cleanly"
        return ThresholdResult(threshold, None, None, None, None, strike, f"{what} up to {threshold:g} km/h", **common)
    failing = by_speed[grid.speed(failed)]
    return ThresholdResult(threshold, failing.limit, failing.wheel, _lift_time(failing), failing.speed_kmh, strike,
                           f"at {failing.speed_kmh:.1f} km/h: {failing.detail}", failure_time_s=failing.time_s,
                           **common)


def _lift_time(run: RunVerdict) -> float | None:
    """When a failing run's wheel lifted [s], None when none did (it failed otherwise)."""
    return run.time_s if run.wheel is not None else None


def _bisection(attempt, grid: Grid, step_kmh: float) -> tuple[int | None, int | None]:
    """The search before the margin, on ``grid``: bracketing from its first speed in ``step_kmh`` steps, then
    bisection. Returns the grid indices of the certified pass and fail (None: none)."""
    if not attempt(grid.speed(0)).passed:
        return None, 0
    step = max(1, round(step_kmh / grid.resolution_kmh))
    lo, hi = 0, None
    while lo < grid.last:
        k = min(lo + step, grid.last)
        if attempt(grid.speed(k)).passed:
            lo = k
        else:
            hi = k
            break
    if hi is None:
        return lo, None
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if attempt(grid.speed(mid)).passed:
            lo = mid
        else:
            hi = mid
    return lo, hi
