"""``trikedyn uncertainty``: the inputs (uniform assumed values, normal measured ones), the Latin hypercube, a
small run on the reference trike with its files and resume, and one-line user errors."""

from __future__ import annotations

import contextlib
import csv
import io
import json

import numpy as np
import pytest

from trikedyn.cli import main
from trikedyn.errors import InputError
from trikedyn.study.designs import sample_runs
from trikedyn.study.designs import uncertainty as ua

from ..conftest import strict_json
from . import warm_numba_cache

QUICK = ["--manoeuvre", "dlc", "--parameter", "steering.trail_m", "--std", "mass.cg_z_m=0.01", "--samples", "12",
         "--resolution", "0.5", "--workers", "0"]


def run(capsys, *args):
    code = main(list(args))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_inputs_and_latin_hypercube(reference):
    inputs, excluded = ua.build_inputs(reference, ["steering.trail_m"], {"mass.cg_z_m": 0.01})
    assert [(i.name, i.distribution) for i in inputs] == [("steering.trail_m", "uniform"), ("mass.cg_z_m", "normal")]
    assert excluded == {}
    cg = inputs[1]
    assert (cg.factor.low, cg.factor.high) == pytest.approx((cg.factor.value - 0.03, cg.factor.value + 0.03))
    assert cg.to_dict()["mean"] == cg.factor.value and cg.to_dict()["std"] == 0.01
    assert set(inputs[0].to_dict()) >= {"parameter", "distribution", "low", "high"}
    X = ua.sample(inputs, 200, seed=3)
    assert X.shape == (200, 2) and np.array_equal(X, ua.sample(inputs, 200, seed=3))
    trail = inputs[0].factor
    # a Latin hypercube: one sample in each of the n equal-probability strata of every input
    strata = np.floor((X[:, 0] - trail.low) / (trail.high - trail.low) * 200).astype(int)
    assert sorted(strata) == list(range(200))
    assert np.all(np.abs(X[:, 1] - cg.factor.value) <= 0.03 + 1e-12)
    assert np.std(X[:, 1]) == pytest.approx(0.01 * 0.986, rel=0.1)  # a normal truncated at 3 sigma
    # a value both uniform and measured is normal, once
    both, _ = ua.build_inputs(reference, ["mass.cg_z_m", "steering.trail_m"], {"mass.cg_z_m": 0.01})
    assert [i.name for i in both] == ["steering.trail_m", "mass.cg_z_m"]


@pytest.mark.parametrize("text", ["mass.cg_z_m", "=0.01", "mass.cg_z_m=abc", "mass.cg_z_m=-1", "mass.cg_z_m=nan"])
def test_bad_std_is_refused(text):
    with pytest.raises(InputError) as exc:
        ua.parse_std([text])
    assert exc.value.where == "--std"


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    """12 Latin-hypercube samples over the trail (uniform) and the CG height (normal, 1 cm), into a folder."""
    warm_numba_cache()
    out = tmp_path_factory.mktemp("unc") / "out"
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        code = main(["uncertainty", "reference-etrike", *QUICK, "--out", str(out), "--json"])
    assert code == 0, stderr.getvalue()
    return out, strict_json(stdout.getvalue()), stderr.getvalue()


def test_small_run_on_the_reference_trike(small_run):
    out, data, err = small_run
    assert data["n"] + data["failed"] == 12 and data["failed"] == 0
    assert data["p05_kmh"] <= data["median_kmh"] <= data["p95_kmh"]
    assert data["mean_kmh"] > 0 and data["std_kmh"] >= 0
    ref = data["reference_threshold_speed_kmh"]
    assert 40 < ref < 48
    assert data["p05_kmh"] - 1.0 <= ref <= data["p95_kmh"] + 1.0  # within (or near) the band
    assert [(i["parameter"], i["distribution"]) for i in data["inputs"]] == [
        ("steering.trail_m", "uniform"), ("mass.cg_z_m", "normal")]
    assert {"low", "high"} <= set(data["inputs"][0]) and {"mean", "std"} <= set(data["inputs"][1])
    assert len(data["samples"]) == 12
    assert all({"steering.trail_m", "mass.cg_z_m", "threshold_speed_kmh"} <= set(s) for s in data["samples"])
    assert "uncertainty: 0/12 runs" in err and "uncertainty: 12/12 runs" in err
    assert {p.name for p in out.iterdir()} == {"uncertainty.json", "uncertainty-samples.csv", "uncertainty.png",
                                              "uncertainty-plan.json"}
    assert strict_json((out / "uncertainty.json").read_text())["median_kmh"] == data["median_kmh"]
    with open(out / "uncertainty-samples.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert sorted(int(r["sample"]) for r in rows) == list(range(12)) and all(r["status"] == "ok" for r in rows)
    assert (out / "uncertainty.png").read_bytes()[:4] == b"\x89PNG"


def test_resume_and_no_overwrite(capsys, monkeypatch, small_run, tmp_path):
    out, data, _ = small_run
    code, stdout, err = run(capsys, "uncertainty", "reference-etrike", *QUICK, "--out", str(out))
    assert code == 2 and stdout == "" and err.count("\n") == 1 and "--force" in err
    folder = tmp_path / "resumed"
    folder.mkdir()
    for name in ("uncertainty-plan.json", "uncertainty-samples.csv"):
        (folder / name).write_bytes((out / name).read_bytes())
    lines = (folder / "uncertainty-samples.csv").read_text().splitlines(keepends=True)
    (folder / "uncertainty-samples.csv").write_text("".join(lines[:11]))  # 10 of 12 samples done
    calls = []
    evaluate = sample_runs.evaluate_sample
    monkeypatch.setattr(sample_runs, "evaluate_sample", lambda *a: calls.append(1) or evaluate(*a))
    code, stdout, err = run(capsys, "uncertainty", "reference-etrike", *QUICK, "--out", str(folder), "--resume",
                            "--json")
    assert code == 0, err
    assert len(calls) == 2
    assert strict_json(stdout)["median_kmh"] == data["median_kmh"]


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--std", "mass.cg_z_m"], "--std: expected PATH=SIGMA"),
        (["--std", "mass.cg_z_m=-0.01"], "--std"),
        (["--std", "mass.cg_hieght_m=0.01"], "did you mean 'mass.cg_z_m'?"),
        (["--parameter", "wheels.rear_left.y_m"], "track_m"),
        (["--resume"], "--resume: needs --out"),
    ],
)
def test_user_errors_are_one_line(capsys, args, needle):
    code, stdout, err = run(capsys, "uncertainty", "reference-etrike", "--manoeuvre", "dlc", *args, "--json")
    assert code == 2 and err.count("\n") == 1 and needle in err, err
    assert json.loads(stdout)["error"]


def test_two_regimes_are_stacked_in_the_histogram():
    """Samples limited by lift-off and by a lost path are drawn as two stacked parts, each counted; with one
    regime, one histogram."""
    y = np.array([40.0, 41.0, 42.5, 44.0, 47.0, 50.0, np.nan])
    limits = ["lift-off", "lift-off", "lift-off", "tracking", "tracking", "tracking", ""]
    result = ua.UncertaintyResult("v", "dlc", 0.2, 7, 1, [], {}, np.zeros((7, 0)), y, [None] * 6 + ["failed"], 43.8,
                                  limits=limits)
    labels = result.plot().axes[0].get_legend_handles_labels()[1]
    assert "lift-off (n=3)" in labels and "tracking (n=3); 1 failed" in labels
    result.limits = ["lift-off"] * 6 + [""]
    labels = result.plot().axes[0].get_legend_handles_labels()[1]
    assert any(label.startswith("samples (n=6, 1 failed)") for label in labels)
    assert result.to_dict()["limits"] == {"lift-off": 6, "tracking": 0}
