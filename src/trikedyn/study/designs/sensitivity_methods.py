"""The methods of a sensitivity run (:mod:`trikedyn.study.designs.sensitivity`), on SALib: the Morris and
Sobol designs' samples (:func:`sample`), their indices (:func:`analyse`) and which places of a ranking the
samples do not settle (:func:`unsettled_places`).
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import InputError, did_you_mean

__all__ = ["DEFAULT_SAMPLES", "METHODS", "NUM_LEVELS", "analyse", "check_method", "group_size", "sample",
           "unsettled_places"]

METHODS = ("morris", "sobol")
DEFAULT_SAMPLES = {"morris": 10, "sobol": 64}
"""Morris trajectories; Sobol base samples (a power of 2)."""
NUM_LEVELS = 4
"""Levels of the Morris grid (SALib's default)."""


def check_method(method: str) -> str:
    """``method`` if it is a known method (``morris`` or ``sobol``).

    Parameters
    ----------
    method : str
        The method.

    Returns
    -------
    str
        ``method``.

    Raises
    ------
    InputError
        For an unknown method (with a close match).
    """
    if method not in METHODS:
        tip = did_you_mean(str(method), METHODS)
        raise InputError(f"unknown method '{method}'{tip} (expected morris or sobol)", where="--method")
    return method


def group_size(method: str, k: int) -> int:
    """Rows of one Morris trajectory (``k + 1``) or of one Sobol block (``k + 2``, first-order and total).

    Parameters
    ----------
    method : str
        ``morris`` or ``sobol``.
    k : int
        Number of factors.

    Returns
    -------
    int
        Rows per group.
    """
    return k + 1 if check_method(method) == "morris" else k + 2


def sample(prob: dict, method: str, samples: int, seed: int = 1) -> np.ndarray:
    """The input matrix [factor units], one row per evaluation.

    Parameters
    ----------
    prob : dict
        SALib problem (:func:`problem`).
    method : {"morris", "sobol"}
        ``"morris"``: ``samples`` trajectories of ``k + 1`` rows on a 4-level grid. ``"sobol"``: a scrambled
        Sobol' sequence of ``samples`` base points (a power of 2), ``samples * (k + 2)`` rows (Saltelli's
        scheme without second-order indices).
    samples : int
        Trajectories or base samples.
    seed : int
        Seed of the sampling (the same seed, the same rows).

    Returns
    -------
    numpy.ndarray
        The inputs [factor units], one row per evaluation.
    """
    check_method(method)
    if isinstance(samples, bool) or int(samples) != samples or samples < 2:
        raise InputError(f"expected a whole number >= 2, got {samples!r}", where="--samples")
    samples = int(samples)
    if method == "morris":
        from SALib.sample import morris

        return morris.sample(prob, samples, num_levels=NUM_LEVELS, seed=seed)
    if samples & (samples - 1):
        below = 1 << (samples.bit_length() - 1)
        raise InputError(f"Sobol' sampling needs a power of 2, got {samples} (try {below} or {below * 2})",
                         where="--samples")
    from SALib.sample import sobol

    return sobol.sample(prob, samples, calc_second_order=False, scramble=True, seed=seed)


def unsettled_places(indices: list[dict], top: int = 10) -> list[tuple[int, int]]:
    """Runs of places, among the first ``top``, whose order the samples do not settle: ``(first, last)``
    places (1-based) of each chain of neighbours whose 95 % intervals overlap.

    ``indices`` are ranked, most important first (:func:`analyse`): Morris rows overlap when
    ``mu_star +/- mu_star_conf`` do, Sobol rows when ``ST +/- ST_conf`` do. A chain may run past ``top``; a
    row whose interval is not finite ends one.

    Parameters
    ----------
    indices : list of dict
        Ranked indices.
    top : int
        Places looked at.

    Returns
    -------
    list of tuple of int
        (first, last) places of each chain.
    """
    key = "mu_star" if indices and "mu_star" in indices[0] else "ST"
    rows = indices[: top + 1]
    runs, start = [], None
    for k in range(len(rows) - 1):
        a, b = rows[k], rows[k + 1]
        ends = (a[key] - a[f"{key}_conf"], b[key] + b[f"{key}_conf"])
        overlap = all(math.isfinite(v) for v in ends) and ends[0] <= ends[1]
        if overlap and start is None:
            start = k + 1
        if not overlap and start is not None:
            runs.append((start, k + 1))
            start = None
    if start is not None:
        runs.append((start, len(rows)))
    return [r for r in runs if r[0] <= top]


def analyse(prob: dict, method: str, X: np.ndarray, Y: np.ndarray, seed: int = 1) -> tuple[list[dict], int, int]:
    """Sensitivity indices from the rows and their outputs, failed rows (NaN in ``Y``) left out by group.

    Parameters
    ----------
    prob : dict
        SALib problem (:func:`problem`).
    method : {"morris", "sobol"}
    X : ndarray, shape (n, k)
        Inputs as :func:`sample` drew them.
    Y : ndarray, shape (n,)
        Outputs (the threshold velocity [km/h]); NaN for a failed row.
    seed : int
        Seed of the bootstrap confidence intervals.

    Returns
    -------
    indices : list of dict
        Most important first: ``{parameter, mu_star, sigma, mu_star_conf}`` [output units] (Morris), or
        ``{parameter, S1, ST, S1_conf, ST_conf}`` [-] (Sobol; ``_conf``: half-width of the 95 % interval).
    used, dropped : int
        Trajectories (Morris) or blocks (Sobol) analysed, and those left out for a failed row.
    """
    k = prob["num_vars"]
    size = group_size(method, k)
    X, Y = np.asarray(X, dtype=float), np.asarray(Y, dtype=float)
    if Y.shape != (X.shape[0],) or X.shape[1] != k or X.shape[0] % size:
        raise ValueError(f"expected {size} rows a group and one output a row, got X {X.shape} and Y {Y.shape}")
    groups = X.shape[0] // size
    ok = np.isfinite(Y).reshape(groups, size).all(axis=1)
    keep = np.repeat(ok, size)
    used, dropped = int(ok.sum()), int(groups - ok.sum())
    names = prob["names"]
    nan = float("nan")
    if method == "morris":
        keys = ("mu_star", "sigma", "mu_star_conf")
        if used >= 2:
            from SALib.analyze import morris

            res = morris.analyze(prob, X[keep], Y[keep], num_levels=NUM_LEVELS, seed=seed)
            table = {key: np.asarray(res[key], dtype=float) for key in keys}
        else:
            table = {key: np.full(k, nan) for key in keys}
        order_key = "mu_star"
    else:
        keys = ("S1", "ST", "S1_conf", "ST_conf")
        if used >= 2:
            from SALib.analyze import sobol

            res = sobol.analyze(prob, Y[keep], calc_second_order=False, seed=seed)
            table = {key: np.asarray(res[key], dtype=float) for key in keys}
        else:
            table = {key: np.full(k, nan) for key in keys}
        order_key = "ST"
    rows = [{"parameter": name, **{key: float(table[key][i]) for key in keys}} for i, name in enumerate(names)]
    rows.sort(key=lambda r: (not math.isfinite(r[order_key]), -r[order_key] if math.isfinite(r[order_key]) else 0.0))
    return rows, used, dropped
