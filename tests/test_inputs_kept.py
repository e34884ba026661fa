"""Issue 21: no command writes onto a file it reads, not even with ``--force`` (which only allows replacing
earlier outputs); a study never takes over a folder that is not a study's without ``--force``.

Each case runs the command line in a subprocess (with a timeout of 60 s), in a folder of its own, and checks
that it exits 0 or 2 with one line and that no input lost a byte (SHA-256 of every input before and after).
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import SHARED, strict_json
from .study import warm_numba_cache

TIR = SHARED / "data" / "tyres" / "mf_185_80R14.tir"
PATH_CSV = "x_m,y_m\n" + "\n".join(f"{2.0 * i:.1f},{1.5 * (1 if i > 15 else i / 15):.3f}" for i in range(31)) + "\n"
FAST = ["--resolution", "1", "--workers", "0"]


def trikedyn(cwd: Path, *args, timeout: float = 60.0) -> tuple[int, str, str]:
    """Run ``trikedyn ARGS`` in ``cwd``; (exit code, stdout, stderr)."""
    proc = subprocess.run([sys.executable, "-m", "trikedyn", *map(str, args)], cwd=cwd, capture_output=True,
                          text=True, timeout=timeout, env={**os.environ, "COLUMNS": "200"})
    return proc.returncode, proc.stdout, proc.stderr


def digest(*files: Path) -> dict[str, str]:
    return {str(f): hashlib.sha256(f.read_bytes()).hexdigest() for f in files}


def refused(cwd: Path, inputs: list[Path], *args, needle: str = "is also an input of this command") -> str:
    """The command refuses in one line (exit 2; under --json one valid error object), the inputs unchanged."""
    before = digest(*inputs)
    code, out, err = trikedyn(cwd, *args)
    lines = err.strip().splitlines()
    assert code == 2, (code, out, err)
    assert len(lines) == 1 and lines[0].startswith("trikedyn: error: ") and needle in lines[0], err
    if "--json" in args:
        assert "error" in strict_json(out)
    assert digest(*inputs) == before
    return lines[0]


@pytest.fixture
def folder(tmp_path) -> Path:
    """``out/`` with a path CSV under each sampled command's own CSV name, and a chain of vehicle files."""
    out = tmp_path / "out"
    out.mkdir()
    for name in ("sensitivity-samples.csv", "uncertainty-samples.csv", "optimise-evaluations.csv",
                 "loading-chart.csv", "results.csv"):
        (out / name).write_text(PATH_CSV, encoding="utf-8")
    (tmp_path / "base.toml").write_text('extends = "reference-etrike"\nname = "base"\n', encoding="utf-8")
    (tmp_path / "child.toml").write_text('extends = "base.toml"\nname = "child"\n', encoding="utf-8")
    return tmp_path


@pytest.mark.parametrize(("command", "csv", "more"), [
    ("sensitivity", "sensitivity-samples.csv", ["--samples", "2", "-p", "mass.cg_z_m"]),
    ("uncertainty", "uncertainty-samples.csv", ["--samples", "2", "-p", "mass.cg_z_m"]),
    ("optimise", "optimise-evaluations.csv", ["--spec", "battery-layout", "--maxiter", "0", "--popsize", "1"]),
    ("loading-chart", "loading-chart.csv", ["--masses", "0", "--x", "0.8", "--z", "0.5"]),
])
def test_a_path_csv_named_as_the_commands_own_csv_in_out_is_kept(folder, command, csv, more):
    """The issue's case: ``--manoeuvre out/<its csv> --out out --force`` replaced the path with the log."""
    path = folder / "out" / csv
    line = refused(folder, [path], command, "reference-etrike", "--manoeuvre", f"out/{csv}", "--out", "out",
                   "--force", *FAST, *more, "--json")
    assert f"out/{csv}" in line and "not even with --force" in line


def test_resume_does_not_append_to_an_input_either(folder):
    path = folder / "out" / "sensitivity-samples.csv"
    refused(folder, [path], "sensitivity", "reference-etrike", "--manoeuvre", "out/sensitivity-samples.csv",
            "--out", "out", "--resume", "--samples", "2", "-p", "mass.cg_z_m", *FAST)


def _identification(folder: Path) -> Path:
    """An identification JSON (``trikedyn identify --json``) named ``out/uncertainty.json``."""
    import numpy as np

    from trikedyn.measure.suspension import identify_suspension

    t = np.arange(0.0, 20.0, 0.01)
    wn = 2 * np.pi * 2.9
    a = np.where(t >= 5.0, 8.0 * np.exp(-0.2 * wn * (t - 5.0)) * np.cos(wn * np.sqrt(1 - 0.04) * (t - 5.0)), 0.0)
    a = a + np.random.default_rng(1).normal(0.0, 0.05, t.size)
    result = identify_suspension(t, a, 239.2)
    path = folder / "out" / "uncertainty.json"
    path.write_text(json.dumps(result.to_dict()), encoding="utf-8")
    return path


def test_an_identification_named_uncertainty_json_in_out_is_kept(folder):
    path = _identification(folder)
    refused(folder, [path], "uncertainty", "reference-etrike", "--identification", "front=out/uncertainty.json",
            "--out", "out", "--force", "--samples", "2", "-p", "mass.cg_z_m", *FAST)
    # a folder holding it: the file in it counts as read
    (folder / "ids").mkdir()
    shutil.copy(path, folder / "ids" / "uncertainty.json")
    refused(folder, [folder / "ids" / "uncertainty.json"], "uncertainty", "reference-etrike", "--identification",
            "front=ids", "--out", "ids", "--force", "--samples", "2", "-p", "mass.cg_z_m", *FAST)


def test_optimise_keeps_the_file_its_vehicle_extends(folder):
    """A vehicle named 'base' extends out/base-optimised.toml: the optimised vehicle's own file name."""
    out = folder / "out"
    shutil.copy(folder / "base.toml", out / "base-optimised.toml")
    (out / "mine.toml").write_text('extends = "base-optimised.toml"\nname = "base"\n', encoding="utf-8")
    line = refused(folder, [out / "base-optimised.toml", out / "mine.toml"], "optimise", "out/mine.toml", "--spec",
                   "battery-layout", "--out", "out", "--force", "--maxiter", "0", "--popsize", "1", *FAST)
    assert "extended by mine.toml" in line


def test_vehicle_export_keeps_the_file_a_vehicle_extends_even_through_links(folder):
    inputs = [folder / "base.toml", folder / "child.toml"]
    line = refused(folder, inputs, "vehicle", "export", "child.toml", "base.toml", "--force")
    assert line.startswith("trikedyn: error: base.toml: ") and "extended by child.toml" in line
    (folder / "link.toml").symlink_to("base.toml")
    refused(folder, inputs, "vehicle", "export", "child.toml", "link.toml", "--force")
    os.link(folder / "base.toml", folder / "hard.toml")
    refused(folder, inputs, "vehicle", "export", "child.toml", "hard.toml", "--force", "--json")
    # a chain of two: the grandparent too
    (folder / "grandchild.toml").write_text('extends = "child.toml"\nname = "gc"\n', encoding="utf-8")
    refused(folder, inputs, "vehicle", "export", "grandchild.toml", "base.toml", "--force")
    # and a file the vehicle does not read is written as before
    code, _, err = trikedyn(folder, "vehicle", "export", "child.toml", "copy.toml")
    assert code == 0 and err == "" and (folder / "copy.toml").is_file()


@pytest.mark.skipif(not TIR.is_file(), reason=f"no {TIR}")
def test_a_wheels_tyre_file_counts_as_read(folder):
    (folder / "front.tir").write_bytes(TIR.read_bytes())
    (folder / "tyred.toml").write_text('extends = "child.toml"\nname = "tyred"\n[[wheels]]\nname = "front"\n'
                                       'tyre_file = "front.tir"\nradius_m = 0.376\n', encoding="utf-8")
    line = refused(folder, [folder / "front.tir", folder / "tyred.toml"], "vehicle", "export", "tyred.toml",
                   "front.tir", "--force")
    assert "a tyre file named in tyred.toml" in line


def test_study_refuses_a_folder_that_is_not_a_study(folder):
    """The issue's case: a user's results.csv and fig_*.png in --out were replaced without --force."""
    warm_numba_cache()  # the runs below load the compiled code instead of compiling it
    out = folder / "out"
    (out / "fig_mine.png").write_bytes(b"\x89PNG not really")
    spec = folder / "spec.toml"
    spec.write_text('name = "s"\nvehicle = "reference-etrike"\nmanoeuvres = ["slc"]\nfreight_kg = [0]\n'
                    'resolution_kmh = 2.0\n', encoding="utf-8")
    inputs = [out / "results.csv", out / "fig_mine.png", spec]
    line = refused(folder, inputs, "study", "spec.toml", "--out", "out", "--workers", "0", "--json",
                   needle="no study (no study.sqlite)")
    assert "--force" in line and not (out / "study.sqlite").exists()
    # the spec itself is never a study's output, not even with --force
    shutil.copy(spec, out / "results.csv")
    refused(folder, [out / "results.csv"], "study", "out/results.csv", "--out", "out", "--force", "--workers", "0")
    # an empty folder, or a study's own, runs (and resumes)
    code, out_text, err = trikedyn(folder, "study", "spec.toml", "--out", "fresh", "--workers", "0", "--json")
    assert code == 0, err
    code, out_text, err = trikedyn(folder, "study", "spec.toml", "--out", "fresh", "--workers", "0", "--json")
    assert code == 0 and strict_json(out_text)["scenarios"]["skipped"] == 1, err


def test_an_input_in_out_under_another_name_is_fine(folder):
    """Inputs in --out that are not among the command's outputs do not stop it (the vehicle file kept)."""
    warm_numba_cache()
    out = folder / "out"
    shutil.copy(folder / "base.toml", out / "base.toml")
    (out / "mine.toml").write_text('extends = "base.toml"\nname = "mine"\n', encoding="utf-8")
    before = digest(out / "mine.toml", out / "base.toml")
    code, out_text, err = trikedyn(folder, "loading-chart", "out/mine.toml", "--manoeuvre", "slc", "--masses", "0",
                                   "--x", "0.8", "--z", "0.5", "--out", "out", "--force", *FAST, "--json")
    assert code == 0, err
    assert strict_json(out_text)["files"]["csv"] == str(Path("out") / "loading-chart.csv")
    assert digest(out / "mine.toml", out / "base.toml") == before
