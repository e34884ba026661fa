"""One wheel's quasi-static spin balance (trikedyn.analysis.wheel_balance): the compiled balance against the
module's formula evaluated in Python with the tyre's own function, and the slip roots it gives."""

import math
import shutil

import numpy as np
import pytest

from trikedyn.analysis.straight_line import straight_running
from trikedyn.analysis.wheel_balance import _secant, solve_slip, spin_balance
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle
from trikedyn.tyre.interface import tyre_forces

from ..conftest import SHARED

TIR = SHARED / "data" / "tyres" / "mf_185_80R14.tir"


@pytest.fixture(scope="module")
def wheels():
    return straight_running(build_model(load_vehicle("reference-etrike"))).wheels


@pytest.fixture(scope="module")
def tir_wheels(tmp_path_factory):
    if not TIR.exists():
        pytest.skip(f"no .tir file at {TIR} (the shared data folder is absent)")
    folder = tmp_path_factory.mktemp("tir")
    (folder / "tyres").mkdir()
    shutil.copy(TIR, folder / "tyres" / TIR.name)
    wheels = "".join(f'[[wheels]]\nname = "{w}"\ntyre_file = "tyres/{TIR.name}"\n'
                     for w in ("front", "rear_left", "rear_right"))
    (folder / "trike.toml").write_text('extends = "reference-etrike"\nname = "on-tir"\ndescription = "x"\n' + wheels)
    return straight_running(build_model(load_vehicle(folder / "trike.toml"))).wheels


def by_formula(w, kappa, v, v_ref, fz, a, tau_drive, tau_brake):
    """The module's spin balance written out in Python: ``tau_drive - tau_brake tanh(omega / w_low) - F_x R + M_y
    - I omega'`` with ``R_e = R - F_z / k_z / 3`` and ``omega' = a (1 + kappa (v / v_ref)^3) / R_e``."""
    r_eff = w.radius - fz / w.kz / 3.0
    spin = (v + kappa * v_ref) / r_eff
    fx, my = 0.0, 0.0
    if fz > 0.0:
        fx, _, _, _, my, _ = tyre_forces(w.model, w.coeffs, kappa, 0.0, 0.0, fz, v, v_ref, spin, r_eff, w.v_low,
                                         w.w_low)
    spin_rate = a * (1.0 + kappa * (v / v_ref) ** 3) / r_eff
    g = tau_drive - tau_brake * math.tanh(spin / w.w_low) - fx * w.radius + my - w.inertia * spin_rate
    return g, fx, my, spin


@pytest.mark.parametrize("which", ["wheels", "tir_wheels"])
def test_the_compiled_balance_is_the_formula(which, request):
    """The similarity tyre of the preset, and a PAC2002 .tir file's full Magic Formula."""
    wheels = request.getfixturevalue(which)
    rng = np.random.default_rng(7)
    for w in wheels:
        for _ in range(200):
            v = float(rng.uniform(0.05, 30.0))
            v_ref = (v**4 + w.v_low**4) ** 0.25
            args = (float(rng.uniform(-1.0, 0.5)), v, v_ref, float(rng.uniform(-50.0, 2500.0)),
                    float(rng.uniform(-6.0, 3.0)), float(rng.uniform(0.0, 150.0)), float(rng.uniform(0.0, 300.0)))
            got, want = spin_balance(w, *args), by_formula(w, *args)
            np.testing.assert_allclose(got, want, rtol=1e-13, atol=1e-9)
    lifted = spin_balance(wheels[0], 0.01, 10.0, 10.0, -5.0, 0.0, 0.0, 0.0)
    assert lifted[1] == 0.0 and lifted[2] == 0.0  # no load, no tyre force or rolling resistance


def test_the_secant_settles_on_a_stable_root_or_gives_none(wheels):
    w = next(w for w in wheels if w.driven)
    v = 10.0
    v_ref = (v**4 + w.v_low**4) ** 0.25
    args = (v, v_ref, 1200.0, 0.5, 60.0, 0.0)
    root, locked = solve_slip(w, *args, False, None)
    assert root is not None and not locked and root > 0.0
    assert abs(spin_balance(w, root, *args)[0]) < 1e-6
    near = _secant(w, root * 1.05, args)
    assert near == pytest.approx(root, rel=1e-9, abs=1e-12)
    assert _secant(w, -root, args) is None  # the other side of zero slip: not reached by secant steps
