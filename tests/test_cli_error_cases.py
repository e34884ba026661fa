"""Every case reported against the error contract (issue 9), through the command line: exit 2 with one
line (or 0 where the input is in fact valid), valid JSON under --json, and quickly."""

import time

import pytest

from trikedyn.cli import main

from .conftest import WEIGHING, strict_json


def run(capsys, *args):
    start = time.perf_counter()
    code = main(list(args))
    elapsed = time.perf_counter() - start
    captured = capsys.readouterr()
    assert elapsed < 30.0, f"{args}: {elapsed:.0f} s"
    assert "Traceback" not in captured.err
    if code == 2:
        errors = [line for line in captured.err.splitlines() if line.startswith("trikedyn: error: ")]
        assert len(errors) == 1, captured.err
    if "--json" in args:
        strict_json(captured.out)
    return code, captured


def _vehicle(tmp_path, body: str, name="v.toml"):
    path = tmp_path / name
    path.write_text(body, encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("extends", ["/etc/passwd", "../outside.toml", "a" * 5000, "sub/../../outside.toml",
                                     "/proc/self/environ"])
def test_extends_reads_only_presets_and_files_beside(capsys, tmp_path, extends):
    (tmp_path.parent / "outside.toml").write_text('secret_key = "x"\n', encoding="utf-8")
    inner = tmp_path / "inner"
    inner.mkdir()
    code, captured = run(capsys, "vehicle", "check", _vehicle(inner, f'extends = "{extends}"\nname = "x"\n'), "--json")
    assert code == 2
    assert "root:" not in captured.err and "secret_key" not in captured.err


def test_extends_of_a_file_that_is_not_utf8(capsys, tmp_path):
    (tmp_path / "latin.toml").write_bytes(b'name = "caf\xe9"\n')
    code, _ = run(capsys, "vehicle", "check", _vehicle(tmp_path, 'extends = "latin.toml"\nname = "x"\n'))
    assert code == 2


def test_vehicle_values_out_of_physical_range(capsys, tmp_path):
    body = 'extends = "reference-etrike"\nname = "x"\n[suspension.rear]\nstiffness_N_per_m = 1e-300\n'
    code, _ = run(capsys, "vehicle", "check", _vehicle(tmp_path, body), "--json")
    assert code == 2




@pytest.mark.parametrize("extra", ["tilted = [1.0]\n", "[[tilted]]\nraised = {}\nheight_m = 0.2\nraised_axle_kg = 200\n",
                                   "[[tilted]]\nraised = \"front\"\nheight_m = 0.2\n"
                                   "raised_axle_kg = 999999999999999999999999999\n"])
def test_weighing_files_are_type_checked(capsys, tmp_path, extra):
    text = WEIGHING.replace("reading_std_kg", extra + "reading_std_kg") if extra.startswith("tilted") else WEIGHING + extra
    file = tmp_path / "w.toml"
    file.write_text(text, encoding="utf-8")
    code, _ = run(capsys, "cg", "weigh", str(file), "--json")
    assert code == 2


@pytest.mark.parametrize("rows", [
    ["0,0", "1e9,0", "2e9,1"],                                    # points a million km apart
    ["0,0", "1e-12,0", "2e-12,0", "3e-12,1e-12"],                 # points 1e-12 m apart
    [f"{i * 1000.0},0" for i in range(101)],                      # a 100 km line
])
def test_path_csvs_are_bounded(capsys, tmp_path, rows):
    file = tmp_path / "line.csv"
    file.write_text("x_m,y_m\n" + "\n".join(rows) + "\n", encoding="utf-8")
    code, _ = run(capsys, "simulate", "reference-etrike", "--manoeuvre", str(file), "--speed", "20", "--json")
    assert code == 2


def test_a_huge_circle_is_refused_quickly(capsys):
    code, _ = run(capsys, "simulate", "reference-etrike", "--manoeuvre", "circle", "-o", "radius_m=1e5", "--json")
    assert code == 2


def _log(tmp_path, rows):
    file = tmp_path / "log.csv"
    file.write_text("time_s,az_mps2\n" + "\n".join(rows) + "\n", encoding="utf-8")
    return str(file)


def test_identification_inputs_are_bounded(capsys, tmp_path):
    file = _log(tmp_path, [f"{0.1 * i:.1f},{9.81 + (0.5 if i == 20 else 0.0)}" for i in range(200)])
    code, _ = run(capsys, "identify", file, "--sprung-mass", "240", "--resample-hz", "1e9", "--json")
    assert code == 2
    code, captured = run(capsys, "identify", file, "--sprung-mass", "1e300", "--sample-rate", "1e-300", "--json")
    assert code == 2 and strict_json(captured.out)["error"]


def test_logs_with_one_row_or_huge_values_give_valid_json(capsys, tmp_path):
    code, _ = run(capsys, "log", "info", _log(tmp_path, ["0.0,9.81"]), "--json")
    assert code in (0, 2)
    code, _ = run(capsys, "log", "info", _log(tmp_path, ["0.0,9.81", "0.1,1e308", "0.2,9.8"]), "--json")
    assert code in (0, 2)


def test_seven_override_axes_are_refused_before_expansion(capsys, tmp_path):
    """Seven override axes of ten values on two manoeuvres: 2 x 10^7 scenarios, refused at once (the limit is
    10,000)."""
    keys = ["mass.driver_kg", "mass.cg_z_m", "tyre.mu_y", "suspension.rear.stiffness_N_per_m",
            "suspension.front.stiffness_N_per_m", "suspension.rear.damping_Ns_per_m",
            "suspension.front.damping_Ns_per_m"]
    starts = [60.0, 0.35, 0.8, 20000.0, 20000.0, 150.0, 150.0]
    axes = ", ".join(f'"{k}" = [{", ".join(f"{v0 * (1 + 0.01 * i):g}" for i in range(10))}]'
                     for k, v0 in zip(keys, starts, strict=True))
    spec = tmp_path / "big.toml"
    spec.write_text(f'name = "big"\n[[groups]]\nname = "g"\noverrides = {{ {axes} }}\n', encoding="utf-8")
    for extra in (["--dry-run"], []):
        code, captured = run(capsys, "study", str(spec), "--out", str(tmp_path / "o"), *extra, "--json")
        assert code == 2 and "20,000,000 scenarios" in captured.err and "--max-scenarios" in captured.err
    assert not (tmp_path / "o").exists()
