"""Issue 21: ``loading-chart`` keeps each cell as it finishes and resumes. It saved nothing until the end: killed
at 26 of 48 cells, its ``--out`` was empty and the re-run started at 0.

The chart runs in a subprocess (its own session) and is killed with SIGKILL once about half its cells are logged;
the same command with ``--resume`` must run only the cells not logged and end with the table of an uninterrupted
run, byte for byte.
"""

from __future__ import annotations

import csv
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from trikedyn.cli import main

from ..conftest import strict_json
from . import warm_numba_cache

GRID = ["--resolution", "1", "--masses", "0,100,200", "--x", "0.3,0.5", "--z", "0.5,0.7", "--workers", "2"]
CELLS = 12


@pytest.fixture(scope="module", autouse=True)
def warm():
    warm_numba_cache()  # the subprocesses load the compiled code instead of compiling it


def _trikedyn(cwd: Path, *args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "trikedyn", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=300)


def _logged(path: Path) -> list[list[str]]:
    """The complete cell rows of a cells log (a row cut short by the kill left out)."""
    if not path.exists():
        return []
    text = path.read_text(encoding="utf-8")
    text = text[: text.rfind("\n") + 1]
    return [row for row in list(csv.reader(text.splitlines()))[1:] if len(row) == 7 and row[2] in ("ok", "failed")]


def _group_gone(pgid: int, timeout_s: float = 15.0) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.1)
    return False


def test_killed_at_half_way_resumes_without_recomputing(tmp_path):
    whole = _trikedyn(tmp_path, "loading-chart", "reference-etrike", *GRID, "--out", "whole")
    assert whole.returncode == 0, whole.stderr
    expected = (tmp_path / "whole" / "loading-chart.csv").read_bytes()
    assert expected.count(b"\n") == CELLS + 1

    log = tmp_path / "cut" / "loading-chart-cells.csv"
    proc = subprocess.Popen([sys.executable, "-m", "trikedyn", "loading-chart", "reference-etrike", *GRID, "--out",
                             "cut"], cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)
    try:
        deadline = time.monotonic() + 120
        while len(_logged(log)) < CELLS // 2 and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.02)
        assert proc.poll() is None, "the chart ended before it was half way: a larger grid is needed"
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
        assert _group_gone(proc.pid), "a worker outlived the killed chart"
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    before = _logged(log)
    assert CELLS // 2 <= len(before) < CELLS
    assert not (tmp_path / "cut" / "loading-chart.csv").exists()

    again = _trikedyn(tmp_path, "loading-chart", "reference-etrike", *GRID, "--out", "cut")
    assert again.returncode == 2 and "--resume" in again.stderr  # not started over without being asked

    resumed = _trikedyn(tmp_path, "loading-chart", "reference-etrike", *GRID, "--out", "cut", "--resume", "--json")
    assert resumed.returncode == 0, resumed.stderr
    data = strict_json(resumed.stdout)
    assert data["cells_resumed"] == len(before) and data["cells_computed"] == CELLS - len(before)
    assert f"loading-chart: {len(before)}/{CELLS} cells" in resumed.stderr.splitlines()[0]
    after = _logged(log)
    assert sorted(int(row[0]) for row in after) == list(range(CELLS))  # each cell logged once: none run twice
    assert after[: len(before)] == before
    assert (tmp_path / "cut" / "loading-chart.csv").read_bytes() == expected


def test_resume_refuses_another_grid_and_needs_out(capsys, tmp_path):
    out = tmp_path / "chart"
    args = ["loading-chart", "reference-etrike", "--manoeuvre", "slc", "--resolution", "1", "--high", "120",
            "--masses", "0", "--x", "0.3", "--z", "0.5", "--workers", "0", "--out", str(out)]
    assert main(args) == 0
    capsys.readouterr()
    assert main([*args, "--resume", "--masses", "0,50"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "masses_kg" in err and "not resuming" in err
    assert main([*args, "--resume", "--json"]) == 0  # everything logged: nothing to run
    data = strict_json(capsys.readouterr().out)
    assert data["cells_resumed"] == 1 and data["cells_computed"] == 0
    assert main(args[:-2] + ["--resume"]) == 2
    assert "--resume" in capsys.readouterr().err


@pytest.fixture(scope="module")
def one_cell_chart(tmp_path_factory) -> Path:
    """A finished one-cell chart's --out folder (copied by each test that plants a file in it)."""
    folder = tmp_path_factory.mktemp("one-cell")
    done = _one_cell(folder)
    assert done.returncode == 0, done.stderr
    return folder / "chart"


def _one_cell(tmp_path: Path, *more: str) -> subprocess.CompletedProcess:
    return _trikedyn(tmp_path, "loading-chart", "reference-etrike", "--manoeuvre", "slc", "--resolution", "1",
                     "--high", "120", "--masses", "0", "--x", "0.3", "--z", "0.5", "--workers", "0", "--out", "chart",
                     *more)


@pytest.mark.parametrize("planted", ["plan-fifo", "plan-list", "log-fifo", "log-huge"])
def test_resume_reads_its_plan_and_log_bounded(tmp_path, one_cell_chart, planted):
    """A resumed run reads its plan and its log by the bounded reader: a FIFO, a huge file or a plan that is not a
    JSON object in their place is one line and exit 2, never waited on, never a traceback."""
    shutil.copytree(one_cell_chart, tmp_path / "chart")
    name = "loading-chart-plan.json" if planted.startswith("plan") else "loading-chart-cells.csv"
    target = tmp_path / "chart" / name
    target.unlink()
    if planted.endswith("fifo"):
        os.mkfifo(target)
    elif planted == "plan-list":
        target.write_text("[1, 2]")
    else:
        with target.open("wb") as fh:
            fh.truncate(600 << 20)  # sparse: no disk used
    started = time.monotonic()
    done = _one_cell(tmp_path, "--resume", "--json")
    assert time.monotonic() - started < 60
    assert done.returncode == 2, done.stderr
    said = [line for line in done.stderr.splitlines() if line.startswith("trikedyn:")]
    assert len(said) == 1 and said[0].startswith("trikedyn: error:") and name in said[0], done.stderr
    assert "Traceback" not in done.stderr and "error" in strict_json(done.stdout)
    assert ("not resuming" in said[0]) if name.endswith(".json") else ("larger than" in said[0] or "FIFO" in said[0])
