"""The search each sample of a sampled design runs: the threshold velocity on a manoeuvre (its range,
resolution, criterion and speed control), or any registered study metric (:mod:`trikedyn.study.metrics`)
(:class:`Search`); and :func:`raise_interrupt`, which tells a Ctrl-C that landed in compiled code from a failed
search.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ...errors import InputError, SimulationError
from ...params.io import ParameterSet
from ...simulate import DEFAULT_DT_S

__all__ = ["Search", "raise_interrupt"]


@dataclass(frozen=True)
class Search:
    """The threshold search each sample runs (:func:`~trikedyn.analysis.threshold.threshold_velocity`):
    the manoeuvre with its options, the range and resolution [km/h], the time step [s], the criterion
    (``"course"``, ``"lift-off"`` or ``"both"``: the course threshold is then the value) and the speed control
    (``"driver"`` or ``"ideal"``). With a ``metric`` other than ``"threshold"``, each sample measures that
    registered study metric (:mod:`trikedyn.study.metrics`: ``tilt_angle``, ``understeer_gradient``, ...) with
    its ``metric_options`` instead (the manoeuvre and speed control for the metrics that run one)."""

    manoeuvre: str = "dlc"
    options: dict = field(default_factory=dict)
    resolution_kmh: float = 0.1
    low_kmh: float = 10.0
    high_kmh: float = 90.0
    dt_s: float | None = None
    criterion: str = "course"
    speed_control: str = "driver"
    metric: str = "threshold"
    metric_options: dict = field(default_factory=dict)

    def __post_init__(self):
        from ...analysis.search_settings import SearchSettings

        # the range, resolution, criterion and speed control by the search settings' one set of bounds
        SearchSettings(low_kmh=self.low_kmh, high_kmh=self.high_kmh, resolution_kmh=self.resolution_kmh,
                       criterion=self.criterion, speed_control=self.speed_control)
        if self.metric != "threshold" or self.metric_options:
            from ..metrics import parse_entry

            try:  # the options complete (defaults filled in) and checked
                _, options = parse_entry({"name": self.metric, **self.metric_options})
            except InputError as exc:
                raise InputError(exc.reason, where="--metric") from None
            object.__setattr__(self, "metric_options", options)

    @property
    def unit(self) -> str:
        """The unit of what each sample measures (``km/h`` for the threshold)."""
        from ..metrics import get

        return get(self.metric).unit

    def to_dict(self) -> dict:
        """The settings, as a plan file records them.

        Returns
        -------
        dict
            Manoeuvre, options, speeds [km/h], time step [s], criterion, speed control.
        """
        return {"manoeuvre": self.manoeuvre, "options": dict(self.options), "resolution_kmh": self.resolution_kmh,
                "low_kmh": self.low_kmh, "high_kmh": self.high_kmh, "dt_s": self.dt_s, "criterion": self.criterion,
                "speed_control": self.speed_control,
                **({"metric": self.metric, "metric_options": dict(self.metric_options)}
                   if self.metric != "threshold" else {})}

    def on_course_of(self, pset: ParameterSet) -> Search:
        """This search with its course laid out for ``pset``, the reference vehicle of a design: a manoeuvre
        whose course follows the vehicle's width (the double lane change's ``course_width_m``: ISO 3888's lane
        widths) gets ``pset``'s width, so that a wider variant meets the same course; unless the options give
        one (``course_width_m = 0`` asks for each variant's own).

        For designs that compare vehicles (the optimiser, the loading chart, a study's grid). Sensitivity and
        uncertainty do not use it: they ask what the threshold of *this* vehicle is when an assumed value is
        off, and by ISO 3888 the course of a vehicle of another width is laid out for that width.

        Parameters
        ----------
        pset : ParameterSet
            The vehicle. (the design's reference)

        Returns
        -------
        Search
            The search (itself when the course does not follow the width).
        """
        if self.manoeuvre.lower().endswith(".csv") or "course_width_m" in self.options:
            return self
        from ...manoeuvres.registry import get

        if any(o.name == "course_width_m" for o in get(self.manoeuvre).options):
            return replace(self, options={**self.options, "course_width_m": float(pset.params.body.overall_width_m)})
        return self

    def course_note(self) -> str | None:
        """Which course the variants meet, in words (None when the manoeuvre's course is the same for all).

        Returns
        -------
        str or None
            The note.
        """
        if "course_width_m" not in self.options:
            return None
        width = float(self.options["course_width_m"])
        if width == 0:
            return "course: the lanes laid out for each variant's own width"
        return (f"course: the lanes laid out for a {width:.3f} m wide vehicle, the reference's width, for every variant "
                "(-o course_width_m=0: each variant's own)")

    def run(self, pset: ParameterSet, dt_s: float | None = None):
        """The threshold search on ``pset``, with the time step ``dt_s`` [s] (default: :attr:`dt_s`; None: the
        loop's automatic step, :func:`~trikedyn.simulate.run.automatic_step`).

        Parameters
        ----------
        pset : ParameterSet
            The vehicle.
        dt_s : float, optional
            Time step [s].

        Returns
        -------
        ThresholdResult
            The search's result.
        """
        from ...analysis.threshold import threshold_velocity

        return threshold_velocity(pset, self.manoeuvre, options=dict(self.options), low_kmh=self.low_kmh,
                                  high_kmh=self.high_kmh, resolution_kmh=self.resolution_kmh,
                                  dt=self.dt_s if dt_s is None else dt_s, criterion=self.criterion,
                                  speed_control=self.speed_control)

    def threshold(self, pset: ParameterSet) -> tuple[float | None, str | None]:
        """The threshold velocity [km/h] of ``pset``, or None and why there is none (see :meth:`outcome`).

        Parameters
        ----------
        pset : ParameterSet
            The vehicle.

        Returns
        -------
        threshold : float or None
            [km/h].
        error : str or None
            Why there is none.
        """
        speed, error, _ = self.outcome(pset)
        return speed, error

    def outcome(self, pset: ParameterSet) -> tuple[float | None, str | None, str]:
        """The threshold velocity [km/h] of ``pset`` or None, why there is none or None, and what limits it.

        The limit is what failed above the threshold (:mod:`trikedyn.analysis.threshold`: ``"lift-off"``,
        ``"tracking"``, ``"cone strike"``, ``"speed not held"``, ``"top speed"``, ...) or ``""`` (no threshold,
        or none found up to the top of the range). Never raises for a failed search: a
        sampled study reports it and goes on. A variant whose fastest mode needs a finer time step than
        :attr:`dt_s` (a stiffer or lighter part) is searched again with half the step.

        Parameters
        ----------
        pset : ParameterSet
            The vehicle.

        Returns
        -------
        threshold : float or None
            [km/h].
        error : str or None
            Why there is none.
        limit : str
            What limits it.
        """
        from ..engine.executors import one_line

        if self.metric != "threshold":
            return self._measure(pset)
        try:
            try:
                result = self.run(pset)
            except SimulationError as exc:
                if "time step too large" not in str(exc):
                    raise
                result = self.run(pset, dt_s=(self.dt_s or DEFAULT_DT_S) / 2)
        except Exception as exc:  # noqa: BLE001 - a vehicle that cannot be searched is reported, the study goes on
            raise_interrupt(exc)
            return None, one_line(exc), ""
        if result.threshold_speed_kmh is None:
            return None, f"no threshold: {' '.join(str(result.detail).split())}", ""
        return float(result.threshold_speed_kmh), None, result.limit or ""


    def _measure(self, pset: ParameterSet) -> tuple[float | None, str | None, str]:
        """The search's study metric (not the threshold) of ``pset``, as :meth:`outcome` gives it."""
        from ..engine.executors import one_line
        from ..metrics import get

        scenario = {"manoeuvre": self.manoeuvre, "manoeuvre_options": dict(self.options),  # -o, as a spec's
                    "speed_control": self.speed_control, "criterion": self.criterion,
                    "course_width_m": self.options.get("course_width_m"), "low_kmh": self.low_kmh,
                    "high_kmh": self.high_kmh, "resolution_kmh": self.resolution_kmh}
        try:
            result = get(self.metric).fn(pset, scenario, **self.metric_options)
        except Exception as exc:  # noqa: BLE001 - a vehicle that cannot be measured is reported, the study goes on
            raise_interrupt(exc)
            return None, one_line(exc), ""
        value = result.get("value")
        if value is None or not np.isfinite(float(value)):
            return None, f"no {self.metric}: {' '.join(str(result.get('detail') or '').split())}", ""
        return float(value), None, ""


def raise_interrupt(exc: BaseException) -> None:
    """Raise KeyboardInterrupt if ``exc`` came of one: a Ctrl-C that lands in compiled code (numba) comes back
    as a ``SystemError`` ("returned a result with an exception set") caused by it, which a search must not
    report as a failed sample: the run was interrupted, the sample is not done.

    Parameters
    ----------
    exc : BaseException
        The exception a search raised.

    Raises
    ------
    KeyboardInterrupt
        When ``exc`` or one of its causes is one.
    """
    seen: BaseException | None = exc
    for _ in range(32):  # the chain of causes, bounded
        if seen is None:
            return
        if isinstance(seen, KeyboardInterrupt):
            raise KeyboardInterrupt from exc
        seen = seen.__cause__ or seen.__context__
