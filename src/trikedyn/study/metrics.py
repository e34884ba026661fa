"""What a study measures: a registry of study metrics (a study is vehicle variations x manoeuvres x metrics).

A study metric is a function of one varied vehicle (suspension scaled, overrides and freight applied) and,
for a metric *per manoeuvre*, one of the spec's manoeuvres. It returns a dict with at least ``value`` (a
number, or None when there is none); other keys are kept in the result store beside it (the threshold's
``limit``, ``limiting_wheel``, ... fill the table's columns of those names). Built in:

============================  =======  ===============  ==========================================================
name                          unit     per manoeuvre    what
============================  =======  ===============  ==========================================================
``threshold``                 km/h     yes              threshold velocity (the spec's search settings); default
``tilt_angle``                deg      no               tilt-table angle at which the first wheel lifts
``understeer_gradient``       deg/g    no               ISO 4138 constant radius (option ``radius_m``, 20 m)
``peak_ri``                   -        yes              largest |rollover index| of a run at ``speed_kmh``
``min_wheel_load``            N        yes              smallest wheel load of a run at ``speed_kmh``
============================  =======  ===============  ==========================================================

Adding a metric is registering a function in any module (no edit of the runner)::

    from trikedyn.study.metrics import study_metric

    @study_metric("static_margin", unit="m", per_manoeuvre=False)
    def static_margin(pset, scenario, **options):
        return {"value": ...}

A spec names metrics by name, or as a table with options: ``metrics = ["threshold", "tilt_angle",
{ name = "peak_ri", speed_kmh = 40 }]``. Worker processes find a metric by importing the module that
registers it: register in an importable module (the pool's workers also re-import a script's ``__main__``),
not interactively, when the study runs on Dask.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from ..errors import InputError
from ..options import Option, find_option
from ..registry import Registry, first_line

__all__ = ["DEFAULT_METRIC", "STUDY_METRICS", "MetricOption", "Option", "StudyMetric", "course_options", "get",
           "label", "metrics", "parse_entry", "study_metric", "table_fields"]

DEFAULT_METRIC = "threshold"
"""The metric of a spec that lists none (every study before metrics existed): its scenario ids and table
columns are exactly those of then."""


MetricOption = Option
"""An option of a study metric: :class:`trikedyn.options.Option` (no default: required; a number or a word)."""


@dataclass(frozen=True)
class StudyMetric:
    """A registered study metric (see :func:`study_metric`)."""

    name: str
    unit: str
    help: str
    per_manoeuvre: bool
    uses_search: bool
    options: tuple[Option, ...] = field(default_factory=tuple)
    fn: Callable = field(default=None, repr=False)

    def option(self, name: str) -> Option:
        """The option ``name``; an :class:`InputError` with a close match when it has none.

        Parameters
        ----------
        name : str
            The option's name.

        Returns
        -------
        Option
            The option (default, unit, bounds).
        """
        return find_option(self.options, name, f"metric '{self.name}'", "metrics")


STUDY_METRICS: Registry[StudyMetric] = Registry("metric", group="trikedyn.study_metrics", where="metrics")
"""The registered study metrics (plug-ins: entry-point group ``trikedyn.study_metrics``)."""


def study_metric(name: str, *, unit: str = "", per_manoeuvre: bool, uses_search: bool = False,
                 options: tuple[Option, ...] = (), help: str = "", replace: bool = False):  # noqa: A002
    """Decorator: register ``fn(pset, scenario, **options) -> {"value": number | None, ...}`` as a study metric.

    ``pset`` is the scenario's vehicle, varied and loaded; ``scenario`` the scenario dict (its ``manoeuvre``
    is None for a metric not per manoeuvre; the threshold search settings are in it when ``uses_search``).
    A taken ``name`` raises ValueError unless ``replace=True``.

    Parameters
    ----------
    name : str
        The metric's name.
    unit : str
        Its unit, for the table.
    per_manoeuvre : bool
        Evaluated once per manoeuvre (True) or once per vehicle.
    uses_search : bool
        It takes the threshold search settings.
    options : tuple of Option
        Its options, with units and bounds.
    help : str
        One line; the function's first docstring line by default.
    replace : bool
        Replace a metric of the same name.

    Returns
    -------
    callable
        The decorator.
    """

    def decorate(fn):
        """Register ``fn`` as the study metric ``name`` and return it unchanged."""
        STUDY_METRICS.register(name, StudyMetric(name, unit, help or first_line(fn), per_manoeuvre, uses_search,
                                                 tuple(options), fn), replace=replace)
        return fn

    return decorate


def metrics() -> list[StudyMetric]:
    """Every registered study metric.

    Returns
    -------
    list of StudyMetric
        The metrics.
    """
    return STUDY_METRICS.values()


def get(name: str) -> StudyMetric:
    """The study metric ``name``; an unknown name is an :class:`InputError` with a close match.

    Parameters
    ----------
    name : str
        The metric's name.

    Returns
    -------
    StudyMetric
        The metric.
    """
    return STUDY_METRICS.get(name)


def parse_entry(entry) -> tuple[str, dict]:
    """A spec's ``metrics`` entry (a name, or a table ``{name = ..., option = value}``) -> (name, options),
    the options complete (defaults filled in) and checked.

    Parameters
    ----------
    entry : str or dict
        The entry.

    Returns
    -------
    name : str
        The metric.
    options : dict
        Its options, complete and checked.

    Raises
    ------
    InputError
        An unknown metric or option, or a value out of its bounds.
    """
    if isinstance(entry, str):
        name, given = entry, {}
    elif isinstance(entry, dict):
        given = dict(entry)
        name = given.pop("name", None)
        if not isinstance(name, str):
            raise InputError(f"a metric given as a table needs a name, got {entry!r}", where="metrics")
    else:
        raise InputError(f"a metric is a name or a table with a name, got {entry!r}", where="metrics")
    metric = get(name)
    options = {}
    for key, value in given.items():
        options[key] = metric.option(key).parse(value, where=f"metrics[{name}]", text=False)
    for opt in metric.options:
        if opt.name not in options:
            if opt.required:
                raise InputError(f"metric '{name}' needs the option '{opt.name}' ({opt.help}), e.g. "
                                 f"{{ name = \"{name}\", {opt.name} = ... }}", where="metrics")
            options[opt.name] = opt.default
    return name, dict(sorted(options.items()))


def label(name: str, options: dict) -> str:
    """The metric as the table and the figures show it: ``peak_ri(speed_kmh=40)``; options at their default
    are left out (``understeer_gradient``).

    Parameters
    ----------
    name : str
        The metric's name.
    options : dict
        Its options.

    Returns
    -------
    str
        The label.
    """
    try:
        defaults = {o.name: o.default for o in get(name).options}
    except InputError:
        defaults = {}
    shown = [(k, v) for k, v in sorted(options.items()) if defaults.get(k, object()) != v]
    if not shown:
        return name
    return f"{name}({', '.join(f'{k}={v:g}' if isinstance(v, float) else f'{k}={v}' for k, v in shown)})"


# ------------------------------------------------------------------------------------------------
# the built-in metrics
# ------------------------------------------------------------------------------------------------
@study_metric("threshold", unit="km/h", per_manoeuvre=True, uses_search=True,
              help="threshold velocity: the highest speed at which a run passes (the spec's criterion: course, "
                   "lift-off or both)")
def _threshold(pset, scenario):
    from ..analysis.threshold import DEFAULT_CRITERION, threshold_velocity
    from ..analysis.verdict import Judging

    band = {k: scenario[k] for k in ("speed_band_percent", "speed_band_kmh") if scenario.get(k) is not None}
    result = threshold_velocity(pset, scenario["manoeuvre"], options=course_options(scenario), low_kmh=scenario["low_kmh"],
                                high_kmh=scenario["high_kmh"], step_kmh=scenario["step_kmh"],
                                resolution_kmh=scenario["resolution_kmh"],
                                criterion=scenario.get("criterion") or DEFAULT_CRITERION,
                                speed_control=scenario.get("speed_control") or "driver", judging=Judging(**band))
    return {"value": result.threshold_speed_kmh, **table_fields(result)}


def course_options(scenario: dict) -> dict:
    """The manoeuvre options a scenario sets: those its spec gives the manoeuvre, and the base vehicle's width
    for a course laid out from it.

    Parameters
    ----------
    scenario : dict
        The scenario.

    Returns
    -------
    dict
        The spec's ``manoeuvre_options`` and ``course_width_m`` [m] when the scenario sets it; empty for a
        manoeuvre at its defaults on its own course.
    """
    options = dict(scenario.get("manoeuvre_options") or {})
    width = scenario.get("course_width_m")
    return options if width is None else {**options, "course_width_m": width}


def table_fields(result) -> dict:
    """A threshold result as the study table's columns: its fields, the speed driven flattened
    (``driven_min_kmh``, ``driven_mean_kmh``, ``driven_max_kmh``), and the lift-off search's limit under
    ``both`` (``lift_off_limit``).

    Parameters
    ----------
    result : ThresholdResult
        The search's result.

    Returns
    -------
    dict
        Column -> value (speeds [km/h]).
    """
    out = result.to_dict()
    window = out.pop("window_speed_kmh", None) or {}
    lift = out.pop("lift_off", None)
    out.update({f"driven_{k}_kmh": window.get(k) for k in ("min", "mean", "max")})
    out["lift_off_limit"] = None if lift is None else lift.get("limit")
    return out


@study_metric("tilt_angle", unit="deg", per_manoeuvre=False,
              help="tilt-table angle at which the first wheel lifts (compliant model, the weaker side)")
def _tilt(pset, scenario):
    from ..analysis.tilt import tilt_table

    result = tilt_table(pset)
    return {"value": result.tilt_angle_deg,
            "detail": f"{result.first_lifting_wheel} lifts tilting to the {result.side}"}


@study_metric("understeer_gradient", unit="deg/g", per_manoeuvre=False,
              options=(Option("radius_m", 20.0, "m", "circle radius", minimum=1.0, maximum=1000.0),),
              help="understeer gradient, ISO 4138 constant radius (positive: understeer)")
def _understeer(pset, scenario, radius_m):
    from ..analysis.handling_tests import steady_state_test

    test = steady_state_test(pset, radius_m=radius_m)
    return {"value": float(test.diagram.understeer_gradient_deg_per_g),
            "detail": f"R = {radius_m:g} m; ends at {test.max_lateral_acceleration_mps2:.2f} m/s^2 ({test.limit})"}


_SPEED = Option("speed_kmh", None, "km/h", "speed of the run", minimum=1.0, maximum=300.0, kind=float)


def _run_metric(pset, scenario, speed_kmh, metric_name):
    from ..analysis.metrics import evaluate, first_lift
    from ..analysis.threshold import manoeuvre_builder
    from ..model.vehicle import build_model
    from ..simulate.closed_loop import run

    model = build_model(pset)
    result = run(model, manoeuvre_builder(scenario["manoeuvre"], course_options(scenario))(model.params, speed_kmh),
                 speed_control=scenario.get("speed_control") or "driver")
    value = evaluate(result, metric_name)
    lift = first_lift(result)
    detail = f"at {speed_kmh:g} km/h: " + (f"{lift.wheel} lifted at {lift.time_s:.2f} s" if lift is not None
                                           else "every wheel on the ground")
    return {"value": None if value is None else float(value), "detail": detail}


@study_metric("peak_ri", unit="-", per_manoeuvre=True, options=(_SPEED,),
              help="largest |rollover index| (Eq. 5) of a run at speed_kmh, in the judged window")
def _peak_ri(pset, scenario, speed_kmh):
    return _run_metric(pset, scenario, speed_kmh, "max_abs_ri")


@study_metric("min_wheel_load", unit="N", per_manoeuvre=True, options=(_SPEED,),
              help="smallest vertical wheel load of a run at speed_kmh, in the judged window")
def _min_wheel_load(pset, scenario, speed_kmh):
    return _run_metric(pset, scenario, speed_kmh, "min_wheel_load_N")
