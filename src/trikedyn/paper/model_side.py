"""The model side of ``trikedyn reproduce`` (paper sections 2.3 and 3): the model's own speed-bump test
read through the emulated 10 Hz seat sensor, both lane changes with their time histories and rollover
index (Figs. 7-9), and the parametric study of the threshold velocity (Fig. 10), each with its verdict.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._files import atomic_write
from ..analysis.metrics import summary
from ..manoeuvres import registry, speed
from ..measure.suspension import identify_suspension
from ..model.statics import static_equilibrium
from ..model.vehicle import build_model, speed_bump
from ..params import load_vehicle
from ..params.ops import static_wheel_loads, unsprung_mass
from ..report import figures
from ..simulate.closed_loop import run
from ..simulate.result import rollover_index
from ..simulate.run import simulate
from ..units import STANDARD_GRAVITY
from .data import STUDY_SPEC

__all__ = ["model_bump_test", "manoeuvres", "parametric_study", "speed_controls", "STUDY_FINDINGS"]

MODEL_BUMP = {"height_m": 0.05, "length_m": 0.5, "speed_kmh": 5.0, "start_m": 3.0, "duration_s": 30.0}
"""The model's speed-bump test: a cushion under one axle at a time (assumed size), the paper's 5 km/h."""
SLC_SPEED_KMH = 30.0
DLC_SPEED_KMH = (25.0, 35.0)
"""The manoeuvres' speeds: the paper gives no figures; its SLC held the speed, its DLC rose about
linearly with the throttle held (section 2.2, Fig. 8a)."""


def model_bump_test(out: Path, figures_on: bool = True) -> list[dict]:
    """Table 1 from the multibody model itself: bump under the front (a central cushion) or under the rear
    wheels (two side cushions), the seat sensor's vertical acceleration at 10 Hz with noise and bias,
    identified with the paper's method (and the tyre in series); beside the model's own suspension.

    Parameters
    ----------
    out : Path
        The output folder.
    figures_on : bool
        Draw the figures.

    Returns
    -------
    list of dict
        One row per preset and axle: identified f_n [Hz], xi (dimensionless), K [N/m], C [N s/m] beside the model's.
    """
    rows = []
    lanes = {"front": ((0.0, 0.3), "front"), "rear": ((0.3, 5.0), "rear_left")}
    for preset in ("reference-etrike", "reference-etrike-eq4"):
        pset = load_vehicle(preset)
        p = pset.params
        for station, (lateral, wheel) in lanes.items():
            road = speed_bump(MODEL_BUMP["start_m"], MODEL_BUMP["length_m"], MODEL_BUMP["height_m"], lateral)
            run = simulate(pset, duration_s=MODEL_BUMP["duration_s"], speed_kmh=MODEL_BUMP["speed_kmh"],
                           drive_torque_Nm=25.0, road=road, raise_on_failure=True)
            log = run.imu_log(10.0, noise_std=0.05, bias=(0.0, 0.0, 0.2), seed=7)
            sprung = static_wheel_loads(p)[wheel] / STANDARD_GRAVITY - unsprung_mass(p, wheel)
            result = identify_suspension(
                log["time_s"].to_numpy(), log["az_mps2"].to_numpy(), sprung,
                tyre_stiffness_N_per_m=p.tyre.vertical_stiffness_N_per_m,
                tyre_damping_Ns_per_m=p.tyre.vertical_damping_Ns_per_m, unsprung_mass_kg=unsprung_mass(p, wheel),
            )
            susp = p.suspension[station]
            rows.append({
                "vehicle": preset, "suspension": station, "sprung_mass_kg": sprung,
                "identified_frequency_hz": result.natural_frequency_hz,
                "identified_damping_ratio": result.damping_ratio,
                "model_stiffness_N_per_m": susp.stiffness_N_per_m,
                "identified_stiffness_N_per_m": result.stiffness_N_per_m,
                "stiffness_error_pct": 100 * (result.stiffness_N_per_m / susp.stiffness_N_per_m - 1),
                "model_damping_Ns_per_m": susp.damping_Ns_per_m,
                "identified_damping_Ns_per_m": result.damping_Ns_per_m,
                "damping_error_pct": 100 * (result.damping_Ns_per_m / susp.damping_Ns_per_m - 1),
                "warnings": " | ".join(result.warnings),
            })
            if figures_on and preset == "reference-etrike-eq4":
                figures._plt()  # the Agg backend before the figure is made
                fig = result.plot()
                fig.suptitle(f"multibody model, {station} cushion: seat sensor at 10 Hz (Fig. 2c-d)", fontsize=10)
                figures.save(fig, out / f"fig2_model_bump_{station}.png")
    return rows


def manoeuvres(out: Path, figures_on: bool = True) -> tuple[dict, list[dict], float]:
    """Both lane changes on reference-etrike (Figs. 7-9): time histories, rollover index, summaries.

    Parameters
    ----------
    out : Path
        The output folder.
    figures_on : bool
        Draw the figures.

    Returns
    -------
    runs : dict
        Label -> Result.
    summaries : list of dict
        Each run's metrics.
    static_ri : float
        Static rollover index, dimensionless.
    """
    pset = load_vehicle("reference-etrike")
    model = build_model(pset)
    slc = run(model, "slc", speed_kmh=SLC_SPEED_KMH, raise_on_failure=True)
    dlc_track = registry.build("dlc", pset.params, DLC_SPEED_KMH[0])
    dlc = run(model, dlc_track.at_speed(speed.linear(*DLC_SPEED_KMH, 22.0)), raise_on_failure=True)
    runs = {f"single lane change (ISO 14791), {SLC_SPEED_KMH:g} km/h": slc,
            f"double lane change (ISO 3888-1), {DLC_SPEED_KMH[0]:g}-{DLC_SPEED_KMH[1]:g} km/h": dlc}
    eq = static_equilibrium(model)
    static_ri = float(rollover_index(eq.wheel_loads_N["rear_right"], eq.wheel_loads_N["rear_left"]))
    rows = []
    for label, result in runs.items():
        frame = result.to_pandas().reset_index()
        name = "slc" if label.startswith("single") else "dlc"
        atomic_write(out / f"run_{name}.csv", lambda fh, frame=frame: frame.to_csv(fh, index=False), binary=False)
        judged = summary(result)
        window = judged.pop("window_speed_kmh") or {}
        judged["reasons"] = "; ".join(r["detail"] for r in judged["reasons"])
        rows.append({**judged, **{f"driven_{k}_kmh": window.get(k) for k in ("min", "max")}, "manoeuvre": label})
    if figures_on:
        figures.time_histories({k: v for k, v in runs.items() if k.startswith("single")}, out / "fig7_slc.png",
                               "single lane change: velocity, lateral acceleration, yaw rate (cf. Fig. 7)")
        figures.time_histories({k: v for k, v in runs.items() if k.startswith("double")}, out / "fig8_dlc.png",
                               "double lane change (cf. Fig. 8)")
        figures.rollover_index(runs, static_ri, out / "fig9_rollover_index.png", "rollover index, Eq. 5 (cf. Fig. 9)")
    return runs, rows, static_ri


SPEED_CONTROL_FREIGHT_KG = (0.0, 200.0)
"""The freights at which :func:`speed_controls` compares the speed controls and criteria."""


def speed_controls(out: Path) -> list[dict]:
    """The paper's thresholds with each speed control and under each criterion (``thresholds_by_control.csv``).

    The paper's SIMPACK model drove at the speed given to it (section 3.1: the velocity was "the
    simulation input"), which the ideal speed control reproduces and ``reproduce``'s study uses; with the
    trike's own (assumed) drive the searches stop at its top speed. Each row: a lane change at a freight,
    under one speed control, with the threshold under the paper's criterion (lift-off) and under ISO 3888-1's
    validity (course), what limits each, and the speed the course threshold's run drove.

    Parameters
    ----------
    out : Path
        The output folder.

    Returns
    -------
    list of dict
        The rows (speeds [km/h], freight [kg]).
    """
    from ..analysis.threshold import threshold_velocity
    from ..params import with_freight

    base = load_vehicle("reference-etrike")
    rows = []
    for freight in SPEED_CONTROL_FREIGHT_KG:
        model = build_model(with_freight(base, freight))
        for manoeuvre in ("dlc", "slc"):
            for control in ("ideal", "driver"):
                found = threshold_velocity(model, manoeuvre, criterion="both", speed_control=control)
                lift = found.lift_off
                window = found.window_speed_kmh or {}
                rows.append({
                    "manoeuvre": manoeuvre, "freight_kg": freight, "speed_control": control,
                    "lift_off_kmh": found.lift_off_speed_kmh, "lift_off_limit": None if lift is None else lift.limit,
                    "course_kmh": found.course_speed_kmh, "course_limit": found.limit,
                    "course_driven_min_kmh": window.get("min"), "course_driven_max_kmh": window.get("max"),
                    "top_speed_kmh": found.top_speed_kmh, "runs": found.n_runs,
                })
    atomic_write(out / "thresholds_by_control.csv",
                 lambda fh: _csv(fh, rows), binary=False)
    return rows


def _csv(fh, rows: list[dict]) -> None:
    import csv

    writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
    writer.writeheader()
    writer.writerows(rows)


STUDY_FINDINGS = ("falls with freight", "rises with stiffness", "damping matters less than stiffness")


def parametric_study(out: Path, workers: int | None = 2, figures_on: bool = True):
    """The paper's study (Fig. 10) with its built-in spec (:data:`trikedyn.paper.STUDY_SPEC`); returns the table and the findings.

    Parameters
    ----------
    out : Path
        The output folder.
    workers : int, optional
        Worker processes.
    figures_on : bool
        Draw the figures.

    Returns
    -------
    table : pandas.DataFrame
        Threshold speeds [km/h] by freight [kg] and scales.
    findings : dict
        The paper's findings checked.
    """
    table = study_table(out, workers)
    if figures_on:
        study_figure(table, out)
    return table, study_findings(table)


def study_table(out: Path, workers: int | None = 2):
    """The paper's study run into ``out / "study"`` (resumable), its table also as ``fig10_threshold_study.csv``.

    Uses no pyplot, so that :func:`~trikedyn.paper.reproduce.reproduce` can run it in a thread while it draws
    the other figures."""
    from ..study.designs.runner import run_study

    table = run_study(STUDY_SPEC, out / "study", workers=workers, progress=False)
    atomic_write(out / "fig10_threshold_study.csv", lambda fh: table.to_csv(fh, index=False), binary=False)
    return table


def study_figure(table, out: Path) -> None:
    """Fig. 10: the threshold velocity over the study."""
    figures.threshold_study(table, out / "fig10_threshold_study.png",
                            "threshold velocity: no wheel lifts, at the speed imposed (lift-off criterion, ideal "
                            "speed control; cf. Fig. 10)")


def study_findings(table) -> dict:
    """The paper's three findings checked on a study table, with the numbers behind each."""
    ok = table[table["threshold_speed_kmh"].notna()]
    falls, rises, spans = [], [], {"stiffness": [], "damping": []}
    for man in sorted(ok["manoeuvre"].unique()):
        sub = ok[ok["manoeuvre"] == man]
        for _, line in sub.groupby(["stiffness_scale", "damping_scale"]):
            v = line.sort_values("freight_kg")["threshold_speed_kmh"].to_numpy()
            falls.append(bool(np.all(np.diff(v) <= 0.0)) and v[-1] < v[0])
        for _, col in sub.groupby("freight_kg"):
            stiff = col[col["damping_scale"] == 1.0].sort_values("stiffness_scale")["threshold_speed_kmh"].to_numpy()
            damp = col[col["stiffness_scale"] == 1.0].sort_values("damping_scale")["threshold_speed_kmh"].to_numpy()
            if stiff.size == 3:
                rises.append(bool(stiff[2] >= stiff[1] >= stiff[0]))
                spans["stiffness"].append(float(stiff[2] - stiff[0]))
            if damp.size == 3:
                spans["damping"].append(float(damp[2] - damp[0]))
    mean_k = float(np.mean(np.abs(spans["stiffness"]))) if spans["stiffness"] else float("nan")
    mean_c = float(np.mean(np.abs(spans["damping"]))) if spans["damping"] else float("nan")
    drop = ok.groupby("manoeuvre").apply(
        lambda g: float(g[g.freight_kg == g.freight_kg.min()].threshold_speed_kmh.mean()
                        - g[g.freight_kg == g.freight_kg.max()].threshold_speed_kmh.mean()),
        include_groups=False,
    ).to_dict()
    return {
        "falls with freight": {"holds": all(falls) if falls else False, "lines": len(falls),
                               "lines_falling": int(sum(falls)), "mean_drop_0_to_200_kg_kmh": drop},
        "rises with stiffness": {"holds": all(rises) if rises else False, "cases": len(rises),
                                 "cases_rising": int(sum(rises)),
                                 "mean_change_80_to_120_pct_kmh": float(np.mean(spans["stiffness"])) if spans["stiffness"] else None},
        "damping matters less than stiffness": {"holds": mean_c < mean_k, "mean_abs_change_stiffness_kmh": mean_k,
                                                "mean_abs_change_damping_kmh": mean_c},
    }
