"""trikedyn: stability analysis of three-wheeled electric vehicles.

The flat public API::

    import trikedyn as td
    trike = td.load_vehicle("reference-etrike")
    result = td.run(trike, "dlc", speed_kmh=40)           # a manoeuvre, closed loop (the driver model)
    ride = td.run_open_loop(trike, duration_s=5.0, speed_kmh=25.0, steer_rad=0.02)   # open-loop inputs

Every name of :data:`__all__` is imported from its module on first use (the table ``_LAZY``); none is the
name of a subpackage (``trikedyn.simulate`` is the package, the open-loop run is ``td.run_open_loop``).

A run that stops early (a wheel lifted into a rollover, a tyre runaway, NaN) is a result, not an exception,
in :func:`run`, :func:`drive` and :func:`run_open_loop` alike: ``result.success`` is False and
``result.message`` says why. Pass ``raise_on_failure=True`` to get a
:class:`~trikedyn.errors.SimulationError` carrying the partial ``.result`` instead. Bad input (an unknown
manoeuvre, a negative speed, a time step too large for the model) raises in every case.
"""

from ._version import __version__


def _numba_cache_dir() -> None:
    """Key numba's on-disk cache by the package's compiled sources.

    numba invalidates a cached function only when *its own* file changes, not when a function it calls
    from another module does; a stale time loop would then run old physics. Caching into a folder named
    after a hash of every compiled module avoids that. A user's own ``NUMBA_CACHE_DIR`` wins.
    """
    import hashlib
    import os
    from pathlib import Path

    if "NUMBA_CACHE_DIR" in os.environ:
        return
    here = Path(__file__).parent
    digest = hashlib.sha1(__version__.encode())
    # the compiled code lives in these folders; of the top level it uses only the numba options (_jit.py):
    # editing the command line or this file costs no recompilation
    for path in [here / "_jit.py", *(p for sub in ("model", "tyre", "simulate", "driver")
                                      for p in sorted((here / sub).glob("*.py")))]:
        digest.update(path.read_bytes())
    base = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
    os.environ["NUMBA_CACHE_DIR"] = str(base / "trikedyn" / f"numba-{digest.hexdigest()[:16]}")
    import sys

    if "numba" in sys.modules:  # numba read its configuration already
        from numba.core import config

        config.reload_config()


_numba_cache_dir()

# The flat API, each name imported from its module when first used (``import trikedyn`` and
# ``trikedyn --version`` load neither scipy, pandas nor the compiled model).
_LAZY = {
    "TrikedynError": ("errors", "TrikedynError"),
    "InputError": ("errors", "InputError"),
    "LogFormatError": ("errors", "LogFormatError"),
    "ParameterError": ("errors", "ParameterError"),
    "SimulationError": ("errors", "SimulationError"),
    "Box": ("mechanics", "Box"),
    "MassProperties": ("mechanics", "MassProperties"),
    "Payload": ("mechanics", "Payload"),
    "PointMass": ("mechanics", "PointMass"),
    "ImuLog": ("measure.imu_log", "ImuLog"),
    "read_log": ("measure.logs", "read_log"),
    "write_log": ("measure.logs", "write_log"),
    "identify_suspension": ("measure.suspension", "identify_suspension"),
    "reduce_weighing": ("measure.weighing", "reduce_weighing"),
    "modes": ("model.linear", "modes"),
    "rhs": ("model.rhs", "f"),
    "static_equilibrium": ("model.statics", "static_equilibrium"),
    "Road": ("model.vehicle", "Road"),
    "build_model": ("model.vehicle", "build_model"),
    "flat_road": ("model.vehicle", "flat_road"),
    "speed_bump": ("model.vehicle", "speed_bump"),
    "ParameterSet": ("params", "ParameterSet"),
    "mirror_layout": ("params", "mirror_layout"),
    "compare_layouts": ("analysis.layouts", "compare_layouts"),
    "VehicleParameters": ("params", "VehicleParameters"),
    "audit": ("params", "audit"),
    "list_presets": ("params", "list_presets"),
    "load_vehicle": ("params", "load_vehicle"),
    "save_vehicle": ("params", "save_vehicle"),
    "scale_suspension": ("params", "scale_suspension"),
    "with_freight": ("params", "with_freight"),
    "with_payload": ("params", "with_payload"),
    "Result": ("simulate.result", "Result"),
    "rollover_index": ("simulate.result", "rollover_index"),
    "run": ("simulate.closed_loop", "run"),
    "run_open_loop": ("simulate.run", "simulate"),
    "threshold_velocity": ("analysis.threshold", "threshold_velocity"),
    "tilt_table": ("analysis.tilt", "tilt_table"),
    "summary": ("analysis.metrics", "summary"),
    "read_tir": ("tyre.tir", "read_tir"),
    "list_manoeuvres": ("manoeuvres.registry", "available"),
    "build_manoeuvre": ("manoeuvres.registry", "build"),
    "drive": ("simulate.closed_loop", "drive"),
    "compare": ("analysis.compare", "compare"),
    "override": ("params", "override"),
    "run_study": ("study.designs.runner", "run_study"),
}


def __getattr__(name):
    """A name of the flat API, imported from its module on first use (then cached in this module)."""
    if name not in _LAZY:
        raise AttributeError(f"module 'trikedyn' has no attribute {name!r}")
    import importlib

    module, attribute = _LAZY[name]
    value = getattr(importlib.import_module(f".{module}", __name__), attribute)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))


__all__ = ["__version__", *_LAZY]
"""The flat API: the names of the lazy table (no second list to keep in step)."""
