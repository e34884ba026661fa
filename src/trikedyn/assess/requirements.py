"""Requirements a stability dossier is judged against: a TOML file of items, each PASS or FAIL with its margin.

A requirements file (or a shipped preset, :func:`preset_names`)::

    title = "Our fleet's requirements"          # optional
    source = "where the figures come from"      # optional

    [[requirement]]
    id = "tilt"                                 # required, unique: how the item is named in the verdict
    metric = "tilt_angle_deg"                   # required: one of METRICS (`trikedyn assess --help`)
    at_least = 35                               # a number, or the name of another metric
    laden = true                                # judged with --payload aboard (default: false, as given)
    note = "35 deg fully laden"                 # optional: shown beside the verdict

    [[requirement]]
    id = "dlc-above-top-speed"
    metric = "dlc_threshold_kmh"
    at_least = "top_speed_kmh"                  # the bound is another metric of the same vehicle
    tolerance = 0.1                             # a margin down to -tolerance still passes [metric's unit]

    [[requirement]]
    id = "ri-dlc-30"
    metric = "max_abs_ri"                       # needs a run: manoeuvre and speed
    manoeuvre = "dlc"
    speed_kmh = 30
    at_most = 0.8

Each item has ``at_least``, ``at_most`` or both. Its margin is ``value - at_least`` (``at_most - value``; the
smaller of the two with both) in the metric's unit; it passes when the margin is at least ``-tolerance``. A
metric the assessment could not find (no threshold: the lowest speed searched failed) fails, saying so.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass
from pathlib import Path

from ..errors import InputError, did_you_mean
from ..registry import Registry

__all__ = ["METRICS", "MAX_REQUIREMENTS_BYTES", "Judgement", "Metric", "Requirement", "RequirementSet", "judge",
           "load_requirements", "metric_help", "parse_requirements", "preset_names"]

MAX_REQUIREMENTS_BYTES = 1 << 20
"""Largest requirements file read [bytes]."""

PRESET_DIR = Path(__file__).parent / "presets"


@dataclass(frozen=True)
class Metric:
    """A quantity of the dossier a requirement can bound.

    Attributes
    ----------
    unit : str
        Its unit (``"deg"``, ``"km/h"``, ``"1"``).
    description : str
        What it is, and which command prints the same number.
    key : str
        Where it is in an assessment state's ``metrics`` (:func:`trikedyn.assess.runs.state_metrics`);
        empty for a metric computed on demand.
    needs : tuple of str
        Fields the requirement must give (``manoeuvre``, ``speed_kmh``).
    """

    unit: str
    description: str
    key: str = ""
    needs: tuple = ()


METRICS: Registry[Metric] = Registry("requirement metric", where="metric")
"""Name -> :class:`Metric`: every quantity a requirement can bound."""

for _name, _unit, _text in (
    ("mass_kg", "kg", "total mass, driver (and payload when laden) included (trikedyn cg payload)"),
    ("cg_height_m", "m", "height of the whole vehicle's CG above the ground (trikedyn cg payload)"),
    ("tilt_angle_deg", "deg", "compliant tilt-table angle at which the first wheel lifts, the weaker side "
                              "(trikedyn tilt)"),
    ("rigid_tilt_angle_deg", "deg", "rigid-vehicle tilt angle, the weaker side (trikedyn tilt: rigid)"),
    ("static_stability_g", "1", "rigid lateral tip-over acceleration a_y/g, the weaker edge "
                                "(trikedyn vehicle check: tip-over)"),
    ("understeer_gradient_deg_per_g", "deg/g", "understeer gradient in the linear range, ISO 4138 "
                                               "(trikedyn handling)"),
    ("max_lateral_acceleration_mps2", "m/s^2", "highest steady lateral acceleration reached on the circle "
                                               "(trikedyn handling)"),
    ("top_speed_kmh", "km/h", "top speed on the flat (trikedyn performance)"),
    ("dlc_threshold_kmh", "km/h", "DLC threshold velocity, course criterion (trikedyn threshold)"),
    ("slc_threshold_kmh", "km/h", "SLC threshold velocity, course criterion (trikedyn threshold --manoeuvre slc)"),
    ("fishhook_threshold_kmh", "km/h", "fishhook threshold velocity, course criterion "
                                       "(trikedyn threshold --manoeuvre fishhook)"),
    ("dlc_lift_off_kmh", "km/h", "DLC threshold velocity, lift-off criterion (--criterion lift-off)"),
    ("slc_lift_off_kmh", "km/h", "SLC threshold velocity, lift-off criterion"),
    ("fishhook_lift_off_kmh", "km/h", "fishhook threshold velocity, lift-off criterion"),
    ("min_threshold_kmh", "km/h", "the lowest course threshold of the DLC, SLC and fishhook"),
):
    METRICS.register(_name, Metric(_unit, _text, key=_name))
METRICS.register("max_abs_ri", Metric("1", "largest |rollover index| over the judged window of one run (Eq. 5) "
                                           "at speed_kmh in manoeuvre (trikedyn simulate)",
                                      needs=("manoeuvre", "speed_kmh")))

_FIELDS = ("id", "metric", "at_least", "at_most", "tolerance", "laden", "note", "manoeuvre", "speed_kmh")
_TOP = ("title", "source", "requirement")


def metric_help() -> str:
    """The metrics, one line each, for ``--help`` and the docs.

    Returns
    -------
    str
        ``name [unit]: description`` lines.
    """
    return "\n".join(f"{name} [{m.unit}]: {m.description}" for name, m in METRICS.items())


@dataclass(frozen=True)
class Requirement:
    """One item of a requirements file (see the module's docstring).

    Attributes
    ----------
    id : str
    metric : str
    at_least, at_most : float or str or None
        Bounds: a number in the metric's unit, or another metric's name.
    tolerance : float
        A margin down to ``-tolerance`` still passes [the metric's unit].
    laden : bool
        Judged on the vehicle with the assessment's payload aboard.
    note : str
    manoeuvre : str or None
    speed_kmh : float or None
        Target speed of the run a run metric needs [km/h].
    """

    id: str
    metric: str
    at_least: float | str | None = None
    at_most: float | str | None = None
    tolerance: float = 0.0
    laden: bool = False
    note: str = ""
    manoeuvre: str | None = None
    speed_kmh: float | None = None

    def bound_text(self) -> str:
        """The bound in words (``>= 35``, ``<= 0.8``, ``>= top_speed_kmh``).

        Returns
        -------
        str
            The bound(s).
        """
        parts = [f">= {b:g}" if isinstance(b, float) else f">= {b}" for b in (self.at_least,) if b is not None]
        parts += [f"<= {b:g}" if isinstance(b, float) else f"<= {b}" for b in (self.at_most,) if b is not None]
        return " and ".join(parts)


@dataclass(frozen=True)
class RequirementSet:
    """A parsed requirements file.

    Attributes
    ----------
    name : str
        The preset's name or the file's path.
    title, source : str
    items : tuple of Requirement
    """

    name: str
    title: str
    source: str
    items: tuple

    def to_dict(self) -> dict:
        """JSON-ready.

        Returns
        -------
        dict
            Name, title, source and the items.
        """
        return {"name": self.name, "title": self.title, "source": self.source,
                "items": [asdict(r) for r in self.items]}


def _bound(value, key: str, where: str) -> float | str | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise InputError(f"'{key}' must be a number or a metric's name, got {value!r}", where=where)
    if isinstance(value, str):
        if value not in METRICS:
            raise InputError(f"'{key}': unknown metric '{value}'" + did_you_mean(value, METRICS.names()), where=where)
        if METRICS.get(value).needs:
            raise InputError(f"'{key}': metric '{value}' needs a run of its own and cannot be a bound", where=where)
        return value
    if not math.isfinite(value):
        raise InputError(f"'{key}' must be finite, got {value!r}", where=where)
    return float(value)


def _item(raw, index: int, where: str) -> Requirement:
    here = f"{where}: requirement {index}"
    if not isinstance(raw, Mapping):
        raise InputError(f"must be a table ([[requirement]]), got {type(raw).__name__}", where=here)
    if isinstance(raw.get("id"), str) and raw["id"].strip():
        here = f"{where}: requirement '{raw['id']}'"
    unknown = [k for k in raw if k not in _FIELDS]
    if unknown:
        raise InputError(f"unknown key '{unknown[0]}'" + did_you_mean(unknown[0], _FIELDS), where=here)
    for key in ("id", "metric"):
        if not isinstance(raw.get(key), str) or not raw[key].strip():
            raise InputError(f"'{key}' is required (a non-empty string)", where=here)
    if raw["metric"] not in METRICS:
        raise InputError(METRICS.unknown(raw["metric"]), where=here)
    metric = METRICS.get(raw["metric"])
    at_least, at_most = _bound(raw.get("at_least"), "at_least", here), _bound(raw.get("at_most"), "at_most", here)
    if at_least is None and at_most is None:
        raise InputError("give 'at_least', 'at_most' or both", where=here)
    tolerance = raw.get("tolerance", 0.0)
    if isinstance(tolerance, bool) or not isinstance(tolerance, int | float) or not (0 <= tolerance < math.inf):
        raise InputError(f"'tolerance' must be a number >= 0, got {tolerance!r}", where=here)
    laden, note = raw.get("laden", False), raw.get("note", "")
    if not isinstance(laden, bool):
        raise InputError(f"'laden' must be true or false, got {laden!r}", where=here)
    if not isinstance(note, str):
        raise InputError(f"'note' must be a string, got {note!r}", where=here)
    manoeuvre, speed = raw.get("manoeuvre"), raw.get("speed_kmh")
    for need in metric.needs:
        if raw.get(need) is None:
            raise InputError(f"metric '{raw['metric']}' needs '{need}'", where=here)
    for key in ("manoeuvre", "speed_kmh"):
        if key not in metric.needs and raw.get(key) is not None:
            raise InputError(f"'{key}' applies only to a metric that needs a run (max_abs_ri)", where=here)
    if manoeuvre is not None:
        from ..manoeuvres.registry import get

        if not isinstance(manoeuvre, str):
            raise InputError(f"'manoeuvre' must be a manoeuvre's name, got {manoeuvre!r}", where=here)
        try:
            get(manoeuvre)
        except InputError as exc:
            raise InputError(f"'manoeuvre': {exc.reason}", where=here) from None
    if speed is not None and (isinstance(speed, bool) or not isinstance(speed, int | float)
                              or not 0 < speed <= 400):
        raise InputError(f"'speed_kmh' must be a number in (0, 400], got {speed!r}", where=here)
    return Requirement(id=raw["id"].strip(), metric=raw["metric"], at_least=at_least, at_most=at_most,
                       tolerance=float(tolerance), laden=laden, note=note, manoeuvre=manoeuvre,
                       speed_kmh=None if speed is None else float(speed))


def parse_requirements(text: str, where: str) -> RequirementSet:
    """Parse a requirements file's text.

    Parameters
    ----------
    text : str
        The TOML text.
    where : str
        The file's name or the preset's, for messages and :attr:`RequirementSet.name`.

    Returns
    -------
    RequirementSet
        The items, in the file's order.

    Raises
    ------
    InputError
        Not TOML, an unknown key, metric or manoeuvre (with a close match), a missing or duplicate id, a
        bound that is not a number or a metric, no item at all; one line naming the file and the item.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not valid TOML: {exc}", where=where) from None
    unknown = [k for k in data if k not in _TOP]
    if unknown:
        raise InputError(f"unknown key '{unknown[0]}'" + did_you_mean(unknown[0], _TOP), where=where)
    for key in ("title", "source"):
        if not isinstance(data.get(key, ""), str):
            raise InputError(f"'{key}' must be a string", where=where)
    raw = data.get("requirement")
    if not isinstance(raw, list) or not raw:
        raise InputError("no requirement: expected at least one [[requirement]] table", where=where)
    items = [_item(r, i, where) for i, r in enumerate(raw, start=1)]
    seen = set()
    for item in items:
        if item.id in seen:
            raise InputError(f"requirement id '{item.id}' is given twice", where=where)
        seen.add(item.id)
    return RequirementSet(name=where, title=data.get("title", ""), source=data.get("source", ""), items=tuple(items))


def preset_names() -> list[str]:
    """The shipped requirement presets (``assess/presets/*.toml``).

    Returns
    -------
    list of str
        Their names, sorted.
    """
    return sorted(p.stem for p in PRESET_DIR.glob("*.toml"))


def load_requirements(name_or_path: str | Path, where: str = "--requirements") -> RequirementSet:
    """A requirements file, or a shipped preset by name, read by the bounded reader.

    Parameters
    ----------
    name_or_path : str or Path
        A preset's name (:func:`preset_names`) or a ``.toml`` file.
    where : str
        The option it came from, for an unknown preset's message.

    Returns
    -------
    RequirementSet
        The parsed items.

    Raises
    ------
    InputError
        An unknown preset (with a close match), a file that cannot be read (missing, a folder, a FIFO, over
        1 MiB, not UTF-8) or that is malformed (:func:`parse_requirements`).
    """
    from .._reading import read_text

    text = str(name_or_path)
    if text in preset_names():
        path, shown = PRESET_DIR / f"{text}.toml", text
    elif text.endswith(".toml") or "/" in text or Path(text).exists():
        path, shown = Path(text), text
    else:
        raise InputError(f"not a .toml file nor a preset '{text}'" + (did_you_mean(text, preset_names())
                         or f"; presets: {', '.join(preset_names())}"), where=where)
    body = read_text(path, shown, max_bytes=MAX_REQUIREMENTS_BYTES, expected="a requirements file (TOML)")
    return parse_requirements(body, shown)


@dataclass(frozen=True)
class Judgement:
    """One requirement judged.

    Attributes
    ----------
    id, metric : str
    value : float or None
        The vehicle's value [metric's unit]; None when it could not be found.
    bound : str
        The bound in words, with a metric bound's value.
    margin : float or None
        ``value - at_least`` / ``at_most - value`` (the smaller with both) [metric's unit].
    passed : bool
    unit, note, detail : str
        ``detail`` says why a value is missing, or on which state (laden) it was judged.
    """

    id: str
    metric: str
    value: float | None
    bound: str
    margin: float | None
    passed: bool
    unit: str
    note: str
    detail: str

    @property
    def verdict(self) -> str:
        """``"PASS"`` or ``"FAIL"``."""
        return "PASS" if self.passed else "FAIL"

    def to_dict(self) -> dict:
        """JSON-ready, with the verdict.

        Returns
        -------
        dict
            The judgement.
        """
        return asdict(self) | {"verdict": self.verdict}


def judge(requirements: RequirementSet, value_of: Callable[[Requirement, str], float | None]) -> list[Judgement]:
    """Judge every item.

    Parameters
    ----------
    requirements : RequirementSet
        The items.
    value_of : callable
        ``value_of(item, metric_name)``: the vehicle's value of a metric for that item (laden or not, the
        item's run), None when the assessment could not find it.

    Returns
    -------
    list of Judgement
        One per item, in order.
    """
    out = []
    for item in requirements.items:
        metric = METRICS.get(item.metric)
        value = value_of(item, item.metric)
        margins, bounds, missing = [], [], []
        for bound, sign, word in ((item.at_least, 1.0, ">="), (item.at_most, -1.0, "<=")):
            if bound is None:
                continue
            limit = value_of(item, bound) if isinstance(bound, str) else bound
            if isinstance(bound, str):
                bounds.append(f"{word} {bound}" + ("" if limit is None else f" ({limit:.4g})"))
            else:
                bounds.append(f"{word} {bound:g}")
            if limit is None:
                missing.append(str(bound))
            elif value is not None:
                margins.append(sign * (value - limit))
        margin = min(margins) if margins and not missing else None
        passed = margin is not None and margin >= -item.tolerance
        detail = "laden" if item.laden else "as given"
        if value is None:
            detail += f"; {item.metric} not found"
        if missing:
            detail += f"; {', '.join(missing)} not found"
        out.append(Judgement(id=item.id, metric=item.metric, value=value, bound=" and ".join(bounds), margin=margin,
                             passed=passed, unit=metric.unit, note=item.note, detail=detail))
    return out
