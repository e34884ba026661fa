"""Evaluating a sampled design's samples: one search (:class:`~trikedyn.study.designs.search.Search`: the
threshold, or any study metric) per sample, handed to the engine (:class:`~trikedyn.study.engine.pool.ResilientPool`
on :func:`~trikedyn.study.engine.loop.drive`), logged as they finish so that an interrupted run resumes (see
:mod:`trikedyn.study.designs.sensitivity`, steps 3 and the log).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import numpy as np

from ...errors import ParameterError, RunIncomplete
from ...params.io import ParameterSet
from ..engine.pool import MAX_RESTARTS, ExecutorLost, ResilientPool
from .csv_log import SampleLog
from .factors import Factor, apply_factors
from .limits import LIMITS, limit_counts, limits_line, regimes  # noqa: F401  (re-exported)
from .search import Search, raise_interrupt  # noqa: F401  (re-exported: where the designs find them)

__all__ = ["LIMITS", "MAX_RESTARTS", "SampleLog", "Search", "evaluate_sample", "limit_counts", "limits_line",
           "raise_interrupt", "regimes", "run_logged_samples", "run_samples"]


def evaluate_sample(pset: ParameterSet, factors: tuple[Factor, ...], x,
                    search: Search) -> tuple[float | None, str | None, str]:
    """The threshold velocity [km/h] of the vehicle with the factors at ``x`` or None, why it failed, and its
    limit (:meth:`Search.outcome`).

    A failed sample (an invalid vehicle, a search with no threshold, a simulation error) is not an error:
    the sensitivity run goes on and reports it.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    factors : tuple of Factor
        The factors.
    x : sequence of float
        Their values [factor units].
    search : Search
        The threshold search.

    Returns
    -------
    threshold : float or None
        [km/h].
    error : str or None
        Why it failed.
    limit : str
        What limits it.
    """
    try:
        varied = apply_factors(pset, factors, x)
    except ParameterError as exc:
        return None, f"invalid vehicle: {' '.join(str(exc).split())}", ""
    return search.outcome(varied)


def run_samples(pset: ParameterSet, factors: Iterable[Factor], X: np.ndarray, search: Search, *, workers: int | None = 2,
                dask_local: int | None = None, scheduler: str | None = None, known: dict | None = None, on_result: Callable | None = None,
                progress: Callable | None = None) -> tuple[np.ndarray, list[str | None], list[str]]:
    """Evaluate every row of ``X`` (:func:`evaluate_sample`) on a process pool.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    factors : iterable of Factor
        The factors.
    X : numpy.ndarray
        Inputs, one row per sample [factor units].
    search : Search
        The threshold search.
    workers : int or None
        Processes (0: one row after the other in this process; None: all cores).
    dask_local : int, optional
        Workers of a new local Dask cluster instead.
    scheduler : str, optional
        Address of a Dask scheduler instead (``tcp://host:port``).
    known : dict, optional
        Row index -> ``(threshold [km/h] or None, error or None, limit)`` already evaluated (a resumed run): not
        evaluated again.
    on_result : callable, optional
        ``on_result(index, threshold, error, limit)``, called in this process as each row finishes.
    progress : callable, optional
        ``progress(done, total)``, called at the start and as each row finishes.

    Returns
    -------
    Y : ndarray
        Threshold velocity [km/h] per row, NaN where the row failed.
    errors : list
        Per row: None, or why it failed.
    limits : list
        Per row: ``"lift-off"``, ``"tracking"`` or ``""`` (:meth:`Search.outcome`).

    Raises
    ------
    RunIncomplete
        Worker processes died more than :data:`MAX_RESTARTS` times (after each death the rows in flight go to a
        new pool; a row on which a worker dies twice fails), or the Dask scheduler is gone; the rows reported
        are kept.
    """
    factors = tuple(factors)
    n = X.shape[0]
    Y = np.full(n, np.nan)
    errors: list[str | None] = [None] * n
    limits = [""] * n
    for i, (y, err, limit) in (known or {}).items():
        Y[i] = np.nan if y is None else y
        errors[i], limits[i] = err, limit
    done = len(known or {})

    def record(i, y, err, limit=""):
        """Keep row ``i``'s threshold ``y`` [km/h] (NaN if None), error and limit, hand them to ``on_result`` and
        report progress."""
        nonlocal done
        Y[i] = np.nan if y is None else y
        errors[i], limits[i] = err, limit
        done += 1
        if on_result is not None:
            on_result(i, y, err, limit)
        if progress is not None:
            progress(done, n)

    if progress is not None:
        progress(done, n)
    pool = ResilientPool(workers, dask_local, scheduler)
    try:
        pool.run(evaluate_sample, ((i, (pset, factors, X[i], search)) for i in range(n) if i not in (known or {})),
                 lambda i, value: record(i, *value),
                 lambda i: record(i, None, "a worker process died on this sample (twice)"))
    except ExecutorLost as exc:  # workers that kept dying, a lost scheduler
        kept = "; the samples done are logged: run again with --resume" if on_result is not None else ""
        raise RunIncomplete(f"{exc}; {done} of {n} samples done{kept}") from None
    finally:
        pool.close()
    return Y, errors, limits


def run_logged_samples(pset: ParameterSet, factors: Iterable[Factor], X: np.ndarray, search: Search, *,
                       workers: int | None = 2, dask_local: int | None = None, scheduler: str | None = None,
                       log: SampleLog | None = None, resume: bool = False,
                       progress: Callable | None = None) -> tuple[np.ndarray, list[str | None], list[str]]:
    """:func:`run_samples` with each finished sample appended to ``log``; with ``resume`` the samples logged
    already (:meth:`SampleLog.read`, which checks they are this run's) are not evaluated again.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    factors : iterable of Factor
        The factors.
    X : numpy.ndarray
        Inputs, one row per sample [factor units].
    search : Search
        The threshold search.
    workers : int or None
        Processes (0: one row after the other in this process; None: all cores).
    dask_local : int, optional
        Workers of a new local Dask cluster instead.
    scheduler : str, optional
        Address of a Dask scheduler instead (``tcp://host:port``).
    log : SampleLog, optional
        Where each sample is appended.
    resume : bool
        Go on from ``log``.
    progress : callable, optional
        ``progress(done, total)``.

    Returns
    -------
    thresholds : numpy.ndarray
        [km/h], NaN for a failed sample.
    errors : list of str or None
        Why each failed.
    limits : list of str
        What limits each.
    """
    if log is None:
        return run_samples(pset, factors, X, search, workers=workers, dask_local=dask_local, scheduler=scheduler,
                           progress=progress)
    known = log.read(X) if resume else {}
    log.open(fresh=not resume)
    try:
        return run_samples(pset, factors, X, search, workers=workers, dask_local=dask_local, scheduler=scheduler,
                           known=known,
                           on_result=lambda i, y, err, limit: log.append(i, X[i], y, err, limit),
                           progress=progress)
    finally:
        log.close()
