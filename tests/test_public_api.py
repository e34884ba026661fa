"""The flat public API (``import trikedyn as td``): one table, no name hiding a subpackage, one default for
failures (issue 22)."""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import subprocess
import sys

import numpy as np
import pytest

import trikedyn as td
from trikedyn.errors import SimulationError


def test_all_is_the_lazy_table():
    """``__all__`` is the lazy table's names (and ``__version__``), not a second list."""
    assert sorted(td.__all__) == sorted(["__version__", *td._LAZY])
    assert len(td.__all__) == len(set(td.__all__))


def test_every_name_of_all_resolves_to_its_module_s_own_object():
    """Each name is found, in a fresh interpreter too (so not because a test imported its module first), and is
    the object its module defines."""
    for name in td.__all__:
        value = getattr(td, name)
        if name == "__version__":
            continue
        module, attribute = td._LAZY[name]
        assert value is getattr(importlib.import_module(f"trikedyn.{module}"), attribute), name
    code = "import trikedyn as td\nmissing = [n for n in td.__all__ if getattr(td, n, None) is None]\nprint(missing)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_no_flat_name_is_a_subpackage_or_module_of_trikedyn():
    """``td.simulate`` was both a function and the subpackage ``trikedyn/simulate/``; no such name is left."""
    children = {info.name for info in pkgutil.iter_modules(td.__path__)}
    assert "simulate" in children and "errors" in children  # the scan sees the package's own modules
    assert sorted(set(td.__all__) & children) == []


def test_a_subpackage_is_the_package_once_imported():
    """``trikedyn.simulate`` is the package, not a function bound over it."""
    code = ("import trikedyn, trikedyn.simulate.run, types\n"
            "print(isinstance(trikedyn.simulate, types.ModuleType), callable(trikedyn.run_open_loop))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["True", "True"]


def test_unknown_names_are_attribute_errors():
    with pytest.raises(AttributeError, match="no attribute 'simulate_open_loop'"):
        td.simulate_open_loop  # noqa: B018


@pytest.mark.parametrize("name", ["run", "drive", "run_open_loop"])
def test_one_default_for_failures(name):
    """``run``, ``drive`` and ``run_open_loop`` take ``raise_on_failure`` with the same default: False (a run
    that stops early is a result saying so), and each documents it."""
    parameter = inspect.signature(getattr(td, name)).parameters["raise_on_failure"]
    assert parameter.default is False
    assert "raise_on_failure" in inspect.getdoc(getattr(td, name))


def test_a_run_that_stops_early_is_a_result_unless_asked_to_raise():
    """A top-heavy trike thrown into a sharp turn rolls over: by default a result with ``success`` False and
    the reason; with ``raise_on_failure=True`` a SimulationError carrying that partial result."""
    top_heavy = td.override(td.load_vehicle("reference-etrike"), {"mass.cg_z_m": 1.1})
    inputs = {"duration_s": 10.0, "speed_kmh": 40.0, "steer_rad": lambda t: np.minimum(0.3, 0.6 * t)}
    result = td.run_open_loop(top_heavy, **inputs)
    assert not result.success and "rolled over" in result.message
    assert result.to_pandas().index[-1] < 10.0
    with pytest.raises(SimulationError, match="rolled over") as info:
        td.run_open_loop(top_heavy, raise_on_failure=True, **inputs)
    assert info.value.result.to_pandas().shape == result.to_pandas().shape
