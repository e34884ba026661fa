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
    for sub in (".", "model", "tyre", "simulate", "driver"):
        for path in sorted((here / sub).glob("*.py")):
            digest.update(path.read_bytes())
    base = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
    os.environ["NUMBA_CACHE_DIR"] = str(base / "trikedyn" / f"numba-{digest.hexdigest()[:16]}")
    import sys

    if "numba" in sys.modules:  # numba read its configuration already
        from numba.core import config

        config.reload_config()


_numba_cache_dir()

from .errors import InputError, LogFormatError, ParameterError, SimulationError, TrikedynError
from .measure.cg import Box, MassProperties, Payload, PointMass
from .measure.logs import ImuLog, read_log, write_log
from .measure.suspension import identify_suspension
from .measure.weighing import reduce_weighing
from .model.linear import modes
from .model.statics import static_equilibrium
from .model.vehicle import Road, build_model, flat_road, speed_bump
from .params import (
    ParameterSet,
    VehicleParameters,
    audit,
    list_presets,
    load_vehicle,
    save_vehicle,
    scale_suspension,
    with_freight,
    with_payload,
)
from .simulate.result import Result, rollover_index
from .simulate.run import simulate


def __getattr__(name):
    """The manoeuvre-level API, imported when first used: ``run``, ``threshold_velocity``, ``tilt_table``,
    ``summary`` (the metrics of a run) and ``list_manoeuvres`` (the registered manoeuvres)."""
    if name == "run":
        from .simulate.closed_loop import run

        return run
    if name == "threshold_velocity":
        from .analysis.threshold import threshold_velocity

        return threshold_velocity
    if name == "tilt_table":
        from .analysis.tilt import tilt_table

        return tilt_table
    if name == "summary":
        from .analysis.metrics import summary

        return summary
    if name == "list_manoeuvres":
        from .manoeuvres.registry import available

        return available
    raise AttributeError(f"module 'trikedyn' has no attribute {name!r}")

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
    "build_model",
    "flat_road",
    "modes",
    "rollover_index",
    "run",
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
