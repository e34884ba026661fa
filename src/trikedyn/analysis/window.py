"""The judged window of a run: which samples count, the first wheel lift and the cones struck in it.

A run is judged over its manoeuvre's window (the ``judged`` channel: entry gate to exit gate), never over the
run-out beyond the exit gate; a lift before the entry gate counts when asked for (``from_start``). These are
the pieces every judgement is built of (:mod:`trikedyn.analysis.metrics`, :mod:`trikedyn.analysis.verdict`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Lift", "cone_strikes", "first_lift", "judged_mask", "until_exit", "wheel_loads"]


def judged_mask(result) -> np.ndarray:
    """Boolean mask of the samples inside the judged window (all samples when the run has no window).

    Parameters
    ----------
    result : Result
        A run.

    Returns
    -------
    numpy.ndarray of bool
        The mask.
    """
    if "judged" in result.channels:
        return np.asarray(result["judged"]) > 0.5
    return np.ones(result.time_s.size, dtype=bool)


def wheel_loads(result) -> np.ndarray:
    """Every wheel's vertical force [N], one column per wheel (``result.meta["wheels"]`` order).

    Parameters
    ----------
    result : Result
        A run.

    Returns
    -------
    numpy.ndarray, shape (m, n_wheels)
        Vertical forces [N].
    """
    return np.column_stack([result[f"{w}_fz_N"] for w in result.meta["wheels"]])


@dataclass(frozen=True)
class Lift:
    """The first wheel lift inside the window: the wheel, the time [s]."""

    wheel: str
    time_s: float


def until_exit(result) -> np.ndarray:
    """Mask of the samples up to the exit gate: the run-in and the window, not the run-out.

    Parameters
    ----------
    result : Result
        A run.

    Returns
    -------
    numpy.ndarray of bool
        The mask.
    """
    mask = judged_mask(result)
    if not mask.any():
        return mask
    out = np.zeros_like(mask)
    out[: int(np.nonzero(mask)[0][-1]) + 1] = True
    return out


def first_lift(result, *, from_start: bool = False) -> Lift | None:
    """The first sample inside the window (or, with ``from_start``, from the start of the run up to the exit
    gate) at which a wheel's vertical force is zero, or None.

    Parameters
    ----------
    result : Result
        A run.
    from_start : bool
        Look from the start of the run.

    Returns
    -------
    Lift or None
        Wheel and time [s].
    """
    fz = wheel_loads(result)
    lifted = np.nonzero((fz <= 0.0).any(axis=1) & (until_exit(result) if from_start else judged_mask(result)))[0]
    if not lifted.size:
        return None
    i = int(lifted[0])
    return Lift(result.meta["wheels"][int(np.argmin(fz[i]))], float(result.time_s[i]))


def cone_strikes(result) -> list[dict]:
    """Cones the vehicle's plan-view footprint struck inside the window (time, cone, position).

    Parameters
    ----------
    result : Result
        A run.

    Returns
    -------
    list of dict
        ``time_s``, cone and position [m] of each strike.

    Notes
    -----
    Computed once per run (:meth:`~trikedyn.simulate.result.Result.derived`): a threshold search asks for them
    twice, for the verdict and for the count. Each call returns its own copies.
    """
    return [dict(strike) for strike in result.derived("cone_strikes", lambda: _cone_strikes(result))]


def _cone_strikes(result) -> list[dict]:
    """:func:`cone_strikes`, computed."""
    man = result.manoeuvre
    if man is None or man.path is None or not len(man.path.cones):
        return []
    from ..manoeuvres.paths import cone_strikes as strikes

    mask = judged_mask(result)
    if not mask.any():
        return []
    return strikes(man.path, result.time_s[mask], result["x_m"][mask], result["y_m"][mask], result["yaw_rad"][mask],
                   tuple(result.meta["footprint_m"]))
