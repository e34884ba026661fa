"""The engine under every design (:mod:`trikedyn.study.engine`): one scheduling loop, any executor.

A small Morris sensitivity on a local Dask cluster of two workers gives the same files as on a process pool of
two and in this process: the plan byte for byte, the samples' table byte for byte once in sample order (the log
is appended as samples finish, in whatever order the workers end them), the results' JSON but for its run time
and file paths.
"""

from __future__ import annotations

import json
import subprocess
import sys
from concurrent.futures import Executor, Future
from pathlib import Path

import pytest

from trikedyn.study.engine.executors import InlineExecutor
from trikedyn.study.engine.loop import drive

MORRIS = ["sensitivity", "reference-etrike", "--samples", "2", "--resolution", "5", "-p", "track_m", "--json"]
"""One factor, two trajectories: 4 threshold searches at 5 km/h resolution."""


def _trikedyn(cwd: Path, *args: str, timeout: float = 600) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "trikedyn", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=timeout)


def _in_sample_order(path: Path) -> str:
    header, *rows = path.read_text().splitlines(keepends=True)
    return header + "".join(sorted(rows, key=lambda row: int(row.split(",", 1)[0])))


def _results(path: Path) -> dict:
    data = json.loads(path.read_text())
    for key in ("wall_time_s", "files"):  # the run's own time, and paths naming its folder
        assert key in data
        data.pop(key)
    return data


@pytest.mark.slow
def test_morris_gives_the_same_files_on_dask_a_pool_and_in_process(tmp_path):
    pytest.importorskip("distributed", reason="needs dask.distributed (pip install 'trikedyn[dask]')")
    runs = {"in-process": ["--workers", "0"], "pool": ["--workers", "2"], "dask": ["--dask-local", "2"]}
    for name, executor in runs.items():
        done = _trikedyn(tmp_path, *MORRIS, *executor, "--out", name)
        assert done.returncode == 0, (name, done.stderr[-2000:])
        assert json.loads(done.stdout)["n_runs"] == 4
    plan, samples, results = ("sensitivity-plan.json", "sensitivity-samples.csv", "sensitivity.json")
    reference = tmp_path / "in-process"
    table = _in_sample_order(reference / samples)
    assert len(table.splitlines()) == 5 and ",ok," in table
    for name in ("pool", "dask"):
        assert (tmp_path / name / plan).read_bytes() == (reference / plan).read_bytes(), name
        assert _in_sample_order(tmp_path / name / samples) == table, name
        assert _results(tmp_path / name / results) == _results(reference / results), name


@pytest.mark.parametrize("command", [
    ["sensitivity", "reference-etrike"],
    ["uncertainty", "reference-etrike"],
    ["loading-chart", "reference-etrike"],
    ["optimise", "reference-etrike", "--spec", "battery-layout"],
])
def test_every_design_refuses_two_executors_in_one_line(tmp_path, command):
    done = _trikedyn(tmp_path, *command, "--workers", "2", "--dask-local", "2", "--out", "out", timeout=120)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2, done.stderr
    assert len(lines) == 1 and lines[0].startswith("trikedyn: error") and "choose one executor" in lines[0], lines
    assert not (tmp_path / "out").exists()  # refused before anything was written


def test_every_design_takes_the_executor_options():
    from typer.main import get_command

    from trikedyn.cli import app

    group = get_command(app)
    for name in ("study", "sensitivity", "uncertainty", "loading-chart", "optimise"):
        options = {opt for param in group.commands[name].params for opt in param.opts}
        assert {"--workers", "--dask-local", "--scheduler"} <= options, name


def _square(x):
    return x * x


def _dies(x):
    raise RuntimeError(f"worker died on {x}")


class _LostScheduler(Executor):
    """Every call stays in flight; the scheduler is lost once two are submitted."""

    window = 3

    def __init__(self):
        self.lost = None
        self.submitted = 0

    def submit(self, fn, /, *args, **kwargs):
        if self.lost:
            raise RuntimeError(self.lost)
        self.submitted += 1
        if self.submitted == 2:
            self.lost = "the Dask scheduler was lost"
        fut = Future()
        fut.set_running_or_notify_cancel()
        return fut


def test_the_loop_gives_each_value_once_and_says_what_it_lost():
    got = {}
    assert drive(InlineExecutor(), _square, [(x, (x,)) for x in range(5)], got.__setitem__) == []
    assert got == {x: x * x for x in range(5)}

    lost = drive(InlineExecutor(), _dies, [("a", (1,)), ("b", (2,))], pytest.fail)
    assert [(item.key, item.submitted) for item in lost] == [("a", True), ("b", True)]
    assert lost[0].why == "RuntimeError: worker died on 1"

    executor = _LostScheduler()
    lost = drive(executor, _square, [(x, (x,)) for x in range(6)], pytest.fail)
    assert sorted(item.key for item in lost) == list(range(6))  # each once: none waited on for ever
    assert sorted(item.key for item in lost if item.submitted) == [0, 1]  # in flight when it was lost
    assert all("scheduler was lost" in item.why for item in lost)
