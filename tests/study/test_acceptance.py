"""Issue 12, acceptance: a study with a geometry knob, a component move and two manoeuvres runs on the process
pool and on ``--dask-local 2`` with identical tables, and resumes after a kill (SIGKILL mid-run, re-run: the
same final table, the stored scenarios not recomputed)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pandas as pd
import pytest

from trikedyn.cli import main
from trikedyn.study import StudyStore, expand, load_spec

from . import warm_numba_cache
from .test_resume import _group_gone, _stored

SPEC = textwrap.dedent("""
    name = "layout-two-manoeuvres"
    vehicle = "reference-etrike"
    manoeuvres = ["slc", "dlc"]
    freight_kg = [0]
    resolution_kmh = 1.0
    [[groups]]
    name = "layout"
    overrides = { "track_m" = [1.0, 1.1, 1.2, 1.3], "component.battery.x_m" = [0.4, 0.6, 0.8, 1.0] }
""")
TOTAL = 32  # 4 tracks x 4 battery places x 2 manoeuvres: enough that a kill after the first two lands before the
# last (with 8, a search of 20-50 ms, the kill sometimes came after all were stored; tests/study/test_resume.py)


@pytest.fixture(scope="module")
def warm():
    warm_numba_cache()
    from trikedyn.analysis.threshold import threshold_velocity
    from trikedyn.params import load_vehicle

    threshold_velocity(load_vehicle("reference-etrike"), "dlc", low_kmh=10, high_kmh=20, resolution_kmh=5.0)


def _cli(capsys, *args) -> dict:
    code = main(["study", *args, "--json"])
    out = capsys.readouterr().out
    assert code == 0, out
    return json.loads(out)


@pytest.mark.slow
def test_knob_component_two_manoeuvres_pool_dask_and_kill_resume(tmp_path, capsys, warm):
    pytest.importorskip("dask.distributed")
    spec = tmp_path / "layout.toml"
    spec.write_text(SPEC, encoding="utf-8")
    scenarios = expand(load_spec(spec))
    ids = [s["scenario_id"] for s in scenarios]
    assert len(ids) == TOTAL
    assert {s["manoeuvre"] for s in scenarios} == {"slc", "dlc"}
    assert {tuple(sorted(s["overrides"])) for s in scenarios} == {("component.battery.x_m", "track_m")}

    # the process pool and a local Dask cluster: the same table, to the byte
    pool = _cli(capsys, str(spec), "--workers", "2", "--out", str(tmp_path / "pool"))
    dask = _cli(capsys, str(spec), "--dask-local", "2", "--out", str(tmp_path / "dask"))
    assert pool["executor"].startswith("process pool") and dask["executor"].startswith("dask LocalCluster")
    assert pool["scenarios"]["done"] == dask["scenarios"]["done"] == TOTAL
    assert pool["scenarios"]["failed"] == 0
    reference = (tmp_path / "pool" / "results.csv").read_bytes()
    assert (tmp_path / "dask" / "results.csv").read_bytes() == reference
    table = pd.read_csv(tmp_path / "pool" / "results.csv")
    assert list(table["scenario_id"]) == ids
    assert {"track_m", "component.battery.x_m"} <= set(table.columns)
    assert table["threshold_speed_kmh"].notna().all()
    assert [Path(p).name for p in pool["figures"]] == ["fig_threshold.png"]  # two factors: a family of lines
    assert (tmp_path / "pool" / "fig_threshold.png").stat().st_size > 0

    # killed (SIGKILL) mid-run, then run again: the same table, nothing stored before the kill recomputed
    out = tmp_path / "killed"
    cmd = [sys.executable, "-m", "trikedyn", "study", str(spec), "--out", str(out), "--workers", "2", "--json"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    db = out / "study.sqlite"
    try:
        deadline = time.monotonic() + 60
        while len(_stored(db)) < 2:
            assert proc.poll() is None, f"the study ended before the kill: {proc.communicate()}"
            assert time.monotonic() < deadline, "no scenario stored in time"
            time.sleep(0.05)
        os.kill(proc.pid, signal.SIGKILL)
        proc.communicate(timeout=30)
        assert proc.returncode == -signal.SIGKILL
        assert _group_gone(proc.pid), "worker processes outlived the killed main process"
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    before = _stored(db)
    assert 0 < len(before) < TOTAL
    resumed = _cli(capsys, str(spec), "--workers", "2", "--out", str(out))
    assert resumed["scenarios"] == {"total": TOTAL, "done": TOTAL, "failed": 0, "computed": TOTAL - len(before),
                                    "skipped": len(before), "lost": 0}
    after = _stored(db)
    for sid, stamp in before.items():
        assert after[sid] == stamp  # same run token, same finish time: not recomputed
    assert sorted(sid for sid, (token, _) in after.items() if token == resumed["run_token"]) == \
        sorted(set(ids) - set(before))
    assert (out / "results.csv").read_bytes() == reference
    with StudyStore(out) as store:
        assert [r["outcome"] for r in store.runs()] == ["killed", "completed"]
