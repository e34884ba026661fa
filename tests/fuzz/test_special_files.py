"""Every path a user can name, given as a named pipe (FIFO) without a writer, a device (``/dev/zero``, through
a link of the expected name) or a huge sparse file (3 GiB, nothing on disk): a log, a vehicle file and the file
it ``extends``, a weighing, a study spec and the vehicle it names, a path CSV, a run file (CSV, Parquet, and
its ``.json`` sidecar) through ``plot``, ``animate`` and ``compare``, and a ``.tir`` through ``tyre show`` and as
a wheel's ``tyre_file`` (issue 21). Each must exit 0 or 2 with the one line ``trikedyn: error: ...``, no
traceback, within :data:`LIMIT_S` -- a reader that opens a FIFO and waits, or reads a device or a huge file to
its end, fails here.

The commands run as separate processes (a process blocked in ``open`` on a FIFO is killed at the limit, which
a test in this process could not do), several at a time, once per session; each case is its own test.
"""

from __future__ import annotations

import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

LIMIT_S = 60.0
"""A case still running after this long is a hang (killed)."""
HUGE_BYTES = 3 * 2**30
SPECIALS = ("fifo", "device", "huge")

RUN_CSV = "time_s,x_m,y_m,yaw_rad,speed_mps,front_fz_N,rear_left_fz_N,rear_right_fz_N\n" + "".join(
    f"{0.1 * i:.1f},{0.8 * i:.2f},0,0,8.0,1500,1200,1200\n" for i in range(30))
WEIGHING_CONTACTS = "reading_std_kg = 0.5\n"

# path kind -> (the special file's name, other files of the case, the command; {p}: the special file,
# {d}: the case's folder)
CASES = {
    "log": ("log.csv", {}, ["log", "info", "{p}", "--json"]),
    "vehicle": ("vehicle.toml", {}, ["vehicle", "check", "{p}", "--json"]),
    "vehicle-extends": ("base.toml", {"child.toml": 'extends = "base.toml"\nname = "c"\ndescription = "d"\n'},
                        ["vehicle", "check", "{d}/child.toml", "--json"]),
    "weighing": ("weighing.toml", {}, ["cg", "weigh", "{p}", "--json"]),
    "study-spec": ("spec.toml", {}, ["study", "{p}", "--dry-run", "--out", "{d}/out", "--json"]),
    "study-spec-vehicle": ("vehicle.toml", {"spec.toml": 'name = "s"\nvehicle = "vehicle.toml"\nmanoeuvres = '
                                            '["slc"]\nfreight_kg = [0]\n'},
                           ["study", "{d}/spec.toml", "--dry-run", "--out", "{d}/out", "--json"]),
    "path-csv": ("line.csv", {}, ["simulate", "reference-etrike", "--manoeuvre", "{p}", "--speed", "15", "--json"]),
    "run-csv-plot": ("run.csv", {}, ["plot", "{p}", "--out", "{d}/f.png", "--json"]),
    "run-csv-animate": ("run.csv", {}, ["animate", "{p}", "--out", "{d}/a.gif", "--every-s", "60", "--json"]),
    "run-csv-compare": ("run.csv", {"other.csv": RUN_CSV}, ["compare", "{p}", "{d}/other.csv", "--json"]),
    "run-parquet-plot": ("run.parquet", {}, ["plot", "{p}", "--out", "{d}/f.png", "--json"]),
    "run-sidecar-plot": ("run.json", {"run.csv": RUN_CSV}, ["plot", "{d}/run.csv", "--out", "{d}/f.png", "--json"]),
    "run-sidecar-animate": ("run.json", {"run.csv": RUN_CSV},
                            ["animate", "{d}/run.csv", "--out", "{d}/a.gif", "--every-s", "60", "--json"]),
    "tir": ("x.tir", {}, ["tyre", "show", "{p}", "--json"]),
    "tir-in-vehicle": ("x.tir", {"vehicle.toml": 'extends = "reference-etrike"\nname = "t"\ndescription = "d"\n'
                                                 '[[wheels]]\nname = "front"\ntyre_file = "x.tir"\n'},
                       ["vehicle", "check", "{d}/vehicle.toml", "--json"]),
}

PENDING = {}
"""Cases that fail in another engineer's reader before that fix lands: ``(kind, special) -> reason`` (marked
``xfail(strict=False)``)."""


def _make(path: Path, special: str) -> None:
    if special == "fifo":
        os.mkfifo(path)
    elif special == "device":
        path.symlink_to("/dev/zero")
    else:
        with open(path, "wb") as fh:
            fh.truncate(HUGE_BYTES)


def _run(folder: Path, kind: str, special: str) -> dict:
    name, others, command = CASES[kind]
    case = folder / f"{kind}-{special}"
    case.mkdir()
    for other, text in others.items():
        (case / other).write_text(text, encoding="utf-8")
    _make(case / name, special)
    args = [a.format(p=case / name, d=case) for a in command]
    try:
        done = subprocess.run([sys.executable, "-m", "trikedyn", *args], capture_output=True, text=True,
                              timeout=LIMIT_S, cwd=case, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return {"args": args, "code": None, "err": f"still running after {LIMIT_S:g} s (a hang): killed"}
    return {"args": args, "code": done.returncode, "err": done.stderr}


@pytest.fixture(scope="module")
def outcomes(tmp_path_factory):
    """Every case, run in its own folder, four at a time."""
    folder = tmp_path_factory.mktemp("special")
    keys = [(kind, special) for kind in CASES for special in SPECIALS]
    with ThreadPoolExecutor(max_workers=4) as pool:
        results = list(pool.map(lambda key: _run(folder, *key), keys))
    return dict(zip(keys, results, strict=True))


def _params():
    for kind in CASES:
        for special in SPECIALS:
            reason = PENDING.get((kind, special))
            marks = [pytest.mark.xfail(strict=False, reason=reason)] if reason else []
            yield pytest.param(kind, special, id=f"{kind}-{special}", marks=marks)


@pytest.mark.skipif(not hasattr(os, "mkfifo") or not Path("/dev/zero").exists(), reason="needs FIFOs and /dev/zero")
@pytest.mark.parametrize(("kind", "special"), list(_params()))
def test_a_pipe_a_device_or_a_huge_file_is_refused_in_one_line(outcomes, kind, special):
    got = outcomes[(kind, special)]
    assert got["code"] is not None, f"{got['args']}: {got['err']}"
    assert got["code"] in (0, 2), f"{got['args']}: exit {got['code']}\n{got['err'][-3000:]}"
    assert "Traceback" not in got["err"], got["err"][-3000:]
    if got["code"] == 2:
        lines = [line for line in got["err"].splitlines() if line]
        assert len(lines) == 1 and lines[0].startswith("trikedyn: error: "), f"{got['args']}\n{got['err'][-3000:]}"
