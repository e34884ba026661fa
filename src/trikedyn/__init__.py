"""trikedyn: stability analysis of three-wheeled electric vehicles.

The flat public API::

    import trikedyn as td
    trike = td.load_vehicle("reference-etrike")
"""

__version__ = "0.1.0"


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

from .errors import InputError, LogFormatError, ParameterError, SimulationError, TrikedynError

# The flat API, each name imported from its module when first used (``import trikedyn`` and
# ``trikedyn --version`` load neither scipy, pandas nor the compiled model).
_LAZY = {
    "Box": ("mechanics", "Box"),
    "MassProperties": ("mechanics", "MassProperties"),
    "Payload": ("mechanics", "Payload"),
    "PointMass": ("mechanics", "PointMass"),
    "ImuLog": ("measure.logs", "ImuLog"),
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
    "threshold_velocity": ("analysis.threshold", "threshold_velocity"),
    "tilt_table": ("analysis.tilt", "tilt_table"),
    "summary": ("analysis.metrics", "summary"),
    "read_tir": ("tyre.tir", "read_tir"),
    "list_manoeuvres": ("manoeuvres.registry", "available"),
    "build_manoeuvre": ("manoeuvres.registry", "build"),
    "drive": ("simulate.closed_loop", "drive"),
    "compare": ("analysis.compare", "compare"),
    "override": ("params", "override"),
    "run_study": ("study.runner", "run_study"),
}


from . import simulate as _simulate_package  # noqa: E402,F401  (light; bound first so the name below wins)


def simulate(*args, **kwargs):
    """Open-loop simulation: :func:`trikedyn.simulate.run.simulate` (imported on first call).

    Parameters
    ----------
    *args, **kwargs
        As :func:`trikedyn.simulate.run.simulate`.

    Returns
    -------
    Result
        The recorded run.
    """
    from .simulate.run import simulate as _simulate

    return _simulate(*args, **kwargs)


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


__all__ = [
    "Box",
    "ImuLog",
    "InputError",
    "LogFormatError",
    "MassProperties",
    "ParameterError",
    "ParameterSet",
    "Result",
    "Road",
    "Payload",
    "PointMass",
    "SimulationError",
    "TrikedynError",
    "VehicleParameters",
    "__version__",
    "audit",
    "build_manoeuvre",
    "build_model",
    "compare",
    "compare_layouts",
    "drive",
    "mirror_layout",
    "override",
    "read_tir",
    "rhs",
    "flat_road",
    "modes",
    "rollover_index",
    "run",
    "run_study",
    "simulate",
    "summary",
    "threshold_velocity",
    "tilt_table",
    "list_manoeuvres",
    "speed_bump",
    "static_equilibrium",
    "identify_suspension",
    "list_presets",
    "load_vehicle",
    "read_log",
    "reduce_weighing",
    "save_vehicle",
    "scale_suspension",
    "with_freight",
    "with_payload",
    "write_log",
]
