"""Interruption and resume: a study run in a subprocess, killed (SIGINT, SIGKILL) after some scenarios are
stored, then run again: every scenario stored exactly once, and none stored before the kill recomputed."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from trikedyn.study import StudyStore, expand, load_spec

from . import warm_numba_cache, write_spec

TOTAL = 32  # enough that a kill after the first few lands before the last (a search takes 20-50 ms)


@pytest.fixture(scope="module")
def warm():
    warm_numba_cache()


def _spec(folder: Path) -> Path:
    return write_spec(folder, name="thirty-two", freight=(0, 50, 100, 150),
                      stiffness=(0.8, 0.85, 0.9, 0.95, 1.05, 1.1, 1.15, 1.2))  # 32 scenarios


def _launch(spec: Path, out: Path) -> subprocess.Popen:
    cmd = [sys.executable, "-m", "trikedyn", "study", str(spec), "--out", str(out), "--workers", "2", "--json"]
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)


def _stored(db: Path) -> dict[str, tuple]:
    """scenario_id -> (run_token, finished_at), read-only.

    The connection is closed here, not left to the garbage collector (a sqlite3 connection sits in a reference
    cycle with its statement cache): while one is open in this process, a new connection to the file shares its
    WAL index, and after the writer is killed between writing a commit and publishing it in that index, the
    new one reads the store without that commit. A resume (another process) sees it.
    """
    if not db.is_file():
        return {}
    try:
        with contextlib.closing(sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=5)) as conn:
            return {r[0]: (r[1], r[2]) for r in conn.execute("SELECT scenario_id, run_token, finished_at FROM results")}
    except sqlite3.OperationalError:  # the table is not created yet
        return {}


def _kill_after(proc: subprocess.Popen, db: Path, sig: int, at_least: int = 2, timeout_s: float = 45.0) -> None:
    deadline = time.monotonic() + timeout_s
    while len(_stored(db)) < at_least:
        assert proc.poll() is None, f"the study ended before the kill: {proc.communicate()}"
        assert time.monotonic() < deadline, "no scenario stored in time"
        time.sleep(0.05)
    os.kill(proc.pid, sig)


def _group_gone(pgid: int, timeout_s: float = 10.0) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.1)
    return False


def _resume_and_check(spec: Path, out: Path, before: dict) -> dict:
    assert 0 < len(before) < TOTAL
    proc = _launch(spec, out)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 0, stderr
    summary = json.loads(stdout)
    after = _stored(out / "study.sqlite")
    ids = [s["scenario_id"] for s in expand(load_spec(spec))]
    assert sorted(after) == sorted(ids)  # every scenario exactly once (primary key), none missing
    for sid, stamp in before.items():  # finished before the kill: kept as they were, not recomputed
        assert after[sid] == stamp
    new_token = summary["run_token"]
    recomputed = [sid for sid, (token, _) in after.items() if token == new_token]
    assert sorted(recomputed) == sorted(set(ids) - set(before))
    assert summary["scenarios"] == {"total": TOTAL, "done": TOTAL, "failed": 0, "computed": TOTAL - len(before),
                                    "skipped": len(before), "lost": 0}
    with StudyStore(out) as store:
        runs = store.runs()
        assert runs[-1]["run_token"] == new_token and runs[-1]["planned"] == TOTAL - len(before)
        assert runs[-1]["outcome"] == "completed"
        frame = store.to_pandas(ids)
    assert list(frame["scenario_id"]) == ids and set(frame["status"]) == {"ok"}
    assert (out / "results.csv").is_file()
    return summary


@pytest.mark.slow
def test_sigint_stops_cleanly_and_rerun_resumes(tmp_path, warm):
    spec, out = _spec(tmp_path), tmp_path / "out"
    proc = _launch(spec, out)
    try:
        _kill_after(proc, out / "study.sqlite", signal.SIGINT)
        stdout, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130, stderr
    before = _stored(out / "study.sqlite")
    assert f"{len(before)} of {TOTAL} scenarios stored" in stderr and "again to resume" in stderr
    summary = json.loads(stdout)
    assert summary["outcome"] == "interrupted" and summary["scenarios"]["done"] == len(before)
    assert not (out / "results.csv").exists()  # no partial export
    with StudyStore(out) as store:
        assert store.runs()[0]["outcome"] == "interrupted"
    assert _group_gone(proc.pid)
    _resume_and_check(spec, out, before)
    with StudyStore(out) as store:
        assert [r["outcome"] for r in store.runs()] == ["interrupted", "completed"]  # said how it ended: kept


def test_sigkill_leaves_a_consistent_store_and_rerun_resumes(tmp_path, warm):
    spec, out = _spec(tmp_path), tmp_path / "out"
    proc = _launch(spec, out)
    try:
        _kill_after(proc, out / "study.sqlite", signal.SIGKILL, at_least=3)
        proc.communicate(timeout=30)
        assert proc.returncode == -signal.SIGKILL
        # the pool's workers notice that the main process is gone and exit on their own
        assert _group_gone(proc.pid), "worker processes outlived the killed main process"
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    db = out / "study.sqlite"
    with contextlib.closing(sqlite3.connect(db)) as conn:
        assert conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
    before = _stored(db)
    with StudyStore(out) as store:
        assert store.runs()[0]["outcome"] == "running"  # it never got to say how it ended
    found_after = time.time()
    _resume_and_check(spec, out, before)
    with StudyStore(out) as store:
        killed, resumed = store.runs()
    assert killed["outcome"] == "killed"  # the resume, holding the lock, found it dead
    assert found_after <= killed["ended_at"] <= resumed["ended_at"]
