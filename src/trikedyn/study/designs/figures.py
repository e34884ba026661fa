"""The figures of a study, chosen from its shape: one PNG per metric, ``fig_<metric>.png`` in its folder.

The *factors* are the table's columns that a study varies: ``freight_kg``, ``stiffness_scale``,
``damping_scale`` and each override (a dotted path or a design knob), counted as varying when they take more
than one value among the metric's rows. An override left empty in a row (the group does not set it) is the
level ``as given``: the vehicle's own value. Columns that always move together (each level of one meets one
level of the other, as the two rear wheels' ``y_m`` of a wider track) are one factor, named by both.
Manoeuvres are not factors: they are the lines (a metric not per manoeuvre, such as the tilt angle, draws one
line, ``vehicle``). By the number of factors:

- none: a bar per manoeuvre;
- one: the metric against the factor, one line per manoeuvre;
- two: one panel per manoeuvre, the metric against the factor with more levels, one line per level of the
  other (a family of lines); a heat map instead when both have five levels or more and form a full grid;
- three or more: main effects (:func:`main_effects`), one panel per factor, one line per manoeuvre.

**A main effect never averages over an unbalanced design without saying so.** The design is *balanced for
a factor* when every level of it meets the same settings of the other factors (a full grid is balanced for
every factor; a union of one-at-a-time groups, such as the paper's study or a spring group beside a track
group, is not: its middle level meets settings the others never meet). Then:

- balanced: the mean at each level over every setting of the other factors; the panel says ``balanced``;
- unbalanced: the means over the *balanced part*, the settings of the other factors that every level meets
  (e.g. ``damping scale = 1`` and the track as given), and the panel's title names that part;
- unbalanced with no setting met by every level: no mean at all, one thin line per setting of the other
  factors over the levels it meets, and the title says so.

The means are means of the per-setting means, so that a setting run twice does not weigh double. The
figure's title says when a panel is not balanced.

Failed scenarios (no value) are left out, before the balance is judged. matplotlib is imported only here,
and only when a figure is drawn (the figure is drawn without pyplot, so no display or backend is needed).
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

from .effects import (  # noqa: F401  (AS_GIVEN, BASES, factors, main_effects: re-exported)
    AS_GIVEN,
    BASES,
    HEATMAP_LEVELS,
    _groups,
    _key,
    _label,
    _level_label,
    _levels,
    _long,
    _slug,
    _with_keys,
    _x,
    factors,
    main_effects,
)

__all__ = ["AS_GIVEN", "BASES", "KINDS", "factors", "main_effects", "plan", "study_figures"]


# ------------------------------------------------------------------------------------------------------------
# drawing
# ------------------------------------------------------------------------------------------------------------
def _line(ax, sub, col, name, marker="o", levels=None, **style):
    levels = levels or _levels(sub[col])
    pos, ticks = _x(levels)
    means = sub.groupby(sub[col].map(lambda v: pos.get(v)))["value"].mean().sort_index()
    ax.plot(means.index, means.to_numpy(), marker=marker, label=str(name), **style)
    if ticks is not None:
        ax.set_xticks(list(pos.values()), ticks)


def _one(fig, data, group, ylabel):
    ax = fig.subplots()
    col = _key(group)
    for man, sub in data.groupby("manoeuvre", sort=False):
        _line(ax, sub, col, man, levels=_levels(data[col]))
    ax.set_xlabel(_label(group))
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small", title="manoeuvre")


def _is_grid(data, groups) -> bool:
    """Both factors with HEATMAP_LEVELS levels or more, every pair present for every manoeuvre."""
    a, b = (_key(g) for g in groups)
    na, nb = len(_levels(data[a])), len(_levels(data[b]))
    if any(isinstance(v, tuple) for v in (*data[a], *data[b])):
        return False  # joined or partly empty factors: lines, with their labels
    return min(na, nb) >= HEATMAP_LEVELS and all(
        len(sub.groupby([a, b])) == na * nb for _, sub in data.groupby("manoeuvre", sort=False))


def _two(fig, data, groups, ylabel, heat=False):
    ga, gb = groups
    a, b = _key(ga), _key(gb)
    na, nb = len(_levels(data[a])), len(_levels(data[b]))
    (x, gx), (family, gf) = ((a, ga), (b, gb)) if na >= nb else ((b, gb), (a, ga))
    manoeuvres = list(dict.fromkeys(data["manoeuvre"]))
    axes = fig.subplots(1, len(manoeuvres), squeeze=False)[0]
    for ax, man in zip(axes, manoeuvres, strict=True):
        sub = data[data["manoeuvre"] == man]
        if heat:
            table = sub.pivot_table(index=family, columns=x, values="value", aggfunc="mean")
            image = ax.imshow(table.to_numpy(), origin="lower", aspect="auto", cmap="viridis")
            ax.set_xticks(range(table.shape[1]), [_level_label(v) for v in table.columns], rotation=45)
            ax.set_yticks(range(table.shape[0]), [_level_label(v) for v in table.index])
            ax.set_ylabel(_label(gf))
            fig.colorbar(image, ax=ax, label=ylabel)
        else:
            for level in _levels(sub[family]):
                _line(ax, sub[sub[family].map(lambda v, level=level: v == level)], x, _level_label(level),
                      levels=_levels(sub[x]))
            ax.set_ylabel(ylabel)
            ax.grid(alpha=0.3)
            ax.legend(fontsize="small", title=_label(gf))
        ax.set_xlabel(_label(gx))
        ax.set_title(str(man))


def _panel_title(effects) -> str:
    """What one main-effects panel averages, per manoeuvre when they differ."""
    texts = {}
    for man, rows in effects.groupby("manoeuvre", sort=False):
        basis, over = rows["basis"].iloc[0], rows["over"].iloc[0]
        texts[man] = {"balanced": "balanced: mean over every other setting",
                      "balanced part": f"unbalanced: mean where {over}",
                      "per setting": "unbalanced, no setting meets every level: one line per setting"}[basis]
    if len(set(texts.values())) == 1:
        text = next(iter(texts.values()))
    else:
        text = "; ".join(f"{m}: {t}" for m, t in texts.items())
    return textwrap.fill(text, 48)


def _main_effects(fig, data, groups, ylabel, effects):
    n = len(groups)
    ncols = min(n, 3)
    axes = fig.subplots(math.ceil(n / ncols), ncols, squeeze=False).ravel()
    colours = {m: f"C{i}" for i, m in enumerate(dict.fromkeys(data["manoeuvre"]))}
    for ax, group in zip(axes, groups, strict=False):
        mine = effects[effects["factor"] == " & ".join(group)]
        levels = _levels(data[_key(group)])
        pos, ticks = _x(levels)
        for man, rows in mine.groupby("manoeuvre", sort=False):
            for k, (line, pts) in enumerate(rows.groupby("line", sort=False)):
                xs = [pos[v] for v in pts["level"]]
                order = sorted(range(len(xs)), key=xs.__getitem__)
                thin = line != "mean"
                ax.plot([xs[i] for i in order], [pts["value"].iloc[i] for i in order], marker=".o"[not thin],
                        color=colours[man], lw=0.8 if thin else 1.5, alpha=0.6 if thin else 1.0,
                        label=str(man) if k == 0 else None)
        if ticks is not None:
            ax.set_xticks(list(pos.values()), ticks)
        ax.set_xlabel(_label(group))
        ax.set_ylabel(ylabel if set(mine["basis"]) == {"per setting"} else f"mean {ylabel}")
        ax.set_title(_panel_title(mine), fontsize="small")
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


def _shape(rows, columns) -> tuple[str, list[tuple[str, ...]]]:
    varying = [c for c in columns if rows[c].astype(str).nunique(dropna=False) > 1]
    groups = _groups(rows, varying)
    if len(groups) == 2 and _is_grid(_with_keys(rows, groups), groups):
        return "heat map", groups
    return (KINDS[len(groups)] if len(groups) < 3 else "main effects"), groups


def plan(frame) -> list[tuple[str, str, list[str]]]:
    """What :func:`study_figures` draws for a study table: ``(metric, kind, columns)`` per metric with a
    value, ``kind`` one of :data:`KINDS`, ``columns`` the varying columns (columns that move together count
    as one factor for the kind).

    Parameters
    ----------
    frame : pandas.DataFrame
        A study table.

    Returns
    -------
    list of tuple
        ``(metric, kind, columns)``.
    """
    data = _long(frame)
    out = []
    for metric, rows in data.groupby("metric", sort=False):
        rows = rows[rows["value"].notna()]
        if rows.empty:
            continue
        kind, groups = _shape(rows, factors(frame))
        out.append((str(metric), kind, [c for g in groups for c in g]))
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

    Parameters
    ----------
    frame : pandas.DataFrame
        The study table.
    out_dir : str or Path
        The folder.
    title : str, optional
        Figure title.
    dpi : int
        Resolution [dots per inch].

    Returns
    -------
    list of Path
        ``fig_<metric>.png`` per metric with at least one value (the kind: :func:`plan`; a main-effects
        figure's numbers: :func:`main_effects`).
    """
    from matplotlib.figure import Figure

    from ..._files import atomic_write

    out_dir = Path(out_dir)
    data = _long(frame)
    written = []
    for metric, _, _ in plan(frame):
        rows = data[(data["metric"] == metric) & data["value"].notna()]
        kind, groups = _shape(rows, factors(frame))
        rows = _with_keys(rows, groups)
        unit = rows["unit"].dropna().iloc[0] if rows["unit"].notna().any() else ""
        ylabel = f"{metric} [{unit}]" if unit else metric
        n_man = rows["manoeuvre"].nunique()
        note = kind
        if kind == "bars":
            fig = Figure(figsize=(5.5, 4.0))
            _bars(fig, rows, ylabel)
        elif kind == "one factor":
            fig = Figure(figsize=(6.5, 4.2))
            _one(fig, rows, groups[0], ylabel)
        elif kind in ("two factors", "heat map"):
            fig = Figure(figsize=(5.5 * n_man + 1.0, 4.4))
            _two(fig, rows, groups, ylabel, heat=kind == "heat map")
        else:
            n = len(groups)
            fig = Figure(figsize=(4.8 * min(n, 3), 4.2 * math.ceil(n / 3)))
            effects = main_effects(frame, metric)
            _main_effects(fig, rows, groups, ylabel, effects)
            if set(effects["basis"]) != {"balanced"}:
                note = "main effects; the design is unbalanced: each panel says what it averages"
        fig.suptitle(textwrap.fill(f"{title + ': ' if title else ''}{metric}{_judged_by(rows)} ({note})", 100))
        fig.tight_layout()
        path = out_dir / f"fig_{_slug(metric)}.png"
        atomic_write(path, lambda fh, fig=fig: fig.savefig(fh, dpi=dpi, format="png"))
        written.append(path)
    return written
