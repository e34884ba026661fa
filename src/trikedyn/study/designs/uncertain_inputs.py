"""The uncertain inputs of an uncertainty run (:mod:`trikedyn.study.designs.uncertainty`) and their samples.

- **assumed** values (the factors of :mod:`trikedyn.study.designs.factors`): uniform over their range;
- **measured** values with a standard deviation: normal about the vehicle's value, truncated at +/-3 sigma
  (:data:`TRUNCATION`), the sigmas given by hand (:func:`parse_std`) or read from the measurements
  (:mod:`trikedyn.study.designs.measured_sigmas`);
- :func:`sample`: a seeded Latin hypercube mapped through each input's inverse distribution function.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace

import numpy as np

from ...errors import InputError
from ...params.io import ParameterSet
from .factors import DEFAULT_FRACTION, Factor, candidate_factors, select_factors

__all__ = ["TRUNCATION", "Input", "build_inputs", "parse_std", "sample"]

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
