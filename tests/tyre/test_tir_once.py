"""trikedyn.tyre.tir_once: a ``.tir`` named in a vehicle file is parsed once per file, shared by the load's
validation, the audit and the tyre setup (issue 22, "parameters read once")."""

import os
import warnings

import numpy as np
import pytest
from tests.tyre.conftest import tir_text

import trikedyn.tyre.tir as tir_module
from trikedyn.errors import InputError, ParameterError
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle
from trikedyn.params.audit import audit
from trikedyn.tyre.tir_once import KEPT_VERSIONS, forget_tir_files, read_tir_once


@pytest.fixture
def parses(monkeypatch):
    """Every parse_tir call, by the name it was given."""
    calls = []
    real = tir_module.parse_tir

    def counting(text, name="<tir>", **kwargs):
        calls.append(name)
        return real(text, name, **kwargs)

    monkeypatch.setattr(tir_module, "parse_tir", counting)
    return calls


def _vehicle(tmp_path, front: str, rear: str):
    """A tadpole whose front pair names tyres/FRONT and whose rear wheel names tyres/REAR."""
    radius = {w.name: w.radius_m for w in load_vehicle("reference-tadpole").params.wheels}
    (tmp_path / "tyres").mkdir(exist_ok=True)
    for name, wheel in ((front, "front_left"), (rear, "rear")):
        (tmp_path / "tyres" / name).write_text(tir_text(UNLOADED_RADIUS=radius[wheel]), encoding="utf-8")
    body = ['extends = "reference-tadpole"']
    for wheel, name in (("front_left", front), ("front_right", front), ("rear", rear)):
        body += ["[[wheels]]", f'name = "{wheel}"', f'tyre_file = "tyres/{name}"']
    path = tmp_path / "v.toml"
    path.write_text("\n".join(body) + "\n", encoding="utf-8")
    return path


def test_load_audit_and_model_parse_each_file_once(tmp_path, parses):
    path = _vehicle(tmp_path, "front.tir", "rear.tir")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pset = load_vehicle(path)
        assert sorted(os.path.basename(n) for n in parses) == ["front.tir", "rear.tir"]
        findings = audit(pset)
        model = build_model(pset)
        build_model(pset.params)
        audit(pset.params)
    assert len(parses) == 2, parses  # one per distinct file, whatever reads it after the load
    assert any("front.tir" in str(f) for f in findings)  # the audit did use the file's stiffness
    assert [s.name for s in model.tyres] == ["magic-formula"] * 3


def test_the_shared_tyre_gives_the_same_model_as_a_fresh_read(tmp_path, parses):
    path = _vehicle(tmp_path, "front.tir", "rear.tir")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pset = load_vehicle(path)
        shared = build_model(pset).plant
        forget_tir_files()
        fresh = build_model(pset).plant
    assert len(parses) == 4  # the load's two, then two again after forgetting
    np.testing.assert_array_equal(shared.tyres, fresh.tyres)
    assert shared.wheels.tobytes() == fresh.wheels.tobytes()


def test_a_changed_file_is_read_again(tmp_path, parses):
    file = tmp_path / "t.tir"
    file.write_text(tir_text(UNLOADED_RADIUS=0.3), encoding="utf-8")
    first = read_tir_once(file)
    assert read_tir_once(file) is first and len(parses) == 1
    file.write_text(tir_text(UNLOADED_RADIUS=0.31), encoding="utf-8")
    os.utime(file, ns=(first_ns := os.stat(file).st_mtime_ns + 10**9, first_ns))
    second = read_tir_once(file)
    assert len(parses) == 2 and second is not first
    assert second.unloaded_radius == pytest.approx(0.31) and first.unloaded_radius == pytest.approx(0.3)


def test_the_name_given_is_kept_and_errors_are_read_tirs(tmp_path, parses):
    file = tmp_path / "t.tir"
    file.write_text(tir_text(), encoding="utf-8")
    link = tmp_path / "link.tir"
    link.symlink_to(file)
    assert read_tir_once(file).path == str(file) and read_tir_once(link).path == str(link)
    with pytest.raises(InputError, match="no such file|not found|missing"):
        read_tir_once(tmp_path / "absent.tir")
    bad = tmp_path / "bad.tir"
    bad.write_text("[UNITS]\nthis is not a line\n", encoding="utf-8")
    for _ in range(2):  # a refused file is never kept: refused again, in the same words
        with pytest.raises(InputError, match="bad.tir:2"):
            read_tir_once(bad)


def test_versions_kept_are_bounded(tmp_path, parses):
    forget_tir_files()
    text = tir_text()
    files = []
    for i in range(KEPT_VERSIONS + 1):
        files.append(tmp_path / f"t{i}.tir")
        files[-1].write_text(text, encoding="utf-8")
        read_tir_once(files[-1])
    read_tir_once(files[-1])
    assert len(parses) == KEPT_VERSIONS + 1
    read_tir_once(files[0])  # the least recently used went first
    assert len(parses) == KEPT_VERSIONS + 2


def test_a_vehicle_naming_a_broken_file_still_fails_the_load(tmp_path):
    path = _vehicle(tmp_path, "front.tir", "rear.tir")
    (tmp_path / "tyres" / "rear.tir").write_text("[UNITS]\nnot a line\n", encoding="utf-8")
    with pytest.raises(ParameterError, match=r"rear\.tir:2"):
        load_vehicle(path)
