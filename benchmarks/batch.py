"""Issue 25: lockstep batches against the scalar loop, and the batched threshold search, in one process.

Throughput is ten-second runs per core-second (CPU time of this process, one thread): closed loop (the ISO
3888-1 double lane change at 26-34 km/h, cut to 10 s: none lifts a wheel) and open loop (a 0.5 Hz sine steer
at 30 km/h), the compiled loop alone (the scalar loop once per run; the batch loop once per batch of B lanes)
and end to end (results built). Threshold searches per core-second: the margin search against the batched
one (``method="batch"``) on a few scenarios of the paper's study, with the runs and rounds each takes.

usage: python benchmarks/batch.py [--json]
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from trikedyn.model.statics import rolling_state, static_equilibrium  # noqa: E402
from trikedyn.model.vehicle import build_model  # noqa: E402
from trikedyn.params import load_vehicle  # noqa: E402
from trikedyn.simulate.batch import BATCH_KERNELS, plan, run_prepared  # noqa: E402
from trikedyn.simulate.closed_loop import prepare_run  # noqa: E402
from trikedyn.simulate.integrator import OPEN_LOOP  # noqa: E402
from trikedyn.simulate.run import input_table, loop_steps, run_model, stop_step, time_step  # noqa: E402
from trikedyn.simulate.specialised import kernel_choice, time_loop  # noqa: E402

REPEATS = 5
LANES = (1, 4, 8, 16)
JOBS = 16
DURATION_S = 10.0


def best_cpu(func, repeats=REPEATS):
    """Least CPU time [s] of ``repeats`` calls after a warm-up call (compilation excluded)."""
    func()
    times = []
    for _ in range(repeats):
        start = time.process_time()
        func()
        times.append(time.process_time() - start)
    return min(times)


def closed_loop_specs(model):
    """Sixteen 10 s double lane changes, 26-34 km/h."""
    return [prepare_run(model, "dlc", speed_kmh=float(v), duration_s=DURATION_S) for v in np.linspace(26, 34, JOBS)]


def open_loop_specs(model):
    """Sixteen 10 s sine-steer runs at 30 km/h, amplitudes 0.01-0.04 rad."""
    eq = static_equilibrium(model.on_flat_road())
    x0 = rolling_state(model, eq, 30 / 3.6)
    dt = time_step(model, x0, None)
    return [{"model": model, "x0": x0, "duration_s": DURATION_S, "dt": dt,
             "inputs": input_table(DURATION_S, dt, lambda t, a=a: a * np.sin(np.pi * t), 50.0)}
            for a in np.linspace(0.01, 0.04, JOBS)]


def throughput(specs) -> dict:
    """Runs per core-second: scalar loop and batch loop at each B, loop alone and end to end."""
    model = specs[0]["model"]
    loop = time_loop(model.plant)

    def scalar_loops():
        for s in specs:
            dt, every, n_steps = loop_steps(model, s["x0"], s["duration_s"], s.get("dt"), 100.0)
            closed = s.get("path") is not None
            args = (s["path"], s["speed_profile"], s["driver"]) if closed else OPEN_LOOP
            loop(s["x0"], 0.0, dt, n_steps, every, s["inputs"], *args, model.plant, True, stop_step(model)[0])

    def scalar_runs():
        for s in specs:
            run_model(**s, output_rate_hz=100.0, raise_on_failure=False)

    out = {"scalar_loop_runs_per_core_s": len(specs) / best_cpu(scalar_loops),
           "scalar_end_to_end_runs_per_core_s": len(specs) / best_cpu(scalar_runs)}
    _, batches = plan(specs)
    (plant, arguments, _), = batches
    batch = BATCH_KERNELS[kernel_choice()](plant)
    for lanes in LANES:
        out[f"batch_{lanes}_loop_runs_per_core_s"] = len(specs) / best_cpu(lambda lanes=lanes: batch(*arguments,
                                                                                                         lanes, True))
        out[f"batch_{lanes}_end_to_end_runs_per_core_s"] = len(specs) / best_cpu(
            lambda lanes=lanes: run_prepared(specs, lanes=lanes))
    if kernel_choice() == "generated":  # the same batch with each lane through the scalar step (the reference)
        stepwise = BATCH_KERNELS["generated-scalar"](plant)
        out["batch_8_stepwise_loop_runs_per_core_s"] = len(specs) / best_cpu(lambda: stepwise(*arguments, 8, True))
    n_steps = int(round(DURATION_S / arguments[12]))
    out["scalar_loop_us_per_step"] = 1e6 / out["scalar_loop_runs_per_core_s"] / n_steps
    out["batch_8_loop_us_per_lane_step"] = 1e6 / out["batch_8_loop_runs_per_core_s"] / n_steps
    return out


def searches(count: int = 4) -> dict:
    """Threshold searches per core-second, margin and batch, on ``count`` scenarios of the paper's study
    (course criterion, the spec's speed control)."""
    from trikedyn.analysis.threshold import threshold_velocity
    from trikedyn.params import scale_suspension, with_freight
    from trikedyn.study.scenarios import expand
    from trikedyn.study.spec import load_spec

    spec = load_spec("paper")
    base = spec.load_vehicle()
    scenarios = [s for s in expand(spec) if not s["overrides"]]
    scenarios = scenarios[:: max(1, len(scenarios) // count)][:count]
    per = {"margin": {"cpu_s": [], "runs": []}, "batch": {"cpu_s": [], "runs": []}}
    agree = 0
    for s in scenarios:
        model = build_model(with_freight(scale_suspension(base, stiffness=s["stiffness_scale"],
                                                          damping=s["damping_scale"]), s["freight_kg"]))
        found = {}
        for method, v in per.items():
            def search(method=method, model=model, s=s):
                return threshold_velocity(model, s["manoeuvre"], low_kmh=s["low_kmh"], high_kmh=s["high_kmh"],
                                          step_kmh=s["step_kmh"], resolution_kmh=s["resolution_kmh"], method=method,
                                          speed_control=s["speed_control"])

            result = search()  # warm-up
            v["cpu_s"].append(best_cpu(search, 3))
            v["runs"].append(result.n_runs)
            found[method] = (result.threshold_speed_kmh, result.limit)
        agree += found["margin"] == found["batch"]
    return {"scenarios": len(scenarios), "same_threshold": agree,
            **{f"{m}_searches_per_core_s": 1.0 / statistics.fmean(v["cpu_s"]) for m, v in per.items()},
            **{f"{m}_mean_runs": statistics.fmean(v["runs"]) for m, v in per.items()}}


def bench_batch() -> dict:
    """The figures of this module, for ``benchmarks/run.py``."""
    model = build_model(load_vehicle("reference-etrike"))
    return {"batch_closed_loop_10s": throughput(closed_loop_specs(model)),
            "batch_open_loop_10s": throughput(open_loop_specs(model)),
            "batch_threshold_search": searches(), "batch_target_runs_per_core_s": 500}


def main() -> int:
    figures = bench_batch()
    if "--json" in sys.argv:
        print(json.dumps(figures, indent=2))
        return 0
    for name, value in figures.items():
        if isinstance(value, dict):
            print(name)
            for key, number in value.items():
                print(f"  {key:40s} {number:10.2f}" if isinstance(number, float) else f"  {key:40s} {number}")
        else:
            print(f"{name:42s} {value}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
