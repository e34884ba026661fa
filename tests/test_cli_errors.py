"""The error contract of the command line (issue 9): one line, exit 2, valid JSON, nothing overwritten."""


import pytest

from trikedyn.cli import main

from .conftest import strict_json


def _one_line_error(capsys, code, where=None):
    captured = capsys.readouterr()
    assert code == 2, captured
    assert captured.err.startswith("trikedyn: error: ") and captured.err.count("\n") == 1, captured.err
    assert "Traceback" not in captured.err
    if where is not None:
        assert where in captured.err
    return captured


@pytest.fixture
def log_file(tmp_path):
    path = tmp_path / "ride.csv"
    rows = "\n".join(f"{0.1 * i:.1f},{9.81 + 0.01 * (i % 3):.4f}" for i in range(50))
    path.write_text("time_s,az_mps2\n" + rows + "\n", encoding="utf-8")
    return path


def test_log_convert_never_writes_onto_its_input(capsys, log_file):
    before = log_file.read_bytes()
    _one_line_error(capsys, main(["log", "convert", str(log_file), str(log_file)]), "also an input")
    _one_line_error(capsys, main(["log", "convert", str(log_file), str(log_file), "--force"]), "also an input")
    assert log_file.read_bytes() == before


def test_outputs_are_not_overwritten_without_force(capsys, log_file, tmp_path):
    out = tmp_path / "converted.csv"
    out.write_text("keep me", encoding="utf-8")
    _one_line_error(capsys, main(["log", "convert", str(log_file), str(out)]), "--force")
    assert out.read_text(encoding="utf-8") == "keep me"
    assert main(["log", "convert", str(log_file), str(out), "--force"]) == 0
    assert out.read_text(encoding="utf-8").startswith("time_s")
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary file left
    capsys.readouterr()
    exported = tmp_path / "mine.toml"
    assert main(["vehicle", "export", "reference-etrike", str(exported)]) == 0
    capsys.readouterr()
    _one_line_error(capsys, main(["vehicle", "export", "reference-etrike", str(exported)]), "--force")
    _one_line_error(capsys, main(["vehicle", "export", str(exported), str(exported), "--force"]), "also an input")


def test_simulate_refuses_existing_run_files_before_running(capsys, tmp_path):
    run_file = tmp_path / "run.csv"
    run_file.with_suffix(".json").write_text("{}", encoding="utf-8")  # only the summary beside it exists
    _one_line_error(capsys, main(["simulate", "reference-etrike", "--manoeuvre", "step", "--out", str(run_file)]),
                    "run.json")
    assert not run_file.exists() and run_file.with_suffix(".json").read_text(encoding="utf-8") == "{}"


@pytest.mark.parametrize("args", [
    ["simulate", "reference-etrike", "--out", "no/such/dir/run.csv"],
    ["simulate", "reference-etrike", "--out", "run.txt"],
    ["simulate", "reference-etrike", "--speed", "1e9"],
    ["simulate", "reference-etrike", "--speed", "nan"],
    ["simulate", "reference-etrike", "--duration", "nan"],
    ["simulate", "reference-etrike", "--duration", "0"],
    ["simulate", "reference-etrike", "--bogus-option"],
    ["threshold", "reference-etrike", "--resolution", "nan"],
    ["threshold", "reference-etrike", "--low", "50", "--high", "20"],
    ["reproduce", "--workers", "0"],
    ["vehicle", "show", "no-such-trike"],
])
def test_user_mistakes_are_one_line(capsys, tmp_path, monkeypatch, args):
    monkeypatch.chdir(tmp_path)
    _one_line_error(capsys, main(args))


def test_a_vehicle_that_cannot_stand_is_a_user_error(capsys, tmp_path):
    lopsided = tmp_path / "lopsided.toml"
    lopsided.write_text('extends = "reference-etrike"\nname = "lopsided"\n[mass]\ncg_y_m = -1.0\n', encoding="utf-8")
    for command in (["modes", str(lopsided)], ["simulate", str(lopsided), "--manoeuvre", "step"]):
        _one_line_error(capsys, main(command))


def test_errors_under_json_are_json_too(capsys):
    code = main(["simulate", "reference-etrike", "--speed", "-3", "--json"])
    captured = _one_line_error(capsys, code)
    data = strict_json(captured.out)
    assert data["where"] == "--speed" and "must be > 0" in data["error"]


def test_reproduce_does_not_replace_a_folder_without_force(capsys, tmp_path):
    folder = tmp_path / "results"
    folder.mkdir()
    (folder / "mine.txt").write_text("keep", encoding="utf-8")
    _one_line_error(capsys, main(["reproduce", "--out", str(folder), "--no-study", "--no-figures"]), "--force")
    assert (folder / "mine.txt").read_text(encoding="utf-8") == "keep"


def test_json_is_valid_even_with_non_finite_numbers(capsys, tmp_path):
    """A one-row log has no standard deviation: null in JSON, with a warning saying where."""
    one = tmp_path / "one.csv"
    one.write_text("time_s,az_mps2\n0.0,9.81\n", encoding="utf-8")
    code = main(["log", "info", str(one), "--json"])
    out = capsys.readouterr().out
    if code == 0:
        data = strict_json(out)
        assert all("non-finite" in w or w for w in data.get("warnings", []))
    else:
        assert code == 2 and strict_json(out)["error"]


@pytest.mark.parametrize(("command", "units"), [
    (["simulate"], ["[km/h]", "[kg]", "[m]", "[s]"]), (["threshold"], ["[km/h]", "[kg]"]),
    (["tilt"], ["[kg]", "[deg]"]), (["identify"], ["[kg]", "[N/m]"]), (["cg", "payload"], ["[kg]"]),
])
def test_help_keeps_its_units(capsys, command, units):
    """Units in brackets survive the help formatter (rich markup used to swallow them)."""
    assert main([*command, "--help"]) == 0
    out = capsys.readouterr().out
    for unit in units:
        assert unit in out, f"{command}: {unit} missing from --help"
