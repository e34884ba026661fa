"""Simulation: the compiled fixed-step loop, results and output channels."""

from .defaults import DEFAULT_DT_S

__all__ = ["DEFAULT_DT_S"]
