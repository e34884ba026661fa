"""Issue 25: where a step of the generated closed-loop time loop spends its time, part by part, one process.

Each part runs inside compiled code ``N`` times on a state of a 30 km/h double lane change of reference-etrike,
an input nudged each call so LLVM can neither drop nor hoist the work; the figure is the best of 5, in
microseconds per call. A step of the exponential RK4 is four right-hand sides, the spin-slip blocks and their
matrix functions once, the driver once, and the stage arithmetic.

usage: python benchmarks/step_parts.py [vehicle]
"""

from __future__ import annotations

import os
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

from trikedyn.driver.preview import DRIVER_STATE, driver_step  # noqa: E402
from trikedyn.model.dynamics import joint_transforms_into  # noqa: E402
from trikedyn.model.kinematics import body_velocities_into, world_transforms_into  # noqa: E402
from trikedyn.model.packing import WHEEL_OUT  # noqa: E402
from trikedyn.model.rhs import evaluate_into, workspace, wrenches_into  # noqa: E402
from trikedyn.model.vehicle import build_model  # noqa: E402
from trikedyn.params import load_vehicle  # noqa: E402
from trikedyn.simulate.closed_loop import prepare_run  # noqa: E402
from trikedyn.simulate.exponential import BLOCK_WIDTH, block_functions  # noqa: E402
from trikedyn.simulate.specialised import loop_module  # noqa: E402

N = 100_000
REPEATS = 5


def best_us(func) -> float:
    """Least time per call [us] of ``REPEATS`` runs of ``func(N)`` after a warm-up."""
    func(10)
    best = np.inf
    for _ in range(REPEATS):
        start = time.perf_counter()
        func(N)
        best = min(best, time.perf_counter() - start)
    return best / N * 1e6


def parts(vehicle: str = "reference-etrike") -> dict:
    """Microseconds per call of each part of a step on ``vehicle``."""
    model = build_model(load_vehicle(vehicle))
    p, n = model.plant, model.n_dof
    module = loop_module(p)
    spec = prepare_run(model, "dlc", speed_kmh=30.0, duration_s=10.0)
    x = np.ascontiguousarray(spec["x0"], dtype=float)
    u = np.array([0.01, 20.0, 0.0])
    nw = p.wheels.shape[0]
    wout, ws, xdot = np.zeros(nw, WHEEL_OUT), workspace(p.parent), np.zeros(x.size)
    generated, blocks_of = module.evaluate_into, module.spin_slip_blocks
    scratch, idx, mat, fn = np.empty(n), np.zeros((nw, 2), np.int64), np.zeros((nw, 4)), np.zeros((nw, BLOCK_WIDTH))
    generated(0.0, x, u, p, wout, ws, xdot)
    m = blocks_of(p, wout, ws.low, scratch, idx, mat)

    def rhs(evaluate):
        @njit
        def loop(count, x, u, p, wout, ws, xdot):
            total = 0.0
            for _ in range(count):
                x[0] += 1e-12
                evaluate(0.0, x, u, p, wout, ws, xdot)
                total += xdot[-1]
            return total
        return lambda count: loop(count, x, u, p, wout, ws, xdot)

    @njit
    def kinematics(count, x, p, ws, n):
        total = 0.0
        for _ in range(count):
            x[0] += 1e-12
            joint_transforms_into(x[:n], p.parent, p.jtype, p.jaxis, p.tree_e, p.tree_r, ws.e, ws.r, ws.t33)
            world_transforms_into(p.parent, ws.e, ws.r, ws.ew, ws.pw)
            body_velocities_into(ws.e, ws.r, x[n:2 * n], p.parent, p.jtype, p.jaxis, ws.v)
            total += ws.v[3, 2]
        return total

    kinematics_into = module.kinematics_into

    @njit
    def generated_kinematics(count, x, p, ws, n):
        total = 0.0
        for _ in range(count):
            x[0] += 1e-12
            kinematics_into(x[:n], x[n:2 * n], p.tree_e, p.tree_r, ws.e, ws.r, ws.ew, ws.pw, ws.v)
            total += ws.v[3, 2]
        return total

    @njit
    def wrenches(count, x, u, p, wout, ws, xdot):
        total = 0.0
        for _ in range(count):
            x[0] += 1e-12
            wrenches_into(0.0, x, u, p.wheels, p.tyres, p.vehicle, p.road, wout, ws.ew, ws.pw, ws.v, ws.fext, ws.tau,
                          xdot)
            total += xdot[-1] + ws.tau[6]
        return total

    @njit
    def spin_slip(count, p, wout, low, scratch, idx, mat):
        total = 0
        for _ in range(count):
            low[0, 0] += 1e-15
            total += blocks_of(p, wout, low, scratch, idx, mat)
        return total

    @njit
    def functions(count, mat, m, fn):
        total = 0.0
        for i in range(count):
            block_functions(mat, m, 0.01 + i * 1e-12, fn)
            total += fn[0, 3]
        return total

    @njit
    def driver(count, x, n, path, speeds, drv, veh, inputs):
        d = drv[0]
        memory, delay = np.zeros(1, DRIVER_STATE), np.zeros(d.delay_steps + 2)
        total = 0.0
        for i in range(count):
            t = (i % 1000) * 0.01
            a, b, _ = driver_step(t, 0.01, x[0] + 8.3 * t, x[1], x[5], x[n + 2], x[n + 3], path, speeds, d, veh[0],
                                  memory, delay, inputs)
            total += a + b
        return total

    path, speeds, drv, inputs = spec["path"], spec["speed_profile"], spec["driver"], spec["inputs"]
    low = ws.low.copy()
    return {"rhs_generic_us": best_us(rhs(evaluate_into)), "rhs_generated_us": best_us(rhs(generated)),
            "kinematics_generic_us": best_us(lambda c: kinematics(c, x, p, ws, n)),
            "kinematics_generated_us": best_us(lambda c: generated_kinematics(c, x, p, ws, n)),
            "wrenches_us": best_us(lambda c: wrenches(c, x, u, p, wout, ws, xdot)),
            "spin_slip_blocks_us": best_us(lambda c: spin_slip(c, p, wout, low, scratch, idx, mat)),
            "block_functions_us": best_us(lambda c: functions(c, mat, m, fn)),
            "driver_step_us": best_us(lambda c: driver(c, x, n, path, speeds, drv, p.vehicle, inputs)), "blocks": int(m)}


if __name__ == "__main__":
    name = sys.argv[1] if len(sys.argv) > 1 else "reference-etrike"
    for key, value in parts(name).items():
        print(f"{name} {key:26s} {value:8.3f}" if isinstance(value, float) else f"{name} {key:26s} {value}")
