"""The stability dossier of one trike, computed piece by piece into a folder that keeps each piece as it is done.

:func:`assess` runs the pieces of :mod:`trikedyn.assess.runs`, :mod:`trikedyn.assess.transient` (step steer and
frequency response) and :mod:`trikedyn.assess.studies` for the vehicle as given and with its payload, derives the guidelines (:mod:`trikedyn.assess.guidelines`) and judges the
requirements (:mod:`trikedyn.assess.requirements`). Each piece is written to ``OUT/assess-parts/NAME.json``
(its figure beside the report) as soon as it is done; with ``resume`` a piece already there is read, not
computed again, so an interrupted dossier goes on where it stopped.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

__all__ = ["FILES", "PARTS_DIR", "assess"]

PARTS_DIR = "assess-parts"
"""The folder of the pieces, inside the dossier's folder."""

FILES = {"json": "assess.json", "report": "report.html", "plan": "assess-plan.json"}
"""The dossier's own files in its folder."""

MAX_PART_BYTES = 64 << 20


class _Parts:
    """Pieces computed or read back (``resume``), each a JSON file; figures saved beside the report."""

    def __init__(self, out: Path, resume: bool, say: Callable[[str], None]):
        from .._files import ensure_folder

        self.out, self.resume, self.say = Path(out), resume, say
        self.folder = ensure_folder(self.out / PARTS_DIR)

    def get(self, name: str, compute: Callable, figure: str | None = None):
        """The piece ``name``: read back from its JSON file when resuming (and its ``figure`` exists), else
        computed by ``compute`` (which then also returns the figure, saved as ``figure``) and saved."""
        from .._files import atomic_write
        from .._json import finite, json_default
        from .._reading import read_text

        path = self.folder / f"{name}.json"
        if self.resume and path.is_file() and (figure is None or (self.out / figure).is_file()):
            self.say(f"{name}: kept from the earlier run")
            return json.loads(read_text(path, max_bytes=MAX_PART_BYTES, expected="a dossier's piece (JSON)"))
        self.say(name)
        result = compute()
        if figure is not None:
            import matplotlib

            from ..report.figures import save

            matplotlib.use("Agg")
            result, fig = result
            save(fig, self.out / figure, dpi=110)
        text = json.dumps(finite(result)[0], indent=1, default=json_default, allow_nan=False)
        atomic_write(path, lambda fh: fh.write(text), binary=False)
        return json.loads(text)


def _state(parts: _Parts, pset, tag: str, payload_kg: float, sheet: dict) -> dict:
    from . import runs, transient

    suffix = "" if tag == "as_given" else "-laden"
    state = {
        "payload_kg": payload_kg,
        "mass": sheet["mass"][tag],
        "static": parts.get(f"static{suffix}", lambda: runs.static_stability(pset), f"tilt{suffix}.png"),
        "handling": parts.get(f"handling{suffix}", lambda: runs.handling(pset), f"handling{suffix}.png"),
        "performance": parts.get(f"performance{suffix}", lambda: runs.top_speed(pset)),
        "thresholds": parts.get(f"thresholds{suffix}", lambda: runs.thresholds(pset, say=parts.say)),
        "figures": {"tilt": f"tilt{suffix}.png", "handling": f"handling{suffix}.png", "step": f"step{suffix}.png",
                    "sweep": f"sweep{suffix}.png"},
    }
    speed = transient.transient_speed(state["thresholds"])
    state["step"] = parts.get(f"step-{speed:g}{suffix}", lambda: transient.step_response(pset, speed),
                              f"step{suffix}.png")
    state["sweep"] = parts.get(f"sweep-{speed:g}{suffix}", lambda: transient.frequency_response(pset, speed),
                               f"sweep{suffix}.png")
    state["metrics"] = runs.state_metrics(state)
    return state


def assess(pset, *, payload_kg: float = 0.0, out: str | Path, quick: bool = False, resume: bool = False,
           requirements=None, say: Callable[[str], None] | None = None) -> dict:
    """The stability dossier's data.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle as given (no freight).
    payload_kg : float
        Freight of the laden state [kg], at the vehicle's freight site; 0: the laden state is the vehicle as
        given.
    out : str or Path
        The dossier's folder: pieces (``assess-parts/``) and figures go there.
    quick : bool
        Leave out the loading chart, the sensitivity and the animation (and the speed limits beyond the two
        states).
    resume : bool
        Read the pieces already in ``out`` instead of computing them again.
    requirements : RequirementSet, optional
        Judged against the results.
    say : callable, optional
        ``say(text)``: progress, one line per piece.

    Returns
    -------
    dict
        ``vehicle`` (the sheet), ``states`` (``as_given``, ``laden``: mass, static, handling, performance,
        thresholds, step, sweep, metrics),
        ``freight_positions``, ``design_changes``, ``speed_limits``, ``loading_chart``,
        ``sensitivity``, ``animation`` (None with ``quick``), ``guidelines``, ``requirements`` and ``figures``.
    """
    from ..params import with_freight
    from ..study.designs.loading import DEFAULT_MASSES_KG
    from . import runs, studies
    from .guidelines import derive_guidelines
    from .requirements import METRICS, judge

    say = say or (lambda text: None)
    out = Path(out)
    parts = _Parts(out, resume, say)
    payload_kg = float(payload_kg)
    sheet = parts.get("vehicle", lambda: runs.vehicle_sheet(pset, payload_kg))
    laden_pset = with_freight(pset, payload_kg)
    states = {"as_given": _state(parts, pset, "as_given", 0.0, sheet)}
    states["laden"] = _state(parts, laden_pset, "laden", payload_kg, sheet) if payload_kg > 0 else states["as_given"]
    freight_kg = payload_kg if payload_kg > 0 else max(DEFAULT_MASSES_KG)
    data = {"vehicle": sheet, "payload_kg": payload_kg, "quick": quick, "states": states,
            "freight_mass_kg": freight_kg,
            "freight_positions": parts.get("freight-positions", lambda: studies.freight_positions(pset, freight_kg)),
            "design_changes": parts.get("design-changes", lambda: studies.design_changes(pset, say=say))}
    masses = sorted({0.0, payload_kg} | (set() if quick else {float(m) for m in DEFAULT_MASSES_KG}))
    known = {s["payload_kg"]: {n: t["course_kmh"] for n, t in s["thresholds"].items()} for s in states.values()}
    data["speed_limits"] = parts.get("speed-limits-" + "-".join(f"{m:g}" for m in masses),
                                     lambda: studies.speed_limits(pset, masses, say=say, known=known))
    data["loading_chart"] = data["sensitivity"] = data["animation"] = None
    if not quick:
        data["loading_chart"] = parts.get("loading-chart", lambda: studies.loading_chart(pset, out, resume=resume),
                                          "loading-chart.png")
        data["sensitivity"] = parts.get("sensitivity", lambda: studies.sensitivity(pset, out, resume=resume),
                                        "sensitivity.png")
        critical = studies.critical_run(states["laden"]["thresholds"])
        if critical is not None:
            name, speed = critical
            gif = "animation.gif"
            data["animation"] = parts.get("animation", lambda: {
                "manoeuvre": name, "speed_kmh": speed, "payload_kg": payload_kg,
                "file": studies.animate_critical(laden_pset, name, speed, out / gif).name})
    data["guidelines"] = derive_guidelines(data)
    data["requirements"] = None
    if requirements is not None:
        def value_of(item, metric: str):
            """The vehicle's value of ``metric`` for the requirement ``item`` (laden or as given): from a run of its
            manoeuvre at its speed [km/h] when the metric needs one, else from that state's metrics."""
            tag = "laden" if item.laden else "as_given"
            if METRICS.get(metric).needs:
                run = parts.get(f"run-{item.manoeuvre}-{item.speed_kmh:g}-{tag}",
                                lambda: runs.run_metric(laden_pset if item.laden else pset, item.manoeuvre,
                                                        item.speed_kmh))
                return run.get(metric)
            return states[tag]["metrics"].get(metric)

        judged = judge(requirements, value_of)
        data["requirements"] = requirements.to_dict() | {
            "judgements": [j.to_dict() for j in judged], "passed": all(j.passed for j in judged),
            "failed": [j.id for j in judged if not j.passed]}
    return data
