"""The layout optimiser: move named components (and, if asked, the track or the wheelbase) within bounds to
raise the threshold velocity, or its worst case over several manoeuvres.

The paper's design advice is to arrange the cable-connected electrical modules (battery, inverter, control
unit), which can go almost anywhere, so as to get a good centre of gravity. This module searches for that
arrangement:

* an **optimise spec** (:func:`load_optimise_spec`; a small TOML file, or a built-in name such as
  ``battery-layout``) gives the design knobs to move (:mod:`trikedyn.params.knobs`:
  ``component.NAME.x_m|y_m|z_m``, ``track_m``, ``wheelbase_m``, ...) each with ``[low, high]`` bounds, and
  the optimiser's settings::

      [optimise]
      description = "battery within its bay"
      knobs = { "component.battery.x_m" = [0.58, 1.10], "component.battery.z_m" = [0.29, 0.44] }
      manoeuvres = ["dlc"]      # optional (default: dlc); the command's --manoeuvre replaces it
      payload_kg = 0.0          # the paper's freight aboard while searching [kg]
      seed = 1                  # differential evolution's seed
      popsize = 5               # population: popsize x number of knobs (at least 5)
      maxiter = 8               # generations after the first
      # optional: tol = 0.002, step = 0.001 (knob values rounded to this [knob unit]),
      #           resolution_kmh = 0.1, high_kmh = 90 (the threshold search)

* the objective of a layout is the **worst threshold velocity** [km/h] over the manoeuvres, each found by
  the margin search every sampled study uses (:meth:`~trikedyn.study.sample_runs.Search.threshold`); a
  layout that gives an invalid vehicle or no threshold counts as 0 km/h;
* the optimiser is :func:`scipy.optimize.differential_evolution` (``best1bin``, Latin-hypercube start,
  seeded, no gradient polish: the threshold is piecewise constant in steps of the search's resolution;
  ``updating="deferred"``, so the run is the same on one process or many). The reference layout is a member
  of the first population (when inside the bounds), so the best layout is never worse than it;
* knob values are rounded to ``step`` (1 mm) before a layout is evaluated: a buildable layout, and repeated
  layouts are searched once;
* among layouts of equal worst threshold, the best is the one that moves least from the reference (the
  sum of each knob's move as a fraction of its range).

:func:`run_optimise` evaluates each generation on a process pool (:mod:`trikedyn.study.executors`), logs
every evaluation as it finishes (:class:`EvaluationLog`, a CSV; with ``resume`` the logged layouts are
not searched again and, the optimiser being deterministic for its seed, an interrupted run replays to where
it stopped and goes on), and returns an :class:`OptimiseResult` (``to_dict``, ``table``, ``plot``,
``vehicle``: the optimised :class:`~trikedyn.params.io.ParameterSet`, to write with
:func:`~trikedyn.params.io.save_vehicle`).
"""

from __future__ import annotations

import csv
import io
import math
import os
import time
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from difflib import get_close_matches
from importlib import resources
from pathlib import Path

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from .._validation import describe_validation_error
from ..errors import InputError, ParameterError, SimulationError
from ..params.io import ParameterSet
from .sample_runs import MAX_RESTARTS, Search

__all__ = ["MAX_EVALUATIONS", "Evaluation", "EvaluationLog", "OptimiseResult", "OptimiseSpec", "evaluate_layout",
           "list_optimise_specs", "load_optimise_spec", "parse_optimise_spec", "population_size", "run_optimise",
           "worst"]

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
    resolution_kmh: float = Field(default=0.1, ge=0.01, le=10, description="threshold search resolution [km/h]")
    high_kmh: float = Field(default=90.0, ge=11, le=400, description="highest speed searched [km/h]")

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
    description: str = ""
    origin: str = "<string>"

    @property
    def names(self) -> list[str]:
        return [k[0] for k in self.knobs]

    def to_dict(self) -> dict:
        return {"origin": self.origin, "description": self.description,
                "knobs": {n: [lo, hi] for n, lo, hi in self.knobs}, "manoeuvres": list(self.manoeuvres),
                "payload_kg": self.payload_kg, "seed": self.seed, "popsize": self.popsize, "maxiter": self.maxiter,
                "tol": self.tol, "step": self.step, "resolution_kmh": self.resolution_kmh, "high_kmh": self.high_kmh}

    def check(self, pset: ParameterSet) -> None:
        """The knobs exist on ``pset`` and their bounds lie within each knob's own bounds.

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
    """Names of the optimise specs shipped with trikedyn (``battery-layout``)."""
    return sorted(p.name[:-5] for p in _spec_dir().iterdir() if p.name.endswith(".toml"))


def load_optimise_spec(name_or_path: str | Path | OptimiseSpec) -> OptimiseSpec:
    """An optimise spec by built-in name (``"battery-layout"``) or from a TOML file.

    Raises
    ------
    InputError
        An unknown name (with a close match), a missing or unreadable file, invalid TOML, an unknown key
        (with a close match), a value out of range; one line naming the file and the field.
    """
    if isinstance(name_or_path, OptimiseSpec):
        return name_or_path
    text = str(name_or_path)
    path = Path(text)
    if path.suffix == ".toml" or "/" in text or os.sep in text or path.is_file():
        from ..params.tomlfile import is_file, read_text

        if not is_file(path):
            raise InputError("no such optimise spec file", where=text)
        return parse_optimise_spec(read_text(path, text), origin=text)
    names = list_optimise_specs()
    if text not in names:
        hint = get_close_matches(text, names, n=1)
        tip = f"; did you mean '{hint[0]}'?" if hint else ""
        raise InputError(f"unknown optimise spec '{text}'{tip} (built in: {', '.join(names)}; or give a .toml file)",
                         where="--spec")
    return parse_optimise_spec((_spec_dir() / f"{text}.toml").read_text(encoding="utf-8"), origin=text)


def parse_optimise_spec(source: str | dict, origin: str = "<string>") -> OptimiseSpec:
    """Validate an optimise spec given as TOML text or as the dict it parses to (see the module docstring)."""
    if isinstance(source, str):
        try:
            raw = tomllib.loads(source)
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"invalid TOML: {' '.join(str(exc).split())}", where=origin) from None
    else:
        raw = dict(source)
    try:
        model = _File.model_validate(raw)
    except ValidationError as exc:
        raise InputError(describe_validation_error(exc, raw, _File), where=origin) from None
    o = model.optimise
    return OptimiseSpec(knobs=tuple((n, float(lo), float(hi)) for n, (lo, hi) in o.knobs.items()),
                        manoeuvres=tuple(o.manoeuvres), payload_kg=float(o.payload_kg), seed=int(o.seed),
                        popsize=int(o.popsize), maxiter=int(o.maxiter), tol=float(o.tol), step=float(o.step),
                        resolution_kmh=float(o.resolution_kmh), high_kmh=float(o.high_kmh),
                        description=o.description, origin=origin)


def population_size(popsize: int, n_knobs: int) -> int:
    """Layouts per generation: scipy's ``max(5, popsize x n_knobs)``."""
    return max(5, popsize * max(1, n_knobs))


# ------------------------------------------------------------------------------------------------
# one evaluation (runs in a worker process)
# ------------------------------------------------------------------------------------------------
def evaluate_layout(pset: ParameterSet, knobs: dict, searches: tuple[Search, ...],
                    payload_kg: float = 0.0) -> tuple[tuple[float | None, ...], str | None]:
    """The threshold velocity [km/h] on each search's manoeuvre of ``pset`` with the design ``knobs`` set
    (none: the vehicle as given) and ``payload_kg`` of the paper's freight, and why any is None.

    Never raises for a bad layout: an invalid vehicle or a failed search is a None with the reason."""
    from ..params.knobs import apply_knobs
    from ..params.ops import with_freight

    try:
        vehicle = with_freight(apply_knobs(pset, knobs) if knobs else pset, payload_kg)
    except ParameterError as exc:
        return tuple(None for _ in searches), f"invalid vehicle: {' '.join(str(exc).split())}"
    thresholds, errors = [], []
    for search in searches:
        value, error = search.threshold(vehicle)
        thresholds.append(value)
        if error:
            errors.append(f"{search.manoeuvre}: {error}")
    return tuple(thresholds), "; ".join(errors) or None


def worst(thresholds: Sequence[float | None]) -> float:
    """The objective of a layout: its lowest threshold [km/h] over the manoeuvres, a None counting as 0."""
    return min((0.0 if t is None else float(t)) for t in thresholds)


@dataclass(frozen=True)
class Evaluation:
    """One layout searched: its knob values (None: the reference vehicle as given), thresholds per manoeuvre
    [km/h], why any is None, its order and its generation (-1: the reference)."""

    index: int
    generation: int
    values: tuple[float, ...] | None
    thresholds: tuple[float | None, ...]
    error: str | None = None

    @property
    def worst(self) -> float:
        return worst(self.thresholds)


# ------------------------------------------------------------------------------------------------
# the log (CSV, a row appended and flushed as each layout finishes)
# ------------------------------------------------------------------------------------------------
class EvaluationLog:
    """Every evaluation of a run as a CSV file, a row appended as it finishes.

    Columns: ``evaluation``, ``generation`` (-1: the reference vehicle), ``status`` (``ok`` or ``failed``),
    ``worst_threshold_speed_kmh``, ``threshold_MANOEUVRE_kmh`` per manoeuvre, ``error``, then each knob's
    value (blank for the reference).
    """

    def __init__(self, path: str | os.PathLike, knobs: Sequence[str], manoeuvres: Sequence[str]):
        self.path = Path(path)
        self.knobs = list(knobs)
        self.manoeuvres = list(manoeuvres)
        self.columns = ["evaluation", "generation", "status", "worst_threshold_speed_kmh",
                        *(f"threshold_{Path(m).stem if m.lower().endswith('.csv') else m}_kmh" for m in self.manoeuvres),
                        "error", *self.knobs]
        self._fh = None

    def read(self) -> list[Evaluation]:
        """The evaluations logged already (a row cut short by a kill is left out: evaluated again).

        Raises
        ------
        InputError
            The file's columns are not those of this run.
        """
        from .._files import refuse_symlink

        if not refuse_symlink(self.path).exists():
            return []
        text = self.path.read_text(encoding="utf-8", errors="replace")
        if text and not text.endswith("\n"):
            text = text[: text.rfind("\n") + 1]
        rows = list(csv.reader(io.StringIO(text)))
        if not rows:
            return []
        if rows[0] != self.columns:
            raise InputError("its columns are not those of this run; use another --out or --force", where=str(self.path))
        n_m = len(self.manoeuvres)
        out = []
        for row in rows[1:]:
            if len(row) != len(self.columns) or row[2] not in ("ok", "failed"):
                continue
            try:
                index, generation = int(row[0]), int(row[1])
                thresholds = tuple(float(v) if v else None for v in row[4:4 + n_m])
                raw = row[5 + n_m:]
                values = None if generation < 0 else tuple(float(v) for v in raw)
            except ValueError:
                continue
            out.append(Evaluation(index, generation, values, thresholds, row[4 + n_m] or None))
        return out

    def open(self, fresh: bool) -> None:
        """Open for appending (``fresh``: empty it first), the header written into an empty file."""
        from .._files import open_nofollow

        fd = open_nofollow(self.path)
        if fresh:
            os.ftruncate(fd, 0)
        size = os.lseek(fd, 0, os.SEEK_END)
        ends_cleanly = True
        if size:
            os.lseek(fd, size - 1, os.SEEK_SET)
            ends_cleanly = os.read(fd, 1) == b"\n"
            os.lseek(fd, 0, os.SEEK_END)
        self._fh = os.fdopen(fd, "a", encoding="utf-8", newline="")
        if not ends_cleanly:
            self._fh.write("\n")
        if not size:
            csv.writer(self._fh).writerow(self.columns)
        self._fh.flush()

    def append(self, ev: Evaluation) -> None:
        status = "ok" if all(t is not None for t in ev.thresholds) else "failed"
        values = [""] * len(self.knobs) if ev.values is None else [repr(float(v)) for v in ev.values]
        row = [ev.index, ev.generation, status, repr(ev.worst), *("" if t is None else repr(float(t)) for t in ev.thresholds),
               " ".join((ev.error or "").split()), *values]
        csv.writer(self._fh).writerow(row)
        self._fh.flush()

    def close(self) -> None:
        if self._fh is not None:
            self._fh.close()
            self._fh = None


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
        return [s.manoeuvre for s in self.searches]

    @property
    def best_threshold_speed_kmh(self) -> float:
        return self.best.worst

    @property
    def reference_threshold_speed_kmh(self) -> float:
        return self.reference.worst

    def moves(self) -> list[dict]:
        units = _units(self.spec.names)
        return [{"knob": name, "unit": unit, "reference": ref, "best": best, "move": round(best - ref, 9),
                 "low": low, "high": high}
                for (name, low, high), ref, best, unit in zip(self.spec.knobs, self.reference_values,
                                                             self.best.values, units, strict=True)]

    def to_dict(self) -> dict:
        """The result as plain data (the ``--json`` output; the command adds ``vehicle_file`` and ``files``)."""
        failed = sum(e.error is not None for e in self.evaluations)
        return {
            "vehicle": self.vehicle_name, "spec": self.spec.origin, "description": self.spec.description,
            "manoeuvres": self.manoeuvres, "options": {s.manoeuvre: dict(s.options) for s in self.searches},
            "payload_kg": self.spec.payload_kg,
            "objective": "worst threshold velocity over the manoeuvres" if len(self.searches) > 1 else "threshold velocity",
            "best_threshold_speed_kmh": self.best_threshold_speed_kmh,
            "reference_threshold_speed_kmh": self.reference_threshold_speed_kmh,
            "gain_kmh": round(self.best_threshold_speed_kmh - self.reference_threshold_speed_kmh, 9),
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
            "at_search_limit": self.best_threshold_speed_kmh >= self.searches[0].high_kmh - 1e-9,
            "workers": self.workers, "wall_time_s": self.wall_time_s,
        }

    def table(self) -> str:
        """The result for reading."""
        ref, best = self.reference_threshold_speed_kmh, self.best_threshold_speed_kmh
        what = "worst threshold over " + ", ".join(self.manoeuvres) if len(self.searches) > 1 else \
            f"threshold on {self.manoeuvres[0]}"
        load = f", {self.spec.payload_kg:g} kg freight" if self.spec.payload_kg else ""
        lines = [f"{self.vehicle_name}, spec {self.spec.origin}{load}: {what} {ref:.1f} -> {best:.1f} km/h "
                 f"({best - ref:+.1f} km/h)"]
        if len(self.searches) > 1:
            for m, r, b in zip(self.manoeuvres, self.reference.thresholds, self.best.thresholds, strict=True):
                lines.append(f"  {m}: {_kmh(r)} -> {_kmh(b)} km/h")
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
        if best >= self.searches[0].high_kmh - 1e-9:
            lines.append(f"  the best layout passed the whole search ({self.searches[0].high_kmh:g} km/h): raise --high")
        return "\n".join(lines)

    def plot(self):
        """Left: each layout's (worst) threshold over the evaluations, the best so far and the reference;
        right: each knob's reference and best value within its bounds. A matplotlib Figure."""
        from matplotlib.figure import Figure

        fig = Figure(figsize=(11.0, 4.2))
        ax, bx = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.4, 1.0]})
        evs = [e for e in self.evaluations if e.generation >= 0]
        n = np.arange(1, len(evs) + 1)
        y = np.array([e.worst for e in evs])
        ok = np.array([e.error is None for e in evs], dtype=bool)
        ax.plot(n[ok], y[ok], "o", ms=3, color="tab:blue", alpha=0.6, label="a layout")
        if (~ok).any():
            ax.plot(n[~ok], y[~ok], "x", ms=4, color="tab:red", label="failed (counted as 0)")
        if len(y):
            ax.step(n, np.maximum.accumulate(y), where="post", color="k", lw=1.2, label="best so far")
        ax.axhline(self.reference_threshold_speed_kmh, color="tab:orange", ls="--", lw=1.2,
                   label=f"reference {self.reference_threshold_speed_kmh:.1f} km/h")
        finite = y[ok] if ok.any() else np.array([self.reference_threshold_speed_kmh])
        low = min(finite.min(), self.reference_threshold_speed_kmh)
        high = max(finite.max(), self.reference_threshold_speed_kmh)
        pad = max(0.5, 0.1 * (high - low))
        ax.set_ylim(low - pad, high + pad)
        ax.set_xlabel("evaluation")
        label = "worst threshold velocity" if len(self.searches) > 1 else "threshold velocity"
        ax.set_ylabel(f"{label} [km/h]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
        ax.set_title(f"{', '.join(self.manoeuvres)}: {self.reference_threshold_speed_kmh:.1f} -> "
                     f"{self.best_threshold_speed_kmh:.1f} km/h", fontsize=9)
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


def _kmh(value) -> str:
    return "none" if value is None else f"{value:.1f}"


def _units(names: Sequence[str]) -> list[str]:
    from ..params.knobs import KNOBS

    out = []
    for name in names:
        key = name if name in KNOBS else f"component.NAME.{name.rsplit('.', 1)[-1]}"
        out.append(KNOBS[key].unit if key in KNOBS else "")
    return out


# ------------------------------------------------------------------------------------------------
# the run
# ------------------------------------------------------------------------------------------------
def reference_values(pset: ParameterSet, names: Sequence[str]) -> tuple[float, ...]:
    """The value each knob has on the vehicle as given (the track and wheelbase measured from the wheels)."""
    params = pset.params
    out = []
    for name in names:
        if name.startswith("component."):
            _, comp, fld = name.split(".")
            out.append(float(getattr(next(c for c in params.components if c.name == comp), fld)))
        elif name.startswith("freight."):
            out.append(float(getattr(params.freight, name.split(".")[1])))
        elif name == "wheelbase_m":
            steered = [w.x_m for w in params.wheels if w.steered]
            fixed = [w.x_m for w in params.wheels if not w.steered]
            out.append(float(np.mean(steered) - np.mean(fixed)))
        elif name == "track_m":
            pair = [w.y_m for w in params.wheels if w.steered == (params.layout == "tadpole")]
            out.append(float(abs(pair[0] - pair[1])))
        elif name == "cg_height_m":
            out.append(float(params.mass.cg_z_m))
        elif name == "cg_x_fraction":
            steered = np.mean([w.x_m for w in params.wheels if w.steered])
            fixed = np.mean([w.x_m for w in params.wheels if not w.steered])
            out.append(float((params.mass.cg_x_m - fixed) / (steered - fixed)))
        else:
            raise InputError(f"no reference value for the knob '{name}'", where="knobs")
    return tuple(out)


def _rounded(x, spec: OptimiseSpec) -> tuple[float, ...]:
    """Knob values rounded to the spec's step, kept within the bounds."""
    out = []
    for value, (_, low, high) in zip(x, spec.knobs, strict=True):
        v = round(round(float(value) / spec.step) * spec.step, 9)
        out.append(float(min(max(v, low), high)))
    return tuple(out)


class _Evaluator:
    """The map-like callable differential evolution evaluates a generation with: the layouts not yet known
    run on the executor (one for the whole run), each logged as it finishes."""

    def __init__(self, pset, spec, searches, workers, log, known, progress, total):
        self.pset, self.spec, self.searches, self.workers = pset, spec, searches, workers
        self.log, self.progress, self.total = log, progress, total
        self.cache: dict[tuple, Evaluation] = {}
        self.evaluations: list[Evaluation] = []
        self.generation = 0
        self.executor = None
        self.resumed = 0
        self.done = 0
        self.known = {e.values: e for e in known if e.values is not None}
        self.next_index = max((e.index for e in known), default=-1) + 1

    def _executor(self, n_todo):
        from .executors import make_executor

        if self.executor is None:
            self.executor = make_executor(self.workers, None, None, max(n_todo, 1))
        return self.executor

    def close(self, abandon: bool = False):
        """Shut the executor down; ``abandon``: now, the calls in flight lost (a dead worker, Ctrl-C)."""
        if self.executor is not None:
            executor, self.executor = self.executor, None
            if hasattr(executor, "shutdown"):  # a concurrent.futures.Executor
                executor.shutdown(wait=not abandon, cancel_futures=True)
            else:  # the executors' older interface
                if abandon:
                    executor.abandon()
                executor.close()

    def record(self, ev: Evaluation, logged: bool = False):
        self.evaluations.append(ev)
        if ev.values is not None:
            self.cache[ev.values] = ev
            self.done += 1
        if self.log is not None and not logged:
            self.log.append(ev)
        if self.progress is not None:
            self.progress(self.done, self.total)

    def run(self, layouts: list[tuple]) -> None:
        """Evaluate the layouts not in the cache (or the log of an earlier run)."""
        from concurrent.futures import FIRST_COMPLETED, wait
        from concurrent.futures.process import BrokenProcessPool

        todo = []
        for values in dict.fromkeys(layouts):
            if values in self.cache:
                continue
            if values in self.known:
                old = self.known.pop(values)
                self.resumed += 1
                self.record(Evaluation(old.index, old.generation, values, old.thresholds, old.error), logged=True)
            else:
                todo.append(values)
        deaths: dict[tuple, int] = {}
        restarts = 0
        while todo:
            executor = self._executor(len(todo))
            pending: dict = {}
            try:
                while todo or pending:
                    while todo and len(pending) < getattr(executor, "window", 2):
                        values = todo.pop(0)
                        knobs = dict(zip(self.spec.names, values, strict=True))
                        pending[executor.submit(evaluate_layout, self.pset, knobs, self.searches,
                                                self.spec.payload_kg)] = values
                    for fut in wait(list(pending), timeout=1.0, return_when=FIRST_COMPLETED).done:
                        thresholds, error = fut.result()  # a dead worker raises here, its layout still pending
                        values = pending.pop(fut)
                        self.record(Evaluation(self.next_index, self.generation, values, thresholds, error))
                        self.next_index += 1
            except BrokenProcessPool:
                # a worker died (a crash, or out of memory): its layouts go to a new pool; a layout on which
                # workers die twice counts as failed
                self.close(abandon=True)
                restarts += 1
                for values in pending.values():
                    deaths[values] = deaths.get(values, 0) + 1
                    if deaths[values] >= 2:
                        self.record(Evaluation(self.next_index, self.generation, values,
                                               tuple(None for _ in self.searches),
                                               "a worker process died on this layout (twice)"))
                        self.next_index += 1
                    else:
                        todo.insert(0, values)
                if restarts > MAX_RESTARTS:
                    raise SimulationError(f"worker processes died {restarts} times (a crash, or out of memory); the "
                                          "evaluations done are logged: run again with --resume") from None
            except BaseException:
                self.close(abandon=True)
                raise

    def __call__(self, func: Callable, population) -> list[float]:
        xs = list(population)
        self.run([_rounded(x, self.spec) for x in xs])
        self.generation += 1
        return [func(x) for x in xs]

    def objective(self, x) -> float:
        """What differential evolution minimises: minus the worst threshold of the (rounded) layout."""
        ev = self.cache[_rounded(x, self.spec)]
        return -ev.worst


def _least_move(candidates: list[Evaluation], spec: OptimiseSpec, ref: tuple[float, ...]) -> Evaluation:
    """Of layouts with the same objective, the one that moves least from the reference (then the earliest)."""

    def distance(ev):
        return sum(abs(v - r) / (hi - lo) for v, r, (_, lo, hi) in zip(ev.values, ref, spec.knobs, strict=True))

    return min(candidates, key=lambda ev: (round(distance(ev), 12), ev.index))


def run_optimise(pset: ParameterSet, spec: OptimiseSpec | str | Path, searches: Sequence[Search] | None = None, *,
                 workers: int = 2, log: EvaluationLog | None = None, resume: bool = False,
                 progress: Callable | None = None) -> OptimiseResult:
    """Optimise the layout of ``pset`` as ``spec`` says (see the module docstring).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle as given: the reference layout.
    spec : OptimiseSpec, or a built-in name or file
    searches : sequence of Search, optional
        One threshold search per manoeuvre (default: the spec's manoeuvres with its resolution and highest
        speed, default options).
    workers : int
        Processes (0: in this process). The result does not depend on it.
    log : EvaluationLog, optional
        Where each evaluation is appended as it finishes; with ``resume``, the layouts it holds are not
        searched again.
    progress : callable, optional
        ``progress(done, most)``: evaluations done, and the most the run may make.

    Returns
    -------
    OptimiseResult
        With :attr:`OptimiseResult.vehicle`, the optimised vehicle (named ``NAME-optimised``).

    Raises
    ------
    InputError
        A knob the vehicle does not have, bounds outside a knob's own, too many evaluations, a bad manoeuvre.
    """
    from scipy.optimize import differential_evolution

    from ..analysis.threshold import manoeuvre_builder

    start = time.perf_counter()
    spec = load_optimise_spec(spec)
    spec.check(pset)
    if searches is None:
        searches = [Search(m, {}, spec.resolution_kmh, high_kmh=spec.high_kmh) for m in spec.manoeuvres]
    searches = tuple(searches)
    if not searches:
        raise InputError("needs at least one manoeuvre", where="--manoeuvre")
    for s in searches:
        manoeuvre_builder(s.manoeuvre, dict(s.options))  # a bad manoeuvre fails before any process starts
    population = population_size(spec.popsize, len(spec.knobs))
    total = population * (spec.maxiter + 1)
    if total > MAX_EVALUATIONS:
        raise InputError(f"population {population} x {spec.maxiter + 1} generations = {total} evaluations; at most "
                         f"{MAX_EVALUATIONS} (lower popsize or maxiter)", where=spec.origin)
    ref_values = reference_values(pset, spec.names)
    known = log.read() if (log is not None and resume) else []
    if log is not None:
        log.open(fresh=not resume)
    evaluator = _Evaluator(pset, spec, searches, workers, log, known, progress, total)
    try:
        if progress is not None:
            progress(0, total)
        old_ref = next((e for e in known if e.generation < 0), None)
        if old_ref is not None:
            evaluator.resumed += 1
            evaluator.record(old_ref, logged=True)
        else:
            thresholds, error = evaluate_layout(pset, {}, searches, spec.payload_kg)
            evaluator.record(Evaluation(evaluator.next_index, -1, None, thresholds, error))
            evaluator.next_index += 1
        reference = evaluator.evaluations[0]
        bounds = [(lo, hi) for _, lo, hi in spec.knobs]
        x0 = _rounded(ref_values, spec)
        inside = all(lo <= r <= hi for r, (lo, hi) in zip(ref_values, bounds, strict=True))
        import inspect

        # scipy >= 1.15 takes the seed as ``rng`` (a numpy Generator's seed); older releases as ``seed``
        seeding = "rng" if "rng" in inspect.signature(differential_evolution).parameters else "seed"
        result = differential_evolution(
            evaluator.objective, bounds, strategy="best1bin", maxiter=spec.maxiter, popsize=spec.popsize,
            tol=spec.tol, mutation=(0.5, 1.0), recombination=0.7, polish=False, init="latinhypercube",
            updating="deferred", workers=evaluator, x0=x0 if inside else None, **{seeding: spec.seed})
    except BaseException:
        evaluator.close(abandon=True)
        raise
    finally:
        if log is not None:
            log.close()
    evaluator.close()
    if progress is not None:
        progress(evaluator.done, evaluator.done)  # the last line: every evaluation made (repeats are made once)
    layouts = [e for e in evaluator.evaluations if e.generation >= 0]
    top = max(e.worst for e in layouts)
    best = _least_move([e for e in layouts if e.worst == top], spec, ref_values)
    from ..params.knobs import apply_knobs

    vehicle = apply_knobs(pset, dict(zip(spec.names, best.values, strict=True)))
    params = vehicle.params.model_copy(update={
        "name": f"{pset.name}-optimised"[:100],
        "description": (f"{pset.params.description}; layout optimised by trikedyn optimise (spec {spec.origin}: "
                        f"{', '.join(spec.names)})")[:2000]})
    vehicle = vehicle.with_params(params, origin=f"{pset.origin} (optimised)")
    return OptimiseResult(
        vehicle_name=pset.name, spec=spec, searches=searches, reference=reference, best=best,
        reference_values=ref_values, evaluations=evaluator.evaluations, vehicle=vehicle,
        generations=evaluator.generation, message=" ".join(str(result.message).split()),
        resumed=evaluator.resumed, workers=int(workers), wall_time_s=time.perf_counter() - start)
