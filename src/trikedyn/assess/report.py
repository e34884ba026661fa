"""The dossier as one HTML page (``report.html``), from the paper report's machinery: its Jinja2 macros and
stylesheet (``paper/templates``), its tables (headers with units, numbers as :func:`~trikedyn.paper.html.
format_value` writes them) and its images (linked beside the page); the page's layout is
``assess/templates/dossier.html.j2``. Autoescaped, no script, no external URL.
"""

from __future__ import annotations

import datetime as _dt
from pathlib import Path

import pandas as pd

__all__ = ["TITLE", "dossier_sections", "write_dossier"]

TITLE = "Stability dossier"

_STATES = (("as_given", "as given"), ("laden", "laden"))


def _states(data: dict) -> list[tuple[str, str, dict]]:
    """(key, label, state) of each distinct state: one when there is no payload."""
    if data["payload_kg"] <= 0:
        return [("as_given", "as given", data["states"]["as_given"])]
    return [(k, f"{label} ({data['states'][k]['payload_kg']:g} kg)", data["states"][k]) for k, label in _STATES]


def _frame(rows: list[dict], columns=None) -> pd.DataFrame:
    frame = pd.DataFrame(rows)
    return frame[[c for c in columns if c in frame.columns]] if columns is not None and len(frame) else frame


def _vehicle(data: dict) -> dict:
    v = data["vehicle"]
    mass = [{"state": label, "payload_kg": s["mass"]["payload_kg"], "mass_kg": s["mass"]["mass_kg"],
             "cg_x_mm": 1000 * s["mass"]["cg_m"][0], "cg_y_mm": 1000 * s["mass"]["cg_m"][1],
             "cg_z_mm": 1000 * s["mass"]["cg_m"][2]} for _, label, s in _states(data)]
    findings = [{"level": f["level"], "topic": f["topic"], "finding": f["message"]} for f in v["findings"]]
    assumed = [{"value": k, "why assumed": text} for k, text in v["assumed"].items()]
    return {"title": "The vehicle",
            "paragraphs": [f"{v['name']} ({v['layout']}): {v['description']}", f"Source: {v['source']}",
                           f"Parameters from {v['origin']}; {len(v['assumed'])} values are assumed (not measured "
                           "in the source), each with its reason below."],
            "tables": [(_frame(mass), "Mass and centre of gravity (vehicle axes; trikedyn cg payload)"),
                       (_frame(v["modes"]), "Vibration modes at rest (trikedyn modes)")],
            "folded": [(_frame(findings), "The audit's findings (trikedyn vehicle check)"),
                       (_frame(assumed), "Assumed values and why (trikedyn vehicle show)")]}


def _static(data: dict, out: Path) -> dict:
    sides, edges, figures = [], [], []
    for _key, label, s in _states(data):
        for side in s["static"]["tilt"]["sides"].values():
            sides.append({"state": label, "side": side["side"], "tilt_angle_deg": side["tilt_angle_deg"],
                          "first_lifting_wheel": side["first_lifting_wheel"], "body_roll_deg": side["body_roll_deg"],
                          "rigid_tilt_angle_deg": side["rigid_tilt_angle_deg"], "tip_axis": side["tip_axis"]})
        for e in s["static"]["tip_over"]:
            edges.append({"state": label, "edge": e["edge"], "tips_toward": e["tips_toward"],
                          "lateral": e["lateral"], "tipping_acceleration_g": e["acceleration_g"]})
        figures.append((out / s["figures"]["tilt"], f"Tilt table, {label}: wheel loads against table angle "
                                                    "(trikedyn tilt --plot)"))
    return {"title": "Static stability",
            "paragraphs": ["The tilt-table angle is found on the compliant model (suspension and tyres deflect); "
                           "the rigid angle is the closed form about the same edge, tan(angle) = d/h."],
            "tables": [(_frame(sides), "Tilt table per side (trikedyn tilt)"),
                       (_frame(edges), "Rigid tip-over per edge of the support triangle: the acceleration that "
                                       "tips the vehicle, in g (trikedyn vehicle check)")],
            "figures": figures}


def _handling(data: dict, out: Path) -> dict:
    rows, figures = [], []
    for _, label, s in _states(data):
        h = s["handling"]
        rows.append({"state": label, "understeer_gradient_deg_per_g": h["understeer_gradient_deg_per_g"],
                     "limit_behaviour": h["limit_behaviour"], "limit_gradient_deg_per_g": h["limit_gradient_deg_per_g"],
                     "neutral_steer_lateral_acceleration_mps2": h["neutral_steer_lateral_acceleration_mps2"],
                     "max_lateral_acceleration_mps2": h["max_lateral_acceleration_mps2"],
                     "roll_gradient_deg_per_g": h["roll_gradient_deg_per_g"], "limit": h["limit"]})
        figures.append((out / s["figures"]["handling"], f"Handling diagram, {label} (trikedyn handling --plot)"))
    steps, sweeps, speeds = [], [], set()
    for _, label, s in _states(data):
        step, sweep = s["step"], s["sweep"]
        speeds.add(step["speed_kmh"])
        for key, words in (("yaw_rate", "yaw rate"), ("lateral_acceleration", "lateral acceleration")):
            f = (step["figures"] or {}).get(key) or {}
            steps.append({"state": label, "speed_kmh": step["speed_kmh"], "response": words,
                          "steady_state_gain_per_rad": f.get("steady_state_gain"),
                          "response_time_s": f.get("response_time_s"), "rise_time_s": f.get("rise_time_s"),
                          "peak_response_time_s": f.get("peak_response_time_s"),
                          "overshoot_percent": None if f.get("overshoot") is None else 100 * f["overshoot"],
                          "failure": step["failure"]})
            g = (sweep["summary"] or {}).get(key) or {}
            sweeps.append({"state": label, "speed_kmh": sweep["speed_kmh"], "response": words,
                           "low_frequency_hz": g.get("low_frequency_hz"), "gain_per_rad": g.get("low_frequency_gain"),
                           "peak_gain_ratio": g.get("peak_gain_ratio"), "minus_3db_hz": g.get("minus_3db_hz"),
                           "gain_1hz_per_rad": g.get("gain_1hz"), "phase_1hz_deg": g.get("phase_1hz_deg"),
                           "failure": sweep["failure"]})
        figures.append((out / s["figures"]["step"], f"Step steer, {label}: yaw rate and lateral acceleration "
                        f"against time at {step['speed_kmh']:g} km/h (trikedyn simulate --manoeuvre step)"))
        figures.append((out / s["figures"]["sweep"], f"Frequency response, {label}: gain and phase against "
                        f"frequency at {sweep['speed_kmh']:g} km/h (trikedyn simulate --manoeuvre sweep)"))
    at = " and ".join(f"{v:g}" for v in sorted(speeds))
    first = _states(data)[0][2]
    step_o, sweep_o = first["step"]["options"], first["sweep"]["options"]
    return {"title": "Handling", "paragraphs": [
        "ISO 4138 steady-state circular driving on a 20 m circle, the speed raised from 15 km/h: the understeer "
        "gradient of the linear range and the behaviour at the limit.",
        f"ISO 7401 transient response at {at} km/h (30 km/h, or 80 % of the DLC course threshold when that is "
        f"lower), the driver holding the speed: a {step_o['steer_deg']:g} deg step of the steering (times from "
        "50 % steer to 90 % of the steady response and to the peak, overshoot, steady gain per rad of road-wheel "
        f"steer) and a {sweep_o['amplitude_deg']:g} deg sine sweep from {sweep_o['f_start_hz']:g} to "
        f"{sweep_o['f_end_hz']:g} Hz (gain at the lowest frequency, the frequency where it has fallen by 3 dB, "
        "gain and phase at 1 Hz; empty where the band does not reach them)."],
        "tables": [(_frame(rows), "Handling (trikedyn handling)"),
                   (_frame(steps), "Step steer response (trikedyn simulate --manoeuvre step --json, figures)"),
                   (_frame(sweeps), "Frequency response (trikedyn simulate --manoeuvre sweep --json, figures)")],
        "figures": figures}


def _dynamic(data: dict, out: Path) -> dict:
    rows = []
    for _, label, s in _states(data):
        for name, t in s["thresholds"].items():
            rows.append({"state": label, "manoeuvre": name, "course_threshold_kmh": t["course_kmh"],
                         "lift_off_threshold_kmh": t["lift_off_kmh"], "limit": t["limit"], "what_fails": t["detail"]})
    top = [{"state": label, "top_speed_kmh": s["performance"]["top_speed_kmh"], "limit": s["performance"]["limit"],
            "detail": s["performance"]["detail"]} for _, label, s in _states(data)]
    section = {"title": "Dynamic stability", "paragraphs": [
        "Threshold velocity: the highest target speed at which the run passes, under ISO 3888-1's course "
        "criterion (every wheel down, no cone struck, path kept, speed held) and under the paper's lift-off "
        "criterion (no wheel lifts); the trike's own drive holds the speed, so a search stops at its top speed."],
        "tables": [(_frame(rows), "Threshold velocities (trikedyn threshold --criterion both)"),
                   (_frame(top), "Top speed on the flat (trikedyn performance)")], "figures": [], "animations": [],
        "notes": []}
    if data.get("loading_chart"):
        section["figures"].append((out / "loading-chart.png", "Loading chart: safe speed (DLC threshold less "
                                   f"{data['loading_chart']['margin_kmh']:g} km/h) against freight mass and position "
                                   "(trikedyn loading-chart)"))
    else:
        section["notes"].append("The loading chart was left out (--quick).")
    if data.get("animation"):
        a = data["animation"]
        section["animations"].append((out / a["file"], f"The most critical run: {a['manoeuvre']} at "
                                      f"{a['speed_kmh']:g} km/h, {a['payload_kg']:g} kg payload, seen from above"))
    else:
        section["notes"].append("The animation of the most critical run was left out (--quick).")
    return section


def _assumptions(data: dict, out: Path) -> dict:
    s = data.get("sensitivity")
    section = {"title": "Which assumptions matter", "lists": [("Measure first", data["guidelines"]["measure"])]}
    if s:
        top = [{"rank": k, "parameter": r["parameter"], "mu_star_kmh": r["mu_star"], "sigma_kmh": r["sigma"]}
               for k, r in enumerate(s["indices"][:10], 1)]
        section["tables"] = [(_frame(top), f"Morris screening of the DLC threshold ({s['samples']} trajectories, "
                                           f"{s['n_runs']} runs; trikedyn sensitivity)")]
        section["figures"] = [(out / "sensitivity.png", "Sensitivity of the DLC threshold (trikedyn sensitivity)")]
    return section


def _guidelines(data: dict) -> dict:
    g = data["guidelines"]
    limit_cols = ["payload_kg", "dlc_threshold_kmh", "slc_threshold_kmh", "fishhook_threshold_kmh", "limiting",
                  "speed_limit_kmh"]
    changes = [{k: c.get(k) for k in ("change", "knob", "from", "to", "new_tilt_angle_deg", "tilt_gain_deg",
                                      "new_dlc_threshold_kmh", "dlc_gain_kmh")} for c in data["design_changes"]]
    return {"title": "Guidelines",
            "lists": [("Speed limit to print on the vehicle", g["speed"]), ("Where to put freight and heavy "
                      "components", g["freight"]), ("What to change first", g["changes"])],
            "tables": [(_frame(data["speed_limits"], limit_cols), "Speed limit per payload: the lowest course "
                        "threshold less the margin"),
                       (_frame(changes), "Design changes: tilt angle and DLC threshold on the same course")],
            "folded": [(_frame(data["freight_positions"]), f"Rigid static stability with {data['freight_mass_kg']:g} kg "
                        "of freight per position")]}


def _requirements_table(data: dict) -> pd.DataFrame | None:
    r = data.get("requirements")
    if not r:
        return None
    return _frame([{"requirement": j["id"], "verdict": j["verdict"], "metric": j["metric"], "value": j["value"],
                    "bound": j["bound"], "margin": j["margin"], "unit": j["unit"], "judged": j["detail"],
                    "note": j["note"]} for j in r["judgements"]])


def dossier_sections(data: dict, out: Path) -> list[dict]:
    """The report's sections (title, paragraphs, lists, tables, figures ...) from the dossier's data.

    Parameters
    ----------
    data : dict
        :func:`trikedyn.assess.dossier.assess`.
    out : Path
        The folder the figures are in.

    Returns
    -------
    list of dict
        The sections in order.
    """
    out = Path(out)
    sections = [_vehicle(data), _static(data, out), _handling(data, out), _dynamic(data, out),
                _assumptions(data, out), _guidelines(data)]
    r = data.get("requirements")
    if r:
        sections.append({"title": "Requirements", "paragraphs": [
            f"{r['title'] or r['name']}: {len(r['judgements'])} items from {r['name']}.", f"Source: {r['source']}"
            if r["source"] else "No source given."], "tables": [(_requirements_table(data), "Each requirement, "
                                                                "its value, bound and margin")]})
    return sections


def _key_numbers(data: dict) -> pd.DataFrame:
    rows = []
    for _, label, s in _states(data):
        m = s["metrics"]
        rows.append({"state": label, "mass_kg": m["mass_kg"], "tilt_angle_deg": m["tilt_angle_deg"],
                     "understeer_gradient_deg_per_g": m["understeer_gradient_deg_per_g"],
                     "top_speed_kmh": m["top_speed_kmh"], "dlc_threshold_kmh": m["dlc_threshold_kmh"],
                     "slc_threshold_kmh": m["slc_threshold_kmh"], "fishhook_threshold_kmh": m["fishhook_threshold_kmh"]})
    return _frame(rows)


def _environment():
    import jinja2

    return jinja2.Environment(loader=jinja2.ChoiceLoader([jinja2.PackageLoader("trikedyn.assess", "templates"),
                                                          jinja2.PackageLoader("trikedyn.paper", "templates")]),
                              autoescape=True, undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True,
                              keep_trailing_newline=True)


def write_dossier(out: str | Path, data: dict, date: _dt.date | str | None = None) -> Path:
    """Write ``out/report.html``, its figures linked beside it.

    Parameters
    ----------
    out : str or Path
        The dossier's folder, where its figures are.
    data : dict
        :func:`trikedyn.assess.dossier.assess`.
    date : datetime.date or str, optional
        The date in the header; today by default.

    Returns
    -------
    Path
        ``report.html``.
    """
    from .._files import atomic_write
    from .._version import __version__
    from ..paper.cells import _table
    from ..paper.html import _image_source

    out = Path(out)
    taken: dict = {}
    prepared = []
    for i, s in enumerate(dossier_sections(data, out), start=1):
        where = f"section {i} ({s['title']})"
        prepared.append({"title": s["title"], "anchor": f"section-{i}", "paragraphs": s.get("paragraphs", []),
                         "lists": s.get("lists", []), "notes": s.get("notes", []),
                         "tables": [_table(f, cap, where) for f, cap in s.get("tables", []) if len(f)],
                         "folded": [_table(f, cap, where) for f, cap in s.get("folded", []) if len(f)],
                         "figures": [(_image_source(Path(p), out, taken, where), cap, Path(p).name)
                                     for p, cap in s.get("figures", [])],
                         "animations": [(_image_source(Path(p), out, taken, where), cap, Path(p).name)
                                        for p, cap in s.get("animations", [])]})
    r = data.get("requirements")
    verdict = None
    if r:
        failed = r["failed"]
        verdict = {"badge": "ok" if not failed else "bad", "text": "PASS" if not failed else "FAIL",
                   "detail": (f"all {len(r['judgements'])} requirements of {r['name']} are met" if not failed else
                              f"{len(failed)} of {len(r['judgements'])} requirements of {r['name']} fail: "
                              + ", ".join(failed))}
    req = _requirements_table(data)
    when = date if date is not None else _dt.date.today()
    context = {"title": f"{TITLE}: {data['vehicle']['name']}", "vehicle": data["vehicle"]["name"],
               "payload": f"{data['payload_kg']:g} kg", "mode": "quick (no loading chart, sensitivity or animation)"
               if data["quick"] else "full", "date": when.isoformat() if isinstance(when, _dt.date) else str(when),
               "version": __version__, "sections": prepared, "verdict": verdict,
               "requirements": None if req is None else _table(req, "Requirements: PASS or FAIL with the margin "
                                                               "(in the metric's unit)", "summary"),
               "key_numbers": _table(_key_numbers(data), "Key numbers", "summary")}
    document = _environment().get_template("dossier.html.j2").render(context)
    return atomic_write(out / "report.html", lambda fh: fh.write(document), binary=False)
