"""Study specifications: a TOML file that names a vehicle and the grids to sweep (paper Tables 2-3, Fig. 10).

A study file::

    name = "paper-fig10"
    description = "..."
    vehicle = "reference-etrike"        # preset name, or a .toml file in this file's folder or below it
    manoeuvres = ["dlc", "slc"]         # registered manoeuvres (`trikedyn manoeuvres`), default options
    # or with options, as `-o KEY=VALUE` gives them: manoeuvres = ["slc", { name = "dlc", run_in_m = 40 }]
    metrics = ["threshold"]             # optional (this is the default): what each variation measures
    freight_kg = [0, 50, 100, 150, 200]
    resolution_kmh = 0.1                # threshold search resolution [km/h]
    # optional: low_kmh = 10, high_kmh = 90, step_kmh = 10 (search range and bracketing step [km/h];
    #           the bounds are the search settings', trikedyn.analysis.search_settings, as on the command line)
    # optional: criterion = "course"    # or "lift-off" (the paper's) or "both" (the threshold's pass rule)
    # optional: speed_control = "driver"  # or "ideal" (unlimited drive: the speed imposed)
    # optional: speed_band_percent = 3, speed_band_kmh = 1  (the band the speed is held to)

    [[groups]]                          # each group is a grid
    name = "stiffness"
    stiffness_scale = [0.8, 1.0, 1.2]
    damping_scale = [1.0]
    overrides = { "mass.driver_kg" = [75, 90] }   # optional; each listed value is a grid axis

    [[groups]]
    name = "layout"
    overrides = { "track_m" = [1.0, 1.2], "component.battery.z_m" = [0.25, 0.45] }   # design knobs

A manoeuvre entry is a name or a table ``{ name = "dlc", run_in_m = 40 }``: its options are checked
against the manoeuvre's option table (:class:`~trikedyn.manoeuvres.spec.ManoeuvreSpec`), a bad one refused
in one line naming it; the table, the figures and the scenario id show it as ``dlc(run_in_m=40)``. The
search settings (range, step, resolution, criterion, speed control, speed band) are a
:class:`~trikedyn.analysis.search_settings.SearchSettings`, the scale factors and freight a
:class:`~trikedyn.params.variant.Variant`'s: one set of defaults and bounds for the spec, the optimise spec
and the command line.

Metrics (:mod:`trikedyn.study.metrics`): ``threshold`` (the default), ``tilt_angle``,
``understeer_gradient`` (option ``radius_m``), ``peak_ri`` and ``min_wheel_load`` (option ``speed_kmh``,
required), or any metric registered with :func:`~trikedyn.study.metrics.study_metric`; an entry is a name
or a table ``{ name = "peak_ri", speed_kmh = 40 }``. A metric per manoeuvre runs once per manoeuvre, the
others (``tilt_angle``, ``understeer_gradient``) once per vehicle variation, with ``manoeuvre`` empty.

An override is a dotted parameter path (set as written) or a design knob (:mod:`trikedyn.params.knobs`:
``wheelbase_m``, ``track_m``, ``cg_x_fraction``, ``cg_height_m``, ``component.NAME.x_m|y_m|z_m|mass_kg``,
``freight.x_m|y_m|z_m``), which keeps the vehicle consistent. Knob values must be numbers within the knob's
bounds. A path that would vary one wheel of the pair (``wheels.rear_left.y_m = [0.5, 0.6]``: a lopsided trike) or
a component's declared place or mass without moving the CG is refused at load, pointing to the knob that
does it (``track_m``, ``wheelbase_m``, ``component.NAME.FIELD``). Both wheels of the pair set in one group
with one value each are one deliberate layout and stay allowed; :func:`trikedyn.params.override` itself
sets any path as written.

The scenarios are the union of the groups' grids (metric x manoeuvre x stiffness x damping x overrides x
freight);
a scenario that two groups share is run once and carries both group names. Every scenario has a
``scenario_id``: a short SHA-256 of its canonical JSON (vehicle, vehicle content digest, manoeuvre, freight,
scales, overrides, search settings, and the metric with its options unless it is the default threshold,
so that a spec without ``metrics`` keeps the ids it always had). The id is what the result store is keyed by, so a re-run of the same
spec finds its finished scenarios, and a changed vehicle file gives new ids instead of stale results.

A vehicle file, and a ``.tir`` given as a ``wheels.NAME.tyre_file`` override, are files a file names: the one
rule holds (:mod:`trikedyn._reading`): relative to the spec's folder, in it or below it once symbolic links are
resolved (no absolute path, no ``..``); a built-in spec names presets or shipped files only. A tyre file given
as an override is read and checked when the spec is loaded (so ``--dry-run`` refuses it), and the scenarios
carry its absolute path, so a run reads the file that was checked wherever it runs.

:func:`load_spec` does the I/O (reads the file, loads the vehicle once to check override paths and to
digest it; the keys are checked by the schema, :mod:`trikedyn.study.spec_model`, the vehicle, tyre files and
override paths by :mod:`trikedyn.study.spec_files`); the
expansion into scenarios (:func:`~trikedyn.study.scenarios.expand`,
:func:`~trikedyn.study.scenarios.count_scenarios`) is in
:mod:`trikedyn.study.scenarios`.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from ..errors import InputError
from .spec_model import validate_spec

__all__ = [
    "GroupSpec",
    "StudySpec",
    "list_specs",
    "load_spec",
    "norm",
    "parse_spec",
]



# ------------------------------------------------------------------------------------------------
# the loaded spec
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class GroupSpec:
    """One grid of a study: suspension scale factors [-] and overrides (dotted path or design knob -> values)."""

    name: str
    stiffness_scale: tuple[float, ...]
    damping_scale: tuple[float, ...]
    overrides: tuple[tuple[str, tuple[Any, ...]], ...]


@dataclass(frozen=True)
class StudySpec:
    """A validated study, ready to expand into scenarios.

    Attributes
    ----------
    name, description : str
    vehicle : str
        The vehicle as written in the spec (preset name or path relative to the spec file).
    vehicle_source : str
        What :func:`trikedyn.params.load_vehicle` reads: the preset name or the resolved file path.
    vehicle_digest : str
        Short SHA-256 of the vehicle's validated values; part of every scenario id.
    manoeuvres : tuple of str
        The manoeuvres as the table shows them: a registered name, e.g. ``"dlc"`` (ISO 3888-1) and ``"slc"``
        (ISO 14791), or with its options, ``"dlc(run_in_m=40)"`` (:attr:`manoeuvre_specs` has them).
    metrics : tuple of (str, dict)
        The study metrics (:mod:`trikedyn.study.metrics`): name and complete options; ``(("threshold", {}),)``
        by default.
    freight_kg : tuple of float
        The paper's freight in the trunk [kg] (Table 3).
    resolution_kmh, low_kmh, high_kmh, step_kmh : float
        Threshold search settings [km/h] (see :func:`trikedyn.analysis.threshold.threshold_velocity`).
    criterion : str
        The threshold's pass rule: ``"course"``, ``"lift-off"`` or ``"both"``.
    speed_control : str
        ``"driver"`` or ``"ideal"`` (every run of a metric per manoeuvre).
    speed_band_percent, speed_band_kmh : float
        The band the speed is held to [%, km/h] (:class:`~trikedyn.analysis.verdict.Judging`).
    course_width_m : float or None
        The base vehicle's overall width [m]: a course that follows the vehicle's width (the double lane
        change's lanes) is laid out for it in every scenario, so that a wider variant meets the same course.
    groups : tuple of GroupSpec
    origin : str
        Spec name or file path it was read from.
    manoeuvre_specs : tuple of ManoeuvreSpec
        Each manoeuvre with its options (:class:`~trikedyn.manoeuvres.spec.ManoeuvreSpec`); empty: the
        :attr:`manoeuvres` by name with default options.
    """

    name: str
    description: str
    vehicle: str
    vehicle_source: str
    vehicle_digest: str
    manoeuvres: tuple[str, ...]
    freight_kg: tuple[float, ...]
    resolution_kmh: float
    low_kmh: float
    high_kmh: float
    step_kmh: float
    groups: tuple[GroupSpec, ...]
    origin: str = "<string>"
    metrics: tuple[tuple[str, dict], ...] = (("threshold", {}),)
    criterion: str = "course"
    speed_control: str = "driver"
    speed_band_percent: float = 3.0
    speed_band_kmh: float = 1.0
    course_width_m: float | None = None
    manoeuvre_specs: tuple = ()

    @property
    def manoeuvre_list(self) -> tuple:
        """Each manoeuvre with its options (:class:`~trikedyn.manoeuvres.spec.ManoeuvreSpec`), in the spec's order."""
        if self.manoeuvre_specs:
            return self.manoeuvre_specs
        from ..manoeuvres.spec import ManoeuvreSpec

        return tuple(ManoeuvreSpec(m) for m in self.manoeuvres)

    @property
    def search(self):
        """The threshold search's settings (:class:`~trikedyn.analysis.search_settings.SearchSettings`)."""
        from ..analysis.search_settings import SearchSettings

        return SearchSettings(low_kmh=self.low_kmh, high_kmh=self.high_kmh, step_kmh=self.step_kmh,
                              resolution_kmh=self.resolution_kmh, criterion=self.criterion,
                              speed_control=self.speed_control, speed_band_percent=self.speed_band_percent,
                              speed_band_kmh=self.speed_band_kmh)

    def load_vehicle(self):
        """The study's base vehicle (:class:`~trikedyn.params.parameter_set.ParameterSet`), before any variation.

        Returns
        -------
        ParameterSet
            The base vehicle.
        """
        from ..params import load_vehicle

        return load_vehicle(self.vehicle_source)


def norm(value):
    """Numbers as float (so that 75 and 75.0 give the same scenario), other scalars as they are.

    Parameters
    ----------
    value : object
        A value of a study axis or an override.

    Returns
    -------
    object
        ``float(value)`` for an int or a float (not a bool), else ``value`` itself.
    """
    if isinstance(value, bool) or not isinstance(value, int | float):
        return value
    return float(value)


def _spec_dir():
    return resources.files("trikedyn.study") / "specs"


def list_specs() -> list[str]:
    """Names of the study specs shipped with trikedyn (``paper``: the paper's Fig. 10).

    Returns
    -------
    list of str
        The names.
    """
    from ..params.tomlfile import builtin_names

    return builtin_names(_spec_dir())


def load_spec(name_or_path: str | Path | StudySpec) -> StudySpec:
    """Load a study spec by name (``"paper"``) or from a TOML file.

    Parameters
    ----------
    name_or_path : str, Path or StudySpec
        A built-in name, a TOML file, or a spec (returned as it is).

    Returns
    -------
    StudySpec
        The spec.

    Raises
    ------
    InputError
        Unknown spec name (with a close match), unreadable TOML, unknown key (with a close match), a value
        out of range, an unknown vehicle or override path.
    """
    if isinstance(name_or_path, StudySpec):
        return name_or_path
    from ..params.tomlfile import builtin_or_file

    text, path = builtin_or_file(name_or_path, _spec_dir(), "study spec", "study")
    if path is None:
        return _parse(text, str(name_or_path), Path(str(_spec_dir())), "the folder of the built-in specs")
    return _parse(text, str(name_or_path), path.resolve().parent, "the spec's folder")


def parse_spec(source: str | dict, origin: str = "<string>", base_dir: str | Path | None = None) -> StudySpec:
    """Validate a study given as TOML text or as a dict.

    Parameters
    ----------
    source : str or dict
        TOML text, or the table it parses to.
    origin : str
        Name shown in error messages.
    base_dir : path, optional
        The folder the spec's files are named in (the spec file's; the working folder if None): a vehicle
        path and a ``tyre_file`` override lie in it or below it.

    Returns
    -------
    StudySpec
        The spec.
    """
    return _parse(source, origin, Path.cwd() if base_dir is None else Path(base_dir), "the spec's folder")


def _parse(source: str | dict, origin: str, base_dir: Path, place: str) -> StudySpec:
    """:func:`parse_spec` with the folder the spec names its files in and that folder in words."""
    from ..params.tomlfile import parse_toml

    raw = parse_toml(source, origin) if isinstance(source, str) else dict(source)
    model = validate_spec(raw, origin)
    from ..analysis.search_settings import SearchSettings
    from ..manoeuvres.spec import ManoeuvreSpec

    search = SearchSettings.from_dict(model.model_dump(), where=origin)
    manoeuvres = tuple(ManoeuvreSpec.from_entry(entry, where=f"{origin}: manoeuvres[{i}]")
                       for i, entry in enumerate(model.manoeuvres))
    names = [g.name for g in model.groups]
    dup = next((n for n in names if names.count(n) > 1), None)
    if dup is not None:
        raise InputError(f"groups: the name '{dup}' is used twice; group names must be unique", where=origin)

    from .spec_files import override_problem, resolve_vehicle, tyre_files

    vehicle_source = resolve_vehicle(model.vehicle, base_dir, place, origin)
    from ..errors import ParameterError
    from ..params import load_vehicle

    try:
        pset = load_vehicle(vehicle_source)
    except ParameterError as exc:
        raise InputError(f"vehicle: {exc}", where=origin) from None
    plain = pset.params.model_dump(mode="json")
    overrides = {g.name: tyre_files(g.name, g.overrides, base_dir, place, origin) for g in model.groups}
    for group in model.groups:
        for dotted, values in overrides[group.name].items():
            problem = override_problem(pset.params, plain, dotted, values, overrides[group.name])
            if problem:
                raise InputError(f"groups[{group.name}].overrides: {problem}", where=origin)
    digest = hashlib.sha256(pset.params.model_dump_json().encode()).hexdigest()[:12]
    metrics = _parse_metrics(model.metrics, origin)

    groups = tuple(
        GroupSpec(
            name=g.name,
            stiffness_scale=tuple(float(v) for v in g.stiffness_scale),
            damping_scale=tuple(float(v) for v in g.damping_scale),
            overrides=tuple((k, tuple(norm(v) for v in vals)) for k, vals in overrides[g.name].items()),
        )
        for g in model.groups
    )
    return StudySpec(
        name=model.name,
        description=model.description,
        vehicle=model.vehicle,
        vehicle_source=vehicle_source,
        vehicle_digest=digest,
        manoeuvres=tuple(m.label for m in manoeuvres),
        freight_kg=tuple(float(v) for v in model.freight_kg),
        resolution_kmh=search.resolution_kmh,
        low_kmh=search.low_kmh,
        high_kmh=search.high_kmh,
        step_kmh=search.step_kmh,
        groups=groups,
        origin=origin,
        metrics=metrics,
        criterion=search.criterion,
        speed_control=search.speed_control,
        speed_band_percent=search.speed_band_percent,
        speed_band_kmh=search.speed_band_kmh,
        course_width_m=float(pset.params.body.overall_width_m),
        manoeuvre_specs=manoeuvres,
    )


def _parse_metrics(entries, origin: str) -> tuple[tuple[str, dict], ...]:
    """The spec's metric entries, checked against the registry, options complete; the same metric twice
    (with the same options) is refused."""
    from .metrics import label, parse_entry

    parsed: list[tuple[str, dict]] = []
    for entry in entries:
        try:
            name, options = parse_entry(entry)
        except InputError as exc:
            raise InputError(f"{exc.where}: {exc.reason}", where=origin) from None
        if (name, options) in parsed:
            raise InputError(f"metrics: '{label(name, options)}' is listed twice", where=origin)
        parsed.append((name, options))
    return tuple(parsed)
