"""The tadpole layout on the parameter side: validator rules, the reference-tadpole preset, audit, tip-over."""

import math

import pytest

from trikedyn.cli import _flatten
from trikedyn.errors import ParameterError
from trikedyn.params import audit, load_vehicle, override, tip_over_thresholds
from trikedyn.params.ops import mass_properties, static_wheel_loads
from trikedyn.units import STANDARD_GRAVITY


@pytest.fixture(scope="module")
def tadpole():
    return load_vehicle("reference-tadpole")


def test_preset_loads_with_its_layout_and_loads_sum_to_the_weight(tadpole):
    p = tadpole.params
    assert p.layout == "tadpole"
    assert [(w.name, w.steered, w.driven) for w in p.wheels] == [
        ("front_left", True, False), ("front_right", True, False), ("rear", False, True)]
    assert {p.suspension[w.suspension].kind for w in p.wheels if w.steered} == {"telescopic"}
    assert p.suspension[p.wheel("rear").suspension].kind == "swing_arm"
    loads = static_wheel_loads(p)
    assert sum(loads.values()) == pytest.approx(mass_properties(p).mass_kg * STANDARD_GRAVITY, rel=1e-12)
    assert all(f > 0 for f in loads.values())
    # the CG where the delta has it: the rear wheel carries 1 - cg_x / L of the weight of a centred CG
    assert loads["rear"] / sum(loads.values()) == pytest.approx(1 - p.mass.cg_x_m / p.wheelbase_m, rel=1e-9)


def test_preset_keeps_the_reference_mass_cg_wheelbase_and_track(tadpole):
    delta = load_vehicle("reference-etrike").params
    p = tadpole.params
    assert p.mass == delta.mass
    assert (p.wheelbase_m, p.track_m) == (delta.wheelbase_m, delta.track_m) == (1.95, 1.1)
    assert p.tyre == delta.tyre and p.freight == delta.freight


def test_preset_every_value_has_a_reason(tadpole):
    structural = {"name", "description", "source", "layout", "kind", "suspension", "steered", "driven",
                  "braked", "differential", "air_density_kg_per_m3"}
    data = tadpole.params.model_dump(mode="json", exclude_none=True)
    missing = [path for path, value in _flatten(data)
               if path.split(".")[-1] not in structural and value not in (0.0, []) and path not in tadpole.notes]
    assert missing == []
    assert all(note.get("assumed", note.get("source", "")).strip() for note in tadpole.notes.values())


def test_preset_keeps_the_deltas_natural_frequencies_and_sags(tadpole):
    """Springs derived from the delta's so that each end's static natural frequency stays close (5 %)."""
    def frequencies(params):
        out = {}
        for f in audit(params):
            if f.topic == "sprung mass":
                s = params.suspension[params.wheel(f.values["wheel"]).suspension]
                out[f.values["wheel"]] = math.sqrt(s.stiffness_N_per_m / f.values["sprung_mass_from_cg_kg"]) / (2 * math.pi)
        return out

    delta = frequencies(load_vehicle("reference-etrike").params)
    tad = frequencies(tadpole.params)
    assert tad["rear"] == pytest.approx((delta["rear_left"] + delta["rear_right"]) / 2, rel=0.05)
    assert (tad["front_left"] + tad["front_right"]) / 2 == pytest.approx(delta["front"], rel=0.05)


def test_vehicle_check_of_the_preset_is_consistent(tadpole):
    findings = audit(tadpole)
    assert not [f for f in findings if f.level == "inconsistent"]
    book = next(f for f in findings if f.topic == "mass bookkeeping" and "chassis_kg" in f.values)
    p = tadpole.params
    parts = (sum(w.mass_kg for w in p.wheels) + 2 * p.steering.head_mass_kg
             + sum(p.suspension[w.suspension].moving_mass_kg for w in p.wheels))
    assert book.values["parts_kg"] == pytest.approx(parts)  # one steering head per steered wheel


def test_cg_from_eq3_is_layout_aware(tadpole):
    """With f_n given at the values the CG implies, Eq. 3 gives back the tadpole's CG x."""
    p = tadpole.params
    found = {f.values["wheel"]: f.values for f in audit(p) if f.topic == "sprung mass"}
    freq = {w.suspension: found[w.name]["natural_frequency_from_cg_hz"] for w in p.wheels}
    front = (found["front_left"]["natural_frequency_from_cg_hz"] + found["front_right"]["natural_frequency_from_cg_hz"]) / 2
    edited = override(tadpole, {"suspension.front.natural_frequency_hz": front,
                                "suspension.rear.natural_frequency_hz": freq["rear"]})
    eq3 = next(f for f in audit(edited) if f.topic == "CG from Eq. 3")
    assert eq3.level == "ok"
    assert eq3.values["cg_x_eq3_m"] == pytest.approx(p.mass.cg_x_m, rel=0.01)


@pytest.mark.parametrize("cg_x", [0.5, 0.8321, 1.4])
def test_rigid_tip_over_per_edge_is_d_t_over_2hl(tadpole, cg_x):
    """Each side edge of a tadpole: a_y / g = d T / (2 h L), d the CG's distance ahead of the rear axle."""
    p = override(tadpole, {"mass.cg_y_m": 0.0, "mass.cg_x_m": cg_x}).params
    h, L, T = p.mass.cg_z_m, p.wheelbase_m, p.track_m
    edges = {e["edge"]: e for e in tip_over_thresholds(p)}
    for name, side in (("front_left-rear", "left"), ("front_right-rear", "right")):
        assert edges[name]["lateral"] and edges[name]["tips_toward"] == side
        assert edges[name]["acceleration_g"] == pytest.approx(cg_x * T / (2 * h * L), rel=1e-12)
    front = edges["front_left-front_right"]
    assert not front["lateral"] and front["tips_toward"] == "front"
    assert front["acceleration_g"] == pytest.approx((L - cg_x) / h, rel=1e-12)


def test_rigid_tip_over_with_an_offset_cg(tadpole):
    """A CG left of the centre line: the left edge's threshold falls by y / h, the right's rises by it."""
    p = tadpole.params
    h, L, T, d, y = p.mass.cg_z_m, p.wheelbase_m, p.track_m, p.mass.cg_x_m, p.mass.cg_y_m
    edges = {e["tips_toward"]: e["acceleration_g"] for e in tip_over_thresholds(p)}
    assert edges["left"] == pytest.approx((d * T / (2 * L) - y) / h, rel=1e-12)
    assert edges["right"] == pytest.approx((d * T / (2 * L) + y) / h, rel=1e-12)


def test_wheelbase_and_track_of_a_tadpole(tadpole):
    p = override(tadpole, {"wheels.front_left.x_m": 1.9, "wheels.front_right.x_m": 2.0,
                           "wheels.front_left.y_m": 0.6}).params
    assert p.wheelbase_m == pytest.approx(1.95)
    assert p.track_m == pytest.approx(1.15)


@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        ({"wheels.rear.x_m": 0.2}, "the rear wheel's axle is the x origin of a tadpole: wheel 'rear' needs x_m = 0"),
        ({"wheels.front_left.x_m": -0.5, "wheels.front_right.x_m": -0.5},
         "both front (steered) wheels must be ahead of the rear wheel (x_m > 0)"),
        ({"wheels.front_right.y_m": 0.2}, "the two front wheels must be on opposite sides (y_m of opposite signs)"),
        ({"wheels.rear.steered": True}, "a tadpole layout has 2 steered wheel(s), found 3"),
        ({"wheels.front_right.steered": False}, "a tadpole layout has 2 steered wheel(s), found 1"),
    ],
)
def test_bad_tadpole_geometry_is_one_clear_line(tadpole, edit, needle):
    with pytest.raises(ParameterError) as info:
        override(tadpole, edit)
    assert needle in str(info.value) and "\n" not in str(info.value)


def test_delta_rules_unchanged(reference):
    with pytest.raises(ParameterError, match="both rear wheels need x_m = 0"):
        override(reference, {"wheels.rear_left.x_m": 0.1})
    with pytest.raises(ParameterError, match="a delta layout has 1 steered wheel"):
        override(reference, {"wheels.rear_left.steered": True})


def test_steering_linkage_fields_default_and_bounds(reference):
    s = reference.params.steering
    assert (s.ackermann_fraction, s.handlebar_ratio) == (1.0, 1.0)
    ok = override(reference, {"steering.ackermann_fraction": 0.0, "steering.handlebar_ratio": 30.0})
    assert ok.params.steering.ackermann_fraction == 0.0
    for key, value in (("ackermann_fraction", 1.6), ("ackermann_fraction", -0.1), ("handlebar_ratio", 0.0),
                       ("handlebar_ratio", 31.0)):
        with pytest.raises(ParameterError, match=f"steering.{key}"):
            override(reference, {f"steering.{key}": value})
