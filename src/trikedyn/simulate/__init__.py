"""Simulation: the compiled fixed-step loop, results and output channels."""
