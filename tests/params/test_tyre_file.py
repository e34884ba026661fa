"""A wheel's ``tyre_file`` (.tir): relative to the file that names it, in its folder or below it (the rule for every
file a file names, issue 21), checked at load, written back relative (copied beside a file written elsewhere)."""

import json
import shutil
from pathlib import Path

import pytest
from tests.conftest import SHARED

from trikedyn.cli import main
from trikedyn.errors import InputError, ParameterError
from trikedyn.params import load_vehicle, parse_vehicle, save_vehicle
from trikedyn.params.schema import WheelSpec

TYRES = SHARED / "data" / "tyres"
TIR = next(iter(sorted(TYRES.glob("*.tir"))), None) if TYRES.is_dir() else None
needs_tir = pytest.mark.skipif(TIR is None, reason=f"no shared .tir file in {TYRES}")


@pytest.fixture
def folder(tmp_path):
    """tmp/vehicles/ (where the vehicle files go), tmp/vehicles/tyres/<the shared .tir>."""
    (tmp_path / "vehicles" / "tyres").mkdir(parents=True)
    shutil.copy(TIR, tmp_path / "vehicles" / "tyres" / TIR.name)
    return tmp_path


def _vehicle(path: Path, wheels: dict, extends: str = "reference-tadpole") -> Path:
    body = [f'extends = "{extends}"']
    for name, tyre in wheels.items():
        body += ["[[wheels]]", f'name = "{name}"', f"tyre_file = {tyre}"]
    path.write_text("\n".join(body) + "\n", encoding="utf-8")
    return path


def test_default_is_none_and_the_name_must_be_a_tir():
    assert all(w.tyre_file is None for w in load_vehicle("reference-etrike").params.wheels)
    base = load_vehicle("reference-etrike").params.wheels[0].model_dump()
    with pytest.raises(ValueError, match="expected a .tir tyre property file"):
        WheelSpec.model_validate(base | {"tyre_file": "tyres/notes.txt"})
    with pytest.raises(ValueError, match="at most 1000"):
        WheelSpec.model_validate(base | {"tyre_file": "a" * 997 + ".tir"})


@needs_tir
def test_resolved_relative_to_the_vehicle_file(folder):
    file = _vehicle(folder / "vehicles" / "v.toml", {"rear": f'"tyres/{TIR.name}"',
                                                     "front_left": f'{{ value = "tyres/{TIR.name}", source = "lab" }}'})
    pset = load_vehicle(file)
    for name in ("rear", "front_left"):
        path = Path(pset.params.wheel(name).tyre_file)
        assert path.is_absolute() and path.is_file() and path.samefile(folder / "vehicles" / "tyres" / TIR.name)
    assert pset.params.wheel("front_right").tyre_file is None
    assert pset.notes["wheels.front_left.tyre_file"] == {"source": "lab"}


@needs_tir
def test_an_extended_file_names_its_tyre_relative_to_itself(folder, monkeypatch):
    """base.toml in vehicles/sub/ names tyres/X.tir (vehicles/sub/tyres/); the child in vehicles/ extends it (and
    the load runs from elsewhere): the tyre file is found relative to base.toml, not to the child or the cwd."""
    (folder / "vehicles" / "sub" / "tyres").mkdir(parents=True)
    shutil.copy(TIR, folder / "vehicles" / "sub" / "tyres" / TIR.name)
    _vehicle(folder / "vehicles" / "sub" / "base.toml", {"rear": f'"tyres/{TIR.name}"'})
    child = folder / "vehicles" / "child.toml"
    child.write_text('extends = "sub/base.toml"\nname = "child"\n', encoding="utf-8")
    monkeypatch.chdir(folder / "vehicles" / "tyres")
    rear = load_vehicle(child).params.wheel("rear")
    assert Path(rear.tyre_file).samefile(folder / "vehicles" / "sub" / "tyres" / TIR.name)


@needs_tir
def test_parse_vehicle_text_is_relative_to_its_origin(folder):
    text = f'extends = "reference-tadpole"\n[[wheels]]\nname = "rear"\ntyre_file = "tyres/{TIR.name}"\n'
    rear = parse_vehicle(text, origin=str(folder / "vehicles" / "v.toml")).params.wheel("rear")
    assert Path(rear.tyre_file).samefile(folder / "vehicles" / "tyres" / TIR.name)
    with pytest.raises(ParameterError, match="is a path with '..'"):
        parse_vehicle(text.replace("tyres/", "../tyres/"), origin=str(folder / "vehicles" / "v.toml"))


@needs_tir
def test_save_writes_a_path_that_still_resolves(folder):
    pset = load_vehicle(_vehicle(folder / "vehicles" / "v.toml", {"rear": f'"tyres/{TIR.name}"'}))
    (folder / "elsewhere" / "deeper").mkdir(parents=True)
    for target, named in ((folder / "copy.toml", f"vehicles/tyres/{TIR.name}"),  # in its folder: named in place
                          (folder / "elsewhere" / "deeper" / "copy.toml", TIR.name)):  # outside: copied beside
        save_vehicle(pset, target)
        written = [line for line in target.read_text().splitlines() if line.startswith("tyre_file")]
        assert written == [f'tyre_file = "{named}"'], written
        again = load_vehicle(target)
        assert Path(again.params.wheel("rear").tyre_file).read_bytes() == TIR.read_bytes()
        assert again.params.model_copy(update={"wheels": pset.params.wheels}) == pset.params


def test_a_missing_tyre_file_names_the_wheel_and_the_vehicle_file(tmp_path):
    file = _vehicle(tmp_path / "v.toml", {"front_left": '"tyres/none.tir"'})
    with pytest.raises(ParameterError) as info:
        load_vehicle(file)
    err = info.value
    assert isinstance(err, InputError) and err.where == "wheels[front_left].tyre_file"
    text = str(err)
    assert "\n" not in text and "no such file" in text and str(file) in text and "none.tir" in text


def test_a_missing_tyre_file_at_the_command_line_exits_2(tmp_path, capsys):
    file = _vehicle(tmp_path / "v.toml", {"rear": '"none.tir"'})
    code = main(["vehicle", "check", str(file), "--json"])
    captured = capsys.readouterr()
    assert code == 2
    assert json.loads(captured.out)["where"] == "wheels[rear].tyre_file"
    assert captured.err.count("\n") == 1 and "wheels[rear].tyre_file" in captured.err and str(file) in captured.err


def test_an_invalid_tir_names_file_line_and_wheel(tmp_path):
    (tmp_path / "bad.tir").write_text("[MODEL]\nFITTYP = 6\nnot a key value line\n", encoding="utf-8")
    file = _vehicle(tmp_path / "v.toml", {"front_right": '"bad.tir"'})
    with pytest.raises(ParameterError) as info:
        load_vehicle(file)
    text = str(info.value)
    assert info.value.where == "wheels[front_right].tyre_file"
    assert "bad.tir:3" in text and str(file) in text and "\n" not in text


def test_a_file_that_is_not_a_tir_is_refused_unread(tmp_path):
    (tmp_path / "secret.toml").write_text('token = "s3cr3t"\n', encoding="utf-8")
    file = _vehicle(tmp_path / "v.toml", {"rear": '"secret.toml"'})
    with pytest.raises(ParameterError, match="expected a .tir tyre property file") as info:
        load_vehicle(file)
    assert "s3cr3t" not in str(info.value)
