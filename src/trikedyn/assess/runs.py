"""What the stability dossier computes, piece by piece, with the same functions and defaults as the commands.

Each piece is a pure function of a parameter set that returns JSON-ready data (and, for some, a matplotlib
figure): the vehicle sheet (``trikedyn vehicle show``/``check``, ``cg payload``, ``modes``), static stability
(``tilt``, the audit's rigid tip-over), handling (``handling``), the thresholds (``threshold --criterion both``
for the DLC, SLC and fishhook), the top speed (``performance``). :func:`state_metrics` names the numbers a
requirement can bound (:data:`trikedyn.assess.requirements.METRICS`). The slow pieces (loading chart,
sensitivity, animation) are in :mod:`trikedyn.assess.studies`.
"""

from __future__ import annotations

import math

from ..analysis.search_settings import SearchSettings

__all__ = ["MANOEUVRES", "THRESHOLD_SEARCH", "THRESHOLD_SETTINGS", "HANDLING_SETTINGS", "handling", "run_metric", "state_metrics",
           "static_stability", "thresholds", "top_speed", "vehicle_sheet"]

MANOEUVRES = ("dlc", "slc", "fishhook")
"""The manoeuvres whose thresholds the dossier finds (``trikedyn manoeuvres``)."""

THRESHOLD_SEARCH = SearchSettings(criterion="both")
"""The threshold search: ``trikedyn threshold``'s defaults, both criteria at once (the course threshold is
the command's default answer, the lift-off threshold that of ``--criterion lift-off``)."""
THRESHOLD_SETTINGS = {k: v for k, v in THRESHOLD_SEARCH.to_dict().items() if k not in ("step_kmh", "method")}
""":data:`THRESHOLD_SEARCH` as the dossier records it: range and resolution [km/h], criterion, speed control,
speed band [%, km/h]."""

HANDLING_SETTINGS = {"radius_m": 20.0, "start_speed_kmh": 15.0}
"""ISO 4138 circle: ``trikedyn handling``'s defaults."""


def _rules():
    return THRESHOLD_SEARCH.judging()


def vehicle_sheet(pset, payload_kg: float) -> dict:
    """The vehicle: description, provenance of every assumed value, audit findings, mass and CG with and
    without payload, and the vibration modes at rest.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle as given.
    payload_kg : float
        The freight aboard in the laden state [kg] (at the vehicle's freight site).

    Returns
    -------
    dict
        ``name``, ``origin``, ``description``, ``source``, ``mass`` (per state: ``mass_kg``, ``cg_m`` [m]),
        ``assumed`` (dotted path -> reason), ``findings`` (as ``trikedyn vehicle check --json``), ``modes``
        (as ``trikedyn modes --json``).
    """
    from ..model.linear import modes
    from ..model.statics import static_equilibrium
    from ..model.vehicle import build_model
    from ..params import audit, mass_properties, with_freight

    mass = {}
    for state, kg in (("as_given", 0.0), ("laden", payload_kg)):
        mp = mass_properties(with_freight(pset, kg).params)
        mass[state] = {"payload_kg": kg, "mass_kg": float(mp.mass_kg), "cg_m": [float(v) for v in mp.cg_m]}
    model = build_model(pset)
    found = modes(model, static_equilibrium(model), speed_mps=0.0)
    return {"name": pset.name, "origin": pset.origin, "description": pset.params.description,
            "source": pset.params.source, "layout": "tadpole" if sum(w.steered for w in pset.params.wheels) == 2
            else "delta", "mass": mass, "assumed": dict(pset.assumed()),
            "findings": [f.to_dict() for f in audit(pset)],
            "modes": [{"name": m.name, "frequency_hz": float(m.frequency_hz), "damping_ratio": float(m.damping_ratio)}
                      for m in found]}


def static_stability(pset):
    """Rigid tip-over per edge of the support triangle and the compliant tilt-table test on both sides.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle, with its payload.

    Returns
    -------
    data : dict
        ``tip_over`` (per edge, as the audit gives it: ``acceleration_g`` [1]), ``tilt`` (as ``trikedyn tilt
        --json``: angles [deg], loads [N]).
    figure : matplotlib.figure.Figure
        Wheel loads [N] against table angle [deg] (``trikedyn tilt --plot``).
    """
    from ..analysis.tilt import tilt_table
    from ..params import tip_over_thresholds

    tilt = tilt_table(pset, side="both")
    edges = [{k: (float(v) if isinstance(v, float) else v) for k, v in e.items()} for e in tip_over_thresholds(pset.params)]
    return {"tip_over": edges, "tilt": tilt.to_dict()}, tilt.plot()


def handling(pset):
    """ISO 4138 steady-state circular driving, as ``trikedyn handling`` does it (:data:`HANDLING_SETTINGS`).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle, with its payload.

    Returns
    -------
    data : dict
        As ``trikedyn handling --json``: gradients [deg/g], limit behaviour, the diagram.
    figure : matplotlib.figure.Figure
        The handling diagram.
    """
    from ..analysis.handling_tests import steady_state_test

    test = steady_state_test(pset, **HANDLING_SETTINGS)
    return test.to_dict(), test.plot()


def top_speed(pset) -> dict:
    """Straight-line performance on the flat, as ``trikedyn performance`` (top speed [km/h] and its limit).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle, with its payload.

    Returns
    -------
    dict
        As ``trikedyn performance --json``.
    """
    from ..analysis.performance import performance

    return performance(pset, grade_percent=0.0).to_dict()


def thresholds(pset, manoeuvres=MANOEUVRES, say=None) -> dict:
    """The threshold velocity in each manoeuvre under both criteria (:data:`THRESHOLD_SETTINGS`).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle, with its payload.
    manoeuvres : sequence of str
        Registered manoeuvres.
    say : callable, optional
        ``say(text)``: a progress line.

    Returns
    -------
    dict
        Manoeuvre -> ``course_kmh`` and ``lift_off_kmh`` (as ``trikedyn threshold [--criterion lift-off]``
        prints them) [km/h], ``limit``, ``detail``, ``first_failure_kmh`` [km/h] and the lift-off ``limiting_wheel``.
    """
    from ..analysis.threshold import threshold_velocity

    out = {}
    for name in manoeuvres:
        if say:
            say(f"threshold: {name}")
        r = threshold_velocity(pset, name, options={}, **THRESHOLD_SEARCH.threshold_kwargs())
        lift = r.lift_off
        out[name] = {"course_kmh": r.course_speed_kmh, "lift_off_kmh": r.lift_off_speed_kmh, "limit": r.limit,
                     "detail": r.detail, "first_failure_kmh": r.first_failure_kmh,
                     "lift_off_limit": None if lift is None else lift.limit,
                     "lift_off_detail": None if lift is None else lift.detail,
                     "limiting_wheel": None if lift is None else lift.limiting_wheel, "n_runs": len(r.runs)}
    return out


def _finite(value):
    return float(value) if value is not None and math.isfinite(float(value)) else None


def state_metrics(state: dict) -> dict:
    """The named numbers of one state (as given, or laden) that requirements bound.

    Parameters
    ----------
    state : dict
        ``mass`` (``mass_kg``, ``cg_m``), ``static``, ``handling``, ``performance`` and ``thresholds`` of that
        state.

    Returns
    -------
    dict
        Metric name (:data:`~trikedyn.assess.requirements.METRICS`) -> value in its unit, None when not found.
    """
    tilt, hand, perf = state["static"]["tilt"], state["handling"], state["performance"]
    lateral = [e["acceleration_g"] for e in state["static"]["tip_over"] if e["lateral"]]
    out = {"mass_kg": state["mass"]["mass_kg"], "cg_height_m": state["mass"]["cg_m"][2],
           "tilt_angle_deg": _finite(tilt["tilt_angle_deg"]), "rigid_tilt_angle_deg": _finite(tilt["rigid_tilt_angle_deg"]),
           "static_stability_g": _finite(min(lateral)) if lateral else None,
           "understeer_gradient_deg_per_g": _finite(hand.get("understeer_gradient_deg_per_g")),
           "max_lateral_acceleration_mps2": _finite(hand.get("max_lateral_acceleration_mps2")),
           "top_speed_kmh": _finite(perf.get("top_speed_kmh"))}
    course = []
    for name, t in state["thresholds"].items():
        out[f"{name}_threshold_kmh"] = _finite(t["course_kmh"])
        out[f"{name}_lift_off_kmh"] = _finite(t["lift_off_kmh"])
        course.append(t["course_kmh"])
    out["min_threshold_kmh"] = None if not course or None in course else min(course)
    return out


def run_metric(pset, manoeuvre: str, speed_kmh: float) -> dict:
    """One run at a target speed and its summary over the judged window, as ``trikedyn simulate --json``.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle, with its payload.
    manoeuvre : str
        A registered manoeuvre.
    speed_kmh : float
        Target speed [km/h].

    Returns
    -------
    dict
        The run's summary (``max_abs_ri`` [1], ``verdict``, ...); ``failure`` when the run could not end.
    """
    from ..analysis.metrics import summary
    from ..simulate.closed_loop import run

    result = run(pset, manoeuvre, speed_kmh=speed_kmh, duration_s=None, speed_control="driver")
    data = summary(result, _rules()) | {"manoeuvre": manoeuvre, "speed_kmh": speed_kmh}
    if not result.success:
        data["failure"] = result.message
    return data
