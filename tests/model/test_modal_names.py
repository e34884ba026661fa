"""Modes named by what carries their kinetic energy: bounce, pitch, roll once each, each wheel's hop once."""

import json
import math
from collections import Counter

import numpy as np
import pytest

from trikedyn.cli import main
from trikedyn.model.linear import modes
from trikedyn.model.modal_names import assign_names
from trikedyn.model.statics import static_equilibrium
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle, override

UNIQUE = ("bounce", "pitch", "roll")


def bounce_pitch_decoupled():
    """The reference e-trike with its CG on the centre line where the front and rear equivalent rates (tyre
    in series with the spring) balance, ``k_f a = 2 k_r b``, so that bounce and pitch decouple; each wheel
    of its own mass, so that each wheel hops at its own frequency. Everything else is the reference's
    (inclined fork with trail, heavy unsprung parts, dampers, tyre forces)."""
    base = load_vehicle("reference-etrike")
    p = base.params
    kt = p.tyre.vertical_stiffness_N_per_m
    kf = p.suspension["front"].stiffness_N_per_m
    kr = p.suspension["rear"].stiffness_N_per_m
    keq_f, keq_r = kf * kt / (kf + kt), kr * kt / (kr + kt)
    return override(base, {
        "mass.cg_x_m": keq_f * p.wheelbase_m / (keq_f + 2 * keq_r),
        "mass.cg_y_m": 0.0,
        "mass.roll_yaw_product_kgm2": 0.0,
        "wheels.rear_left.mass_kg": 5.0,
        "wheels.rear_right.mass_kg": 16.0,
    })


def hop_frequencies(pset) -> dict:
    """Each wheel's hop by hand [Hz]: its unsprung mass between the tyre and the spring, the chassis held,
    ``sqrt((k_t + k_s) / m_u) / 2 pi``. A telescopic strut moves along the steering axis (angle ``eps``
    to the vertical): both rates act along it times ``cos^2 eps``; a swing arm's inertia about its pivot
    counts as ``I / L^2`` at the axle."""
    p = pset.params
    kt = p.tyre.vertical_stiffness_N_per_m
    out = {}
    for w in p.wheels:
        s = p.suspension[w.suspension]
        if s.kind == "telescopic":
            m_u, factor = w.mass_kg + s.moving_mass_kg, math.cos(p.steering_axis_angle_rad) ** 2
        else:
            m_u, factor = w.mass_kg + s.moving_inertia_kgm2 / s.arm_length_m**2, 1.0
        out[f"{w.name} wheel hop"] = math.sqrt((kt + s.stiffness_N_per_m) * factor / m_u) / (2 * math.pi)
    return out


def check_names(found, pset):
    """Bounce, pitch, roll and each wheel's hop name exactly one mode; each hop at its own frequency."""
    counts = Counter(m.name for m in found)
    table = [(m.name, round(m.frequency_hz, 2)) for m in found]
    hand = hop_frequencies(pset)
    for name in (*UNIQUE, *hand):
        assert counts[name] == 1, (name, table)
    for name, f_hand in hand.items():
        mode = next(m for m in found if m.name == name)
        assert mode.frequency_hz == pytest.approx(f_hand, rel=0.10), (name, mode.frequency_hz, f_hand, table)
        assert next(iter(mode.participation)) == name, (name, mode.participation)


def test_decoupled_bounce_and_pitch_are_named_so_and_each_hop_once():
    pset = bounce_pitch_decoupled()
    model = build_model(pset)
    found = modes(model, static_equilibrium(model))
    check_names(found, pset)
    for name in ("bounce", "pitch"):  # decoupled: each is nearly all of its mode's kinetic energy
        mode = next(m for m in found if m.name == name)
        assert mode.participation[name] > 0.85, (name, mode.participation)
    hops = sorted((m.frequency_hz, m.name) for m in found if m.name.endswith("wheel hop"))
    assert [n for _, n in hops] == ["rear_right wheel hop", "front wheel hop", "rear_left wheel hop"]  # by mass


@pytest.mark.parametrize("speed_kmh", [0.0, 30.0])
@pytest.mark.parametrize("preset", ["reference-etrike", "reference-tadpole"])
def test_presets_name_each_wheel_hop_once(preset, speed_kmh):
    pset = load_vehicle(preset)
    model = build_model(pset)
    found = modes(model, static_equilibrium(model), speed_mps=speed_kmh / 3.6)
    check_names(found, pset)
    for m in found:
        assert sum(m.participation.values()) <= 1.0 + 1e-12
        assert list(m.participation.values()) == sorted(m.participation.values(), reverse=True)


def test_assignment_gives_a_unique_name_to_the_mode_with_the_largest_share():
    groups = ("bounce", "pitch", "roll", "yaw", "rear_left wheel hop", "rear_right wheel hop", "steer")
    unique = {"bounce", "pitch", "roll", "rear_left wheel hop", "rear_right wheel hop"}
    shares = np.array([
        [0.55, 0.40, 0.0, 0.05, 0.0, 0.0, 0.0],  # bounce and pitch coupled: the stronger bounce keeps it
        [0.50, 0.45, 0.0, 0.05, 0.0, 0.0, 0.0],  # ... so this one is pitch
        [0.0, 0.0, 0.0, 0.0, 0.55, 0.45, 0.0],  # the rear hops mixed by symmetry: one each
        [0.0, 0.0, 0.0, 0.0, 0.52, 0.48, 0.0],
        [0.0, 0.0, 0.47, 0.30, 0.0, 0.0, 0.23],  # roll taken below: said as a combination
        [0.0, 0.0, 0.90, 0.10, 0.0, 0.0, 0.0],
        [0.0, 0.02, 0.0, 0.0, 0.0, 0.0, 0.98],  # steer is not unique
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
    ])
    names = assign_names(shares, groups, unique)
    assert names == ["bounce", "pitch", "rear_left wheel hop", "rear_right wheel hop", "roll + yaw", "roll", "steer",
                     "steer"]


def test_modes_command_at_speed(capsys):
    code = main(["modes", "reference-etrike", "--speed", "30", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and data["speed_kmh"] == 30.0
    assert isinstance(data["modes"], list) and data["modes"]
    for mode in data["modes"]:
        assert {"name", "frequency_hz", "damping_ratio", "eigenvalue", "participation"} <= set(mode)
    names = Counter(m["name"] for m in data["modes"])
    assert all(names[n] == 1 for n in ("bounce", "pitch", "roll", "front wheel hop")), names
    code = main(["modes", "reference-etrike", "--speed", "30"])
    out = capsys.readouterr().out
    assert code == 0 and "rolling straight ahead at 30 km/h" in out
