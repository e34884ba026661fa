"""The threshold search's settings as one value that travels, with one set of defaults and bounds.

:class:`SearchSettings` holds what a threshold search (:func:`~trikedyn.analysis.threshold.threshold_velocity`)
is asked: the speed range, the bracketing step and the resolution [km/h], how the runs are chosen, what a
run must do to pass, how the speed is held and the band it is held to. Every setting is an
:class:`~trikedyn.options.Option` of :func:`search_options` (default, unit, bounds, choices): the command
line's options (``trikedyn threshold --high``, ``sensitivity``, ``loading-chart``, ``compare-layouts``,
``optimise``, ...), the study spec and the optimise spec read their defaults and bounds from there, so the
same value is refused the same way wherever it is given.

Example::

    from trikedyn.analysis.search_settings import SearchSettings

    settings = SearchSettings(high_kmh=120.0, criterion="lift-off")
    threshold_velocity(pset, "slc", **settings.threshold_kwargs())
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields, replace
from functools import lru_cache
from types import MappingProxyType
from typing import Any

from ..errors import InputError
from ..options import Option, checked, find_option

__all__ = ["CRITERIA", "DEFAULT_CRITERION", "SEARCH_DEFAULTS", "SearchSettings", "search_option", "search_options"]

CRITERIA = ("course", "lift-off", "both")
"""What a search judges its runs by (:mod:`trikedyn.analysis.criteria`)."""
DEFAULT_CRITERION = "course"
"""The default criterion: a threshold an engineer can sign is a speed at which the run is a valid test."""

_DEFAULTS: dict[str, Any] = {
    "low_kmh": 10.0,
    "high_kmh": 90.0,
    "step_kmh": 10.0,
    "resolution_kmh": 0.1,
    "method": "margin",
    "criterion": DEFAULT_CRITERION,
    "speed_control": "driver",
    "speed_band_percent": 3.0,
    "speed_band_kmh": 1.0,
}
SEARCH_DEFAULTS = MappingProxyType(_DEFAULTS)
"""Every setting's default (read-only; light to import: the command line's option defaults come from here)."""


@lru_cache(maxsize=1)
def search_options() -> tuple[Option, ...]:
    """The settings of a threshold search, each with its default, unit and bounds (inclusive).

    Returns
    -------
    tuple of Option
        ``low_kmh`` [0.1, 400], ``high_kmh`` [1, 400], ``step_kmh`` [0.1, 400], ``resolution_kmh``
        [0.001, 10] (all km/h), ``method``, ``criterion``, ``speed_control`` (words) and
        ``speed_band_percent`` [0, 100] %, ``speed_band_kmh`` [0, 100] km/h.
    """
    from ..simulate.defaults import SPEED_CONTROLS

    d = _DEFAULTS
    return (
        Option("low_kmh", d["low_kmh"], "km/h", "lowest speed searched", minimum=0.1, maximum=400.0),
        Option("high_kmh", d["high_kmh"], "km/h", "highest speed searched (with the driver's speed control a "
               "search stops at the vehicle's top speed when that is lower)", minimum=1.0, maximum=400.0),
        Option("step_kmh", d["step_kmh"], "km/h", "bracketing step", minimum=0.1, maximum=400.0),
        Option("resolution_kmh", d["resolution_kmh"], "km/h", "resolution of the threshold", minimum=0.001,
               maximum=10.0),
        Option("method", d["method"], "", "how the runs are chosen (:data:`~trikedyn.analysis.threshold.METHODS`: "
               "margin, by extrapolated margins; bisection; ...; checked by the search)", kind=str),
        Option("criterion", d["criterion"], "", "what a run must do to pass: course (ISO 3888-1 validity), "
               "lift-off (the paper's) or both", choices=CRITERIA),
        Option("speed_control", d["speed_control"], "", "driver (the vehicle's own drive, within its limits) or "
               "ideal (unlimited drive and brakes)", choices=SPEED_CONTROLS),
        Option("speed_band_percent", d["speed_band_percent"], "%", "half-width of the band the speed is held to "
               "through the judged window, in per cent of the target", minimum=0.0, maximum=100.0),
        Option("speed_band_kmh", d["speed_band_kmh"], "km/h", "smallest half-width of the speed band (the band "
               "is the larger of the two)", minimum=0.0, maximum=100.0),
    )


def search_option(name: str) -> Option:
    """One setting of :func:`search_options` by name (an :class:`InputError` with a close match if none).

    Parameters
    ----------
    name : str
        ``low_kmh``, ``high_kmh``, ``step_kmh``, ``resolution_kmh``, ``method``, ``criterion``,
        ``speed_control``, ``speed_band_percent`` or ``speed_band_kmh``.

    Returns
    -------
    Option
        The setting: default, unit, bounds or choices.
    """
    return find_option(search_options(), name, "a threshold search", "search settings")


@dataclass(frozen=True)
class SearchSettings:
    """What a threshold search is asked (see :func:`~trikedyn.analysis.threshold.threshold_velocity`).

    Parameters
    ----------
    low_kmh, high_kmh : float
        The speed range searched [km/h]; ``low_kmh < high_kmh``.
    step_kmh : float
        Bracketing step [km/h].
    resolution_kmh : float
        Resolution of the threshold [km/h].
    method : str
        How the runs are chosen (:data:`~trikedyn.analysis.threshold.METHODS`: ``"margin"``, ``"bisection"``,
        ...).
    criterion : {"course", "lift-off", "both"}
        What a run must do to pass.
    speed_control : {"driver", "ideal"}
        The vehicle's own drive and brakes, or unlimited ones.
    speed_band_percent : float
        Half-width of the speed band [% of the target].
    speed_band_kmh : float
        Smallest half-width of the speed band [km/h]; not both zero.

    Raises
    ------
    InputError
        A value out of its bounds (:func:`search_options`), a word not among the choices, ``low_kmh`` not
        below ``high_kmh``, or a speed band of zero width; the message names the setting.
    """

    low_kmh: float = _DEFAULTS["low_kmh"]
    high_kmh: float = _DEFAULTS["high_kmh"]
    step_kmh: float = _DEFAULTS["step_kmh"]
    resolution_kmh: float = _DEFAULTS["resolution_kmh"]
    method: str = _DEFAULTS["method"]
    criterion: str = _DEFAULTS["criterion"]
    speed_control: str = _DEFAULTS["speed_control"]
    speed_band_percent: float = _DEFAULTS["speed_band_percent"]
    speed_band_kmh: float = _DEFAULTS["speed_band_kmh"]

    def __post_init__(self):
        for opt in search_options():
            object.__setattr__(self, opt.name, checked(opt, getattr(self, opt.name)))
        if self.low_kmh >= self.high_kmh:
            raise InputError(f"low_kmh ({self.low_kmh:g}) must be below high_kmh ({self.high_kmh:g})",
                             where="high_kmh")
        if self.speed_band_percent == 0 and self.speed_band_kmh == 0:
            raise InputError("speed_band_percent and speed_band_kmh are both 0: no speed can be held",
                             where="speed_band_kmh")

    @classmethod
    def from_dict(cls, data: dict, where: str = "") -> SearchSettings:
        """Settings from a mapping (a spec, a plan file); keys not given take their defaults, other keys are
        left out.

        Parameters
        ----------
        data : dict
            Setting name -> value.
        where : str
            Prefix of an error's place (a file's name).

        Returns
        -------
        SearchSettings
            The settings.
        """
        names = {f.name for f in fields(cls)}
        try:
            return cls(**{k: v for k, v in data.items() if k in names and v is not None})
        except InputError as exc:
            if not where:
                raise
            raise InputError(f"{exc.where}: {exc.reason}", where=where) from None

    def to_dict(self) -> dict:
        """The settings as JSON-safe data, in the order of :func:`search_options`.

        Returns
        -------
        dict
            Setting name -> value ([km/h], [%] or a word).
        """
        return asdict(self)

    def with_(self, **changes) -> SearchSettings:
        """These settings with some changed (checked again).

        Parameters
        ----------
        **changes
            Setting name -> new value.

        Returns
        -------
        SearchSettings
            The new settings.
        """
        return replace(self, **changes)

    def judging(self):
        """The speed band as the :class:`~trikedyn.analysis.verdict.Judging` a search judges its runs by.

        Returns
        -------
        Judging
            The band [%, km/h], the path and spin limits at their defaults.
        """
        from .verdict import Judging

        return Judging(speed_band_percent=self.speed_band_percent, speed_band_kmh=self.speed_band_kmh)

    def threshold_kwargs(self) -> dict:
        """The keyword arguments of :func:`~trikedyn.analysis.threshold.threshold_velocity` these settings
        give.

        Returns
        -------
        dict
            ``low_kmh``, ``high_kmh``, ``step_kmh``, ``resolution_kmh`` [km/h], ``method``, ``criterion``,
            ``speed_control`` and ``judging``.
        """
        return {"low_kmh": self.low_kmh, "high_kmh": self.high_kmh, "step_kmh": self.step_kmh,
                "resolution_kmh": self.resolution_kmh, "method": self.method, "criterion": self.criterion,
                "speed_control": self.speed_control, "judging": self.judging()}
