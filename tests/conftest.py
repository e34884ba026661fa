"""Shared test fixtures."""

import os
from pathlib import Path

import pytest

# The suite runs on the reference (generic) kernels: the generated loop of each tree structure is compiled only by
# the tests that hold it to them (tests/simulate/test_specialised.py: both presets, closed and open loop, 1e-9;
# tests/simulate/test_batch.py; tests/model/test_codegen.py). Compiling a generated loop for every structure the
# suite meets, in every worker and every `python -m trikedyn` subprocess, cost minutes of the 10-minute budget.
# `TRIKEDYN_KERNELS=generated make test` runs the whole suite on the generated loops.
os.environ.setdefault("TRIKEDYN_KERNELS", "generic")

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"


@pytest.fixture(scope="session")
def reference():
    from trikedyn.params import load_vehicle

    return load_vehicle("reference-etrike")


WEIGHING = """reading_std_kg = 0.5
wheel_radius_m = 0.27
[contacts]
front = [1.95, 0.0]
rear_left = [0.0, 0.55]
rear_right = [0.0, -0.55]
[level]
front = 249.1
rear_left = 175.6
rear_right = 158.3
[[tilted]]
raised = "front"
height_m = 0.20
raised_axle_kg = 236.4
"""
"""A valid weighing file (the format of :mod:`trikedyn.measure.weighing`), for the command-line tests."""


def strict_json(text: str):
    """``json.loads`` that refuses NaN and Infinity (which Python's json would accept)."""
    import json

    def refuse(name):
        raise AssertionError(f"non-finite {name} in JSON")

    return json.loads(text, parse_constant=refuse)


# The longest test files, measured (`pytest --durations`), run first: `make test` gives each of its two processes
# whole files (`--dist loadfile`), and a long file taken last leaves the other process idle at the end (the real
# Dask cluster's tests, ~3 minutes, ended a 13-minute run alone).
LONGEST_FIRST = (
    "study/test_real_cluster.py", "study/test_resume.py", "analysis/test_search.py", "test_docs.py",
    "simulate/test_batch.py", "model/test_codegen.py", "study/test_sensitivity_metric.py", "test_interrupts.py",
    "study/test_engine_dask.py", "study/test_acceptance.py", "physics/test_convergence.py",
    "study/test_lost_scheduler.py", "study/test_loading_resume.py", "fuzz/test_special_files.py",
    "paper/test_reproduce.py", "study/test_design_names.py", "study/test_design_metric.py",
)


def pytest_collection_modifyitems(config, items):  # noqa: ARG001
    """Put the tests of :data:`LONGEST_FIRST` first, in its order; the rest keep their order."""
    rank = {name: k for k, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.nodeid.split("::", 1)[0].removeprefix("tests/"), len(rank)))
