"""Issue 21: a study whose Dask scheduler is killed exits, in one line, and resumes.

It never exited: the client gave up reconnecting after 20 s, the futures of the tasks in flight stayed running
forever, and a ``RuntimeError: Future in unexpected state`` traceback was printed for each. Here a scheduler and
two workers run on 127.0.0.1 (subprocesses, each in its own session); the study runs on them in a subprocess;
once three scenarios are stored the scheduler gets SIGKILL. The study must exit within 60 s with code 1 and one
line saying it can be resumed (no traceback, no log lines of the client), and the same command on ``--workers 2``
must store the rest and export a table byte-identical to a pool run's.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from ..conftest import strict_json
from . import warm_numba_cache, write_spec

pytest.importorskip("distributed", reason="the lost-scheduler test needs dask.distributed (pip install 'trikedyn[dask]')")

TOTAL = 25


@pytest.fixture(scope="module", autouse=True)
def warm():
    warm_numba_cache()  # the workers load the compiled code instead of compiling it


def _start(cwd: Path, log: Path, *args) -> subprocess.Popen:
    with log.open("w") as fh:
        return subprocess.Popen([sys.executable, "-m", "dask", *args], cwd=cwd, stdout=fh, stderr=subprocess.STDOUT,
                                start_new_session=True)


def _address(log: Path, proc: subprocess.Popen, timeout_s: float = 60.0) -> str:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        found = re.search(r"Scheduler at:\s+(tcp://127\.0\.0\.1:\d+)", log.read_text())
        if found:
            return found.group(1)
        assert proc.poll() is None, log.read_text()
        time.sleep(0.1)
    raise AssertionError(f"the scheduler gave no address: {log.read_text()}")


def _stored(db: Path) -> int:
    if not db.exists():
        return 0
    try:
        with contextlib.closing(sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=1)) as conn:
            return conn.execute("SELECT count(*) FROM results").fetchone()[0]
    except sqlite3.Error:  # not created yet
        return 0


def _study(cwd: Path, *args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "trikedyn", "study", *map(str, args)], cwd=cwd, capture_output=True,
                          text=True, timeout=300)


def test_a_killed_scheduler_ends_the_study_in_one_line_and_the_rerun_resumes(tmp_path):
    spec = write_spec(tmp_path, name="lost", freight=(0, 50, 100, 150, 200), stiffness=(0.8, 0.9, 1.0, 1.1, 1.2))
    procs: list[subprocess.Popen] = []
    try:
        scheduler = _start(tmp_path, tmp_path / "scheduler.log", "scheduler", "--host", "127.0.0.1", "--port", "0",
                           "--no-dashboard")
        procs.append(scheduler)
        address = _address(tmp_path / "scheduler.log", scheduler)
        for i in range(2):
            procs.append(_start(tmp_path, tmp_path / f"worker{i}.log", "worker", address, "--nthreads", "1",
                                "--no-dashboard", "--local-directory", str(tmp_path / f"w{i}")))
        study = subprocess.Popen([sys.executable, "-m", "trikedyn", "study", str(spec), "--scheduler", address,
                                  "--out", "out"], cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 text=True, start_new_session=True)
        procs.append(study)
        deadline = time.monotonic() + 120
        while _stored(tmp_path / "out" / "study.sqlite") < 3 and study.poll() is None:
            assert time.monotonic() < deadline, "no scenario stored in time"
            time.sleep(0.05)
        assert study.poll() is None, "the study ended before its scheduler was killed: a larger spec is needed"
        os.kill(scheduler.pid, signal.SIGKILL)
        killed = time.monotonic()
        out, err = study.communicate(timeout=60)
        took = time.monotonic() - killed
    finally:
        for proc in procs:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(timeout=30)
    assert took < 60 and study.returncode == 1, (study.returncode, err)
    said = [line for line in err.splitlines() if not re.match(r"study: \d+/\d+ scenarios", line)]
    assert len(said) == 1, err  # no traceback, no log line of the client
    assert said[0].startswith("trikedyn: ") and "scheduler" in said[0] and "again to resume" in said[0], said
    stored = _stored(tmp_path / "out" / "study.sqlite")
    assert 3 <= stored < TOTAL and f"{stored} of {TOTAL} stored" in said[0]
    assert not (tmp_path / "out" / "results.csv").exists()

    resumed = _study(tmp_path, spec, "--workers", "2", "--out", "out", "--json")
    assert resumed.returncode == 0, resumed.stderr
    summary = strict_json(resumed.stdout)
    assert summary["scenarios"]["skipped"] == stored and summary["scenarios"]["computed"] == TOTAL - stored
    pool = _study(tmp_path, spec, "--workers", "2", "--out", "pool")
    assert pool.returncode == 0, pool.stderr
    assert (tmp_path / "out" / "results.csv").read_bytes() == (tmp_path / "pool" / "results.csv").read_bytes()
