"""Parameter sets: schema validation, TOML round trip, presets, clear errors."""

import math

import pytest

from trikedyn.errors import ParameterError
from trikedyn.params import list_presets, load_vehicle, parse_vehicle, save_vehicle
from trikedyn.params.save import _to_toml


def _reference_toml(reference) -> str:
    data = reference.params.model_dump(mode="json", exclude_none=True)
    return _to_toml(data)


def test_presets_listed_and_valid():
    assert {"reference-etrike", "reference-etrike-eq4"} <= set(list_presets())
    for name in list_presets():
        assert load_vehicle(name).params.name == name


def test_reference_values_from_paper(reference):
    p = reference.params
    assert p.mass.curb_kg == 508.0 and p.mass.body_kg == 485.0
    assert (p.mass.cg_y_m, p.mass.cg_z_m) == (0.016, 0.3804)
    assert p.suspension["front"].stiffness_N_per_m == 80289.0
    assert p.suspension["rear"].stiffness_N_per_m == 45787.85
    assert p.suspension["front"].damping_Ns_per_m == 183.83
    assert p.suspension["rear"].damping_Ns_per_m == 160.71
    assert p.tyre.vertical_stiffness_N_per_m == 200e3 and p.tyre.vertical_damping_Ns_per_m == 75.0
    assert [w.name for w in p.wheels] == ["front", "rear_left", "rear_right"]


def test_every_unmeasured_value_has_a_reason(reference):
    """Each value of the reference set carries a `source` (paper) or an `assumed` reason, but for the
    few structural ones (names, flags, zeros by definition)."""
    structural = {"name", "description", "source", "layout", "kind", "suspension", "steered", "driven",
                  "braked", "differential", "air_density_kg_per_m3"}
    from trikedyn.cli import _flatten

    data = reference.params.model_dump(mode="json", exclude_none=True)
    missing = []
    for path, value in _flatten(data):
        leaf = path.split(".")[-1]
        if leaf in structural or value == 0.0 or value == [] or path.startswith("ranges."):
            continue  # (a declared range's reason is its comment: tests/study/test_ranges.py)
        if path not in reference.notes:
            missing.append(path)
    # x of the rear wheels is the origin by definition
    assert missing == [], missing
    for note in reference.notes.values():
        assert note.get("assumed", note.get("source", "")).strip()


def test_eq4_preset_follows_eq4():
    p = load_vehicle("reference-etrike-eq4").params
    for s in p.suspension.values():
        m_s = s.stiffness_N_per_m / (2 * math.pi * s.natural_frequency_hz) ** 2
        assert s.damping_Ns_per_m == pytest.approx(2 * s.damping_ratio * math.sqrt(s.stiffness_N_per_m * m_s), rel=1e-5)
    base = load_vehicle("reference-etrike").params
    assert p.mass == base.mass and p.wheels == base.wheels


def test_toml_round_trip_keeps_values_and_notes(reference, tmp_path):
    path = save_vehicle(reference, tmp_path / "v.toml")
    again = load_vehicle(path)
    assert again.params == reference.params
    assert again.notes == reference.notes
    assert "assumed =" in path.read_text()


def test_a_range_key_of_a_wheel_pair_is_written_quoted(tmp_path):
    """A declared range over a pair of wheels has dots and a '+' in its key: the file written must read back."""
    (tmp_path / "v.toml").write_text('extends = "reference-tadpole"\nname = "v"\n[ranges]\n'
                                     '"wheels.front_left+front_right.radius_m" = [0.25, 0.29]\n', encoding="utf-8")
    written = save_vehicle(load_vehicle(tmp_path / "v.toml"), tmp_path / "out.toml")
    assert '"wheels.front_left+front_right.radius_m" = [' in written.read_text(encoding="utf-8")
    assert load_vehicle(written).params.ranges == {"wheels.front_left+front_right.radius_m": (0.25, 0.29)}


def test_extends_merges_by_key_and_wheel_name(tmp_path):
    (tmp_path / "mine.toml").write_text(
        'extends = "reference-etrike"\nname = "mine"\n[mass]\ndriver_kg = 90.0\n'
        '[[wheels]]\nname = "front"\nradius_m = 0.30\n'
    )
    p = load_vehicle(tmp_path / "mine.toml").params
    assert p.name == "mine" and p.mass.driver_kg == 90.0 and p.mass.curb_kg == 508.0
    assert p.wheel("front").radius_m == 0.30 and p.wheel("front").x_m == 1.95
    assert [w.name for w in p.wheels] == ["rear_left", "rear_right", "front"]


@pytest.mark.parametrize(
    ("edit", "expected"),
    [
        (("curb_kg = { value = 508.0", "curb_kgg = { value = 508.0"), "unknown key 'curb_kgg' in mass; did you mean 'curb_kg'?"),
        (("curb_kg = { value = 508.0", "curb_kg = { value = -508.0"), "mass.curb_kg: input should be greater than 0"),
        (("driver_kg = { value = 75.0", "driver_kg = { value = -75.0"), "mass.driver_kg: input should be greater than or equal to 0"),
        (('suspension = "rear"', 'suspension = "raer"'), "did you mean 'rear'?"),
        (("radius_m = { value = 0.27", "radius_m = { value = 7.0"), "wheels[front].radius_m: input should be less than or equal to 1"),
        (("[aero]", "[aeroo]"), "unknown key 'aeroo' in the top level; did you mean 'aero'?"),
    ],
)
def test_bad_parameters_give_one_clear_line(reference, tmp_path, edit, expected):
    from importlib import resources

    text = (resources.files("trikedyn.params") / "presets" / "reference-etrike.toml").read_text()
    assert edit[0] in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(edit[0], edit[1], 1))
    with pytest.raises(ParameterError) as info:
        load_vehicle(bad)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(str(bad))
    assert expected in message


def test_missing_section_and_bad_toml(reference, tmp_path):
    text = _reference_toml(reference)
    start = text.index("[tyre]")
    end = text.index("[drive]")
    with pytest.raises(ParameterError, match=r"^mine.toml: tyre: missing \(required\)$"):
        parse_vehicle(text[:start] + text[end:], "mine.toml")
    bad = tmp_path / "b.toml"
    bad.write_text("name = [unclosed\n")
    with pytest.raises(ParameterError, match="invalid TOML"):
        load_vehicle(bad)


def test_unknown_preset_hint():
    with pytest.raises(ParameterError, match="did you mean 'reference-etrike'"):
        load_vehicle("reference-etrik")


def test_loading_a_vehicle_imports_no_signal_processing():
    """`trikedyn vehicle list` loads every preset: the parameters must not pull in scipy.signal and the
    identification (a second of imports; the bench's 0.8 s target for vehicle list)."""
    import subprocess
    import sys

    code = ("import sys; from trikedyn.params import load_vehicle, audit; load_vehicle('reference-etrike'); "
            "print(sorted(m for m in ('scipy.signal', 'trikedyn.measure.suspension') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "[]", out.stdout + out.stderr
