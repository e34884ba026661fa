"""The figures of a study, chosen from its shape: one PNG per metric, ``fig_<metric>.png`` in its folder.

The *factors* are the table's columns that a study varies: ``freight_kg``, ``stiffness_scale``,
``damping_scale`` and each override (a dotted path or a design knob), counted as varying when they take more
than one value among the metric's rows. Manoeuvres are not factors: they are the lines (a metric not per
manoeuvre, such as the tilt angle, draws one line, ``vehicle``). By the number of factors:

- none: a bar per manoeuvre;
- one: the metric against the factor, one line per manoeuvre;
- two: one panel per manoeuvre, the metric against the factor with more levels, one line per level of the
  other (a family of lines); a heat map instead when both have five levels or more and form a full grid;
- three or more: main effects, one panel per factor: the mean of the metric at each level of the factor
  (over every other setting), one line per manoeuvre.

Failed scenarios (no value) are left out. matplotlib is imported only here, and only when a figure is drawn
(the figure is drawn without pyplot, so no display or backend is needed).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

__all__ = ["KINDS", "factors", "plan", "study_figures"]

_FIXED = ("scenario_id", "groups", "vehicle", "manoeuvre", "metric", "status", "value", "unit")
_BASE_FACTORS = ("freight_kg", "stiffness_scale", "damping_scale")
_LABELS = {"freight_kg": "freight [kg]", "stiffness_scale": "stiffness scale [-]", "damping_scale": "damping scale [-]"}
HEATMAP_LEVELS = 5


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
    """The columns of a study table that vary (more than one value), in table order."""
    out = []
    for col in (*_BASE_FACTORS, *_override_columns(frame)):
        if col in frame.columns and frame[col].astype(str).nunique() > 1:
            out.append(col)
    return out


def _numeric(values) -> bool:
    return all(isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) for v in values)


def _levels(series) -> list:
    values = list(dict.fromkeys(series.dropna().tolist()))
    return sorted(values) if _numeric(values) else sorted(values, key=str)


def _x(levels):
    """x positions and tick labels: the values themselves if numeric, else 0, 1, 2 ... with labels."""
    if _numeric(levels):
        return {v: float(v) for v in levels}, None
    return {v: float(i) for i, v in enumerate(levels)}, [str(v) for v in levels]


def _label(col: str) -> str:
    return _LABELS.get(col, col)


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.=-]+", "_", text).strip("_") or "metric"


def _line(ax, sub, col, name, marker="o"):
    levels = _levels(sub[col])
    pos, ticks = _x(levels)
    means = sub.groupby(sub[col].map(lambda v: pos.get(v)))["value"].mean().sort_index()
    ax.plot(means.index, means.to_numpy(), marker=marker, label=str(name))
    if ticks is not None:
        ax.set_xticks(list(pos.values()), ticks)


def _one(fig, data, col, ylabel):
    ax = fig.subplots()
    for man, sub in data.groupby("manoeuvre", sort=False):
        _line(ax, sub, col, man)
    ax.set_xlabel(_label(col))
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small", title="manoeuvre")


def _is_grid(data, cols) -> bool:
    """Both factors with HEATMAP_LEVELS levels or more, every pair present for every manoeuvre."""
    a, b = cols
    na, nb = len(_levels(data[a])), len(_levels(data[b]))
    return min(na, nb) >= HEATMAP_LEVELS and all(
        len(sub.groupby([a, b])) == na * nb for _, sub in data.groupby("manoeuvre", sort=False))


def _two(fig, data, cols, ylabel, heat=False):
    a, b = cols
    na, nb = len(_levels(data[a])), len(_levels(data[b]))
    x, family = (a, b) if na >= nb else (b, a)
    manoeuvres = list(dict.fromkeys(data["manoeuvre"]))
    axes = fig.subplots(1, len(manoeuvres), squeeze=False)[0]
    for ax, man in zip(axes, manoeuvres, strict=True):
        sub = data[data["manoeuvre"] == man]
        if heat:
            table = sub.pivot_table(index=family, columns=x, values="value", aggfunc="mean")
            image = ax.imshow(table.to_numpy(), origin="lower", aspect="auto", cmap="viridis")
            ax.set_xticks(range(table.shape[1]), [f"{v:g}" if _numeric([v]) else str(v) for v in table.columns],
                          rotation=45)
            ax.set_yticks(range(table.shape[0]), [f"{v:g}" if _numeric([v]) else str(v) for v in table.index])
            ax.set_ylabel(_label(family))
            fig.colorbar(image, ax=ax, label=ylabel)
        else:
            for level in _levels(sub[family]):
                _line(ax, sub[sub[family] == level], x, f"{level:g}" if _numeric([level]) else level)
            ax.set_ylabel(ylabel)
            ax.grid(alpha=0.3)
            ax.legend(fontsize="small", title=_label(family))
        ax.set_xlabel(_label(x))
        ax.set_title(str(man))


def _main_effects(fig, data, cols, ylabel):
    n = len(cols)
    ncols = min(n, 3)
    axes = fig.subplots(math.ceil(n / ncols), ncols, squeeze=False).ravel()
    for ax, col in zip(axes, cols, strict=False):
        for man, sub in data.groupby("manoeuvre", sort=False):
            _line(ax, sub[sub[col].notna()], col, man)
        ax.set_xlabel(_label(col))
        ax.set_ylabel(f"mean {ylabel}")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize="small", title="manoeuvre")
    for ax in axes[n:]:
        ax.set_visible(False)


def _bars(fig, data, ylabel):
    ax = fig.subplots()
    means = data.groupby("manoeuvre", sort=False)["value"].mean()
    ax.bar([str(m) for m in means.index], means.to_numpy())
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3, axis="y")


KINDS = ("bars", "one factor", "two factors", "heat map", "main effects")


def plan(frame) -> list[tuple[str, str, list[str]]]:
    """What :func:`study_figures` draws for a study table: ``(metric, kind, factors)`` per metric with a
    value, ``kind`` one of :data:`KINDS`."""
    data = _long(frame)
    out = []
    for metric, rows in data.groupby("metric", sort=False):
        rows = rows[rows["value"].notna()]
        if rows.empty:
            continue
        varying = [c for c in factors(frame) if rows[c].astype(str).nunique() > 1]
        if len(varying) == 2 and _is_grid(rows, varying):
            kind = "heat map"
        else:
            kind = KINDS[min(len(varying), 2)] if len(varying) < 3 else "main effects"
        out.append((str(metric), kind, varying))
    return out


def _judged_by(rows) -> str:
    """What a metric's values were judged by, for its title: `` under course, driver speed control``."""
    parts = []
    for col, word in (("criterion", "{} criterion"), ("speed_control", "{} speed control")):
        if col in rows.columns and rows[col].notna().any():
            values = sorted(rows[col].dropna().astype(str).unique())
            parts.append(word.format("/".join(values)))
    return f" ({', '.join(parts)})" if parts else ""


def study_figures(frame, out_dir: str | Path, title: str | None = None, dpi: int = 110) -> list[Path]:
    """Draw the figures of a study table (:meth:`StudyStore.to_pandas`) into ``out_dir``.

    Returns
    -------
    list of Path
        ``fig_<metric>.png`` per metric with at least one value (the kind: :func:`plan`).
    """
    from matplotlib.figure import Figure

    from .._files import atomic_write

    out_dir = Path(out_dir)
    data = _long(frame)
    written = []
    for metric, kind, varying in plan(frame):
        rows = data[(data["metric"] == metric) & data["value"].notna()]
        unit = rows["unit"].dropna().iloc[0] if rows["unit"].notna().any() else ""
        ylabel = f"{metric} [{unit}]" if unit else metric
        n_man = rows["manoeuvre"].nunique()
        if kind == "bars":
            fig = Figure(figsize=(5.5, 4.0))
            _bars(fig, rows, ylabel)
        elif kind == "one factor":
            fig = Figure(figsize=(6.5, 4.2))
            _one(fig, rows, varying[0], ylabel)
        elif kind in ("two factors", "heat map"):
            fig = Figure(figsize=(5.5 * n_man + 1.0, 4.4))
            _two(fig, rows, varying, ylabel, heat=kind == "heat map")
        else:
            n = len(varying)
            fig = Figure(figsize=(4.6 * min(n, 3), 3.8 * math.ceil(n / 3)))
            _main_effects(fig, rows, varying, ylabel)
        fig.suptitle(f"{title + ': ' if title else ''}{metric}{_judged_by(rows)} ({kind})")
        fig.tight_layout()
        path = out_dir / f"fig_{_slug(metric)}.png"
        atomic_write(path, lambda fh, fig=fig: fig.savefig(fh, dpi=dpi, format="png"))
        written.append(path)
    return written
