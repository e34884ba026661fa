"""The command line reads as one tool (issue 13): one name per quantity (``--payload``, with ``--freight`` a
hidden alias), numbers rounded for reading in text (every digit in --json), and ``vehicle check`` exits 1
on an inconsistent vehicle."""

from __future__ import annotations

import re

import pytest

from trikedyn.cli import app, main
from trikedyn.commands._common import readable, round_text

from .conftest import strict_json


def run(capsys, *args):
    code = main(list(args))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _commands(group=None, path=()):
    """Every leaf command of the CLI: ``(path, command)``."""
    import typer.main

    group = group if group is not None else typer.main.get_command(app)
    for name, command in group.commands.items():
        if hasattr(command, "commands"):
            yield from _commands(command, (*path, name))
        else:
            yield (*path, name), command


def _options(command) -> dict[str, object]:
    return {opt: param for param in command.params for opt in getattr(param, "opts", [])}


FREIGHT_COMMANDS = {("simulate",), ("threshold",), ("handling",), ("tilt",), ("compare-layouts",), ("cg", "payload"),
                    ("modes",), ("performance",), ("assess",)}


# ------------------------------------------------------------------------------------------------------------
# one name per quantity
# ------------------------------------------------------------------------------------------------------------
def test_every_command_that_takes_freight_names_it_payload():
    takes = {}
    for path, command in _commands():
        options = _options(command)
        if "--payload" in options or "--freight" in options:
            takes[path] = options
    assert set(takes) == FREIGHT_COMMANDS
    wrong = {" ".join(p): sorted(o) for p, o in takes.items() if "--payload" not in o or "--freight" not in o
             or o["--payload"].hidden or not o["--freight"].hidden}
    assert wrong == {}


@pytest.mark.parametrize("path", sorted(FREIGHT_COMMANDS))
def test_help_shows_payload_not_freight(capsys, path):
    code, out, _ = run(capsys, *path, "--help")
    assert code == 0 and "--payload" in out and "--freight" not in out


class _Stop(Exception):
    """Raised by a stand-in for the analysis, once it has the vehicle it was given."""


# command -> (module, function) that receives the laden vehicle as its first argument
STAND_INS = {
    ("simulate",): ("trikedyn.simulate.closed_loop", "run"),
    ("threshold",): ("trikedyn.analysis.threshold", "threshold_velocity"),
    ("handling",): ("trikedyn.analysis.handling_tests", "steady_state_test"),
    ("tilt",): ("trikedyn.analysis.tilt", "tilt_table"),
    ("compare-layouts",): ("trikedyn.analysis.layouts", "compare_layouts"),
    ("modes",): ("trikedyn.model.vehicle", "build_model"),
    ("performance",): ("trikedyn.analysis.performance", "performance"),
}


@pytest.mark.parametrize("option", ["--payload", "--freight"])
@pytest.mark.parametrize("path", sorted(STAND_INS))
def test_payload_and_its_old_name_reach_the_analysis(capsys, monkeypatch, path, option):
    import importlib

    module, function = STAND_INS[path]
    seen = []

    def stand_in(vehicle, *args, **kwargs):
        seen.append(vehicle.mass_kg)
        raise _Stop

    monkeypatch.setattr(importlib.import_module(module), function, stand_in)
    with pytest.raises(_Stop):
        main([*path, "reference-etrike", option, "120"])
    assert seen == [pytest.approx(583.0 + 120.0)]


@pytest.mark.parametrize("option", ["--payload", "--freight"])
def test_cg_payload_takes_either_name(capsys, option):
    code, out, _ = run(capsys, "cg", "payload", "reference-etrike", option, "100", "--json")
    assert code == 0 and strict_json(out)["payload_kg"] == pytest.approx(100.0)


@pytest.mark.parametrize("args", [["--payload", "10", "--freight", "20"], ["--freight", "20", "--payload", "0"]])
def test_payload_and_freight_together_is_a_user_error(capsys, args):
    code, out, err = run(capsys, "cg", "payload", "reference-etrike", *args)
    assert code == 2 and out == "" and err.count("\n") == 1 and "not both" in err


def test_the_old_name_is_range_checked(capsys):
    code, _, err = run(capsys, "tilt", "reference-etrike", "--freight", "-5")
    assert code == 2 and "--freight" in err


# ------------------------------------------------------------------------------------------------------------
# numbers for reading
# ------------------------------------------------------------------------------------------------------------
NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")


def _significant(number: str) -> int:
    return len(re.split("[eE]", number.lstrip("+-"))[0].replace(".", "").lstrip("0"))


def _longest(text: str) -> int:
    return max((_significant(n) for n in NUMBER.findall(text)), default=0)


@pytest.mark.parametrize(("value", "shown"), [
    (2.657138346546658, "2.657"), (10.450000000000001, "10.45"), (80289.0, "80289"), (0.0, "0"), (30.0, "30"),
    (-0.013657389, "-0.01366"), (1.5e-5, "1.5e-5"), (2.5e7, "2.5e7"), (999.96, "1000"), (True, "True"),
    (None, "None"), (3, "3"),
])
def test_readable_numbers(value, shown):
    assert readable(value) == shown


def test_round_text_keeps_formatted_numbers():
    text = "f 2.916 Hz, K 45787.85 N/m, at 3.5300000000000002 s, v0.29.2, -0.1234567891 m"
    assert round_text(text) == "f 2.916 Hz, K 45787.85 N/m, at 3.53 s, v0.29.2, -0.1235 m"


@pytest.mark.parametrize("args", [
    ["simulate", "reference-etrike", "--manoeuvre", "slc", "--speed", "30", "--payload", "10.45"],
    ["simulate", "reference-etrike", "--manoeuvre", "step", "--speed", "30"],
    ["threshold", "reference-etrike", "--manoeuvre", "slc", "--low", "20", "--high", "30", "--resolution", "5"],
])
def test_text_is_rounded_and_json_keeps_every_digit(capsys, args):
    code, text, _ = run(capsys, *args)
    assert code == 0 and _longest(text) <= 6, text
    code, out, _ = run(capsys, *args, "--json")
    data = strict_json(out)
    assert code == 0
    if args[0] == "simulate":
        assert _significant(repr(data["max_lateral_acceleration_mps2"])) > 6
        assert f"{data['max_lateral_acceleration_mps2']:.4g}" in text


# ------------------------------------------------------------------------------------------------------------
# vehicle check
# ------------------------------------------------------------------------------------------------------------
def _vehicle(tmp_path, base: str, frequency_hz: float | None = None):
    body = f'extends = "{base}"\nname = "mine"\n'
    if frequency_hz is not None:
        body += f"[suspension.front]\nnatural_frequency_hz = {frequency_hz}\n"
    path = tmp_path / "mine.toml"
    path.write_text(body, encoding="utf-8")
    return str(path)


def test_vehicle_check_exits_1_on_an_inconsistent_vehicle(capsys, tmp_path):
    # reference-etrike-eq4 is consistent; a front natural frequency far from what K and the sprung mass give is not
    consistent = _vehicle(tmp_path, "reference-etrike-eq4")
    code, out, _ = run(capsys, "vehicle", "check", consistent)
    assert code == 0 and "0 inconsistent" in out
    bad = _vehicle(tmp_path, "reference-etrike-eq4", frequency_hz=9.0)
    code, out, err = run(capsys, "vehicle", "check", bad)
    assert code == 1 and "INCONSISTENT" in out and err == ""
    code, out, err = run(capsys, "vehicle", "check", bad, "--json")
    findings = strict_json(out)["findings"]
    assert code == 1 and err == "" and any(f["level"] == "inconsistent" for f in findings)


def test_vehicle_check_still_exits_2_on_a_bad_file(capsys, tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('extends = "reference-etrike"\n[mass]\ncurb_kg = -1\n', encoding="utf-8")
    code, out, err = run(capsys, "vehicle", "check", str(path), "--json")
    assert code == 2 and strict_json(out)["error"] and err.count("\n") == 1


@pytest.mark.parametrize("command", [["threshold", "reference-etrike"], ["simulate", "reference-etrike", "--speed", "15"]])
def test_a_relative_path_csv_reaches_the_analysis_absolute(tmp_path, monkeypatch, command):
    """A worker (a pool's, or a Dask worker on another machine) may run in another working directory: the
    command hands on the path CSV made absolute where it was typed, a registered name unchanged."""
    import importlib

    from trikedyn.commands._common import absolute_csv

    module, function = STAND_INS[tuple(command[:1])]
    seen = []

    def stand_in(vehicle, manoeuvre=None, *args, **kwargs):
        seen.append(kwargs.get("manoeuvre", manoeuvre))
        raise _Stop

    monkeypatch.setattr(importlib.import_module(module), function, stand_in)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(_Stop):
        main([*command, "--manoeuvre", "line.csv"])
    assert str(seen[0]).endswith("line.csv") and str(seen[0]).startswith(str(tmp_path))
    assert absolute_csv("dlc") == "dlc" and absolute_csv(["slc", "a.CSV"]) == ["slc", str(tmp_path / "a.CSV")]
