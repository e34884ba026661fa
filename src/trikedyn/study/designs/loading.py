"""A loading chart for operators: the safe speed over freight mass and freight position.

For each cell of a grid (freight mass [kg] x fore-aft position x [m] x height z [m] of the freight site),
the vehicle is given the paper's freight (:func:`~trikedyn.params.ops.with_freight`) at the site moved by
the design knobs ``freight.x_m`` and ``freight.z_m`` (:func:`~trikedyn.params.knobs.apply_knobs`), and the
threshold velocity on a manoeuvre is searched (:func:`~trikedyn.analysis.threshold.threshold_velocity`).
The **safe speed** is the threshold less a stated margin, never below 0:

* ``margin_kmh`` (default 5 km/h): ``safe = max(threshold - margin_kmh, 0)``;
* ``margin_fraction`` F: ``safe = max(threshold * (1 - F), 0)``.

With a search of another registered study metric (``search.metric``: ``tilt_angle``, ``peak_ri`` ...), each cell
holds that metric's value in its unit instead of the threshold, and there is **no safe speed** (a margin is a
speed below a threshold): the chart shows the metric itself, and the JSON and CSV name it by the metric
(:mod:`~trikedyn.study.designs.named`: a cell's ``value``, the CSV's ``METRIC`` column).

A cell whose vehicle is invalid, or whose search fails or finds no threshold, is null with the reason. The
cells run on a process pool (:mod:`trikedyn.study.engine.executors`). :func:`run_loading_chart` returns a
:class:`LoadingChart` (``to_dict``, ``rows`` for a CSV, ``plot``; matplotlib is imported only to plot).

Given a :class:`CellLog`, each cell is appended to it (a CSV, flushed) as it finishes; with ``resume`` the cells
logged already are read back and not run again, so a chart killed half way goes on where it stopped and ends
with the table an uninterrupted run gives.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from ...errors import InputError, RunIncomplete
from ...params.io import ParameterSet
from ..engine.executors import worker_count
from ..engine.pool import ResilientPool, SchedulerGone, WorkersKeptDying
from .loading_grid import (  # noqa: F401  (re-exported: the module is the design's entry point)
    DEFAULT_MARGIN_KMH,
    DEFAULT_MASSES_KG,
    DEFAULT_X_OFFSETS_M,
    DEFAULT_Z_OFFSETS_M,
    CellLog,
    default_grid,
    evaluate_cell,
    grid_cells,
    safe_speed,
)
from .search import Search

__all__ = ["DEFAULT_MARGIN_KMH", "DEFAULT_MASSES_KG", "DEFAULT_X_OFFSETS_M", "DEFAULT_Z_OFFSETS_M", "CellLog",
           "LoadingChart", "default_grid", "evaluate_cell", "grid_cells", "run_loading_chart", "safe_speed"]

@dataclass
class LoadingChart:
    """The safe speed over freight mass and position.

    Attributes
    ----------
    vehicle, manoeuvre : str
    masses_kg, x_m, z_m : list of float
        The grid: freight masses [kg], fore-aft positions and heights of the freight [m] (vehicle axes).
    threshold : dict
        ``(mass, x, z)`` -> threshold velocity [km/h] or None.
    errors : dict
        ``(mass, x, z)`` -> None or why the cell is null.
    margin_kmh, margin_fraction : float or None
        The margin: one of them is set.
    search : Search
    """

    vehicle: str
    manoeuvre: str
    masses_kg: list
    x_m: list
    z_m: list
    threshold: dict
    errors: dict
    margin_kmh: float | None = DEFAULT_MARGIN_KMH
    margin_fraction: float | None = None
    search: Search = field(default_factory=Search)
    site_m: tuple = (0.0, 0.0, 0.0)
    workers: int | None = 2
    wall_time_s: float = 0.0
    resumed: int = 0
    """Cells read from the log of an earlier, interrupted run (not run again)."""
    computed: int = 0
    """Cells run by this call."""

    @property
    def of_threshold(self) -> bool:
        """The cells hold the threshold (else another study metric, and there is no safe speed)."""
        return self.search.metric == "threshold"

    @property
    def margin_text(self) -> str:
        """The margin in words (``'10% below the threshold'`` or ``'5 km/h below the threshold'``)."""
        if not self.of_threshold:
            return f"none: a chart of {self.search.metric} has no safe speed"
        if self.margin_fraction is not None:
            return f"{self.margin_fraction:.0%} below the threshold"
        return f"{self.margin_kmh:g} km/h below the threshold"

    def safe(self, key) -> float | None:
        """The safe speed of one cell [km/h] (:func:`safe_speed`).

        Parameters
        ----------
        key : tuple of float
            (mass [kg], x [m], z [m]).

        Returns
        -------
        float or None
            Speed [km/h], None without a threshold (or in a chart of another metric).
        """
        if not self.of_threshold:
            return None
        return safe_speed(self.threshold[key], self.margin_kmh, self.margin_fraction)

    def keys(self):
        """The cells in their order: z, then mass, then x.

        Returns
        -------
        list of tuple of float
            (mass [kg], x [m], z [m]) per cell.
        """
        return [(m, x, z) for z in self.z_m for m in self.masses_kg for x in self.x_m]

    @property
    def failed(self) -> int:
        """Number of cells without a threshold."""
        return sum(e is not None for e in self.errors.values())

    def cells(self) -> list[dict]:
        """Each cell as a dict.

        Returns
        -------
        list of dict
            ``freight_kg``, ``freight_position_m``, ``threshold_speed_kmh``, ``safe_speed_kmh``, ``error`` (the
            threshold's names whatever the metric: :meth:`to_dict` names another metric's value ``value``).
        """
        return [{"freight_kg": m, "freight_position_m": [x, z], "threshold_speed_kmh": self.threshold[(m, x, z)],
                 "safe_speed_kmh": self.safe((m, x, z)), "error": self.errors[(m, x, z)]} for m, x, z in self.keys()]

    def to_dict(self) -> dict:
        """The chart as plain data (the ``--json`` output).

        Returns
        -------
        dict
            The chart (masses [kg], positions [m], speeds [km/h]).
        """
        from .named import by_metric

        at_limit = sum(t is not None and t >= self.search.high_kmh - 1e-9 for t in self.threshold.values()
                       if self.of_threshold)
        return by_metric({
            "vehicle": self.vehicle, "manoeuvre": self.manoeuvre, "options": dict(self.search.options),
            "margin_kmh": self.margin_kmh, "margin_fraction": self.margin_fraction, "margin": self.margin_text,
            "resolution_kmh": self.search.resolution_kmh, "high_kmh": self.search.high_kmh,
            "criterion": self.search.criterion, "speed_control": self.search.speed_control,
            "metric": self.search.metric, "unit": self.search.unit, "metric_options": dict(self.search.metric_options),
            "freight_site_m": list(self.site_m), "masses_kg": list(self.masses_kg), "x_m": list(self.x_m),
            "z_m": list(self.z_m), "cells": self.cells(), "failed": self.failed, "at_search_limit": at_limit,
            "workers": self.workers, "wall_time_s": self.wall_time_s, "cells_resumed": self.resumed,
            "cells_computed": self.computed,
        }, self.search.metric)

    def rows(self) -> list[list]:
        """The cells as CSV rows, the header first.

        Returns
        -------
        list of list
            The rows.
        """
        from .named import column

        out = [["freight_kg", "x_m", "z_m", column("threshold_speed_kmh", self.search.metric), "safe_speed_kmh", "error"]]
        for c in self.cells():
            out.append([c["freight_kg"], *c["freight_position_m"], _blank(c["threshold_speed_kmh"]),
                        _blank(c["safe_speed_kmh"]), c["error"] or ""])
        return out

    def table(self) -> str:
        """A printable table per height: rows freight mass, columns x; each cell ``safe (threshold)``.

        Returns
        -------
        str
            The table.
        """
        if self.of_threshold:
            lines = [f"{self.vehicle} on {self.manoeuvre}: safe speed [km/h] = threshold - margin "
                     f"({self.margin_text}, not below 0); cells: safe (threshold); the threshold under the "
                     f"{self.search.criterion} criterion, {self.search.speed_control} speed control"]
        else:
            lines = [f"{self.vehicle}: {self.search.metric} [{self.search.unit}] per cell (no safe speed: "
                     "a margin applies to the threshold only)"]
        from .named import meets_the_course

        if self.search.course_note() and meets_the_course(self.search.metric):
            lines.append(self.search.course_note())
        width = 15
        for z in self.z_m:
            lines += ["", f"freight height z = {z:.3f} m"]
            lines.append(f"{'freight [kg]':>12}" + "".join(f"{f'x = {x:.3f} m':>{width}}" for x in self.x_m))
            for m in self.masses_kg:
                cells = []
                for x in self.x_m:
                    t = self.threshold[(m, x, z)]
                    if not self.of_threshold:
                        cells.append("-" if t is None else f"{t:.4g} {self.search.unit}")
                        continue
                    cells.append("-" if t is None else f"{self.safe((m, x, z)):.1f} ({t:.1f})")
                lines.append(f"{m:>12g}" + "".join(f"{c:>{width}}" for c in cells))
        reasons = {}
        for key, err in self.errors.items():
            if err is not None:
                reasons.setdefault(err, []).append(key)
        if reasons:
            lines += ["", f"{self.failed} cells null (-):"]
            lines += [f"  {len(keys)} x {err}" for err, keys in reasons.items()]
        if self.of_threshold and any(t is not None and t >= self.search.high_kmh - 1e-9 for t in self.threshold.values()):
            lines.append(f"cells at {self.search.high_kmh:g} km/h passed the whole search (raise --high)")
        return "\n".join(lines)

    def plot(self):
        """One panel per height: safe speed vs freight mass, one line per fore-aft position; a Figure.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from matplotlib.figure import Figure

        n = len(self.z_m)
        fig = Figure(figsize=(3.6 * n + 1.0, 4.2))
        axes = fig.subplots(1, n, sharey=True, squeeze=False)[0]
        for ax, z in zip(axes, self.z_m, strict=True):
            for x in self.x_m:
                ys = [self.safe((m, x, z)) if self.of_threshold else self.threshold[(m, x, z)] for m in self.masses_kg]
                ax.plot(self.masses_kg, [math.nan if y is None else y for y in ys], "o-", label=f"x = {x:.2f} m")
            ax.set_title(f"freight height z = {z:.2f} m", fontsize=9)
            ax.set_xlabel("freight mass [kg]")
            ax.grid(alpha=0.3)
            if self.of_threshold:
                ax.set_ylim(bottom=0)
        axes[-1].legend(fontsize=8, loc="best")
        if self.of_threshold:
            axes[0].set_ylabel("safe speed [km/h]")
            fig.suptitle(f"Loading chart: {self.vehicle}, {self.manoeuvre}; safe speed = threshold velocity less "
                         f"{self.margin_text.replace(' below the threshold', '')}", fontsize=10)
        else:
            what = self.search.metric.replace("_", " ")
            axes[0].set_ylabel(f"{what} [{self.search.unit}]")
            fig.suptitle(f"Loading chart: {self.vehicle}; {what} over the freight's mass and position", fontsize=10)
        fig.tight_layout()
        return fig


def _blank(value):
    return "" if value is None else value


def run_loading_chart(pset: ParameterSet, search: Search, masses_kg: Sequence[float] | None = None,
                      x_m: Sequence[float] | None = None, z_m: Sequence[float] | None = None, *,
                      margin_kmh: float | None = DEFAULT_MARGIN_KMH, margin_fraction: float | None = None,
                      workers: int | None = 2, progress: Callable | None = None, log: CellLog | None = None,
                      resume: bool = False, dask_local: int | None = None,
                      scheduler: str | None = None) -> LoadingChart:
    """The loading chart of ``pset`` (grid: :func:`grid_cells`); cells on ``workers`` processes (0: in this
    process); ``progress(done, total)`` is called about once a second and at the end.

    Each finished cell is appended to ``log`` if given; with ``resume`` the cells in it already
    (:meth:`CellLog.read`) are taken as they are and not run again. Cells left out by workers that kept
    dying are null and not logged: a resumed run tries them again.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    search : Search
        The threshold search (manoeuvre, options, speed range [km/h], criterion).
    masses_kg : sequence of float, optional
        Freight masses [kg].
    x_m : sequence of float, optional
        Fore-aft positions [m].
    z_m : sequence of float, optional
        Heights [m].
    margin_kmh : float, optional
        Margin below the threshold [km/h].
    margin_fraction : float, optional
        Margin as a fraction of the threshold, dimensionless.
    workers : int or None
        Processes (0: one row after the other in this process; None: all cores).
    dask_local : int, optional
        Workers of a new local Dask cluster instead.
    scheduler : str, optional
        Address of a Dask scheduler instead (``tcp://host:port``).
    progress : callable, optional
        ``progress(done, total)``.
    log : CellLog, optional
        Where each cell is logged.
    resume : bool
        Go on from ``log``.

    Returns
    -------
    LoadingChart
        The chart.
    """
    start = time.perf_counter()
    masses, xs, zs = grid_cells(pset, masses_kg, x_m, z_m)
    if margin_fraction is not None and not 0 <= margin_fraction < 1:
        raise InputError("must be >= 0 and < 1", where="--margin-fraction")
    from ...analysis.threshold import manoeuvre_builder

    if search.metric != "threshold":  # no safe speed: no margin
        margin_kmh, margin_fraction = None, None
    elif margin_fraction is None and (margin_kmh is None or not 0 <= margin_kmh < 1000):
        raise InputError("must be >= 0 km/h", where="--margin-kmh")
    search = search.on_course_of(pset)  # every cell meets the reference vehicle's course
    manoeuvre_builder(search.manoeuvre, dict(search.options))  # a bad manoeuvre fails before any process starts
    keys = [(m, x, z) for z in zs for m in masses for x in xs]
    index = {key: i for i, key in enumerate(keys)}
    known = log.read(keys) if log is not None and resume else {}
    threshold: dict = {key: value for key, (value, _) in known.items()}
    errors: dict = {key: error for key, (_, error) in known.items()}
    computed = 0
    if progress is not None:
        progress(len(threshold), len(keys))

    def record(key, value):
        """Keep cell ``key``'s ``value`` (threshold [km/h] or metric value, error or None), log it and report
        progress."""
        nonlocal computed
        speed, error = value
        error = None if error is None else " ".join(str(error).split())
        threshold[key], errors[key] = speed, error
        computed += 1
        if log is not None:
            log.append(index[key], key, speed, error)
        if progress is not None:
            progress(len(threshold), len(keys))

    if log is not None:
        log.open(fresh=not resume)
    pool = ResilientPool(workers, dask_local, scheduler)
    try:
        pool.run(evaluate_cell, ((key, (pset, *key, search)) for key in keys if key not in known), record,
                 lambda key: record(key, (None, "a worker process died on this cell (a crash, or out of memory)")))
    except WorkersKeptDying as exc:  # the cells not run are null
        for key in exc.remaining:
            threshold[key], errors[key] = None, "worker processes kept dying; cell not run"
    except SchedulerGone as exc:  # what finished is logged: a resumed run goes on
        kept = "; the cells done are logged: run again with --resume" if log is not None else ""
        raise RunIncomplete(f"{exc}; {len(threshold)} of {len(keys)} cells done{kept}") from None
    finally:
        pool.close()
        if log is not None:
            log.close()
    if progress is not None:
        progress(len(threshold), len(keys))
    site = pset.params.freight
    return LoadingChart(pset.name, search.manoeuvre, masses, xs, zs, threshold, errors, margin_kmh=margin_kmh
                        if margin_fraction is None else None, margin_fraction=margin_fraction, search=search,
                        site_m=(site.x_m, site.y_m, site.z_m), workers=worker_count(workers, dask_local, scheduler),
                        wall_time_s=time.perf_counter() - start, resumed=len(known), computed=computed)
