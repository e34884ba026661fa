"""The verdict of a run: did the vehicle pass the manoeuvre, and if not, what went wrong first.

``Result.success`` says only that the simulation ran to its end. Whether the *vehicle* passed is judged
here, from the run's channels, over the manoeuvre's judged window (entry gate to exit gate; a lift-off,
lost path or spin counts from the start of the run, since a wheel in the air before the entry gate is no
better than one after it):

=================  ==========================================================================================
reason             when
=================  ==========================================================================================
``lift-off``       a wheel's vertical force reaches zero (the paper's criterion, section 3.2)
``cone strike``    the vehicle's plan-view footprint touches a cone (ISO 3888-1 counts the run invalid)
``path lost``      the CG is farther than :attr:`Judging.lost_m` from the path (closed loop only)
``spin``           the sideslip angle at the CG exceeds :attr:`Judging.spin_deg`: the vehicle slides
``speed not held`` the speed leaves the band around the target (:meth:`Judging.band_kmh`) inside the window
                   (or, for a test that takes its speed at the start, at the entry gate:
                   :attr:`~trikedyn.manoeuvres.base.Manoeuvre.speed_judged`), or the run never reaches the exit
                   gate: the run did not test the speed asked for (neither a pass nor a lift)
``stopped``        the simulation stopped early (rollover limit, divergence) without any reason above
=================  ==========================================================================================

Every reason found is listed with its first time; the **verdict** is the earliest of them (``pass`` when
there is none). The speed actually driven is reported beside the target: at the entry gate
(``entry_speed_kmh``) and over the window (``window_speed_kmh``: min, mean, max).

A threshold search judges its runs by a **criterion** (:func:`failures`): ``lift-off`` (the paper's: a
wheel lifts, or the driver loses the vehicle, or the speed is not held; cone strikes are reported, not
failed) or ``course`` (ISO 3888-1's validity: every wheel down, no cone struck, path kept, speed held).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..errors import InputError

__all__ = ["CRITERIA", "REASONS", "Judging", "Reason", "Verdict", "failures", "judge", "target_speed_mps"]

PASS, LIFT_OFF, CONE_STRIKE, PATH_LOST, SPIN, SPEED_NOT_HELD, STOPPED = (
    "pass", "lift-off", "cone strike", "path lost", "spin", "speed not held", "stopped")
REASONS = (LIFT_OFF, CONE_STRIKE, PATH_LOST, SPIN, SPEED_NOT_HELD, STOPPED)
"""The reasons a run fails, in the order that breaks a tie in time."""

CRITERIA = ("lift-off", "course")
"""What a threshold search judges a run by (:func:`failures`); ``both`` searches under each."""

_FAILS = {
    "lift-off": (LIFT_OFF, PATH_LOST, SPIN, SPEED_NOT_HELD, STOPPED),
    "course": REASONS,
}


@dataclass(frozen=True)
class Judging:
    """How strictly a run is judged.

    Attributes
    ----------
    speed_band_percent : float
        Half-width of the speed band around the target, in per cent of the target [%] (default 3 %).
    speed_band_kmh : float
        Smallest half-width of the band [km/h] (default 1 km/h): the band is the larger of the two.
    lost_m : float
        Lateral distance of the CG from the path beyond which the driver has lost it [m].
    spin_deg : float
        Sideslip angle at the CG beyond which the vehicle is sliding out of control [deg]. A tight circle's
        kinematic sideslip (CG distance ahead of the rear axle over the radius) stays far below it.
    """

    speed_band_percent: float = 3.0
    speed_band_kmh: float = 1.0
    lost_m: float = 2.5
    spin_deg: float = 20.0

    def __post_init__(self):
        for name, low, high in (("speed_band_percent", 0.0, 100.0), ("speed_band_kmh", 0.0, 100.0),
                                ("lost_m", 0.01, 100.0), ("spin_deg", 1.0, 180.0)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value) \
                    or not low <= value <= high:
                raise InputError(f"must be within [{low:g}, {high:g}], got {value!r}", where=name)
        if self.speed_band_percent == 0 and self.speed_band_kmh == 0:
            raise InputError("a speed band of zero width cannot be held", where="speed_band_kmh")

    def band_kmh(self, target_kmh):
        """Half-width of the speed band around ``target_kmh`` [km/h] (a number, or an array: a rising target
        has a band that widens with it).

        Parameters
        ----------
        target_kmh : float or array_like
            Target speed [km/h].

        Returns
        -------
        float or numpy.ndarray
            Half-width [km/h].
        """
        band = np.maximum(self.speed_band_percent / 100.0 * np.abs(target_kmh), self.speed_band_kmh)
        return float(band) if np.ndim(band) == 0 else band

    def to_dict(self) -> dict:
        """The settings as a plain dict.

        Returns
        -------
        dict
            The settings.
        """
        return asdict(self)


@dataclass(frozen=True)
class Reason:
    """One thing that went wrong in a run: which (:data:`REASONS`), first when [s], and in words."""

    reason: str
    time_s: float
    detail: str
    wheel: str | None = None

    def to_dict(self) -> dict:
        """``reason``, ``time_s``, ``detail`` and ``wheel`` (None unless a wheel lifted).

        Returns
        -------
        dict
            The reason.
        """
        return asdict(self)


@dataclass(frozen=True)
class Verdict:
    """How a run went (see the module docstring).

    Attributes
    ----------
    passed : bool
        No reason found.
    verdict : str
        ``"pass"`` or the earliest reason.
    reasons : tuple of Reason
        Every reason found, in time order.
    target_speed_kmh : float or None
        The highest target speed of the manoeuvre [km/h].
    entry_speed_kmh : float or None
        Speed at the entry gate [km/h] (None when the run never reached it).
    window_speed_kmh : dict or None
        ``{"min", "mean", "max"}`` of the speed over the window [km/h].
    speed_band_kmh : float or None
        Half-width of the band the speed was held to at the highest target [km/h] (None when the manoeuvre's
        speed is not judged); a varying target has the band of each moment's target.
    """

    passed: bool
    verdict: str
    reasons: tuple[Reason, ...]
    target_speed_kmh: float | None
    entry_speed_kmh: float | None
    window_speed_kmh: dict | None
    speed_band_kmh: float | None

    def first(self, criterion: str | None = None) -> Reason | None:
        """The earliest reason (failing under ``criterion``, all when None), or None.

        Parameters
        ----------
        criterion : str, optional
            ``"lift-off"`` or ``"course"``.

        Returns
        -------
        Reason or None
            The reason.
        """
        wanted = REASONS if criterion is None else failures(criterion)
        return next((r for r in self.reasons if r.reason in wanted), None)

    def reason(self, name: str) -> Reason | None:
        """The reason ``name`` if it was found.

        Parameters
        ----------
        name : str
            A reason (:data:`REASONS`).

        Returns
        -------
        Reason or None
            The reason.
        """
        return next((r for r in self.reasons if r.reason == name), None)

    def passes(self, criterion: str) -> bool:
        """Whether the run passes under ``criterion`` (:data:`CRITERIA`).

        Parameters
        ----------
        criterion : str
            ``"lift-off"`` or ``"course"``.

        Returns
        -------
        bool
            True when no failing reason was found.
        """
        return self.first(criterion) is None

    @property
    def speed_text(self) -> str:
        """The speed driven in words: ``driven 43.6 km/h at the entry gate, 42.9-43.8 in the window``."""
        if self.entry_speed_kmh is None or self.window_speed_kmh is None:
            return "the window was not reached"
        w = self.window_speed_kmh
        return (f"driven {self.entry_speed_kmh:.1f} km/h at the entry gate, {w['min']:.1f}-{w['max']:.1f} km/h in "
                f"the window")

    def to_dict(self) -> dict:
        """``passed``, ``verdict``, ``reasons`` (list of dicts) and the speeds.

        Returns
        -------
        dict
            The verdict.
        """
        out = asdict(self)
        out["reasons"] = [r.to_dict() for r in self.reasons]
        return out


def failures(criterion: str) -> tuple[str, ...]:
    """The reasons that fail a run under ``criterion``: ``"lift-off"`` or ``"course"`` (:data:`CRITERIA`).

    Parameters
    ----------
    criterion : str
        ``"lift-off"`` or ``"course"``.

    Returns
    -------
    tuple of str
        The reasons.

    Raises
    ------
    InputError
        For an unknown criterion.
    """
    if criterion not in _FAILS:
        raise InputError(f"unknown criterion {criterion!r}; expected one of {', '.join(CRITERIA)} (or both)",
                         where="criterion")
    return _FAILS[criterion]


def target_speed_mps(result) -> np.ndarray | None:
    """The target speed at each sample of a run [m/s], from its manoeuvre's profile (None without one).

    Parameters
    ----------
    result : Result
        A run.

    Returns
    -------
    numpy.ndarray or None
        Target speed [m/s].
    """
    man = result.manoeuvre
    if man is None or getattr(man, "speed", None) is None:
        return None
    return np.interp(result.time_s, man.speed.time_s, man.speed.speed_mps)


def sideslip_rad(result) -> np.ndarray:
    """Sideslip angle at the CG [rad], in ``[0, pi]``: ``atan2(|v_y|, v_x)`` (pi when rolling backwards)."""
    return np.arctan2(np.abs(np.asarray(result["vy_mps"], dtype=float)), np.asarray(result["vx_mps"], dtype=float))


def judge(result, judging: Judging | None = None) -> Verdict:
    """The verdict of a run (see the module docstring).

    Parameters
    ----------
    result : Result
        A run (:func:`trikedyn.simulate.closed_loop.run`, or an open-loop
        :func:`~trikedyn.simulate.run.simulate`, judged over all of it and without a speed band).
    judging : Judging, optional
        The band and limits; defaults otherwise.

    Returns
    -------
    Verdict
    """
    from .window import cone_strikes, first_lift, judged_mask, until_exit

    judging = judging or Judging()
    time = np.asarray(result.time_s, dtype=float)
    window = judged_mask(result)
    scope = until_exit(result) if window.any() else np.ones(time.size, dtype=bool)
    reasons: list[Reason] = []

    lift = first_lift(result, from_start=True)
    if lift is not None:
        reasons.append(Reason(LIFT_OFF, lift.time_s, f"{lift.wheel} lifted at {lift.time_s:.2f} s", lift.wheel))
    strikes = cone_strikes(result)
    if strikes:
        t = min(float(s["time_s"]) for s in strikes)
        reasons.append(Reason(CONE_STRIKE, t, f"{len(strikes)} cone(s) struck, the first at {t:.2f} s"))
    man = result.manoeuvre
    if "path_error_m" in result.channels and man is not None and man.closed_loop:
        error = np.abs(np.asarray(result["path_error_m"], dtype=float))
        lost = np.nonzero((error > judging.lost_m) & scope)[0]
        if lost.size:
            t = float(time[lost[0]])
            reasons.append(Reason(PATH_LOST, t, f"path lost (CG over {judging.lost_m:g} m off it) at {t:.2f} s"))
    slid = np.nonzero((sideslip_rad(result) > math.radians(judging.spin_deg)) & scope)[0]
    if slid.size:
        t = float(time[slid[0]])
        reasons.append(Reason(SPIN, t, f"spin (sideslip over {judging.spin_deg:g} deg) at {t:.2f} s"))

    speed = np.asarray(result["speed_mps"], dtype=float) * 3.6
    target = target_speed_mps(result)
    top = None if target is None else float(np.max(target) * 3.6)
    entry = window_speed = band = None
    if window.any():
        inside = speed[window]
        entry = float(inside[0])
        window_speed = {"min": float(inside.min()), "mean": float(inside.mean()), "max": float(inside.max())}
    where = getattr(man, "speed_judged", "window") if target is not None else "none"
    if where != "none":
        band = judging.band_kmh(top)
        bands = judging.band_kmh(target * 3.6)
        judged = window
        if where == "entry" and window.any():
            judged = np.zeros_like(window)
            judged[int(np.nonzero(window)[0][0])] = True
        off = np.nonzero(judged & (np.abs(speed - target * 3.6) > bands))[0]
        if off.size:
            i = int(off[0])
            reasons.append(Reason(SPEED_NOT_HELD, float(time[i]),
                                  f"speed not held: {speed[i]:.1f} km/h at {time[i]:.2f} s against a target of "
                                  f"{target[i] * 3.6:.1f} +/- {bands[i]:.1f} km/h"))
        elif man is not None and result.success and not _reached_exit(result):
            t = float(time[-1])
            where = "the exit gate" if window.any() else "the entry gate"
            reasons.append(Reason(SPEED_NOT_HELD, t, f"speed not held: the run ended at {t:.2f} s before {where}"))
    if not result.success and not any(r.reason == LIFT_OFF for r in reasons):
        t = float(time[-1])
        reasons.append(Reason(STOPPED, t, f"the simulation stopped at {t:.2f} s: {result.status}"))
    reasons.sort(key=lambda r: (r.time_s, REASONS.index(r.reason)))
    verdict = reasons[0].reason if reasons else PASS
    return Verdict(not reasons, verdict, tuple(reasons), top, entry, window_speed, band)


def _reached_exit(result) -> bool:
    man = result.manoeuvre
    w = man.window
    if w.kind == "distance":
        if "path_s_m" not in result.channels:
            return True
        return bool(float(np.max(result["path_s_m"])) >= w.end - 1e-9)
    return bool(float(result.time_s[-1]) >= w.end - 1e-9)
