"""Design knobs as study overrides: counted and expanded like any axis, lopsided paths refused at load."""

from __future__ import annotations

import textwrap

import pytest

from trikedyn.errors import InputError
from trikedyn.params import override, scale_suspension
from trikedyn.study import expand, load_spec, parse_spec
from trikedyn.study.scenarios import count_scenarios

LAYOUT = textwrap.dedent("""
    name = "layout"
    manoeuvres = ["slc", "dlc"]
    freight_kg = [0, 100]
    [[groups]]
    name = "geometry"
    overrides = { "track_m" = [1.0, 1.2], "component.battery.z_m" = [0.25, 0.45] }
    [[groups]]
    name = "wheelbase"
    overrides = { "wheelbase_m" = [1.8, 2.1], "cg_x_fraction" = [0.45] }
""")


def test_knob_overrides_count_expand_and_build_consistent_vehicles():
    spec = parse_spec(LAYOUT)
    assert count_scenarios(spec) == (2 * 2 * (2 * 2 + 2 * 1), True)
    scenarios = expand(spec)
    assert len(scenarios) == 24 and len({s["scenario_id"] for s in scenarios}) == 24
    base = spec.load_vehicle()
    # what the runner does before its threshold search (run_scenario), without simulating
    for s in scenarios:
        pset = scale_suspension(base, stiffness=s["stiffness_scale"], damping=s["damping_scale"])
        p = override(pset, s["overrides"]).params
        left, right = p.wheel("rear_left").y_m, p.wheel("rear_right").y_m
        assert left == -right and p.track_m == pytest.approx(s["overrides"].get("track_m", 1.1))
        if "wheelbase_m" in s["overrides"]:
            assert p.wheelbase_m == s["overrides"]["wheelbase_m"]
            assert p.mass.cg_x_m == pytest.approx(0.45 * p.wheelbase_m)


def test_cli_dry_run_counts_a_knob_study(tmp_path, capsys):
    from trikedyn.cli import main

    path = tmp_path / "layout.toml"
    path.write_text(LAYOUT, encoding="utf-8")
    assert main(["study", str(path), "--dry-run"]) == 0
    assert "24 scenarios" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("overrides", "needle"),
    [
        ('{ "wheels.rear_left.y_m" = [0.5, 0.6] }',
         "groups[g].overrides: 'wheels.rear_left.y_m' moves one wheel of the pair (rear_left and rear_right) only, "
         "a lopsided trike; use the knob track_m, which moves both wheels of the pair symmetrically"),
        ('{ "wheels.rear_left.y_m" = [0.5, 0.6], "wheels.rear_right.y_m" = [-0.5, -0.6] }',
         "'wheels.rear_left.y_m' moves one wheel of the pair"),  # crossed: two of four combinations lopsided
        ('{ "wheels.rear_right.x_m" = [0.1] }', "use the knob wheelbase_m"),
        ('{ "components.battery.x_m" = [0.5] }', "use the knob component.battery.x_m, which moves them with it"),
        ('{ "trak_m" = [1.2] }', "no design knob or parameter 'trak_m'; did you mean 'track_m'?"),
        ('{ "component.batery.z_m" = [0.3] }', "no component 'batery'; did you mean 'component.battery.z_m'?"),
        ('{ "track_m" = [1.2, 12.0] }', "track_m: expected a value from 0.3 to 3 m, got 12.0"),
        ('{ "cg_height_m" = ["high"] }', "cg_height_m: expected a number, got 'high'"),
        ('{ "mass.drivr_kg" = [80] }', "did you mean 'driver_kg'?"),
    ],
)
def test_refused_overrides_name_the_knob_to_use(tmp_path, overrides, needle):
    path = tmp_path / "bad.toml"
    path.write_text(f'name = "x"\n[[groups]]\nname = "g"\noverrides = {overrides}\n', encoding="utf-8")
    with pytest.raises(InputError) as info:
        load_spec(path)
    message = str(info.value)
    assert needle in message and message.startswith(str(path)) and "\n" not in message


def test_single_wheel_paths_that_are_consistent_stay_allowed():
    spec = parse_spec('name = "x"\n[[groups]]\nname = "g"\n'
                      'overrides = { "wheels.front.x_m" = [2.0], "wheels.rear_left.radius_m" = [0.28] }\n')
    assert count_scenarios(spec) == (2, True)
    # both wheels of the pair, one value each: one deliberate layout (the design-study tutorial's group)
    both = parse_spec('name = "x"\n[[groups]]\nname = "g"\n'
                      'overrides = { "wheels.rear_left.y_m" = [0.60], "wheels.rear_right.y_m" = [-0.60] }\n')
    assert count_scenarios(both) == (2, True)
