"""Uncertainty of the threshold velocity (or of any registered study metric: the search's ``metric``): its
distribution from the vehicle's uncertain inputs.

Two kinds of input:

- **assumed** values (the factors of :mod:`trikedyn.study.designs.factors`): uniform over their range
  (``value * (1 -/+ fraction)`` or the range declared in the vehicle file), as the sensitivity study varies them;
- **measured** values with a standard deviation (``mass.cg_z_m`` from a weighing, a suspension stiffness from an
  identification): normal about the vehicle's value, truncated at +/-3 sigma (:data:`TRUNCATION`). The sigmas
  are given by hand (``--std PATH=SIGMA``, :func:`parse_std`) or read from the measurements themselves:
  :func:`weighing_stds` (a weighing file, :mod:`trikedyn.measure.weighing`: the CG's x and y from the level
  weighing, its z from the tilted ones) and :func:`identification_stds` (the JSON of ``trikedyn identify
  --json``: K and C of one suspension, their sigmas propagated from those of f_n and xi). Each input says where
  its sigma came from (``source``); a sigma given with ``--std`` wins over a measured one.

The samples are a seeded Latin hypercube (:class:`scipy.stats.qmc.LatinHypercube`) mapped through each input's
inverse distribution function; each sample's threshold is searched as in a sensitivity run
(:func:`~trikedyn.study.designs.sample_runs.run_samples`, :class:`~trikedyn.study.designs.sample_runs.Search`). A failed sample
is reported, not an error. :func:`run_uncertainty` returns an :class:`UncertaintyResult` (median, 5 % and 95 %
percentiles, mean, standard deviation [km/h]; ``to_dict``, ``plot``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ...errors import InputError
from ...params.io import ParameterSet
from .factors import DEFAULT_FRACTION
from .measured_sigmas import (  # noqa: F401  (re-exported: the module is the design's entry point)
    Measured,
    identification_stds,
    measured_stds,
    weighing_stds,
)
from .sample_runs import SampleLog, Search, limit_counts, regimes, run_logged_samples
from .uncertain_inputs import TRUNCATION, Input, build_inputs, parse_std, sample  # noqa: F401  (re-exported)

__all__ = ["DEFAULT_SAMPLES", "TRUNCATION", "Input", "Measured", "UncertaintyResult", "build_inputs",
           "identification_stds", "measured_stds", "parse_std", "run_uncertainty", "sample", "weighing_stds"]

DEFAULT_SAMPLES = 64


def _stat(values: np.ndarray, fn) -> float | None:
    return float(fn(values)) if values.size else None


@dataclass
class UncertaintyResult:
    """An uncertainty run: the inputs, every sample and its threshold, the distribution's statistics [km/h].

    With a search of another metric (``search.metric``), the thresholds and statistics are that metric's values in
    its unit (``search.unit``): the attributes and :meth:`statistics` keep the threshold's names, and
    :meth:`to_dict` names them by the metric (:func:`~trikedyn.study.designs.named.by_metric`: ``reference_value``,
    ``median`` ..., with ``metric`` and ``unit``)."""

    vehicle: str
    manoeuvre: str
    fraction: float
    samples: int
    seed: int
    inputs: list
    excluded: dict
    X: np.ndarray
    Y: np.ndarray
    errors: list
    reference_threshold_speed_kmh: float | None
    search: Search = field(default_factory=Search)
    wall_time_s: float = 0.0
    measured: list = field(default_factory=list)
    """The :class:`Measured` sigmas read from files (those a ``--std`` overrode too)."""
    notes: list = field(default_factory=list)
    """Remarks on the inputs (a vehicle value far from its measurement), one line each."""
    limits: list = field(default_factory=list)
    """Per sample: what limits its threshold (``"lift-off"``, ``"cone strike"``, ...) or ``""``, :meth:`Search.outcome`."""

    @property
    def ok(self) -> np.ndarray:
        """The thresholds that were found [km/h]."""
        return self.Y[np.isfinite(self.Y)]

    @property
    def failed(self) -> int:
        """Number of samples without a threshold."""
        return int(sum(e is not None for e in self.errors))

    def statistics(self) -> dict:
        """Statistics of the thresholds found.

        Returns
        -------
        dict
            ``median_kmh``, ``p05_kmh``, ``p95_kmh``, ``mean_kmh``, ``std_kmh`` [km/h], ``n``, ``failed``.
        """
        y = self.ok
        return {"median_kmh": _stat(y, np.median), "p05_kmh": _stat(y, lambda v: np.percentile(v, 5)),
                "p95_kmh": _stat(y, lambda v: np.percentile(v, 95)), "mean_kmh": _stat(y, np.mean),
                "std_kmh": _stat(y, lambda v: np.std(v, ddof=1)) if y.size > 1 else None,
                "n": int(y.size), "failed": self.failed}

    def to_dict(self) -> dict:
        """The result as plain data (the ``--json`` output).

        Returns
        -------
        dict
            The result (thresholds [km/h]).
        """
        names = [i.name for i in self.inputs]
        rows = []
        for k, (x, y, err) in enumerate(zip(self.X, self.Y, self.errors, strict=True)):
            row = {"sample": k, **{n: float(v) for n, v in zip(names, x, strict=True)},
                   "threshold_speed_kmh": float(y) if math.isfinite(y) else None}
            if err is not None:
                row["error"] = err
            if k < len(self.limits) and self.limits[k]:
                row["limit"] = self.limits[k]
            rows.append(row)
        failures: dict[str, int] = {}
        for err in self.errors:
            if err is not None:
                failures[err] = failures.get(err, 0) + 1
        from .named import by_metric

        return by_metric({
            "vehicle": self.vehicle, "manoeuvre": self.manoeuvre, "options": dict(self.search.options),
            "sampling": "latin-hypercube", "fraction": self.fraction, "seed": self.seed,
            "resolution_kmh": self.search.resolution_kmh, "high_kmh": self.search.high_kmh,
            "criterion": self.search.criterion, "speed_control": self.search.speed_control,
            "reference_threshold_speed_kmh": self.reference_threshold_speed_kmh,
            "metric": self.search.metric, "unit": self.search.unit, "metric_options": dict(self.search.metric_options),
            **self.statistics(),
            "at_search_limit": int(np.sum(self.ok >= self.search.high_kmh - 1e-9)) if self.search.metric == "threshold"
            else 0,
            "limits": limit_counts(self.limits),
            "inputs": [i.to_dict() for i in self.inputs],
            "measured": [m.to_dict() | {"used": any(i.name == m.path and i.source == m.source for i in self.inputs)}
                         for m in self.measured],
            "notes": list(self.notes),
            "excluded": [{"parameter": k, "reason": v} for k, v in self.excluded.items()],
            "samples": rows,
            "failures": [{"error": k, "samples": v} for k, v in failures.items()],
            "wall_time_s": self.wall_time_s,
        }, self.search.metric)

    def plot(self):
        """Histogram of the thresholds [km/h], the 5-95 % band, the median and the reference threshold marked;
        returns a :class:`matplotlib.figure.Figure`.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from matplotlib.figure import Figure

        s = self.statistics()
        what = "threshold velocity" if self.search.metric == "threshold" else self.search.metric.replace("_", " ")
        unit, shown = self.search.unit, (".1f" if self.search.metric == "threshold" else ".4g")
        fig = Figure(figsize=(7.0, 4.0))
        ax = fig.subplots()
        y = self.ok
        if y.size:
            bins = np.histogram_bin_edges(y, bins=max(5, min(30, int(np.sqrt(y.size)) * 2)))
            limits = np.array(self.limits if len(self.limits) == len(self.Y) else [""] * len(self.Y))[np.isfinite(self.Y)]
            count = regimes(limits)
            if count:  # two regimes or more: stacked, so the mix shows
                parts = [y[limits == name] for name in count]
                labels = [f"{name} (n={n})" for name, n in count.items()]
                labels[-1] += f"; {self.failed} failed" if self.failed else ""
                ax.hist(parts, bins=bins, stacked=True, alpha=0.75, label=labels)
            else:
                ax.hist(y, bins=bins, color="tab:blue", alpha=0.75, label=f"samples (n={y.size}, {self.failed} failed)")
            ax.axvspan(s["p05_kmh"], s["p95_kmh"], color="tab:orange", alpha=0.2, zorder=0, label="5-95 %")
            ax.axvline(s["median_kmh"], color="tab:orange", lw=2, label=f"median {s['median_kmh']:{shown}} {unit}")
        ref = self.reference_threshold_speed_kmh
        if ref is not None:
            ax.axvline(ref, color="k", ls="--", lw=1.2, label=f"as given {ref:{shown}} {unit}")
        ax.set_xlabel(f"{what} [{unit}]")
        ax.set_ylabel("samples")
        ax.set_title(f"{self.vehicle}, {self.manoeuvre}: {what} over {len(self.inputs)} uncertain inputs "
                     "(Latin hypercube)", fontsize=9)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        return fig


def run_uncertainty(pset: ParameterSet, search: Search, inputs: list[Input], *, samples: int = DEFAULT_SAMPLES,
                    seed: int = 1, fraction: float = DEFAULT_FRACTION, excluded: dict | None = None,
                    workers: int | None = 2, dask_local: int | None = None, scheduler: str | None = None,
                    log: SampleLog | None = None, resume: bool = False,
                    progress: Callable | None = None) -> UncertaintyResult:
    """Sample (Latin hypercube), evaluate (in parallel; logged, resumable) and summarise the threshold velocity.

    Parameters are those of :func:`~trikedyn.study.designs.sensitivity.run_sensitivity`; ``inputs`` from
    :func:`build_inputs`; ``log`` a :class:`SampleLog` over ``[i.factor for i in inputs]`` (group 1).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    search : Search
        The threshold search (manoeuvre, options, speed range [km/h], criterion), or its study metric.
    inputs : list of Input
        The uncertain inputs.
    samples : int
        Number of samples.
    seed : int
        Random seed.
    fraction : float
        Default relative range, dimensionless.
    excluded : dict, optional
        Candidates left out, recorded.
    workers : int or None
        Processes (0: one row after the other in this process; None: all cores).
    dask_local : int, optional
        Workers of a new local Dask cluster instead.
    scheduler : str, optional
        Address of a Dask scheduler instead (``tcp://host:port``).
    log : SampleLog, optional
        Where each sample is logged.
    resume : bool
        Go on from ``log``: what it holds is not evaluated again.
    progress : callable, optional
        ``progress(done, total)``.

    Returns
    -------
    UncertaintyResult
        Samples, thresholds [km/h] and statistics.
    """
    start = time.perf_counter()
    if not inputs:
        raise InputError("no input to vary", where="--parameter")
    X = sample(inputs, samples, seed)
    if search.metric == "threshold":
        reference = search.run(pset).threshold_speed_kmh  # also checks the manoeuvre before any process starts
    else:
        reference, why, _ = search.outcome(pset)
        if reference is None:
            raise InputError(f"the vehicle as given has no {search.metric} ({why})", where="--metric")
    Y, errors, limits = run_logged_samples(pset, [i.factor for i in inputs], X, search, workers=workers, log=log,
                                           dask_local=dask_local, scheduler=scheduler, resume=resume,
                                           progress=progress)
    return UncertaintyResult(pset.name, search.manoeuvre, float(fraction), int(samples), int(seed), list(inputs),
                             dict(excluded or {}), X, Y, errors, None if reference is None else float(reference),
                             search, time.perf_counter() - start, limits=limits)
