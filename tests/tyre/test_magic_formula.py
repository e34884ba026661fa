"""The verification ladder's tyre rung: peak force, slope at zero slip, odd symmetry, friction ellipse.

Every check runs on the reference e-trike's tyre and on a made-up tyre with other shape, curvature and
load-sensitivity values (curvatures of both signs, C near both ends of its range).
"""

import math

import numba
import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from trikedyn.errors import ParameterError
from trikedyn.params.schema import TyreSpec
from trikedyn.tyre import magic_formula as mf

MADE_UP = TyreSpec(
    vertical_stiffness_N_per_m=150e3,
    vertical_damping_Ns_per_m=300.0,
    nominal_load_N=3000.0,
    mu_x=1.1,
    mu_y=1.0,
    load_sensitivity=-0.25,
    shape_x=1.9,
    shape_y=1.15,
    curvature_x=0.6,
    curvature_y=-1.5,
    slip_stiffness_factor=22.0,
    cornering_stiffness_factor=18.0,
    cornering_stiffness_load_factor=1.5,
    rolling_resistance=0.02,
    relaxation_length_x_m=0.2,
    relaxation_length_y_m=0.4,
)


@pytest.fixture(scope="module", params=["reference", "made_up"])
def tyre(request):
    if request.param == "reference":
        from trikedyn.params import load_vehicle

        spec = load_vehicle("reference-etrike").params.tyre
    else:
        spec = MADE_UP
    return spec, mf.tyre_coefficients(spec)


def _loads(spec):
    return spec.nominal_load_N * np.array([0.2, 0.6, 1.0, 1.7, 2.5])


# ---- coefficient vector --------------------------------------------------------------------------------
def test_coefficient_vector_layout(tyre):
    spec, c = tyre
    assert c.dtype == np.float64 and c.shape == (mf.N_COEFFS,)
    indices = [
        getattr(mf, n)
        for n in mf.__all__
        if n.isupper() and n not in ("N_COEFFS", "MU_FLOOR_FRACTION", "RHO_LINEAR")
    ]
    assert sorted(indices) == list(range(mf.N_COEFFS))
    assert c[mf.KZ] == spec.vertical_stiffness_N_per_m and c[mf.CZ] == spec.vertical_damping_Ns_per_m
    assert c[mf.FZ0] == spec.nominal_load_N and c[mf.LOAD_SENSITIVITY] == spec.load_sensitivity
    assert (c[mf.MU_X], c[mf.MU_Y]) == (spec.mu_x, spec.mu_y)
    assert (c[mf.SHAPE_X], c[mf.SHAPE_Y], c[mf.CURVATURE_X], c[mf.CURVATURE_Y]) == (
        spec.shape_x,
        spec.shape_y,
        spec.curvature_x,
        spec.curvature_y,
    )
    assert c[mf.SLIP_STIFFNESS_FACTOR] == spec.slip_stiffness_factor
    assert c[mf.CORNERING_STIFFNESS_FACTOR] == spec.cornering_stiffness_factor
    assert c[mf.CORNERING_STIFFNESS_LOAD_FACTOR] == spec.cornering_stiffness_load_factor
    assert c[mf.ROLLING_RESISTANCE] == spec.rolling_resistance
    for u_index, cc, ee in (
        (mf.U_PEAK_X, spec.shape_x, spec.curvature_x),
        (mf.U_PEAK_Y, spec.shape_y, spec.curvature_y),
    ):
        u = c[u_index]  # the peak input solves C atan(u - E (u - atan u)) = pi/2
        assert cc * math.atan(u - ee * (u - math.atan(u))) == pytest.approx(math.pi / 2, rel=1e-14)


def test_peak_input_hand_values():
    assert mf.peak_input(2.0, 0.0) == pytest.approx(1.0, rel=1e-15)  # tan(pi/4)
    assert mf.peak_input(1.5, 0.0) == pytest.approx(math.tan(math.pi / 3), rel=1e-14)
    assert mf.peak_input(1.9, 1.0) == pytest.approx(math.tan(math.tan(math.pi / 3.8)), rel=1e-14)


def test_curve_that_never_peaks_is_refused():
    spec = MADE_UP.model_copy(update={"curvature_y": 1.0, "shape_y": 1.3})
    with pytest.raises(ParameterError, match="tyre.curvature_y"):
        mf.tyre_coefficients(spec)


# ---- pure slip ------------------------------------------------------------------------------------------
def _numerical_peak(f, x_hi):
    grid = np.linspace(0.0, x_hi, 4001)
    values = np.array([f(x) for x in grid])
    i = int(np.argmax(values))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    res = minimize_scalar(lambda x: -f(x), bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
    return max(-res.fun, values[i])


def test_peak_force_is_mu_fz(tyre):
    _, c = tyre
    for fz in _loads(tyre[0]):
        mu_x, mu_y = mf.peak_friction(fz, c)
        fx_peak = _numerical_peak(lambda k, fz=fz: mf.pure_longitudinal(k, fz, c), 2.0)
        fy_peak = _numerical_peak(lambda a, fz=fz: mf.pure_lateral(a, fz, c), 1.5)
        assert fx_peak == pytest.approx(mu_x * fz, rel=1e-3)
        assert fy_peak == pytest.approx(mu_y * fz, rel=1e-3)
        assert fx_peak <= mu_x * fz * (1 + 1e-12) and fy_peak <= mu_y * fz * (1 + 1e-12)


def test_slope_at_zero_slip_is_the_stiffness(tyre):
    _, c = tyre
    h = 1e-6
    for fz in _loads(tyre[0]):
        kx = (mf.pure_longitudinal(h, fz, c) - mf.pure_longitudinal(-h, fz, c)) / (2 * h)
        ky = (mf.pure_lateral(h, fz, c) - mf.pure_lateral(-h, fz, c)) / (2 * h)
        assert kx == pytest.approx(c[mf.SLIP_STIFFNESS_FACTOR] * fz, rel=1e-3)
        assert kx == pytest.approx(mf.slip_stiffness(fz, c), rel=1e-3)
        fz0, pky2 = c[mf.FZ0], c[mf.CORNERING_STIFFNESS_LOAD_FACTOR]
        c_alpha = c[mf.CORNERING_STIFFNESS_FACTOR] * fz0 * math.sin(2 * math.atan(fz / (pky2 * fz0)))
        assert ky == pytest.approx(c_alpha, rel=1e-3)
        assert mf.cornering_stiffness(fz, c) == pytest.approx(c_alpha, rel=1e-14)


def test_cornering_stiffness_peaks_at_load_factor_times_fz0(tyre):
    _, c = tyre
    fz0, pky2 = c[mf.FZ0], c[mf.CORNERING_STIFFNESS_LOAD_FACTOR]
    res = minimize_scalar(
        lambda fz: -mf.cornering_stiffness(fz, c),
        bounds=(0.1 * fz0, 10 * fz0),
        method="bounded",
        options={"xatol": 1e-6},
    )
    assert res.x == pytest.approx(pky2 * fz0, rel=1e-3)
    assert -res.fun == pytest.approx(c[mf.CORNERING_STIFFNESS_FACTOR] * fz0, rel=1e-12)
    # and the slope of the force curve itself peaks there
    h = 1e-7
    slope = [
        (mf.pure_lateral(h, fz, c) - mf.pure_lateral(-h, fz, c)) / (2 * h)
        for fz in pky2 * fz0 * np.array([0.9, 1.0, 1.1])
    ]
    assert slope[1] > slope[0] and slope[1] > slope[2]


def test_pure_slip_is_exactly_odd(tyre):
    _, c = tyre
    xs = np.concatenate([np.geomspace(1e-12, 50.0, 200), [0.0, 0.3, 0.7, 1.0, 1.5]])
    for fz in _loads(tyre[0]):
        for x in xs:
            assert mf.pure_longitudinal(-x, fz, c) == -mf.pure_longitudinal(x, fz, c)
            assert mf.pure_lateral(-x, fz, c) == -mf.pure_lateral(x, fz, c)


def test_pure_slip_sign_and_no_force_without_load(tyre):
    _, c = tyre
    assert mf.pure_longitudinal(0.05, 1000.0, c) > 0 and mf.pure_lateral(0.05, 1000.0, c) > 0
    for fz in (0.0, -10.0):
        assert mf.pure_longitudinal(0.1, fz, c) == 0.0 and mf.pure_lateral(0.1, fz, c) == 0.0
        assert mf.combined_forces(0.1, 0.1, fz, c) == (0.0, 0.0)
    # the force vanishes smoothly with the load (no 0/0 at tiny loads)
    for fz in (1e-9, 1e-3):
        assert 0 < mf.pure_lateral(0.1, fz, c) <= c[mf.MU_Y] * 2 * fz


def test_load_sensitivity():
    c = mf.tyre_coefficients(MADE_UP)
    loads = MADE_UP.nominal_load_N * np.linspace(0.2, 2.5, 12)
    mu = np.array([mf.peak_friction(fz, c) for fz in loads])
    assert np.all(np.diff(mu[:, 0]) < 0) and np.all(np.diff(mu[:, 1]) < 0)
    assert mf.peak_friction(MADE_UP.nominal_load_N, c) == (MADE_UP.mu_x, MADE_UP.mu_y)
    fz = 1.4 * MADE_UP.nominal_load_N
    assert mf.peak_friction(fz, c)[0] == pytest.approx(MADE_UP.mu_x * (1 - 0.25 * 0.4), rel=1e-14)
    # peak force over load falls too
    peaks = [_numerical_peak(lambda a, f=f: mf.pure_lateral(a, f, c), 1.5) / f for f in loads[::4]]
    assert peaks[0] > peaks[1] > peaks[2]
    # floored at a small positive value, never zero or negative
    c_hard = c.copy()
    c_hard[mf.LOAD_SENSITIVITY] = -1.0
    for fz in (2.0, 3.0, 100.0):
        mu_x, mu_y = mf.peak_friction(fz * MADE_UP.nominal_load_N, c_hard)
        assert mu_x == pytest.approx(mf.MU_FLOOR_FRACTION * MADE_UP.mu_x) and mu_y > 0
        assert mf.pure_lateral(0.2, fz * MADE_UP.nominal_load_N, c_hard) > 0
    # positive sensitivity: mu rises with load
    c_up = c.copy()
    c_up[mf.LOAD_SENSITIVITY] = 0.2
    assert mf.peak_friction(2000.0, c_up)[0] < mf.peak_friction(4000.0, c_up)[0]


# ---- combined slip --------------------------------------------------------------------------------------
KAPPAS = np.linspace(-1.0, 1.0, 41)
ALPHAS = np.linspace(-0.5, 0.5, 41)


def test_combined_force_within_friction_ellipse(tyre):
    _, c = tyre
    for fz in _loads(tyre[0]):
        mu_x, mu_y = mf.peak_friction(fz, c)
        worst = 0.0
        for k in KAPPAS:
            for a in ALPHAS:
                fx, fy = mf.combined_forces(k, a, fz, c)
                assert math.isfinite(fx) and math.isfinite(fy)
                worst = max(worst, (fx / (mu_x * fz)) ** 2 + (fy / (mu_y * fz)) ** 2)
        assert worst <= 1 + 1e-9
        assert worst > 0.9  # the grid reaches well into saturation


def test_combined_reaches_the_ellipse_at_the_peak_slips(tyre):
    """With both slips at the same fraction of their peak slips (rho = 1) the force lies on the ellipse."""
    _, c = tyre
    fz = c[mf.FZ0]
    mu_x, mu_y = mf.peak_friction(fz, c)
    bx = c[mf.SLIP_STIFFNESS_FACTOR] / (c[mf.SHAPE_X] * mu_x)
    by = mf.cornering_stiffness(fz, c) / (c[mf.SHAPE_Y] * mu_y * fz)
    k_peak, a_peak = c[mf.U_PEAK_X] / bx, c[mf.U_PEAK_Y] / by
    for theta in np.linspace(0, 2 * math.pi, 13):
        fx, fy = mf.combined_forces(k_peak * math.cos(theta), a_peak * math.sin(theta), fz, c)
        assert (fx / (mu_x * fz)) ** 2 + (fy / (mu_y * fz)) ** 2 == pytest.approx(1.0, rel=1e-12)


def test_combined_reduces_to_pure_slip(tyre):
    _, c = tyre
    ks = np.concatenate([KAPPAS, np.geomspace(1e-14, 5.0, 60), -np.geomspace(1e-14, 5.0, 60)])
    als = np.concatenate([ALPHAS, np.geomspace(1e-14, 1.5, 60), -np.geomspace(1e-14, 1.5, 60)])
    for fz in _loads(tyre[0]):
        for k in ks:
            fx, fy = mf.combined_forces(k, 0.0, fz, c)
            assert fx == pytest.approx(mf.pure_longitudinal(k, fz, c), rel=1e-12, abs=0.0) and fy == 0.0
        for a in als:
            fx, fy = mf.combined_forces(0.0, a, fz, c)
            assert fy == pytest.approx(mf.pure_lateral(a, fz, c), rel=1e-12, abs=0.0) and fx == 0.0


def test_combined_symmetry(tyre):
    _, c = tyre
    fz = 1.2 * c[mf.FZ0]
    for k in KAPPAS:
        for a in ALPHAS:
            fx, fy = mf.combined_forces(k, a, fz, c)
            fx_m, fy_m = mf.combined_forces(k, -a, fz, c)
            assert fy_m == -fy and fx_m == fx
            fx_k, fy_k = mf.combined_forces(-k, a, fz, c)
            assert fx_k == -fx and fy_k == fy


def test_combined_well_defined_and_smooth_at_zero_slip(tyre):
    _, c = tyre
    fz = c[mf.FZ0]
    assert mf.combined_forces(0.0, 0.0, fz, c) == (0.0, 0.0)
    # linear with the exact stiffnesses at small slip, in any direction
    kx, ky = mf.slip_stiffness(fz, c), mf.cornering_stiffness(fz, c)
    for scale in (1e-20, 1e-12, 1e-9, 1e-8, 1e-7):
        for theta in np.linspace(0, 2 * math.pi, 9):
            k, a = scale * math.cos(theta), scale * math.sin(theta)
            fx, fy = mf.combined_forces(k, a, fz, c)
            assert fx == pytest.approx(kx * k, rel=1e-9, abs=1e-300)
            assert fy == pytest.approx(ky * a, rel=1e-9, abs=1e-300)
    # no jump across the switch to the zero-slip limit: force / slip continuous along a ray
    mu_x, _ = mf.peak_friction(fz, c)
    bx = c[mf.SLIP_STIFFNESS_FACTOR] / (c[mf.SHAPE_X] * mu_x)
    k_switch = mf.RHO_LINEAR * c[mf.U_PEAK_X] / bx
    ratio = [
        mf.combined_forces(s * k_switch, 0.3 * s * k_switch, fz, c)[0] / (s * k_switch)
        for s in (1 - 1e-6, 1 + 1e-6)
    ]
    assert ratio[0] == pytest.approx(ratio[1], rel=1e-12)
    # smooth further out: second differences along kappa at fixed alpha are small and regular
    ks = np.linspace(-0.05, 0.05, 2001)
    fx = np.array([mf.combined_forces(k, 0.02, fz, c)[0] for k in ks])
    d2 = np.diff(fx, 2)
    assert np.all(np.isfinite(fx)) and np.max(np.abs(np.diff(d2))) < 1e-3 * np.max(np.abs(fx))


def test_combined_slip_reduces_the_other_force(tyre):
    _, c = tyre
    fz = c[mf.FZ0]
    fy_pure = mf.pure_lateral(0.05, fz, c)
    fy = [mf.combined_forces(k, 0.05, fz, c)[1] for k in (0.0, 0.02, 0.05, 0.1, 0.3)]
    assert fy[0] == pytest.approx(fy_pure, rel=1e-12) and np.all(np.diff(fy) < 0)


# ---- vertical force ------------------------------------------------------------------------------------
def test_vertical_force(tyre):
    _, c = tyre
    kz, cz = c[mf.KZ], c[mf.CZ]
    for rate in (-5.0, 0.0, 5.0):  # out of contact: nothing, whatever the rate
        for d in (0.0, -1e-9, -0.01):
            assert mf.vertical_force(d, rate, c) == 0.0
    ds = np.linspace(1e-4, 0.05, 50)
    f = np.array([mf.vertical_force(d, 0.0, c) for d in ds])
    np.testing.assert_allclose(f, kz * ds, rtol=1e-15)  # linear in d
    assert mf.vertical_force(0.01, 0.2, c) == pytest.approx(kz * 0.01 + cz * 0.2, rel=1e-15)
    # a fast rebound in contact would pull: it gives zero instead
    d = 1e-3
    assert kz * d + cz * (-2 * kz * d / max(cz, 1.0)) < 0
    assert mf.vertical_force(d, -2 * kz * d / max(cz, 1.0), c) == 0.0
    for d in np.linspace(-0.01, 0.05, 31):
        for rate in np.linspace(-50, 50, 21):
            assert mf.vertical_force(d, rate, c) >= 0.0


# ---- slips ------------------------------------------------------------------------------------------------
def test_slip_definitions_at_speed():
    r, v_low = 0.27, 1.0
    vx = 15.0
    kappa, alpha = mf.slip_quantities(vx, 0.0, 1.02 * vx / r, r, v_low)
    assert kappa == pytest.approx(0.02, rel=1e-4) and alpha == 0.0
    kappa, _ = mf.slip_quantities(vx, 0.0, 0.0, r, v_low)  # locked wheel
    assert kappa == pytest.approx(-1.0, rel=1e-4)
    kappa, alpha = mf.slip_quantities(vx, 1.0, vx / r, r, v_low)  # sliding to the left
    assert kappa == pytest.approx(0.0, abs=1e-14)
    assert alpha == pytest.approx(-math.atan(1.0 / vx), rel=1e-4) and alpha < 0
    kappa, alpha = mf.slip_quantities(-vx, 1.0, -0.98 * vx / r, r, v_low)  # reversing, braking
    assert kappa == pytest.approx(0.02, rel=1e-4) and alpha < 0
    # relative error of the regularisation: (v_low / vx)^4 / 4
    k_exact = 0.1
    kappa, _ = mf.slip_quantities(10.0, 0.0, 11.0 / r, r, 1.0)
    assert kappa / k_exact - 1 == pytest.approx(-0.25e-4, rel=1e-2)


def test_sign_convention_of_forces():
    c = mf.tyre_coefficients(MADE_UP)
    r, d = 0.3, 0.02
    fx, fy, fz, my = mf.tyre_forces(d, 0.0, 10.0, 0.0, 10.5 / r, r, c, 1.0, 1.0)  # driving
    assert fx > 0 and fy == 0.0 and fz == pytest.approx(MADE_UP.vertical_stiffness_N_per_m * d) and my < 0
    fx, fy, fz, my = mf.tyre_forces(d, 0.0, 10.0, 0.0, 9.5 / r, r, c, 1.0, 1.0)  # braking
    assert fx < 0
    fx, fy, fz, my = mf.tyre_forces(d, 0.0, 10.0, 0.5, 10.0 / r, r, c, 1.0, 1.0)  # sliding left
    assert fy < 0 and abs(fx) < 1e-9 * fz
    fx, fy, fz, my = mf.tyre_forces(d, 0.0, -10.0, 0.5, -10.0 / r, r, c, 1.0, 1.0)  # reversing, left
    assert fy < 0 and my > 0


def test_slips_bounded_and_smooth_at_low_speed():
    r, v_low = 0.27, 1.0
    assert mf.slip_quantities(0.0, 0.0, 0.0, r, v_low) == (0.0, 0.0)
    assert mf.slip_quantities(0.0, 0.0, 0.0, r, 0.0) == (0.0, 0.0)  # v_low = 0 at rest: no NaN
    vs = np.linspace(-3.0, 3.0, 6001)
    for vy, omega in ((0.0, 0.0), (0.3, 0.0), (-0.2, 2.0), (0.5, -3.0)):
        slips = np.array([mf.slip_quantities(v, vy, omega, r, v_low) for v in vs])
        assert np.all(np.isfinite(slips))
        assert np.all(np.abs(slips[:, 1]) < math.pi / 2)
        assert np.max(np.abs(slips[:, 0])) <= (abs(omega) * r + 3.0) / v_low
        step = vs[1] - vs[0]
        d1 = np.diff(slips, axis=0) / step
        assert np.all(np.abs(d1) < 10.0 / v_low)  # bounded derivative: no jump
        d2 = np.diff(d1, axis=0) / step
        assert np.all(np.abs(d2) < 50.0 / v_low**2)  # and no kink
    # the tyre becomes a viscous damper through zero speed: the forces are finite and odd in vy
    c = mf.tyre_coefficients(MADE_UP)
    f_pos = mf.tyre_forces(0.02, 0.0, 0.0, 0.1, 0.0, r, c, v_low, 1.0)
    f_neg = mf.tyre_forces(0.02, 0.0, 0.0, -0.1, 0.0, r, c, v_low, 1.0)
    assert all(math.isfinite(f) for f in f_pos) and f_pos[1] == -f_neg[1] and f_pos[1] < 0


# ---- rolling resistance and the convenience call ---------------------------------------------------------
def test_rolling_resistance_moment(tyre):
    spec, c = tyre
    fz, r, w_low = 2000.0, 0.27, 1.0
    full = spec.rolling_resistance * fz * r
    assert mf.rolling_resistance_moment(fz, 0.0, r, c, w_low) == 0.0
    assert mf.rolling_resistance_moment(fz, 50.0, r, c, w_low) == pytest.approx(-full, rel=1e-12)
    assert mf.rolling_resistance_moment(fz, -50.0, r, c, w_low) == pytest.approx(full, rel=1e-12)
    assert mf.rolling_resistance_moment(fz, 0.5, r, c, w_low) == pytest.approx(-full * math.tanh(0.5))
    assert mf.rolling_resistance_moment(0.0, 50.0, r, c, w_low) == 0.0


def test_tyre_forces_is_the_composition(tyre):
    _, c = tyre
    r, v_low, w_low = 0.27, 1.0, 1.0
    rng = np.random.default_rng(3)
    for _ in range(50):
        d, rate = rng.uniform(-0.005, 0.03), rng.uniform(-0.5, 0.5)
        vx, vy, omega = rng.uniform(-20, 20), rng.uniform(-3, 3), rng.uniform(-80, 80)
        fz = mf.vertical_force(d, rate, c)
        kappa, alpha = mf.slip_quantities(vx, vy, omega, r, v_low)
        fx, fy = mf.combined_forces(kappa, alpha, fz, c)
        my = mf.rolling_resistance_moment(fz, omega, r, c, w_low)
        assert mf.tyre_forces(d, rate, vx, vy, omega, r, c, v_low, w_low) == (fx, fy, fz, my)
    assert mf.tyre_forces(-0.01, 0.0, 10.0, 1.0, 40.0, r, c, v_low, w_low) == (0.0, 0.0, 0.0, 0.0)


@numba.njit
def _compiled_caller(coeffs, n):
    """A tiny compiled loop calling every tyre function, as the time loop will."""
    total = np.zeros(4)
    for i in range(n):
        d = 0.01 + 1e-5 * i
        fz = mf.vertical_force(d, 0.0, coeffs)
        mu_x, mu_y = mf.peak_friction(fz, coeffs)
        kappa, alpha = mf.slip_quantities(10.0, 0.1, 10.2 / 0.27, 0.27, 1.0)
        fx, fy = mf.combined_forces(kappa, alpha, fz, coeffs)
        fx0 = mf.pure_longitudinal(kappa, fz, coeffs)
        fy0 = mf.pure_lateral(alpha, fz, coeffs)
        my = mf.rolling_resistance_moment(fz, 37.0, 0.27, coeffs, 1.0)
        a, b, c, e = mf.tyre_forces(d, 0.0, 10.0, 0.1, 10.2 / 0.27, 0.27, coeffs, 1.0, 1.0)
        total[0] += fx + a + fx0 * 0.0 + mu_x * 0.0
        total[1] += fy + b + fy0 * 0.0 + mu_y * 0.0
        total[2] += fz + c + mf.cornering_stiffness(fz, coeffs) * 0.0 + mf.slip_stiffness(fz, coeffs) * 0.0
        total[3] += my + e
    return total


def test_callable_from_njit(tyre):
    _, c = tyre
    total = _compiled_caller(c, 10)
    expected = np.zeros(4)
    for i in range(10):
        f = mf.tyre_forces(0.01 + 1e-5 * i, 0.0, 10.0, 0.1, 10.2 / 0.27, 0.27, c, 1.0, 1.0)
        expected += 2 * np.array(f)
    np.testing.assert_allclose(total, expected, rtol=1e-12)
    assert mf.combined_forces.nopython_signatures  # compiled in nopython mode
