"""Shared test fixtures."""

from pathlib import Path

import pytest

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
