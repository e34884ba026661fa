"""Issue 23's acceptance on a real Dask cluster: a ``dask scheduler`` and two ``dask worker`` processes on
127.0.0.1 (:class:`~tests.study.dask_processes.DaskProcesses`), the designs run through the CLI in
subprocesses with ``--scheduler ADDR``.

- A small Sobol (of the tilt angle) and a small Morris (of the threshold) give the same files on the scheduler
  as on ``--workers 2`` and in this process (``--workers 0``).
- One worker killed with SIGKILL in the middle of a Morris: the design completes on the other, each sample once.
- The scheduler killed in the middle of every sampled design (sensitivity, uncertainty, loading chart,
  optimiser, run at the same time on one cluster): each exits within 60 s with code 1 and one line saying it
  can be resumed; each re-run with ``--resume`` on a new scheduler ends with the files of an uninterrupted run.

"The same files": each run writes into a folder ``out`` of its own working directory (so that the paths
written in the files are the same); the results' JSON equal but for the run's time, the executor and the counts of resumed
and computed evaluations; the evaluations' logs (appended as evaluations finish, in whatever order the workers
end them) equal once sorted by their first column (the sample, cell or evaluation number), each number once;
every other file but the figures byte for byte (the figures are drawn from those files).
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

from . import warm_numba_cache
from .dask_processes import DaskProcesses

pytestmark = pytest.mark.slow  # a real scheduler and two workers, ~3 min: `make test-all` (see the Makefile)

pytest.importorskip("distributed", reason="the real-cluster tests need dask.distributed (pip install 'trikedyn[dask]')")

SOBOL = ["sensitivity", "reference-etrike", "--method", "sobol", "--samples", "2", "-p", "track_m,cg_height_m",
         "--metric", "tilt_angle", "--json"]
"""Sobol of the tilt angle: 2 base samples x (2 factors + 2) = 8 tilt tables."""

MORRIS = ["sensitivity", "reference-etrike", "--samples", "2", "--resolution", "5", "-p", "track_m,cg_height_m",
          "--json"]
"""Morris of the threshold (double lane change): 2 trajectories x (2 factors + 1) = 6 searches at 5 km/h."""

DESIGNS = {  # command, its evaluations' log, how many evaluations
    "sensitivity": (MORRIS, "sensitivity-samples.csv", 6),
    "uncertainty": (["uncertainty", "reference-etrike", "--samples", "6", "--resolution", "5", "-p", "track_m",
                     "--json"], "uncertainty-samples.csv", 6),
    "loading-chart": (["loading-chart", "reference-etrike", "--masses", "0,100,200", "--x", "0.5,0.9", "--z", "0.5",
                       "--resolution", "5", "--json"], "loading-chart-cells.csv", 6),
    "optimise": (["optimise", "reference-etrike", "--spec", "battery-layout", "--maxiter", "1", "--popsize", "1",
                  "--resolution", "5", "--json"], "optimise-evaluations.csv", 11),
}
"""Every sampled design, small: 6-11 threshold searches at 5 km/h each."""

VOLATILE = ("wall_time_s", "workers", "cells_resumed", "cells_computed", "resumed_evaluations")
"""JSON keys that differ between equal runs: the run's time, its executor, what a resumed run found done."""

PROGRESS = re.compile(r"^[\w-]+: \d+/\d+ ")
"""A progress line on stderr (``sensitivity: 3/6 runs``)."""


@pytest.fixture(scope="module", autouse=True)
def warm():
    warm_numba_cache()  # the workers load the compiled code instead of compiling it


@pytest.fixture(scope="module")
def _cluster(tmp_path_factory):
    with DaskProcesses(tmp_path_factory.mktemp("dask"), workers=2) as cluster:
        yield cluster


@pytest.fixture
def cluster(_cluster):
    """The module's scheduler with two live workers (a worker killed by a test is replaced)."""
    _cluster.ensure_workers()
    return _cluster


_LAUNCHED: list[subprocess.Popen] = []


@pytest.fixture(autouse=True)
def _end_launched():
    """A test that fails leaves no command running: each is ended by its process id."""
    yield
    _end(_LAUNCHED)


def _end(procs: list[subprocess.Popen]) -> None:
    """SIGKILL those of ``procs`` still running, by their process ids."""
    while procs:
        proc = procs.pop()
        if proc.poll() is None:
            proc.kill()
            proc.communicate(timeout=30)


def _launch(cwd: Path, *args: str) -> subprocess.Popen:
    cwd.mkdir(parents=True, exist_ok=True)
    proc = subprocess.Popen([sys.executable, "-m", "trikedyn", *args, "--out", "out"], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    _LAUNCHED.append(proc)
    return proc


def _finish(proc: subprocess.Popen, code: int = 0, timeout: float = 300) -> tuple[str, str]:
    out, err = proc.communicate(timeout=timeout)
    assert proc.returncode == code, (proc.args, proc.returncode, err[-3000:])
    return out, err


@pytest.fixture(scope="module")
def in_process(tmp_path_factory) -> Path:
    """The small Sobol and Morris run in one process each: ``<folder>/sobol/out``, ``<folder>/morris/out``."""
    folder = tmp_path_factory.mktemp("in-process")
    runs = [_launch(folder / name, *args, "--workers", "0") for name, args in (("sobol", SOBOL), ("morris", MORRIS))]
    try:
        for proc in runs:
            _finish(proc)
    finally:
        _end(runs)
    return folder


def _rows(log: Path) -> list[str]:
    """The log's rows (not its header) sorted by their number; each number must come once."""
    rows = log.read_text().splitlines()[1:]
    numbers = [int(row.split(",", 1)[0]) for row in rows]
    assert len(set(numbers)) == len(numbers), f"{log.name}: numbers logged twice: {sorted(numbers)}"
    return [row for _, row in sorted(zip(numbers, rows, strict=True))]


def _logged(log: Path) -> int:
    return max(len(log.read_text().splitlines()) - 1, 0) if log.exists() else 0


def _json(path: Path) -> dict:
    data = json.loads(path.read_text())
    assert "wall_time_s" in data, path
    return {key: value for key, value in data.items() if key not in VOLATILE}


def assert_same_files(got: Path, want: Path, log: str) -> None:
    """The files in ``got`` are those in ``want`` (see the module's notes on what "the same" means)."""
    names = sorted(p.name for p in want.iterdir())
    assert sorted(p.name for p in got.iterdir()) == names
    for name in names:
        if name.endswith(".png"):
            continue
        if name == log:
            assert _rows(got / name) == _rows(want / name), name
        elif name.endswith(".json") and not name.endswith("-plan.json"):  # a plan: byte for byte
            assert _json(got / name) == _json(want / name), name
        else:
            assert (got / name).read_bytes() == (want / name).read_bytes(), name


def test_sobol_and_morris_are_the_same_on_a_scheduler_a_pool_and_in_process(tmp_path, cluster, in_process):
    runs = {}
    for name, args in (("sobol", SOBOL), ("morris", MORRIS)):
        for executor in (["--scheduler", cluster.address], ["--workers", "2"]):
            runs[name, executor[0]] = _launch(tmp_path / name / executor[0].strip("-"), *args, *executor)
    for (name, executor), proc in runs.items():
        out, _ = _finish(proc)
        data = json.loads(out)
        assert (data["n_runs"], data["failed"]) == ((8, 0) if name == "sobol" else (6, 0)), (name, executor)
        assert_same_files(tmp_path / name / executor.strip("-") / "out", in_process / name / "out",
                          "sensitivity-samples.csv")
    sobol = json.loads((in_process / "sobol" / "out" / "sensitivity.json").read_text())
    assert sobol["method"] == "sobol" and {row["parameter"] for row in sobol["indices"]} == {"track_m", "cg_height_m"}
    assert all("ST" in row for row in sobol["indices"])


def test_a_worker_killed_mid_design_leaves_the_other_to_finish_each_sample_once(tmp_path, cluster, in_process):
    log = tmp_path / "out" / "sensitivity-samples.csv"
    proc = _launch(tmp_path, *MORRIS, "--scheduler", cluster.address)
    deadline = time.monotonic() + 120
    while _logged(log) < 1 and proc.poll() is None:
        assert time.monotonic() < deadline, "no sample logged in time"
        time.sleep(0.02)
    assert proc.poll() is None and _logged(log) < 6, "the design ended before a worker was killed: make it larger"
    cluster.kill_worker(0)
    out, _ = _finish(proc)
    data = json.loads(out)
    assert (data["n_runs"], data["failed"]) == (6, 0)
    assert [int(row.split(",")[0]) for row in _rows(log)] == list(range(6))  # each sample once
    assert cluster.registered() == {list(cluster.workers)[1]}  # the killed worker is gone: the other did the rest
    assert_same_files(tmp_path / "out", in_process / "morris" / "out", "sensitivity-samples.csv")


def test_a_killed_scheduler_ends_every_design_in_one_line_and_resume_finishes_on_a_new_one(tmp_path, in_process):
    first = DaskProcesses(tmp_path / "dask-1", workers=2)
    try:
        first.start_scheduler()
        runs = {name: _launch(tmp_path / name, *args, "--scheduler", first.address)
                for name, (args, _, _) in DESIGNS.items()}
        logs = {name: tmp_path / name / "out" / log for name, (_, log, _) in DESIGNS.items()}
        deadline = time.monotonic() + 180
        while not ((held := first.client_tasks()) and len(held) == len(DESIGNS) and min(held) >= 1):
            # the workers start once each design has work waiting: the first calls of all run before the later
            # ones of any (the scheduler takes them in the order submitted), so that none can end before the kill
            ended = {name: proc.poll() for name, proc in runs.items() if proc.poll() is not None}
            assert not ended and time.monotonic() < deadline, (ended, held)
            time.sleep(0.1)
        first.start_workers()
        while any(_logged(log) < 1 for log in logs.values()):
            ended = [name for name, proc in runs.items() if proc.poll() is not None]
            assert not ended, f"ended before the scheduler was killed: {ended}"
            assert time.monotonic() < deadline, {name: _logged(log) for name, log in logs.items()}
            time.sleep(0.02)
        first.kill_scheduler()
        killed = time.monotonic()
        said = {}
        for name, proc in runs.items():
            out, err = _finish(proc, code=1, timeout=max(killed + 60 - time.monotonic(), 1))
            lines = [line for line in err.splitlines() if not PROGRESS.match(line)]
            assert len(lines) == 1, (name, err)  # no traceback, no log line of the Dask client
            said[name] = lines[0]
            assert json.loads(out)["incomplete"] is True, name
        took = time.monotonic() - killed
    finally:
        first.stop()
    assert took < 60
    for name, line in said.items():
        assert line.startswith("trikedyn: ") and not line.startswith("trikedyn: error"), (name, line)
        assert "scheduler" in line and "--resume" in line, (name, line)
        assert 1 <= _logged(logs[name]) < DESIGNS[name][2], (name, _logged(logs[name]))
    with DaskProcesses(tmp_path / "dask-2", workers=2) as second:
        resumed = {name: _launch(tmp_path / name, *args, "--resume", "--scheduler", second.address)
                   for name, (args, _, _) in DESIGNS.items()}
        references = {name: _launch(tmp_path / "reference" / name, *args, "--workers", "0")  # uninterrupted
                      for name, (args, _, _) in DESIGNS.items() if args is not MORRIS}  # that one: in_process
        for proc in resumed.values():
            _finish(proc)
    for proc in references.values():
        _finish(proc)
    for name, (args, log, total) in DESIGNS.items():
        assert len(_rows(logs[name])) == total, name  # nothing lost, nothing repeated
        reference = in_process / "morris" if args is MORRIS else tmp_path / "reference" / name
        assert_same_files(tmp_path / name / "out", reference / "out", log)
