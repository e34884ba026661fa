"""Vehicle parameter sets: schema, TOML load/save, presets, variants, design knobs and the consistency audit."""

from .audit import Finding, audit, static_wheel_loads, tip_over_thresholds
from .io import ParameterSet, load_vehicle, parse_vehicle
from .knobs import KNOBS, apply_knobs, knob_names
from .layouts import mirror_layout
from .ops import freight, mass_properties, override, scale_suspension, with_freight, with_payload
from .save import save_vehicle
from .schema import VehicleParameters
from .shipped import list_presets

__all__ = [
    "KNOBS",
    "Finding",
    "ParameterSet",
    "VehicleParameters",
    "apply_knobs",
    "audit",
    "freight",
    "knob_names",
    "list_presets",
    "load_vehicle",
    "mass_properties",
    "mirror_layout",
    "override",
    "parse_vehicle",
    "save_vehicle",
    "scale_suspension",
    "static_wheel_loads",
    "tip_over_thresholds",
    "with_freight",
    "with_payload",
]
