"""Uncertainty of the threshold velocity: its distribution from the vehicle's uncertain inputs.

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

import json
import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ...errors import InputError, did_you_mean
from ...params.io import ParameterSet
from .factors import DEFAULT_FRACTION, Factor, candidate_factors, select_factors
from .sample_runs import SampleLog, Search, limit_counts, regimes, run_logged_samples

__all__ = ["DEFAULT_SAMPLES", "TRUNCATION", "Input", "Measured", "UncertaintyResult", "build_inputs",
           "identification_stds", "measured_stds", "parse_std", "run_uncertainty", "sample", "weighing_stds"]

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
    source : str
        Where the sigma came from (normal only): ``"--std"``, or the weighing or identification file.
    """

    factor: Factor
    distribution: str = "uniform"
    std: float = 0.0
    source: str = ""

    @property
    def name(self) -> str:
        """The input's name (its factor's)."""
        return self.factor.name

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        """The values [parameter unit] at the quantiles ``u`` in (0, 1).

        Parameters
        ----------
        u : numpy.ndarray
            Quantiles in (0, 1), dimensionless.

        Returns
        -------
        numpy.ndarray
            Values [parameter unit].
        """
        f = self.factor
        if self.distribution == "normal":
            from scipy.stats import truncnorm

            return truncnorm.ppf(u, -TRUNCATION, TRUNCATION, loc=f.value, scale=self.std)
        return f.low + np.asarray(u, dtype=float) * (f.high - f.low)

    def to_dict(self) -> dict:
        """The input as JSON-ready values.

        Returns
        -------
        dict
            Parameter, distribution and its values (mean, std, truncation or low, high; parameter units), paths set, source.
        """
        f = self.factor
        if self.distribution == "normal":
            return {"parameter": f.name, "distribution": "normal", "mean": f.value, "std": self.std,
                    "truncated": [f.low, f.high], "sets": list(f.paths), "source": self.source or "--std"}
        return {"parameter": f.name, "distribution": "uniform", "low": f.low, "high": f.high, "value": f.value,
                "range_from": f.range_from, "sets": list(f.paths), "note": f.note}


def parse_std(items: Iterable[str]) -> dict[str, float]:
    """``PATH=SIGMA`` items (``mass.cg_z_m=0.01``) -> ``{path: sigma}`` [parameter units].

    Parameters
    ----------
    items : iterable of str
        ``PATH=SIGMA`` items.

    Returns
    -------
    dict of str to float
        Path -> sigma [parameter unit].

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
                 fraction: float = DEFAULT_FRACTION, sources: dict[str, str] | None = None,
                 ) -> tuple[list[Input], dict[str, str]]:
    """The inputs: the named (or every candidate) assumed factor uniform, each ``stds`` path normal.

    A path given both ways is normal. ``sources``: path -> where its sigma came from (``"--std"`` if not
    given). Returns the inputs and the assumed values left out (with why; empty when parameters are named).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    parameters : iterable of str
        Factors taken uniform.
    stds : dict of str to float, optional
        Path -> sigma [parameter unit], taken normal.
    fraction : float
        Default relative range, dimensionless.
    sources : dict of str to str, optional
        Path -> where its sigma came from.

    Returns
    -------
    inputs : list of Input
        The inputs.
    excluded : dict of str to str
        Candidates left out and why.
    """
    sources = dict(sources or {})
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
            raise InputError(exc.reason, where=sources.get(path, "--std")) from None
        normal.append(Input(replace(factor, low=factor.value - TRUNCATION * sigma,
                                    high=factor.value + TRUNCATION * sigma, range_from="measured"),
                            "normal", float(sigma), sources.get(path, "--std")))
    names = {i.name for i in normal}
    inputs = [Input(f) for f in factors if f.name not in names] + normal
    if not inputs:
        raise InputError("no input to vary", where="--parameter")
    return inputs, excluded


# ------------------------------------------------------------------------------------------------
# measured sigmas: a weighing file, an identification
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Measured:
    """A measured value's standard deviation and where it came from.

    Attributes
    ----------
    path : str
        The vehicle's parameter (``mass.cg_z_m``, ``suspension.front.stiffness_N_per_m``).
    std : float
        Its standard deviation [the parameter's unit].
    measured : float
        The value the measurement gave (the vehicle's own value is the mean sampled about).
    source : str
        The file and what in it (``weighing.toml: tilted weighings``).
    """

    path: str
    std: float
    measured: float
    source: str

    def to_dict(self) -> dict:
        """The measured sigma as JSON-ready values.

        Returns
        -------
        dict
            ``parameter``, ``std`` [parameter unit], ``measured``, ``source``.
        """
        return {"parameter": self.path, "std": self.std, "measured": self.measured, "source": self.source}


def weighing_stds(path: str | Path) -> list[Measured]:
    """The CG's standard deviations from a weighing file (:mod:`trikedyn.measure.weighing`): x and y from
    the level weighing (the readings' ``reading_std_kg``), z from the ``[[tilted]]`` weighings if any.

    Parameters
    ----------
    path : str or Path
        The weighing file.

    Returns
    -------
    list of Measured
        CG sigmas [m].

    Raises
    ------
    InputError
        ``where=FILE``: the file cannot be read or reduced, or it gives no uncertainty (``reading_std_kg = 0``
        and no scatter).
    """
    from ...measure.weighing import load_weighing, reduce_weighing

    where = str(path)
    result = reduce_weighing(load_weighing(path), where=where)
    lvl = result.level
    found = [Measured("mass.cg_x_m", float(lvl.cg_x_std_m), float(lvl.cg_x_m), f"{where}: level weighing"),
             Measured("mass.cg_y_m", float(lvl.cg_y_std_m), float(lvl.cg_y_m), f"{where}: level weighing")]
    if result.height is not None:
        found.append(Measured("mass.cg_z_m", float(result.height.cg_z_std_m), float(result.height.cg_z_m),
                              f"{where}: tilted weighings"))
    found = [m for m in found if math.isfinite(m.std) and m.std > 0]
    if not found:
        raise InputError("gives the CG without an uncertainty (reading_std_kg = 0 and no scatter): no sigma to "
                         "sample; give reading_std_kg", where=where)
    return found


IDENTIFICATION_KEYS = ("natural_frequency_hz", "natural_frequency_std_hz", "damping_ratio", "damping_ratio_std",
                       "sprung_mass_kg", "stiffness_N_per_m", "damping_Ns_per_m")
"""The keys of an identification's JSON (``trikedyn identify --json``) that its K and C sigmas come from."""


def _identification_file(path: Path) -> Path:
    """The identification JSON: the file itself, or the one ``*.json`` file of a folder."""
    if path.is_dir():
        found = sorted(path.glob("*.json"))
        if len(found) != 1:
            raise InputError(f"expected a folder with one identification JSON, found {len(found)} .json files",
                             where=str(path))
        return found[0]
    return path


def identification_stds(path: str | Path, suspension: str) -> list[Measured]:
    """K and C of suspension ``suspension`` with their standard deviations, from the JSON that ``trikedyn identify
    --json`` writes (a file, or a folder holding one).

    The identification gives the standard errors of the natural frequency and damping ratio (``*_std``); K and
    C are functions of them (Eqs. 3-4, or the quarter car with the tyre in series when ``tyre_stiffness_N_per_m``
    was given: :func:`~trikedyn.measure.suspension.suspension_from_body_mode`), so their sigmas follow to first
    order, f_n and xi taken as independent.

    Parameters
    ----------
    path : str or Path
        The identification JSON, or a folder holding one.
    suspension : str
        The suspension it measured.

    Returns
    -------
    list of Measured
        K [N/m] and C [N s/m] with their sigmas.

    Raises
    ------
    InputError
        ``where=FILE``: not a readable JSON object, a key missing or not a finite number, no uncertainty.
    """
    from ...measure.suspension import damping_coefficient, stiffness_from_frequency, suspension_from_body_mode
    from ...params.tomlfile import is_file, read_text

    file = _identification_file(Path(path))
    where = str(file)
    if not is_file(file):
        raise InputError("no such identification file (the JSON of `trikedyn identify --json`)", where=where)
    text = read_text(file, where)  # at most MAX_FILE_BYTES
    try:
        data = json.loads(text)
    except ValueError as exc:
        raise InputError(f"not JSON ({exc.msg} at line {exc.lineno}); expected the output of `trikedyn identify "
                         "--json`", where=where) from None
    if not isinstance(data, dict):
        raise InputError("expected a JSON object (the output of `trikedyn identify --json`)", where=where)
    values = {}
    for key in IDENTIFICATION_KEYS:
        value = data.get(key)
        if value is None and key.endswith("_std"):
            raise InputError(f"{key}: no uncertainty in this identification (the fit gave none)", where=where)
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise InputError(f"{key}: expected a finite number, got {value!r} (is this the JSON of `trikedyn "
                             "identify --json`?)", where=where)
        values[key] = float(value)
    kt = data.get("tyre_stiffness_N_per_m")
    if kt is not None and (isinstance(kt, bool) or not isinstance(kt, int | float) or not kt > 0):
        raise InputError(f"tyre_stiffness_N_per_m: expected a number > 0 or null, got {kt!r}", where=where)
    extra = {}  # the tyre's damping and the unsprung mass, when the identification had them (exact quarter car)
    for key, name in (("tyre_damping_Ns_per_m", "tyre_damping"), ("unsprung_mass_kg", "unsprung_mass_kg")):
        value = data.get(key)
        if value is not None:
            if isinstance(value, bool) or not isinstance(value, int | float) or not (math.isfinite(value) and value >= 0):
                raise InputError(f"{key}: expected a number >= 0 or null, got {value!r}", where=where)
            extra[name] = float(value)
    f, xi, m = values["natural_frequency_hz"], values["damping_ratio"], values["sprung_mass_kg"]
    sf, sxi = values["natural_frequency_std_hz"], values["damping_ratio_std"]
    if not (f > 0 and 0 < xi < 1 and m > 0 and sf >= 0 and sxi >= 0):
        raise InputError(f"expected f_n > 0, 0 < xi < 1, a sprung mass > 0 and sigmas >= 0; got f_n = {f:g} Hz, "
                         f"xi = {xi:g}, M_s = {m:g} kg", where=where)

    def kc(fn, z):
        if kt is None:
            k = stiffness_from_frequency(fn, m)
            return float(k), float(damping_coefficient(z, k, m))
        k, c = suspension_from_body_mode(fn, z, m, float(kt), **extra)
        return float(k), float(c)

    hf, hxi = 1e-6 * f, 1e-6 * max(xi, 1e-3)
    (kf1, cf1), (kf0, cf0) = kc(f + hf, xi), kc(f - hf, xi)
    (kx1, cx1), (kx0, cx0) = kc(f, xi + hxi), kc(f, xi - hxi)
    std_k = math.hypot((kf1 - kf0) / (2 * hf) * sf, (kx1 - kx0) / (2 * hxi) * sxi)
    std_c = math.hypot((cf1 - cf0) / (2 * hf) * sf, (cx1 - cx0) / (2 * hxi) * sxi)
    if not (std_k > 0 and std_c > 0):
        raise InputError("no uncertainty in this identification (natural_frequency_std_hz and damping_ratio_std "
                         "are 0)", where=where)
    how = f"identified f_n = {f:.3f} +/- {sf:.3g} Hz, xi = {xi:.3f} +/- {sxi:.3g}"
    return [Measured(f"suspension.{suspension}.stiffness_N_per_m", std_k, values["stiffness_N_per_m"],
                     f"{where}: {how}"),
            Measured(f"suspension.{suspension}.damping_Ns_per_m", std_c, values["damping_Ns_per_m"],
                     f"{where}: {how}")]


def _suspension_of(pset: ParameterSet, item: str) -> tuple[str, str]:
    """``[NAME=]FILE`` of ``--identification`` -> (suspension name, file)."""
    names = list(pset.params.suspension)
    name, sep, file = str(item).partition("=")
    if sep and name.strip() in names:
        return name.strip(), file.strip()
    if sep and "/" not in name and "." not in name:  # NAME=FILE with an unknown NAME
        tip = did_you_mean(name.strip(), names)
        raise InputError(f"no suspension '{name.strip()}' on this vehicle{tip} (it has {', '.join(names)})",
                         where="--identification")
    if len(names) == 1:
        return names[0], str(item)
    raise InputError(f"name the suspension the file identifies: NAME=FILE, NAME one of {', '.join(names)} "
                     f"(e.g. {names[0]}={item})", where="--identification")


def measured_stds(pset: ParameterSet, weighing: str | Path | None = None, identifications: Iterable[str] = (),
                  ) -> list[Measured]:
    """The measured sigmas from a weighing file and identifications (``[NAME=]FILE``, NAME a suspension of the
    vehicle, needed when it has more than one), in that order; a path measured twice keeps the last.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    weighing : str or Path, optional
        A weighing file.
    identifications : iterable of str
        ``[NAME=]FILE`` items.

    Returns
    -------
    list of Measured
        The sigmas.
    """
    found: dict[str, Measured] = {}
    if weighing is not None:
        found.update((m.path, m) for m in weighing_stds(weighing))
    for item in identifications:
        name, file = _suspension_of(pset, item)
        found.update((m.path, m) for m in identification_stds(file, name))
    return list(found.values())


def sample(inputs: Iterable[Input], samples: int, seed: int = 1) -> np.ndarray:
    """The Latin-hypercube samples [parameter units], one row per sample, one column per input (seeded).

    Parameters
    ----------
    inputs : iterable of Input
        The inputs.
    samples : int
        Number of samples, >= 2.
    seed : int
        Random seed.

    Returns
    -------
    numpy.ndarray
        One row per sample [parameter units].
    """
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
        return {
            "vehicle": self.vehicle, "manoeuvre": self.manoeuvre, "options": dict(self.search.options),
            "sampling": "latin-hypercube", "fraction": self.fraction, "seed": self.seed,
            "resolution_kmh": self.search.resolution_kmh, "high_kmh": self.search.high_kmh,
            "criterion": self.search.criterion, "speed_control": self.search.speed_control,
            "reference_threshold_speed_kmh": self.reference_threshold_speed_kmh,
            **self.statistics(),
            "at_search_limit": int(np.sum(self.ok >= self.search.high_kmh - 1e-9)),
            "limits": limit_counts(self.limits),
            "inputs": [i.to_dict() for i in self.inputs],
            "measured": [m.to_dict() | {"used": any(i.name == m.path and i.source == m.source for i in self.inputs)}
                         for m in self.measured],
            "notes": list(self.notes),
            "excluded": [{"parameter": k, "reason": v} for k, v in self.excluded.items()],
            "samples": rows,
            "failures": [{"error": k, "samples": v} for k, v in failures.items()],
            "wall_time_s": self.wall_time_s,
        }

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
        The threshold search (manoeuvre, options, speed range [km/h], criterion).
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
    reference = search.run(pset).threshold_speed_kmh  # also checks the manoeuvre before any process starts
    Y, errors, limits = run_logged_samples(pset, [i.factor for i in inputs], X, search, workers=workers, log=log,
                                           dask_local=dask_local, scheduler=scheduler, resume=resume,
                                           progress=progress)
    return UncertaintyResult(pset.name, search.manoeuvre, float(fraction), int(samples), int(seed), list(inputs),
                             dict(excluded or {}), X, Y, errors, None if reference is None else float(reference),
                             search, time.perf_counter() - start, limits=limits)
