"""The layout optimiser: move named components (and, if asked, the track or the wheelbase) within bounds to
raise the threshold velocity, or its worst case over several manoeuvres.

The paper's design advice is to arrange the cable-connected electrical modules (battery, inverter, control
unit), which can go almost anywhere, so as to get a good centre of gravity. This module searches for that
arrangement:

* an **optimise spec** (:mod:`trikedyn.study.optimise_spec`; a small TOML file, or a built-in name such as
  ``battery-layout``) gives the design knobs to move, each with ``[low, high]`` bounds, and the optimiser's
  settings;

* the objective of a layout is the **worst threshold velocity** [km/h] over the manoeuvres, each found by
  the margin search every sampled study uses (:meth:`~trikedyn.study.designs.search.Search.threshold`); a
  layout that gives an invalid vehicle or no threshold counts as 0 km/h. With searches of another registered
  study metric (``Search.metric``), that metric is the objective: **maximised**, or minimised with
  ``minimise=True`` (a metric says nothing of which way is better: the caller does); the worst over several
  manoeuvres is then the lowest (the highest when minimising), and a layout that cannot be measured counts as
  the worst possible value;
* the optimiser is :func:`scipy.optimize.differential_evolution` (``best1bin``, Latin-hypercube start,
  seeded, no gradient polish: the threshold is piecewise constant in steps of the search's resolution;
  ``updating="deferred"``, so the run is the same on one process or many). The reference layout is a member
  of the first population (when inside the bounds), so the best layout is never worse than it;
* knob values are rounded to ``step`` (1 mm) before a layout is evaluated: a buildable layout, and repeated
  layouts are searched once;
* among layouts of equal worst threshold, the best is the one that moves least from the reference (the
  sum of each knob's move as a fraction of its range).

:func:`run_optimise` evaluates each generation on a process pool (:mod:`trikedyn.study.engine.executors`), logs
every evaluation as it finishes (:class:`EvaluationLog`, a CSV; with ``resume`` the logged layouts are
not searched again and, the optimiser being deterministic for its seed, an interrupted run replays to where
it stopped and goes on; :mod:`trikedyn.study.designs.optimise_log`), and returns an :class:`OptimiseResult` (``to_dict``, ``table``, ``plot``,
``vehicle``: the optimised :class:`~trikedyn.params.parameter_set.ParameterSet`, to write with
:func:`~trikedyn.params.io.save_vehicle`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from ...errors import InputError, ParameterError, RunIncomplete, SimulationError
from ...params.io import ParameterSet
from ..engine.executors import worker_count
from ..engine.pool import ExecutorLost, ResilientPool
from ..optimise_spec import (
    MAX_EVALUATIONS,
    OptimiseSpec,
    list_optimise_specs,
    load_optimise_spec,
    parse_optimise_spec,
    population_size,
)
from .optimise_log import Evaluation, EvaluationLog, OptimiseResult, worst
from .search import Search

__all__ = ["MAX_EVALUATIONS", "Evaluation", "EvaluationLog", "OptimiseResult", "OptimiseSpec", "evaluate_layout",
           "list_optimise_specs", "load_optimise_spec", "parse_optimise_spec", "population_size", "run_optimise",
           "worst"]


# ------------------------------------------------------------------------------------------------
# one evaluation (runs in a worker process)
# ------------------------------------------------------------------------------------------------
def evaluate_layout(pset: ParameterSet, knobs: dict, searches: tuple[Search, ...],
                    payload_kg: float = 0.0) -> tuple[tuple[float | None, ...], str | None]:
    """The threshold velocity [km/h] on each search's manoeuvre of ``pset`` with the design ``knobs`` set
    (none: the vehicle as given) and ``payload_kg`` of the paper's freight, and why any is None.

    Never raises for a bad layout: an invalid vehicle or a failed search is a None with the reason.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    knobs : dict
        Knob -> value [its unit].
    searches : tuple of Search
        One search per manoeuvre.
    payload_kg : float
        Freight [kg].

    Returns
    -------
    thresholds : tuple of float or None
        [km/h].
    error : str or None
        Why one is None.
    """
    from ...params.knobs import apply_knobs
    from ...params.ops import with_freight

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
    run on its pool (one for the whole run), each logged as it finishes."""

    def __init__(self, pset, spec, searches, workers, log, known, progress, total, dask_local=None, scheduler=None,
                 minimise=False):
        self.pset, self.spec, self.searches, self.workers = pset, spec, searches, workers
        self.minimise, self.metric = bool(minimise), searches[0].metric
        self.log, self.progress, self.total = log, progress, total
        self.cache: dict[tuple, Evaluation] = {}
        self.evaluations: list[Evaluation] = []
        self.generation = 0
        self.pool = ResilientPool(workers, dask_local, scheduler)
        self.resumed = 0
        self.done = 0
        self.known = {e.values: e for e in known if e.values is not None}
        self.next_index = 0  # the reference is evaluation 0; then each generation's new layouts in its order

    def make(self, index: int, generation: int, values, thresholds, error) -> Evaluation:
        """An :class:`Evaluation` of this run (its metric, and which way is better)."""
        return Evaluation(index, generation, values, tuple(thresholds), error, self.minimise, self.metric)

    def close(self, abandon: bool = False):
        """Shut the pool down; ``abandon``: now, the calls in flight lost (Ctrl-C)."""
        self.pool.close(abandon)

    def record(self, ev: Evaluation, logged: bool = False):
        """Keep a finished evaluation (the reference vehicle's too): cached by its knob values, logged, counted."""
        self.evaluations.append(ev)
        self.done += 1
        if ev.values is not None:
            self.cache[ev.values] = ev
        if self.log is not None and not logged:
            self.log.append(ev)
        if self.progress is not None:
            self.progress(self.done, self.total)

    def run(self, layouts: list[tuple]) -> None:
        """Evaluate the layouts not in the cache (or the log of an earlier run).

        Each layout new to the run is numbered by its place in the generation, whatever order the workers
        finish in: the same run numbers its evaluations the same on any number of processes, and a resumed run
        as an uninterrupted one."""
        fresh = [values for values in dict.fromkeys(layouts) if values not in self.cache]
        index = {values: self.next_index + k for k, values in enumerate(fresh)}
        self.next_index += len(fresh)
        todo = []
        for values in fresh:
            if values in self.known:
                old = self.known.pop(values)
                self.resumed += 1
                self.record(self.make(index[values], self.generation, values, old.thresholds, old.error),
                            logged=True)
            else:
                todo.append(values)

        def finished(values, result):
            """Record a layout's evaluation once its worker returns ``result`` = (thresholds, error)."""
            thresholds, error = result
            self.record(self.make(index[values], self.generation, values, thresholds, error))

        def died(values):
            """Record a layout on which a worker died twice as failed (no thresholds)."""
            finished(values, (tuple(None for _ in self.searches), "a worker process died on this layout (twice)"))

        tasks = ((values, (self.pset, dict(zip(self.spec.names, values, strict=True)), self.searches,
                           self.spec.payload_kg)) for values in todo)
        try:
            self.pool.run(evaluate_layout, tasks, finished, died)
        except ExecutorLost as exc:  # workers that kept dying, a lost scheduler
            raise RunIncomplete(f"{exc}; the evaluations done are logged: run again with --resume") from None

    def __call__(self, func: Callable, population) -> list[float]:
        xs = list(population)
        self.run([_rounded(x, self.spec) for x in xs])
        self.generation += 1
        return [func(x) for x in xs]

    def objective(self, x) -> float:
        """What differential evolution minimises: minus the worst threshold of the (rounded) layout (the worst
        value itself when minimising; a failed layout's infinity as a large finite number)."""
        ev = self.cache[_rounded(x, self.spec)]
        return min(-ev.score, 1e300)


def _check_found(layouts: list[Evaluation], log: EvaluationLog | None) -> None:
    """Refuse a run in which no layout was searched on every manoeuvre: its "best" would be a failure (a
    worst threshold of 0 km/h), not an optimised vehicle."""
    if any(all(t is not None for t in e.thresholds) for e in layouts):
        return
    first = next((e.error for e in layouts if e.error), None)
    why = f" (the first: {' '.join(first.split())[:300]})" if first else ""
    kept = f"; each is logged in {log.path}" if log is not None else ""
    raise SimulationError(f"every one of the {len(layouts)} layouts failed{why}: no optimised vehicle{kept}")


def _least_move(candidates: list[Evaluation], spec: OptimiseSpec, ref: tuple[float, ...]) -> Evaluation:
    """Of layouts with the same objective, the one that moves least from the reference (then the earliest)."""

    def distance(ev):
        """How far ``ev``'s layout moves from the reference: the sum of each knob's move over its range,
        dimensionless."""
        return sum(abs(v - r) / (hi - lo) for v, r, (_, lo, hi) in zip(ev.values, ref, spec.knobs, strict=True))

    return min(candidates, key=lambda ev: (round(distance(ev), 12), ev.index))


def run_optimise(pset: ParameterSet, spec: OptimiseSpec | str | Path, searches: Sequence[Search] | None = None, *,
                 workers: int | None = 2, log: EvaluationLog | None = None, resume: bool = False,
                 progress: Callable | None = None, dask_local: int | None = None,
                 scheduler: str | None = None, minimise: bool = False) -> OptimiseResult:
    """Optimise the layout of ``pset`` as ``spec`` says (see the module docstring).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle as given: the reference layout.
    spec : OptimiseSpec, or a built-in name or file
    searches : sequence of Search, optional
        One threshold search per manoeuvre (default: the spec's manoeuvres with its resolution and highest
        speed, default options); all of one study metric (``Search.metric``: the threshold, or another).
    workers : int or None
        Processes (0: in this process; None: all cores). The result does not depend on it (nor on the executor).
    dask_local : int, optional
        Workers of a new local Dask cluster instead.
    scheduler : str, optional
        Address of a Dask scheduler instead (``tcp://host:port``).
    log : EvaluationLog, optional
        Where each evaluation is appended as it finishes; with ``resume``, the layouts it holds are not
        searched again.
    resume : bool
        Go on from ``log`` (a run killed part way): its layouts are kept, not searched again.
    progress : callable, optional
        ``progress(done, most)``: evaluations done (the reference vehicle's included), and the most the run may
        make.
    minimise : bool
        Minimise the searches' metric (default: maximise it).

    Returns
    -------
    OptimiseResult
        With :attr:`OptimiseResult.vehicle`, the optimised vehicle (named ``NAME-optimised``).

    Raises
    ------
    InputError
        A knob the vehicle does not have, bounds outside a knob's own, too many evaluations, a bad manoeuvre.
    SimulationError
        No layout could be searched on every manoeuvre (every evaluation failed: there is no optimised
        vehicle; ``log`` keeps them).
    RunIncomplete
        Worker processes kept dying, or the Dask scheduler is gone (``log`` keeps what finished).

    Notes
    -----
    Evaluations are numbered in a fixed order: the reference 0, then each generation's new layouts in their
    place in it, however many processes run them and in whatever order they finish. ``log`` gets each row as
    it finishes (what a resumed run reads) and, at the end, is written again in that order: two runs of the
    same vehicle and spec write the same file.
    """
    from scipy.optimize import differential_evolution

    from ...analysis.threshold import manoeuvre_builder

    start = time.perf_counter()
    spec = load_optimise_spec(spec)
    spec.check(pset)
    if searches is None:
        searches = [Search(m, {}, spec.resolution_kmh, high_kmh=spec.high_kmh, criterion=spec.criterion,
                           speed_control=spec.speed_control) for m in spec.manoeuvres]
    searches = tuple(s.on_course_of(pset) for s in searches)  # every layout meets the reference's course
    if not searches:
        raise InputError("needs at least one manoeuvre", where="--manoeuvre")
    if len({(s.metric, tuple(sorted(s.metric_options.items()))) for s in searches}) > 1:
        raise InputError("the searches measure different metrics: one objective needs one", where="--metric")
    if minimise and searches[0].metric == "threshold":
        raise InputError("the threshold velocity is maximised; --minimise needs another --metric", where="--minimise")
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
    most = total + 1  # the layouts, and the reference vehicle first
    evaluator = _Evaluator(pset, spec, searches, workers, log, known, progress, most, dask_local, scheduler, minimise)
    try:
        if progress is not None:
            progress(0, most)
        old_ref = next((e for e in known if e.generation < 0), None)
        if old_ref is not None:
            evaluator.resumed += 1
            evaluator.record(evaluator.make(0, -1, None, old_ref.thresholds, old_ref.error), logged=True)
        else:
            thresholds, error = evaluate_layout(pset, {}, searches, spec.payload_kg)
            evaluator.record(evaluator.make(0, -1, None, thresholds, error))
        evaluator.next_index = 1
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
    evaluations = sorted(evaluator.evaluations, key=lambda e: e.index)
    if log is not None:  # in evaluation order: two runs of the same spec write the same file
        log.rewrite(evaluations)
    if progress is not None:
        progress(evaluator.done, evaluator.done)  # the last line: every evaluation made (repeats are made once)
    layouts = [e for e in evaluations if e.generation >= 0]
    _check_found(layouts, log)
    top = max(e.score for e in layouts)
    best = _least_move([e for e in layouts if e.score == top], spec, ref_values)
    from ...params.knobs import apply_knobs

    vehicle = apply_knobs(pset, dict(zip(spec.names, best.values, strict=True)))
    params = vehicle.params.model_copy(update={
        "name": f"{pset.name}-optimised"[:100],
        "description": (f"{pset.params.description}; layout optimised by trikedyn optimise (spec {spec.origin}: "
                        f"{', '.join(spec.names)})")[:2000]})
    vehicle = vehicle.with_params(params, origin=f"{pset.origin} (optimised)")
    return OptimiseResult(
        vehicle_name=pset.name, spec=spec, searches=searches, reference=reference, best=best,
        reference_values=ref_values, evaluations=evaluations, vehicle=vehicle,
        generations=evaluator.generation, message=" ".join(str(result.message).split()),
        resumed=evaluator.resumed, workers=worker_count(workers, dask_local, scheduler), wall_time_s=time.perf_counter() - start)
