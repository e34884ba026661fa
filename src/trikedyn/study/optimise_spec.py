"""Optimise specs: what ``trikedyn optimise`` moves, within which bounds, and the optimiser's settings.

A small TOML file, or a built-in name such as ``battery-layout`` (``study/specs/optimise/``)::

    [optimise]
    description = "battery within its bay"
    knobs = { "component.battery.x_m" = [0.58, 1.10], "component.battery.z_m" = [0.29, 0.44] }
    manoeuvres = ["dlc"]      # optional (default: dlc); the command's --manoeuvre replaces it
    payload_kg = 0.0          # the paper's freight aboard while searching [kg]
    seed = 1                  # differential evolution's seed
    popsize = 5               # population: popsize x number of knobs (at least 5)
    maxiter = 8               # generations after the first
    # optional: tol = 0.002, step = 0.001 (knob values rounded to this [knob unit]),
    #           resolution_kmh = 0.1, high_kmh = 90 (the threshold search),
    #           criterion = "course" (or "lift-off", "both"), speed_control = "driver" (or "ideal")

The knobs are :mod:`trikedyn.params.knobs`' (``component.NAME.x_m|y_m|z_m``, ``track_m``, ``wheelbase_m``,
...). A manoeuvre may be a path ``.csv`` file (the ``path`` manoeuvre): a file the spec names, so the one rule
holds (:mod:`trikedyn._reading`): relative to the spec's folder, in it or below it once symbolic links are
resolved (no absolute path, no ``..``; a built-in spec names shipped files only). It is read and checked when
the spec is loaded, and the spec carries its absolute path. Parsed with pydantic; a mistake is an
:class:`~trikedyn.errors.InputError` naming the file and key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from .._validation import describe_validation_error
from ..analysis.search_settings import SEARCH_DEFAULTS
from ..errors import InputError
from ..params.io import ParameterSet

__all__ = ["MAX_EVALUATIONS", "OptimiseSpec", "list_optimise_specs", "load_optimise_spec", "parse_optimise_spec",
           "population_size"]

MAX_EVALUATIONS = 20_000
"""Most layouts a run may evaluate (population x generations)."""
MAX_KNOBS = 20


# ------------------------------------------------------------------------------------------------
# the spec
# ------------------------------------------------------------------------------------------------
class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class _Optimise(_Model):
    description: str = ""
    knobs: dict[str, tuple[float, float]] = Field(
        min_length=1, max_length=MAX_KNOBS,
        description="design knob (component.NAME.x_m, track_m, wheelbase_m, ...) = [low, high] in its unit")
    manoeuvres: list[str] = Field(default=["dlc"], min_length=1, max_length=10,
                                  description="the objective is the worst threshold over these")
    payload_kg: float = Field(default=0.0, ge=0, le=2000, description="the paper's freight aboard [kg]")
    seed: int = Field(default=1, ge=0, le=2**32 - 1, description="seed of differential evolution")
    popsize: int = Field(default=5, ge=1, le=100, description="population = popsize x number of knobs (at least 5)")
    maxiter: int = Field(default=8, ge=0, le=1000, description="generations after the first")
    tol: float = Field(default=0.002, ge=0, le=1, description="stop when the population's spread of thresholds "
                       "is below tol x their mean")
    step: float = Field(default=0.001, gt=0, le=1, description="knob values are rounded to this [knob unit]")
    # the threshold search: defaults and bounds are SearchSettings' (checked in _parse, one line naming the key)
    resolution_kmh: float = Field(default=SEARCH_DEFAULTS["resolution_kmh"],
                                  description="threshold search resolution [km/h]")
    high_kmh: float = Field(default=SEARCH_DEFAULTS["high_kmh"], description="highest speed searched [km/h]")
    criterion: str = Field(default=SEARCH_DEFAULTS["criterion"], description="the threshold's pass rule (course: a "
                           "valid ISO run; lift-off: the paper's; both)")
    speed_control: str = Field(default=SEARCH_DEFAULTS["speed_control"], description="the vehicle's own drive "
                               "(driver), or an unlimited one (ideal)")

    @field_validator("knobs")
    @classmethod
    def _bounds(cls, values):
        for name, (low, high) in values.items():
            if not (math.isfinite(low) and math.isfinite(high)):
                raise ValueError(f"'{name}': bounds must be finite numbers, got [{low!r}, {high!r}]")
            if not low < high:
                raise ValueError(f"'{name}': expected [low, high] with low < high, got [{low!r}, {high!r}]")
        return values

    @field_validator("manoeuvres")
    @classmethod
    def _registered(cls, values):
        from ..manoeuvres.registry import get

        for name in values:
            if not name.lower().endswith(".csv"):
                try:
                    get(name)
                except InputError as exc:
                    raise ValueError(exc.reason) from None
        if len(set(values)) != len(values):
            raise ValueError("a manoeuvre is listed twice")
        return values


class _File(_Model):
    optimise: _Optimise


@dataclass(frozen=True)
class OptimiseSpec:
    """A validated optimise spec.

    Attributes
    ----------
    knobs : tuple of (str, float, float)
        Design knob, lower and upper bound [its unit], in the spec's order.
    manoeuvres : tuple of str
    payload_kg : float
    seed, popsize, maxiter : int
    tol, step, resolution_kmh, high_kmh : float
    criterion, speed_control : str
        The threshold search's pass rule and speed control (:class:`~trikedyn.study.designs.sample_runs.Search`).
    description, origin : str
        ``origin``: the built-in name or file path it was read from (named in error messages).
    """

    knobs: tuple[tuple[str, float, float], ...]
    manoeuvres: tuple[str, ...] = ("dlc",)
    payload_kg: float = 0.0
    seed: int = 1
    popsize: int = 5
    maxiter: int = 8
    tol: float = 0.002
    step: float = 0.001
    resolution_kmh: float = 0.1
    high_kmh: float = 90.0
    criterion: str = "course"
    speed_control: str = "driver"
    description: str = ""
    origin: str = "<string>"

    @property
    def names(self) -> list[str]:
        """The knobs' names, in the spec's order."""
        return [k[0] for k in self.knobs]

    def to_dict(self) -> dict:
        """The spec as plain JSON-ready values (what a run's plan records).

        Returns
        -------
        dict
            The spec.
        """
        return {"origin": self.origin, "description": self.description,
                "knobs": {n: [lo, hi] for n, lo, hi in self.knobs}, "manoeuvres": list(self.manoeuvres),
                "payload_kg": self.payload_kg, "seed": self.seed, "popsize": self.popsize, "maxiter": self.maxiter,
                "tol": self.tol, "step": self.step, "resolution_kmh": self.resolution_kmh, "high_kmh": self.high_kmh,
                "criterion": self.criterion, "speed_control": self.speed_control}

    def check(self, pset: ParameterSet) -> None:
        """The knobs exist on ``pset`` and their bounds lie within each knob's own bounds.

        Parameters
        ----------
        pset : ParameterSet
            The vehicle.

        Raises
        ------
        InputError
            ``where=`` the spec's origin: ``optimise.knobs: ...`` (an unknown knob or component, with a
            close match; a bound outside what the knob accepts).
        """
        from ..params.knobs import is_knob, knob_problem

        for name, low, high in self.knobs:
            if not is_knob(name):
                from ..params.knobs import _unknown

                problem = _unknown(pset.params, name)
                problem += "; the optimiser moves design knobs only"
            else:
                problem = knob_problem(pset, name, (low, high))
            if problem:
                raise InputError(f"optimise.knobs: {problem}", where=self.origin)


def _spec_dir():
    return resources.files("trikedyn.study") / "specs" / "optimise"


def list_optimise_specs() -> list[str]:
    """Names of the optimise specs shipped with trikedyn (``battery-layout``).

    Returns
    -------
    list of str
        The names.
    """
    from ..params.tomlfile import builtin_names

    return builtin_names(_spec_dir())


def load_optimise_spec(name_or_path: str | Path | OptimiseSpec) -> OptimiseSpec:
    """An optimise spec by built-in name (``"battery-layout"``) or from a TOML file.

    Parameters
    ----------
    name_or_path : str, Path or OptimiseSpec
        A built-in name, a TOML file, or a spec (returned as it is).

    Returns
    -------
    OptimiseSpec
        The spec.

    Raises
    ------
    InputError
        An unknown name (with a close match), a missing or unreadable file, invalid TOML, an unknown key
        (with a close match), a value out of range; one line naming the file and the field.
    """
    if isinstance(name_or_path, OptimiseSpec):
        return name_or_path
    from ..params.tomlfile import builtin_or_file

    text, path = builtin_or_file(name_or_path, _spec_dir(), "optimise spec", "--spec")
    if path is None:
        return _parse(text, str(name_or_path), Path(str(_spec_dir())), "the folder of the built-in specs")
    return _parse(text, str(name_or_path), path.resolve().parent, "the spec's folder")


def parse_optimise_spec(source: str | dict, origin: str = "<string>", base_dir: str | Path | None = None
                        ) -> OptimiseSpec:
    """Validate an optimise spec given as TOML text or as the dict it parses to (see the module docstring).

    ``base_dir``: the folder the spec names its path CSVs in (the working folder if None).

    Parameters
    ----------
    source : str or dict
        TOML text or its dict.
    origin : str
        Where it came from, for errors.
    base_dir : str or Path, optional
        Folder of its path CSVs.

    Returns
    -------
    OptimiseSpec
        The spec.
    """
    return _parse(source, origin, Path.cwd() if base_dir is None else Path(base_dir), "the spec's folder")


def _parse(source: str | dict, origin: str, base_dir: Path, place: str) -> OptimiseSpec:
    """:func:`parse_optimise_spec` with the folder the spec names its files in and that folder in words."""
    from ..params.tomlfile import parse_toml

    raw = parse_toml(source, origin) if isinstance(source, str) else dict(source)
    try:
        model = _File.model_validate(raw)
    except ValidationError as exc:
        raise InputError(describe_validation_error(exc, raw, _File), where=origin) from None
    o = model.optimise
    from ..analysis.search_settings import SearchSettings

    SearchSettings.from_dict(o.model_dump(), where=f"{origin}: optimise")  # one set of bounds, as the commands'
    manoeuvres = tuple(_path_csv(m, base_dir, place, origin) if m.lower().endswith(".csv") else m
                       for m in o.manoeuvres)
    return OptimiseSpec(knobs=tuple((n, float(lo), float(hi)) for n, (lo, hi) in o.knobs.items()),
                        manoeuvres=manoeuvres, payload_kg=float(o.payload_kg), seed=int(o.seed),
                        popsize=int(o.popsize), maxiter=int(o.maxiter), tol=float(o.tol), step=float(o.step),
                        resolution_kmh=float(o.resolution_kmh), high_kmh=float(o.high_kmh),
                        criterion=o.criterion, speed_control=o.speed_control, description=o.description,
                        origin=origin)


def _path_csv(name: str, base_dir: Path, place: str, origin: str) -> str:
    """The absolute path of a path CSV the spec names (the rule of :func:`trikedyn._reading.named_file`), read
    and checked as a path now (one line naming the spec and the CSV, not a failure in every evaluation)."""
    from .._reading import named_file
    from ..manoeuvres.csv_path import path_from_csv

    named = named_file(name, base_dir, expected="a path .csv file", where=origin, key="optimise.manoeuvres",
                       place=place, suffixes=(".csv",))
    try:
        path_from_csv(named.path)
    except InputError as exc:
        raise InputError(f"optimise.manoeuvres: {exc}", where=origin) from None
    return str(named.path)


def population_size(popsize: int, n_knobs: int) -> int:
    """Layouts per generation: scipy's ``max(5, popsize x n_knobs)``.

    Parameters
    ----------
    popsize : int
        scipy's population multiplier.
    n_knobs : int
        Number of knobs.

    Returns
    -------
    int
        Layouts per generation.
    """
    return max(5, popsize * max(1, n_knobs))
