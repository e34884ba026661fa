"""A study table read for its figures (:mod:`trikedyn.study.designs.figures`): which columns are its factors
(:func:`factors`: columns that always move together are one), their levels and labels, and the main effects
(:func:`main_effects`: never averaged over an unbalanced design without saying so; the rules are those of
:mod:`trikedyn.study.designs.figures`). Plain pandas: nothing here draws.
"""

from __future__ import annotations

import math
import re

__all__ = ["AS_GIVEN", "BASES", "factors", "main_effects"]

_FIXED = ("scenario_id", "groups", "vehicle", "manoeuvre", "metric", "status", "value", "unit")
_BASE_FACTORS = ("freight_kg", "stiffness_scale", "damping_scale")
_LABELS = {"freight_kg": "freight [kg]", "stiffness_scale": "stiffness scale [-]", "damping_scale": "damping scale [-]"}
_WORDS = {"freight_kg": "freight", "stiffness_scale": "stiffness scale", "damping_scale": "damping scale"}
HEATMAP_LEVELS = 5
AS_GIVEN = "as given"
"""The label of an override's empty cell: the vehicle's own value (the row's group does not set it)."""
BASES = ("balanced", "balanced part", "per setting")
"""How a main effect's panel is drawn (:func:`main_effects`' ``basis``)."""


def _override_columns(frame) -> list[str]:
    cols = list(frame.columns)
    start = cols.index("damping_scale") + 1
    end = cols.index("metric") if "metric" in cols else cols.index("status")
    return cols[start:end]


def _long(frame):
    """The table as (metric, unit, value) rows; a threshold-only table's value is its threshold."""
    data = frame.copy()
    if "metric" not in data.columns:
        data["metric"] = "threshold"
        data["unit"] = "km/h"
        data["value"] = data["threshold_speed_kmh"]
    data["value"] = data["value"].astype("float64")
    data["manoeuvre"] = data["manoeuvre"].where(data["manoeuvre"].notna(), "vehicle")
    return data


def factors(frame) -> list[str]:
    """The columns of a study table that vary (more than one value), in table order.

    Parameters
    ----------
    frame : pandas.DataFrame
        A study table.

    Returns
    -------
    list of str
        The columns.
    """
    out = []
    for col in (*_BASE_FACTORS, *_override_columns(frame)):
        if col in frame.columns and frame[col].astype(str).nunique(dropna=False) > 1:
            out.append(col)
    return out


def _numeric(values) -> bool:
    return all(isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) for v in values)


def _missing(value) -> bool:
    return value is None or (isinstance(value, float) and math.isnan(value))


def _fmt(value) -> str:
    if _missing(value):
        return AS_GIVEN
    return f"{value:g}" if _numeric([value]) else str(value)


# ------------------------------------------------------------------------------------------------------------
# factors as the figures see them: aliased columns joined, an empty override cell a level of its own
# ------------------------------------------------------------------------------------------------------------
def _cell(value):
    return None if _missing(value) else value


def _groups(rows, cols: list[str]) -> list[tuple[str, ...]]:
    """The varying columns joined into factors: columns whose levels map one to one are one factor."""
    cells = {c: [_cell(v) for v in rows[c].tolist()] for c in cols}
    out: list[list[str]] = []
    for col in cols:
        for group in out:
            pairs = set(zip(cells[group[0]], cells[col], strict=True))
            if len(pairs) == len({a for a, _ in pairs}) == len({b for _, b in pairs}):
                group.append(col)
                break
        else:
            out.append([col])
    return [tuple(g) for g in out]


def _key(group: tuple[str, ...]) -> str:
    return "\x00".join(group)


def _with_keys(rows, groups):
    """``rows`` with one column per factor holding its level: the value (a single column with no empty cell)
    or the tuple of the group's cells (None: as given)."""
    data = rows.copy()
    for group in groups:
        tuples = list(zip(*(map(_cell, data[c].tolist()) for c in group), strict=True))
        simple = len(group) == 1 and all(t[0] is not None for t in tuples)
        data[_key(group)] = [t[0] for t in tuples] if simple else tuples
    return data


def _sort_key(level):
    parts = level if isinstance(level, tuple) else (level,)
    return tuple((0, 0.0, "") if v is None else (1, float(v), "") if _numeric([v]) else (2, 0.0, str(v))
                 for v in parts)


def _levels(series) -> list:
    values = [v for v in dict.fromkeys(series.tolist()) if not _missing(v)]
    return sorted(values, key=_sort_key)


def _level_label(level) -> str:
    if isinstance(level, tuple):
        return AS_GIVEN if all(v is None for v in level) else ", ".join(_fmt(v) for v in level)
    return _fmt(level)


def _x(levels):
    """x positions and tick labels: the values themselves if numeric, else 0, 1, 2 ... with labels."""
    if _numeric(levels):
        return {v: float(v) for v in levels}, None
    return {v: float(i) for i, v in enumerate(levels)}, [_level_label(v) for v in levels]


def _label(group) -> str:
    group = (group,) if isinstance(group, str) else group
    return _LABELS.get(group[0], group[0]) if len(group) == 1 else " & ".join(group)


def _words(group: tuple[str, ...]) -> str:
    return _WORDS.get(group[0], group[0]) if len(group) == 1 else " & ".join(group)


def _slug(text: str) -> str:
    """A metric's label as a plain file name: ``peak_ri(speed_kmh=25)`` -> ``peak_ri_speed_kmh_25`` (no ``=``,
    brackets or spaces, which shells and some file systems treat specially)."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_") or "metric"


# ------------------------------------------------------------------------------------------------------------
# main effects and the balance they rest on
# ------------------------------------------------------------------------------------------------------------
def _part_words(part: set, others: list[tuple[str, ...]], sub) -> str:
    """The balanced part in words: ``damping scale = 1; track as given`` when it is a sub-grid, else a count."""
    if not others:
        return ""
    values = [{p[i] for p in part} for i in range(len(others))]
    if len(part) == math.prod(len(v) for v in values):
        words = []
        for group, vals in zip(others, values, strict=True):
            if len(vals) == len(_levels(sub[_key(group)])):
                continue  # every level of it: not a restriction
            names = sorted(vals, key=_sort_key)
            text = ", ".join(_level_label(v) for v in names)
            words.append(f"{_words(group)} {'=' if len(names) == 1 else 'in'} {text}"
                         if text != AS_GIVEN else f"{_words(group)} {AS_GIVEN}")
        return "; ".join(words)
    return f"the {len(part)} settings of the other factors that every level meets"


def _effect(sub, group, others, metric: str, man: str) -> list[dict]:
    """The rows of :func:`main_effects` for one factor and one manoeuvre."""
    levels = _levels(sub[_key(group)])
    settings = list(zip(*(sub[_key(o)].tolist() for o in others), strict=True)) if others else [()] * len(sub)
    cells: dict = {}
    for level, setting, value in zip(sub[_key(group)].tolist(), settings, sub["value"].tolist(), strict=True):
        cells.setdefault(level, {}).setdefault(setting, []).append(value)
    met = [set(cells[lv]) for lv in levels]
    common = set.intersection(*met)
    base = {"metric": metric, "factor": " & ".join(group), "manoeuvre": man}
    out = []
    if common:
        balanced = all(s == common for s in met)
        basis, where = ("balanced", "") if balanced else ("balanced part", _part_words(common, others, sub))
        for lv in levels:
            means = [sum(cells[lv][s]) / len(cells[lv][s]) for s in common]
            out.append({**base, "level": lv, "level_label": _level_label(lv), "value": sum(means) / len(means),
                        "n": sum(len(cells[lv][s]) for s in common), "basis": basis, "line": "mean", "over": where})
        return out
    for lv in levels:
        for setting, values in cells[lv].items():
            line = "; ".join(f"{_words(o)} {AS_GIVEN}" if _level_label(v) == AS_GIVEN
                             else f"{_words(o)} = {_level_label(v)}" for o, v in zip(others, setting, strict=True))
            out.append({**base, "level": lv, "level_label": _level_label(lv), "value": sum(values) / len(values),
                        "n": len(values), "basis": "per setting", "line": line, "over": ""})
    return out


def main_effects(frame, metric: str | None = None):
    """The main effects of a study table, as :func:`study_figures` draws them, with what each mean is over.

    For each metric, each factor (aliased columns joined with ``" & "``) and each manoeuvre: the metric at
    each level of the factor. Whether the design is balanced for that factor is judged on the rows with a
    value, per manoeuvre (see the module docstring).

    Parameters
    ----------
    frame : pandas.DataFrame
        A study table (:meth:`StudyStore.to_pandas`, ``results.parquet``).
    metric : str, optional
        Only this metric (``"threshold"`` for a threshold-only table).

    Returns
    -------
    pandas.DataFrame
        One row per point drawn: ``metric``, ``factor``, ``manoeuvre``, ``level`` (the value, or a tuple for a
        joined or partly empty factor), ``level_label``, ``value`` (in the metric's unit), ``n`` (scenarios
        averaged), ``basis`` (one of :data:`BASES`), ``line`` (``"mean"``, or the setting of the other factors
        for ``per setting``) and ``over`` (the balanced part in words; empty when balanced).
    """
    import pandas as pd

    data = _long(frame)
    out = []
    for name, rows in data.groupby("metric", sort=False):
        if metric is not None and name != metric:
            continue
        rows = rows[rows["value"].notna()]
        varying = [c for c in factors(frame) if rows[c].astype(str).nunique(dropna=False) > 1]
        if rows.empty or not varying:
            continue
        groups = _groups(rows, varying)
        keyed = _with_keys(rows, groups)
        for group in groups:
            others = [g for g in groups if g != group]
            for man, sub in keyed.groupby("manoeuvre", sort=False):
                out.extend(_effect(sub, group, others, str(name), str(man)))
    columns = ["metric", "factor", "manoeuvre", "level", "level_label", "value", "n", "basis", "line", "over"]
    return pd.DataFrame(out, columns=columns)
