"""The simulation's defaults, kept apart so that the package and the compiled loop both import them from
here (light: no numba)."""

__all__ = ["DEFAULT_DT_S"]

DEFAULT_DT_S = 0.01
"""The loop's default time step [s]: 100 Hz, the default output rate's period. With the wheels' spin-slip
pairs exact (:mod:`trikedyn.simulate.exponential`) it keeps the wheel loads of the ISO 3888-1 lane change at
40 km/h within 0.1 % of the static load of DOP853 at rtol 1e-10 (``tests/physics/test_convergence.py``)."""
