"""The figures a run is judged by, over the manoeuvre's judged window only.

Every metric is a function of a :class:`~trikedyn.simulate.result.Result` registered with :func:`metric`;
:func:`summary` evaluates them all (``trikedyn simulate --json``), :func:`evaluate` one by name. They read
the samples inside the manoeuvre's window (the ``judged`` channel: entry gate to exit gate), never the
run-out beyond it; a run without a manoeuvre (open-loop :func:`~trikedyn.simulate.run.simulate`) is judged
over all of it. Nothing is written into the result.

Rollover index (paper Eq. 5): ``RI = (F_R - F_L) / (F_R + F_L)`` over the two-wheel axle, |RI| = 1 when a
wheel of the pair lifts; load-transfer ratio likewise over all wheels.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..registry import Registry, first_line
from ..simulate.result import load_transfer_ratio, rollover_index
from .window import Lift, cone_strikes, first_lift, judged_mask, until_exit
from .window import wheel_loads as _wheel_loads

__all__ = ["METRICS", "Lift", "MetricType", "cone_strikes", "evaluate", "first_lift", "judged_mask", "load_transfer_ratio",
           "metric", "metrics", "rollover_index", "summary", "until_exit"]


@dataclass(frozen=True)
class MetricType:
    """A registered metric: its name (with its unit), what it means, and the function."""

    name: str
    unit: str
    help: str
    fn: Callable


METRICS: Registry[MetricType] = Registry("metric", group="trikedyn.metrics", where="metric")
"""The registered run metrics (plug-ins: entry-point group ``trikedyn.metrics``)."""


def metric(name: str, unit: str = "", help: str = "", *, replace: bool = False):  # noqa: A002 - the word users see
    """Decorator: register ``fn(result) -> number | None`` as a metric (a taken ``name`` raises ValueError
    unless ``replace=True``).

    Parameters
    ----------
    name : str
        The metric's name.
    unit : str
        Its unit, for tables.
    help : str
        One line; the function's first docstring line by default.
    replace : bool
        Replace an existing metric.

    Returns
    -------
    callable
        The decorator.
    """

    def decorate(fn):
        """Register ``fn`` as the metric ``name`` and return it unchanged."""
        METRICS.register(name, MetricType(name, unit, help or first_line(fn), fn), replace=replace)
        return fn

    return decorate


def metrics() -> list[MetricType]:
    """Every registered metric.

    Returns
    -------
    list of MetricType
        Name, unit, help and function of each.
    """
    return METRICS.values()


def evaluate(result, name: str):
    """The metric ``name`` of a run (:class:`InputError` with a close match for an unknown name).

    Parameters
    ----------
    result : Result
        A run.
    name : str
        A registered metric.

    Returns
    -------
    float or None
        The metric, in its unit (:func:`metrics` lists them).
    """
    return METRICS.get(name).fn(result)


def _judged(result, channel: str) -> np.ndarray:
    return np.asarray(result[channel])[judged_mask(result)]


def _max_abs(values: np.ndarray) -> float | None:
    values = values[np.isfinite(values)]
    return float(np.abs(values).max()) if values.size else None


# ------------------------------------------------------------------------------------------------------------
# the metrics
# ------------------------------------------------------------------------------------------------------------
@metric("max_abs_ri", "", "largest |rollover index| (Eq. 5) in the window")
def _max_abs_ri(result):
    return _max_abs(_judged(result, "ri"))


@metric("max_abs_ri_all_wheels_down", "", "largest |RI| in the window while every wheel is on the ground")
def _max_abs_ri_down(result):
    down = (_wheel_loads(result) > 0).all(axis=1) & judged_mask(result)
    return _max_abs(np.asarray(result["ri"])[down])


@metric("max_abs_ltr", "", "largest |load-transfer ratio| in the window")
def _max_abs_ltr(result):
    return _max_abs(_judged(result, "ltr"))


@metric("min_wheel_load_N", "N", "smallest vertical force of any wheel in the window")
def _min_wheel_load(result):
    fz = _wheel_loads(result)[judged_mask(result)]
    return float(fz.min()) if fz.size else None


@metric("wheel_lifted", "", "whether a wheel left the ground in the window")
def _wheel_lifted(result):
    return first_lift(result) is not None


@metric("lift_time_s", "s", "time of the first wheel lift in the window")
def _lift_time(result):
    lift = first_lift(result)
    return None if lift is None else lift.time_s


@metric("lifted_wheel", "", "the wheel that lifted first in the window")
def _lifted_wheel(result):
    lift = first_lift(result)
    return None if lift is None else lift.wheel


@metric("cone_strikes", "", "cones struck in the window")
def _cone_strikes(result):
    return len(cone_strikes(result))


@metric("max_lateral_acceleration_mps2", "m/s^2", "largest |lateral acceleration| at the CG in the window")
def _max_ay(result):
    return _max_abs(_judged(result, "ay_mps2"))


@metric("max_yaw_rate_radps", "rad/s", "largest |yaw rate| in the window")
def _max_yaw_rate(result):
    return _max_abs(_judged(result, "yaw_rate_radps"))


@metric("max_path_error_m", "m", "largest |lateral path error| of the CG in the window")
def _max_path_error(result):
    if "path_error_m" not in result.channels:
        return None
    return _max_abs(_judged(result, "path_error_m"))


@metric("max_speed_kmh", "km/h", "highest speed in the window")
def _max_speed(result):
    v = _judged(result, "speed_mps")
    return float(v.max() * 3.6) if v.size else None


@metric("min_speed_kmh", "km/h", "lowest speed in the window")
def _min_speed(result):
    v = _judged(result, "speed_mps")
    return float(v.min() * 3.6) if v.size else None


@metric("max_abs_roll_deg", "deg", "largest |roll angle| in the window")
def _max_roll(result):
    value = _max_abs(_judged(result, "roll_rad"))
    return None if value is None else math.degrees(value)


@metric("window_complete", "", "whether the run reached the exit gate")
def _window_complete(result):
    man = result.manoeuvre
    if man is None:
        return result.success
    w = man.window
    reached = float(np.max(result["path_s_m"])) if w.kind == "distance" else float(result.time_s[-1])
    return bool(reached >= w.end - 1e-9)


def summary(result, judging=None) -> dict:
    """Every metric of a run, with its verdict, the speed it drove, the manoeuvre, status and judged window
    (``trikedyn simulate --json``).

    ``passed`` and ``verdict`` say how the vehicle did (:func:`trikedyn.analysis.verdict.judge`, with
    ``judging``'s speed band and limits), ``reasons`` everything that went wrong; ``success`` only that the
    simulation ran to its end.

    Parameters
    ----------
    result : Result
        A run.
    judging : Judging, optional
        Speed band and limits for the verdict; defaults otherwise.

    Returns
    -------
    dict
        Metric name -> value, with the verdict, speeds, manoeuvre, status and window, JSON-safe.
    """
    from .verdict import judge

    mask = judged_mask(result)
    times = result.time_s[mask]
    verdict = judge(result, judging)
    out = {
        "manoeuvre": result.meta.get("manoeuvre", "open loop"),
        **verdict.to_dict(),
        "status": result.status,
        "success": result.success,
        "duration_s": float(result.time_s[-1]),
        "window_s": [float(times[0]), float(times[-1])] if times.size else None,
    }
    for m in METRICS.values():
        out[m.name] = m.fn(result)
    return out
