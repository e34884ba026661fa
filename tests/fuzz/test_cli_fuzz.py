"""Fuzzing the command line with mutated real inputs: logs, vehicle files, weighing files, path CSVs and
study specs (run files and ``.tir`` files: ``test_run_files.py``, ``test_tir_files.py``; pipes, devices and huge
files: ``test_special_files.py``). Every case must exit 0 or 2; an error is one line on stderr; `--json`
output is always valid JSON (no NaN or Infinity); nothing hangs (:mod:`tests.fuzz.contract`).

Each input kind starts from a valid seed (the real WitMotion logs when ``shared/data`` is at hand) and
applies a few random edits: delete, duplicate or swap spans and lines, replace characters, insert
troublesome tokens (``nan``, ``1e308``, ``-0``, huge integers, ``../``), truncate.
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from trikedyn.cli import main

from ..conftest import SHARED, WEIGHING
from .contract import check_contract, mutated


# ----------------------------------------------------------------------------------------------------------
# seeds
# ----------------------------------------------------------------------------------------------------------
def _synthetic_log() -> bytes:
    rows = [f"{0.01 * i:.2f},{0.1 * ((i * 7) % 11) - 0.5:.3f},{0.05 * ((i * 3) % 5):.3f},"
            f"{9.81 + 0.3 * ((i * 5) % 9 - 4) / 4:.3f}" for i in range(400)]
    return ("time_s,ax_mps2,ay_mps2,az_mps2\n" + "\n".join(rows) + "\n").encode()


def _log_seeds() -> list[bytes]:
    seeds = [_synthetic_log()]
    folder = SHARED / "data" / "witmotion"
    if folder.is_dir():
        for path in sorted(folder.iterdir()):
            if path.suffix.lower() in (".txt", ".csv"):
                seeds.append(path.read_bytes()[:20_000])
    return seeds


VEHICLE = b'''extends = "reference-etrike"
name = "fuzzed"
description = "a variant"
[mass]
curb_kg = 420.0
cg_z_m = 0.42
[suspension.rear]
stiffness_N_per_m = 30000.0
'''


PATH = ("x_m,y_m\n" + "\n".join(f"{2.0 * i:.1f},{1.5 * (1 if i > 15 else i / 15):.3f}" for i in range(31))
        + "\n").encode()

SPEC = b'''name = "fuzz"
vehicle = "reference-etrike"
manoeuvres = ["slc"]
freight_kg = [0, 100]
resolution_kmh = 1.0
[[groups]]
name = "stiffness"
stiffness_scale = [0.9, 1.1]
overrides = { "mass.driver_kg" = [70, 90] }
'''


def _write(tmp_path: Path, name: str, data: bytes) -> str:
    path = tmp_path / name
    path.write_bytes(data)
    return str(path)


# ----------------------------------------------------------------------------------------------------------
# the cases
# ----------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("seed", range(len(_log_seeds())))
@given(data=st.data())
def test_logs(tmp_path, seed, data):
    raw = data.draw(mutated(_log_seeds()[seed]))
    file = _write(tmp_path, "log.txt" if seed else "log.csv", raw)
    check_contract(["log", "info", file, "--json"])
    check_contract(["identify", file, "--sprung-mass", "240", "--json"])


@given(raw=mutated(VEHICLE))
def test_vehicle_files(tmp_path, raw):
    file = _write(tmp_path, "vehicle.toml", raw)
    check_contract(["vehicle", "check", file, "--json"])


@given(raw=mutated(WEIGHING.encode()))
def test_weighing_files(tmp_path, raw):
    check_contract(["cg", "weigh", _write(tmp_path, "weighing.toml", raw), "--json"])


@pytest.fixture(scope="module")
def compiled():
    """The simulation loop compiled before the first timed case: a cold compile (no numba cache yet, a loaded
    machine) took 191 s in the campaign and counted as a hang of the first path CSV, which it is not."""
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert main(["simulate", "reference-etrike", "--manoeuvre", "slc", "--speed", "15", "--json"]) == 0


@given(raw=mutated(PATH))
def test_path_csvs(tmp_path, compiled, raw):  # noqa: ARG001
    file = _write(tmp_path, "line.csv", raw)
    check_contract(["simulate", "reference-etrike", "--manoeuvre", file, "--speed", "15", "--json"])


@given(raw=mutated(SPEC))
def test_study_specs(tmp_path, raw):
    check_contract(["study", _write(tmp_path, "spec.toml", raw), "--dry-run", "--out", str(tmp_path / "o"),
                    "--json"])
