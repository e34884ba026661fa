"""Shared test fixtures."""

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"


@pytest.fixture(scope="session")
def reference():
    from trikedyn.params import load_vehicle

    return load_vehicle("reference-etrike")
