"""Rigid-body mechanics shared by measurement, parameters and the model: mass properties and their
composition, static support loads. Imports nothing else of trikedyn but its errors and units."""

from .mass import Box, MassProperties, Payload, PointMass, combine
from .support import wheel_loads_from_cg

__all__ = ["Box", "MassProperties", "Payload", "PointMass", "combine", "wheel_loads_from_cg"]
