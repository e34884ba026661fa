"""The standard tracks as paths: ISO 3888-1/-2 double lane change, ISO 14791 single lane change, ISO 4138
circle, and a straight. Each function's docstring says which choices are ours where the standard leaves one.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..errors import InputError
from .geometry import (
    MAX_LENGTH_M,
    Corridor,
    Path,
    _direction,
    _from_graph,
    _lane_cones,
    _lateral_profile,
    _mirror,
    _number,
    _uniform_count,
)

__all__ = ["circle", "double_lane_change", "single_lane_change", "straight"]

# --------------------------------------------------------------------------------------------------------------
# ISO 3888 double lane change
# --------------------------------------------------------------------------------------------------------------
_ISO3888 = ("ISO 3888-1", "ISO 3888-2")


def _iso3888_track(w: float, standard: str):
    """Section lengths [m] and lanes (section names, x_from, x_to, y_min, y_max) for a left-first track.

    x from the start of section 1; y = 0 on the centre of section 1.
    """
    if standard == "ISO 3888-1":
        lengths = (15.0, 30.0, 25.0, 25.0, 15.0, 15.0)
        a = 1.1 * w + 0.25  # section 1
        b = 1.2 * w + 0.25  # section 3
        c = 1.3 * w + 0.25  # sections 5 and 6
        y3_min = -0.5 * a + 3.5  # lane offset 3.5 m between the right-hand limits of sections 1 and 3
    else:  # ISO 3888-2
        lengths = (12.0, 13.5, 11.0, 12.5, 12.0)
        a = 1.1 * w + 0.25
        b = w + 1.0
        c = max(1.3 * w + 0.25, 3.0)
        y3_min = 0.5 * a + 1.0  # lane offset 1 m: gap between the left limit of section 1 and the right of section 3
    edges = np.concatenate(([0.0], np.cumsum(lengths)))
    lanes = [
        (("section 1",), edges[0], edges[1], -0.5 * a, 0.5 * a),
        (("section 3",), edges[2], edges[3], y3_min, y3_min + b),
        # exit lane: its right-hand limit continues that of section 1
        (
            ("section 5", "section 6") if len(lengths) == 6 else ("section 5",),
            edges[4],
            edges[-1],
            -0.5 * a,
            -0.5 * a + c,
        ),
    ]
    return lengths, edges, lanes


@functools.lru_cache(maxsize=64)  # a threshold search builds the same track at every speed
def double_lane_change(
    vehicle_width_m: float,
    *,
    run_in_m: float = 30.0,
    run_out_m: float = 30.0,
    standard: str = "ISO 3888-1",
    direction: str = "left",
) -> Path:
    """Double lane change track: ISO 3888-1 (default) or ISO 3888-2, cones, lanes and a reference line.

    Parameters
    ----------
    vehicle_width_m : float
        Vehicle width w [m] (the paper's e-trike: 1.25 m). The lane widths are functions of it.
    run_in_m : float
        Straight approach before section 1 [m]; section 1 starts at ``x = run_in_m``.
    run_out_m : float
        Straight after the last section, on the exit-lane centre [m].
    standard : {"ISO 3888-1", "ISO 3888-2"}
        ISO 3888-1 double lane change (the paper's test) or ISO 3888-2 obstacle avoidance.
    direction : {"left", "right"}
        Side of the first lane change (the paper's: left).

    Returns
    -------
    Path
        With one corridor per lane section and the cones.

    Notes
    -----
    **ISO 3888-1** (Passenger cars -- Test track for a severe lane-change manoeuvre -- Part 1: Double
    lane-change), Table 1, as Project Chrono's ISO 3888 helper implements it and other public models cite
    it from the 1999 edition (we could not read the standard's text; we assume the 2018 edition the paper
    cites kept the track):

    ========  ==========  ==================  =====================================
    section   length [m]  lane width [m]      lateral position
    ========  ==========  ==================  =====================================
    1         15          1.1 w + 0.25        reference lane
    2         30          --                  --
    3         25          1.2 w + 0.25        lane offset 3.5 m
    4         25          --                  --
    5         15          1.3 w + 0.25        right-hand limit in line with section 1
    6         15          1.3 w + 0.25        as section 5
    ========  ==========  ==================  =====================================

    Total 125 m. For w = 1.25 m the lanes are 1.625, 1.75 and 1.875 m wide; for w = 2 m, 2.45, 2.65 and
    2.85 m. *Choice*: the standard gives a "lane offset" of 3.5 m; we measure it between the right-hand
    lane limits of sections 1 and 3 (same-side cone lines), so the lane centres are 3.5 + 0.05 w m apart
    (3.5625 m for the e-trike). Project Chrono measures it from the centre of section 1 to the right-hand
    limit of section 3 (centres 3.5 + (1.2 w + 0.25)/2 apart, 4.375 m for the e-trike), and simple models
    take it centre to centre; a reading of the standard's Figure 1 settles it.

    **ISO 3888-2** (Part 2: Obstacle avoidance, 2011), clause 4.1 and Table 1, as Project Chrono and other
    public tracks implement it: sections of 12, 13.5, 11, 12.5 and 12 m (total 61 m, as 4.1 states); lanes 1.1 w + 0.25 (section 1), w + 1 (section 3, its
    right-hand limit 1 m left of the left-hand limit of section 1) and 1.3 w + 0.25 but not less than 3 m
    (section 5, right-hand limit in line with section 1). *Uncertain*: public implementations disagree on
    section 5 (Project Chrono: 3 m; others: 1.3 w + 0.25 capped at 3 m); we take "not less than 3 m".

    **Cones**: at the start, the middle and the end of each lane (sections 1, 3 and the exit lane: for
    ISO 3888-1 sections 5 and 6 together), on both limits, as Project Chrono and other public tracks
    place them. ISO 3888-2 clause 4.2 puts the lane limits tangent to the cones' base circles; we do the
    same for both parts, so cone centres lie ``CONE_RADIUS_M`` outside the corridor edges.

    **Reference line** (the standards prescribe the cones, not a line): the lane centres, joined across
    the free sections 2 and 4 by a sine blend -- the lateral position ``y = y0 + D (u - sin(2 pi u)/(2 pi))``,
    ``u`` the fraction of the free section -- which is the ISO 14791 lane-change shape. Heading and
    curvature are continuous (the curvature rate jumps at the ends of a blend); the line is straight and
    centred in every lane section, so a vehicle on it keeps ``(lane width - w) / 2`` to each limit.
    """
    w = _number(vehicle_width_m, "vehicle_width_m", positive=True)
    if w > 5.0:
        raise InputError(f"expected a vehicle width in metres (<= 5), got {w:g}", where="vehicle_width_m")
    run_in = _number(run_in_m, "run_in_m", minimum=0.0)
    run_out = _number(run_out_m, "run_out_m", minimum=0.0)
    if standard not in _ISO3888:
        raise InputError(f"expected one of {', '.join(_ISO3888)}, got {standard!r}", where="standard")
    sign = _direction(direction)

    lengths, edges, lanes = _iso3888_track(w, standard)
    corridors: list[Corridor] = []
    cones: list[tuple[float, float]] = []
    centres = []
    for names, x_from, x_to, y_min, y_max in lanes:
        x_from += run_in
        x_to += run_in
        lane = Corridor(x_from, x_to, y_min, y_max, " + ".join(names))
        cones += _lane_cones(lane, (x_from, 0.5 * (x_from + x_to), x_to))
        centres.append(lane.centre_y_m)
        cut = x_from
        for k, name in enumerate(names):  # one corridor per section
            x_cut = x_to if k == len(names) - 1 else cut + (x_to - x_from) / len(names)
            corridors.append(Corridor(cut, x_cut, y_min, y_max, name))
            cut = x_cut
    e = edges + run_in
    transitions = ((e[1], e[2], centres[1]), (e[3], e[4], centres[2]))
    x_end = e[-1] + run_out

    def profile(x):
        """``(y [m], y' [-], y'' [1/m])`` of the reference line at ``x`` [m]: the lane centres joined by sine
        blends, mirrored for a change to the right."""
        y, dy, ddy = _lateral_profile(x, centres[0], transitions)
        return sign * y, sign * dy, sign * ddy

    cones_xy = np.array(cones)
    cones_xy[:, 1] *= sign
    lane_text = ", ".join(f"{c.name} {c.width_m:.3f} m" for c in corridors)
    return _from_graph(
        profile,
        x_end,
        name=f"{standard} {'double lane change' if standard == 'ISO 3888-1' else 'obstacle avoidance'}",
        cones=cones_xy,
        corridors=tuple(_mirror(c, sign) for c in corridors),
        description=(
            f"{standard} (Table 1) track for vehicle width {w:g} m, first change to the {direction}: "
            f"sections {', '.join(f'{v:g}' for v in lengths)} m (total {sum(lengths):g} m) from x = {run_in:g} m; "
            f"lanes {lane_text}. "
            + (
                "Lane offset 3.5 m taken between the right-hand limits of sections 1 and 3 (our reading). "
                if standard == "ISO 3888-1"
                else "Section 5 width: 1.3 w + 0.25 m, not less than 3 m (our reading; sources differ). "
            )
            + "Cones at the start, middle and end of each lane, tangent to the lane limits. Reference line: "
            "lane centres joined by sine blends (one sine period of curvature) across the free sections; "
            f"run-in {run_in:g} m, run-out {run_out:g} m."
        ),
    )


# --------------------------------------------------------------------------------------------------------------
# ISO 14791 single lane change
# --------------------------------------------------------------------------------------------------------------
@functools.lru_cache(maxsize=64)
def single_lane_change(
    *,
    lateral_offset_m: float = 3.5,
    length_m: float = 50.0,
    run_in_m: float = 30.0,
    run_out_m: float = 30.0,
    lane_width_m: float = 3.5,
) -> Path:
    """Single lane change (ISO 14791:2000): one full sine period of lateral acceleration.

    Parameters
    ----------
    lateral_offset_m : float
        Lateral displacement A of the lane change [m], positive to the left (the paper's: left).
    length_m : float
        Longitudinal length L of the lane change [m].
    run_in_m, run_out_m : float
        Straights before and after it [m]; the change starts at ``x = run_in_m``.
    lane_width_m : float
        Width of the start and the target lane [m] (corridors and cones).

    Returns
    -------
    Path
        Corridors "start lane" (the run-in) and "target lane" (the run-out), cones at their ends.

    Notes
    -----
    ISO 14791 (Road vehicles -- Heavy commercial vehicle combinations and articulated buses -- Lateral
    stability test methods) drives the single lane change along a path whose lateral acceleration is one
    full sine period. Over the change, with ``x' = x - run_in_m``::

        y(x') = A (x'/L - sin(2 pi x'/L) / (2 pi))
        a_y   = v^2 y'' = (2 pi A v^2 / L^2) sin(2 pi x'/L)   (small slope, constant speed)

    so the peak lateral acceleration is ``2 pi A v^2 / L^2`` and its frequency ``v / L``. The path's exact
    curvature, which this function returns, is ``y'' / (1 + y'^2)^1.5``; at the peak the slope is A/L, so
    it falls short of ``y''`` by about ``1.5 (A/L)^2``: under 1 % for L > 12 A (0.7 % with the defaults).

    *Choices* (the standard's text was not available to us; it is written for heavy vehicles and sets the
    test by speed and lateral-acceleration frequency): the offset defaults to 3.5 m (one road lane) and the
    length to 50 m, so that the peak lateral acceleration, 0.0088 v^2, is moderate at the e-trike's test
    speeds (0.6 m/s^2 at 30 km/h, 1.7 m/s^2 at 50 km/h). Shorten ``length_m`` for a sharper change
    (``L = v / f`` for a lateral-acceleration frequency ``f``). Lanes of 3.5 m by default.
    """
    a = _number(lateral_offset_m, "lateral_offset_m")
    if a == 0.0:
        raise InputError("must not be 0 (positive: to the left, negative: to the right)", where="lateral_offset_m")
    span = _number(length_m, "length_m", positive=True)
    run_in = _number(run_in_m, "run_in_m", minimum=0.0)
    run_out = _number(run_out_m, "run_out_m", minimum=0.0)
    width = _number(lane_width_m, "lane_width_m", positive=True)
    x0, x1 = run_in, run_in + span
    x_end = x1 + run_out
    corridors = []
    cones: list[tuple[float, float]] = []
    if run_in > 0.0:
        lane = Corridor(0.0, x0, -0.5 * width, 0.5 * width, "start lane")
        corridors.append(lane)
        cones += _lane_cones(lane, (0.0, x0))
    if run_out > 0.0:
        lane = Corridor(x1, x_end, a - 0.5 * width, a + 0.5 * width, "target lane")
        corridors.append(lane)
        cones += _lane_cones(lane, (x1, x_end))

    def profile(x):
        """``(y [m], y' [-], y'' [1/m])`` of the path at ``x`` [m]: 0 up to ``run_in_m``, a sine blend to
        ``lateral_offset_m`` over ``length_m``, then constant."""
        return _lateral_profile(x, 0.0, ((x0, x1, a),))

    return _from_graph(
        profile,
        x_end,
        name="ISO 14791 single lane change",
        cones=np.array(cones) if cones else np.zeros((0, 2)),
        corridors=tuple(corridors),
        description=(
            f"ISO 14791:2000 single lane change: lateral offset {a:g} m over {span:g} m from x = {run_in:g} m, "
            "y = A (x'/L - sin(2 pi x'/L)/(2 pi)): one sine period of lateral acceleration, peak "
            f"2 pi A v^2/L^2 = {2 * math.pi * abs(a) / span**2:.4g} v^2 m/s^2. Offset and length are our choices "
            f"(not taken from the standard's text). Lanes {width:g} m wide: start lane over the run-in, target "
            f"lane over the run-out ({run_out:g} m), cones at their ends tangent to the lane limits."
        ),
    )


# --------------------------------------------------------------------------------------------------------------
# ISO 4138 circle, straight
# --------------------------------------------------------------------------------------------------------------
def circle(radius_m: float, *, laps: float = 1.0, run_in_m: float = 10.0, direction: str = "left") -> Path:
    """Constant-radius circle (ISO 4138 steady-state circular driving, constant-radius method).

    Parameters
    ----------
    radius_m : float
        Radius of the reference line [m].
    laps : float
        Number of laps (fractions allowed).
    run_in_m : float
        Straight along +x before the circle [m]; the circle is tangent to it at ``x = run_in_m``.
    direction : {"left", "right"}
        Turning direction (left: counter-clockwise seen from above, centre at ``(run_in_m, +R)``).

    Returns
    -------
    Path
        No cones, no corridors.

    Notes
    -----
    ISO 4138 (Passenger cars -- Steady-state circular driving behaviour -- Open-loop test methods) leaves
    the radius to the tester (a large radius such as 100 m is usual for cars; a trike's lower speeds suit
    a smaller one). The curvature steps from 0 to 1/R where the run-in meets the circle; the driver's
    preview smooths the entry. The heading keeps growing over the laps (it is not wrapped).
    """
    r = _number(radius_m, "radius_m", positive=True, minimum=1.0)
    n_laps = _number(laps, "laps", positive=True)
    run_in = _number(run_in_m, "run_in_m", minimum=0.0)
    sign = _direction(direction)
    total = run_in + 2.0 * math.pi * r * n_laps
    if not total <= MAX_LENGTH_M:
        raise InputError(f"run_in_m {run_in:g} m + {n_laps:g} lap(s) of radius {r:g} m make {total:.4g} m; at "
                         f"most {MAX_LENGTH_M:g} m", where="circle")
    s = np.linspace(0.0, total, _uniform_count(total, "circle"))
    phi = np.clip(s - run_in, 0.0, None) / r
    on_circle = s > run_in
    x = np.where(on_circle, run_in + r * np.sin(phi), s)
    y = sign * r * (1.0 - np.cos(phi))
    return Path(
        name=f"ISO 4138 circle R = {r:g} m",
        x_m=x,
        y_m=y,
        s_m=s,
        heading_rad=sign * phi,
        curvature_per_m=np.where(on_circle, sign / r, 0.0),
        description=(
            f"ISO 4138 constant-radius circle, R = {r:g} m, {n_laps:g} lap(s) to the {direction}, "
            f"after a {run_in:g} m straight run-in (curvature steps to 1/R at the entry)."
        ),
    )


def straight(length_m: float) -> Path:
    """A straight line along +x from the origin.

    Parameters
    ----------
    length_m : float
        Length [m].

    Returns
    -------
    Path
        The line, no cones.
    """
    length = _number(length_m, "length_m", positive=True)
    s = np.linspace(0.0, length, _uniform_count(length, "length_m"))
    zero = np.zeros_like(s)
    return Path(
        name="straight",
        x_m=s.copy(),
        y_m=zero,
        s_m=s,
        heading_rad=zero.copy(),
        curvature_per_m=zero.copy(),
        description=f"straight line along +x, {length:g} m",
    )
