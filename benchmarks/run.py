"""Speed benchmarks (``make bench``): prints the figures and writes them to ``benchmarks/results.json``.

Each timing is the best of several repeats after a warm-up run (numba compilation excluded), on one core.
Not part of ``make test``: timings depend on the machine.
"""

from __future__ import annotations

import json
import os
import platform
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from batch import bench_batch  # noqa: E402  (benchmarks/batch.py, issue 25)
from cluster import bench_cluster  # noqa: E402  (benchmarks/cluster.py, issue 23)
from cluster import report as report_cluster  # noqa: E402
from codegen import bench_generated_kernels  # noqa: E402  (benchmarks/codegen.py, issue 25)
from lane_math import bench_lane_math  # noqa: E402  (benchmarks/lane_math.py, issue 25)
from lanes import bench_lane_kernels  # noqa: E402  (benchmarks/lanes.py, issue 25)
from step_parts import parts as step_parts  # noqa: E402  (benchmarks/step_parts.py, issue 25)

from trikedyn import __version__  # noqa: E402
from trikedyn.model.statics import rolling_state, static_equilibrium  # noqa: E402
from trikedyn.model.vehicle import build_model  # noqa: E402
from trikedyn.params import load_vehicle  # noqa: E402
from trikedyn.simulate import DEFAULT_DT_S  # noqa: E402
from trikedyn.simulate.integrator import OPEN_LOOP  # noqa: E402
from trikedyn.simulate.run import input_table, simulate, stop_step  # noqa: E402
from trikedyn.simulate.specialised import kernel_choice, time_loop  # noqa: E402

REPEATS = 7


def best_of(func, repeats=REPEATS):
    func()  # warm-up (compilation, caches)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return min(times)


def sine_steer(t):
    """The sine-steer run: 0.03 rad at 0.5 Hz about the steering axis."""
    return 0.03 * np.sin(2 * np.pi * 0.5 * t)


def bench_sine_steer() -> dict:
    """Issue 3: a 10 s, 30 km/h sine-steer run of reference-etrike."""
    model = build_model(load_vehicle("reference-etrike"))
    duration = 10.0

    def run():
        simulate(model, duration_s=duration, speed_kmh=30.0, steer_rad=sine_steer, drive_torque_Nm=50.0)

    end_to_end = best_of(run)
    # the compiled loop alone, and one right-hand-side evaluation
    eq = static_equilibrium(model)
    x0 = rolling_state(model, eq, 30 / 3.6)
    dt = DEFAULT_DT_S  # the default step (exponential RK4, trikedyn.simulate.exponential)
    inputs = input_table(duration, dt, sine_steer, 50.0)
    rk4_loop = time_loop(model.plant)  # the loop the run took: the kernels generated for the tree by default
    loop = best_of(lambda: rk4_loop(x0, 0.0, dt, int(duration / dt), 2, inputs, *OPEN_LOOP, model.plant, True,
                                    stop_step(model)[0]))
    per_eval = loop / (4 * int(duration / dt))  # four stages a step, with the step's other work shared out
    return {
        "sine_steer_10s_30kmh": {
            "simulated_s": duration,
            "time_step_s": dt,
            "wall_s": end_to_end,
            "real_time_factor": duration / end_to_end,
            "loop_wall_s": loop,
            "loop_real_time_factor": duration / loop,
            "rhs_evaluation_us": per_eval * 1e6,
        }
    }


def bench_double_lane_change() -> dict:
    """Issue 4: a 10 s closed-loop ISO 3888-1 double lane change at 30 km/h (driver in the loop)."""
    from trikedyn.manoeuvres.paths import double_lane_change
    from trikedyn.simulate.closed_loop import drive

    pset = load_vehicle("reference-etrike")
    model = build_model(pset)
    path = double_lane_change(pset.params.body.overall_width_m)
    duration = 10.0
    wall = best_of(lambda: drive(model, path, 30.0, duration_s=duration))
    return {"double_lane_change_10s_30kmh": {"simulated_s": duration, "wall_s": wall, "real_time_factor": duration / wall}}


def bench_threshold() -> dict:
    """Issues 5, 11 and 19: one threshold search on the double lane change (reference-etrike, 0.1 km/h, the
    default course criterion), by the margin search and by bisection; then both on every scenario of the
    paper's study under each criterion (runs per search, time per search, agreement): with the spec's ideal
    speed control, and the course criterion again with the driver's (the single lane change then stops at the
    top speed)."""
    import statistics

    from trikedyn.analysis.threshold import threshold_velocity
    from trikedyn.params import override, scale_suspension, with_freight
    from trikedyn.study.scenarios import expand
    from trikedyn.study.spec import load_spec

    model = build_model(load_vehicle("reference-etrike"))
    out = {}
    for method in ("margin", "bisection"):
        holder = {}

        def search(method=method, holder=holder):
            holder["result"] = threshold_velocity(model, "dlc", method=method)

        wall = best_of(search, 3)
        r = holder["result"]
        out[f"threshold_search_dlc_{method}"] = {"wall_s": wall, "runs": r.n_runs, "speeds_kmh": list(r.speeds_kmh),
                                                 "threshold_speed_kmh": r.threshold_speed_kmh, "limit": r.limit,
                                                 "criterion": r.criterion}
    spec = load_spec("paper")
    base = spec.load_vehicle()
    scenarios = list(expand(spec))
    models = []
    for s in scenarios:
        pset = scale_suspension(base, stiffness=s["stiffness_scale"], damping=s["damping_scale"])
        if s["overrides"]:
            pset = override(pset, s["overrides"])
        models.append(build_model(with_freight(pset, s["freight_kg"])))
    cases = (("course", spec.speed_control), ("lift-off", spec.speed_control), ("course", "driver"))
    for criterion, control in cases:
        per = {"margin": {"runs": [], "wall_s": []}, "bisection": {"runs": [], "wall_s": []}}
        agree = 0
        for s, m in zip(scenarios, models, strict=True):
            found = {}
            for method in per:
                start = time.perf_counter()
                r = threshold_velocity(m, s["manoeuvre"], options=s["manoeuvre_options"] or None,
                                       low_kmh=s["low_kmh"], high_kmh=s["high_kmh"],
                                       step_kmh=s["step_kmh"], resolution_kmh=s["resolution_kmh"], method=method,
                                       criterion=criterion, speed_control=control)
                per[method]["wall_s"].append(time.perf_counter() - start)
                per[method]["runs"].append(r.n_runs)
                found[method] = (r.threshold_speed_kmh, r.limit)
            agree += found["margin"] == found["bisection"]
        out[f"threshold_search_paper_study_{criterion}_{control}"] = {
            "scenarios": len(scenarios), "criterion": criterion, "speed_control": control,
            "same_threshold_as_bisection": agree,
            **{f"{method}_{key}": value for method, v in per.items() for key, value in (
                ("median_runs", statistics.median(v["runs"])), ("mean_runs", statistics.fmean(v["runs"])),
                ("max_runs", max(v["runs"])), ("mean_wall_s", statistics.fmean(v["wall_s"])))},
            "target_median_runs": 6 if criterion == "course" else None,
        }
    return out


def bench_study_and_reproduce(repeats: int = 3) -> dict:
    """Issues 5 and 11: the built-in study on 2 workers, and `trikedyn reproduce`, each ``repeats`` times from
    a fresh folder; the median and the range (the machine's load moves a single run by a third)."""
    import shutil
    import subprocess
    import tempfile

    commands = {
        "study_paper_2_workers": (["study", "paper", "--workers", "2"], 2.0),  # issue 25's target (issue 11: 5 s)
        "reproduce": (["reproduce"], 12.0),
        "assess_quick": (["assess", "reference-etrike", "--quick"], 60.0),  # issue 24
    }
    out = {}
    for name, (args, target) in commands.items():
        walls, parts = [], []
        for _ in range(repeats):
            folder = Path(tempfile.mkdtemp(prefix="trikedyn-bench-"))
            start, started_at = time.perf_counter(), time.time()
            subprocess.run([sys.executable, "-m", "trikedyn", *args, "--out", str(folder / "out")], check=True,
                           capture_output=True)
            walls.append(time.perf_counter() - start)
            if args[0] == "study":
                parts.append(study_phases(folder / "out", started_at, started_at + walls[-1]))
            shutil.rmtree(folder, ignore_errors=True)
        out[name] = {"wall_s": float(np.median(walls)), "min_s": min(walls), "max_s": max(walls), "runs": repeats,
                     "target_s": target}
        if parts:  # the phases of the run of median wall time
            out[name]["phases"] = parts[int(np.argsort(walls)[len(walls) // 2])]
    return out


def study_phases(folder: Path, started_at: float, ended_at: float) -> dict:
    """Where a study's wall time went, from the rows of its store in ``folder`` (each scenario's ``finished_at``
    [s since the epoch] and ``wall_time_s``, stamped by the worker): until its first scenario was done (the
    command's start, the pool's fork server's imports, a worker's first search, which also loads the compiled
    code), from the first to the last, and after it (the export and the figures); with the scenarios' summed
    and median time."""
    from trikedyn.study.engine.store import StudyStore

    with StudyStore(folder) as store:
        rows = store.rows()
    done = sorted(r["finished_at"] for r in rows)
    search = [r["wall_time_s"] for r in rows]
    return {"until_first_result_s": done[0] - started_at, "first_to_last_result_s": done[-1] - done[0],
            "after_last_result_s": ended_at - done[-1], "scenarios": len(rows), "search_sum_s": float(np.sum(search)),
            "search_median_s": float(np.median(search))}


def bench_peer(dlc: dict) -> dict:
    """Issue 11: the CommonRoad multi-body model on its own 10 s lane change, in this process."""
    from commonroad_peer import lane_change_real_time_factor

    rtf = lane_change_real_time_factor()
    if rtf is None:
        return {"commonroad_mb_lane_change_10s": None}
    ours = dlc["double_lane_change_10s_30kmh"]["real_time_factor"]
    return {"commonroad_mb_lane_change_10s": {"real_time_factor": rtf, "trikedyn_dlc_over_commonroad": ours / rtf,
                                              "target_ratio": 300.0}}


def bench_startup() -> dict:
    """Issue 11: wall time of ``trikedyn --version`` and ``trikedyn vehicle list`` (warm cache, best of 3)."""
    import subprocess

    exe = Path(sys.executable).with_name("trikedyn")
    out = {}
    for name, args in (("version", ["--version"]), ("vehicle_list", ["vehicle", "list"])):
        def call(args=args):
            subprocess.run([str(exe), *args], check=True, capture_output=True)

        call()
        out[name] = best_of(call, 3)
    return {"startup_s": out}


def main() -> int:
    results = {
        "trikedyn": __version__,
        "python": sys.version.split()[0],
        "machine": platform.machine(),
        "processor": platform.processor() or platform.machine(),
        "cpus": os.cpu_count(),
    }
    results.update(bench_sine_steer())
    results.update(bench_generated_kernels())
    results.update(bench_lane_kernels())
    results.update(bench_lane_math())
    results.update(bench_double_lane_change())
    results["step_parts_reference_etrike_us"] = step_parts("reference-etrike")
    results.update(bench_peer(results))
    results.update(bench_startup())
    results.update(bench_threshold())
    results.update(bench_batch())
    results.update(bench_study_and_reproduce())
    results.update(bench_cluster())
    out = Path(__file__).with_name("results.json")
    out.write_text(json.dumps(results, indent=2))
    s = results["sine_steer_10s_30kmh"]
    print(f"sine steer, 10 s at 30 km/h (reference-etrike, dt {s['time_step_s'] * 1e3:g} ms, {kernel_choice()} kernels):")
    print(f"  end to end  {s['wall_s'] * 1e3:7.1f} ms   real-time factor {s['real_time_factor']:6.0f}")
    print(f"  loop only   {s['loop_wall_s'] * 1e3:7.1f} ms   real-time factor {s['loop_real_time_factor']:6.0f}")
    print(f"  per right-hand-side evaluation, the step's other work included (4 per step) {s['rhs_evaluation_us']:.2f} us")
    k = results["forward_dynamics_generated_vs_generic"]
    print(f"forward dynamics, generic {k['generic_us']:.2f} us, generated for the tree {k['generated_us']:.2f} us: {k['speedup']:.1f}x")
    lk = results["lane_kernels"]
    print(f"lane kernels (the lockstep batch's kinematics and dynamics): scalar generated forward dynamics {lk['scalar_dynamics_us']:.3f} us, "
          f"kinematics {lk['scalar_kinematics_us']:.3f} us, dynamics keeping the factor {lk['scalar_factor_us']:.3f} us; "
          "per lane-evaluation " + ", ".join(
              f"B={b} {v['dynamics_us']:.3f}/{v['kinematics_us']:.3f}/{v['factor_us']:.3f} us "
              f"({v['dynamics_speedup']:.1f}x/{v['kinematics_speedup']:.1f}x/{v['factor_speedup']:.1f}x)"
              for b, v in lk["lanes"].items()))
    print("branch-free functions over lanes (trikedyn.model.lane_math) against the C library, ns a value: " + ", ".join(
        f"{k} {v['lanes_ns']:.2f}/{v['library_ns']:.2f}" for k, v in results["lane_math_ns_per_value"].items()))
    d = results["double_lane_change_10s_30kmh"]
    print("closed-loop ISO 3888-1 double lane change, 10 s at 30 km/h:")
    print(f"  end to end  {d['wall_s'] * 1e3:7.1f} ms   real-time factor {d['real_time_factor']:6.0f} (target 1500)")
    sp = results["step_parts_reference_etrike_us"]
    print("  a step's parts [us per call]: right-hand side " f"{sp['rhs_generated_us']:.2f} (x4; generic {sp['rhs_generic_us']:.2f}),"
          f" of which kinematics {sp['kinematics_generated_us']:.2f} and tyres/springs {sp['wrenches_us']:.2f};"
          f" spin-slip blocks {sp['spin_slip_blocks_us']:.2f}, their functions {sp['block_functions_us']:.2f},"
          f" driver {sp['driver_step_us']:.2f}")
    peer = results["commonroad_mb_lane_change_10s"]
    if peer is None:
        print("CommonRoad multi-body model: not installed (pip install commonroad-vehicle-models)")
    else:
        print(f"CommonRoad multi-body model (scipy odeint), its 10 s lane change: real-time factor "
              f"{peer['real_time_factor']:.1f}; trikedyn's DLC is {peer['trikedyn_dlc_over_commonroad']:.0f}x faster (target 300x)")
    su = results["startup_s"]
    print(f"trikedyn --version {su['version']:.2f} s (target 0.3 s), trikedyn vehicle list {su['vehicle_list']:.2f} s"
          " (target 0.8 s)")
    t, b = results["threshold_search_dlc_margin"], results["threshold_search_dlc_bisection"]
    print(f"threshold search, DLC ({t['criterion']}): {t['wall_s']:.2f} s ({t['runs']} runs) -> {t['threshold_speed_kmh']} km/h ({t['limit']});"
          f" bisection {b['wall_s']:.2f} s ({b['runs']} runs) -> {b['threshold_speed_kmh']} km/h")
    for key, p in results.items():
        if not key.startswith("threshold_search_paper_study_"):
            continue
        target = f"; target <= {p['target_median_runs']}" if p["target_median_runs"] else ""
        print(f"threshold searches over the paper's study ({p['scenarios']} scenarios, {p['criterion']} criterion, "
              f"{p['speed_control']} speed control): median {p['margin_median_runs']:g} runs per search (mean "
              f"{p['margin_mean_runs']:.2f}, max {p['margin_max_runs']}{target}), {p['margin_mean_wall_s']:.2f} s per "
              f"search; bisection median {p['bisection_median_runs']:g} runs, {p['bisection_mean_wall_s']:.2f} s; same "
              f"threshold and limit in {p['same_threshold_as_bisection']}/{p['scenarios']}")
    for kind in ("closed", "open"):
        b = results[f"batch_{kind}_loop_10s"]
        print(f"10 s {kind}-loop runs per core-second (target {results['batch_target_runs_per_core_s']}): scalar loop "
              f"{b['scalar_loop_runs_per_core_s']:.0f} (end to end {b['scalar_end_to_end_runs_per_core_s']:.0f}), lockstep "
              f"batch of 8 {b['batch_8_loop_runs_per_core_s']:.0f} (end to end {b['batch_8_end_to_end_runs_per_core_s']:.0f}; "
              f"stepping each lane through the scalar step {b.get('batch_8_stepwise_loop_runs_per_core_s', float('nan')):.0f})")
    ts = results["batch_threshold_search"]
    print(f"threshold searches per core-second ({ts['scenarios']} scenarios of the paper's study; target 40): margin "
          f"{ts['margin_searches_per_core_s']:.1f} ({ts['margin_mean_runs']:.2f} runs each), batched "
          f"{ts['batch_searches_per_core_s']:.1f} ({ts['batch_mean_runs']:.2f} runs each); same threshold in "
          f"{ts['same_threshold']}/{ts['scenarios']}")
    st, rp = results["study_paper_2_workers"], results["reproduce"]
    print(f"built-in study, 2 workers: median {st['wall_s']:.1f} s of {st['runs']} ({st['min_s']:.1f}-{st['max_s']:.1f} s;"
          f" target {st['target_s']:g} s)")
    ph = st.get("phases")
    if ph:
        print(f"  that run: {ph['until_first_result_s']:.2f} s until the first scenario was done (start, fork server, first "
              f"search), {ph['first_to_last_result_s']:.2f} s to the last, {ph['after_last_result_s']:.2f} s after it "
              f"(export, figures); {ph['scenarios']} searches of {ph['search_sum_s']:.2f} s in all (median "
              f"{ph['search_median_s'] * 1e3:.0f} ms)")
    print(f"trikedyn reproduce: median {rp['wall_s']:.1f} s of {rp['runs']} ({rp['min_s']:.1f}-{rp['max_s']:.1f} s;"
          f" target {rp['target_s']:g} s)")
    aq = results["assess_quick"]
    print(f"trikedyn assess reference-etrike --quick: median {aq['wall_s']:.1f} s of {aq['runs']} ({aq['min_s']:.1f}-"
          f"{aq['max_s']:.1f} s; target {aq['target_s']:g} s)")
    report_cluster(results)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
