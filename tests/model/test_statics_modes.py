"""Verification ladder, rung 4: statics and small motions against hand calculations."""

import math

import pytest

from trikedyn.model.linear import modes
from trikedyn.model.statics import static_equilibrium
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle, mass_properties, override, static_wheel_loads, with_freight
from trikedyn.units import STANDARD_GRAVITY as G


@pytest.mark.parametrize("freight_kg", [0.0, 200.0])
@pytest.mark.parametrize("preset", ["reference-etrike", "reference-etrike-eq4"])
def test_static_loads_sum_and_split(preset, freight_kg):
    pset = with_freight(load_vehicle(preset), freight_kg)
    eq = static_equilibrium(build_model(pset))
    mass = mass_properties(pset.params).mass_kg
    total = sum(eq.wheel_loads_N.values())
    assert total == pytest.approx(mass * G, rel=1e-3)
    rigid = static_wheel_loads(pset.params)
    for wheel, load in eq.wheel_loads_N.items():
        assert load == pytest.approx(rigid[wheel], rel=5e-3), wheel


def decoupled_vehicle():
    """A delta trike built so that bounce, pitch, roll and wheel hop decouple: light unsprung parts,
    vertical steering axis with no trail, level swing arms, CG on the centre line where the front and rear
    equivalent (tyre in series) rates balance, no roll-yaw product."""
    base = load_vehicle("reference-etrike")
    p = base.params
    kt = p.tyre.vertical_stiffness_N_per_m
    kf = p.suspension["front"].stiffness_N_per_m
    kr = p.suspension["rear"].stiffness_N_per_m
    keq_f, keq_r = kf * kt / (kf + kt), kr * kt / (kr + kt)
    wheelbase = p.wheelbase_m
    x_cg = keq_f * wheelbase / (keq_f + 2 * keq_r)
    values = {
        "mass.cg_x_m": x_cg,
        "mass.cg_y_m": 0.0,
        "mass.roll_yaw_product_kgm2": 0.0,
        "steering.axis_angle_deg": 0.0,
        "steering.trail_m": 0.0,
        "steering.head_mass_kg": 0.5,
        "steering.head_inertia_kgm2": 0.05,
        "suspension.front.moving_mass_kg": 0.5,
        "suspension.rear.moving_mass_kg": 0.5,
        "suspension.rear.moving_inertia_kgm2": 0.04,
        "suspension.rear.pivot_height_m": p.wheel("rear_left").radius_m,
    }
    for w in ("front", "rear_left", "rear_right"):
        values[f"wheels.{w}.mass_kg"] = 1.0
        values[f"wheels.{w}.spin_inertia_kgm2"] = 0.03
    return override(base, values)


def hand_frequencies(pset):
    """Bounce, pitch, roll and wheel-hop frequencies [Hz] by hand (tyre in series with the suspension).

    With no horizontal tyre forces the body pitches and rolls about its CG while the contact points slide;
    they are ``h`` below the CG, so tilting by ``phi`` lifts them by ``h phi^2 / 2`` and the body sinks as
    much: gravity takes ``M g h`` off the pitch and roll stiffness (Gillespie 1992, ch. 9 does the same
    with the roll-centre height).
    """
    p = pset.params
    kt = p.tyre.vertical_stiffness_N_per_m
    kf = p.suspension["front"].stiffness_N_per_m
    kr = p.suspension["rear"].stiffness_N_per_m
    keq_f, keq_r = kf * kt / (kf + kt), kr * kt / (kr + kt)
    arm = p.suspension["rear"]
    m_u_front = p.wheel("front").mass_kg + p.suspension["front"].moving_mass_kg
    m_u_rear = p.wheel("rear_left").mass_kg + arm.moving_inertia_kgm2 / arm.arm_length_m**2
    whole = mass_properties(p)
    sprung = whole.mass_kg - m_u_front - 2 * m_u_rear
    x_cg = whole.cg_m[0]
    # the unsprung masses move with the ground in the sprung modes: take them off the pitch and roll inertia
    i_yy = whole.inertia_kgm2[1, 1] - m_u_front * (p.wheelbase_m - x_cg) ** 2 - 2 * m_u_rear * x_cg**2
    half = p.track_m / 2
    gravity = sprung * G * whole.cg_m[2]
    i_xx = whole.inertia_kgm2[0, 0] - 2 * m_u_rear * half**2
    two_pi = 2 * math.pi
    return {
        "bounce": math.sqrt((keq_f + 2 * keq_r) / sprung) / two_pi,
        "pitch": math.sqrt((keq_f * (p.wheelbase_m - x_cg) ** 2 + 2 * keq_r * x_cg**2 - gravity) / i_yy) / two_pi,
        "roll": math.sqrt((2 * keq_r * half**2 - gravity) / i_xx) / two_pi,
        "front wheel hop": math.sqrt((kf + kt) / m_u_front) / two_pi,
        "rear_left wheel hop": math.sqrt((kr + kt) / m_u_rear) / two_pi,
    }


def test_mode_frequencies_match_hand_calculations():
    pset = decoupled_vehicle()
    model = build_model(pset).variant(damping=False, slip_forces=False, drag=False)
    found = modes(model, static_equilibrium(model))
    expected = hand_frequencies(pset)
    for name, f_hand in expected.items():
        candidates = [m for m in found if m.name == name]
        assert candidates, (name, [(m.name, round(m.frequency_hz, 3)) for m in found])
        best = min(candidates, key=lambda m: abs(m.frequency_hz - f_hand))
        assert best.frequency_hz == pytest.approx(f_hand, rel=0.03), (name, best.frequency_hz, f_hand)
