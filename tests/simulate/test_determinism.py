"""A closed-loop run is deterministic: the same inputs give the same numbers, bit for bit, run after run.

It guards the compiled loop's memory: a driver state taken from a temporary array (freed while the loop still
wrote to it) once made closed-loop runs depend on what else the process had allocated.
"""

import numpy as np

import trikedyn as td
from trikedyn.model.vehicle import build_model


def test_closed_loop_runs_repeat_bit_for_bit(reference):
    model = build_model(reference)
    first = td.run(model, "dlc", speed_kmh=35.0)
    for speed in (20.0, 35.0, 45.0, 35.0):
        again = td.run(model, "dlc", speed_kmh=speed)
        junk = [np.random.default_rng(int(speed)).normal(size=1000) for _ in range(50)]  # churn the heap
        if speed == 35.0:
            assert np.array_equal(again.states, first.states)
        del junk
