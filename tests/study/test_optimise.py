"""``trikedyn optimise``: the layout optimiser (issue 12).

The acceptance test: the optimiser's vehicle file, run through ``trikedyn threshold`` on its own, gives the
reported best threshold (within 0.2 km/h), better than the reference. The runs are small (a population of
5, two generations) so that the file stays cheap; the built-in ``battery-layout`` spec is only loaded.
"""

import contextlib
import csv
import io
import json
import subprocess
import sys

import pytest

from tests.conftest import strict_json
from trikedyn.cli import main
from trikedyn.errors import InputError
from trikedyn.study.designs import optimise as opt

# the battery moved rearwards and lower than the reference (x 0.70 m, z 0.32 m): a box where most layouts beat it
SMALL = """[optimise]
description = "battery rearwards and lower, a small test run"
knobs = { "component.battery.x_m" = [0.30, 0.70], "component.battery.z_m" = [0.25, 0.32] }
manoeuvres = ["dlc"]
seed = 3
popsize = 2
maxiter = 2
"""


def run_cli(*args) -> tuple[int, str, str]:
    """``trikedyn ARGS`` in this process: exit code, stdout, stderr."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def small_spec(tmp_path_factory):
    path = tmp_path_factory.mktemp("spec") / "small.toml"
    path.write_text(SMALL, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def pool_run(small_spec, tmp_path_factory):
    """The small spec through the command line, on a pool of two processes, with --json."""
    out = tmp_path_factory.mktemp("runs") / "pool"
    code, stdout, err = run_cli("optimise", "reference-etrike", "--spec", str(small_spec), "--manoeuvre", "dlc",
                                "--workers", "2", "--out", str(out), "--json")
    assert code == 0, err
    return out, strict_json(stdout), err


# ------------------------------------------------------------------------------------------------
# acceptance: the vehicle file on its own gives the reported threshold, better than the reference
# ------------------------------------------------------------------------------------------------
def test_vehicle_file_through_trikedyn_threshold_gives_the_reported_best(pool_run):
    out, data, _ = pool_run
    best, reference = data["best_threshold_speed_kmh"], data["reference_threshold_speed_kmh"]
    assert best > reference
    # a fresh process: nothing of the optimiser's run (caches, the in-memory vehicle) is shared
    done = subprocess.run([sys.executable, "-m", "trikedyn", "threshold", data["vehicle_file"], "--manoeuvre", "dlc",
                           "--json"], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    threshold = strict_json(done.stdout)["threshold_speed_kmh"]
    assert abs(threshold - best) <= 0.2, (threshold, best)
    assert threshold > reference
    assert data["vehicle_file_verified"] is True


def test_json_and_files(pool_run, reference):
    out, data, err = pool_run
    assert {"best_threshold_speed_kmh", "reference_threshold_speed_kmh", "vehicle_file", "moves"} <= set(data)
    assert data["manoeuvres"] == ["dlc"] and data["workers"] == 2 and data["failed_evaluations"] == 0
    assert [m["knob"] for m in data["moves"]] == ["component.battery.x_m", "component.battery.z_m"]
    battery = next(c for c in reference.params.components if c.name == "battery")
    for move, ref in zip(data["moves"], (battery.x_m, battery.z_m), strict=True):
        assert {"knob", "reference", "best"} <= set(move)
        assert move["reference"] == pytest.approx(ref)
        assert move["low"] <= move["best"] <= move["high"]
        assert move["best"] == round(move["best"], 3)  # rounded to the spec's 1 mm step
    assert "optimise: " in err and "evaluations" in err  # the progress line
    # the files: the JSON as printed, a row per evaluation (the reference first), a figure, the vehicle
    assert json.loads((out / "optimise.json").read_text())["moves"] == data["moves"]
    rows = list(csv.reader((out / "optimise-evaluations.csv").open()))
    assert rows[0][:4] == ["evaluation", "generation", "status", "worst_threshold_speed_kmh"]
    assert len(rows) == 1 + data["evaluations"] and rows[1][1] == "-1"  # "evaluations" counts the reference
    assert max(float(r[3]) for r in rows[1:]) == data["best_threshold_speed_kmh"]
    assert (out / "optimise.png").read_bytes()[:4] == b"\x89PNG"
    from trikedyn.params import load_vehicle

    optimised = load_vehicle(data["vehicle_file"])
    moved = next(c for c in optimised.params.components if c.name == "battery")
    assert (moved.x_m, moved.z_m) == (data["moves"][0]["best"], data["moves"][1]["best"])
    assert optimised.mass_kg == pytest.approx(reference.mass_kg)  # moved, not re-weighed
    assert optimised.name == "reference-etrike-optimised"


def test_same_result_in_process_and_resumed_after_a_kill(pool_run, small_spec, tmp_path):
    """Differential evolution is deferred and seeded: one process gives the pool's answer; a log cut short
    (a kill) resumes to the same answer without searching the logged layouts again."""
    _, pooled, _ = pool_run
    out = tmp_path / "serial"
    args = ("optimise", "reference-etrike", "--spec", str(small_spec), "--workers", "0", "--out", str(out), "--json")
    code, stdout, err = run_cli(*args)
    assert code == 0, err
    serial = json.loads(stdout)
    for key in ("best_threshold_speed_kmh", "reference_threshold_speed_kmh", "moves", "evaluations"):
        assert serial[key] == pooled[key], key
    log = out / "optimise-evaluations.csv"
    pool_log = (pool_run[0] / "optimise-evaluations.csv").read_bytes()
    assert log.read_bytes() == pool_log  # evaluations numbered by generation and place, not finishing order
    lines = log.read_text().splitlines(keepends=True)
    log.write_text("".join(lines[:6]) + lines[6][:10])  # header, reference, 4 layouts, and a row cut short
    code, stdout, err = run_cli(*args[:-1], "--resume", "--json")
    assert code == 0, err
    resumed = json.loads(stdout)
    assert resumed["resumed_evaluations"] == 5
    for key in ("best_threshold_speed_kmh", "moves", "evaluations"):
        assert resumed[key] == serial[key], key
    assert log.read_bytes() == pool_log  # a resumed run writes the log an uninterrupted one does
    # again, without --resume or --force: refused, one line, nothing run
    code, stdout, err = run_cli(*args[:-1])
    assert code == 2 and stdout == "" and err.count("\n") == 1 and "--force" in err


def test_two_runs_on_two_workers_write_the_same_log(pool_run, small_spec, tmp_path):
    """Issue 21: the log numbered evaluations in the order the workers finished them, so two identical runs
    on 2 workers wrote different files."""
    out = tmp_path / "again"
    done = subprocess.run([sys.executable, "-m", "trikedyn", "optimise", "reference-etrike", "--spec", str(small_spec),
                           "--manoeuvre", "dlc", "--workers", "2", "--out", str(out), "--json"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert (out / "optimise-evaluations.csv").read_bytes() == (pool_run[0] / "optimise-evaluations.csv").read_bytes()
    rows = list(csv.reader((out / "optimise-evaluations.csv").open()))[1:]
    assert [int(r[0]) for r in rows] == list(range(len(rows)))
    assert [int(r[1]) for r in rows] == sorted(int(r[1]) for r in rows)  # by generation, the reference first


def test_every_evaluation_failed_is_refused_and_the_log_kept(tmp_path):
    """Issue 21: with every evaluation failed, optimise exited 0 with a best of 0.0 km/h and wrote an
    "optimised" vehicle. Now: one line, exit 2, no vehicle written, the log of the failures kept."""
    out = tmp_path / "out"
    args = ["-m", "trikedyn", "optimise", "reference-etrike", "--spec", "battery-layout", "--manoeuvre", "slc", "-o",
            "lateral_offset_m=40", "-o", "length_m=2", "--maxiter", "0", "--popsize", "1", "--resolution", "1",
            "--workers", "0", "--out", str(out)]
    for json_flag in ([], ["--json"]):
        done = subprocess.run([sys.executable, *args, *json_flag, "--force"], capture_output=True, text=True,
                              timeout=60)
        errors = [line for line in done.stderr.splitlines() if line.startswith("trikedyn:")]
        assert done.returncode == 2 and len(errors) == 1, done.stderr
        assert "every one of the 5 layouts failed" in errors[0] and "no optimised vehicle" in errors[0]
        assert str(out / "optimise-evaluations.csv") in errors[0]
        assert (strict_json(done.stdout)["error"] if json_flag else done.stdout) in (errors[0][17:], "")
        assert not list(out.glob("*.toml")) and not (out / "optimise.json").exists()
        rows = list(csv.reader((out / "optimise-evaluations.csv").open()))[1:]
        assert len(rows) == 6 and {r[2] for r in rows} == {"failed"} and all("no threshold" in r[-4] for r in rows)


def test_worst_case_over_two_manoeuvres(reference):
    spec = opt.parse_optimise_spec({"optimise": {
        "knobs": {"component.battery.z_m": [0.25, 0.40]}, "manoeuvres": ["dlc", "slc"], "popsize": 1,
        "maxiter": 0, "resolution_kmh": 1.0, "high_kmh": 120.0}}, origin="two.toml")
    result = opt.run_optimise(reference, spec, workers=0)
    assert len(result.evaluations) == 1 + 5
    for ev in result.evaluations:
        assert ev.worst == min(ev.thresholds) and len(ev.thresholds) == 2
    assert result.best.worst == max(e.worst for e in result.evaluations if e.generation >= 0)
    assert result.best_threshold_speed_kmh >= result.reference_threshold_speed_kmh
    data = result.to_dict()
    assert set(data["thresholds"]) == {"dlc", "slc"} and data["objective"].startswith("worst")


def test_pure_helpers():
    assert opt.worst([None, 40.0]) == 0.0 and opt.worst([41.0, 40.5]) == 40.5
    assert opt.population_size(1, 2) == 5 and opt.population_size(5, 3) == 15
    spec = opt.parse_optimise_spec('[optimise]\nknobs = { "track_m" = [1.0, 1.3] }\n')
    assert (spec.manoeuvres, spec.seed, spec.step, spec.payload_kg) == (("dlc",), 1, 0.001, 0.0)
    assert opt._rounded([1.23456], spec) == (1.235,) and opt._rounded([1.19999], spec) == (1.2,)
    assert opt._rounded([0.9], spec) == (1.0,)  # kept within the bounds


def test_builtin_battery_layout_spec(reference):
    from trikedyn.study.spec import list_specs

    assert "battery-layout" in opt.list_optimise_specs()
    assert "battery-layout" not in list_specs()  # not a study spec
    spec = opt.load_optimise_spec("battery-layout")
    assert spec.names == ["component.battery.x_m", "component.battery.y_m", "component.battery.z_m"]
    spec.check(reference)
    battery = next(c for c in reference.params.components if c.name == "battery")
    for (_, low, high), value in zip(spec.knobs, (battery.x_m, battery.y_m, battery.z_m), strict=True):
        assert low <= value <= high  # the reference layout is in the bay: the optimum is never worse
    assert opt.population_size(spec.popsize, 3) * (spec.maxiter + 1) <= 200  # a run of about a minute


# ------------------------------------------------------------------------------------------------
# bad input: one line, exit code 2, no traceback, nothing written
# ------------------------------------------------------------------------------------------------
BAD_SPECS = [
    ('[optimise]\nknobs = { "component.battery.x_m" = [0.9, 0.6] }\n',
     "knobs: 'component.battery.x_m': expected [low, high] with low < high"),
    ('[optimise]\nknobs = { "component.battery.x_m" = [0.6, 0.9] }\npopsiz = 4\n',
     "unknown key 'popsiz' in optimise; did you mean 'popsize'?"),
    ('[optimise]\nknobs = { "component.batery.x_m" = [0.6, 0.9] }\n',
     "optimise.knobs: no component 'batery'; did you mean 'component.battery.x_m'?"),
    ('[optimise]\nknobs = { "track_m" = [0.1, 1.2] }\n', "track_m: expected a value from 0.3 to 3 m"),
    ('[optimise]\nknobs = { "mass.cg_z_m" = [0.3, 0.4] }\n', "the optimiser moves design knobs only"),
    ('[optimise]\nknobs = { "track_m" = [1.0, 1.2] }\nmanoeuvres = ["dlcc"]\n', "manoeuvres"),
    ('[optimise]\nknobs = { "track_m" = [1.0, 1.2] }\nmaxiter = -1\n', "maxiter"),
    ('[optimise]\nknobs = {}\n', "knobs"),
    ('[optimise\nknobs = 1\n', "invalid TOML"),
    ('knobs = { "track_m" = [1.0, 1.2] }\n', "unknown key 'knobs'"),
]


@pytest.mark.parametrize(("text", "expected"), BAD_SPECS)
def test_bad_spec_is_one_line(tmp_path, text, expected):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    code, stdout, err = run_cli("optimise", "reference-etrike", "--spec", str(path), "--out", str(out))
    assert code == 2, err
    assert stdout == "" and err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("trikedyn: error: ") and expected in err, err
    assert str(path) in err  # names the file
    assert not out.exists()  # nothing written


@pytest.mark.parametrize(("spec", "expected"), [
    ("battery-layuot", "unknown optimise spec 'battery-layuot'; did you mean 'battery-layout'?"),
    ("missing.toml", "missing.toml: no such optimise spec file"),
])
def test_bad_spec_name_is_one_line_and_json(tmp_path, spec, expected):
    code, stdout, err = run_cli("optimise", "reference-etrike", "--spec", spec, "--out", str(tmp_path / "o"), "--json")
    assert code == 2 and err.count("\n") == 1 and expected in err and "Traceback" not in err
    assert expected in strict_json(stdout)["error"]


def test_other_bad_options(tmp_path):
    code, _, err = run_cli("optimise", "reference-etrike", "--spec", "battery-layout", "--manoeuvre", "dlc",
                           "--manoeuvre", "slc", "-o", "speed_kmh=40", "--out", str(tmp_path / "o"))
    assert code == 2 and err.count("\n") == 1 and "--option" in err
    code, _, err = run_cli("optimise", "reference-etrike", "--spec", "battery-layout", "--resume", "--force",
                           "--out", str(tmp_path / "o"))
    assert code == 2 and err.count("\n") == 1 and "--resume" in err
    code, _, err = run_cli("optimise", "reference-etrike", "--spec", "battery-layout", "--popsize", "0")
    assert code == 2 and err.count("\n") == 1 and "--popsize" in err


def test_parse_errors_name_the_origin():
    with pytest.raises(InputError, match=r"^mine\.toml: optimise: missing"):
        opt.parse_optimise_spec("", origin="mine.toml")
