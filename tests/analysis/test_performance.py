"""Straight-line performance: top speed against the hand power balance and the torque limit's closed form, the
grade, and each figure against the simulation itself (the verification ladder); the command line."""

import json
import math
import shutil
from dataclasses import replace

import numpy as np
import pytest
from scipy.optimize import brentq

from trikedyn.analysis.performance import CRAWL_KMH, STOP_KMH, acceleration, braking, performance, top_speed
from trikedyn.cli import main
from trikedyn.errors import InputError
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle, override
from trikedyn.simulate.run import simulate

from ..conftest import SHARED, strict_json


@pytest.fixture(scope="module")
def etrike():
    return load_vehicle("reference-etrike")


@pytest.fixture(scope="module")
def model(etrike):
    return build_model(etrike)


def by_hand(pset):
    """The vehicle file's values: mass with driver [kg], C_rr, 0.5 rho C_d A [kg/m], P [W], T [N m], R [m]."""
    p = pset.params
    drive = p.drive
    rear = next(w for w in p.wheels if w.driven)
    k = 0.5 * p.aero.air_density_kg_per_m3 * p.aero.drag_coefficient * p.aero.frontal_area_m2
    return (p.mass.curb_kg + p.mass.driver_kg, p.tyre.rolling_resistance, k, drive.max_power_W,
            drive.max_drive_torque_Nm, rear.radius_m)


G = 9.80665


def end_speed_kmh(model, start_kmh, duration_s, torque):
    run = simulate(model, duration_s=duration_s, speed_kmh=start_kmh, drive_torque_Nm=torque)
    assert run.success
    return float(run["speed_mps"][-1] * 3.6)


# ------------------------------------------------------------------------------------------------------------
# the closed forms
# ------------------------------------------------------------------------------------------------------------
def test_top_speed_is_the_hand_power_balance(etrike):
    """P = (m g C_rr + rho C_d A v^2 / 2) v, solved by hand from the file's values: 55.14 km/h. The function
    gives 54.87 km/h (-0.49 %): the driven wheels' slip and the force arm R against the rolling radius R_e
    cost 1.7 % of the power at the road."""
    mass, crr, k, power, _, _ = by_hand(etrike)
    v = brentq(lambda v: (mass * G * crr + k * v * v) * v - power, 1.0, 100.0)
    result = top_speed(etrike)
    assert result.limit == "power"
    assert result.top_speed_kmh == pytest.approx(v * 3.6, rel=0.01)
    assert result.top_speed_kmh == pytest.approx(54.87, abs=0.01)
    assert result.power_W == pytest.approx(power, rel=1e-6)
    # the balance it reports: drive force = rolling + aero (+ grade)
    assert result.drive_force_N == pytest.approx(result.rolling_resistance_N + result.aero_drag_N, rel=1e-6)
    assert result.aero_drag_N == pytest.approx(k * (result.top_speed_kmh / 3.6) ** 2, rel=1e-9)
    assert result.rolling_resistance_N == pytest.approx(mass * G * crr, rel=0.02)
    assert "power-limited" in result.detail


def test_torque_limit_where_it_binds_first(etrike):
    """With 50 kW the 300 N m limit binds on the flat: T / R = m g C_rr + k v^2 (113.81 km/h by hand)."""
    strong = override(etrike, {"drive.max_power_W": 50000.0})
    mass, crr, k, _, torque, radius = by_hand(strong)
    v = math.sqrt((torque / radius - mass * G * crr) / k)
    result = top_speed(strong)
    assert result.limit == "torque"
    assert result.drive_torque_Nm == pytest.approx(torque)
    assert result.top_speed_kmh == pytest.approx(v * 3.6, rel=0.005)


def grade_for(force, mass, crr):
    """The grade [%] at which m g (C_rr cos + sin) equals ``force``."""
    theta = brentq(lambda t: mass * G * (crr * math.cos(t) + math.sin(t)) - force, 0.0, 1.0)
    return 100.0 * math.tan(theta)


def test_grade_switches_the_limit_from_power_to_torque_to_cannot_climb(etrike):
    """Up a grade the top speed falls to the corner speed where T_max omega = P (15.7 km/h); steeper, the
    torque holds it (between 5 km/h and the corner), then it cannot climb. The grades by hand from the file."""
    mass, crr, k, power, torque, radius = by_hand(etrike)
    force = torque / radius
    corner = power / force  # speed [m/s] at which the torque limit meets the power limit
    crawl = CRAWL_KMH / 3.6
    corner_grade = grade_for(force - k * corner**2, mass, crr)  # about 17.9 %
    steepest = grade_for(force - k * crawl**2, mass, crr)  # about 18.3 %
    assert top_speed(etrike, corner_grade - 0.5).limit == "power"
    between = top_speed(etrike, 0.5 * (corner_grade + steepest))
    assert between.limit == "torque"
    assert CRAWL_KMH < between.top_speed_kmh < corner * 3.6
    assert between.drive_torque_Nm == pytest.approx(torque)
    assert between.drive_force_N == pytest.approx(
        between.rolling_resistance_N + between.aero_drag_N + between.grade_resistance_N, rel=1e-6)
    steep = top_speed(etrike, steepest + 0.5)
    assert (steep.top_speed_kmh, steep.limit) == (0.0, "cannot climb")


def test_grade_by_the_closed_form(etrike):
    """The simulated road is flat: the grade is checked by the closed form only. The hand power balance
    ``P = (m g (C_rr cos + sin) + k v^2) v`` (tan = grade / 100) within 2 %; with the model's two losses by hand
    (the force arm R against the rolling radius R_e = R - d / 3, d the mean static deflection; the driven
    wheels' slip F / (2 C_kappa), C_kappa = 16 F_z from the file, F_z from rigid statics) within 0.3 %
    (measured 0.10 % flat, 0.17 % at 5 %, 0.22 % at 10 %, 0.06 % at -5 %). The grade's force is m g sin."""
    p = etrike.params
    mass, crr, k, power, _, radius = by_hand(etrike)
    rear_share = 1.0 - p.mass.cg_x_m / next(w.x_m for w in p.wheels if w.steered)

    def plain(v, cos, sin):
        return (mass * G * (crr * cos + sin) + k * v * v) * v - power

    def refined(v, cos, sin):
        rolling = radius - mass * G * cos / 3 / p.tyre.vertical_stiffness_N_per_m / 3  # R_e at the mean load
        force = mass * G * (crr * cos * rolling / radius + sin) + k * v * v
        slip = force / 2 / (p.tyre.slip_stiffness_factor * mass * G * cos * rear_share / 2)
        return power * rolling / radius / (1 + slip) / v - force

    for grade in (5.0, 10.0, -5.0):
        theta = math.atan(grade / 100)
        args = (math.cos(theta), math.sin(theta))
        v = brentq(plain, 1.0, 100.0, args=args)
        better = brentq(refined, 1.0, 100.0, args=args)
        result = top_speed(etrike, grade)
        assert result.limit == "power"
        assert result.top_speed_kmh == pytest.approx(v * 3.6, rel=0.02), grade
        assert result.top_speed_kmh == pytest.approx(better * 3.6, rel=0.003), grade
        assert result.grade_resistance_N == pytest.approx(mass * G * args[1], rel=1e-9)
    assert "coast downhill" in top_speed(etrike, -5.0).detail


def test_runs_away_downhill_without_drag(etrike):
    bare = override(etrike, {"aero.drag_coefficient": 0.0})
    result = top_speed(bare, -10.0)
    assert result.top_speed_kmh is None and result.limit == "runs away downhill"
    assert top_speed(bare).limit == "power"  # on the flat the rolling resistance still balances it
    assert result.to_dict()["top_speed_kmh"] is None


def test_bad_grade_is_an_input_error(etrike):
    for bad in (float("nan"), 150.0, -101.0):
        with pytest.raises(InputError, match="grade_percent"):
            top_speed(etrike, bad)


def test_results_follow_the_drive_limits_of_a_model_that_shares_the_cache(model):
    """A variant with other limits that shares the model's cache (as ``with_ideal_drive`` does) gets its own
    figures, not the cached ones."""
    first = top_speed(model)
    vehicle = model.plant.vehicle.copy()
    vehicle["max_power"] = 2500.0
    weaker = replace(model, plant=model.plant._replace(vehicle=vehicle), cache=model.cache)
    assert top_speed(weaker).top_speed_kmh < first.top_speed_kmh - 5.0
    assert top_speed(model) is first


# ------------------------------------------------------------------------------------------------------------
# against the simulation (verification ladder)
# ------------------------------------------------------------------------------------------------------------
def test_simulated_full_throttle_run_settles_at_the_top_speed(model, etrike):
    """60 s at full drive from 1 km/h below and above: both runs end within 0.02 % of the function's top speed
    (measured: -0.008 % and +0.010 %; the time constant is about 12 s, so 60 s leaves 0.006 km/h)."""
    v = top_speed(model).top_speed_kmh
    torque = etrike.params.drive.max_drive_torque_Nm
    below = end_speed_kmh(model, v - 1.0, 60.0, torque)
    above = end_speed_kmh(model, v + 1.0, 60.0, torque)
    assert below < above
    for end in (below, above):
        assert end == pytest.approx(v, rel=2e-4)


def test_acceleration_matches_a_simulated_run(model, etrike):
    """3 -> 30 km/h at full drive (from a rolling start: the slip's regularisation below v_low = 1 m/s is in
    both): time and distance within 0.3 % (measured -0.02 % and -0.03 %)."""
    result = acceleration(model, 30.0, from_kmh=3.0)
    run = simulate(model, duration_s=8.0, speed_kmh=3.0, drive_torque_Nm=etrike.params.drive.max_drive_torque_Nm)
    speed, t, x = run["speed_mps"] * 3.6, run.time_s, run["x_m"]
    i = int(np.argmax(speed >= 30.0))
    f = (30.0 - speed[i - 1]) / (speed[i] - speed[i - 1])
    t30 = t[i - 1] + f * (t[i] - t[i - 1])
    x30 = x[i - 1] + f * (x[i] - x[i - 1]) - x[0]
    assert result.time_s == pytest.approx(t30, rel=3e-3)
    assert result.distance_m == pytest.approx(x30, rel=3e-3)
    assert result.power_limited_from_kmh == pytest.approx(15.7, abs=0.1)  # 300 N m x omega = 5 kW
    full = acceleration(model)  # from rest
    assert full.time_s > result.time_s and full.to_dict()["from_kmh"] == 0.0


def simulated_stop(model, pset):
    """Distance [m] and time [s] to STOP_KMH of a full-brake run from 30 km/h at a 1 ms step (the default
    10 ms step is too long for a wheel near lock: the brake's tanh(omega / w_low) is stiff there)."""
    run = simulate(model, duration_s=2.5, speed_kmh=30.0, brake_torque_Nm=pset.params.drive.max_brake_torque_Nm,
                   dt=0.001, output_rate_hz=1000.0)
    speed, x = run["speed_mps"], run["x_m"]
    j = int(np.argmax(speed < STOP_KMH / 3.6))
    return float(x[j] - x[0]), float(run.time_s[j])


def test_braking_matches_a_simulated_run(model, etrike):
    """Full brakes from 30 km/h to 0.5 km/h: both rear wheels lock at once; distance within 1 % (measured
    -0.3 %) and time within 2 % (measured -0.5 %) of the simulation, whose suspension pitches and overshoots at
    the brake's onset."""
    result = braking(model)
    assert set(result.locked_wheels) == {"rear_left", "rear_right"}
    distance, time = simulated_stop(model, etrike)
    assert result.distance_m == pytest.approx(distance, rel=0.01)
    assert result.time_s == pytest.approx(time, rel=0.02)


def test_tadpole(etrike):
    """The tadpole (one driven rear wheel, the pair in front): a 30 s full-drive run from the function's top
    speed stays there (within 0.05 %; a 1 % error would leave 0.9 %), and braking locks the front pair
    (distance measured +0.13 % off the simulation)."""
    tadpole = load_vehicle("reference-tadpole")
    model = build_model(tadpole)
    result = top_speed(model)
    assert result.limit == "power"
    assert result.top_speed_kmh == pytest.approx(top_speed(etrike).top_speed_kmh, rel=0.01)
    end = end_speed_kmh(model, result.top_speed_kmh, 30.0, tadpole.params.drive.max_drive_torque_Nm)
    assert end == pytest.approx(result.top_speed_kmh, rel=5e-4)
    stop = braking(model)
    assert set(stop.locked_wheels) == {"front_left", "front_right"}
    assert stop.distance_m == pytest.approx(simulated_stop(model, tadpole)[0], rel=0.01)


TIR = SHARED / "data" / "tyres" / "mf_185_80R14.tir"


@pytest.mark.skipif(not TIR.is_file(), reason=f"shared tyre data absent ({TIR})")
def test_tir_tyres_use_their_own_force_function(tmp_path):
    """On a PAC2002 .tir tyre at every wheel (its Fx, rolling resistance and vertical stiffness): the simulated
    run from the top speed stays there (within 0.05 %)."""
    (tmp_path / "tyres").mkdir()
    shutil.copy(TIR, tmp_path / "tyres" / TIR.name)
    wheels = "".join(f'[[wheels]]\nname = "{w}"\ntyre_file = "tyres/{TIR.name}"\n'
                     for w in ("front", "rear_left", "rear_right"))
    (tmp_path / "trike.toml").write_text('extends = "reference-etrike"\nname = "on-tir"\ndescription = "x"\n' + wheels)
    pset = load_vehicle(tmp_path / "trike.toml")
    model = build_model(pset)
    result = top_speed(model)
    assert result.limit == "power"
    end = end_speed_kmh(model, result.top_speed_kmh, 30.0, pset.params.drive.max_drive_torque_Nm)
    assert end == pytest.approx(result.top_speed_kmh, rel=5e-4)


def test_performance_bundles_the_three(etrike):
    result = performance(etrike, grade_percent=5.0)
    data = result.to_dict()
    assert data["top_speed_kmh"] == pytest.approx(top_speed(etrike, 5.0).top_speed_kmh)
    assert data["acceleration"]["time_s"] > acceleration(etrike).time_s
    assert data["braking"]["distance_m"] < braking(etrike).distance_m  # uphill helps
    json.dumps(data, allow_nan=False)


# ------------------------------------------------------------------------------------------------------------
# the command line
# ------------------------------------------------------------------------------------------------------------
def run(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_text_leads_with_the_top_speed(capsys):
    code, out, _ = run(capsys, "performance", "reference-etrike")
    assert code == 0
    lines = out.splitlines()
    assert lines[0].startswith("top speed 54.9 km/h on the flat (power-limited: 5.0 kW at the wheels against")
    assert lines[1].startswith("0-30 km/h in ") and lines[2].startswith("braking from 30 km/h: ")


def test_cli_json(capsys):
    code, out, _ = run(capsys, "performance", "reference-etrike", "--payload", "100", "--grade-percent", "5", "--json")
    data = strict_json(out)
    assert code == 0
    assert {"vehicle", "payload_kg", "grade_percent", "top_speed_kmh", "limit", "acceleration", "braking"} <= set(data)
    assert (data["vehicle"], data["payload_kg"], data["grade_percent"], data["limit"]) == (
        "reference-etrike", 100.0, 5.0, "power")
    assert data["top_speed_kmh"] < top_speed(load_vehicle("reference-etrike"), 5.0).top_speed_kmh


@pytest.mark.parametrize("grade", ["120", "-60", "nan"])
def test_cli_bad_grade_is_one_line_and_exit_2(capsys, grade):
    code, out, err = run(capsys, "performance", "reference-etrike", "--grade-percent", grade)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and "--grade-percent" in err
