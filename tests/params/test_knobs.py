"""Design knobs and components: each knob keeps what it should, components are inside the body mass."""

import numpy as np
import pytest

from trikedyn.errors import ParameterError
from trikedyn.params import (
    KNOBS,
    apply_knobs,
    knob_names,
    load_vehicle,
    mass_properties,
    override,
    parse_vehicle,
    save_vehicle,
    with_freight,
)
from trikedyn.params.knobs import inconsistent_override


@pytest.fixture(scope="module")
def tadpole():
    return load_vehicle("reference-tadpole")


# ------------------------------------------------------------------------------------------------
# components at the reference layout
# ------------------------------------------------------------------------------------------------
def test_reference_components_leave_todays_mass_and_cg_exactly(reference):
    p = reference.params
    assert [c.name for c in p.components] == ["battery", "motor_controller", "motor", "control_unit"]
    before = mass_properties(p.model_copy(update={"components": ()}))  # the preset as it was
    after = mass_properties(p)
    assert after.mass_kg == before.mass_kg == 583.0
    assert np.array_equal(after.cg_m, before.cg_m) and tuple(after.cg_m) == (0.8321, 0.016, 0.3804)
    assert np.array_equal(after.inertia_kgm2, before.inertia_kgm2)
    assert sum(c.mass_kg for c in p.components) < p.mass.body_kg
    assert all("assumed" in reference.notes[f"components.{c.name}.mass_kg"] for c in p.components)


@pytest.mark.parametrize("name", ["battery", "motor_controller", "motor", "control_unit"])
def test_a_component_knob_at_its_reference_place_gives_todays_cg(reference, name):
    c = next(c for c in reference.params.components if c.name == name)
    moved = apply_knobs(reference, {f"component.{name}.x_m": c.x_m, f"component.{name}.mass_kg": c.mass_kg})
    a, b = mass_properties(reference.params), mass_properties(moved.params)
    assert b.mass_kg == a.mass_kg
    np.testing.assert_allclose(b.cg_m, a.cg_m, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.inertia_kgm2, a.inertia_kgm2, rtol=0, atol=1e-9)


# ------------------------------------------------------------------------------------------------
# each knob
# ------------------------------------------------------------------------------------------------
def test_track_moves_both_wheels_symmetrically_and_keeps_the_mass(reference):
    p = reference.params
    wide = apply_knobs(reference, {"track_m": 1.3}).params
    assert (wide.wheel("rear_left").y_m, wide.wheel("rear_right").y_m) == (0.65, -0.65)
    assert wide.track_m == pytest.approx(1.3, abs=1e-15) and wide.wheelbase_m == p.wheelbase_m
    assert wide.wheel("front") == p.wheel("front")
    assert wide.mass == p.mass and wide.components == p.components
    assert np.array_equal(mass_properties(wide).cg_m, mass_properties(p).cg_m)
    # the body widens with the track (the wheels' overhang kept), not narrower with a narrower one
    assert wide.body.overall_width_m == pytest.approx(p.body.overall_width_m + 0.2)
    narrow = apply_knobs(reference, {"track_m": 0.9}).params
    assert (narrow.wheel("rear_left").y_m, narrow.wheel("rear_right").y_m) == (0.45, -0.45)
    assert narrow.body.overall_width_m == p.body.overall_width_m


def test_track_of_a_tadpole_moves_its_front_pair(tadpole):
    p = apply_knobs(tadpole, {"track_m": 1.2}).params
    assert (p.wheel("front_left").y_m, p.wheel("front_right").y_m) == (0.6, -0.6)
    assert p.wheel("rear") == tadpole.params.wheel("rear") and p.mass == tadpole.params.mass


def test_wheelbase_keeps_the_cg_on_the_body_unless_a_fraction_is_given(reference):
    p = reference.params
    long = apply_knobs(reference, {"wheelbase_m": 2.2}).params
    assert long.wheel("front").x_m == 2.2 and long.wheelbase_m == 2.2
    assert [long.wheel(n).x_m for n in ("rear_left", "rear_right")] == [0.0, 0.0]
    assert long.mass == p.mass and long.components == p.components and long.freight == p.freight
    assert long.body.overall_length_m == pytest.approx(p.body.overall_length_m + 0.25)
    # given in either order, the fraction is of the new wheelbase
    for knobs in ({"wheelbase_m": 2.2, "cg_x_fraction": 0.45}, {"cg_x_fraction": 0.45, "wheelbase_m": 2.2}):
        q = apply_knobs(reference, knobs).params
        assert q.mass.cg_x_m == pytest.approx(0.45 * 2.2, rel=1e-15)
        assert (q.mass.cg_y_m, q.mass.cg_z_m) == (p.mass.cg_y_m, p.mass.cg_z_m)
    short = apply_knobs(reference, {"wheelbase_m": 1.7}).params
    assert short.wheel("front").x_m == 1.7 and short.body.overall_length_m == p.body.overall_length_m


def test_wheelbase_of_a_tadpole_moves_both_front_wheels(tadpole):
    p = apply_knobs(tadpole, {"wheelbase_m": 2.1}).params
    assert (p.wheel("front_left").x_m, p.wheel("front_right").x_m, p.wheel("rear").x_m) == (2.1, 2.1, 0.0)


def test_cg_height_keeps_mass_and_inertia(reference):
    p = reference.params
    high = apply_knobs(reference, {"cg_height_m": 0.55}).params
    assert high.mass.cg_z_m == 0.55
    assert high.mass.model_dump() == {**p.mass.model_dump(), "cg_z_m": 0.55}
    assert high.wheels == p.wheels and high.components == p.components


def test_moving_a_component_moves_the_cg_by_m_dx_over_M_and_the_inertia_by_parallel_axis(reference):
    p = reference.params
    battery = next(c for c in p.components if c.name == "battery")
    m, (x0, y0, z0) = battery.mass_kg, (battery.x_m, battery.y_m, battery.z_m)
    big_m, (cx, cy, cz) = p.mass.total_kg, p.mass.cg_m
    x1, z1 = x0 - 0.3, z0 + 0.2
    q = apply_knobs(reference, {"component.battery.x_m": x1, "component.battery.z_m": z1}).params
    assert q.mass.total_kg == big_m and q.mass.curb_kg == p.mass.curb_kg
    assert q.mass.cg_x_m == pytest.approx(cx + m * (x1 - x0) / big_m, abs=1e-12)
    assert q.mass.cg_y_m == pytest.approx(cy, abs=1e-12)
    assert q.mass.cg_z_m == pytest.approx(cz + m * (z1 - z0) / big_m, abs=1e-12)
    ncx, ncz = q.mass.cg_x_m, q.mass.cg_z_m
    # about the origin, the battery's own box inertia is unchanged; only its position terms change
    iyy = p.mass.pitch_inertia_kgm2 + big_m * (cx**2 + cz**2) + m * (x1**2 + z1**2 - x0**2 - z0**2) - big_m * (ncx**2 + ncz**2)
    izz = p.mass.yaw_inertia_kgm2 + big_m * (cx**2 + cy**2) + m * (x1**2 - x0**2) - big_m * (ncx**2 + cy**2)
    ixx = p.mass.roll_inertia_kgm2 + big_m * (cy**2 + cz**2) + m * (z1**2 - z0**2) - big_m * (cy**2 + ncz**2)
    ixz = p.mass.roll_yaw_product_kgm2 + big_m * cx * cz + m * (x1 * z1 - x0 * z0) - big_m * ncx * ncz
    ixy = p.mass.roll_pitch_product_kgm2 + big_m * cx * cy + m * (x1 - x0) * y0 - big_m * ncx * cy
    iyz = p.mass.pitch_yaw_product_kgm2 + big_m * cy * cz + m * y0 * (z1 - z0) - big_m * cy * ncz
    got = q.mass
    assert got.pitch_inertia_kgm2 == pytest.approx(iyy, abs=1e-9)
    assert got.yaw_inertia_kgm2 == pytest.approx(izz, abs=1e-9)
    assert got.roll_inertia_kgm2 == pytest.approx(ixx, abs=1e-9)
    assert got.roll_yaw_product_kgm2 == pytest.approx(ixz, abs=1e-9)
    assert got.roll_pitch_product_kgm2 == pytest.approx(ixy, abs=1e-9)
    assert got.pitch_yaw_product_kgm2 == pytest.approx(iyz, abs=1e-9)
    moved = next(c for c in q.components if c.name == "battery")
    assert (moved.x_m, moved.z_m) == (x1, z1)


def test_reweighing_a_component_changes_the_vehicles_mass(reference):
    p = reference.params
    battery = next(c for c in p.components if c.name == "battery")
    q = apply_knobs(reference, {"component.battery.mass_kg": 80.0}).params
    assert q.mass.curb_kg == p.mass.curb_kg + 20.0 and q.mass.body_kg == p.mass.body_kg + 20.0
    expected = (p.mass.total_kg * np.array(p.mass.cg_m) + 20.0 * np.array([battery.x_m, battery.y_m, battery.z_m]))
    np.testing.assert_allclose(q.mass.cg_m, expected / (p.mass.total_kg + 20.0), rtol=0, atol=1e-12)
    gone = apply_knobs(reference, {"component.battery.mass_kg": 0.0}).params
    assert gone.mass.curb_kg == p.mass.curb_kg - 60.0
    # a heavier component is heavier body too: the budget (components < body) still holds
    heavy = apply_knobs(reference, {"component.battery.mass_kg": 500.0}).params
    assert sum(c.mass_kg for c in heavy.components) < heavy.mass.body_kg == p.mass.body_kg + 440.0


def test_freight_knobs_move_the_freight_site(reference):
    q = apply_knobs(reference, {"freight.x_m": 0.4, "freight.z_m": 0.8})
    assert (q.params.freight.x_m, q.params.freight.y_m, q.params.freight.z_m) == (0.4, 0.0, 0.8)
    assert q.params.mass == reference.params.mass
    laden = mass_properties(with_freight(q, 100.0).params)
    assert laden.cg_m[2] == pytest.approx((583.0 * 0.3804 + 100.0 * 0.8) / 683.0, rel=1e-12)


def test_changed_values_carry_a_note_naming_the_knobs(reference):
    q = apply_knobs(reference, {"track_m": 1.2})
    note = q.notes["wheels.rear_left.y_m"]
    assert note["note"] == "set by design knobs: track_m = 1.2" and "assumed" in note
    assert "note" not in q.notes.get("wheels.front.x_m", {})


def test_a_measured_value_moved_by_a_knob_loses_its_source(reference):
    """The CG of reference-etrike is from the paper's weighing: moved by a component knob, its note says what set
    it and what it was, and no longer names the weighing as its source."""
    source = reference.notes["mass.cg_z_m"]["source"]
    q = apply_knobs(reference, {"component.battery.z_m": 0.40})
    note = q.notes["mass.cg_z_m"]
    assert "source" not in note and note["note"].startswith("set by design knobs: component.battery.z_m = 0.4")
    assert f"was {reference.params.mass.cg_z_m:.6g} from {source}" in note["note"]


def test_override_takes_knobs_after_paths(reference):
    q = override(reference, {"track_m": 1.2, "mass.cg_z_m": 0.5, "component.motor.z_m": 0.4}).params
    assert q.track_m == pytest.approx(1.2) and q.wheel("rear_left").y_m == 0.6
    motor = next(c for c in reference.params.components if c.name == "motor")
    assert q.mass.cg_z_m == pytest.approx(0.5 + motor.mass_kg * (0.4 - motor.z_m) / 583.0, abs=1e-12)


# ------------------------------------------------------------------------------------------------
# errors
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("knobs", "needle"),
    [
        ({"trak_m": 1.2}, "no design knob or parameter 'trak_m'; did you mean 'track_m'?"),
        ({"component.batery.x_m": 0.5}, "no component 'batery'; did you mean 'component.battery.x_m'?"),
        ({"component.battery.xm": 0.5}, "did you mean 'component.battery.x_m'?"),
        ({"track_m": 9.0}, "track_m: expected a value from 0.3 to 3 m, got 9.0"),
        ({"cg_x_fraction": True}, "cg_x_fraction: expected a number, got True"),
        ({"wheelbase_m": float("nan")}, "wheelbase_m: expected a value from 0.5 to 5 m, got nan"),
        ({"component.battery.mass_kg": 3000.0}, "component.battery.mass_kg: expected a value from 0 to 2000 kg"),
        ({"cg_height_m": 0.01}, "cg_height_m: expected a value from 0.05 to 3 m, got 0.01"),
    ],
)
def test_knob_errors_are_one_clear_line(reference, knobs, needle):
    for apply in (apply_knobs, override):
        with pytest.raises(ParameterError) as info:
            apply(reference, knobs)
        assert needle in str(info.value) and "\n" not in str(info.value), str(info.value)


def test_component_knob_on_a_vehicle_without_components(tadpole):
    with pytest.raises(ParameterError, match=r"lists no components \(add \[\[components\]\] to its file\)"):
        apply_knobs(tadpole, {"component.battery.x_m": 0.5})


def test_registry_and_names(reference):
    assert list(KNOBS)[:4] == ["wheelbase_m", "track_m", "cg_x_fraction", "cg_height_m"]
    assert all(k.unit and k.description and k.bounds[0] < k.bounds[1] for k in KNOBS.values())
    names = knob_names(reference)
    assert "component.battery.z_m" in names and "component.NAME.x_m" not in names and "freight.x_m" in names


def test_inconsistent_paths_point_to_the_knob(reference, tadpole):
    assert "use the knob track_m" in inconsistent_override(reference, "wheels.rear_left.y_m")
    assert "use the knob wheelbase_m" in inconsistent_override(tadpole, "wheels.front_left.x_m")
    assert "use the knob component.battery.x_m" in inconsistent_override(reference, "components.battery.x_m")
    assert inconsistent_override(reference, "wheels.front.x_m") is None
    pair = {"wheels.rear_left.y_m": [0.6], "wheels.rear_right.y_m": [-0.6]}
    assert inconsistent_override(reference, "wheels.rear_left.y_m", pair) is None
    crossed = {"wheels.rear_left.y_m": [0.5, 0.6], "wheels.rear_right.y_m": [-0.5, -0.6]}
    assert "use the knob track_m" in inconsistent_override(reference, "wheels.rear_left.y_m", crossed)
    assert inconsistent_override(reference, "wheels.rear_left.radius_m") is None


# ------------------------------------------------------------------------------------------------
# the components section
# ------------------------------------------------------------------------------------------------
def _with_components(rows: str) -> str:
    return 'extends = "reference-etrike"\n' + rows


@pytest.mark.parametrize(
    ("rows", "needle"),
    [
        ('[[components]]\nname = "battery"\nmass_kg = 1.0\nx_m = 0.5\ny_m = 0.0\nz_m = 0.3\n'
         '[[components]]\nname = "x"\nmass_kg = 1.0\nx_m = 0.5\ny_m = 0.0\nz_m = 0.3\n'
         '[[components]]\nname = "x"\nmass_kg = 1.0\nx_m = 0.5\ny_m = 0.0\nz_m = 0.3\n',
         "component names must be unique; repeated: x"),
        ('[[components]]\nname = "ballast"\nmass_kg = 400.0\nx_m = 0.5\ny_m = 0.0\nz_m = 0.3\n',
         "the components weigh 489 kg, not less than the body mass 485 kg they are part of"),
        ('[[components]]\nname = "Big Box"\nmass_kg = 1.0\nx_m = 0.5\ny_m = 0.0\nz_m = 0.3\n', "name"),
        ('[[components]]\nname = "box"\nmass_kg = 1.0\nx_m = 0.5\ny_m = 0.0\nz_m = 0.3\ncolour = 1\n',
         "unknown key 'colour'"),
    ],
)
def test_bad_components_are_refused(rows, needle):
    with pytest.raises(ParameterError) as info:
        parse_vehicle(_with_components(rows))
    assert needle in str(info.value) and "\n" not in str(info.value)


def test_components_survive_a_save_and_a_load(reference, tmp_path):
    moved = apply_knobs(reference, {"component.battery.y_m": 0.0})
    back = load_vehicle(save_vehicle(moved, tmp_path / "moved.toml"))
    assert back.params == moved.params
    assert back.notes["components.battery.y_m"]["note"] == "set by design knobs: component.battery.y_m = 0"
