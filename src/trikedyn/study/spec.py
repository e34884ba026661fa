"""Study specifications: a TOML file that names a vehicle and the grids to sweep (paper Tables 2-3, Fig. 10).

A study file::

    name = "paper-fig10"
    description = "..."
    vehicle = "reference-etrike"        # preset name, or a .toml path relative to this file
    manoeuvres = ["dlc", "slc"]         # registered manoeuvres (`trikedyn manoeuvres`), default options
    metrics = ["threshold"]             # optional (this is the default): what each variation measures
    freight_kg = [0, 50, 100, 150, 200]
    resolution_kmh = 0.1                # threshold search: bisection resolution [km/h]
    # optional: low_kmh = 10, high_kmh = 90, step_kmh = 10 (search range and bracketing step [km/h])

    [[groups]]                          # each group is a grid
    name = "stiffness"
    stiffness_scale = [0.8, 1.0, 1.2]
    damping_scale = [1.0]
    overrides = { "mass.driver_kg" = [75, 90] }   # optional; each listed value is a grid axis

    [[groups]]
    name = "layout"
    overrides = { "track_m" = [1.0, 1.2], "component.battery.z_m" = [0.25, 0.45] }   # design knobs

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

:func:`load_spec` does the I/O (reads the file, loads the vehicle once to check override paths and to
digest it); :func:`expand` is a pure function of the loaded spec. :func:`count_scenarios` counts what
:func:`expand` would give without building it, so that a run can refuse a spec that expands to millions
of scenarios (a few lines of TOML can) before it spends the memory.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import tomllib
from dataclasses import dataclass
from difflib import get_close_matches
from importlib import resources
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from .._validation import describe_validation_error
from ..errors import InputError

__all__ = [
    "GroupSpec",
    "StudySpec",
    "canonical_json",
    "count_scenarios",
    "expand",
    "list_specs",
    "load_spec",
    "parse_spec",
    "scenario_id",
]

SCENARIO_KEYS = (
    "scenario_id",
    "groups",
    "vehicle",
    "vehicle_digest",
    "manoeuvre",
    "freight_kg",
    "stiffness_scale",
    "damping_scale",
    "overrides",
    "resolution_kmh",
    "low_kmh",
    "high_kmh",
    "step_kmh",
    "metric",
    "metric_options",
    "metric_label",
)
"""Keys of a scenario dict, in this order."""

_NOT_HASHED = ("scenario_id", "groups", "metric_label")


# ------------------------------------------------------------------------------------------------
# validation models (TOML -> checked values)
# ------------------------------------------------------------------------------------------------
class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


Scalar = float | int | bool | str


class _Group(_Model):
    name: str = Field(min_length=1)
    stiffness_scale: list[float] = Field(default=[1.0], min_length=1)
    damping_scale: list[float] = Field(default=[1.0], min_length=1)
    overrides: dict[str, list[Scalar]] = Field(
        default_factory=dict,
        description="dotted parameter path or design knob (track_m, component.NAME.x_m ...) = list of values, "
        "each list one more grid axis",
    )

    @field_validator("stiffness_scale", "damping_scale")
    @classmethod
    def _positive(cls, values):
        for v in values:
            if not math.isfinite(v) or v <= 0:
                raise ValueError(f"scale factors must be finite and > 0, got {v!r}")
        return values

    @field_validator("overrides")
    @classmethod
    def _non_empty(cls, values):
        for key, axis in values.items():
            if not axis:
                raise ValueError(f"override '{key}' needs at least one value")
            for v in axis:
                if isinstance(v, float) and not math.isfinite(v):  # a scenario id is JSON: no nan or inf
                    raise ValueError(f"override '{key}': values must be finite, got {v!r}")
        return values


class _Spec(_Model):
    name: str = Field(min_length=1)
    description: str = ""
    vehicle: str = "reference-etrike"
    manoeuvres: list[str] = Field(default=["dlc", "slc"], min_length=1)
    metrics: list[str | dict[str, Scalar]] = Field(
        default=["threshold"], min_length=1,
        description="what each vehicle variation measures: registered study metrics (threshold, tilt_angle, "
        "understeer_gradient, peak_ri, min_wheel_load, ...), each a name or a table { name = ..., option = value }",
    )
    freight_kg: list[float] = Field(default=[0.0], min_length=1)
    resolution_kmh: float = Field(default=0.1, gt=0, le=10)
    low_kmh: float = Field(default=10.0, gt=0)
    high_kmh: float = Field(default=90.0, gt=0, le=300)
    step_kmh: float = Field(default=10.0, gt=0)
    groups: list[_Group] = Field(default_factory=lambda: [_Group(name="base")], min_length=1)

    @field_validator("manoeuvres")
    @classmethod
    def _registered(cls, values):
        from ..manoeuvres.registry import get

        for name in values:
            try:
                get(name)
            except InputError as exc:
                raise ValueError(exc.reason) from None
        return values

    @field_validator("freight_kg")
    @classmethod
    def _freight(cls, values):
        for v in values:
            if not math.isfinite(v) or v < 0:
                raise ValueError(f"freight masses must be >= 0 kg, got {v!r}")
        return values


def _describe(exc: ValidationError, raw: dict) -> str:
    """One line for the first validation error of a study spec."""
    return describe_validation_error(exc, raw, _Spec)


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
        Registered manoeuvres, e.g. ``"dlc"`` (ISO 3888-1) and ``"slc"`` (ISO 14791).
    metrics : tuple of (str, dict)
        The study metrics (:mod:`trikedyn.study.metrics`): name and complete options; ``(("threshold", {}),)``
        by default.
    freight_kg : tuple of float
        The paper's freight in the trunk [kg] (Table 3).
    resolution_kmh, low_kmh, high_kmh, step_kmh : float
        Threshold search settings [km/h] (see :func:`trikedyn.analysis.threshold.threshold_velocity`).
    groups : tuple of GroupSpec
    origin : str
        Spec name or file path it was read from.
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

    def scenarios(self) -> list[dict]:
        """The unique scenarios, in spec order (see :func:`expand`)."""
        return expand(self)

    def load_vehicle(self):
        """The study's base vehicle (:class:`~trikedyn.params.io.ParameterSet`), before any variation."""
        from ..params import load_vehicle

        return load_vehicle(self.vehicle_source)


def _spec_dir():
    return resources.files("trikedyn.study") / "specs"


def list_specs() -> list[str]:
    """Names of the study specs shipped with trikedyn (``paper``: the paper's Fig. 10)."""
    return sorted(p.name[:-5] for p in _spec_dir().iterdir() if p.name.endswith(".toml"))


def load_spec(name_or_path: str | Path | StudySpec) -> StudySpec:
    """Load a study spec by name (``"paper"``) or from a TOML file.

    Raises
    ------
    InputError
        Unknown spec name (with a close match), unreadable TOML, unknown key (with a close match), a value
        out of range, an unknown vehicle or override path.
    """
    if isinstance(name_or_path, StudySpec):
        return name_or_path
    text = str(name_or_path)
    path = Path(text)
    if path.suffix == ".toml" or path.exists() or "/" in text:
        if not path.is_file():
            raise InputError("no such study spec file", where=text)
        try:
            raw = path.read_text(encoding="utf-8")
        except UnicodeDecodeError as exc:
            raise InputError(f"not UTF-8 text ({exc.reason} at byte {exc.start})", where=text) from None
        return parse_spec(raw, origin=text, base_dir=path.resolve().parent)
    names = list_specs()
    if text not in names:
        hint = get_close_matches(text, names, n=1)
        tip = f"; did you mean '{hint[0]}'?" if hint else ""
        raise InputError(f"unknown study '{text}'{tip} (built in: {', '.join(names)}; or give a .toml file)",
                         where="study")
    return parse_spec((_spec_dir() / f"{text}.toml").read_text(encoding="utf-8"), origin=text, base_dir=None)


def parse_spec(source: str | dict, origin: str = "<string>", base_dir: str | Path | None = None) -> StudySpec:
    """Validate a study given as TOML text or as a dict.

    Parameters
    ----------
    source : str or dict
        TOML text, or the table it parses to.
    origin : str
        Name shown in error messages.
    base_dir : path, optional
        Folder that a relative vehicle path is relative to (the spec file's; the working folder if None).
    """
    if isinstance(source, str):
        try:
            raw = tomllib.loads(source)
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"invalid TOML: {exc}", where=origin) from None
    else:
        raw = dict(source)
    try:
        model = _Spec.model_validate(raw)
    except ValidationError as exc:
        raise InputError(_describe(exc, raw), where=origin) from None
    if model.low_kmh >= model.high_kmh:
        raise InputError(f"low_kmh ({model.low_kmh:g}) must be below high_kmh ({model.high_kmh:g})", where=origin)
    names = [g.name for g in model.groups]
    dup = next((n for n in names if names.count(n) > 1), None)
    if dup is not None:
        raise InputError(f"groups: the name '{dup}' is used twice; group names must be unique", where=origin)

    vehicle_source = _resolve_vehicle(model.vehicle, base_dir)
    from ..errors import ParameterError
    from ..params import load_vehicle

    try:
        pset = load_vehicle(vehicle_source)
    except ParameterError as exc:
        raise InputError(f"vehicle: {exc}", where=origin) from None
    plain = pset.params.model_dump(mode="json")
    for group in model.groups:
        for dotted, values in group.overrides.items():
            problem = _override_problem(pset.params, plain, dotted, values, group.overrides)
            if problem:
                raise InputError(f"groups[{group.name}].overrides: {problem}", where=origin)
    digest = hashlib.sha256(pset.params.model_dump_json().encode()).hexdigest()[:12]
    metrics = _parse_metrics(model.metrics, origin)

    groups = tuple(
        GroupSpec(
            name=g.name,
            stiffness_scale=tuple(float(v) for v in g.stiffness_scale),
            damping_scale=tuple(float(v) for v in g.damping_scale),
            overrides=tuple((k, tuple(_norm(v) for v in vals)) for k, vals in g.overrides.items()),
        )
        for g in model.groups
    )
    return StudySpec(
        name=model.name,
        description=model.description,
        vehicle=model.vehicle,
        vehicle_source=vehicle_source,
        vehicle_digest=digest,
        manoeuvres=tuple(model.manoeuvres),
        freight_kg=tuple(float(v) for v in model.freight_kg),
        resolution_kmh=float(model.resolution_kmh),
        low_kmh=float(model.low_kmh),
        high_kmh=float(model.high_kmh),
        step_kmh=float(model.step_kmh),
        groups=groups,
        origin=origin,
        metrics=metrics,
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


def _resolve_vehicle(vehicle: str, base_dir: str | Path | None) -> str:
    """A preset name stays a name; a path is made relative to the spec file's folder."""
    from ..params import list_presets

    if vehicle in list_presets() and not vehicle.endswith(".toml"):
        return vehicle
    path = Path(vehicle)
    if path.suffix == ".toml" or "/" in vehicle:
        if not path.is_absolute() and base_dir is not None:
            path = Path(base_dir) / path
        return str(path)
    return vehicle  # an unknown name: load_vehicle explains, with a close match


def _override_problem(params, plain: dict, dotted: str, values, group: dict) -> str | None:
    """Why an override axis of a group cannot be varied (None if it can): an unknown knob or path (with a
    close match), a knob value that is not a number within the knob's bounds, or a path that moves one wheel
    of the pair or one component's declared place without the rest (a pointer to the knob that does it
    consistently; both wheels of the pair set in the group, one value each, are one deliberate layout)."""
    from ..params.knobs import _unknown, inconsistent_override, is_knob, knob_problem

    if is_knob(dotted):
        return knob_problem(params, dotted, values)
    if "." not in dotted and dotted not in plain:
        return _unknown(params, dotted)
    return _check_path(plain, dotted) or inconsistent_override(params, dotted, group)


def _check_path(plain: dict, dotted: str) -> str | None:
    """Why a dotted parameter path does not exist in a parameter set (None if it does)."""
    node: Any = plain
    keys = dotted.split(".")
    for i, key in enumerate(keys):
        if isinstance(node, list):
            names = [w.get("name") for w in node if isinstance(w, dict)]
            nxt = next((w for w in node if isinstance(w, dict) and w.get("name") == key), None)
        elif isinstance(node, dict):
            names = list(node)
            nxt = node.get(key) if key in node else None
            if key in node and i == len(keys) - 1:
                return None
        else:
            return f"no parameter '{dotted}' ('{'.'.join(keys[:i])}' is a value)"
        if nxt is None:
            hint = get_close_matches(key, [str(n) for n in names], n=1)
            tip = f"; did you mean '{hint[0]}'?" if hint else ""
            return f"no parameter '{dotted}' (no '{key}'){tip}"
        node = nxt
    if isinstance(node, dict | list):
        return f"'{dotted}' is a section, not a value"
    return None


def _norm(value):
    """Numbers as float (so that 75 and 75.0 give the same scenario), other scalars as they are."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return value
    return float(value)


# ------------------------------------------------------------------------------------------------
# expansion (pure)
# ------------------------------------------------------------------------------------------------
def canonical_json(scenario: dict) -> str:
    """The canonical JSON of a scenario's defining fields (sorted keys, no spaces): what its id hashes."""
    keys = [k for k in SCENARIO_KEYS if k not in _NOT_HASHED]
    data = {k: scenario.get(k) for k in keys}
    data["overrides"] = dict(sorted(data["overrides"].items()))
    if data["metric"] in (None, "threshold") and not data["metric_options"]:  # the ids from before metrics
        del data["metric"], data["metric_options"]
    return json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)


def scenario_id(scenario: dict) -> str:
    """A short, deterministic id of a scenario: the first 16 hex digits of SHA-256 of its canonical JSON."""
    return hashlib.sha256(canonical_json(scenario).encode()).hexdigest()[:16]


def expand(spec: StudySpec) -> list[dict]:
    """The unique scenarios of a study, in a fixed order.

    The order is: metric (as listed), manoeuvre (as listed; once, None, for a metric not per manoeuvre),
    then group (as listed), then stiffness scale, damping scale, overrides (each as listed) and freight. A
    scenario met again in a later group keeps its first place and adds that group's name to ``groups``
    (names joined by ``;``).

    Returns
    -------
    list of dict
        Each with the keys of ``SCENARIO_KEYS``: ``scenario_id`` (str), ``groups`` (str), ``vehicle`` (str),
        ``vehicle_digest`` (str), ``manoeuvre`` (str), ``freight_kg`` [kg], ``stiffness_scale`` and
        ``damping_scale`` [-], ``overrides`` (dict: dotted path -> value), ``resolution_kmh``, ``low_kmh``,
        ``high_kmh``, ``step_kmh`` [km/h] (None for a metric that does not search), ``metric`` (name),
        ``metric_options`` (dict) and ``metric_label`` (as the table shows it).
    """
    from .metrics import get, label

    by_id: dict[str, dict] = {}
    for metric_name, options in spec.metrics:
        metric = get(metric_name)
        search = (spec.resolution_kmh, spec.low_kmh, spec.high_kmh, spec.step_kmh) if metric.uses_search \
            else (None,) * 4
        for manoeuvre, group in itertools.product(spec.manoeuvres if metric.per_manoeuvre else (None,), spec.groups):
            paths = [p for p, _ in group.overrides]
            axes = [vals for _, vals in group.overrides]
            for k, c, combo, m in itertools.product(
                group.stiffness_scale, group.damping_scale, itertools.product(*axes), spec.freight_kg
            ):
                scenario = {
                    "scenario_id": "",
                    "groups": group.name,
                    "vehicle": spec.vehicle,
                    "vehicle_digest": spec.vehicle_digest,
                    "manoeuvre": manoeuvre,
                    "freight_kg": m,
                    "stiffness_scale": k,
                    "damping_scale": c,
                    "overrides": dict(zip(paths, combo, strict=True)),
                    "resolution_kmh": search[0],
                    "low_kmh": search[1],
                    "high_kmh": search[2],
                    "step_kmh": search[3],
                    "metric": metric_name,
                    "metric_options": dict(options),
                    "metric_label": label(metric_name, options),
                }
                sid = scenario_id(scenario)
                if sid in by_id:
                    seen = by_id[sid]["groups"].split(";")
                    if group.name not in seen:
                        by_id[sid]["groups"] = ";".join([*seen, group.name])
                    continue
                scenario["scenario_id"] = sid
                by_id[sid] = scenario
    return list(by_id.values())


def _distinct(values) -> frozenset[str]:
    """The distinct values of an axis, as a scenario id sees them (their JSON: 1.0 and True differ)."""
    return frozenset(json.dumps(v) for v in values)


def count_scenarios(spec: StudySpec) -> tuple[int, bool]:
    """How many scenarios :func:`expand` gives, computed from the axis lengths, without expanding.

    Each group is a grid (a box): stiffness x damping x one axis per override path. Values repeated in an
    axis count once, and a scenario in the grids of several groups (same override paths, same values)
    counts once, by inclusion-exclusion over the groups that share their override paths; subsets of groups
    whose grids do not meet are pruned, so this is cheap for any spec written by hand. Past
    ``2**16`` overlapping subsets it stops and returns the sum of the group grids instead, an upper bound.
    Freight multiplies every group alike; so does each metric, once per manoeuvre or once.

    Returns
    -------
    (int, bool)
        The number of scenarios, and whether it is exact (``len(expand(spec))``) or an upper bound.
    """
    families: dict[tuple[str, ...], list[tuple[frozenset[str], ...]]] = {}
    for group in spec.groups:
        axes = dict(group.overrides)
        paths = tuple(sorted(axes))
        box = (_distinct(group.stiffness_scale), _distinct(group.damping_scale),
               *(_distinct(axes[p]) for p in paths))
        families.setdefault(paths, []).append(box)
    from .metrics import get

    n_manoeuvres = len(_distinct(spec.manoeuvres))
    runs = sum(n_manoeuvres if get(name).per_manoeuvre else 1 for name, _ in spec.metrics)
    common = runs * len(_distinct(spec.freight_kg))
    exact = True
    union = 0
    for boxes in families.values():
        n, family_exact = _union_size(boxes)
        union += n
        exact = exact and family_exact
    return common * union, exact


def _union_size(boxes: list[tuple[frozenset[str], ...]], budget: int = 2**16) -> tuple[int, bool]:
    """Points in the union of grids (each a tuple of per-axis value sets): (count, exact)."""
    boxes = list(dict.fromkeys(boxes))  # groups with the same grid (under other names) count once
    upper = sum(math.prod(len(axis) for axis in box) for box in boxes)
    if len(boxes) == 1:
        return upper, True
    total = 0
    steps = 0
    stack = [(i, boxes[i], 1) for i in range(len(boxes))]  # (last box index, intersection, subset size)
    while stack:
        last, meet, size = stack.pop()
        steps += 1
        if steps > budget:
            return upper, False
        total += math.prod(len(axis) for axis in meet) * (1 if size % 2 else -1)
        for j in range(last + 1, len(boxes)):
            nxt = tuple(a & b for a, b in zip(meet, boxes[j], strict=True))
            if all(nxt):
                stack.append((j, nxt, size + 1))
    return total, True
