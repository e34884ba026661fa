"""Parametric studies: grids over stiffness, damping, freight and any parameter (paper Tables 2-3, Fig. 10).

A study is a TOML spec (:mod:`~trikedyn.study.spec`), expanded into scenarios with deterministic ids, run
in parallel on a process pool or a Dask cluster (:mod:`~trikedyn.study.runner`) into a resumable SQLite
store (:mod:`~trikedyn.study.store`)::

    from trikedyn.study import run_study
    table = run_study("paper", "paper-study", workers=2)   # the paper's 50 scenarios

Names are imported lazily, so ``python -m trikedyn.study.runner`` does not import the runner twice.
"""

from __future__ import annotations

import importlib

__all__ = [
    "StudyIncomplete",
    "StudyInterrupted",
    "StudySpec",
    "StudyStore",
    "count_scenarios",
    "expand",
    "list_specs",
    "load_spec",
    "parse_spec",
    "run_scenario",
    "run_study",
    "scenario_id",
    "study_command",
]

_WHERE = {
    "StudySpec": "spec",
    "count_scenarios": "spec",
    "expand": "spec",
    "list_specs": "spec",
    "load_spec": "spec",
    "parse_spec": "spec",
    "scenario_id": "spec",
    "StudyStore": "store",
    "StudyIncomplete": "runner",
    "StudyInterrupted": "runner",
    "run_scenario": "runner",
    "run_study": "runner",
    "study_command": "runner",
}


def __getattr__(name: str):
    if name in _WHERE:
        return getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted([*globals(), *__all__])
