"""The peer a Python user would pick: CommonRoad's multi-body car model (29 states, Magic Formula tyres),
integrated with scipy's ``odeint``, on its own 10 s lane change (for ``make bench``).

``commonroad-vehicle-models`` is installed into the bench's environment by ``make bench``; it is not a
dependency of trikedyn. Returns None when it is absent.
"""

from __future__ import annotations

import time

import numpy as np


def lane_change_real_time_factor(duration_s: float = 10.0, speed_mps: float = 30 / 3.6, repeats: int = 3):
    """Best-of-``repeats`` real-time factor of the CommonRoad multi-body model (vehicle 2, a VW Vanagon)
    through a sine-steer lane change: the steering rate ``0.4 sin(2 pi t / 2.5)`` rad/s for one period,
    then straight; constant speed (zero longitudinal acceleration); state recorded at 100 Hz."""
    try:
        from scipy.integrate import odeint
        from vehiclemodels.init_mb import init_mb
        from vehiclemodels.parameters_vehicle2 import parameters_vehicle2
        from vehiclemodels.vehicle_dynamics_mb import vehicle_dynamics_mb
    except ImportError:
        return None
    p = parameters_vehicle2()
    x0 = init_mb([0.0, 0.0, 0.0, speed_mps, 0.0, 0.0, 0.0], p)
    period = 2.5

    def rhs(x, t):
        steer_rate = 0.4 * np.sin(2 * np.pi * t / period) if t < period else 0.0
        return vehicle_dynamics_mb(x, [steer_rate, 0.0], p)

    grid = np.arange(0.0, duration_s + 1e-9, 0.01)
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        states = odeint(rhs, x0, grid)
        best = min(best, time.perf_counter() - start)
    assert np.all(np.isfinite(states)) and abs(states[-1, 1]) > 0.5  # it did change lane
    return duration_s / best
