"""Centre of gravity: weighing round trips, uncertainty coverage, mass composition, Table 3."""

import numpy as np
import pytest

from trikedyn.errors import InputError
from trikedyn.measure.cg import (
    Box,
    MassProperties,
    Payload,
    PointMass,
    cg_from_level_weighing,
    cg_height_from_tilted_weighings,
    combine,
    tilted_wheel_loads,
    wheel_loads_from_cg,
)
from trikedyn.paper import data as paper
from trikedyn.units import STANDARD_GRAVITY as G

CONTACTS = np.array([[1.95, 0.0], [0.0, 0.55], [0.0, -0.55]])
TRUTH = np.array([0.8321, 0.016, 0.3804])
MASS = 583.0
RADIUS = 0.27
HEIGHTS = np.array([0.10, 0.20, 0.30, 0.40])


def test_wheel_loads_balance_forces_and_moments():
    loads = wheel_loads_from_cg(MASS, TRUTH[:2], CONTACTS)
    assert loads.sum() == pytest.approx(MASS * G, rel=1e-12)
    assert loads @ CONTACTS[:, 0] == pytest.approx(MASS * G * TRUTH[0], rel=1e-12)
    assert loads @ CONTACTS[:, 1] == pytest.approx(MASS * G * TRUTH[1], rel=1e-12)


def test_level_weighing_round_trip_exact():
    loads = wheel_loads_from_cg(MASS, TRUTH[:2], CONTACTS)
    res = cg_from_level_weighing(loads, CONTACTS)
    assert res.mass_kg == pytest.approx(MASS, rel=1e-12)
    assert abs(res.cg_x_m - TRUTH[0]) < 1e-4 * 1e-3  # far below 0.1 mm
    assert abs(res.cg_y_m - TRUTH[1]) < 1e-7


@pytest.mark.parametrize("raised", ["front", "rear"])
def test_tilted_weighing_round_trip_exact(raised):
    loads = tilted_wheel_loads(MASS, TRUTH, 1.95, HEIGHTS, wheel_radius_m=RADIUS, raised=raised)
    res = cg_height_from_tilted_weighings(
        loads, HEIGHTS, mass_kg=MASS, cg_x_m=TRUTH[0], wheelbase_m=1.95, wheel_radius_m=RADIUS, raised=raised
    )
    assert abs(res.cg_z_m - TRUTH[2]) < 1e-7
    np.testing.assert_allclose(res.per_height_z_m, TRUTH[2], atol=1e-9)


def test_uncertainty_covers_truth_with_noise():
    """Over many noisy weighings the reported 1-sigma interval covers the truth about 68 % of the time
    (and the 3-sigma one nearly always): the uncertainty is honest, neither too small nor huge."""
    rng = np.random.default_rng(7)
    sigma_kg = 0.5
    hits1 = np.zeros(3)
    hits3 = np.zeros(3)
    trials = 400
    for _ in range(trials):
        level = wheel_loads_from_cg(MASS, TRUTH[:2], CONTACTS) + rng.normal(0, sigma_kg * G, 3)
        lvl = cg_from_level_weighing(level, CONTACTS, load_std_N=sigma_kg * G)
        tilt = tilted_wheel_loads(MASS, TRUTH, 1.95, HEIGHTS, wheel_radius_m=RADIUS) + rng.normal(0, sigma_kg * G, 4)
        z = cg_height_from_tilted_weighings(
            tilt, HEIGHTS, mass_kg=MASS, cg_x_m=TRUTH[0], wheelbase_m=1.95, wheel_radius_m=RADIUS,
            load_std_N=sigma_kg * G,
        )
        err = np.abs([lvl.cg_x_m - TRUTH[0], lvl.cg_y_m - TRUTH[1], z.cg_z_m - TRUTH[2]])
        std = np.array([lvl.cg_x_std_m, lvl.cg_y_std_m, z.cg_z_std_m])
        hits1 += err <= std
        hits3 += err <= 3 * std
    cover1 = hits1 / trials
    assert np.all(cover1 > 0.55), cover1
    assert np.all(hits3 / trials > 0.97), hits3 / trials


def test_weighing_rejects_bad_input():
    with pytest.raises(InputError, match="loads"):
        cg_from_level_weighing([100.0, -5.0, 100.0], CONTACTS)
    with pytest.raises(InputError, match="raise_heights_m"):
        cg_height_from_tilted_weighings([1.0], [2.5], mass_kg=1, cg_x_m=1, wheelbase_m=1.95, wheel_radius_m=0.27)


def test_composition_parallel_axis_and_removal():
    a = Box(100.0, (0.5, 0.1, 0.6), (0.4, 0.3, 0.2))
    b = PointMass(50.0, (1.5, -0.2, 1.0))
    both = combine([a, b])
    assert both.mass_kg == 150.0
    np.testing.assert_allclose(both.cg_m, (100 * np.array([0.5, 0.1, 0.6]) + 50 * np.array([1.5, -0.2, 1.0])) / 150)
    # the yaw inertia of two bodies about their common CG, by hand
    d_a = np.array([0.5, 0.1]) - both.cg_m[:2]
    d_b = np.array([1.5, -0.2]) - both.cg_m[:2]
    izz = 100 / 12 * (0.4**2 + 0.3**2) + 100 * d_a @ d_a + 50 * d_b @ d_b
    assert both.inertia_kgm2[2, 2] == pytest.approx(izz, rel=1e-12)
    back = both - b.mass_properties()
    np.testing.assert_allclose(back.cg_m, a.centre_m, atol=1e-12)
    np.testing.assert_allclose(back.inertia_kgm2, a.mass_properties().inertia_kgm2, atol=1e-10)
    payload = Payload("p", (b,))
    np.testing.assert_allclose(payload.removed_from(payload.added_to(a.mass_properties())).cg_m, a.centre_m)


def test_negative_mass_is_an_error():
    with pytest.raises(InputError, match="crate"):
        Payload("p", (PointMass(-3.0, (0, 0, 0), name="crate"),)).mass_properties()
    with pytest.raises(InputError):
        MassProperties(10.0, (0, 0, 0)) - MassProperties(20.0, (0, 0, 0))


def test_table3_reproduced_to_half_a_millimetre(reference):
    """Table 3 with one freight position (fitted, in the preset) and a base mass of 583 kg
    (508 kg vehicle + 75 kg driver): every CG coordinate within 0.5 mm for all five freight masses."""
    from trikedyn.params import mass_properties, with_freight

    assert reference.params.mass.total_kg == 583.0
    for freight_kg, *cg_mm in paper.TABLE3:
        cg = mass_properties(with_freight(reference, freight_kg).params).cg_m
        ours_mm = (cg - [paper.REFERENCE_X_DATUM_M, 0.0, 0.0]) * 1000
        assert np.max(np.abs(ours_mm - cg_mm)) < 0.5, (freight_kg, ours_mm, cg_mm)


def test_table3_fails_with_vehicle_mass_alone(reference):
    """The same freight position cannot reproduce Table 3 with the 508 kg vehicle alone: the best
    position for 508 kg still misses by more than 0.5 mm (why the base mass includes a driver)."""
    from scipy.optimize import least_squares

    rows = np.array(paper.TABLE3)
    base = rows[0, 1:]

    def residual(site, m0):
        m = rows[1:, :1]
        return ((m0 * base + m * site) / (m0 + m) - rows[1:, 1:]).ravel()

    best_508 = least_squares(residual, [-400.0, 0.0, 1000.0], args=(508.0,))
    best_583 = least_squares(residual, [-400.0, 0.0, 1000.0], args=(583.0,))
    assert np.abs(best_508.fun).max() > 0.5
    assert np.abs(best_583.fun).max() < 0.1
