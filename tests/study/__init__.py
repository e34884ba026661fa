"""Tests of trikedyn.study: specs, the result store, executors, interruption and resume."""

from __future__ import annotations

import functools
import textwrap
from pathlib import Path

SMALL = textwrap.dedent(
    """
    name = "{name}"
    vehicle = "reference-etrike"
    manoeuvres = ["slc"]
    freight_kg = {freight}
    resolution_kmh = 1.0
    [[groups]]
    name = "stiffness"
    stiffness_scale = {stiffness}
    """
)


def write_spec(folder: Path, name: str = "small", freight=(0, 100), stiffness=(0.9, 1.1), extra: str = "") -> Path:
    """A small study: slc at 1 km/h resolution (each threshold search 20-50 ms, the first of a process more)."""
    path = Path(folder) / f"{name}.toml"
    text = SMALL.format(name=name, freight=list(freight), stiffness=list(stiffness)) + textwrap.dedent(extra)
    path.write_text(text, encoding="utf-8")
    return path


@functools.cache
def warm_numba_cache() -> None:
    """Compile (or load) the numba cache once in this process, so that spawned workers only load it."""
    from trikedyn.analysis.threshold import threshold_velocity
    from trikedyn.params import load_vehicle

    threshold_velocity(load_vehicle("reference-etrike"), "slc", low_kmh=10, high_kmh=20, resolution_kmh=5.0)
