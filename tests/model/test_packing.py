"""The vehicle packed into named compiled records: same physics as before, readable by name.

``golden_delta.npz`` holds results of trikedyn 0.x at commit dfddce0, before the repacking (numbered
arrays): the static equilibrium, the right-hand side at a perturbed rolling state with inputs, the ISO
3888-1 run at 35 km/h (states, every 10th sample at 100 Hz), the ISO 14791 run at 40 km/h (wheel loads) and
an open-loop sine steer at 30 km/h (states, every 5th sample). The repacking changes no physics: all agree
to 1e-9 relative. They were recorded with classical RK4 at 5 ms, which the runs here ask for (the default
integrator is now ETDRK4 at 10 ms, :mod:`trikedyn.simulate.exponential`).
"""

from pathlib import Path

import numpy as np
import pytest

import trikedyn as td
from trikedyn.model.packing import INPUT_NAMES, VEHICLE, WHEEL, WHEEL_OUT
from trikedyn.model.rhs import f, f_with_outputs
from trikedyn.model.statics import static_equilibrium
from trikedyn.model.vehicle import build_model
from trikedyn.simulate.closed_loop import run

GOLDEN = np.load(Path(__file__).with_name("golden_delta.npz"))
WHEELS = ("front", "rear_left", "rear_right")
CLASSICAL = {"dt": 5e-3, "integrator": "rk4"}


def _rel(ours, before):
    return float(np.max(np.abs(ours - before)) / np.max(np.abs(before)))


def test_equilibrium_and_rhs_unchanged(reference):
    model = build_model(reference)
    assert _rel(static_equilibrium(model).state, GOLDEN["eq"]) < 1e-9
    xdot, wout = f_with_outputs(0.3, GOLDEN["xr"], np.array([0.05, 20.0, 5.0]), model.plant)
    assert _rel(xdot, GOLDEN["xd"]) < 1e-9
    assert _rel(wout["fz"], GOLDEN["fz"]) < 1e-9


@pytest.mark.parametrize(("name", "speed"), [("dlc", 35.0), ("slc", 40.0)])
def test_lane_changes_unchanged(reference, name, speed):
    result = run(reference, name, speed_kmh=speed, **CLASSICAL)
    loads = np.column_stack([result[f"{w}_fz_N"] for w in WHEELS])[::10]
    assert _rel(loads, GOLDEN[f"{name}_fz"]) < 1e-9
    if name == "dlc":
        assert _rel(result.states[::10], GOLDEN["dlc_states"]) < 1e-9


def test_open_loop_sine_unchanged(reference):
    result = td.run_open_loop(reference, duration_s=3.0, speed_kmh=30,
                              steer_rad=lambda t: 0.05 * np.sin(2 * np.pi * 0.5 * t), **CLASSICAL)
    assert _rel(result.states[::5], GOLDEN["sine_states"]) < 1e-9


def test_records_are_read_by_name(reference):
    model = build_model(reference)
    p = model.plant
    assert p.wheels.dtype == WHEEL and p.vehicle.dtype == VEHICLE
    front = model.wheel_names.index("front")
    assert p.wheels[front]["radius"] == reference.params.wheel("front").radius_m
    assert p.wheels[front]["steer_body"] >= 0 and p.wheels[front]["steer_kp"] > 0
    assert all(p.wheels[k]["steer_body"] == -1 for k in range(3) if k != front)
    assert model.vehicle["wheelbase"] == pytest.approx(reference.params.wheelbase_m)
    assert model.gravity == pytest.approx(9.80665)
    assert {"fx", "fy", "fz", "mz", "camber", "clamped"} <= set(WHEEL_OUT.names)


def test_variant_switches_parts_off_by_name(reference):
    model = build_model(reference)
    bare = model.variant(damping=False, slip_forces=False, gravity=0.0, drag=False)
    assert np.all(bare.wheels["damping"] == 0) and np.all(bare.wheels["vertical_damping"] == 0)
    assert np.all(bare.wheels["steer_kd"] == 0)
    assert bare.vehicle["slip_forces"] == 0 and bare.vehicle["g"] == 0 and bare.vehicle["aero"] == 0
    assert model.vehicle["g"] > 0 and np.all(model.wheels["steer_kd"] >= 0)  # the original is untouched


def test_public_rhs_has_labelled_states_and_inputs_and_feeds_scipy(reference):
    from scipy.integrate import solve_ivp

    model = build_model(reference)
    names = model.state_names
    assert len(names) == model.n_states and len(set(names)) == len(names)
    assert names[:6] == ("x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad")
    assert INPUT_NAMES == ("steer_rad", "drive_torque_Nm", "brake_torque_Nm")
    eq = static_equilibrium(model)
    x0 = eq.state.copy()
    x0[names.index("vx_mps")] = 5.0
    u = np.array([0.0, 0.0, 0.0])
    xdot = f(0.0, x0, u, model.plant)
    assert xdot[names.index("x_m")] == pytest.approx(5.0, rel=1e-3)  # it moves forward at 5 m/s
    sol = solve_ivp(f, (0.0, 0.2), x0, args=(u, model.plant), rtol=1e-8, atol=1e-10)
    assert sol.success and sol.y[names.index("x_m"), -1] == pytest.approx(1.0, rel=0.02)
