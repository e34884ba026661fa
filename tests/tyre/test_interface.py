"""The tyre interface the compiled loop calls: the functions checked here are the ones the loop runs."""

import math

import numpy as np
import pytest

from trikedyn import tyre as mf
from trikedyn.model.packing import ROAD, VEHICLE, WHEEL, WHEEL_OUT
from trikedyn.tyre import pac2002, pac2002_pack
from trikedyn.tyre.contact import slip_rates
from trikedyn.tyre.interface import (
    COEFFS_WIDTH,
    MAGIC_FORMULA,
    SIMILARITY,
    linear_stiffnesses,
    tyre_forces,
    vertical_force,
    wheel_wrench,
)


@pytest.fixture(scope="module")
def similarity_row(reference):
    row = np.zeros(COEFFS_WIDTH)
    row[: mf.N_COEFFS] = mf.tyre_coefficients(reference.params.tyre)
    return row


def _wheel(kz=200e3, cz=75.0, model=SIMILARITY, sigma=0.3):
    w = np.zeros(1, WHEEL)
    w[0]["radius"] = 0.3
    w[0]["vertical_stiffness"] = kz
    w[0]["vertical_damping"] = cz
    w[0]["relaxation_x"] = sigma
    w[0]["relaxation_y"] = sigma
    w[0]["tyre_model"] = model
    return w


def _vehicle():
    v = np.zeros(1, VEHICLE)
    v[0]["v_low"] = 1.0
    v[0]["w_low"] = 1.0
    v[0]["slip_forces"] = 1.0
    return v


def test_vertical_force_is_the_similarity_models(similarity_row):
    w = _wheel(kz=similarity_row[mf.KZ], cz=similarity_row[mf.CZ])
    for d, rate in [(0.0, 1.0), (-0.01, 0.0), (0.01, 0.2), (0.02, -5.0), (0.005, -100.0)]:
        assert vertical_force(d, rate, w[0]) == mf.vertical_force(d, rate, similarity_row)


@pytest.mark.parametrize(("vx", "vy", "omega"), [(10.0, 0.3, 10.5 / 0.29), (-4.0, 0.2, -4.1 / 0.29), (0.3, 0.05, 0.0)])
def test_transient_slips_settle_on_the_steady_slips(vx, vy, omega):
    r, v_low = 0.29, 1.0
    kappa, alpha = mf.slip_quantities(vx, vy, omega, r, v_low)
    dk, da, v_ref = slip_rates(kappa, math.tan(alpha), vx, vy, omega, r, v_low, 0.3, 0.2)
    assert abs(dk) < 1e-12 and abs(da) < 1e-12
    assert v_ref == pytest.approx((vx**4 + v_low**4) ** 0.25)


def test_similarity_forces_are_the_magic_formula_modules(similarity_row):
    c = similarity_row
    for kappa, alpha, fz in [(0.02, 0.0, 1500.0), (-0.05, 0.04, 900.0), (0.0, -0.1, 2000.0)]:
        fx, fy, mz, mx, my, clamped = tyre_forces(SIMILARITY, c, kappa, alpha, 0.02, fz, 10.0, 10.0, 30.0, 0.29, 1.0, 1.0)
        assert (fx, fy) == mf.combined_forces(kappa, alpha, fz, c)
        assert my == mf.rolling_resistance_moment(fz, 30.0, 0.29, c, 1.0)
        assert mz == mx == clamped == 0.0


def test_full_magic_formula_takes_the_iso_slip_angle(real_tir):
    c = np.zeros(COEFFS_WIDTH)
    c[: pac2002.N_PACKED] = pac2002_pack.pack(real_tir)
    for kappa, alpha, gamma in [(0.0, 0.05, 0.0), (0.03, -0.04, 0.02), (-0.1, 0.1, -0.03)]:
        ours = tyre_forces(MAGIC_FORMULA, c, kappa, alpha, gamma, 3000.0, 15.0, 15.0, 50.0, 0.3, 1.0, 1.0)
        iso = pac2002.mf_forces(3000.0, kappa, -alpha, gamma, 15.0, c[: pac2002.N_PACKED])
        assert ours[:4] == pytest.approx(iso[:4], rel=1e-14, abs=1e-9)
        assert ours[4] == pytest.approx(iso[4] * math.tanh(50.0), rel=1e-14)  # rolling resistance, smoothed
        assert ours[4] < 0  # against the forward spin
    # trikedyn's sign: a wheel sliding left (alpha < 0) is pushed right, and the moment turns it left, toward
    # its velocity (the lateral force acts behind the contact centre, at the pneumatic trail)
    fx, fy, mz, *_ = tyre_forces(MAGIC_FORMULA, c, 0.0, -0.05, 0.0, 3000.0, 15.0, 15.0, 50.0, 0.3, 1.0, 1.0)
    assert fy < 0 and mz > 0
    # the cornering stiffness in trikedyn's sign is positive, and is the file's
    kx, ca = linear_stiffnesses(MAGIC_FORMULA, c, 3000.0)
    assert ca > 0 and kx > 0
    assert ca == pytest.approx(-pac2002.mf_stiffness(3000.0, 0.0, c[: pac2002.N_PACKED])[1], rel=1e-15)


def _upright_wheel(height, spin=0.0, vx=0.0, vy=0.0):
    e = np.eye(3)  # the wheel's axes are the world's: spin axis along +y
    vb = np.array([0.0, spin, 0.0, vx, vy, 0.0])
    return e, 0.0, 0.0, height, vb


@pytest.mark.parametrize("model", [SIMILARITY, MAGIC_FORMULA])
def test_wheel_wrench_at_rest_is_the_vertical_spring(model, similarity_row, real_tir):
    c = similarity_row.copy()
    if model == MAGIC_FORMULA:
        c[: pac2002.N_PACKED] = pac2002_pack.pack(real_tir)
    w = _wheel(model=model)
    road = np.zeros(1, ROAD)
    out = np.zeros(1, WHEEL_OUT)
    e, cx, cy, cz, vb = _upright_wheel(0.29)
    fwx, fwy, fwz, mwx, mwy, mwz, dk, da = wheel_wrench(w[0], c, _vehicle()[0], road[0], e, cx, cy, cz, vb, 0.0,
                                                        0.0, out[0])
    assert fwz == pytest.approx(200e3 * 0.01, rel=1e-12)
    assert out[0]["deflection"] == pytest.approx(0.01, rel=1e-12) and out[0]["camber"] == 0.0
    if model == SIMILARITY:
        assert abs(fwx) < 1e-9 and abs(fwy) < 1e-9 and abs(mwz) < 1e-9 and dk == 0.0 and da == 0.0


def test_aligning_moment_reaches_the_wheel(real_tir):
    """A slip angle gives an aligning moment about the road normal on the wheel: the steering feels it."""
    c = np.zeros(COEFFS_WIDTH)
    c[: pac2002.N_PACKED] = pac2002_pack.pack(real_tir)
    w = _wheel(model=MAGIC_FORMULA)
    out = np.zeros(1, WHEEL_OUT)
    e, cx, cy, cz, vb = _upright_wheel(0.29, spin=10.0 / 0.297, vx=10.0, vy=0.5)
    tan_alpha = -0.05  # a wheel sliding to the left, in trikedyn's sign
    fwx, fwy, fwz, mwx, mwy, mwz, _, _ = wheel_wrench(w[0], c, _vehicle()[0], np.zeros(1, ROAD)[0], e, cx, cy, cz,
                                                      vb, 0.0, tan_alpha, out[0])
    # moment about the centre = r x F + Mz n (+ Mx, My about the tyre's x and the axle)
    r = np.array([0.0, 0.0, -0.3])
    moment = np.array([mwx, mwy, mwz]) - np.cross(r, [fwx, fwy, fwz])
    assert out[0]["mz"] != 0.0 and moment[2] == pytest.approx(out[0]["mz"], rel=1e-12)
    assert out[0]["mz"] > 0  # turns the wheel left, toward its velocity: self-aligning


def test_full_magic_formula_carries_no_zero_slip_force_at_rest(real_tir):
    """Its offsets (ply steer, conicity, residual torque) and camber thrust fade out below v_low: at rest a
    tyre carries only what slip causes, so that a vehicle can stand; from v_low on they are whole."""
    c = np.zeros(COEFFS_WIDTH)
    c[: pac2002.N_PACKED] = pac2002_pack.pack(real_tir)
    at_rest = tyre_forces(MAGIC_FORMULA, c, 0.0, 0.0, 0.03, 3000.0, 0.0, 1.0, 0.0, 0.3, 1.0, 1.0)
    assert at_rest[:5] == (0.0, 0.0, 0.0, 0.0, 0.0)
    rolling = tyre_forces(MAGIC_FORMULA, c, 0.0, 0.0, 0.03, 3000.0, 1.0, 1.0, 3.3, 0.3, 1.0, 1.0)
    iso = pac2002.mf_forces(3000.0, 0.0, 0.0, 0.03, 1.0, c[: pac2002.N_PACKED])
    assert rolling[:4] == pytest.approx(iso[:4], rel=1e-14) and abs(rolling[1]) > 10.0
    halfway = tyre_forces(MAGIC_FORMULA, c, 0.0, 0.0, 0.03, 3000.0, 0.5, 1.0, 1.7, 0.3, 1.0, 1.0)
    assert halfway[1] == pytest.approx(0.5 * iso[1], rel=1e-12)


def test_a_file_without_relaxation_data_falls_back_to_the_tyre_section(real_tir, reference, tmp_path):
    """No PTX / PTY: no relaxation lengths (NaN, no division by zero); the vehicle uses its [tyre] lengths."""
    from trikedyn.tyre.interface import tyre_setup

    text = "\n".join(line for line in open(real_tir.path).read().splitlines()
                     if not line.startswith(("PTX", "PTY")))
    path = tmp_path / "no_relaxation.tir"
    path.write_text(text)
    from trikedyn.tyre.tir import read_tir

    c = pac2002_pack.pack(read_tir(path))
    with np.errstate(all="raise"):
        sk, sa = pac2002.mf_relaxation_lengths(2000.0, 0.0, c)
    assert math.isnan(sk) and math.isnan(sa)
    wheel = reference.params.wheel("front").model_copy(update={"tyre_file": str(path)})
    setup = tyre_setup(reference.params, wheel, 2000.0)
    assert setup.model == MAGIC_FORMULA
    assert setup.relaxation_x_m == reference.params.tyre.relaxation_length_x_m
    assert setup.relaxation_y_m == reference.params.tyre.relaxation_length_y_m
