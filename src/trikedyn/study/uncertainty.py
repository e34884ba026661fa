"""Uncertainty of the threshold velocity: its distribution from the vehicle's uncertain inputs.

Two kinds of input:

- **assumed** values (the factors of :mod:`trikedyn.study.factors`): uniform over their range
  (``value * (1 -/+ fraction)`` or the range declared in the vehicle file), as the sensitivity study varies them;
- **measured** values with a standard deviation (``mass.cg_z_m`` from a weighing, a suspension stiffness from an
  identification): normal about the vehicle's value, truncated at +/-3 sigma (:data:`TRUNCATION`).

The samples are a seeded Latin hypercube (:class:`scipy.stats.qmc.LatinHypercube`) mapped through each input's
inverse distribution function; each sample's threshold is searched as in a sensitivity run
(:func:`~trikedyn.study.sample_runs.run_samples`, :class:`~trikedyn.study.sample_runs.Search`). A failed sample
is reported, not an error. :func:`run_uncertainty` returns an :class:`UncertaintyResult` (median, 5 % and 95 %
percentiles, mean, standard deviation [km/h]; ``to_dict``, ``plot``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError
from ..params.io import ParameterSet
from .factors import DEFAULT_FRACTION, Factor, candidate_factors, select_factors
from .sample_runs import SampleLog, Search, run_samples

__all__ = ["DEFAULT_SAMPLES", "TRUNCATION", "Input", "UncertaintyResult", "build_inputs", "parse_std",
           "run_uncertainty", "sample"]

DEFAULT_SAMPLES = 64
TRUNCATION = 3.0
"""A measured value's normal distribution is truncated at this many standard deviations."""


@dataclass(frozen=True)
class Input:
    """One uncertain input: a factor and its distribution.

    Attributes
    ----------
    factor : Factor
        What the input sets; for a normal input ``low``/``high`` are the truncation bounds.
    distribution : {"uniform", "normal"}
    std : float
        Standard deviation [the parameter's unit] (normal only; the mean is ``factor.value``).
    """

    factor: Factor
    distribution: str = "uniform"
    std: float = 0.0

    @property
    def name(self) -> str:
        return self.factor.name

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        """The values [parameter unit] at the quantiles ``u`` in (0, 1)."""
        f = self.factor
        if self.distribution == "normal":
            from scipy.stats import truncnorm

            return truncnorm.ppf(u, -TRUNCATION, TRUNCATION, loc=f.value, scale=self.std)
        return f.low + np.asarray(u, dtype=float) * (f.high - f.low)

    def to_dict(self) -> dict:
        f = self.factor
        if self.distribution == "normal":
            return {"parameter": f.name, "distribution": "normal", "mean": f.value, "std": self.std,
                    "truncated": [f.low, f.high], "sets": list(f.paths)}
        return {"parameter": f.name, "distribution": "uniform", "low": f.low, "high": f.high, "value": f.value,
                "range_from": f.range_from, "sets": list(f.paths), "note": f.note}


def parse_std(items: Iterable[str]) -> dict[str, float]:
    """``PATH=SIGMA`` items (``mass.cg_z_m=0.01``) -> ``{path: sigma}`` [parameter units].

    Raises
    ------
    InputError
        ``where="--std"``: not ``PATH=SIGMA``, or sigma not a finite number > 0.
    """
    out: dict[str, float] = {}
    for raw in items:
        path, sep, value = str(raw).partition("=")
        path = path.strip()
        if not sep or not path:
            raise InputError(f"expected PATH=SIGMA (e.g. mass.cg_z_m=0.01), got {raw!r}", where="--std")
        try:
            sigma = float(value)
        except ValueError:
            raise InputError(f"'{path}': sigma must be a number, got {value.strip()!r}", where="--std") from None
        if not (math.isfinite(sigma) and sigma > 0):
            raise InputError(f"'{path}': sigma must be > 0, got {value.strip()!r}", where="--std")
        out[path] = sigma
    return out


def build_inputs(pset: ParameterSet, parameters: Iterable[str] = (), stds: dict[str, float] | None = None,
                 fraction: float = DEFAULT_FRACTION) -> tuple[list[Input], dict[str, str]]:
    """The inputs: the named (or every candidate) assumed factor uniform, each ``stds`` path normal.

    A path given both ways is normal. Returns the inputs and the assumed values left out (with why; empty
    when parameters are named).
    """
    stds = dict(stds or {})
    parameters = [p for p in parameters if str(p).strip()]
    if parameters:
        factors, excluded = select_factors(pset, parameters, fraction), {}
    else:
        factors, excluded = candidate_factors(pset, fraction)
    normal: list[Input] = []
    for path, sigma in stds.items():
        try:
            (factor,) = select_factors(pset, [path], fraction)
        except InputError as exc:
            raise InputError(exc.reason, where="--std") from None
        normal.append(Input(replace(factor, low=factor.value - TRUNCATION * sigma,
                                    high=factor.value + TRUNCATION * sigma, range_from="measured"),
                            "normal", float(sigma)))
    names = {i.name for i in normal}
    inputs = [Input(f) for f in factors if f.name not in names] + normal
    if not inputs:
        raise InputError("no input to vary", where="--parameter")
    return inputs, excluded


def sample(inputs: Iterable[Input], samples: int, seed: int = 1) -> np.ndarray:
    """The Latin-hypercube samples [parameter units], one row per sample, one column per input (seeded)."""
    from scipy.stats import qmc

    inputs = list(inputs)
    if isinstance(samples, bool) or int(samples) != samples or samples < 2:
        raise InputError(f"expected a whole number >= 2, got {samples!r}", where="--samples")
    U = qmc.LatinHypercube(d=len(inputs), seed=np.random.default_rng(seed)).random(int(samples))
    return np.column_stack([inp.from_unit(U[:, j]) for j, inp in enumerate(inputs)])


def _stat(values: np.ndarray, fn) -> float | None:
    return float(fn(values)) if values.size else None


@dataclass
class UncertaintyResult:
    """An uncertainty run: the inputs, every sample and its threshold, the distribution's statistics [km/h]."""

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

    @property
    def ok(self) -> np.ndarray:
        return self.Y[np.isfinite(self.Y)]

    @property
    def failed(self) -> int:
        return int(sum(e is not None for e in self.errors))

    def statistics(self) -> dict:
        y = self.ok
        return {"median_kmh": _stat(y, np.median), "p05_kmh": _stat(y, lambda v: np.percentile(v, 5)),
                "p95_kmh": _stat(y, lambda v: np.percentile(v, 95)), "mean_kmh": _stat(y, np.mean),
                "std_kmh": _stat(y, lambda v: np.std(v, ddof=1)) if y.size > 1 else None,
                "n": int(y.size), "failed": self.failed}

    def to_dict(self) -> dict:
        """The result as plain data (the ``--json`` output)."""
        names = [i.name for i in self.inputs]
        rows = []
        for k, (x, y, err) in enumerate(zip(self.X, self.Y, self.errors, strict=True)):
            row = {"sample": k, **{n: float(v) for n, v in zip(names, x, strict=True)},
                   "threshold_speed_kmh": float(y) if math.isfinite(y) else None}
            if err is not None:
                row["error"] = err
            rows.append(row)
        failures: dict[str, int] = {}
        for err in self.errors:
            if err is not None:
                failures[err] = failures.get(err, 0) + 1
        return {
            "vehicle": self.vehicle, "manoeuvre": self.manoeuvre, "options": dict(self.search.options),
            "sampling": "latin-hypercube", "fraction": self.fraction, "seed": self.seed,
            "resolution_kmh": self.search.resolution_kmh, "high_kmh": self.search.high_kmh,
            "reference_threshold_speed_kmh": self.reference_threshold_speed_kmh,
            **self.statistics(),
            "at_search_limit": int(np.sum(self.ok >= self.search.high_kmh - 1e-9)),
            "inputs": [i.to_dict() for i in self.inputs],
            "excluded": [{"parameter": k, "reason": v} for k, v in self.excluded.items()],
            "samples": rows,
            "failures": [{"error": k, "samples": v} for k, v in failures.items()],
            "wall_time_s": self.wall_time_s,
        }

    def plot(self):
        """Histogram of the thresholds [km/h], the 5-95 % band, the median and the reference threshold marked;
        returns a :class:`matplotlib.figure.Figure`."""
        from matplotlib.figure import Figure

        s = self.statistics()
        fig = Figure(figsize=(7.0, 4.0))
        ax = fig.subplots()
        y = self.ok
        if y.size:
            ax.hist(y, bins=max(5, min(30, int(np.sqrt(y.size)) * 2)), color="tab:blue", alpha=0.75,
                    label=f"samples (n={y.size}, {self.failed} failed)")
            ax.axvspan(s["p05_kmh"], s["p95_kmh"], color="tab:orange", alpha=0.2, zorder=0, label="5-95 %")
            ax.axvline(s["median_kmh"], color="tab:orange", lw=2, label=f"median {s['median_kmh']:.1f} km/h")
        ref = self.reference_threshold_speed_kmh
        if ref is not None:
            ax.axvline(ref, color="k", ls="--", lw=1.2, label=f"as given {ref:.1f} km/h")
        ax.set_xlabel("threshold velocity [km/h]")
        ax.set_ylabel("samples")
        ax.set_title(f"{self.vehicle}, {self.manoeuvre}: threshold velocity over {len(self.inputs)} uncertain inputs "
                     "(Latin hypercube)", fontsize=9)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        return fig


def run_uncertainty(pset: ParameterSet, search: Search, inputs: list[Input], *, samples: int = DEFAULT_SAMPLES,
                    seed: int = 1, fraction: float = DEFAULT_FRACTION, excluded: dict | None = None,
                    workers: int = 2, log: SampleLog | None = None, resume: bool = False,
                    progress: Callable | None = None) -> UncertaintyResult:
    """Sample (Latin hypercube), evaluate (in parallel; logged, resumable) and summarise the threshold velocity.

    Parameters are those of :func:`~trikedyn.study.sensitivity.run_sensitivity`; ``inputs`` from
    :func:`build_inputs`; ``log`` a :class:`SampleLog` over ``[i.factor for i in inputs]`` (group 1).
    """
    start = time.perf_counter()
    if not inputs:
        raise InputError("no input to vary", where="--parameter")
    X = sample(inputs, samples, seed)
    reference = search.run(pset).threshold_speed_kmh  # also checks the manoeuvre before any process starts
    known = {}
    if log is not None:
        known = log.read(X) if resume else {}
        log.open(fresh=not resume)

    def logged(i, y, err):
        log.append(i, X[i], y, err)

    try:
        Y, errors = run_samples(pset, [i.factor for i in inputs], X, search, workers=workers, known=known,
                                on_result=logged if log is not None else None, progress=progress)
    finally:
        if log is not None:
            log.close()
    return UncertaintyResult(pset.name, search.manoeuvre, float(fraction), int(samples), int(seed), list(inputs),
                             dict(excluded or {}), X, Y, errors, None if reference is None else float(reference),
                             search, time.perf_counter() - start)
