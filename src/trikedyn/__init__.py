"""trikedyn: stability analysis of three-wheeled electric vehicles.

The flat public API::

    import trikedyn as td
    trike = td.load_vehicle("reference-etrike")
"""

__version__ = "0.1.0"

from .errors import InputError, LogFormatError, ParameterError, SimulationError, TrikedynError  # noqa: E402
from .measure.cg import Box, MassProperties, Payload, PointMass  # noqa: E402
from .measure.logs import ImuLog, read_log, write_log  # noqa: E402
from .measure.suspension import identify_suspension  # noqa: E402
from .measure.weighing import reduce_weighing  # noqa: E402
from .params import (  # noqa: E402
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

__all__ = [
    "Box",
    "ImuLog",
    "InputError",
    "LogFormatError",
    "MassProperties",
    "ParameterError",
    "ParameterSet",
    "Payload",
    "PointMass",
    "SimulationError",
    "TrikedynError",
    "VehicleParameters",
    "__version__",
    "audit",
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
