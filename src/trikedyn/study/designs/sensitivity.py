"""Global sensitivity of the threshold velocity to the vehicle's assumed values (Morris screening, Sobol indices).

The reference vehicle carries some sixty values that were not measured (their ``assumed`` notes in the
vehicle file, :attr:`~trikedyn.params.parameter_set.ParameterSet.notes`). This module asks which of them the threshold
velocity on a manoeuvre depends on:

1. :func:`candidate_factors` lists the **factors**: every assumed number, each varied over
   ``value * (1 - fraction) .. value * (1 + fraction)`` (or over a ``range`` declared next to it in the
   vehicle file), less the values that cannot vary on their own or do not act on the vehicle (see
   :data:`EXCLUDED_GROUPS` and the function's notes). A mirrored pair of wheels (the delta trike's rear
   wheels) is varied as a pair: the design knob ``track_m`` (:mod:`trikedyn.params.knobs`) moves both
   wheels' ``y_m`` symmetrically about their centre line, and a value both wheels share (radius, spin
   inertia) is one factor ``wheels.LEFT+RIGHT.ATTR``. :func:`select_factors` picks named factors instead:
   any numeric parameter, measured ones too (``mass.cg_z_m``), or a design knob (``wheelbase_m``,
   ``cg_height_m``, ``component.battery.z_m``, ...).
2. :func:`sample` draws the input matrix with SALib, seeded: Morris trajectories (``method="morris"``,
   ``samples`` trajectories of ``k + 1`` points) or a Saltelli/Sobol' design (``method="sobol"``,
   ``samples * (k + 2)`` points, first-order and total indices).
3. :func:`evaluate_sample` applies one row (:func:`~trikedyn.params.ops.override`) and searches the threshold
   velocity (:func:`~trikedyn.analysis.threshold.threshold_velocity`); a row that gives an invalid vehicle or
   no threshold is a failed sample, not an error of the run. :func:`run_samples` evaluates the rows on a
   process pool (:mod:`trikedyn.study.engine.executors`), reporting each as it finishes.
4. :func:`analyse` computes the indices with SALib. A failed sample removes its Morris trajectory (or its
   Sobol block of ``k + 2`` rows) from the analysis; the number left out is reported.

The factors are :mod:`trikedyn.study.designs.factors`; the evaluation of the samples is
:mod:`trikedyn.study.designs.sample_runs`; both are re-exported here.

:class:`SampleLog` keeps the samples in a CSV file, a row appended as each finishes, so an interrupted run
loses nothing and can resume. :func:`run_sensitivity` ties the steps together and returns a
:class:`SensitivityResult` (``to_dict``, ``plot``).

Units: the threshold velocity and the Morris indices ``mu_star``, ``sigma``, ``mu_star_conf`` are in
km/h. SALib computes the elementary effects on the unit scale of each factor's range, so ``mu_star`` is the
mean absolute change of the threshold [km/h] for a move of the whole range (``2 * fraction`` of the value),
comparable across factors whatever their units. Sobol indices ``S1``, ``ST`` are fractions of the variance.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ...errors import InputError
from ...params.io import ParameterSet
from .factors import (  # noqa: F401  (re-exported: the module is the study's entry point)
    DEFAULT_FRACTION,
    EXCLUDED_GROUPS,
    Factor,
    apply_factors,
    candidate_factors,
    numeric_parameters,
    problem,
    select_factors,
)
from .sample_runs import (  # noqa: F401
    MAX_RESTARTS,
    SampleLog,
    Search,
    evaluate_sample,
    limit_counts,
    regimes,
    run_logged_samples,
    run_samples,
)
from .sensitivity_methods import (  # noqa: F401  (re-exported)
    DEFAULT_SAMPLES,
    METHODS,
    NUM_LEVELS,
    analyse,
    check_method,
    group_size,
    sample,
    unsettled_places,
)

__all__ = ["DEFAULT_FRACTION", "DEFAULT_SAMPLES", "METHODS", "Factor", "SampleLog", "Search", "SensitivityResult",
           "analyse", "apply_factors", "candidate_factors", "check_method", "evaluate_sample", "group_size",
           "numeric_parameters", "problem", "run_samples", "run_sensitivity", "sample", "select_factors",
           "unsettled_places"]


# ------------------------------------------------------------------------------------------------
# evaluation
# ------------------------------------------------------------------------------------------------


@dataclass
class SensitivityResult:
    """A sensitivity run: the factors, every sample and its threshold, the indices.

    Attributes
    ----------
    vehicle, manoeuvre, method : str
    fraction : float
        The default relative half-range of a factor [-] (0.2: +/-20 %).
    samples, seed : int
        Morris trajectories or Sobol base samples; the seed of the sampling and of the bootstrap.
    factors : list of Factor
    excluded : dict
        Assumed values left out -> why (empty when the factors were named).
    X : ndarray, shape (n, k)
        The samples [factor units].
    Y : ndarray, shape (n,)
        Their threshold velocity [km/h], NaN where a sample failed.
    errors : list
        Per sample: None, or why it failed.
    indices : list of dict
        Most important first (:func:`analyse`).
    used, dropped : int
        Trajectories or blocks analysed, and those left out for a failed sample.
    reference_threshold_speed_kmh : float or None
        The threshold [km/h] of the vehicle as given.
    search : Search
    wall_time_s : float
    limits : list of str
        Per sample: what limits its threshold (``"lift-off"``, ``"cone strike"``, ...) or ``""``, :meth:`Search.outcome`.
    """

    vehicle: str
    manoeuvre: str
    method: str
    fraction: float
    samples: int
    seed: int
    factors: list
    excluded: dict
    X: np.ndarray
    Y: np.ndarray
    errors: list
    indices: list
    used: int
    dropped: int
    reference_threshold_speed_kmh: float | None
    search: Search = field(default_factory=Search)
    wall_time_s: float = 0.0
    limits: list = field(default_factory=list)

    @property
    def n_runs(self) -> int:
        """Samples evaluated (threshold searches), the reference not counted."""
        return int(self.X.shape[0])

    @property
    def failed(self) -> int:
        """Number of evaluations that failed."""
        return int(sum(e is not None for e in self.errors))

    @property
    def at_search_limit(self) -> int:
        """Samples whose threshold is the top of the search range [km/h] (nothing failed below it); 0 for
        another metric (no search)."""
        if self.search.metric != "threshold":
            return 0
        return int(np.sum(self.Y >= self.search.high_kmh - 1e-9))

    def to_dict(self) -> dict:
        """The result as plain data (the ``--json`` output).

        Returns
        -------
        dict
            The result (indices in [km/h] for Morris, dimensionless for Sobol).
        """
        failures: dict[str, int] = {}
        for err in self.errors:
            if err is not None:
                failures[err] = failures.get(err, 0) + 1
        from .named import by_metric

        return by_metric({
            "vehicle": self.vehicle, "manoeuvre": self.manoeuvre, "options": dict(self.search.options),
            "method": self.method, "fraction": self.fraction, "samples": self.samples, "seed": self.seed,
            "resolution_kmh": self.search.resolution_kmh, "high_kmh": self.search.high_kmh,
            "criterion": self.search.criterion, "speed_control": self.search.speed_control,
            "reference_threshold_speed_kmh": self.reference_threshold_speed_kmh,
            "metric": self.search.metric, "unit": self.search.unit, "metric_options": dict(self.search.metric_options),
            "n_runs": self.n_runs, "failed": self.failed, "at_search_limit": self.at_search_limit,
            "groups_used": self.used, "groups_dropped": self.dropped, "limits": limit_counts(self.limits),
            "indices": self.indices,
            "factors": [f.to_dict() for f in self.factors],
            "excluded": [{"parameter": k, "reason": v} for k, v in self.excluded.items()],
            "failures": [{"error": k, "samples": v} for k, v in failures.items()],
            "wall_time_s": self.wall_time_s,
        }, self.search.metric)

    def plot(self, top: int | None = None):
        """Bars of ``mu_star`` with its confidence interval and ``sigma`` [km/h] (Morris), or ``ST`` and ``S1``
        with theirs [-] (Sobol), most important at the top; returns a :class:`matplotlib.figure.Figure`.

        Parameters
        ----------
        top : int, optional
            Show only the most important factors.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from matplotlib.figure import Figure

        rows = [r for r in self.indices if all(isinstance(v, str) or math.isfinite(v) for v in r.values())]
        rows = rows[:top] if top else rows
        rows = rows[::-1]
        names = [r["parameter"] for r in rows]
        y = np.arange(len(rows))
        fig = Figure(figsize=(8.0, 1.6 + 0.28 * max(len(rows), 1)))
        what = "threshold" if self.search.metric == "threshold" else self.search.metric.replace("_", " ")
        unit = self.search.unit
        shown = ".1f" if self.search.metric == "threshold" else ".4g"
        ax = fig.subplots()
        if self.method == "morris":
            ax.barh(y, [r["mu_star"] for r in rows], xerr=[r["mu_star_conf"] for r in rows], height=0.6,
                    color="tab:blue", ecolor="0.3", capsize=2, label="mu* (95 % interval)")
            ax.plot([r["sigma"] for r in rows], y, "kd", ms=4, label="sigma")
            ax.set_xlabel(f"Morris mu* and sigma: change of the {what} over the range [{unit}]")
        else:
            h = 0.38
            ax.barh(y + h / 2, [r["ST"] for r in rows], xerr=[r["ST_conf"] for r in rows], height=h,
                    color="tab:blue", ecolor="0.3", capsize=2, label="ST (total)")
            ax.barh(y - h / 2, [r["S1"] for r in rows], xerr=[r["S1_conf"] for r in rows], height=h,
                    color="tab:orange", ecolor="0.3", capsize=2, label="S1 (first order)")
            ax.set_xlabel(f"Sobol index of the {what} [-]")
        ax.set_yticks(y, names, fontsize=8)
        ax.axvline(0.0, color="k", lw=0.8)
        ref = self.reference_threshold_speed_kmh
        count = regimes(self.limits)
        regime = ("\nlimits: " + ", ".join(f"{n} {name}" for name, n in count.items())
                  + ": regimes mixed in the indices") if count else ""
        ax.set_title(f"{self.vehicle}, {self.manoeuvre}: {what} {'-' if ref is None else format(ref, shown)} {unit}; "
                     f"factors +/-{self.fraction:.0%} ({self.method}, {self.n_runs} runs){regime}", fontsize=9)
        ax.legend(loc="lower right", fontsize=8)
        ax.grid(axis="x", alpha=0.3)
        fig.tight_layout()
        return fig


def run_sensitivity(pset: ParameterSet, search: Search, factors: list[Factor], *, method: str = "morris",
                    samples: int | None = None, seed: int = 1, fraction: float = DEFAULT_FRACTION,
                    excluded: dict | None = None, workers: int | None = 2, dask_local: int | None = None,
                    scheduler: str | None = None, log: SampleLog | None = None,
                    resume: bool = False, progress: Callable | None = None, figures: bool = False) -> SensitivityResult:
    """Sample, evaluate (in parallel) and analyse: the sensitivity of the threshold velocity to ``factors``.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    search : Search
        The manoeuvre and the threshold search of every sample.
    factors : list of Factor
        From :func:`candidate_factors` or :func:`select_factors`.
    method : {"morris", "sobol"}
    samples : int, optional
        Morris trajectories or Sobol base samples (:data:`DEFAULT_SAMPLES`).
    seed : int
        Seed of the sampling and of the bootstrap intervals.
    fraction : float
        The fraction the factors were made with (reported).
    excluded : dict, optional
        Assumed values left out -> why (reported).
    workers : int or None
        Processes (0: one row after the other in this process; None: all cores).
    dask_local : int, optional
        Workers of a new local Dask cluster instead.
    scheduler : str, optional
        Address of a Dask scheduler instead (``tcp://host:port``).
    log : SampleLog, optional
        Where each sample is appended as it finishes; with ``resume``, the samples logged already are not
        evaluated again.
    resume : bool
        Go on from ``log`` (a run killed part way): the samples it holds are kept.
    progress : callable, optional
        ``progress(done, total)`` (see :func:`run_samples`).
    figures : bool
        The caller will plot the result (:meth:`SensitivityResult.plot`): with workers, matplotlib loads while
        they compute, with the analysis' libraries.

    Returns
    -------
    SensitivityResult
        The samples, thresholds [km/h] and indices.
    """
    start = time.perf_counter()
    check_method(method)
    samples = DEFAULT_SAMPLES[method] if samples is None else samples
    if not factors:
        raise InputError("no factor to vary", where="--parameter")
    prob = problem(factors)
    X = sample(prob, method, samples, seed)
    if search.metric == "threshold":
        reference = search.run(pset).threshold_speed_kmh  # also checks the manoeuvre before any process starts
    else:
        reference, why, _ = search.outcome(pset)
        if reference is None:
            raise InputError(f"the vehicle as given has no {search.metric} ({why})", where="--metric")
    if workers != 0:  # the analysis' libraries (SALib, scipy.stats: 0.7 s) load while the workers compute
        from ..engine.background import import_in_background

        import_in_background(f"SALib.analyze.{method}", *(("matplotlib.figure",) if figures else ()))
    Y, errors, limits = run_logged_samples(pset, factors, X, search, workers=workers, dask_local=dask_local,
                                           scheduler=scheduler, log=log, resume=resume,
                                           progress=progress)
    indices, used, dropped = analyse(prob, method, X, Y, seed)
    return SensitivityResult(pset.name, search.manoeuvre, method, float(fraction), int(samples), int(seed),
                             list(factors), dict(excluded or {}), X, Y, errors, indices, used, dropped,
                             None if reference is None else float(reference), search,
                             time.perf_counter() - start, limits)
