"""Issue 9, "nothing is lost, bounded inputs": the scenario-count limit, runs that died, planted symbolic
links, atomic exports and unwritable output folders.

Most tests run the real loop (``run_study(..., workers=0)``) with a stand-in for the threshold search
(:func:`_fake_scenario`), so that they take milliseconds and need no numba.
"""

from __future__ import annotations

import errno
import os
import random
import signal
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import pandas as pd
import pytest

from trikedyn.errors import InputError
from trikedyn.study import StudyStore, count_scenarios, expand, load_spec, parse_spec, run_study
from trikedyn.study.spec import GroupSpec, StudySpec

from . import write_spec

# seven override axes of ten values each: 10^7 scenarios from a few lines of TOML
AXES = {
    "mass.driver_kg": [70 + i for i in range(10)],
    "mass.cg_z_m": [0.35 + 0.01 * i for i in range(10)],
    "mass.roll_inertia_kgm2": [110 + i for i in range(10)],
    "suspension.front.stiffness_N_per_m": [70000 + 1000 * i for i in range(10)],
    "suspension.rear.stiffness_N_per_m": [40000 + 1000 * i for i in range(10)],
    "tyre.mu_y": [0.80 + 0.01 * i for i in range(10)],
    "aero.drag_coefficient": [0.80 + 0.02 * i for i in range(10)],
}


def _huge_spec(folder: Path) -> Path:
    axes = ", ".join(f'"{path}" = {values}' for path, values in AXES.items())
    text = f'name = "huge"\nmanoeuvres = ["slc"]\n[[groups]]\nname = "g"\noverrides = {{ {axes} }}\n'
    path = folder / "huge.toml"
    path.write_text(text, encoding="utf-8")
    assert len(text.splitlines()) <= 9
    return path


def _fake_scenario(scenario, vehicle=None, run_token=None):
    """Stands in for run_scenario: a plausible ok row at once."""
    row = dict(scenario)
    row.update(status="ok", threshold_speed_kmh=50.0 + scenario["freight_kg"] / 100, limit="lift-off",
               limiting_wheel="rear_left", lift_time_s=4.2, first_failure_kmh=51.0, first_cone_strike_kmh=None,
               n_runs=12, detail="d", error=None, traceback=None, wall_time_s=0.0, worker="h:1",
               run_token=run_token, finished_at=time.time())
    return row


@pytest.fixture
def fake(monkeypatch):
    """Run studies with the stand-in threshold search (in this process: workers=0)."""
    import trikedyn.study.designs.runner as runner

    monkeypatch.setattr(runner, "run_scenario", _fake_scenario)


def _leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


# ------------------------------------------------------------------------------------------------
# 1. the scenario-count limit
# ------------------------------------------------------------------------------------------------
def test_ten_million_scenarios_are_refused_at_once_with_little_memory(tmp_path):
    spec = _huge_spec(tmp_path)
    assert count_scenarios(load_spec(spec)) == (10**7, True)  # also warms the imports and the vehicle cache
    out = tmp_path / "out"
    tracemalloc.start()
    start = time.perf_counter()
    try:
        with pytest.raises(InputError) as info:
            run_study(spec, out, workers=0, progress=False)
        elapsed = time.perf_counter() - start
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert info.value.where == str(spec)
    assert str(info.value) == (f"{spec}: the spec expands to 10,000,000 scenarios, more than the limit 10,000; "
                               "pass --max-scenarios 10000000 to run it")
    assert elapsed < 2.0
    assert peak < 50e6  # 10^7 scenario dicts would take gigabytes
    assert not out.exists()  # refused before anything is written


def test_limit_is_checked_against_the_exact_count_and_validated(tmp_path, fake):
    spec = write_spec(tmp_path)  # 2 stiffnesses x 2 freights = 4 scenarios
    with pytest.raises(InputError, match=r"expands to 4 scenarios, more than the limit 3; pass --max-scenarios 4"):
        run_study(spec, tmp_path / "out", workers=0, progress=False, max_scenarios=3)
    assert len(run_study(spec, tmp_path / "out", workers=0, progress=False, max_scenarios=4)) == 4
    assert len(run_study(spec, tmp_path / "out", workers=0, progress=False, max_scenarios=None)) == 4
    for bad in (0, -5, 2.5, True, "10"):
        with pytest.raises(InputError) as info:
            run_study(spec, tmp_path / "o2", max_scenarios=bad)
        assert info.value.where == "max_scenarios"
    assert not (tmp_path / "o2").exists()


def test_cli_entry_refuses_with_exit_code_2_and_one_line(tmp_path):
    spec = _huge_spec(tmp_path)
    proc = subprocess.run([sys.executable, "-m", "trikedyn", "study", str(spec), "--out", str(tmp_path / "o")],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert proc.stderr == (f"trikedyn: error: {spec}: the spec expands to 10,000,000 scenarios, more than the "
                           "limit 10,000; pass --max-scenarios 10000000 to run it\n")


def _random_spec(rng: random.Random) -> StudySpec:
    pool = [0.5, 1.0, 1.5, 2.0, True, "a"]

    def axis():
        return tuple(rng.choice(pool) for _ in range(rng.randint(1, 3)))  # repeats on purpose

    paths = ["p.a", "p.b", "p.c"]
    groups = []
    for i in range(rng.randint(1, 5)):
        chosen = rng.sample(paths, rng.randint(0, 2))
        groups.append(GroupSpec(name=f"g{i}", stiffness_scale=tuple(rng.choice([0.8, 1.0, 1.2]) for _ in range(2)),
                                damping_scale=tuple(rng.choice([1.0, 1.2]) for _ in range(rng.randint(1, 2))),
                                overrides=tuple((p, axis()) for p in chosen)))
    return StudySpec(name="r", description="", vehicle="v", vehicle_source="v", vehicle_digest="d",
                     manoeuvres=tuple(rng.choice(["dlc", "slc"]) for _ in range(rng.randint(1, 2))),
                     freight_kg=tuple(rng.choice([0.0, 50.0, 100.0]) for _ in range(rng.randint(1, 3))),
                     resolution_kmh=0.1, low_kmh=10.0, high_kmh=90.0, step_kmh=10.0, groups=tuple(groups))


def test_count_is_exact_despite_repeats_and_overlapping_groups():
    assert count_scenarios(load_spec("paper")) == (50, True)  # its two groups share 10 scenarios
    rng = random.Random(9)
    for _ in range(300):
        spec = _random_spec(rng)
        assert count_scenarios(spec) == (len(expand(spec)), True), spec


def test_count_falls_back_to_an_upper_bound_when_overlaps_explode():
    # 20 groups that all share stiffness 1.0: 2^20 intersecting subsets, past the counting budget
    groups = tuple(GroupSpec(name=f"g{i}", stiffness_scale=(1.0, 1.0 + (i + 1) / 100), damping_scale=(1.0,),
                             overrides=()) for i in range(20))
    spec = StudySpec(name="o", description="", vehicle="v", vehicle_source="v", vehicle_digest="d",
                     manoeuvres=("slc",), freight_kg=(0.0,), resolution_kmh=0.1, low_kmh=10.0, high_kmh=90.0,
                     step_kmh=10.0, groups=groups)
    start = time.perf_counter()
    n, exact = count_scenarios(spec)
    assert time.perf_counter() - start < 2.0
    assert (n, exact) == (40, False) and len(expand(spec)) == 21
    with pytest.raises(InputError, match=r"expands to up to 40 scenarios, more than the limit 30"):
        run_study(spec, "never-made", max_scenarios=30)
    assert not Path("never-made").exists()


def test_non_finite_override_is_an_input_error_not_a_crash():
    with pytest.raises(InputError, match=r"override 'mass.driver_kg': values must be finite, got nan"):
        parse_spec('name = "x"\n[[groups]]\nname = "g"\noverrides = { "mass.driver_kg" = [nan] }\n')


# ------------------------------------------------------------------------------------------------
# 2. a run that died is not left "running"
# ------------------------------------------------------------------------------------------------
DIE = """
import os, signal
from trikedyn.study import StudyStore
store = StudyStore({out!r}, "small", lock=True)
store.begin_run("dead0000run", 4, "process pool (2 workers)")
os.kill(os.getpid(), signal.SIGKILL)   # no end_run: the row stays 'running'
"""


def test_run_killed_before_recording_its_end_is_marked_killed_on_resume(tmp_path, fake):
    spec, out = write_spec(tmp_path), tmp_path / "out"
    proc = subprocess.run([sys.executable, "-c", DIE.format(out=str(out))], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == -signal.SIGKILL, proc.stderr
    with StudyStore(out) as reader:  # a reader takes no lock and changes nothing
        assert [(r["run_token"], r["outcome"], r["ended_at"]) for r in reader.runs()] == [("dead0000run", "running",
                                                                                           None)]
    before = time.time()
    run_study(spec, out, workers=0, progress=False)  # the resume takes the lock
    with StudyStore(out) as reader:
        dead, new = reader.runs()
    assert dead["run_token"] == "dead0000run" and dead["outcome"] == "killed"
    assert before <= dead["ended_at"] <= time.time()  # when it was found so
    assert new["outcome"] == "completed"


def test_marking_needs_the_lock_and_reports_what_it_marked(tmp_path):
    with StudyStore(tmp_path, "s", lock=True) as store:
        store.begin_run("alive", 1, "x")
        with StudyStore(tmp_path, "s") as reader:  # no lock: the live run is left alone
            assert reader.runs()[0]["outcome"] == "running" and reader.found_killed == []
        with pytest.raises(InputError, match="another study run is writing"):
            StudyStore(tmp_path, "s", lock=True)
        assert store.runs()[0]["outcome"] == "running"
        # the process "dies": the lock goes, the row stays
        os.close(store._lock_fd)
        store._lock_fd = None
        with StudyStore(tmp_path, "s", lock=True) as second:
            assert second.found_killed == ["alive"] and second.runs()[0]["outcome"] == "killed"


def test_run_ended_by_an_exception_is_marked_failed(tmp_path, monkeypatch, fake):
    spec, out = write_spec(tmp_path), tmp_path / "out"

    def broken_put(self, row):
        raise RuntimeError("disk on fire")

    monkeypatch.setattr(StudyStore, "put", broken_put)
    with pytest.raises(RuntimeError, match="disk on fire"):
        run_study(spec, out, workers=0, progress=False)
    with StudyStore(out) as reader:
        assert [r["outcome"] for r in reader.runs()] == ["failed"]


# ------------------------------------------------------------------------------------------------
# 3. symbolic links planted in the output folder are not followed
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["study.lock", "study.sqlite", "study.sqlite-wal", "study.sqlite-shm",
                                  "results.csv", "results.parquet"])
@pytest.mark.parametrize("dangling", [False, True])
def test_planted_symlink_is_refused_and_its_target_untouched(tmp_path, fake, name, dangling):
    spec, out = write_spec(tmp_path), tmp_path / "out"
    out.mkdir()
    victim = tmp_path / "elsewhere" / "precious.txt"
    victim.parent.mkdir()
    if not dangling:
        victim.write_bytes(b"precious\n")
        os.chmod(victim, 0o644)
    (out / name).symlink_to(victim)
    with pytest.raises(InputError) as info:
        run_study(spec, out, workers=0, progress=False)
    assert info.value.where == str(out / name)
    assert "is a symbolic link; not following it" in str(info.value)
    if dangling:
        assert not victim.exists()
    else:
        assert victim.read_bytes() == b"precious\n"
    assert (out / name).is_symlink()  # left as it was, for the user to look at
    assert {p.name for p in out.iterdir()} <= {"study.lock", name}  # refused before the store was opened


def test_symlink_planted_during_the_run_is_refused_at_export(tmp_path):
    spec = write_spec(tmp_path)
    scenarios = expand(load_spec(spec))
    order = [s["scenario_id"] for s in scenarios]
    victim = tmp_path / "precious.csv"
    victim.write_text("precious\n")
    with StudyStore(tmp_path / "out", "small", lock=True) as store:
        for s in scenarios:
            store.put(_fake_scenario(s, run_token="t"))
        (tmp_path / "out" / "results.csv").symlink_to(victim)
        with pytest.raises(InputError, match="results.csv: is a symbolic link; not following it"):
            store.export(order)
    assert victim.read_text() == "precious\n"
    assert _leftovers(tmp_path / "out") == []


# ------------------------------------------------------------------------------------------------
# 4. atomic outputs
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("table", ["csv", "parquet"])
@pytest.mark.parametrize(("error", "raised"), [(RuntimeError("writer bug"), RuntimeError),
                                                (OSError(errno.ENOSPC, "No space left on device"), InputError)])
def test_failed_export_leaves_the_old_table_and_no_temporary_file(tmp_path, monkeypatch, fake, table, error, raised):
    spec, out = write_spec(tmp_path), tmp_path / "out"
    run_study(spec, out, workers=0, progress=False)
    old = {kind: (out / f"results.{kind}").read_bytes() for kind in ("csv", "parquet")}
    writer = "to_csv" if table == "csv" else "to_parquet"
    original = getattr(pd.DataFrame, writer)

    def half_then_fail(self, fh, *args, **kwargs):
        original(self.iloc[:1], fh, *args, **kwargs)  # some bytes are out ...
        raise error  # ... and the writer dies

    monkeypatch.setattr(pd.DataFrame, writer, half_then_fail)
    with StudyStore(out, "small", lock=True) as store:
        order = [s["scenario_id"] for s in expand(load_spec(spec))]
        with pytest.raises(raised) as info:
            store.export(order)
    if raised is InputError:
        assert str(info.value) == f"{out / f'results.{table}'}: cannot write (no space left on device)"
    assert (out / f"results.{table}").read_bytes() == old[table]
    assert _leftovers(out) == []


def test_exports_are_plain_files_with_the_usual_permissions(tmp_path, fake):
    out = tmp_path / "out"
    run_study(write_spec(tmp_path), out, workers=0, progress=False)
    umask = os.umask(0)
    os.umask(umask)
    for name in ("results.csv", "results.parquet"):
        path = out / name
        assert path.is_file() and not path.is_symlink()
        assert path.stat().st_mode & 0o777 == 0o666 & ~umask  # not mkstemp's 0o600
    assert _leftovers(out) == []
    assert pd.read_csv(out / "results.csv").shape[0] == 4


# ------------------------------------------------------------------------------------------------
# 5. an output folder that cannot be written
# ------------------------------------------------------------------------------------------------
def test_out_below_a_regular_file_is_an_input_error_naming_the_folder(tmp_path):
    spec = write_spec(tmp_path)
    blocker = tmp_path / "notes.txt"
    blocker.write_text("a file, not a folder\n")
    out = blocker / "sub" / "out"
    with pytest.raises(InputError) as info:
        run_study(spec, out, workers=0, progress=False)
    assert info.value.where == str(out)
    assert str(info.value) == f"{out}: cannot be created: '{blocker}' is not a folder"
    with pytest.raises(InputError, match="exists and is not a folder"):
        run_study(spec, blocker, workers=0, progress=False)
    dangling = tmp_path / "link-out"
    dangling.symlink_to(tmp_path / "nowhere")
    with pytest.raises(InputError, match="link-out: exists and is not a folder"):
        run_study(spec, dangling, workers=0, progress=False)
    assert blocker.read_text() == "a file, not a folder\n"


def test_cli_entry_reports_an_unwritable_folder_in_one_line(tmp_path):
    spec = write_spec(tmp_path)
    blocker = tmp_path / "notes.txt"
    blocker.write_text("x")
    out = blocker / "out"
    proc = subprocess.run([sys.executable, "-m", "trikedyn", "study", str(spec), "--out", str(out)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert proc.stderr == f"trikedyn: error: {out}: cannot be created: '{blocker}' is not a folder\n"


@pytest.mark.parametrize(("code", "reason"), [(errno.EACCES, "permission denied"),
                                              (errno.EROFS, "read-only file system")])
def test_folder_that_cannot_be_created_is_an_input_error(tmp_path, monkeypatch, code, reason):
    # root ignores permissions, so the refusal of mkdir is simulated here (the real one is tested below)
    def refuse(self, *args, **kwargs):
        raise OSError(code, os.strerror(code), str(self))

    monkeypatch.setattr(Path, "mkdir", refuse)
    out = tmp_path / "out"
    with pytest.raises(InputError) as info:
        StudyStore(out, "s", lock=True)
    assert str(info.value) == f"{out}: cannot create this folder ({reason})"


@pytest.mark.skipif(os.geteuid() == 0, reason="running as root: root bypasses file permissions "
                                               "(CAP_DAC_OVERRIDE), so a read-only folder does not stop it")
def test_read_only_folder_is_an_input_error(tmp_path):
    spec = write_spec(tmp_path)
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o555)
    try:
        with pytest.raises(InputError) as info:
            run_study(spec, locked / "out", workers=0, progress=False)
        assert str(info.value) == f"{locked / 'out'}: cannot create this folder (permission denied)"
        with pytest.raises(InputError) as info:
            run_study(spec, locked, workers=0, progress=False)
        assert str(info.value) == f"{locked}: cannot write into this folder (permission denied)"
    finally:
        locked.chmod(0o755)


@pytest.mark.parametrize("plant", ["folder", "garbage"])
def test_store_that_is_not_a_database_is_an_input_error(tmp_path, plant):
    out = tmp_path / "out"
    out.mkdir()
    if plant == "folder":
        (out / "study.sqlite").mkdir()
    else:
        (out / "study.sqlite").write_bytes(b"not a database, just some text that is long enough" * 40)
    with pytest.raises(InputError) as info:
        StudyStore(out, "s", lock=True)
    assert info.value.where == str(out / "study.sqlite")
    assert info.value.reason.startswith("cannot open the study store (")
    with pytest.raises(InputError, match="cannot open the study store"):  # not "another run is writing":
        StudyStore(out, "s", lock=True)  # the lock was released on the way out
