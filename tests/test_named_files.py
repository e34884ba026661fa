"""Issue 21: no hangs, one bounded reader, and one rule for every file a file names.

Through the command line (``trikedyn.cli.main``): a named pipe (FIFO), a device, a folder or a huge sparse file
named where a file is expected is refused in one line (exit 2), fast, and no input changes; a path that a file
names lies in that file's folder or below it (``extends``, a wheel's ``tyre_file``, a study spec's ``vehicle``
and its ``tyre_file`` overrides, an optimise spec's path CSV); a refused file is not echoed. The FIFO cases
run in a child process with a timeout, so that a hang fails the test instead of hanging the suite.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.conftest import SHARED
from trikedyn._reading import excerpt, file_problem, named_file, read_bytes
from trikedyn.cli import main
from trikedyn.errors import InputError

TIR = SHARED / "data" / "tyres" / "mf_185_80R14.tir"
needs_tir = pytest.mark.skipif(not TIR.is_file(), reason=f"no shared .tir file {TIR}")
needs_fifo = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes on this system")
SPARSE = 4 * 2**30  # a 4 GiB sparse file: no disk used, and no reader may take it whole

_CHILD = r"""
import contextlib, io, json, sys, time
from trikedyn.cli import main
for args in json.loads(sys.argv[1]):
    print(json.dumps({"start": args}), flush=True)
    out, err = io.StringIO(), io.StringIO()
    start = time.perf_counter()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(args)
    print(json.dumps({"args": args, "code": code, "err": err.getvalue(), "s": time.perf_counter() - start}),
          flush=True)
"""


def _digests(folder: Path) -> dict[str, tuple]:
    """Every regular file below ``folder``: its SHA-256 (size and mtime for the sparse giants, which are
    never read whole); pipes, devices and links to them are left alone (hashing a pipe would wait)."""
    out = {}
    for path in sorted(folder.rglob("*")):
        try:
            info = path.stat()
        except OSError:
            continue
        if not stat.S_ISREG(info.st_mode):
            continue
        if info.st_size > 2**26:
            out[str(path)] = (info.st_size, info.st_mtime_ns)
        else:
            out[str(path)] = (hashlib.sha256(path.read_bytes()).hexdigest(),)
    return out


def _run_in_child(folder: Path, cases: list[list[str]]) -> list[dict]:
    """Run each argument list through ``main`` in one child process (cwd ``folder``) within 60 s."""
    try:
        done = subprocess.run([sys.executable, "-c", _CHILD, json.dumps(cases)], cwd=folder, capture_output=True,
                              text=True, timeout=60)
    except subprocess.TimeoutExpired as exc:
        lines = (exc.stdout or b"").decode() if isinstance(exc.stdout, bytes) else (exc.stdout or "")
        started = [json.loads(line)["start"] for line in lines.splitlines() if '"start"' in line]
        pytest.fail(f"hung: no answer within 60 s, at {started[-1] if started else 'start-up'}")
    assert done.returncode == 0, done.stderr[-2000:]
    return [json.loads(line) for line in done.stdout.splitlines() if line.startswith('{"args"')]


def _one_line_refusal(result: dict, *needles: str) -> str:
    err = result["err"]
    assert result["code"] == 2, result
    assert err.count("\n") == 1 and err.startswith("trikedyn: error: "), result
    assert "Traceback" not in err
    for needle in needles:
        assert needle in err, (needle, result)
    return err


def _write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def _tyred(tyre: str, extends: str = "reference-etrike") -> str:
    return f'extends = "{extends}"\nname = "t"\n[[wheels]]\nname = "front"\ntyre_file = "{tyre}"\n'


# ------------------------------------------------------------------------------------------------
# pipes, devices, folders, giants: refused before they are opened, in one line, fast
# ------------------------------------------------------------------------------------------------
@needs_fifo
def test_pipes_devices_folders_and_giants_never_block(tmp_path):
    for name in ("x.tir", "pipe.toml", "p.csv", "p.txt"):
        os.mkfifo(tmp_path / name)
    (tmp_path / "d.tir").mkdir()
    (tmp_path / "z.tir").symlink_to("/dev/zero")
    for name in ("big.tir", "big.csv", "big.txt"):
        with open(tmp_path / name, "wb") as fh:
            fh.truncate(SPARSE)
    _write(tmp_path / "v.toml", _tyred("x.tir"))
    _write(tmp_path / "vd.toml", _tyred("d.tir"))
    _write(tmp_path / "vbig.toml", _tyred("big.tir"))
    _write(tmp_path / "e.toml", 'extends = "pipe.toml"\nname = "e"\n')
    _write(tmp_path / "s-vehicle.toml", 'name = "s"\nvehicle = "pipe.toml"\nmanoeuvres = ["slc"]\n')
    _write(tmp_path / "s-tyre.toml", 'name = "s"\nmanoeuvres = ["slc"]\n[[groups]]\nname = "g"\n'
                                     'overrides = { "wheels.front.tyre_file" = ["x.tir"] }\n')
    _write(tmp_path / "o.toml", '[optimise]\nknobs = { "component.battery.x_m" = [0.6, 1.0] }\n'
                                'manoeuvres = ["p.csv"]\n')
    before = _digests(tmp_path)
    cases = {
        "tyre_file pipe, vehicle check": (["vehicle", "check", "v.toml"], "named pipe"),
        "tyre_file pipe, vehicle show": (["vehicle", "show", "v.toml"], "named pipe"),
        "tyre_file pipe, simulate": (["simulate", "v.toml", "--duration", "1"], "named pipe"),
        "tyre show pipe": (["tyre", "show", "x.tir"], "named pipe"),
        "tyre show device": (["tyre", "show", "z.tir"], "is a device"),
        "tyre_file folder": (["vehicle", "check", "vd.toml"], "is a folder"),
        "tyre_file giant": (["vehicle", "check", "vbig.toml"], "larger than 1024 KiB"),
        "tyre show giant": (["tyre", "show", "big.tir"], "larger than 1024 KiB"),
        "extends pipe": (["vehicle", "check", "e.toml"], "named pipe"),
        "vehicle file pipe": (["vehicle", "check", "pipe.toml"], "named pipe"),
        "study spec's vehicle pipe": (["study", "s-vehicle.toml", "--dry-run"], "named pipe"),
        "study override tyre_file pipe": (["study", "s-tyre.toml", "--dry-run"], "named pipe"),
        "study spec pipe": (["study", "pipe.toml", "--dry-run"], "named pipe"),
        "optimise spec's csv pipe": (["optimise", "reference-etrike", "--spec", "o.toml", "--out", "out"],
                                     "named pipe"),
        "--manoeuvre pipe": (["simulate", "reference-etrike", "--manoeuvre", "p.csv"], "named pipe"),
        "--manoeuvre giant": (["simulate", "reference-etrike", "--manoeuvre", "big.csv"], "4096 MiB"),
        "log pipe": (["log", "info", "p.txt"], "named pipe"),
        "log giant": (["log", "info", "big.txt"], "4096 MiB, more than the 256 MiB read"),
        "weighing pipe": (["cg", "weigh", "pipe.toml"], "pipe.toml"),
    }
    start = time.perf_counter()
    results = _run_in_child(tmp_path, [args for args, _ in cases.values()])
    assert len(results) == len(cases)
    for (label, (_, needle)), result in zip(cases.items(), results, strict=True):
        assert result["s"] < 20, (label, result)
        _one_line_refusal(result, needle)
    assert time.perf_counter() - start < 60
    assert _digests(tmp_path) == before
    assert not (tmp_path / "out").exists()


def test_the_reader_refuses_before_opening_and_reads_a_bounded_amount(tmp_path):
    assert file_problem(tmp_path) == "is a folder, not a regular file"
    assert file_problem(tmp_path / "none") == "no such file"
    if Path("/dev/null").exists():
        with pytest.raises(InputError, match="null: is a device, not a regular file; expected a log"):
            read_bytes("/dev/null", max_bytes=10, expected="a log")
    small = _write(tmp_path / "small.txt", "0123456789")
    assert read_bytes(small, max_bytes=10) == b"0123456789"
    with pytest.raises(InputError, match="small.txt: larger than 9 bytes"):
        read_bytes(small, max_bytes=9)
    with pytest.raises(InputError, match="no such file"):
        read_bytes(tmp_path / ("y" * 5000), max_bytes=9)


def test_a_file_that_grows_while_read_is_cut_at_the_bound(tmp_path, monkeypatch):
    """A /proc file says size 0 and then gives more: the reader stops one byte past the bound."""
    file = _write(tmp_path / "grows.txt", "")
    real_read = os.read
    monkeypatch.setattr("trikedyn._reading.os.read", lambda fd, n: b"x" * n if n else real_read(fd, n))
    with pytest.raises(InputError, match="grows.txt: larger than 1 KiB"):
        read_bytes(file, max_bytes=1024)


# ------------------------------------------------------------------------------------------------
# the rule for a file a file names
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("name", "needle"),
    [
        ("/etc/hosts.tir", "is an absolute path"),
        ("~/x.tir", "is an absolute path"),
        ("../tyres/x.tir", "is a path with '..'"),
        ("sub/../../x.tir", "is a path with '..'"),
        ("a\\b.tir", "a backslash"),
        ("x" * 2000 + ".tir", "a name too long"),
    ],
)
def test_a_tyre_file_out_of_the_vehicle_files_folder_is_refused_unread(tmp_path, capsys, name, needle):
    inner = tmp_path / "inner"
    file = _write(inner / "v.toml", _tyred(name.replace("\\", "\\\\")))
    before = _digests(tmp_path)
    code = main(["vehicle", "check", str(file)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and len(err) < 500
    assert "wheels[front].tyre_file" in err and needle in err and "in the vehicle file's folder or below it" in err
    assert str(file) in err  # the vehicle file that names it
    assert _digests(tmp_path) == before


def test_a_tyre_file_link_out_of_the_folder_is_refused_without_its_target(tmp_path, capsys):
    secret = _write(tmp_path / "elsewhere" / "hidden-name.tir", "[MODEL]\n")
    inner = tmp_path / "inner"
    inner.mkdir()
    (inner / "front.tir").symlink_to(secret)
    (inner / "door").symlink_to(secret.parent, target_is_directory=True)
    for tyre in ("front.tir", "door/hidden-name.tir"):
        file = _write(inner / "v.toml", _tyred(tyre))
        code = main(["vehicle", "check", str(file), "--json"])
        out, err = capsys.readouterr()
        assert code == 2 and err.count("\n") == 1
        assert "leads out of the vehicle file's folder (a symbolic link)" in err
        assert str(secret.parent) not in err and str(secret.parent) not in out
        if tyre == "front.tir":
            assert "hidden-name" not in err


@needs_tir
def test_a_tyre_file_in_the_folder_or_below_loads_through_an_inner_link(tmp_path, capsys):
    inner = tmp_path / "inner"
    (inner / "tyres").mkdir(parents=True)
    shutil.copy(TIR, inner / "tyres" / "front.tir")
    (inner / "alias.tir").symlink_to(inner / "tyres" / "front.tir")
    for tyre in ("tyres/front.tir", "alias.tir", "./tyres/front.tir"):
        file = _write(inner / "v.toml", _tyred(tyre))
        assert main(["vehicle", "show", str(file), "--json"]) == 0, capsys.readouterr().err
        shown = json.dumps(json.loads(capsys.readouterr().out))
        assert "front.tir" in shown or "alias.tir" in shown


@pytest.mark.parametrize(("vehicle", "needle"), [("../v.toml", "is a path with '..'"),
                                                 ("{root}/v.toml", "is an absolute path")])
def test_a_study_specs_vehicle_out_of_its_folder_is_refused(tmp_path, capsys, vehicle, needle):
    _write(tmp_path / "v.toml", 'extends = "reference-etrike"\nname = "v"\n')
    spec = _write(tmp_path / "studies" / "s.toml",
                  f'name = "s"\nvehicle = "{vehicle.format(root=tmp_path)}"\nmanoeuvres = ["slc"]\n')
    assert main(["study", str(spec), "--dry-run"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "vehicle: " in err and needle in err and "in the spec's folder or below it" in err
    # beside it, or below it, is fine
    _write(tmp_path / "studies" / "vehicles" / "v.toml", 'extends = "reference-etrike"\nname = "v"\n')
    _write(spec, 'name = "s"\nvehicle = "vehicles/v.toml"\nmanoeuvres = ["slc"]\n')
    assert main(["study", str(spec), "--dry-run"]) == 0, capsys.readouterr().err


@needs_tir
def test_a_study_override_tyre_file_follows_the_rule_and_is_checked_at_load(tmp_path, capsys):
    from trikedyn.study.spec import load_spec

    (tmp_path / "studies" / "tyres").mkdir(parents=True)
    shutil.copy(TIR, tmp_path / "studies" / "tyres" / "front.tir")
    _write(tmp_path / "bad.tir", "[MODEL]\nFITTYP = 6\nnot a key value line\n")
    spec = tmp_path / "studies" / "s.toml"
    for values, needle in ((["../bad.tir"], "is a path with '..'"), (["tyres/none.tir"], "no such file"),
                           (["tyres/front.toml"], "is not a .tir file")):
        _write(spec, 'name = "s"\nmanoeuvres = ["slc"]\n[[groups]]\nname = "g"\n'
                     f'overrides = {{ "wheels.front.tyre_file" = {json.dumps(values)} }}\n')
        assert main(["study", str(spec), "--dry-run"]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "groups[g].overrides.wheels.front.tyre_file" in err and needle in err, err
    _write(spec, 'name = "s"\nmanoeuvres = ["slc"]\n[[groups]]\nname = "g"\n'
                 'overrides = { "wheels.front.tyre_file" = ["tyres/front.tir"] }\n')
    loaded = load_spec(spec)
    (value,) = dict(loaded.groups[0].overrides)["wheels.front.tyre_file"]
    assert Path(value).is_absolute() and Path(value).samefile(tmp_path / "studies" / "tyres" / "front.tir")


@pytest.mark.parametrize(("csv", "needle"), [("../p.csv", "is a path with '..'"),
                                             ("{root}/p.csv", "is an absolute path")])
def test_an_optimise_specs_path_csv_follows_the_rule(tmp_path, capsys, csv, needle):
    from trikedyn.study.optimise_spec import load_optimise_spec

    points = "x_m,y_m\n" + "\n".join(f"{i},0" for i in range(60)) + "\n"
    _write(tmp_path / "p.csv", points)
    spec = tmp_path / "specs" / "o.toml"
    body = '[optimise]\nknobs = { "component.battery.x_m" = [0.6, 1.0] }\nmanoeuvres = ["{csv}"]\n'
    _write(spec, body.replace("{csv}", csv.format(root=tmp_path)))
    before = _digests(tmp_path)
    assert main(["optimise", "reference-etrike", "--spec", str(spec), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "optimise.manoeuvres: " in err and needle in err
    assert _digests(tmp_path) == before and not (tmp_path / "out").exists()
    _write(tmp_path / "specs" / "lines" / "p.csv", points)
    _write(spec, body.replace("{csv}", "lines/p.csv"))
    (path,) = load_optimise_spec(spec).manoeuvres
    assert Path(path).is_absolute() and Path(path).samefile(tmp_path / "specs" / "lines" / "p.csv")


def test_named_file_keeps_the_extends_wording(tmp_path):
    with pytest.raises(InputError) as info:
        named_file("../x.toml", tmp_path, expected="a preset name or a .toml file", where="v.toml", key="extends")
    assert str(info.value) == ("v.toml: extends: '../x.toml' is a path with '..'; expected a preset name or a "
                               ".toml file in this file's folder or below it")
    with pytest.raises(InputError, match=r"'a\\x00b.tir' is a name with a backslash or a control character"):
        named_file("a\0b.tir", tmp_path, expected="a .tir file", where="v.toml")
    assert named_file("sub/x.tir", tmp_path, expected="a .tir file", where="v.toml").path == tmp_path / "sub/x.tir"


# ------------------------------------------------------------------------------------------------
# what a refused file shows of itself
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("first", [
    "root:x:0:0:root:/root:/bin/bash" + ",daemon:x:1:1" * 30,
    "PATH=/usr/bin\0HOME=/root\0SECRET_TOKEN=abcdef0123456789\0" * 5,
])
def test_a_rejected_path_csv_shows_a_short_printable_excerpt(tmp_path, capsys, first):
    bad = tmp_path / "bad.csv"
    bad.write_text(first + "\n1,2\n", encoding="utf-8")
    before = _digests(tmp_path)
    assert main(["simulate", "reference-etrike", "--manoeuvre", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "missing column 'x_m'" in err
    assert "\0" not in err and "SECRET_TOKEN=abcdef0123456789" not in err and "daemon:x:1:1,daemon" not in err
    assert len(err) < len(str(bad)) + 200
    assert _digests(tmp_path) == before


def test_excerpt_is_short_and_printable():
    assert excerpt("abc") == "'abc'"
    assert excerpt("a\0b\x1b[31m") == "'a\\x00b\\x1b[31m'"
    assert excerpt("x" * 100, 10) == "'xxxxxxxxxx'..."


# ------------------------------------------------------------------------------------------------
# writing a vehicle keeps it loadable under the rule
# ------------------------------------------------------------------------------------------------
@needs_tir
def test_export_copies_a_tyre_file_beside_the_new_file_never_over_another(tmp_path, capsys):
    (tmp_path / "vehicles" / "tyres").mkdir(parents=True)
    shutil.copy(TIR, tmp_path / "vehicles" / "tyres" / "front.tir")
    source = _write(tmp_path / "vehicles" / "v.toml", _tyred("tyres/front.tir") + "radius_m = 0.376\n")
    out = tmp_path / "out"
    out.mkdir()
    assert main(["vehicle", "export", str(source), str(out / "x.toml")]) == 0, capsys.readouterr().err
    assert (out / "front.tir").read_bytes() == TIR.read_bytes()
    assert 'tyre_file = "front.tir"' in (out / "x.toml").read_text()
    assert main(["vehicle", "show", str(out / "x.toml")]) == 0, capsys.readouterr().err
    # again, with the same copy there: used; into the vehicle's own tree: named in place, no copy
    assert main(["vehicle", "export", str(source), str(out / "x.toml"), "--force"]) == 0
    assert main(["vehicle", "export", str(source), str(tmp_path / "vehicles" / "y.toml")]) == 0
    assert 'tyre_file = "tyres/front.tir"' in (tmp_path / "vehicles" / "y.toml").read_text()
    assert sorted(p.name for p in (tmp_path / "vehicles").iterdir()) == ["tyres", "v.toml", "y.toml"]
    # another file of that name beside the new file is never replaced
    other = tmp_path / "other"
    _write(other / "front.tir", "mine\n")
    before = _digests(tmp_path)
    capsys.readouterr()
    assert main(["vehicle", "export", str(source), str(other / "x.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "wheels[front].tyre_file" in err and "another file" in err
    assert _digests(tmp_path) == before and not (other / "x.toml").exists()
