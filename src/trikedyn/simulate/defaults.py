"""The simulation's defaults, kept apart so that the package and the compiled loop both import them from
here (light: no numba)."""

__all__ = ["DEFAULT_DT_S", "SPEED_CONTROLS"]

DEFAULT_DT_S = 0.01
"""The loop's default time step [s]: 100 Hz, the default output rate's period. With the wheels' spin-slip
pairs exact (:mod:`trikedyn.simulate.exponential`) it keeps the wheel loads of the ISO 3888-1 lane change at
40 km/h within 0.1 % of the static load of DOP853 at rtol 1e-10 (``tests/physics/test_convergence.py``)."""

SPEED_CONTROLS = ("driver", "ideal")
"""How a closed-loop run holds its target speed (:func:`trikedyn.simulate.closed_loop.run`): ``"driver"``, the
PI controller on the vehicle's own drive and brakes, within their torque and power limits; ``"ideal"``, the same
controller on a drive and brakes without limits (the speed a multibody package's kinematic drive would
impose, whatever the vehicle's motor can give). Here, not in
:mod:`~trikedyn.simulate.closed_loop`, so that checking a search's settings does not load the simulation
(numba, the model): a study's main process only hands the searches to its workers."""
