"""Parametric studies: vehicle variations (stiffness, damping, freight, any parameter or design knob) x
manoeuvres x metrics (paper Tables 2-3, Fig. 10).

A study is a TOML spec (:mod:`~trikedyn.study.spec`), expanded into scenarios with deterministic ids, each
measuring one metric (:mod:`~trikedyn.study.metrics`: the threshold velocity by default), run in parallel
on any :class:`concurrent.futures.Executor` (:mod:`~trikedyn.study.engine.executors`: a process pool or a Dask
cluster) by :mod:`~trikedyn.study.designs.runner` into a resumable SQLite store
(:mod:`~trikedyn.study.engine.store`), with figures chosen from the study's shape
(:mod:`~trikedyn.study.designs.figures`). The engine (:mod:`~trikedyn.study.engine`) runs every design's
evaluations; the designs (:mod:`~trikedyn.study.designs`: the grid study, Morris/Sobol sensitivity, uncertainty,
the loading chart, the optimiser) say what to evaluate::

    from trikedyn.study import run_study
    table = run_study("paper", "paper-study", workers=2)   # the paper's 50 scenarios

Names are imported lazily (importing the package loads neither pandas nor the model).
"""

from __future__ import annotations

import importlib

__all__ = [
    "StudyIncomplete",
    "StudyInterrupted",
    "StudyRun",
    "StudySpec",
    "StudyStore",
    "count_scenarios",
    "execute_study",
    "expand",
    "list_specs",
    "load_spec",
    "parse_spec",
    "run_scenario",
    "run_study",
    "scenario_id",
    "study_metric",
]

_WHERE = {
    "StudySpec": "spec",
    "count_scenarios": "scenarios",
    "expand": "scenarios",
    "list_specs": "spec",
    "load_spec": "spec",
    "parse_spec": "spec",
    "scenario_id": "scenarios",
    "StudyStore": "engine.store",
    "StudyIncomplete": "designs.runner",
    "StudyInterrupted": "designs.runner",
    "StudyRun": "designs.runner",
    "execute_study": "designs.runner",
    "run_scenario": "designs.runner",
    "run_study": "designs.runner",
    "study_metric": "metrics",
}


def __getattr__(name: str):
    if name in _WHERE:
        return getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted([*globals(), *__all__])
