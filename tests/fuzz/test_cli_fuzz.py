"""Fuzzing the command line with mutated real inputs: logs, vehicle files, weighing files, path CSVs and
study specs. Every case must exit 0 or 2; an error is one line on stderr; `--json` output is always valid
JSON (no NaN or Infinity); nothing hangs.

Each input kind starts from a valid seed (the real WitMotion logs when ``shared/data`` is at hand) and
applies a few random edits: delete, duplicate or swap spans and lines, replace characters, insert
troublesome tokens (``nan``, ``1e308``, ``-0``, huge integers, ``../``), truncate.
"""

from __future__ import annotations

import contextlib
import io
import time
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from trikedyn.cli import main

from ..conftest import SHARED, WEIGHING, strict_json

TOKENS = ["nan", "inf", "-inf", "1e308", "-1e308", "1e-300", "0", "-0", "-1", "99999999999999999999999999",
          "1e9", "''", '""', "[]", "{}", "true", "../../../../etc/passwd", "/etc/passwd", "\x00", "é", ",", "=",
          "\n", "[", "]", "#", '"', "0x1F", "1_000", "NaN"]
LIMIT_S = 60.0
"""A case taking longer than this counts as a hang."""


@st.composite
def mutated(draw, seed: bytes) -> bytes:
    data = bytearray(seed)
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["delete", "duplicate", "replace", "token", "truncate", "swap_lines"]))
        n = len(data)
        i = draw(st.integers(0, max(n - 1, 0)))
        j = min(n, i + draw(st.integers(1, 40)))
        if kind == "delete":
            del data[i:j]
        elif kind == "duplicate":
            data[i:i] = data[i:j]
        elif kind == "replace" and n:
            data[i] = draw(st.integers(0, 255))
        elif kind == "token":
            data[i:i] = draw(st.sampled_from(TOKENS)).encode("utf-8")
        elif kind == "truncate":
            del data[i:]
        elif kind == "swap_lines":
            lines = bytes(data).split(b"\n")
            if len(lines) > 2:
                a = draw(st.integers(0, len(lines) - 1))
                b = draw(st.integers(0, len(lines) - 1))
                lines[a], lines[b] = lines[b], lines[a]
                data = bytearray(b"\n".join(lines))
    return bytes(data)


def run_cli(args: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    start = time.perf_counter()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(args)
    assert time.perf_counter() - start < LIMIT_S, f"{args}: took {time.perf_counter() - start:.0f} s"
    return code, out.getvalue(), err.getvalue()


def check_contract(args: list[str]) -> int:
    code, out, err = run_cli(args)
    ok = (0, 1, 2) if args[:2] == ["vehicle", "check"] else (0, 2)  # vehicle check: 1 = inconsistent findings
    assert code in ok, f"{args}: exit {code}\n{err[-3000:]}"
    lines = [line for line in err.splitlines() if line]
    assert all(line.startswith(("trikedyn: error: ", "trikedyn: warning: ")) for line in lines), err[-3000:]
    assert "Traceback" not in err
    if code == 2:
        assert sum(line.startswith("trikedyn: error: ") for line in lines) == 1, err
    if "--json" in args:
        strict_json(out)
    return code


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


@given(raw=mutated(PATH))
def test_path_csvs(tmp_path, raw):
    file = _write(tmp_path, "line.csv", raw)
    check_contract(["simulate", "reference-etrike", "--manoeuvre", file, "--speed", "15", "--json"])


@given(raw=mutated(SPEC))
def test_study_specs(tmp_path, raw):
    check_contract(["study", _write(tmp_path, "spec.toml", raw), "--dry-run", "--out", str(tmp_path / "o"),
                    "--json"])
