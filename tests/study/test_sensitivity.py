"""``trikedyn sensitivity``: the factors (assumed values that can vary), the SALib machinery (Ishigami), a
Morris run on the reference trike (CG height above trail), its files, resume, and one-line user errors."""

from __future__ import annotations

import csv
import dataclasses
import json
import math

import numpy as np
import pytest

from trikedyn.cli import main
from trikedyn.study.designs import factors as factor_module
from trikedyn.study.designs import sample_runs
from trikedyn.study.designs import sensitivity as sa

from ..conftest import strict_json
from . import warm_numba_cache

THREE = "mass.cg_z_m,wheels.front.x_m,steering.trail_m"
QUICK = ["--manoeuvre", "dlc", "--parameter", THREE, "--samples", "4", "--resolution", "0.5", "--criterion", "lift-off"]


def run(capsys, *args):
    code = main(list(args))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


# ------------------------------------------------------------------------------------------------------------
# the factors
# ------------------------------------------------------------------------------------------------------------
def test_factors_are_the_assumed_values_that_can_vary(reference):
    factors, excluded = sa.candidate_factors(reference)
    names = {f.name for f in factors}
    assert {"mass.roll_inertia_kgm2", "mass.cg_x_m", "steering.trail_m", "wheels.front.x_m", "tyre.mu_y",
            "track_m", "wheels.rear_left+rear_right.radius_m"} <= names
    # measured values, one wheel of a pair alone, zero values, no effect on the dynamics: not factors
    absent = {"mass.cg_z_m", "suspension.front.stiffness_N_per_m", "wheels.rear_left.y_m", "wheels.rear_right.y_m",
              "wheels.rear_left.x_m", "wheels.rear_left.radius_m", "mass.roll_yaw_product_kgm2", "tyre.curvature_x",
              "sensor.x_m", "freight.z_m", "steering.ackermann_fraction", "name", "layout"}
    assert not names & absent and not any(n.startswith(("components.", "component.")) for n in names)
    assert {"mass.roll_yaw_product_kgm2", "sensor.x_m", "freight.z_m", "steering.ackermann_fraction"} <= set(excluded)
    assert "components.battery.z_m" in excluded or not reference.params.components
    # every assumed number is either a factor (alone or in its pair's) or excluded with a reason
    covered = {p for f in factors for p in f.covers} | set(excluded)
    assert set(reference.assumed()) <= covered
    assert 40 <= len(factors) <= 60
    for f in factors:
        assert f.low < f.high and f.range_from in ("fraction", "narrowed", "declared")
        if f.range_from == "fraction":
            assert min(abs(f.low), abs(f.high)) == pytest.approx(0.8 * abs(f.value))


def test_the_inertias_are_narrowed_to_rigid_bodies(reference):
    """Each +/-20 %, the reference inertias (118, 373, 421 kg m^2) break the triangle inequality in a quarter
    of the samples: their ranges are narrowed so that every corner of the box is a rigid body."""
    import itertools

    factors, _ = sa.candidate_factors(reference)
    inertias = [f for f in factors if f.name in factor_module.INERTIAS]
    assert len(inertias) == 3 and all(f.range_from == "narrowed" for f in inertias)
    assert 0.05 < inertias[0].high / inertias[0].value - 1 < 0.2
    for corner in itertools.product(*[(f.low, f.high) for f in inertias]):
        sa.apply_factors(reference, inertias, corner)  # no ParameterError
    alone = sa.select_factors(reference, ["mass.roll_inertia_kgm2"])  # alone, +/-20 % is a rigid body
    assert alone[0].range_from == "fraction"


def test_track_moves_both_wheels_symmetrically_and_keeps_the_mass(reference):
    (track,) = sa.select_factors(reference, ["track_m"])
    assert track.value == pytest.approx(1.10) and (track.low, track.high) == pytest.approx((0.88, 1.32))
    wide = sa.apply_factors(reference, [track], [1.30])
    ys = {w.name: w.y_m for w in wide.params.wheels}
    assert ys == pytest.approx({"front": 0.0, "rear_left": 0.65, "rear_right": -0.65})
    assert wide.mass_kg == pytest.approx(reference.mass_kg, abs=1e-12)
    assert wide.cg_m == pytest.approx(reference.cg_m, abs=1e-12)


def test_named_parameters_and_their_mistakes(reference):
    chosen = sa.select_factors(reference, [THREE, "mass.cg_z_m"])
    assert [f.name for f in chosen] == ["mass.cg_z_m", "wheels.front.x_m", "steering.trail_m"]
    for name, needle in [("mass.cg_z", "did you mean 'mass.cg_z_m'?"), ("wheels.rear_left.y_m", "track_m"),
                         ("wheels.rear_right.y_m", "both wheels"),
                         ("layout", "not a number"), ("mass.roll_yaw_product_kgm2", "is 0")]:
        with pytest.raises(sa.InputError, match="--parameter") as info:
            sa.select_factors(reference, [name])
        assert needle in str(info.value)


def test_an_invalid_vehicle_is_a_failed_sample_not_an_error(reference):
    (cg,) = sa.select_factors(reference, ["mass.cg_z_m"])
    y, err, limit = sa.evaluate_sample(reference, (cg,), [-1.0], sa.Search("slc", {}, 5.0))
    assert y is None and err.startswith("invalid vehicle: ") and "\n" not in err and limit == ""


# ------------------------------------------------------------------------------------------------------------
# the machinery, independent of the vehicle
# ------------------------------------------------------------------------------------------------------------
def ishigami(X, a=7.0, b=0.1):
    return np.sin(X[:, 0]) + a * np.sin(X[:, 1]) ** 2 + b * X[:, 2] ** 4 * np.sin(X[:, 0])


ISHIGAMI = {"num_vars": 3, "names": ["x1", "x2", "x3"], "bounds": [[-math.pi, math.pi]] * 3}


def test_sobol_indices_of_the_ishigami_function():
    a, b = 7.0, 0.1  # published values (Ishigami & Homma 1990; Saltelli et al. 2008)
    v1 = 0.5 * (1 + b * math.pi**4 / 5) ** 2
    v2, v13 = a**2 / 8, b**2 * math.pi**8 * (1 / 18 - 1 / 50)
    var = v1 + v2 + v13
    s1, st = [v1 / var, v2 / var, 0.0], [(v1 + v13) / var, v2 / var, v13 / var]
    X = sa.sample(ISHIGAMI, "sobol", 2**13, seed=1)
    indices, used, dropped = sa.analyse(ISHIGAMI, "sobol", X, ishigami(X), seed=1)
    got = {r["parameter"]: r for r in indices}
    assert (used, dropped) == (2**13, 0) and [r["parameter"] for r in indices] == ["x1", "x2", "x3"]  # by ST
    for i, name in enumerate(ISHIGAMI["names"]):
        assert got[name]["S1"] == pytest.approx(s1[i], abs=0.02)
        assert got[name]["ST"] == pytest.approx(st[i], abs=0.02)
        assert 0 < got[name]["ST_conf"] < 0.05


def test_morris_screening_and_failed_rows_left_out_by_trajectory():
    X = sa.sample(ISHIGAMI, "morris", 40, seed=3)
    assert X.shape == (40 * 4, 3)
    np.testing.assert_array_equal(X, sa.sample(ISHIGAMI, "morris", 40, seed=3))  # seeded
    Y = ishigami(X)
    Y[5] = np.nan  # trajectory 1 (rows 4-7)
    indices, used, dropped = sa.analyse(ISHIGAMI, "morris", X, Y, seed=1)
    assert (used, dropped) == (39, 1)
    assert all(set(r) == {"parameter", "mu_star", "sigma", "mu_star_conf"} for r in indices)
    assert all(math.isfinite(r["mu_star"]) for r in indices)


def test_sobol_needs_a_power_of_two():
    with pytest.raises(sa.InputError, match="power of 2.*try 64 or 128"):
        sa.sample(ISHIGAMI, "sobol", 100)


# ------------------------------------------------------------------------------------------------------------
# the command
# ------------------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def morris_run(tmp_path_factory):
    """A Morris run over three parameters on the process pool, into a folder."""
    warm_numba_cache()
    import contextlib
    import io

    out = tmp_path_factory.mktemp("sens") / "out"
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        code = main(["sensitivity", "reference-etrike", *QUICK, "--workers", "2", "--out", str(out), "--json"])
    assert code == 0, stderr.getvalue()
    return out, strict_json(stdout.getvalue()), stderr.getvalue()


def test_morris_on_the_reference_trike(morris_run):
    out, data, err = morris_run
    assert data["method"] == "morris" and data["manoeuvre"] == "dlc" and data["fraction"] == 0.2
    assert data["n_runs"] == 4 * (3 + 1) and data["failed"] == 0
    assert 40 < data["reference_threshold_speed_kmh"] < 48
    assert [set(r) for r in data["indices"]] == [{"parameter", "mu_star", "sigma", "mu_star_conf"}] * 3
    ranked = [r["parameter"] for r in data["indices"]]
    assert ranked.index("mass.cg_z_m") < ranked.index("steering.trail_m")  # CG height dominates rollover
    mu = {r["parameter"]: r["mu_star"] for r in data["indices"]}
    assert mu["mass.cg_z_m"] > 2.0 and mu["mass.cg_z_m"] > 3 * mu["steering.trail_m"]
    assert "sensitivity: 0/16 runs" in err and "sensitivity: 16/16 runs" in err
    # the files: the same JSON, every sample with its threshold, the figure
    assert {p.name for p in out.iterdir()} == {"sensitivity.json", "sensitivity-samples.csv", "sensitivity.png",
                                              "sensitivity-plan.json"}
    assert strict_json((out / "sensitivity.json").read_text())["indices"] == data["indices"]
    with open(out / "sensitivity-samples.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert sorted(int(r["sample"]) for r in rows) == list(range(16))
    assert all(r["status"] == "ok" and float(r["threshold_speed_kmh"]) > 30 for r in rows)
    # what limited each sample's threshold, logged and counted
    assert {r["limit"] for r in rows} <= {"lift-off", "tracking", "speed not held"}
    assert data["limits"] == sample_runs.limit_counts(r["limit"] for r in rows)
    assert data["criterion"] == "lift-off" and data["speed_control"] == "driver"
    assert (out / "sensitivity.png").read_bytes()[:4] == b"\x89PNG"


def test_the_limits_are_said_only_when_both_occur():
    assert sample_runs.limit_counts(["lift-off", "", "tracking", "lift-off"]) == {"lift-off": 2, "tracking": 1}
    assert sample_runs.limit_counts(["cone strike", "lift-off", "top speed"]) == {
        "lift-off": 1, "tracking": 0, "cone strike": 1, "top speed": 1}
    assert sample_runs.limits_line(["lift-off", "lift-off", ""]) is None
    assert sample_runs.limits_line(["cone strike", "cone strike"]) is None
    line = sample_runs.limits_line(["lift-off", "tracking", "tracking"], ": so what")
    assert line.startswith("limits: 1 lift-off (a wheel lifted first), 2 tracking") and "two regimes" in line
    assert line.endswith(": so what")
    line = sample_runs.limits_line(["lift-off", "cone strike", "cone strike"])
    assert "2 cone strike (a cone was struck first)" in line and "tracking" not in line


def test_an_output_folder_is_not_overwritten_without_force(capsys, morris_run):
    out, _, _ = morris_run
    code, stdout, err = run(capsys, "sensitivity", "reference-etrike", *QUICK, "--out", str(out))
    assert code == 2 and stdout == "" and err.count("\n") == 1 and "--force" in err


def test_resume_runs_only_the_samples_missing(capsys, monkeypatch, morris_run, tmp_path):
    out, data, _ = morris_run
    folder = tmp_path / "resumed"
    folder.mkdir()
    for name in ("sensitivity-plan.json", "sensitivity-samples.csv"):
        (folder / name).write_bytes((out / name).read_bytes())
    lines = (folder / "sensitivity-samples.csv").read_text().splitlines(keepends=True)
    (folder / "sensitivity-samples.csv").write_text("".join(lines[:11]) + lines[11][:9])  # 10 rows and a cut one
    calls = []
    evaluate = sample_runs.evaluate_sample
    monkeypatch.setattr(sample_runs, "evaluate_sample", lambda *a: calls.append(1) or evaluate(*a))
    code, stdout, err = run(capsys, "sensitivity", "reference-etrike", *QUICK, "--workers", "0",
                            "--out", str(folder), "--resume", "--json")
    assert code == 0, err
    assert len(calls) == 6
    assert strict_json(stdout)["indices"] == data["indices"]
    assert strict_json(stdout)["limits"] == data["limits"]  # the logged samples' limits are read back
    with open(folder / "sensitivity-samples.csv", newline="") as fh:
        rows = [r for r in csv.DictReader(fh) if None not in r.values()]  # the cut row stays, on a line of its own
    assert sorted(int(r["sample"]) for r in rows) == list(range(16))
    # another seed into the same folder is another run: refused
    code, _, err = run(capsys, "sensitivity", "reference-etrike", *QUICK, "--seed", "2", "--out", str(folder),
                       "--resume")
    assert code == 2 and err.count("\n") == 1 and "seed" in err


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--parameter", "mass.cg_hieght_m"], "unknown parameter 'mass.cg_hieght_m'; did you mean 'mass.cg_z_m'?"),
        (["--parameter", "wheels.rear_left.y_m"], "track_m"),
        (["--method", "sobolev"], "--method: unknown method 'sobolev'; did you mean 'sobol'?"),
        (["--method", "sobol", "--samples", "10"], "power of 2"),
        (["--fraction", "1.5"], "--fraction"),
        (["--resume"], "--resume: needs --out"),
        (["--manoeuvre", "no-such"], "--manoeuvre"),
    ],
)
def test_user_errors_are_one_line(capsys, args, needle):
    code, stdout, err = run(capsys, "sensitivity", "reference-etrike", *args, "--json")
    assert code == 2 and err.count("\n") == 1 and needle in err, err
    assert json.loads(stdout)["error"]


# ------------------------------------------------------------------------------------------------------------
# a worker that dies
# ------------------------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class _DyingOnce(sa.Search):
    """A stand-in search: the first call in any worker kills its process (as a crash would); the others answer
    at once, the CG height in cm as the 'threshold'."""

    marker: str = ""

    def run(self, pset, dt_s=None):
        import os
        from types import SimpleNamespace

        if not os.path.exists(self.marker):
            open(self.marker, "w").close()
            os._exit(1)
        return SimpleNamespace(threshold_speed_kmh=100 * pset.params.mass.cg_z_m, detail="", limit="lift-off")


def test_a_dead_worker_costs_a_new_pool_not_the_run(reference, tmp_path):
    factors = sa.select_factors(reference, ["mass.cg_z_m", "steering.trail_m"])
    X = sa.sample(sa.problem(factors), "morris", 2, seed=1)
    seen = []
    Y, errors, limits = sa.run_samples(reference, factors, X, _DyingOnce(marker=str(tmp_path / "died")), workers=2,
                                       on_result=lambda i, y, err, limit: seen.append(i))
    assert (tmp_path / "died").exists() and errors == [None] * len(X) and limits == ["lift-off"] * len(X)
    np.testing.assert_allclose(Y, 100 * X[:, 0])
    assert sorted(seen) == list(range(len(X)))  # each sample reported once


def test_the_figure_says_when_the_indices_mix_two_regimes():
    empty = (np.zeros((0, 1)), np.zeros(0), [])
    indices = [{"parameter": "a", "mu_star": 2.0, "mu_star_conf": 0.5, "sigma": 1.0}]
    result = sa.SensitivityResult("v", "dlc", "morris", 0.2, 1, 1, [], {}, *empty, indices, 1, 0, 43.8,
                                  limits=["lift-off", "tracking", "tracking"])
    assert "1 lift-off, 2 tracking" in result.plot().axes[0].get_title()
    result.limits = ["lift-off"] * 3
    assert "tracking" not in result.plot().axes[0].get_title()


def test_places_whose_intervals_overlap_are_reported_as_unsettled():
    def rows(*pairs):
        return [{"parameter": f"p{k}", "mu_star": m, "mu_star_conf": c, "sigma": 0.0} for k, (m, c) in enumerate(pairs)]

    # 1 stands out; 2-4 chain (2 overlaps 3, 3 overlaps 4); 5 apart; 6-7 overlap
    ranked = rows((12.0, 1.0), (3.5, 1.0), (2.5, 0.5), (2.2, 0.3), (1.0, 0.1), (0.5, 0.2), (0.4, 0.2))
    assert sa.unsettled_places(ranked) == [(2, 4), (6, 7)]
    assert sa.unsettled_places(ranked, top=5) == [(2, 4)]
    assert sa.unsettled_places(rows((3.0, 0.1), (2.0, 0.1), (1.0, 0.1))) == []
    assert sa.unsettled_places(rows((3.0, float("nan")), (2.9, 0.1))) == []
    sobol = [{"parameter": "a", "ST": 0.6, "ST_conf": 0.1, "S1": 0.5, "S1_conf": 0.1},
             {"parameter": "b", "ST": 0.55, "ST_conf": 0.1, "S1": 0.4, "S1_conf": 0.1}]
    assert sa.unsettled_places(sobol) == [(1, 2)]


@pytest.mark.parametrize("command, design", [("sensitivity", "trikedyn.study.designs.sensitivity.run_sensitivity"),
                                             ("uncertainty", "trikedyn.study.designs.uncertainty.run_uncertainty")])
def test_the_pool_starts_before_the_reference_search(capsys, monkeypatch, command, design):
    """The pool's fork server (its imports, about a second) starts with the command, so that it overlaps the
    main process's set-up and reference search instead of following them; not without workers."""
    import importlib

    import trikedyn.study.engine.executors as executors

    calls = []
    monkeypatch.setattr(executors, "pool_context", lambda: calls.append("pool"))

    def design_run(*args, **kwargs):
        calls.append("design")
        raise RuntimeError("stop here")

    module, name = design.rsplit(".", 1)
    monkeypatch.setattr(importlib.import_module(module), name, design_run)
    for workers, expected in (("2", ["pool", "design"]), ("0", ["design"])):
        calls.clear()
        with pytest.raises(RuntimeError, match="stop here"):
            main([command, "reference-etrike", "--workers", workers, "-p", "track_m"])
        assert calls == expected
