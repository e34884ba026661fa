"""A study spec expanded into its scenarios (pure functions of a loaded :class:`~trikedyn.study.spec.StudySpec`).

The scenarios are the union of the groups' grids (metric x manoeuvre x stiffness x damping x overrides x
freight); a scenario two groups share is run once and carries both group names. Its ``scenario_id`` is a
short SHA-256 of its canonical JSON (see :mod:`trikedyn.study.spec`). :func:`count_scenarios` counts what
:func:`expand` would give without building it, so that a run can refuse a spec that expands to millions of
scenarios (a few lines of TOML can) before it spends the memory.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the spec is the data; this module expands it (spec.py does not import it)
    from .spec import StudySpec

__all__ = ["SCENARIO_KEYS", "canonical_json", "count_scenarios", "expand", "scenario_id"]

SCENARIO_KEYS = (
    "scenario_id",
    "groups",
    "vehicle",
    "vehicle_digest",
    "manoeuvre",
    "manoeuvre_options",
    "freight_kg",
    "stiffness_scale",
    "damping_scale",
    "overrides",
    "resolution_kmh",
    "low_kmh",
    "high_kmh",
    "step_kmh",
    "criterion",
    "speed_control",
    "speed_band_percent",
    "speed_band_kmh",
    "course_width_m",
    "metric",
    "metric_options",
    "metric_label",
)
"""Keys of a scenario dict, in this order."""

_NOT_HASHED = ("scenario_id", "groups", "metric_label")
_JUDGING = ("criterion", "speed_control", "speed_band_percent", "speed_band_kmh", "course_width_m")
"""How a run is judged, driven and laid out: None on a scenario whose metric or manoeuvre does not use it."""


# ------------------------------------------------------------------------------------------------
# expansion (pure)
# ------------------------------------------------------------------------------------------------
def canonical_json(scenario: dict) -> str:
    """The canonical JSON of a scenario's defining fields (sorted keys, no spaces): what its id hashes.

    Parameters
    ----------
    scenario : dict
        The scenario.

    Returns
    -------
    str
        The JSON.
    """
    keys = [k for k in SCENARIO_KEYS if k not in _NOT_HASHED]
    data = {k: scenario.get(k) for k in keys}
    data["overrides"] = dict(sorted(data["overrides"].items()))
    if data["metric"] in (None, "threshold") and not data["metric_options"]:  # the ids from before metrics
        del data["metric"], data["metric_options"]
    if not data.get("manoeuvre_options"):  # a manoeuvre at its defaults keeps the id it had before options
        data.pop("manoeuvre_options", None)
    for key in _JUDGING:  # a metric that neither searches nor drives keeps the id it had before them
        if data.get(key) is None:
            data.pop(key, None)
    return json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)


def scenario_id(scenario: dict) -> str:
    """A short, deterministic id of a scenario: the first 16 hex digits of SHA-256 of its canonical JSON.

    Parameters
    ----------
    scenario : dict
        The scenario.

    Returns
    -------
    str
        16 hex digits.
    """
    return hashlib.sha256(canonical_json(scenario).encode()).hexdigest()[:16]


def expand(spec: StudySpec) -> list[dict]:
    """The unique scenarios of a study, in a fixed order.

    The order is: metric (as listed), manoeuvre (as listed; once, None, for a metric not per manoeuvre),
    then group (as listed), then stiffness scale, damping scale, overrides (each as listed) and freight. A
    scenario met again in a later group keeps its first place and adds that group's name to ``groups``
    (names joined by ``;``).

    Parameters
    ----------
    spec : StudySpec
        The study.

    Returns
    -------
    list of dict
        Each with the keys of ``SCENARIO_KEYS``: ``scenario_id`` (str), ``groups`` (str), ``vehicle`` (str),
        ``vehicle_digest`` (str), ``manoeuvre`` (str), ``manoeuvre_options`` (dict: the options the spec gives
        it, each in its unit; hashed into the id only when not empty), ``freight_kg`` [kg], ``stiffness_scale`` and
        ``damping_scale`` [-], ``overrides`` (dict: dotted path -> value), ``resolution_kmh``, ``low_kmh``,
        ``high_kmh``, ``step_kmh`` [km/h], ``criterion``, ``speed_band_percent`` [%], ``speed_band_kmh``
        [km/h] (None for a metric that does not search), ``speed_control`` (None for a metric not per
        manoeuvre), ``course_width_m`` [m] (the base vehicle's width, for a course laid out from it unless
        the manoeuvre's options give one; else None), ``metric`` (name),
        ``metric_options`` (dict) and ``metric_label`` (as the table shows it).
    """
    from .metrics import get, label

    by_id: dict[str, dict] = {}
    for metric_name, options in spec.metrics:
        metric = get(metric_name)
        search = (spec.resolution_kmh, spec.low_kmh, spec.high_kmh, spec.step_kmh) if metric.uses_search \
            else (None,) * 4
        judged = (spec.criterion, spec.speed_band_percent, spec.speed_band_kmh) if metric.uses_search else (None,) * 3
        driven = spec.speed_control if metric.per_manoeuvre else None
        manoeuvres = spec.manoeuvre_list if metric.per_manoeuvre else (None,)
        for man, group in itertools.product(manoeuvres, spec.groups):
            manoeuvre = None if man is None else man.name
            man_options = {} if man is None else dict(man.options)
            width = spec.course_width_m if _follows_width(manoeuvre) and "course_width_m" not in man_options else None
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
                    "manoeuvre_options": man_options,
                    "freight_kg": m,
                    "stiffness_scale": k,
                    "damping_scale": c,
                    "overrides": dict(zip(paths, combo, strict=True)),
                    "resolution_kmh": search[0],
                    "low_kmh": search[1],
                    "high_kmh": search[2],
                    "step_kmh": search[3],
                    "criterion": judged[0],
                    "speed_control": driven,
                    "speed_band_percent": judged[1],
                    "speed_band_kmh": judged[2],
                    "course_width_m": width,
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


def _follows_width(manoeuvre: str | None) -> bool:
    """Whether a manoeuvre's course is laid out from the vehicle's width (it takes ``course_width_m``)."""
    if manoeuvre is None or str(manoeuvre).lower().endswith(".csv"):
        return False
    from ..manoeuvres.registry import get

    return any(o.name == "course_width_m" for o in get(manoeuvre).options)


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

    Parameters
    ----------
    spec : StudySpec
        The study.

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

    n_manoeuvres = len({m.label for m in spec.manoeuvre_list})
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
