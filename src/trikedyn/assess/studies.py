"""The dossier's studies: where the freight goes, what a design change buys, the speed limit per payload, and
the slow ones left out by ``--quick`` (loading chart, sensitivity, an animation of the most critical run).

Each uses the same function as its command with that command's defaults: ``trikedyn loading-chart``
(:func:`loading_chart`), ``trikedyn sensitivity`` with fewer trajectories (:func:`sensitivity`), ``trikedyn
threshold`` (:func:`design_changes`, :func:`speed_limits`), ``trikedyn animate`` through the paper's lane-change
animation (:func:`animate_critical`).
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["DESIGN_STEPS", "SENSITIVITY_SETTINGS", "animate_critical", "critical_run", "design_changes",
           "freight_positions", "loading_chart", "sensitivity", "speed_limits"]

DESIGN_STEPS = (("track_m", +0.10, "track 10 cm wider"), ("cg_height_m", -0.05, "CG 5 cm lower"),
                ("wheelbase_m", +0.20, "wheelbase 20 cm longer"), ("battery_z", -0.10, "heaviest component 10 cm lower"))
"""Design changes tried: knob, step [m], in words (``battery_z``: the heaviest component's ``z_m``)."""

SENSITIVITY_SETTINGS = {"method": "morris", "samples": 2, "seed": 1, "fraction": 0.2, "manoeuvre": "dlc"}
"""The small sensitivity: ``trikedyn sensitivity`` with 2 Morris trajectories (its default is 10) over every
assumed value that can vary, +/-20 % (or the range the vehicle file declares)."""


def _search(pset, manoeuvre: str = "dlc"):
    """``trikedyn threshold``'s search (course criterion, driver speed control), on the course of ``pset``."""
    from ..study.designs.sample_runs import Search

    return Search(manoeuvre, {}, 0.1, high_kmh=90.0, criterion="course", speed_control="driver").on_course_of(pset)


def _static_g(pset) -> float:
    from ..params import tip_over_thresholds

    return float(min(e["acceleration_g"] for e in tip_over_thresholds(pset.params) if e["lateral"]))


def freight_positions(pset, mass_kg: float) -> list[dict]:
    """Rigid static stability with ``mass_kg`` of freight over the loading chart's default positions.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle without freight.
    mass_kg : float
        Freight mass [kg].

    Returns
    -------
    list of dict
        Per position: ``x_m``, ``z_m`` [m] (vehicle axes), ``static_stability_g`` (rigid lateral tip-over
        a_y/g of the weaker edge) and ``rigid_tilt_angle_deg`` [deg].
    """
    import math

    from ..errors import ParameterError
    from ..params import apply_knobs, with_freight
    from ..study.designs.loading import grid_cells

    _, xs, zs = grid_cells(pset)
    rows = []
    for x in xs:
        for z in zs:
            try:
                g = _static_g(with_freight(apply_knobs(pset, {"freight.x_m": x, "freight.z_m": z}), mass_kg))
            except ParameterError:
                continue
            rows.append({"x_m": x, "z_m": z, "static_stability_g": g, "rigid_tilt_angle_deg": math.degrees(math.atan(g))})
    return rows


def _current(pset, knob: str) -> tuple[str, float] | None:
    """(knob name, its value now) of a step of :data:`DESIGN_STEPS`; None when the vehicle has no such knob."""
    from ..params import mass_properties

    params = pset.params
    xs = [w.x_m for w in params.wheels]
    if knob == "track_m":
        pair = [w for w in params.wheels if abs(w.y_m) > 1e-9]
        return knob, abs(pair[0].y_m - pair[1].y_m)
    if knob == "wheelbase_m":
        return knob, max(xs) - min(xs)
    if knob == "cg_height_m":
        return knob, float(mass_properties(params).cg_m[2])
    if not params.components:
        return None
    heaviest = max(params.components, key=lambda c: c.mass_kg)
    return f"component.{heaviest.name}.z_m", heaviest.z_m


def design_changes(pset, say=None) -> list[dict]:
    """What each design change of :data:`DESIGN_STEPS` does to the tilt angle and the DLC threshold.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle as given.
    say : callable, optional
        ``say(text)``: a progress line.

    Returns
    -------
    list of dict
        Per change: ``change`` (words), ``knob``, ``from``/``to`` [m], ``tilt_angle_deg`` [deg] and
        ``dlc_threshold_kmh`` [km/h] before and after (the DLC on the vehicle's own course), the gains; a
        change the vehicle cannot take says why (``error``).
    """
    from ..analysis.tilt import tilt_table
    from ..errors import ParameterError
    from ..params import apply_knobs

    search = _search(pset)
    base_tilt = tilt_table(pset).tilt_angle_deg
    base_dlc, _ = search.threshold(pset)
    rows = []
    for knob, step, words in DESIGN_STEPS:
        found = _current(pset, knob)
        if found is None:
            continue
        name, now = found
        if say:
            say(f"design change: {words}")
        row = {"change": words, "knob": name, "from": now, "to": now + step, "tilt_angle_deg": base_tilt,
               "dlc_threshold_kmh": base_dlc}
        try:
            variant = apply_knobs(pset, {name: now + step})
        except ParameterError as exc:
            rows.append(row | {"error": " ".join(str(exc).split())})
            continue
        tilt = tilt_table(variant).tilt_angle_deg
        dlc, error = search.threshold(variant)
        row |= {"new_tilt_angle_deg": tilt, "tilt_gain_deg": tilt - base_tilt, "new_dlc_threshold_kmh": dlc,
                "dlc_gain_kmh": None if dlc is None or base_dlc is None else dlc - base_dlc}
        rows.append(row | ({"error": error} if error else {}))
    return rows


def speed_limits(pset, masses_kg, say=None, known: dict | None = None) -> list[dict]:
    """The speed to print on the vehicle per payload: the lowest course threshold of the DLC, SLC and
    fishhook less the loading chart's margin (:data:`trikedyn.study.designs.loading.DEFAULT_MARGIN_KMH`).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle without freight.
    masses_kg : sequence of float
        Payloads [kg] at the vehicle's freight site.
    say : callable, optional
        ``say(text)``: a progress line.
    known : dict, optional
        Payload [kg] -> manoeuvre -> course threshold [km/h] found already (the dossier's states): not
        searched again.

    Returns
    -------
    list of dict
        Per payload: ``payload_kg``, each manoeuvre's course threshold [km/h], ``limiting`` (the manoeuvre),
        ``speed_limit_kmh`` [km/h] of the manoeuvres with a threshold (None when none has one), and
        ``failed_everywhere``: the manoeuvres failed already at the lowest speed searched.
    """
    from ..params import with_freight
    from ..study.designs.loading import DEFAULT_MARGIN_KMH, safe_speed
    from .runs import MANOEUVRES

    rows = []
    for kg in masses_kg:
        laden = with_freight(pset, kg)
        row = {"payload_kg": float(kg)}
        for name in MANOEUVRES:
            if known and float(kg) in known:
                row[f"{name}_threshold_kmh"] = known[float(kg)][name]
                continue
            if say:
                say(f"speed limit: {kg:g} kg, {name}")
            row[f"{name}_threshold_kmh"] = _search(pset, name).threshold(laden)[0]
        found = {n: row[f"{n}_threshold_kmh"] for n in MANOEUVRES}
        known = {n: v for n, v in found.items() if v is not None}
        limiting = min(known, key=known.get) if known else None
        row |= {"limiting": limiting, "margin_kmh": DEFAULT_MARGIN_KMH,
                "speed_limit_kmh": safe_speed(known[limiting]) if limiting else None,
                "failed_everywhere": [n for n, v in found.items() if v is None]}
        rows.append(row)
    return rows


def loading_chart(pset, out: Path, *, resume: bool = False, workers: int = 2):
    """``trikedyn loading-chart``'s default chart (DLC), its cells logged in ``out`` as they finish.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    out : Path
        The dossier's folder (``loading-chart-cells.csv``).
    resume : bool
        Take the cells already logged.
    workers : int
        Processes.

    Returns
    -------
    data : dict
        As ``trikedyn loading-chart --json``.
    figure : matplotlib.figure.Figure
        The chart.
    """
    from ..study.designs import loading as lc
    from ..study.engine.progress import ProgressLine

    chart = lc.run_loading_chart(pset, _search(pset), margin_kmh=lc.DEFAULT_MARGIN_KMH, workers=workers,
                                 log=lc.CellLog(Path(out) / "loading-chart-cells.csv"), resume=resume,
                                 progress=ProgressLine("assess: loading chart", "cells", every_s=5.0))
    return chart.to_dict(), chart.plot()


def sensitivity(pset, out: Path, *, resume: bool = False, workers: int = 2):
    """A small Morris sensitivity of the DLC threshold (:data:`SENSITIVITY_SETTINGS`), samples logged in ``out``.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    out : Path
        The dossier's folder (``sensitivity-samples.csv``).
    resume : bool
        Take the samples already logged.
    workers : int
        Processes.

    Returns
    -------
    data : dict
        As ``trikedyn sensitivity --json`` (``indices``: mu* [km/h] per factor, largest first).
    figure : matplotlib.figure.Figure
        The ranking.
    """
    from ..study.designs import sensitivity as sa
    from ..study.engine.progress import ProgressLine

    s = SENSITIVITY_SETTINGS
    factors, excluded = sa.candidate_factors(pset, s["fraction"])
    log = sa.SampleLog(Path(out) / "sensitivity-samples.csv", factors, sa.group_size(s["method"], len(factors)))
    search = sa.Search(s["manoeuvre"], {}, 0.1, high_kmh=90.0, criterion="course", speed_control="driver")
    result = sa.run_sensitivity(pset, search, factors, method=s["method"],
                                samples=s["samples"], seed=s["seed"], fraction=s["fraction"], excluded=excluded,
                                workers=workers, log=log, resume=resume,
                                progress=ProgressLine("assess: sensitivity", every_s=5.0))
    return result.to_dict(), result.plot(top=10)


def critical_run(thresholds: dict) -> tuple[str, float] | None:
    """The most critical run: the manoeuvre with the lowest course threshold, at the speed it first fails.

    Parameters
    ----------
    thresholds : dict
        :func:`trikedyn.assess.runs.thresholds`.

    Returns
    -------
    (str, float) or None
        Manoeuvre and target speed [km/h]; None when no threshold was found.
    """
    known = {n: t for n, t in thresholds.items() if t["course_kmh"] is not None}
    if not known:
        return None
    name = min(known, key=lambda n: known[n]["course_kmh"])
    t = known[name]
    return name, float(t["first_failure_kmh"] if t["first_failure_kmh"] is not None else t["course_kmh"])


def animate_critical(pset, manoeuvre: str, speed_kmh: float, path: Path) -> Path:
    """A GIF of one run seen from above, drawn as the paper's report draws its lane changes.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    manoeuvre : str
        A registered manoeuvre.
    speed_kmh : float
        Target speed [km/h].
    path : Path
        The GIF to write.

    Returns
    -------
    Path
        The file written.
    """
    from ..paper.report import animate_lane_change
    from ..simulate.closed_loop import run

    result = run(pset, manoeuvre, speed_kmh=speed_kmh, duration_s=None, speed_control="driver")
    return animate_lane_change(result, Path(path))
