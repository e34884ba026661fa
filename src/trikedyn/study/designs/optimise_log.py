"""What a layout optimisation found: each evaluation, their CSV log (appended as each finishes, read back
to resume), and the result (:class:`OptimiseResult`: ``to_dict``, ``table``, ``plot``, ``vehicle``)."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...params.io import ParameterSet
from ..optimise_spec import OptimiseSpec, population_size
from .csv_log import AppendedCsv
from .search import Search

__all__ = ["Evaluation", "EvaluationLog", "OptimiseResult", "worst"]


def worst(thresholds: Sequence[float | None], minimise: bool = False, metric: str = "threshold") -> float:
    """The objective of a layout: its worst value over the manoeuvres, the lowest (the highest when the metric
    is minimised). A None (a failed search) counts as 0 km/h for the threshold, as the worst possible value
    (-inf, or +inf when minimised) for another metric.

    Parameters
    ----------
    thresholds : sequence of float or None
        Thresholds [km/h] (or the metric's values [its unit]).
    minimise : bool
        Smaller is better.
    metric : str
        What the values are (``"threshold"``: a failure counts as 0 km/h).

    Returns
    -------
    float
        [km/h] (or the metric's unit).
    """
    if minimise:
        return max((math.inf if t is None else float(t)) for t in thresholds)
    failed = 0.0 if metric == "threshold" else -math.inf
    return min((failed if t is None else float(t)) for t in thresholds)


@dataclass(frozen=True)
class Evaluation:
    """One layout searched: its knob values (None: the reference vehicle as given), thresholds per manoeuvre
    [km/h], why any is None, its order and its generation (-1: the reference)."""

    index: int
    generation: int
    values: tuple[float, ...] | None
    thresholds: tuple[float | None, ...]
    error: str | None = None
    minimise: bool = False
    """Smaller values are better (``--minimise``)."""
    metric: str = "threshold"
    """What :attr:`thresholds` hold: the threshold [km/h] or another study metric [its unit]."""

    @property
    def worst(self) -> float:
        """The layout's objective, its worst value (:func:`worst`): the lowest threshold [km/h] by default."""
        return worst(self.thresholds, self.minimise, self.metric)

    @property
    def score(self) -> float:
        """The objective with larger better: :attr:`worst`, negated when minimising."""
        return -self.worst if self.minimise else self.worst


# ------------------------------------------------------------------------------------------------
# the log (CSV, a row appended and flushed as each layout finishes)
# ------------------------------------------------------------------------------------------------
class EvaluationLog(AppendedCsv):
    """Every evaluation of a run as a CSV file, a row appended as it finishes (and the whole file written again
    in evaluation order at the end of the run, :meth:`rewrite`).

    Columns: ``evaluation``, ``generation`` (-1: the reference vehicle), ``status`` (``ok`` or ``failed``),
    ``worst_threshold_speed_kmh``, ``threshold_MANOEUVRE_kmh`` per manoeuvre, ``error``, then each knob's
    value (blank for the reference). With another ``metric``, ``worst_METRIC`` and ``METRIC_MANOEUVRE``
    (:func:`~trikedyn.study.designs.named.column`).
    """

    def __init__(self, path: str | os.PathLike, knobs: Sequence[str], manoeuvres: Sequence[str],
                 metric: str = "threshold"):
        from .named import column

        self.knobs = list(knobs)
        self.manoeuvres = list(manoeuvres)
        columns = ["evaluation", "generation", "status", "worst_threshold_speed_kmh",
                   *(f"threshold_{Path(m).stem if m.lower().endswith('.csv') else m}_kmh" for m in self.manoeuvres),
                   "error", *self.knobs]
        named = [column(c, metric) if 3 <= i < 4 + len(self.manoeuvres) else c for i, c in enumerate(columns)]
        super().__init__(path, named, columns)

    def read(self) -> list[Evaluation]:
        """The evaluations logged already (a row cut short by a kill is left out: evaluated again).

        Returns
        -------
        list of Evaluation
            The evaluations.

        Raises
        ------
        InputError
            The file's columns are not those of this run.
        """
        n_m = len(self.manoeuvres)
        out = []
        for row in self.logged_rows("use another --out or --force"):
            try:
                index, generation = int(row[0]), int(row[1])
                thresholds = tuple(float(v) if v else None for v in row[4:4 + n_m])
                raw = row[5 + n_m:]
                values = None if generation < 0 else tuple(float(v) for v in raw)
            except ValueError:
                continue
            out.append(Evaluation(index, generation, values, thresholds, row[4 + n_m] or None))
        return out

    def _row(self, ev: Evaluation) -> list:
        status = "ok" if all(t is not None for t in ev.thresholds) else "failed"
        values = [""] * len(self.knobs) if ev.values is None else [repr(float(v)) for v in ev.values]
        return [ev.index, ev.generation, status, repr(ev.worst),
                *("" if t is None else repr(float(t)) for t in ev.thresholds),
                " ".join((ev.error or "").split()), *values]

    def append(self, ev: Evaluation) -> None:
        """Log one finished evaluation (flushed at once).

        Parameters
        ----------
        ev : Evaluation
            The evaluation.
        """
        self.write(self._row(ev))

    def rewrite(self, evaluations: Sequence[Evaluation]) -> None:
        """Write the whole log again with ``evaluations`` in their order (atomically: a kill leaves the old
        file). The log must be closed.

        Parameters
        ----------
        evaluations : sequence of Evaluation
            All of them.
        """
        import csv

        from ..._files import atomic_write

        def fill(fh):
            """Write the header and every evaluation's row to the open file ``fh``."""
            writer = csv.writer(fh)
            writer.writerow(self.columns)
            writer.writerows(self._row(ev) for ev in evaluations)

        atomic_write(self.path, fill, binary=False)


# ------------------------------------------------------------------------------------------------
# the result
# ------------------------------------------------------------------------------------------------
@dataclass
class OptimiseResult:
    """What :func:`run_optimise` found.

    Attributes
    ----------
    vehicle : ParameterSet
        The optimised vehicle (without the payload), named ``NAME-optimised``; write it with
        :func:`~trikedyn.params.io.save_vehicle`.
    reference, best : Evaluation
        The vehicle as given, and the best layout.
    evaluations : list of Evaluation
        Every layout searched, in order (the reference first).
    """

    vehicle_name: str
    spec: OptimiseSpec
    searches: tuple[Search, ...]
    reference: Evaluation
    best: Evaluation
    reference_values: tuple[float, ...]
    evaluations: list
    vehicle: ParameterSet | None = None
    generations: int = 0
    message: str = ""
    resumed: int = 0
    workers: int = 2
    wall_time_s: float = 0.0
    history: list = field(default_factory=list)

    @property
    def manoeuvres(self) -> list[str]:
        """The manoeuvres of the searches, in order."""
        return [s.manoeuvre for s in self.searches]

    @property
    def metric(self) -> str:
        """What is optimised: ``"threshold"`` or another study metric (:attr:`Search.metric`)."""
        return self.searches[0].metric

    @property
    def minimise(self) -> bool:
        """The metric is minimised (else maximised)."""
        return self.best.minimise

    @property
    def best_threshold_speed_kmh(self) -> float:
        """The best layout's worst threshold [km/h] (or metric value)."""
        return self.best.worst

    @property
    def reference_threshold_speed_kmh(self) -> float:
        """The reference vehicle's worst threshold [km/h] (or metric value)."""
        return self.reference.worst

    def moves(self) -> list[dict]:
        """How each knob moved from the reference to the best layout.

        Returns
        -------
        list of dict
            ``knob``, ``unit``, ``reference``, ``best``, ``move``, ``low``, ``high`` (in the knob's unit).
        """
        units = _units(self.spec.names)
        return [{"knob": name, "unit": unit, "reference": ref, "best": best, "move": round(best - ref, 9),
                 "low": low, "high": high}
                for (name, low, high), ref, best, unit in zip(self.spec.knobs, self.reference_values,
                                                             self.best.values, units, strict=True)]

    def to_dict(self) -> dict:
        """The result as plain data (the ``--json`` output; the command adds ``vehicle_file`` and ``files``).

        Returns
        -------
        dict
            The result.
        """
        from .named import by_metric

        failed = sum(e.error is not None for e in self.evaluations)
        best, ref = _finite(self.best_threshold_speed_kmh), _finite(self.reference_threshold_speed_kmh)
        return by_metric({
            "vehicle": self.vehicle_name, "spec": self.spec.origin, "description": self.spec.description,
            "manoeuvres": self.manoeuvres, "options": {s.manoeuvre: dict(s.options) for s in self.searches},
            "payload_kg": self.spec.payload_kg,
            "objective": self._objective_words(),
            "metric": self.metric, "unit": self.searches[0].unit, "metric_options": dict(self.searches[0].metric_options),
            "minimise": self.minimise,
            "best_threshold_speed_kmh": best,
            "reference_threshold_speed_kmh": ref,
            "gain_kmh": None if best is None or ref is None else round(best - ref, 9),
            "thresholds": {m: {"reference": r, "best": b} for m, r, b in
                           zip(self.manoeuvres, self.reference.thresholds, self.best.thresholds, strict=True)},
            "vehicle_file": None,
            "moves": self.moves(),
            "evaluations": len(self.evaluations), "failed_evaluations": failed, "resumed_evaluations": self.resumed,
            "generations": self.generations, "optimiser": {
                "method": "scipy.optimize.differential_evolution (best1bin, latinhypercube, polish off, deferred)",
                "seed": self.spec.seed, "popsize": self.spec.popsize, "population": population_size(
                    self.spec.popsize, len(self.spec.knobs)), "maxiter": self.spec.maxiter, "tol": self.spec.tol,
                "step": self.spec.step, "message": self.message},
            "resolution_kmh": self.searches[0].resolution_kmh, "high_kmh": self.searches[0].high_kmh,
            "criterion": self.searches[0].criterion, "speed_control": self.searches[0].speed_control,
            "at_search_limit": self.metric == "threshold" and self.best_threshold_speed_kmh >= self.searches[0].high_kmh - 1e-9,
            "workers": self.workers, "wall_time_s": self.wall_time_s,
        }, self.metric)

    def _objective_words(self) -> str:
        what = "threshold velocity" if self.metric == "threshold" else self.metric.replace("_", " ")
        how = "minimised" if self.minimise else "maximised"
        if len(self.searches) > 1:
            return f"worst {what} over the manoeuvres ({'highest' if self.minimise else 'lowest'}), {how}"
        return f"{what}, {how}"

    def table(self) -> str:
        """The result for reading.

        Returns
        -------
        str
            The text.
        """
        ref, best = self.reference_threshold_speed_kmh, self.best_threshold_speed_kmh
        name = "threshold" if self.metric == "threshold" else self.metric.replace("_", " ")
        unit, shown = self.searches[0].unit, (".1f" if self.metric == "threshold" else ".4g")
        what = f"worst {name} over " + ", ".join(self.manoeuvres) if len(self.searches) > 1 else \
            f"{name} on {self.manoeuvres[0]}"
        what += " (minimised)" if self.minimise else ""
        load = f", {self.spec.payload_kg:g} kg freight" if self.spec.payload_kg else ""
        gain = f"{best - ref:+{shown}} {unit}" if math.isfinite(best - ref) else "the reference has none"
        lines = [f"{self.vehicle_name}, spec {self.spec.origin}{load}: {what} {ref:{shown}} -> {best:{shown}} {unit} "
                 f"({gain})"]
        if len(self.searches) > 1:
            for m, r, b in zip(self.manoeuvres, self.reference.thresholds, self.best.thresholds, strict=True):
                lines.append(f"  {m}: {_kmh(r, shown)} -> {_kmh(b, shown)} {unit}")
        from .named import meets_the_course

        if self.metric == "threshold":
            lines.append(f"  {self.searches[0].criterion} criterion, {self.searches[0].speed_control} speed control")
        if meets_the_course(self.metric):
            lines += [f"  {m}: {note}" for m, note in ((s.manoeuvre, s.course_note()) for s in self.searches) if note]
        width = max(len(n) for n in self.spec.names) + 2
        lines.append(f"  {'knob':<{width}}{'reference':>10}{'best':>10}{'move':>9}   bounds")
        for mv in self.moves():
            unit = "" if mv["unit"] == "1" else f" {mv['unit']}"
            lines.append(f"  {mv['knob']:<{width}}{mv['reference']:>10.3f}{mv['best']:>10.3f}{mv['move']:>+9.3f}   "
                         f"{mv['low']:g} .. {mv['high']:g}{unit}")
        failed = sum(e.error is not None for e in self.evaluations)
        lines.append(f"  {len(self.evaluations)} evaluations ({self.generations} generations"
                     + (f", {self.resumed} from the log" if self.resumed else "")
                     + (f", {failed} failed" if failed else "")
                     + f", {_workers(self.workers)}, {self.wall_time_s:.0f} s); "
                     f"{self.message}")
        if self.metric == "threshold" and best >= self.searches[0].high_kmh - 1e-9:
            lines.append(f"  the best layout passed the whole search ({self.searches[0].high_kmh:g} km/h): raise --high")
        return "\n".join(lines)

    def plot(self):
        """Left: each layout's (worst) threshold over the evaluations, the best so far and the reference;
        right: each knob's reference and best value within its bounds. A matplotlib Figure.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from matplotlib.figure import Figure

        fig = Figure(figsize=(11.0, 4.2))
        ax, bx = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.4, 1.0]})
        evs = [e for e in self.evaluations if e.generation >= 0]
        n = np.arange(1, len(evs) + 1)
        y = np.array([e.worst for e in evs])
        ok = np.array([e.error is None for e in evs], dtype=bool) & np.isfinite(y)
        ref = self.reference_threshold_speed_kmh
        name = "threshold velocity" if self.metric == "threshold" else self.metric.replace("_", " ")
        unit, shown = self.searches[0].unit, (".1f" if self.metric == "threshold" else ".4g")
        ax.plot(n[ok], y[ok], "o", ms=3, color="tab:blue", alpha=0.6, label="a layout")
        if (~ok).any() and self.metric == "threshold":
            ax.plot(n[~ok], y[~ok], "x", ms=4, color="tab:red", label="failed (counted as 0)")
        if ok.any():
            best_so_far = (np.fmin if self.minimise else np.fmax).accumulate(np.where(ok, y, np.nan))
            ax.step(n, best_so_far, where="post", color="k", lw=1.2, label="best so far")
        if math.isfinite(ref):
            ax.axhline(ref, color="tab:orange", ls="--", lw=1.2, label=f"reference {ref:{shown}} {unit}")
        finite = np.concatenate([y[ok], [ref] if math.isfinite(ref) else []])
        if finite.size:
            pad = max(0.5 if self.metric == "threshold" else 1e-9, 0.1 * (finite.max() - finite.min()))
            ax.set_ylim(finite.min() - pad, finite.max() + pad)
        ax.set_xlabel("evaluation")
        label = f"worst {name}" if len(self.searches) > 1 else name
        ax.set_ylabel(f"{label} [{unit}]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right" if self.minimise else "lower right")
        ax.set_title(f"{', '.join(self.manoeuvres)}: {ref:{shown}} -> "
                     f"{self.best_threshold_speed_kmh:{shown}} {unit}" + (" (minimised)" if self.minimise else ""),
                     fontsize=9)
        moves = self.moves()
        rows = np.arange(len(moves))[::-1]
        for row, mv in zip(rows, moves, strict=True):
            span = mv["high"] - mv["low"]
            r, b = (mv["reference"] - mv["low"]) / span, (mv["best"] - mv["low"]) / span
            bx.plot([0, 1], [row, row], color="0.8", lw=6, solid_capstyle="butt")
            bx.annotate("", xy=(b, row), xytext=(r, row), arrowprops={"arrowstyle": "->", "color": "0.3"})
            bx.plot(r, row, "o", color="tab:orange", ms=7, label="reference" if row == rows[0] else None)
            bx.plot(b, row, "*", color="tab:green", ms=12, label="best" if row == rows[0] else None)
            unit = "" if mv["unit"] == "1" else f" {mv['unit']}"
            bx.text(0.0, row + 0.22, f"{mv['low']:g}", fontsize=7, ha="left", color="0.4")
            bx.text(1.0, row + 0.22, f"{mv['high']:g}{unit}", fontsize=7, ha="right", color="0.4")
            bx.text(b, row - 0.3, f"{mv['best']:.3f}", fontsize=7, ha="center", color="tab:green")
        bx.set_yticks(rows, [mv["knob"] for mv in moves], fontsize=8)
        bx.set_xlim(-0.05, 1.05)
        bx.set_ylim(-0.7, len(moves) + 0.2)
        bx.set_xlabel("position within the bounds [-]")
        bx.set_title("moves", fontsize=9)
        bx.legend(fontsize=8, loc="upper center", ncol=2)
        fig.suptitle(f"Layout optimiser: {self.vehicle_name}, spec {self.spec.origin} ({len(self.evaluations)} "
                     "evaluations, differential evolution)", fontsize=10)
        fig.tight_layout()
        return fig


def _workers(n: int) -> str:
    return "in this process" if n == 0 else f"{n} worker{'s' if n != 1 else ''}"


def _kmh(value, shown: str = ".1f") -> str:
    return "none" if value is None else format(value, shown)


def _finite(value: float) -> float | None:
    """A value for JSON: None for the infinity a failed layout counts as."""
    return float(value) if math.isfinite(value) else None


def _units(names: Sequence[str]) -> list[str]:
    from ...params.knobs import KNOBS

    out = []
    for name in names:
        key = name if name in KNOBS else f"component.NAME.{name.rsplit('.', 1)[-1]}"
        out.append(KNOBS[key].unit if key in KNOBS else "")
    return out
