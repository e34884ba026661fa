"""The study store's rows as a table (:meth:`~trikedyn.study.engine.store.StudyStore.to_pandas`, and the exports
``results.csv`` and ``results.parquet``): one row per scenario, in the spec's order, the columns named in
:mod:`trikedyn.study.engine.store`'s docstring. pandas is imported only here, when a table is asked for.
"""

from __future__ import annotations

from ...errors import InputError

__all__ = ["EXPORT_COLUMNS", "METRIC_COLUMNS", "RESULT_KEYS", "RUN_INFO_COLUMNS", "SCENARIO_COLUMNS",
           "SEARCH_COLUMNS", "results_table"]

SCENARIO_COLUMNS = ("scenario_id", "groups", "vehicle", "manoeuvre", "freight_kg", "stiffness_scale",
                    "damping_scale")
RESULT_KEYS = ("threshold_speed_kmh", "limit", "limiting_wheel", "lift_time_s", "first_failure_kmh",
               "first_cone_strike_kmh", "n_runs", "detail", "failure_time_s", "entry_speed_kmh", "driven_min_kmh", "driven_mean_kmh",
               "driven_max_kmh", "top_speed_kmh", "course_speed_kmh", "lift_off_speed_kmh", "lift_off_limit")
SEARCH_COLUMNS = ("resolution_kmh", "low_kmh", "high_kmh", "step_kmh", "criterion", "speed_control",
                  "speed_band_percent", "speed_band_kmh", "course_width_m")
EXPORT_COLUMNS = (*SCENARIO_COLUMNS, "status", *RESULT_KEYS, *SEARCH_COLUMNS, "error")
"""Columns of the exported table; override columns (named by their dotted parameter path) follow
``damping_scale``."""
RUN_INFO_COLUMNS = ("wall_time_s", "worker", "run_token", "finished_at")
METRIC_COLUMNS = ("metric", "value", "unit")
"""Columns of a study with metrics other than the threshold: ``metric`` after the overrides, ``value`` and
``unit`` after ``status``."""


def _unit(metric: str) -> str | None:
    """A metric's unit from the registry (a failed row keeps no result, hence no unit)."""
    from ..metrics import get

    try:
        return get(metric).unit
    except InputError:
        return None




def results_table(stored: list[dict], order: list[str] | None = None, *, run_info: bool = False):
    """The stored rows (:meth:`~trikedyn.study.engine.store.StudyStore.rows`) as a tidy table.

    Parameters
    ----------
    stored : list of dict
        The store's rows.
    order : list of str, optional
        Scenario ids in the wanted order (the spec's); rows not listed are left out. All rows, sorted by
        id, if None.
    run_info : bool
        Add ``wall_time_s`` [s], ``worker``, ``run_token`` and ``finished_at`` [s since the epoch].

    Returns
    -------
    pandas.DataFrame
        As :meth:`~trikedyn.study.engine.store.StudyStore.to_pandas` describes it.
    """
    import pandas as pd

    rows = {r["scenario_id"]: r for r in stored}
    ids = sorted(rows) if order is None else [i for i in order if i in rows]
    chosen = [rows[i] for i in ids]
    paths: list[str] = []
    for r in chosen:
        paths.extend(p for p in r["overrides"] if p not in paths)
    with_metrics = any(r["metric"] != "threshold" for r in chosen)
    columns = [*SCENARIO_COLUMNS, *paths, *(["metric"] if with_metrics else []), "status",
               *(["value", "unit"] if with_metrics else []), *RESULT_KEYS, *SEARCH_COLUMNS, "error"]
    if run_info:
        columns += list(RUN_INFO_COLUMNS)
    records = []
    for r in chosen:
        rec = {c: r.get(c) for c in columns if c not in paths}
        if r.get("manoeuvre_options"):  # a manoeuvre with options shows them: dlc(run_in_m=40)
            from ...manoeuvres.spec import manoeuvre_label

            rec["manoeuvre"] = manoeuvre_label(r["manoeuvre"], r["manoeuvre_options"])
        if with_metrics:
            rec.update(metric=r["metric_label"], value=r.get("value"), unit=r.get("unit") or _unit(r["metric"]))
        rec.update({p: r["overrides"].get(p) for p in paths})
        records.append(rec)
    frame = pd.DataFrame.from_records(records, columns=columns)
    frame["n_runs"] = frame["n_runs"].astype("Int64")
    for col in ("freight_kg", "stiffness_scale", "damping_scale", "threshold_speed_kmh", "lift_time_s",
                "first_failure_kmh", "first_cone_strike_kmh", "failure_time_s", "entry_speed_kmh", "driven_min_kmh",
                "driven_mean_kmh", "driven_max_kmh", "top_speed_kmh", "course_speed_kmh", "lift_off_speed_kmh",
                "resolution_kmh", "low_kmh", "high_kmh", "step_kmh", "speed_band_percent", "speed_band_kmh",
                "course_width_m",
                *(["value"] if with_metrics else [])):
        frame[col] = frame[col].astype("float64")
    return frame
