"""Variants (payload, scaling, overrides) and the consistency audit."""

import math

import pytest

from trikedyn.errors import InputError, ParameterError
from trikedyn.params import (
    audit,
    freight,
    load_vehicle,
    override,
    scale_suspension,
    static_wheel_loads,
    tip_over_thresholds,
    with_freight,
    with_payload,
)
from trikedyn.units import STANDARD_GRAVITY as G


def test_scale_suspension_table2(reference):
    s = scale_suspension(reference, stiffness=0.8, damping=1.2).params.suspension
    # Table 2: 64 231.20 and 36 630.28 N/m at 80 %; 220.60 and 192.85 N s/m at 120 %
    assert s["front"].stiffness_N_per_m == pytest.approx(64231.20, abs=0.005)
    assert s["rear"].stiffness_N_per_m == pytest.approx(36630.28, abs=0.005)
    assert s["front"].damping_Ns_per_m == pytest.approx(220.60, abs=0.005)
    assert s["rear"].damping_Ns_per_m == pytest.approx(192.85, abs=0.005)
    with pytest.raises(ParameterError, match="stiffness"):
        scale_suspension(reference, stiffness=-1)


def test_override_and_its_errors(reference):
    p = override(reference, {"mass.driver_kg": 90.0, "wheels.front.radius_m": 0.3}).params
    assert p.mass.driver_kg == 90.0 and p.wheel("front").radius_m == 0.3
    with pytest.raises(ParameterError, match="did you mean 'driver_kg'"):
        override(reference, {"mass.drivr_kg": 1.0})
    with pytest.raises(ParameterError, match="greater than or equal to 0"):
        override(reference, {"mass.driver_kg": -1.0})


def test_freight_raises_mass_and_cg(reference):
    from trikedyn.params import mass_properties

    laden = with_freight(reference, 200.0)
    mp = mass_properties(laden.params)
    assert mp.mass_kg == 783.0 and laden.params.mass.total_kg == 583.0  # the vehicle itself is unchanged
    assert mp.cg_m[2] > reference.params.mass.cg_z_m
    emptied = with_payload(laden, freight(laden.params, 200.0), remove=True)
    assert mass_properties(emptied.params).cg_m == pytest.approx(reference.params.mass.cg_m, abs=1e-12)
    with pytest.raises(InputError, match="cannot remove"):
        with_payload(reference, freight(reference.params, 2000.0), remove=True)
    with pytest.raises(ParameterError):
        with_freight(reference, -10.0)


def test_static_loads_sum_and_moments(reference):
    loads = static_wheel_loads(reference.params)
    p = reference.params
    assert sum(loads.values()) == pytest.approx(p.mass.total_kg * G)
    assert loads["front"] * p.wheelbase_m == pytest.approx(p.mass.total_kg * G * p.mass.cg_x_m)
    assert loads["rear_left"] > loads["rear_right"]  # CG 16 mm to the left


def test_tip_over_matches_closed_form(reference):
    """Lateral edges: a_y/g = (a T / (2 L) -+ y) / h with a the CG's distance behind the front contact."""
    p = reference.params
    a = p.wheelbase_m - p.mass.cg_x_m
    half = a * p.track_m / (2 * p.wheelbase_m)
    edges = {e["tips_toward"]: e for e in tip_over_thresholds(p)}
    assert edges["left"]["acceleration_g"] == pytest.approx((half - p.mass.cg_y_m) / p.mass.cg_z_m, rel=1e-12)
    assert edges["right"]["acceleration_g"] == pytest.approx((half + p.mass.cg_y_m) / p.mass.cg_z_m, rel=1e-12)
    assert edges["rear"]["acceleration_g"] == pytest.approx(p.mass.cg_x_m / p.mass.cg_z_m, rel=1e-12)


def test_audit_shows_table1_damping_inconsistency(reference):
    """Table 1's C is about 9.5x below what Eq. 4 gives from Table 1's own xi, f_n and K."""
    found = {f.values["suspension"]: f for f in audit(reference) if f.topic == "damping (Eq. 4)"}
    assert found["front"].level == "inconsistent" and found["rear"].level == "inconsistent"
    assert found["front"].values["ratio_eq4_to_given"] == pytest.approx(9.535, abs=0.01)
    assert found["rear"].values["ratio_eq4_to_given"] == pytest.approx(9.669, abs=0.01)
    assert found["front"].values["damping_ratio_of_given_C"] == pytest.approx(0.20 / 9.535, rel=1e-3)
    eq4 = {f.values["suspension"]: f for f in audit(load_vehicle("reference-etrike-eq4")) if f.topic == "damping (Eq. 4)"}
    assert all(f.level == "ok" for f in eq4.values())


def test_audit_flags_literal_cg_reading(reference):
    """Reading the paper's x literally (240.1 mm ahead of the rear axle) contradicts Table 1's Eq. 3 masses. As the
    preset reads it, the CG fits; Table 1's K fits the paper's rigid-tyre Eq. 3, not the model's tyre in series:
    a warning on the sprung mass (the spring convention, issue 20), not an inconsistency."""
    ok = [f for f in audit(reference) if f.topic in ("sprung mass", "CG from Eq. 3")]
    assert all(f.level == ("warning" if f.topic == "sprung mass" else "ok") for f in ok)
    literal = override(reference, {"mass.cg_x_m": 0.2401})
    found = {f.topic: f for f in audit(literal) if f.topic == "CG from Eq. 3"}
    assert found["CG from Eq. 3"].level == "inconsistent"
    front = next(f for f in audit(literal) if f.topic == "sprung mass" and f.values["wheel"] == "front")
    assert front.level == "inconsistent" and front.values["ratio_eq3_to_cg"] > 3


def test_audit_flags_cg_outside_support(reference):
    outside = override(reference, {"mass.cg_y_m": 0.6})
    assert any(f.level == "inconsistent" and "OUTSIDE" in f.message for f in audit(outside))


def test_eq3_masses_of_table1():
    """Sprung masses implied by Eq. 3 with Table 1's K and f_n (hand: 80289/(2 pi 2.916)^2 = 239.18 kg)."""
    assert 80289.0 / (2 * math.pi * 2.916) ** 2 == pytest.approx(239.18, abs=0.01)
    assert 45787.85 / (2 * math.pi * 2.72) ** 2 == pytest.approx(156.77, abs=0.01)
