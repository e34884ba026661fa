"""The full Magic Formula: hand values of the slip stiffnesses and peaks (from numerical derivatives and
maxima of the evaluated forces, not from the same formula), combined slip reducing to pure slip, odd
symmetry, mirroring, validity ranges, ISO signs, MF 6.1 at zero camber, and the real PAC2002 file."""

import math

import numpy as np
import pytest

from trikedyn.tyre import mf_figures, pac2002, pac2002_arrays, pac2002_pack
from trikedyn.tyre.tir import parse_tir, read_tir


def slope(f, x0, h):
    """Central difference with one Richardson step: error O(h^4)."""
    d1 = (f(x0 + h) - f(x0 - h)) / (2.0 * h)
    d2 = (f(x0 + h / 2) - f(x0 - h / 2)) / h
    return (4.0 * d2 - d1) / 3.0


def fy_at(tir, fz, gamma=0.0, kappa=0.0):
    return lambda a: float(pac2002_arrays.forces(tir, fz, kappa=kappa, alpha=a, gamma=gamma).fy)


def fx_at(tir, fz, alpha=0.0):
    return lambda k: float(pac2002_arrays.forces(tir, fz, kappa=k, alpha=alpha).fx)


def hand_kya(c, fz):
    """Pacejka (2006) 4.E25 at zero camber: PKY1 F'z0 sin(2 atan(Fz / (PKY2 F'z0))) LKY."""
    fz0 = c["FNOMIN"] * c["LFZO"]
    return c["PKY1"] * fz0 * math.sin(2.0 * math.atan(fz / (c["PKY2"] * fz0))) * c["LKY"]


def hand_kxk(c, fz):
    """4.E15: (PKX1 + PKX2 dfz) exp(PKX3 dfz) Fz LKX."""
    dfz = (fz - c["FNOMIN"] * c["LFZO"]) / (c["FNOMIN"] * c["LFZO"])
    return (c["PKX1"] + c["PKX2"] * dfz) * math.exp(c["PKX3"] * dfz) * fz * c["LKX"]


def dfz_of(c, fz):
    return (fz - c["FNOMIN"] * c["LFZO"]) / (c["FNOMIN"] * c["LFZO"])


SCALED = {"LFZO": 1.2, "LKY": 0.8, "LKX": 1.3, "LMUY": 0.9, "LMUX": 1.1, "LCY": 1.05, "LEY": 0.7}


@pytest.fixture
def symmetric_tir(write_tir, symmetric):
    return read_tir(write_tir("sym.tir", **symmetric, **SCALED))


@pytest.fixture
def tir(write_tir):
    return read_tir(write_tir("asym.tir"))


@pytest.fixture
def scaled_tir(write_tir):
    return read_tir(write_tir("scaled.tir", LVY=1.1, LVX=0.9, LHX=1.2, LHY=0.8, LGAY=1.3, LGAZ=0.7, LTR=1.1,
                              LRES=0.9, **SCALED))


def test_cornering_stiffness_at_nominal_load(symmetric_tir):
    c = symmetric_tir.coefficients
    fz = c["FNOMIN"] * c["LFZO"]  # the nominal load F'z0
    expected = c["PKY1"] * c["FNOMIN"] * c["LFZO"] * math.sin(2.0 * math.atan(1.0 / c["PKY2"])) * c["LKY"]
    measured = slope(fy_at(symmetric_tir, fz), 0.0, 1e-4)
    assert measured == pytest.approx(expected, rel=1e-9)
    assert mf_figures.cornering_stiffness(symmetric_tir, fz) == pytest.approx(expected, rel=1e-12)
    assert expected < 0.0  # ISO: a positive slip angle gives a negative side force


@pytest.mark.parametrize("load", [0.3, 1.0, 1.7, 2.5])
@pytest.mark.parametrize("which", ["tir", "scaled_tir"])
def test_slip_stiffnesses_at_several_loads_with_shifts(which, load, request):
    tir = request.getfixturevalue(which)
    c = tir.coefficients
    fz = load * c["FNOMIN"]
    dfz = dfz_of(c, fz)
    shx = (c["PHX1"] + c["PHX2"] * dfz) * c["LHX"]  # slopes at the shifted origins (4.E17), (4.E27)
    assert slope(fx_at(tir, fz), -shx, 1e-5) == pytest.approx(hand_kxk(c, fz), rel=1e-9)
    shy = (c["PHY1"] + c["PHY2"] * dfz) * c["LHY"]
    a0 = math.atan(-shy)  # alpha* = tan(alpha) (4.E3): d alpha*/d alpha = 1 + tan^2
    assert slope(fy_at(tir, fz), a0, 1e-4) / (1.0 + shy * shy) == pytest.approx(hand_kya(c, fz), rel=1e-9)
    assert mf_figures.longitudinal_slip_stiffness(tir, fz) == pytest.approx(hand_kxk(c, fz), rel=1e-12)


def test_scaled_slip_stiffness(symmetric_tir):
    c = symmetric_tir.coefficients
    for fz in (500.0, 2400.0, 4000.0):
        assert slope(fx_at(symmetric_tir, fz), 0.0, 1e-5) == pytest.approx(hand_kxk(c, fz), rel=1e-9)
        assert slope(fy_at(symmetric_tir, fz), 0.0, 1e-4) == pytest.approx(hand_kya(c, fz), rel=1e-9)


@pytest.mark.parametrize("load", [0.3, 1.0, 2.0])
def test_pure_slip_peaks_are_d_plus_sv(tir, symmetric_tir, scaled_tir, load):
    for t in (tir, symmetric_tir, scaled_tir):
        c = t.coefficients
        fz = load * c["FNOMIN"]
        dfz = dfz_of(c, fz)
        dy = (c["PDY1"] + c["PDY2"] * dfz) * c["LMUY"] * fz  # 4.E22, 4.E23
        svy = fz * (c["PVY1"] + c["PVY2"] * dfz) * c["LVY"] * c["LMUY"]  # 4.E29
        dx = (c["PDX1"] + c["PDX2"] * dfz) * c["LMUX"] * fz  # 4.E12, 4.E13
        svx = fz * (c["PVX1"] + c["PVX2"] * dfz) * c["LVX"] * c["LMUX"]  # 4.E18
        peaks = mf_figures.peak_forces(t, fz)
        assert peaks.fy_max_N == pytest.approx(dy + svy, rel=1e-6)
        assert peaks.fy_min_N == pytest.approx(-dy + svy, rel=1e-6)
        assert peaks.fx_max_N == pytest.approx(dx + svx, rel=1e-6)
        assert peaks.fx_min_N == pytest.approx(-dx + svx, rel=1e-6)
        assert peaks.alpha_at_fy_max_rad < 0.0 < peaks.kappa_at_fx_max  # ISO signs
        grid = pac2002_arrays.pure_forces(t, fz, alpha=np.linspace(-1.0, 1.0, 20001)).fy  # an independent search
        assert grid.max() <= peaks.fy_max_N * (1 + 1e-12) and grid.max() == pytest.approx(peaks.fy_max_N, rel=1e-5)


def test_combined_slip_reduces_to_pure_slip(write_tir):
    t = read_tir(write_tir("noshiftx.tir", PHX1=0.0, PHX2=0.0, PVX1=0.0, PVX2=0.0))
    kappa = np.linspace(-0.8, 0.8, 161)
    alpha = np.linspace(-0.6, 0.6, 121)
    for fz in (300.0, 2000.0, 5000.0):
        for gamma in (0.0, 0.05, -0.2):
            comb, pure = pac2002_arrays.forces(t, fz, kappa=kappa, gamma=gamma), pac2002_arrays.pure_forces(t, fz, kappa=kappa,
                                                                                             gamma=gamma)
            np.testing.assert_allclose(comb.fx, pure.fx, rtol=1e-12, atol=0)
            comb, pure = pac2002_arrays.forces(t, fz, alpha=alpha, gamma=gamma), pac2002_arrays.pure_forces(t, fz, alpha=alpha,
                                                                                             gamma=gamma)
            np.testing.assert_allclose(comb.fy, pure.fy, rtol=1e-12, atol=0)
            np.testing.assert_allclose(comb.mz, pure.mz, rtol=1e-12, atol=1e-12)
    # and the weighting functions do act once both slips are there
    both = pac2002_arrays.forces(t, 2000.0, kappa=0.1, alpha=0.1)
    alone = pac2002_arrays.pure_forces(t, 2000.0, kappa=0.1, alpha=0.1)
    assert abs(both.fx) < 0.9 * abs(alone.fx) and abs(both.fy) < 0.95 * abs(alone.fy)


def test_odd_symmetry_without_shifts(symmetric_tir):
    k, a = np.meshgrid(np.linspace(-0.9, 0.9, 37), np.linspace(-0.9, 0.9, 41))
    for fz in (400.0, 2400.0, 5500.0):
        f = pac2002_arrays.forces(symmetric_tir, fz, kappa=k, alpha=a)
        fk, fa = pac2002_arrays.forces(symmetric_tir, fz, kappa=-k, alpha=a), pac2002_arrays.forces(symmetric_tir, fz, kappa=k,
                                                                                     alpha=-a)
        scale = fz * 1e-12
        np.testing.assert_allclose(fk.fx, -f.fx, rtol=1e-12, atol=scale)  # odd in kappa
        np.testing.assert_allclose(fa.fx, f.fx, rtol=1e-12, atol=scale)  # even in alpha
        np.testing.assert_allclose(fa.fy, -f.fy, rtol=1e-12, atol=scale)  # odd in alpha
        np.testing.assert_allclose(fk.fy, f.fy, rtol=1e-12, atol=scale)  # even in kappa
        np.testing.assert_allclose(fa.mz, -f.mz, rtol=1e-12, atol=scale)
        np.testing.assert_allclose(fa.mx, -f.mx, rtol=1e-12, atol=scale)
    zero = pac2002_arrays.forces(symmetric_tir, 2000.0)
    assert (zero.fx, zero.fy, zero.mz) == (0.0, 0.0, 0.0)


def test_mirroring_flips_fy_mx_and_mz(write_tir):
    left = read_tir(write_tir("left.tir", side="LEFT"))
    right = read_tir(write_tir("right.tir", side="RIGHT"))
    k, a, g = np.meshgrid(np.linspace(-0.5, 0.5, 11), np.linspace(-0.4, 0.4, 9), [-0.1, 0.0, 0.07])
    for side in ("left", "right"):
        same, other = (left, right) if side == "left" else (right, left)
        f = pac2002_arrays.forces(same, 2500.0, kappa=k, alpha=a, gamma=g, side=side)  # as measured
        m = pac2002_arrays.forces(other, 2500.0, kappa=k, alpha=-a, gamma=-g, side=side)  # mirrored
        np.testing.assert_allclose(m.fx, f.fx, rtol=1e-13, atol=1e-9)
        np.testing.assert_allclose(m.my, f.my, rtol=1e-13, atol=1e-9)
        for name in ("fy", "mz", "mx"):
            np.testing.assert_allclose(getattr(m, name), -getattr(f, name), rtol=1e-13, atol=1e-9)
    as_measured = pac2002_arrays.forces(right, 2500.0, alpha=0.0)
    mirrored = pac2002_arrays.forces(right, 2500.0, alpha=0.0, side="left")
    assert as_measured.fy != 0.0 and mirrored.fy == pytest.approx(-as_measured.fy)  # the ply steer flips
    symmetric = read_tir(write_tir("sym.tir", side="SYMMETRIC"))
    assert pac2002_arrays.forces(symmetric, 2500.0, side="right").fy == pac2002_arrays.forces(symmetric, 2500.0).fy


def test_validity_ranges_clamp_and_report(tir):
    c = pac2002_pack.pack(tir)
    at_edge = pac2002.mf_forces(2000.0, 1.0, 1.0, 0.3, 15.0, c)
    assert at_edge[5] == 0
    beyond = pac2002.mf_forces(2000.0, 2.0, 1.2, 0.5, 15.0, c)
    assert beyond[:5] == at_edge[:5]
    assert pac2002.clamped_names(beyond[5]) == ["kappa", "alpha", "gamma"]
    low, at_min = pac2002.mf_forces(50.0, 0.1, 0.1, 0.0, 15.0, c), pac2002.mf_forces(100.0, 0.1, 0.1, 0.0, 15.0, c)
    assert low[5] == pac2002.CLAMPED_FZ and np.allclose(low[:5], np.array(at_min[:5]) * 0.5, rtol=1e-14)
    high = pac2002_arrays.forces(tir, 9000.0, kappa=0.1)
    assert pac2002.clamped_names(high.clamped) == ["fz"]
    assert pac2002.mf_forces(0.0, 0.1, 0.1, 0.0, 15.0, c) == (0.0, 0.0, 0.0, 0.0, 0.0, 0)
    assert pac2002.mf_forces(-5.0, 0.1, 0.1, 0.0, 15.0, c)[:5] == (0.0,) * 5
    assert pac2002.mf_vertical_force(0.01, 0.1, c) == pytest.approx(150000.0 * 0.01 + 200.0 * 0.1)
    assert pac2002.mf_vertical_force(-0.01, 0.1, c) == 0.0 and pac2002.mf_vertical_force(0.001, -10.0, c) == 0.0
    assert np.isnan(pac2002.mf_forces(2000.0, math.nan, 0.0, 0.0, 15.0, c)[0])  # NaN propagates


def test_relaxation_lengths_hand_values(tir):
    c = tir.coefficients
    r0 = c["UNLOADED_RADIUS"]
    sk, sa = mf_figures.relaxation_lengths(tir, c["FNOMIN"])
    assert sk == pytest.approx(c["PTX1"] * r0, rel=1e-12)  # dfz = 0: Fz PTX1 R0 / Fz0
    sk, sa = mf_figures.relaxation_lengths(tir, c["PTY2"] * c["FNOMIN"])
    assert sa == pytest.approx(c["PTY1"] * r0, rel=1e-12)  # the peak of sigma_alpha, at Fz = PTY2 F'z0
    sks, sas = mf_figures.relaxation_lengths(tir, [500.0, 2000.0, 4000.0])
    assert np.all(np.diff(sks) > 0) and np.all(sas > 0)


def test_iso_signs_and_rolling_resistance(tir):
    f = pac2002_arrays.forces(tir, 2000.0, kappa=[0.1, -0.1, 0.0, 0.0], alpha=[0.0, 0.0, 0.05, -0.05])
    assert f.fx[0] > 0 > f.fx[1] and f.fy[2] < 0 < f.fy[3] and f.mz[2] > 0 > f.mz[3]
    camber = pac2002_arrays.forces(tir, 2000.0, gamma=0.1)
    assert camber.fy < pac2002_arrays.forces(tir, 2000.0).fy  # top leaning to -y pushes the tyre to -y
    roll = pac2002_arrays.forces(tir, 2000.0, vcx=[15.0, 0.0, -15.0]).my
    c = tir.coefficients
    expected = c["UNLOADED_RADIUS"] * 2000.0 * (c["QSY1"] + c["QSY3"])  # Fx(0) is ~0 and QSY2 = 0
    assert roll[0] == pytest.approx(-expected, rel=1e-12) and roll[1] == 0.0 and roll[2] == pytest.approx(expected)


def test_mf61_equals_pac2002_at_zero_camber(make_tir_text):
    pac = parse_tir(make_tir_text(), "pac.tir")
    extra = "\n[ROLLING_COEFFICIENTS_6]\n"  # an unknown section is kept, not an error
    mf61 = parse_tir(make_tir_text(fmt="MF_61", header_extra=extra.strip())
                     .replace("QSY4                     = 0.0", "QSY4 = 0.0\nQSY7 = 1.0\nPKY6 = -0.9\nPKY7 = -0.2"),
                     "mf61.tir")
    k, a = np.meshgrid(np.linspace(-0.5, 0.5, 21), np.linspace(-0.5, 0.5, 21))
    for fz in (500.0, 2000.0, 4500.0):
        fp, f6 = pac2002_arrays.forces(pac, fz, kappa=k, alpha=a), pac2002_arrays.forces(mf61, fz, kappa=k, alpha=a)
        for name in ("fx", "fy", "mz", "mx", "my"):
            np.testing.assert_allclose(getattr(f6, name), getattr(fp, name), rtol=1e-12, atol=1e-9, err_msg=name)
    thrust = pac2002_arrays.forces(mf61, 2000.0, gamma=[0.0, 0.1]).fy
    assert np.all(np.isfinite(thrust)) and thrust[1] < thrust[0]
    assert np.all(np.isnan(mf_figures.relaxation_lengths(mf61, 2000.0)))  # no carcass stiffnesses in the file
    stiff = parse_tir(make_tir_text(fmt="MF_61", header_extra="LONGITUDINAL_STIFFNESS = 3e5\nLATERAL_STIFFNESS = 1.5e5"),
                      "stiff.tir")
    sk, sa = mf_figures.relaxation_lengths(stiff, 2000.0)  # MF 6.1: sigma = K / C
    assert sk == pytest.approx(hand_kxk(stiff.coefficients, 2000.0) / 3e5) and sa == pytest.approx(
        abs(hand_kya(stiff.coefficients, 2000.0)) / 1.5e5)


def test_evaluation_at_the_real_file(real_tir):
    c = real_tir.coefficients
    fz0 = real_tir.fnomin
    expected = c["PKY1"] * fz0 * math.sin(2.0 * math.atan(1.0 / c["PKY2"]))
    shy = c["PHY1"]
    assert slope(fy_at(real_tir, fz0), math.atan(-shy), 1e-4) / (1 + shy * shy) == pytest.approx(expected, rel=1e-9)
    for fz in (1000.0, 3800.0, 7000.0):
        shx = (c["PHX1"] + c["PHX2"] * dfz_of(c, fz)) * c["LHX"]
        assert slope(fx_at(real_tir, fz), -shx, 1e-5) == pytest.approx(hand_kxk(c, fz), rel=1e-9)
    peaks = mf_figures.peak_forces(real_tir, fz0)
    assert 0.8 < peaks.mu_y < 1.3 and 0.8 < peaks.mu_x < 1.3
    k, a, g = np.meshgrid(np.linspace(-1.5, 1.5, 31), np.radians(np.linspace(-30, 30, 13)), [-0.2, 0.0, 0.2])
    for fz in (190.0, 1000.0, 3800.0, 8550.0):
        f = pac2002_arrays.forces(real_tir, fz, kappa=k, alpha=a, gamma=g)
        for name in ("fx", "fy", "mz", "mx", "my"):
            assert np.all(np.isfinite(getattr(f, name))), name
        # bounded, sensible magnitudes (the fit's combined slip with camber thrust reaches |F| = 1.32 Fz at 190 N)
        assert np.all(np.hypot(f.fx, f.fy) < 1.5 * fz) and np.all(np.abs(f.mz) < 0.1 * fz)
    f = pac2002_arrays.forces(real_tir, fz0, kappa=[0.1, 0.0], alpha=[0.0, math.radians(4)])
    assert f.fx[0] > 0.8 * fz0 and f.fy[1] < -0.5 * fz0 and f.mz[1] > 0


def reference_pure(c, fz, kappa, alpha, gamma):
    """PAC2002 pure slip written out once more, plainly, from Pacejka (2006) 4.E1-4.E49 (Vcx > 0)."""
    fz0 = c["FNOMIN"] * c["LFZO"]
    dfz = (fz - fz0) / fz0
    a, g = math.tan(alpha), math.sin(gamma)
    sgn = lambda x: (x > 0) - (x < 0)  # noqa: E731
    mf = lambda b, cc, d, e, x: d * math.sin(cc * math.atan(b * x - e * (b * x - math.atan(b * x))))  # noqa: E731
    gx = g * c["LGAX"]
    kx = fz * (c["PKX1"] + c["PKX2"] * dfz) * math.exp(c["PKX3"] * dfz) * c["LKX"]
    dx = (c["PDX1"] + c["PDX2"] * dfz) * (1 - c["PDX3"] * gx ** 2) * c["LMUX"] * fz
    kxs = kappa + (c["PHX1"] + c["PHX2"] * dfz) * c["LHX"]
    ex = min((c["PEX1"] + c["PEX2"] * dfz + c["PEX3"] * dfz ** 2) * (1 - c["PEX4"] * sgn(kxs)) * c["LEX"], 1)
    cx = c["PCX1"] * c["LCX"]
    fx0 = mf(kx / (cx * dx), cx, dx, ex, kxs) + fz * (c["PVX1"] + c["PVX2"] * dfz) * c["LVX"] * c["LMUX"]
    gy = g * c["LGAY"]
    cy = c["PCY1"] * c["LCY"]
    dy = (c["PDY1"] + c["PDY2"] * dfz) * (1 - c["PDY3"] * gy ** 2) * c["LMUY"] * fz
    ky = c["PKY1"] * fz0 * math.sin(2 * math.atan(fz / (c["PKY2"] * fz0))) * (1 - c["PKY3"] * abs(gy)) * c["LKY"]
    shy = (c["PHY1"] + c["PHY2"] * dfz) * c["LHY"] + c["PHY3"] * gy
    svy = fz * ((c["PVY1"] + c["PVY2"] * dfz) * c["LVY"] + (c["PVY3"] + c["PVY4"] * dfz) * gy) * c["LMUY"]
    ay = a + shy
    ey = min((c["PEY1"] + c["PEY2"] * dfz) * (1 - (c["PEY3"] + c["PEY4"] * gy) * sgn(ay)) * c["LEY"], 1)
    by = ky / (cy * dy)
    fy0 = mf(by, cy, dy, ey, ay) + svy
    gz = g * c["LGAZ"]
    at = a + c["QHZ1"] + c["QHZ2"] * dfz + (c["QHZ3"] + c["QHZ4"] * dfz) * gz
    bt = ((c["QBZ1"] + c["QBZ2"] * dfz + c["QBZ3"] * dfz ** 2) * (1 + c["QBZ4"] * gz + c["QBZ5"] * abs(gz))
          * c["LKY"] / c["LMUY"])
    ct, r0 = c["QCZ1"], c["UNLOADED_RADIUS"]
    dt = fz * (c["QDZ1"] + c["QDZ2"] * dfz) * (1 + c["QDZ3"] * gz + c["QDZ4"] * gz ** 2) * r0 / fz0 * c["LTR"]
    et = min((c["QEZ1"] + c["QEZ2"] * dfz + c["QEZ3"] * dfz ** 2)
             * (1 + (c["QEZ4"] + c["QEZ5"] * gz) * 2 / math.pi * math.atan(bt * ct * at)), 1)
    t = dt * math.cos(ct * math.atan(bt * at - et * (bt * at - math.atan(bt * at)))) * math.cos(alpha)
    ar = a + shy + svy / ky
    br = c["QBZ9"] * c["LKY"] / c["LMUY"] + c["QBZ10"] * by * cy
    dr = fz * r0 * ((c["QDZ6"] + c["QDZ7"] * dfz) * c["LRES"] + (c["QDZ8"] + c["QDZ9"] * dfz) * gz) * c["LMUY"]
    mz0 = -t * fy0 + dr * math.cos(math.atan(br * ar)) * math.cos(alpha)
    return fx0, fy0, mz0


@pytest.mark.parametrize("which", ["tir", "scaled_tir"])
def test_pure_slip_against_a_plain_rewrite_of_the_equations(which, request):
    t = request.getfixturevalue(which)
    for fz in (300.0, 2000.0, 4500.0):
        for kappa, alpha, gamma in ((0.05, 0.03, 0.0), (-0.3, -0.2, 0.1), (0.6, 0.5, -0.25), (-0.01, 0.001, 0.3)):
            got = pac2002_arrays.pure_forces(t, fz, kappa=kappa, alpha=alpha, gamma=gamma)
            want = reference_pure(t.coefficients, fz, kappa, alpha, gamma)
            assert [float(got.fx), float(got.fy), float(got.mz)] == pytest.approx(want, rel=1e-9, abs=1e-9)
