"""Study specs, the SQLite result store, scenario failures and executor equivalence."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import sqlite3
import subprocess
import sys
import textwrap

import pandas as pd
import pytest

from trikedyn.errors import InputError
from trikedyn.study import StudyStore, expand, load_spec, parse_spec, run_scenario, run_study
from trikedyn.study.scenarios import canonical_json, scenario_id

from . import warm_numba_cache, write_spec


@pytest.fixture(scope="module")
def warm():
    warm_numba_cache()


# ------------------------------------------------------------------------------------------------
# spec
# ------------------------------------------------------------------------------------------------
def test_paper_spec_expands_to_50_unique_scenarios():
    spec = load_spec("paper")
    scenarios = expand(spec)
    assert len(scenarios) == 50
    assert len({s["scenario_id"] for s in scenarios}) == 50
    configs = {(s["stiffness_scale"], s["damping_scale"]) for s in scenarios}
    assert configs == {(0.8, 1.0), (1.0, 1.0), (1.2, 1.0), (1.0, 0.8), (1.0, 1.2)}
    assert {s["freight_kg"] for s in scenarios} == {0.0, 50.0, 100.0, 150.0, 200.0}
    assert {s["manoeuvre"] for s in scenarios} == {"dlc", "slc"}
    assert {s["resolution_kmh"] for s in scenarios} == {0.1}
    # the 100 %/100 % configuration belongs to both parts of Fig. 10 and is run once
    shared = [s for s in scenarios if (s["stiffness_scale"], s["damping_scale"]) == (1.0, 1.0)]
    assert len(shared) == 10 and {s["groups"] for s in shared} == {"stiffness;damping"}


def test_scenario_ids_are_deterministic_and_canonical(tmp_path):
    a = [s["scenario_id"] for s in expand(load_spec("paper"))]
    b = [s["scenario_id"] for s in expand(load_spec("paper"))]
    assert a == b
    assert all(len(i) == 16 and int(i, 16) >= 0 for i in a)
    # 100 and 100.0 are the same freight; a different resolution is a different scenario
    ints = expand(load_spec(write_spec(tmp_path, freight=(0, 100))))
    floats = expand(load_spec(write_spec(tmp_path, name="small", freight=(0.0, 100.0))))
    assert [s["scenario_id"] for s in ints] == [s["scenario_id"] for s in floats]
    changed = dict(ints[0], resolution_kmh=0.5)
    assert scenario_id(changed) != ints[0]["scenario_id"]
    assert scenario_id(ints[0]) == ints[0]["scenario_id"]
    assert json.loads(canonical_json(ints[0]))["manoeuvre"] == "slc"


def test_group_overrides_are_grid_axes_and_duplicates_merge():
    spec = parse_spec(textwrap.dedent("""
        name = "t"
        manoeuvres = ["slc"]
        freight_kg = [0, 50]
        [[groups]]
        name = "a"
        stiffness_scale = [1.0, 1.2]
        overrides = { "mass.driver_kg" = [75, 90] }
        [[groups]]
        name = "b"
        stiffness_scale = [1.2]
        overrides = { "mass.driver_kg" = [90] }
    """))
    scenarios = expand(spec)
    assert len(scenarios) == 2 * 2 * 2
    merged = [s for s in scenarios if s["groups"] == "a;b"]
    assert {(s["stiffness_scale"], s["overrides"]["mass.driver_kg"]) for s in merged} == {(1.2, 90.0)}
    assert len(merged) == 2


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ('name = "x"\nmanouvres = ["dlc"]\n', "unknown key 'manouvres' in the top level; did you mean 'manoeuvres'?"),
        ('name = "x"\n[[groups]]\nname = "g"\nstifness_scale = [1.0]\n',
         "unknown key 'stifness_scale' in groups[g]; did you mean 'stiffness_scale'?"),
        ('name = "x"\nmanoeuvres = ["dlc", "zigzag"]\n', "unknown manoeuvre 'zigzag'"),
        ('name = "x"\nfreight_kg = [-5]\n', "freight_kg: must be within [0, 2000] kg, got -5"),
        ('name = "x"\n[[groups]]\nname = "g"\noverrides = { "mass.drivr_kg" = [80] }\n',
         "did you mean 'driver_kg'?"),
        ('name = "x"\nvehicle = "reference-etrik"\n', "did you mean 'reference-etrike'?"),
        ('description = "no name"\n', "name: missing"),
    ],
)
def test_spec_errors_name_the_field_and_hint(tmp_path, text, expected):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as info:
        load_spec(path)
    message = str(info.value)
    assert expected in message
    assert message.startswith(str(path)) and "\n" not in message


def test_unknown_study_name_hints():
    with pytest.raises(InputError, match="did you mean 'paper'"):
        load_spec("papr")


def test_vehicle_path_is_relative_to_the_spec_file(tmp_path, monkeypatch):
    sub = tmp_path / "specs"
    sub.mkdir()
    (sub / "heavy.toml").write_text('extends = "reference-etrike"\n[mass]\ndriver_kg = 95.0\n', encoding="utf-8")
    spec_path = write_spec(sub)
    spec_path.write_text(spec_path.read_text().replace('"reference-etrike"', '"heavy.toml"'))
    monkeypatch.chdir(tmp_path)  # not the spec's folder
    spec = load_spec(spec_path)
    assert spec.vehicle == "heavy.toml"
    assert spec.load_vehicle().params.mass.driver_kg == 95.0
    assert spec.vehicle_digest != load_spec("paper").vehicle_digest


# ------------------------------------------------------------------------------------------------
# store
# ------------------------------------------------------------------------------------------------
def _fake_row(scenario, threshold=50.0, status="ok", token="t0"):
    row = dict(scenario)
    result = dict(threshold_speed_kmh=threshold, limit="lift-off", limiting_wheel="rear_left", lift_time_s=4.2,
                  first_failure_kmh=threshold + 1, first_cone_strike_kmh=None, detail="d", n_runs=12)
    if status != "ok":
        result = dict.fromkeys(result)
    row.update(status=status, **result, error=None if status == "ok" else "Boom: x", traceback=None,
               wall_time_s=0.1, worker="h:1", run_token=token, finished_at=1.0)
    return row


def test_store_write_read_skip_and_sorted_export(tmp_path):
    scenarios = expand(load_spec(write_spec(tmp_path, freight=(0, 50, 100))))
    order = [s["scenario_id"] for s in scenarios]
    with StudyStore(tmp_path / "a", "small") as store:
        for k, s in reversed(list(enumerate(scenarios))):  # finish in the reverse order
            assert store.put(_fake_row(s, threshold=40.0 + k))
        assert store.put(_fake_row(scenarios[0], threshold=99.0, token="t1")) is False  # no overwrite
        assert len(store) == len(scenarios) and store.done_ids() == set(order)
        frame = store.to_pandas(order)
        files = store.export(order)
        full = store.to_pandas(order, run_info=True)
    assert list(frame["scenario_id"]) == order
    assert list(frame["threshold_speed_kmh"]) == [40.0 + k for k in range(len(order))]
    assert "wall_time_s" not in frame and set(full["run_token"]) == {"t0"}
    assert str(frame["n_runs"].dtype) == "Int64"
    with StudyStore(tmp_path / "b", "small") as store:  # another insertion order, the same files
        for k, s in enumerate(scenarios):
            store.put(_fake_row(s, threshold=40.0 + k))
        other = store.export(order)
    assert files["csv"].read_bytes() == other["csv"].read_bytes()
    pd.testing.assert_frame_equal(pd.read_parquet(files["parquet"]), pd.read_parquet(other["parquet"]))


def test_store_refuses_another_study_and_a_second_writer(tmp_path):
    with StudyStore(tmp_path, "one"):
        pass
    with pytest.raises(InputError, match="holds the results of study 'one'"):
        StudyStore(tmp_path, "two")
    with StudyStore(tmp_path, "one", lock=True):
        with pytest.raises(InputError, match="another study run is writing"):
            StudyStore(tmp_path, "one", lock=True)
        with StudyStore(tmp_path, "one") as reader:  # readers need no lock
            assert len(reader) == 0


CRASH = """
import os, signal, sys
from trikedyn.study import StudyStore, expand, load_spec
from trikedyn.study.engine.store import StudyStore as S
sys.path.insert(0, {tests!r})
from study.test_study import _fake_row
scenarios = expand(load_spec({spec!r}))
store = StudyStore({out!r}, "small", lock=True)
store.put(_fake_row(scenarios[0]))
original = S._insert
def crash(self, row):
    original(self, row)   # the row is written inside the transaction ...
    os.kill(os.getpid(), signal.SIGKILL)   # ... and the process dies before COMMIT
S._insert = crash
store.put(_fake_row(scenarios[1]))
"""


def test_store_row_is_all_or_nothing_when_killed_mid_transaction(tmp_path):
    spec = write_spec(tmp_path)
    scenarios = expand(load_spec(spec))
    out = tmp_path / "out"
    code = CRASH.format(tests=str(os.path.dirname(os.path.dirname(__file__))), spec=str(spec), out=str(out))
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert proc.returncode == -signal.SIGKILL, proc.stderr
    with contextlib.closing(sqlite3.connect(out / "study.sqlite")) as conn:
        assert conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
    with StudyStore(out, "small", lock=True) as store:  # the lock died with the process
        assert store.done_ids() == {scenarios[0]["scenario_id"]}
        assert store.put(_fake_row(scenarios[1]))
        assert len(store) == 2


# ------------------------------------------------------------------------------------------------
# running
# ------------------------------------------------------------------------------------------------
def test_failing_scenario_is_recorded_and_the_study_goes_on(tmp_path, warm):
    spec = write_spec(tmp_path, freight=(0,), stiffness=(1.0,), extra="""
        [[groups]]
        name = "invalid"
        overrides = { "mass.driver_kg" = [-10] }
    """)
    scenarios = expand(load_spec(spec))
    bad = next(s for s in scenarios if s["groups"] == "invalid")
    row = run_scenario(bad)  # returns, does not raise
    assert row["status"] == "error" and "driver_kg" in row["error"] and row["threshold_speed_kmh"] is None
    frame = run_study(spec, tmp_path / "out", workers=0, progress=False)
    assert list(frame["status"]) == ["ok", "error"]
    assert frame.loc[0, "threshold_speed_kmh"] > 50
    assert frame.loc[1, "error"].startswith("ParameterError: ") and "mass.driver_kg" in frame.loc[1, "error"]
    assert frame.loc[1, "mass.driver_kg"] == -10.0
    assert (tmp_path / "out" / "results.csv").is_file()


def test_process_pool_and_dask_give_identical_tables(tmp_path, warm):
    pytest.importorskip("dask.distributed")
    spec = write_spec(tmp_path)  # 2 stiffnesses x 2 freights, slc
    pool = run_study(spec, tmp_path / "pool", workers=2, progress=False)
    dask = run_study(spec, tmp_path / "dask", dask_local=2, progress=False)
    assert len(pool) == 4 and set(pool["status"]) == {"ok"}
    pd.testing.assert_frame_equal(pool, dask, check_exact=True)
    assert (tmp_path / "pool" / "results.csv").read_bytes() == (tmp_path / "dask" / "results.csv").read_bytes()
    pd.testing.assert_frame_equal(pd.read_parquet(tmp_path / "pool" / "results.parquet"),
                                  pd.read_parquet(tmp_path / "dask" / "results.parquet"), check_exact=True)
    with StudyStore(tmp_path / "dask") as store:
        assert store.runs()[0]["executor"].startswith("dask LocalCluster")


def test_executor_options_are_checked(tmp_path):
    spec = write_spec(tmp_path)
    with pytest.raises(InputError, match="choose one executor"):
        run_study(spec, tmp_path / "o", workers=2, dask_local=2)
    with pytest.raises(InputError, match="workers"):
        run_study(spec, tmp_path / "o", workers=-1)
    assert not (tmp_path / "o").exists()  # checked before anything is written
