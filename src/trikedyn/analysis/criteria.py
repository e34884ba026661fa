"""One run judged the way a threshold search judges it: its :class:`~trikedyn.analysis.verdict.Verdict` seen
under a **criterion** (``"course"``, ``"lift-off"``; a search also takes ``"both"``) as a
:class:`RunVerdict`: passed or not, and what failed first (``limit``: the verdict's reason under ``course``;
``"lift-off"``, ``"tracking"`` or ``"speed not held"`` under ``lift-off``; see
:mod:`trikedyn.analysis.threshold`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

from ..errors import InputError
from .search_settings import CRITERIA, DEFAULT_CRITERION
from .verdict import CONE_STRIKE, LIFT_OFF, PATH_LOST, SPEED_NOT_HELD, SPIN, STOPPED, Judging, Verdict, judge

__all__ = ["CRITERIA", "DEFAULT_CRITERION", "TRACKING", "RunVerdict", "check_criterion", "classify", "judge_run",
           "strikes_and_load"]

TRACKING = "tracking"
"""The limit of a lift-off run that had lost the path, struck a cone or spun before the lift."""
@dataclass(frozen=True)
class RunVerdict:
    """How one run at one target speed went, under the search's criterion.

    ``speed_kmh`` [km/h] is the target; ``passed`` under ``criterion``; ``limit`` what failed (see the module
    docstring) with the wheel and time [s] of the first lift (or of the failure); ``min_wheel_load_N`` [N]
    the smallest wheel load up to the exit gate; ``margin_N`` [N] the smallest wheel entry of the margin
    table (negative when a wheel lifted). ``verdict`` is the run's own verdict (the earliest reason of all,
    :mod:`trikedyn.analysis.verdict`); ``entry_speed_kmh`` and ``window_speed_kmh`` (min, mean, max) the
    speed it drove [km/h].
    """

    speed_kmh: float
    passed: bool
    limit: str | None
    wheel: str | None
    time_s: float | None
    detail: str
    cone_strikes: int = 0
    min_wheel_load_N: float | None = None
    margin_N: float | None = None
    verdict: str = "pass"
    entry_speed_kmh: float | None = None
    window_speed_kmh: dict | None = None
    criterion: str = DEFAULT_CRITERION

    def to_dict(self) -> dict:
        """Every field, JSON-ready.

        Returns
        -------
        dict
            The fields.
        """
        return asdict(self)


def check_criterion(criterion: str, allowed=CRITERIA) -> None:
    """Refuse a criterion not in ``allowed``.

    Parameters
    ----------
    criterion : str
        The criterion asked for.
    allowed : tuple of str
        The criteria accepted (:data:`CRITERIA` by default).

    Raises
    ------
    InputError
        An unknown criterion (``where="criterion"``), naming those accepted.
    """
    if criterion not in allowed:
        raise InputError(f"unknown criterion {criterion!r}; expected one of {', '.join(allowed)}", where="criterion")


def classify(verdict: Verdict, criterion: str, speed_kmh: float, cone_strikes: int = 0,
             min_wheel_load_N: float | None = None) -> RunVerdict:
    """A run's :class:`~trikedyn.analysis.verdict.Verdict` seen by a search under ``criterion``
    (``"lift-off"`` or ``"course"``).

    Parameters
    ----------
    verdict : Verdict
        The run's verdict (:func:`~trikedyn.analysis.verdict.judge`).
    criterion : {"lift-off", "course"}
        What the run is judged by.
    speed_kmh : float
        Target speed [km/h].
    cone_strikes : int
        Cones struck in the judged window.
    min_wheel_load_N : float, optional
        Smallest wheel load up to the exit gate [N].

    Returns
    -------
    RunVerdict
        Passed or not, and what failed first.
    """
    check_criterion(criterion, ("lift-off", "course"))
    speeds = {"verdict": verdict.verdict, "entry_speed_kmh": verdict.entry_speed_kmh,
              "window_speed_kmh": verdict.window_speed_kmh, "criterion": criterion}
    first = verdict.first(criterion)
    lift = verdict.reason(LIFT_OFF)
    if first is None:
        note = f", {cone_strikes} cone strike(s) from {verdict.reason(CONE_STRIKE).time_s:.2f} s" if cone_strikes else ""
        return RunVerdict(speed_kmh, True, None, None, None, f"every wheel down{note}; {verdict.speed_text}",
                          cone_strikes, min_wheel_load_N, **speeds)
    if criterion == "course":
        wheel = lift.wheel if first.reason == LIFT_OFF else None
        return RunVerdict(speed_kmh, False, first.reason, wheel, first.time_s, first.detail, cone_strikes,
                          min_wheel_load_N, **speeds)
    if lift is not None and first.reason in (LIFT_OFF, PATH_LOST, SPIN, STOPPED):
        earlier = [r for r in verdict.reasons if r.reason in (CONE_STRIKE, PATH_LOST, SPIN) and r.time_s < lift.time_s]
        if earlier:
            lead = "cone strike" if earlier[0].reason == CONE_STRIKE else earlier[0].reason
            detail = f"{lead} at {earlier[0].time_s:.2f} s, then {lift.wheel} lifted at {lift.time_s:.2f} s"
            return RunVerdict(speed_kmh, False, TRACKING, lift.wheel, lift.time_s, detail, cone_strikes,
                              min_wheel_load_N, **speeds)
        if first.reason == LIFT_OFF:
            return RunVerdict(speed_kmh, False, LIFT_OFF, lift.wheel, lift.time_s,
                              f"{lift.wheel} lifted at {lift.time_s:.2f} s", cone_strikes, min_wheel_load_N, **speeds)
    limit = SPEED_NOT_HELD if first.reason == SPEED_NOT_HELD else TRACKING
    return RunVerdict(speed_kmh, False, limit, None, first.time_s, first.detail, cone_strikes, min_wheel_load_N,
                      **speeds)


def judge_run(result, lost_m: float = 2.5, speed_kmh: float | None = None, *, criterion: str = DEFAULT_CRITERION,
              judging: Judging | None = None) -> RunVerdict:
    """Pass or fail of a run under ``criterion`` (see the module docstring), and what went wrong first.

    Judged up to the exit gate: a lift in the run-in counts, nothing in the run-out does. A run that
    stopped early (rollover, divergence) fails. ``lost_m`` [m] is used when ``judging`` is not given.

    Parameters
    ----------
    result : Result
        A run.
    lost_m : float
        Path error that counts as a lost course [m].
    speed_kmh : float, optional
        Target speed [km/h]; the run's own by default.
    criterion : str
        ``"lift-off"``, ``"course"`` or both.
    judging : Judging, optional
        Judging settings.

    Returns
    -------
    RunVerdict
        Pass or fail and the first failure.
    """
    verdict = judge(result, judging or Judging(lost_m=lost_m))
    speed_kmh = float(result.meta.get("target_speed_kmh", float("nan")) if speed_kmh is None else speed_kmh)
    return classify(verdict, criterion, speed_kmh, *strikes_and_load(result))


def strikes_and_load(result) -> tuple[int, float | None]:
    """Cones struck in the window, and the smallest wheel load up to the exit gate [N].

    Parameters
    ----------
    result : Result
        A run (its ``<wheel>_fz_N`` channels [N]).

    Returns
    -------
    strikes : int
        Cones struck in the judged window.
    min_load_N : float or None
        The smallest wheel load up to the exit gate [N]; None without samples.
    """
    import numpy as np

    from .window import cone_strikes, until_exit

    scope = until_exit(result)
    fz = np.column_stack([result[f"{w}_fz_N"] for w in result.meta["wheels"]])
    fz = fz[scope] if scope.any() else fz
    return len(cone_strikes(result)), (float(fz.min()) if fz.size else None)
