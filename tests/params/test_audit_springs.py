"""The audit's Eq. 3 with the tyre in series (issue 20): the vehicle file's K is the suspension's own spring, the
model adds the tyre; the paper's rigid-tyre Eq. 3 is reported beside it."""

from __future__ import annotations

import math

import pytest

from trikedyn.measure.quarter_car import quarter_car_modes, sprung_mass_for_frequency
from trikedyn.measure.suspension import suspension_from_body_mode
from trikedyn.params import audit, load_vehicle, override
from trikedyn.params.springs import series_stiffness, suspension_quarter_car, wheel_quarter_car


def _found(pset, topic, key, name):
    return next(f for f in audit(pset) if f.topic == topic and f.values.get(key) == name)


def test_sprung_mass_for_frequency_inverts_the_body_mode():
    # rigid, massless tyre: Eq. 3 inverted (hand: 80289 / (2 pi 2.916)^2 = 239.18 kg)
    assert sprung_mass_for_frequency(2.916, 1e-6, 80289.0, 0.0, 1e12) == pytest.approx(239.178, abs=1e-3)
    # the paper's tyre in series: close to K_eq / (2 pi f)^2 (unsprung mass and damping shift it a little)
    m = sprung_mass_for_frequency(2.916, 11.667, 80289.0, 1752.87, 200e3, 75.0)
    assert quarter_car_modes(m, 11.667, 80289.0, 1752.87, 200e3, 75.0).sprung_frequency_hz == pytest.approx(2.916, rel=1e-10)
    assert m == pytest.approx(series_stiffness(80289.0, 200e3) / (2 * math.pi * 2.916) ** 2, rel=0.05)
    assert sprung_mass_for_frequency(40.0, 11.667, 80289.0, 0.0, 200e3) is None  # above the wheel on its tyre


def test_the_papers_k_reads_as_tyre_inclusive(reference):
    """Table 1's K fits the paper's rigid-tyre Eq. 3 and not the model, which adds the 200 kN/m tyre in series."""
    for wheel in ("front", "rear_left", "rear_right"):
        f = _found(reference, "sprung mass", "wheel", wheel)
        assert f.level == "warning" and f.values["reading"] == "rigid tyre" and "tyre-inclusive" in f.message
        assert abs(f.values["ratio_eq3_to_cg"] - 1) <= 0.10 and f.values["ratio_series_to_cg"] < 0.9
    front = _found(reference, "sprung mass", "wheel", "front")
    car = wheel_quarter_car(reference.params, "front")
    assert front.values["natural_frequency_model_hz"] == pytest.approx(car.body_mode()[0], rel=1e-12)
    assert front.values["natural_frequency_model_hz"] < 0.9 * 2.916
    # the spring and damper that would give the paper's 2.916 Hz and xi 0.2 on the model's quarter car
    own = {"suspension.front.stiffness_N_per_m": front.values["stiffness_own_for_frequency_N_per_m"],
           "suspension.front.damping_Ns_per_m": front.values["damping_own_for_frequency_Ns_per_m"]}
    f, xi = wheel_quarter_car(override(reference, own).params, "front").body_mode()
    assert (f, xi) == pytest.approx((2.916, 0.20), rel=1e-9)
    # one cause, flagged once: Eq. 4 and the CG follow the rigid-tyre reading of Table 1
    assert _found(reference, "damping (Eq. 4)", "suspension", "front").values["ratio_eq4_to_given"] == pytest.approx(9.535, abs=0.01)
    cg = next(f for f in audit(reference) if f.topic == "CG from Eq. 3")
    assert cg.level == "ok" and "rigid-tyre" in cg.message
    assert not [f for f in audit(load_vehicle("reference-etrike-eq4")) if f.level == "inconsistent"]


def test_a_spring_that_gives_its_f_n_with_the_tyre_is_consistent(reference):
    """f_n and xi set to the model's quarter car: the series Eq. 3 and Eq. 4 hold exactly; the rigid Eq. 3 not."""
    p = reference.params
    car = suspension_quarter_car(p, "front")
    f, xi = car.body_mode()
    pset = override(reference, {"suspension.front.natural_frequency_hz": f, "suspension.front.damping_ratio": xi})
    front = _found(pset, "sprung mass", "wheel", "front")
    assert front.level == "ok" and front.values["reading"] == "series"
    assert front.values["ratio_series_to_cg"] == pytest.approx(1.0, abs=1e-9)  # one wheel: its own quarter car
    assert front.values["ratio_eq3_to_cg"] == pytest.approx(p.suspension["front"].stiffness_N_per_m / (2 * math.pi * f) ** 2
                                                            / car.sprung_mass_kg, rel=1e-12)
    assert front.values["ratio_eq3_to_cg"] > 1.3  # the old check would have said inconsistent
    eq4 = _found(pset, "damping (Eq. 4)", "suspension", "front")
    assert eq4.level == "ok" and eq4.values["ratio_series_to_given"] == pytest.approx(1.0, rel=1e-6)
    k, c = suspension_from_body_mode(f, xi, car.sprung_mass_kg, car.tyre_stiffness_N_per_m,
                                     tyre_damping=car.tyre_damping_Ns_per_m, unsprung_mass_kg=car.unsprung_mass_kg)
    assert float(k) == pytest.approx(p.suspension["front"].stiffness_N_per_m, rel=1e-6)
    assert eq4.values["damping_series_Ns_per_m"] == pytest.approx(float(c), rel=1e-9)
    # the rear still reads as tyre-inclusive: the CG from Eq. 3 takes each suspension in its reading
    cg = next(f for f in audit(pset) if f.topic == "CG from Eq. 3")
    assert cg.level == "ok" and cg.values["readings"] == {"front": "series", "rear": "rigid tyre"}


def test_neither_reading_fits_is_inconsistent(reference):
    bad = override(reference, {"suspension.front.natural_frequency_hz": 9.0})
    front = _found(bad, "sprung mass", "wheel", "front")
    assert front.level == "inconsistent" and front.values["reading"] is None


def test_without_f_n_the_model_frequency_is_given():
    tadpole = load_vehicle("reference-tadpole")
    for f in (f for f in audit(tadpole) if f.topic == "sprung mass"):
        series, rigid = f.values["natural_frequency_from_cg_hz"], f.values["natural_frequency_rigid_tyre_hz"]
        assert f.level == "ok" and series < rigid
        assert series == pytest.approx(wheel_quarter_car(tadpole.params, f.values["wheel"]).body_mode()[0], rel=1e-12)
