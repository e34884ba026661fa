"""The reference trike on the shipped PAC2002 tyre (a .tir per wheel station): the ladder still holds.

Statics, energy, and the steady cornering of the linear single-track model built from the file's own
cornering stiffness (Pacejka's full Magic Formula, :mod:`trikedyn.tyre.pac2002`); and the aligning moment
reaches the steering.
"""

import shutil
import warnings

import numpy as np
import pytest

import trikedyn as td
from trikedyn.model.linear import single_track
from trikedyn.model.statics import rolling_state, static_equilibrium
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle
from trikedyn.params.ops import static_wheel_loads
from trikedyn.simulate.integrator import OPEN_LOOP, STATUS_OK, rk4_loop
from trikedyn.simulate.run import TyreRangeWarning
from trikedyn.tyre.interface import MAGIC_FORMULA

from ..conftest import SHARED
from .energy import kinetic_energy, potential_energy

TIR = SHARED / "data" / "tyres" / "mf_185_80R14.tir"
pytestmark = pytest.mark.skipif(not TIR.is_file(), reason=f"shared tyre data absent ({TIR})")

VEHICLE = """extends = "reference-etrike"
name = "reference-etrike-pac2002"
description = "the reference trike on a PAC2002 tyre at every wheel"
[[wheels]]
name = "front"
tyre_file = "tyres/mf_185_80R14.tir"
[[wheels]]
name = "rear_left"
tyre_file = "tyres/mf_185_80R14.tir"
[[wheels]]
name = "rear_right"
tyre_file = "tyres/mf_185_80R14.tir"
"""


@pytest.fixture(scope="module")
def on_tir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("vehicle")
    (folder / "tyres").mkdir()
    shutil.copy(TIR, folder / "tyres" / TIR.name)
    (folder / "trike.toml").write_text(VEHICLE)
    return load_vehicle(folder / "trike.toml")


@pytest.fixture(scope="module")
def model(on_tir):
    return build_model(on_tir)


def test_every_wheel_runs_the_full_magic_formula_of_its_file(model):
    assert [t.model for t in model.tyres] == [MAGIC_FORMULA] * 3
    assert np.all(model.wheels["vertical_stiffness"] == 175000.0)  # the file's VERTICAL_STIFFNESS
    # relaxation lengths from PTX/PTY at each wheel's static load: the heavier front wheel's are longer
    front = model.wheel_names.index("front")
    assert model.wheels[front]["relaxation_y"] > max(model.wheels["relaxation_y"][k] for k in range(3) if k != front)


def test_static_loads_match_rigid_statics(model, on_tir):
    loads = static_equilibrium(model).wheel_loads_N
    rigid = static_wheel_loads(on_tir.params)
    for name, value in rigid.items():
        assert loads[name] == pytest.approx(value, rel=5e-3)


def test_energy_conserved_on_the_tir_vertical_springs(model):
    conservative = model.variant(damping=False, slip_forces=False, drag=False)
    n = conservative.n_dof
    x0 = rolling_state(conservative, static_equilibrium(conservative), 5.0)
    x0[2] += 0.01
    x0[n + 0] = 0.05
    energy0 = kinetic_energy(conservative, x0) + potential_energy(conservative, x0)
    scale = kinetic_energy(conservative, x0)
    times, states, _, _, _, status, rec, _ = rk4_loop(x0, 0.0, 2.5e-4, 8000, 400, np.zeros((1, 4)), *OPEN_LOOP,
                                                     conservative.plant, True, 0.0)
    assert status == STATUS_OK
    energy = np.array([kinetic_energy(conservative, x) + potential_energy(conservative, x) for x in states[:rec]])
    assert np.abs(energy - energy0).max() / scale < 1e-6


@pytest.mark.parametrize(("speed_mps", "steer_rad"), [(5.0, 0.03), (8.0, 0.012), (12.0, 0.006)])
def test_steady_cornering_matches_single_track_with_the_files_cornering_stiffness(model, speed_mps, steer_rad):
    """r / delta = v / (L + K_us v^2), with K_us from the file's cornering stiffness at the static loads.

    delta is the road steer angle the front wheel actually takes (the steer joint times cos(rake)): the
    aligning moment turns the wheel back against the servo. The tyre's offsets (ply steer, conicity) make
    left and right turns differ, so the gain is taken between a left and a right turn.
    """
    st = single_track(model)
    cos_rake = float(model.vehicle["cos_rake"])
    turns = []
    for steer in (steer_rad, -steer_rad):
        run = td.run_open_loop(model, duration_s=8.0, speed_kmh=speed_mps * 3.6, steer_rad=steer, drive_torque_Nm=51.0)
        tail = run.to_pandas().loc[7.0:8.0]
        turns.append((tail.speed_mps.mean(), tail.yaw_rate_radps.mean(), tail.steer_rad.mean() * cos_rake))
    speed = 0.5 * (turns[0][0] + turns[1][0])
    gain = (turns[0][1] - turns[1][1]) / (turns[0][2] - turns[1][2])
    expected = speed / (st.wheelbase_m + st.understeer_gradient_rad_per_mps2 * speed**2)
    assert gain == pytest.approx(expected, rel=0.03)
    assert max(abs(t[1]) * t[0] for t in turns) <= 1.0  # a_y within the linear range


def test_aligning_moment_turns_the_steering_back(model, reference):
    """In a steady turn the front tyre's aligning moment holds the steering short of the command, against
    the servo: the extra shortfall over the similarity tyre (which has no aligning moment; its shortfall is
    the mechanical trail's) times the servo stiffness is the moment about the steering axis, Mz cos(rake)."""
    shortfall, mz = {}, 0.0
    for name, vehicle in (("tir", model), ("similarity", build_model(reference))):
        run = td.run_open_loop(vehicle, duration_s=5.0, speed_kmh=25.0, steer_rad=0.02, drive_torque_Nm=51.0)
        tail = run.to_pandas().loc[4.0:5.0]
        shortfall[name] = 0.02 - tail.steer_rad.mean()
        if name == "tir":
            # turning left, the front tyre pushes left and slides right: its moment turns it back right
            assert tail.front_fy_N.mean() > 0 and tail.front_mz_Nm.mean() < -5.0
            mz = tail.front_mz_Nm.mean()
    front = model.wheel_names.index("front")
    moment = (shortfall["tir"] - shortfall["similarity"]) * model.wheels[front]["steer_kp"]
    assert moment == pytest.approx(-mz * float(model.vehicle["cos_rake"]), rel=0.1)


def test_leaving_the_files_ranges_warns_once_per_run(model):
    """A lane change fast enough to lift a wheel takes its load below the file's FZMIN (190 N): one warning."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = td.run(model, "dlc", speed_kmh=55.0)
    assert result.channels["min_wheel_load_N"].min() < 190.0
    ranges = [w for w in caught if issubclass(w.category, TyreRangeWarning)]
    assert len(ranges) == 1 and "clamped" in str(ranges[0].message)
