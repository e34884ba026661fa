"""Issue 23: what a Dask cluster costs per evaluation (``python benchmarks/cluster.py``; also in ``make bench``).

Two jobs, each on a process pool of two (``--workers 2``) and on a real local cluster: a ``dask scheduler``
and two ``dask worker`` processes of one thread each on 127.0.0.1 (``--scheduler ADDR``), each from a fresh
folder:

- the paper's study (``trikedyn study paper``: its scenarios' threshold searches);
- a 520-search Morris screening: every assumed value of the reference trike that can vary (51 factors) with 10
  trajectories, 10 x (51 + 1) = 520 threshold searches on the double lane change
  (``trikedyn sensitivity reference-etrike --samples 10``, the defaults).

The cluster's overhead per evaluation is (cluster wall time - pool wall time) / evaluations. The cluster is
started and its workers warmed (a small Morris loads the compiled code in each) before the timing: a cluster's
workers live on from one job to the next, whereas a pool is started by each command. The machine's load
average is printed beside the figures: a shared machine moves them. Writes ``benchmarks/cluster.json``.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests.study.dask_processes import DaskProcesses  # noqa: E402  (the tests' real cluster on 127.0.0.1)

JOBS = {
    "study_paper": ["study", "paper", "--json"],
    "morris_520": ["sensitivity", "reference-etrike", "--samples", "10", "--json"],
}
"""The timed commands (``--out`` and the executor are added)."""

WARM_UP = ["sensitivity", "reference-etrike", "--samples", "2", "--resolution", "5", "-p", "track_m"]
"""A small Morris that makes each worker load the compiled code before the timing."""


def evaluations(name: str, data: dict) -> int:
    """The evaluations a job's JSON summary reports (the study's scenarios computed, the Morris's runs)."""
    return data["scenarios"]["computed"] if name == "study_paper" else data["n_runs"]


def timed(args: list[str], executor: list[str]) -> tuple[float, dict]:
    """Wall time [s] and JSON summary of one command from a fresh folder."""
    folder = Path(tempfile.mkdtemp(prefix="trikedyn-cluster-bench-"))
    try:
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "trikedyn", *args, *executor, "--out", str(folder / "out")],
                              capture_output=True, text=True, check=False)
        wall = time.perf_counter() - start
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(args + executor)}: exit {done.returncode}: {done.stderr[-2000:]}")
        return wall, json.loads(done.stdout)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def bench_cluster() -> dict:
    """Each job on ``--workers 2`` and on a local scheduler with two worker processes: wall times [s],
    evaluations, the overhead per evaluation [ms] and the load average before and after (None without
    ``distributed``)."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        return {"dask_cluster_overhead": None}
    out = {}
    with tempfile.TemporaryDirectory(prefix="trikedyn-dask-") as tmp, DaskProcesses(Path(tmp), workers=2) as cluster:
        timed(WARM_UP, ["--scheduler", cluster.address, "--json"])
        for name, args in JOBS.items():
            load_before = os.getloadavg()[0]
            pool_s, pool = timed(args, ["--workers", "2"])
            cluster_s, on_cluster = timed(args, ["--scheduler", cluster.address])
            n = evaluations(name, pool)
            if evaluations(name, on_cluster) != n:
                raise RuntimeError(f"{name}: {n} evaluations on the pool, {evaluations(name, on_cluster)} on the cluster")
            out[name] = {"evaluations": n, "pool_2_workers_s": pool_s, "cluster_2_workers_s": cluster_s,
                         "overhead_per_evaluation_ms": (cluster_s - pool_s) / n * 1e3,
                         "load_average_before": load_before, "load_average_after": os.getloadavg()[0]}
    return {"dask_cluster_overhead": out}


def report(results: dict) -> None:
    """Print the figures of :func:`bench_cluster`."""
    if results["dask_cluster_overhead"] is None:
        print("Dask cluster overhead: not measured (pip install 'trikedyn[dask]')")
        return
    targets = {"study_paper": 2.0, "morris_520": 20.0}  # issue 25, on 2 workers
    for name, r in results["dask_cluster_overhead"].items():
        print(f"{name}: {r['evaluations']} evaluations; --workers 2 {r['pool_2_workers_s']:.1f} s "
              f"(target {targets[name]:g} s), scheduler + 2 "
              f"workers {r['cluster_2_workers_s']:.1f} s: {r['overhead_per_evaluation_ms']:+.0f} ms per evaluation "
              f"(load average {r['load_average_before']:.1f} -> {r['load_average_after']:.1f} on "
              f"{os.cpu_count()} cores)")


def main() -> int:
    results = bench_cluster()
    Path(__file__).with_name("cluster.json").write_text(json.dumps(results, indent=2))
    report(results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
