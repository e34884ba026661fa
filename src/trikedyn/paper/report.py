"""The report of ``trikedyn reproduce``: the paper's statements grouped by topic, each with its verdict,
the equations it rests on (MathML), its figures, an animation of each lane change and its tables.

:func:`start_animations` draws a GIF of each lane change (``animation_slc.gif``, ``animation_dlc.gif``) in
another process; :func:`write_reproduction_report` writes ``report.html`` into the reproduction's folder,
beside the PNG figures and the GIFs it links. The page itself is rendered by :mod:`trikedyn.paper.html`
from the templates in ``paper/templates/``.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

__all__ = ["ANIMATION", "SECTIONS", "Animations", "animate_lane_change", "lane_change_scene", "report_sections",
           "start_animations", "write_reproduction_report"]

TITLE = "trikedyn reproduction of the electric delta trike paper"
INTRO = ("Each statement of the paper is set beside what trikedyn finds on the built-in reference vehicle "
         "(reference-etrike), with the numbers; the sections group the statements by topic.")

ANIMATION = {"every_s": 2.0, "fps": 2, "dpi": 72, "margin_s": 1.0}
"""The lane changes' animations: simulated time between frames [s], frames per second, resolution of the
6 x 4 in frame, and the time shown before and after the judged window [s]. Few, small frames (about 0.1 s
of drawing each), drawn in another process while ``reproduce`` goes on."""

SECTIONS = (
    {"title": "Suspension stiffness and damping (Table 1, Eqs. 1-4)", "statements": ("eq4", "eq3"),
     "equations": ("eq1", "eq2", "eq3", "eq4"), "tables": (("table1_equations.csv", None),)},
    {"title": "Identification from a 10 Hz speed-bump record (Fig. 2)",
     "statements": ("sampling", "tyre", "model_bump"),
     "figures": ("fig2_identification_reference-etrike-eq4_front.png",
                 "fig2_identification_reference-etrike-eq4_rear.png",
                 "fig2_model_bump_front.png", "fig2_model_bump_rear.png"),
     "tables": (("table1_identified.csv", ("vehicle", "suspension", "body_mode_frequency_hz",
                                           "body_mode_damping_ratio", "identified_frequency_hz",
                                           "identified_damping_ratio", "model_stiffness_N_per_m",
                                           "identified_stiffness_N_per_m", "stiffness_error_pct",
                                           "model_damping_Ns_per_m", "identified_damping_Ns_per_m",
                                           "damping_error_pct")),
                ("table1_model_bump.csv", ("vehicle", "suspension", "identified_frequency_hz",
                                           "identified_damping_ratio", "model_stiffness_N_per_m",
                                           "identified_stiffness_N_per_m", "stiffness_error_pct",
                                           "model_damping_Ns_per_m", "identified_damping_Ns_per_m",
                                           "damping_error_pct")))},
    {"title": "Centre of gravity (Table 3)", "statements": ("table3", "cg_offset"),
     "tables": (("table3.csv", None),)},
    {"title": "Lane changes (Figs. 7-8)", "statements": ("lane_changes",),
     "animations": ("slc", "dlc"), "figures": ("fig7_slc.png", "fig8_dlc.png"),
     "tables": (("manoeuvres.csv", ("manoeuvre", "verdict", "min_speed_kmh", "max_speed_kmh",
                                    "max_lateral_acceleration_mps2", "max_yaw_rate_radps", "max_abs_roll_deg",
                                    "max_abs_ri", "min_wheel_load_N", "max_path_error_m", "cone_strikes",
                                    "wheel_lifted")),)},
    {"title": "Rollover index (Fig. 9, Eq. 5)", "statements": ("rollover",), "equations": ("eq5",),
     "figures": ("fig9_rollover_index.png",)},
    {"title": "Threshold velocity (Fig. 10)", "statements": ("freight", "stiffness", "damping", "speed_control"),
     "figures": ("fig10_threshold_study.png",),
     "tables": (("thresholds_by_control.csv", None),),
     "folded": (("fig10_threshold_study.csv", ("manoeuvre", "freight_kg", "stiffness_scale", "damping_scale",
                                               "threshold_speed_kmh", "driven_min_kmh", "driven_max_kmh", "limit",
                                               "limiting_wheel")),)},
)
"""The report's sections: the statements (by id) they hold, and the files they show."""

_PAPER_TEXT = {  # the statements whose own text writes an equation in ASCII: the section shows it in MathML
    "eq4": "Eq. 4 gives Table 1's damping coefficients from its damping ratios, stiffnesses and sprung masses",
    "eq3": "Eq. 3 gives the stiffness from the natural frequency, with M_s from the loads on each suspension",
}

_CAPTIONS = {
    "table1_equations.csv": "Table 1 and what Eqs. 3-4 give from its own numbers (table1_equations.csv)",
    "table1_identified.csv": "Quarter car: emulated 10 Hz records identified, beside the model's suspension "
                             "and body mode (table1_identified.csv)",
    "table1_model_bump.csv": "Multibody model: its seat sensor at 10 Hz identified, beside its suspension "
                             "(table1_model_bump.csv)",
    "table3.csv": "Centre of gravity against freight, the paper's axes (table3.csv)",
    "manoeuvres.csv": "The two lane changes (manoeuvres.csv)",
    "fig10_threshold_study.csv": "Every scenario of the study, from fig10_threshold_study.csv",
    "thresholds_by_control.csv": "The thresholds with the speed imposed (ideal) and with the trike's own drive "
                                 "(driver), under the paper's criterion (lift-off) and ISO 3888-1's (course) "
                                 "(thresholds_by_control.csv)",
    "fig2_identification_reference-etrike-eq4_front.png": "Quarter car, front: emulated 10 Hz record and its "
                                                          "spectrum (cf. Fig. 2c-d)",
    "fig2_identification_reference-etrike-eq4_rear.png": "Quarter car, rear: emulated 10 Hz record and its spectrum",
    "fig2_model_bump_front.png": "Multibody model, cushion under the front wheel: seat sensor at 10 Hz",
    "fig2_model_bump_rear.png": "Multibody model, cushions under the rear wheels: seat sensor at 10 Hz",
    "fig7_slc.png": "Single lane change: speed, lateral acceleration, yaw rate (cf. Fig. 7)",
    "fig8_dlc.png": "Double lane change (cf. Fig. 8)",
    "fig9_rollover_index.png": "Rollover index in both lane changes, and its static value (cf. Fig. 9)",
    "fig10_threshold_study.png": "Threshold velocity against freight, by stiffness and by damping (cf. Fig. 10)",
}
_ANIMATION_CAPTIONS = {"slc": "Single lane change (ISO 14791), seen from above",
                       "dlc": "Double lane change (ISO 3888-1), seen from above"}


def lane_change_scene(result):
    """The scene of a lane change for its animation: the judged window and a second either side.

    Parameters
    ----------
    result : Result
        The lane change run.

    Returns
    -------
    Scene
        The scene, cut to the window and a second either side.
    """
    from ..report.scene import Scene

    scene = Scene.from_result(result)
    t = np.asarray(scene.time_s)
    keep = np.ones(t.size, dtype=bool)
    if "judged" in result.channels:
        inside = np.nonzero(np.asarray(result["judged"]) > 0.5)[0]
        if inside.size:
            keep = (t >= t[inside[0]] - ANIMATION["margin_s"]) & (t <= t[inside[-1]] + ANIMATION["margin_s"])
    cut = {}  # every time series of the scene (a field that holds one value per sample)
    for item in dataclasses.fields(scene):
        value = getattr(scene, item.name)
        if item.name not in ("cone_hit_s", "path_xy", "cones_xy") and isinstance(value, np.ndarray) \
                and value.shape[:1] == t.shape:
            cut[item.name] = value[keep]
    cut["loads_N"] = {wheel: np.asarray(load)[keep] for wheel, load in scene.loads_N.items()}
    return dataclasses.replace(scene, **cut)


def _animate(scene, path: Path) -> Path:
    from ..report.animation import animate

    animate(scene, path, view="plan", fps=ANIMATION["fps"], every_s=ANIMATION["every_s"], dpi=ANIMATION["dpi"])
    return Path(path)


def animate_lane_change(result, path: Path) -> Path:
    """A small GIF of a lane change seen from above (:data:`ANIMATION`): the judged window and a second
    either side.

    Parameters
    ----------
    result : Result
        The lane change run.
    path : Path
        The GIF file.

    Returns
    -------
    Path
        The file written.
    """
    return _animate(lane_change_scene(result), Path(path))


def _key(label: str) -> str:
    return "slc" if label.startswith("single") else "dlc"


class Animations:
    """The GIFs of the lane changes, drawn in another process (:func:`start_animations`)."""

    def __init__(self, out: Path, scenes: dict):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        self.paths = {key: Path(out) / f"animation_{key}.gif" for key in scenes}
        self._scenes, self._futures = scenes, {}
        try:
            pool = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn"))
            self._futures = {key: pool.submit(_animate, scene, self.paths[key]) for key, scene in scenes.items()}
            pool.shutdown(wait=False)
        except (OSError, RuntimeError):  # a platform or sandbox that starts no process: wait() draws them here
            self._futures = {}

    def wait(self) -> dict[str, Path]:
        """``{"slc": path, "dlc": path}`` once every GIF is written; one that the other process could not
        draw (it could not start, or died) is drawn here.

        Returns
        -------
        dict of str to Path
            The GIF of each lane change.
        """
        from concurrent.futures.process import BrokenProcessPool

        for key, scene in self._scenes.items():
            future = self._futures.get(key)
            try:
                if future is None:
                    raise BrokenProcessPool("not started")
                future.result()
            except BrokenProcessPool:
                _animate(scene, self.paths[key])
        return dict(self.paths)


def start_animations(out: Path, runs: dict) -> Animations:
    """Start drawing the GIF of each lane change of ``runs`` (label -> Result) into ``out``, in one other
    process (the drawing is matplotlib's, single-threaded: on a machine with a free core it costs no time).
    :func:`write_reproduction_report` waits for them (:meth:`Animations.wait`).

    Parameters
    ----------
    out : Path
        The output folder.
    runs : dict
        Label -> Result.

    Returns
    -------
    Animations
        The drawing in progress.
    """
    return Animations(out, {_key(label): lane_change_scene(result) for label, result in runs.items()})


def _table(path: Path, columns):
    """A CSV file's table cut to ``columns`` (a DataFrame), and its warnings as notes (a long text column is
    hard to read in a table, and would widen it)."""
    import pandas as pd  # here: the process that draws the animations does without it

    full = pd.read_csv(path)
    notes = []
    if "warnings" in full.columns:
        texts = full["warnings"].map(lambda v: "" if pd.isna(v) else str(v).strip())  # all-empty reads as float
        for _, row in full[texts != ""].iterrows():
            who = ", ".join(str(row[c]) for c in ("vehicle", "suspension") if c in full.columns)
            notes.append(f"{path.name}, {who}: {row['warnings']}")
    frame = full[[c for c in columns if c in full.columns]] if columns else full
    return frame, notes


def _pretty(text: str) -> str:
    """Subscripts and arrows the statements write in ASCII, as a reader expects them (M_s, f_n, ->)."""
    return text.replace("M_s", "M\u209b").replace("f_n", "f\u2099").replace(" -> ", " \u2192 ")


def report_sections(out: Path, statements: list[dict], animations: dict[str, Path] | None = None) -> list[dict]:
    """The report's sections from a reproduction's statements and the files in its folder ``out``.

    A section whose statements are all missing (the study's, after ``--no-study``) is left out; a file that
    was not written is left out of its section.

    Parameters
    ----------
    out : Path
        The output folder.
    statements : list of dict
        The reproduction's statements.
    animations : dict of str to Path, optional
        The GIFs.

    Returns
    -------
    list of dict
        The sections.
    """
    out = Path(out)
    by_id = {s["id"]: s for s in statements}
    animations = animations or {}
    sections = []
    for spec in SECTIONS:
        found = [by_id[i] for i in spec["statements"] if i in by_id]
        if not found:
            continue
        section = {
            "title": spec["title"],
            "statements": [{"paper": _pretty(_PAPER_TEXT.get(s["id"], s["paper"])), "verdict": s["verdict"],
                            "evidence": _pretty(s["evidence"])} for s in found],
            "equations": list(spec.get("equations", ())),
            "figures": [(out / f, _CAPTIONS.get(f, f)) for f in spec.get("figures", ()) if (out / f).is_file()],
            "animations": [(animations[k], _ANIMATION_CAPTIONS[k]) for k in spec.get("animations", ())
                           if k in animations],
            "tables": [],
            "folded": [],
            "notes": [],
        }
        for key in ("tables", "folded"):
            for name, columns in spec.get(key, ()):
                if (out / name).is_file():
                    frame, notes = _table(out / name, columns)
                    section[key].append((frame, _CAPTIONS.get(name, name)))
                    section["notes"] += notes
        sections.append(section)
    return sections


def write_reproduction_report(out: Path, summary: dict, animations: dict | None = None) -> Path:
    """Write ``report.html`` of a reproduction into ``out``, where its figures and tables are.

    ``animations`` maps ``"slc"``/``"dlc"`` to the GIF of that lane change beside the report, or is the
    :class:`Animations` being drawn (:func:`start_animations`), which the report waits for.

    Parameters
    ----------
    out : Path
        The output folder.
    summary : dict
        The reproduction's summary.
    animations : dict or Animations, optional
        The GIFs, or their drawing.

    Returns
    -------
    Path
        ``report.html``.
    """
    from .html import write_report

    out = Path(out)
    ready = animations.wait() if isinstance(animations, Animations) else dict(animations or {})
    sections = report_sections(out, summary["statements"], ready)
    return write_report(out, TITLE, sections, summary=INTRO, vehicle="reference-etrike")
