"""The margin of one run: how far it was from failing, per wheel (and per criterion) and stretch of the window.

The threshold search (:mod:`trikedyn.analysis.search`) steers by a table of continuous margins that fall
smoothly with speed and cross zero where the run starts to fail:

- **wheel rows** (:func:`margin_table`): the minimum vertical force [N] of each wheel in each of ``BINS``
  stretches of the judged window (column 0: the run-in), extended below zero beyond a lift;
- **criterion rows** (:func:`criterion_rows`), one per other reason a run fails
  (:mod:`trikedyn.analysis.verdict`): the speed's distance inside its band [km/h], the CG's distance inside
  the ``lost_m`` corridor around the path [m], the sideslip's distance below the spin limit [deg] and,
  under the ``course`` criterion, the footprint's signed clearance to the nearest cone [m]
  (:func:`~trikedyn.manoeuvres.judging.cone_clearance`). Each is continuous through its failure (a cone
  overlapped by 5 cm is -0.05 m), so the search extrapolates to its zero as it does a wheel's load.

Each row has its value at ``v = 0`` (the wheel's static load, the band, ``lost_m``, the spin limit; none for
the cones), the anchor of the first secant. Rows of different units never mix: each row predicts its own
crossing and the search takes the lowest.
"""

from __future__ import annotations

import numpy as np

__all__ = ["BINS", "criterion_rows", "margin_table", "run_margins"]

BINS = 24
"""Stretches of the judged window the margin is tracked over (plus the run-in)."""


def _columns(result, bins: int) -> tuple[np.ndarray, np.ndarray]:
    """The stretch (column) of each sample and the mask of the samples up to the exit gate."""
    from .window import judged_mask, until_exit

    judged = judged_mask(result)
    scope = until_exit(result) if judged.any() else np.ones(result.time_s.size, dtype=bool)
    coord, start, end = _coordinate(result, judged)
    width = (end - start) / bins
    column = np.clip(np.floor((coord - start) / width).astype(int) + 1, 0, bins) if width > 0 \
        else np.zeros(result.time_s.size, dtype=int)
    return column, scope


def _stretch_minima(values: np.ndarray, mask: np.ndarray, column: np.ndarray, bins: int) -> np.ndarray:
    """The minimum of ``values`` (samples along the first axis) over the samples in ``mask``, per stretch:
    shape ``(bins + 1,) + values.shape[1:]``, NaN where a stretch has no sample (a NaN value makes its
    stretch's minimum NaN, as :func:`numpy.min` does). One sort and one :func:`numpy.minimum.reduceat`
    instead of a pass per stretch."""
    out = np.full((bins + 1,) + values.shape[1:], np.nan)
    where = np.nonzero(mask)[0]
    if not where.size:
        return out
    order = where[np.argsort(column[where], kind="stable")]
    cols = column[order]
    starts = np.concatenate(([0], np.nonzero(np.diff(cols))[0] + 1))
    out[cols[starts]] = np.minimum.reduceat(values[order], starts, axis=0)
    return out


def _row(values: np.ndarray, mask: np.ndarray, column: np.ndarray, bins: int) -> np.ndarray:
    """The minimum of ``values`` over the samples in ``mask``, per stretch (NaN where none)."""
    return _stretch_minima(np.asarray(values, dtype=float), mask, column, bins)


def margin_table(result, *, fail_time_s: float | None = None, lift_wheel: str | None = None,
                 bins: int = BINS) -> tuple[np.ndarray, np.ndarray]:
    """The margin table of a run and its wheels' static loads.

    Parameters
    ----------
    result : Result
        A run of :func:`trikedyn.simulate.closed_loop.run`.
    fail_time_s : float, optional
        Time of its first failure [s] (lift or lost path): later samples are not used.
    lift_wheel : str, optional
        The wheel that lifted at ``fail_time_s``: its stretch gets the negative extension.
    bins : int
        Stretches of the judged window.

    Returns
    -------
    margins : ndarray (wheels, bins + 1)
        Minimum vertical force [N] per wheel and stretch (column 0: the run-in), NaN where unknown.
    static : ndarray (wheels,)
        Vertical force of each wheel at the start of the run [N] (the margin at ``v = 0``).
    """
    wheels = result.meta["wheels"]
    fz = np.column_stack([np.asarray(result[f"{w}_fz_N"], dtype=float) for w in wheels])
    static = fz[0].copy()
    column, scope = _columns(result, bins)
    time = np.asarray(result.time_s)
    before = scope & (time < fail_time_s) if fail_time_s is not None else scope
    out = _stretch_minima(fz, before, column, bins).T.copy()
    if lift_wheel is not None and fail_time_s is not None and lift_wheel in wheels:
        w = wheels.index(lift_wheel)
        after = np.nonzero(scope & (time >= fail_time_s))[0]
        if after.size:
            i = int(after[0])
            out[w, column[i]] = max(_virtual_dip(time, fz[:, w], i, int(after[-1])), -static[w])
    return out, static


def _virtual_dip(time: np.ndarray, load: np.ndarray, i: int, end: int) -> float:
    """How deep below zero a wheel's load would have dipped [N], from the lift at sample ``i``.

    Near its minimum a dip is a parabola, ``F(t) = F_min + F'' (t - t_min)^2 / 2``: it stays below zero for
    ``T = 2 sqrt(-2 F_min / F'')`` and falls through zero at the rate ``F' = -F'' T / 2``, so
    ``F_min = F' T / 4``. ``F'`` is the load's rate of fall before the lift [N/s], ``T`` the time the wheel
    stayed up (to ``end`` if it did not come down). Zero at the threshold, it grows smoothly beyond it.
    """
    if i < 2:
        return 0.0
    rate = (load[i - 1] - load[i - 2]) / (time[i - 1] - time[i - 2])
    if not rate < 0:
        return 0.0
    down = min(time[i - 1] + load[i - 1] / -rate, time[i])
    landed = np.nonzero(load[i:end + 1] > 0)[0]
    up = 0.5 * (time[i + landed[0] - 1] + time[i + landed[0]]) if landed.size else time[end]
    return float(rate * max(up - down, 0.0) / 4)


def _coordinate(result, judged: np.ndarray) -> tuple[np.ndarray, float, float]:
    """Where along the manoeuvre each sample is (distance along the path [m] or time [s]), and the gates."""
    man = result.manoeuvre
    time = np.asarray(result.time_s, dtype=float)
    if man is not None:
        w = man.window
        if w.kind == "distance" and "path_s_m" in result.channels:
            return np.asarray(result["path_s_m"], dtype=float), float(w.start), float(w.end)
        if w.kind == "time":
            return time, float(w.start), float(w.end)
    if judged.any():
        inside = time[judged]
        return time, float(inside[0]), float(inside[-1])
    return time, float(time[0]), float(time[-1])


def criterion_rows(result, verdict, criterion: str, judging, bins: int = BINS) -> tuple[np.ndarray, np.ndarray]:
    """The criterion rows of a run (see the module docstring) and their values at ``v = 0``.

    Parameters
    ----------
    result : Result
        A run of :func:`trikedyn.simulate.closed_loop.run`.
    verdict : Verdict
        Its verdict (:func:`trikedyn.analysis.verdict.judge`): samples after a lift are not used (the run is
        another motion from there on).
    criterion : {"lift-off", "course"}
        ``course`` adds the cone row.
    judging : Judging
        The band and limits the run was judged by.
    bins : int
        Stretches of the judged window.

    Returns
    -------
    rows : ndarray (3 or 4, bins + 1)
        Speed [km/h], path [m], spin [deg] and, under ``course``, cones [m]; NaN where unknown or not
        judged (an open-loop run has no path row).
    anchors : ndarray (3 or 4,)
        The rows' values at ``v = 0`` (NaN for the cones).
    """
    from .verdict import LIFT_OFF, sideslip_rad, target_speed_mps
    from .window import judged_mask

    column, scope = _columns(result, bins)
    time = np.asarray(result.time_s, dtype=float)
    lift = verdict.reason(LIFT_OFF)
    before = time <= lift.time_s if lift is not None else np.ones(time.size, dtype=bool)
    window = judged_mask(result) & before
    n = 4 if criterion == "course" else 3
    rows = np.full((n, bins + 1), np.nan)
    anchors = np.array([judging.speed_band_kmh, judging.lost_m, judging.spin_deg, np.nan][:n])
    man = result.manoeuvre
    target = target_speed_mps(result)
    if target is not None and verdict.speed_band_kmh is not None and window.any():
        speed = np.asarray(result["speed_mps"], dtype=float) * 3.6
        judged = window
        if getattr(man, "speed_judged", "window") == "entry":
            judged = np.zeros_like(window)
            judged[int(np.nonzero(window)[0][0])] = True
        rows[0] = _row(judging.band_kmh(target * 3.6) - np.abs(speed - target * 3.6), judged, column, bins)
    if "path_error_m" in result.channels and man is not None and man.closed_loop:
        error = np.abs(np.asarray(result["path_error_m"], dtype=float))
        rows[1] = _row(judging.lost_m - error, scope & before, column, bins)
    rows[2] = _row(judging.spin_deg - np.degrees(sideslip_rad(result)), scope & before, column, bins)
    if criterion == "course" and man is not None and man.path is not None and len(man.path.cones) \
            and window.any():
        from ..manoeuvres.judging import cone_clearance

        clearance = np.full(time.size, np.nan)  # only the window's samples are read: only they are computed
        clearance[window] = cone_clearance(man.path, time[window], result["x_m"][window], result["y_m"][window],
                                           result["yaw_rad"][window], tuple(result.meta["footprint_m"]))
        rows[3] = _row(np.where(np.isfinite(clearance), clearance, np.nan), window, column, bins)
    return rows, anchors


def run_margins(result, verdict, criterion: str, judging, bins: int = BINS) -> tuple[np.ndarray, np.ndarray, float | None]:
    """The whole margin table of a run under ``criterion``: wheel rows then criterion rows.

    Parameters
    ----------
    result : Result
        A run.
    verdict : Verdict
        Its verdict (:func:`~trikedyn.analysis.verdict.judge`).
    criterion : str
        ``"lift-off"``, ``"course"`` or both.
    judging : Judging
        The judging settings.
    bins : int
        Stretches of the window.

    Returns
    -------
    table : ndarray (rows, bins + 1)
    anchors : ndarray (rows,)
        Values at ``v = 0`` (the wheels' static loads first).
    margin_N : float or None
        The smallest wheel entry [N] (negative when a wheel lifted), None when unknown.
    """
    from .verdict import LIFT_OFF, PATH_LOST, SPIN, STOPPED

    lift = verdict.reason(LIFT_OFF)
    if lift is not None:
        cut, wheel = lift.time_s, lift.wheel
    else:
        lost = [r.time_s for r in verdict.reasons if r.reason in (PATH_LOST, SPIN, STOPPED)]
        cut, wheel = (min(lost) if lost else None), None
    wheels, static = margin_table(result, fail_time_s=cut, lift_wheel=wheel, bins=bins)
    rows, anchors = criterion_rows(result, verdict, criterion, judging, bins)
    margin = float(np.nanmin(wheels)) if np.isfinite(wheels).any() else None
    return np.vstack((wheels, rows)), np.concatenate((static, anchors)), margin
