"""trikedyn.tyre.lanes: the similarity tyre over lanes against the scalar tyre function, lane by lane; its loop
vectorised."""

from __future__ import annotations

import re

import numpy as np
import pytest
from numba import njit

from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle
from trikedyn.tyre.interface import tyre_forces
from trikedyn.tyre.lanes import similarity_forces_lanes
from trikedyn.tyre.magic_formula import FZ0, MU_X, MU_Y, SLIP_STIFFNESS_FACTOR
from trikedyn.tyre.models import SIMILARITY

W_LOW = 1.0


@njit(cache=False)
def _scalar(coeffs, kappa, alpha, fz, spin, r_eff, w_low):
    """The scalar tyre function of each lane: ``(fx, fy, my)`` rows."""
    out = np.zeros((3, kappa.size))
    for j in range(kappa.size):
        if fz[j] > 0.0:  # as wheel_wrench calls it
            f = tyre_forces(SIMILARITY, coeffs[:, j].copy(), kappa[j], alpha[j], 0.0, fz[j], 10.0, 10.0, spin[j],
                            r_eff[j], 1.0, w_low)
            out[0, j], out[1, j], out[2, j] = f[0], f[1], f[4]
    return out


def _lanes(preset: str, n: int, seed: int):
    """``n`` lanes: the preset's tyres, each lane's friction and stiffness moved by up to 20 %, and slips from none
    to far past the peak, loads from none (and negative) to three times the rated load."""
    rng = np.random.default_rng(seed)
    tyres = build_model(load_vehicle(preset)).plant.tyres
    coeffs = np.ascontiguousarray(tyres[rng.integers(0, tyres.shape[0], n)].T)
    for row in (MU_X, MU_Y, SLIP_STIFFNESS_FACTOR):
        coeffs[row] *= rng.uniform(0.8, 1.2, n)
    kappa = rng.choice([0.0, 1e-12, -1e-9], n) + rng.normal(0, 0.1, n) * rng.choice([0, 1, 1, 3], n)
    alpha = rng.choice([0.0, 1e-12], n) + rng.normal(0, 0.1, n) * rng.choice([0, 1, 1, 4], n)
    fz = coeffs[FZ0] * rng.uniform(-0.2, 3.0, n)
    spin = rng.normal(0, 30, n) * rng.choice([0, 0.01, 1], n)
    r_eff = rng.uniform(0.2, 0.35, n)
    return coeffs, kappa, alpha, fz, spin, r_eff


@pytest.mark.parametrize("preset", ["reference-etrike", "reference-tadpole"])
def test_every_lane_equals_the_scalar_tyre(preset):
    coeffs, kappa, alpha, fz, spin, r_eff = _lanes(preset, 20_000, 5)
    fx, fy, my = (np.full(kappa.size, np.nan) for _ in range(3))
    similarity_forces_lanes(coeffs, kappa, alpha, fz, spin, r_eff, np.full(kappa.size, W_LOW), fx, fy, my)
    expected = _scalar(coeffs, kappa, alpha, fz, spin, r_eff, W_LOW)
    peak = np.maximum(coeffs[MU_X], coeffs[MU_Y]) * np.maximum(fz, 0.0) * 1.3 + 1.0  # above any force [N]
    for got, want in zip((fx, fy, my), expected, strict=True):
        assert np.all(np.isfinite(got))
        assert np.max(np.abs(got - want) / peak) <= 1e-15
    off = fz <= 0.0
    assert off.any() and not (fx[off].any() or fy[off].any() or my[off].any())
    assert np.count_nonzero((kappa == 0) & (alpha == 0) & ~off) > 0  # the zero-slip limit was taken


def test_the_lanes_loop_is_vectorised():
    """Its reason to be: LLVM does the lanes' arithmetic on vectors (compiled afresh: numba does not show the IR of
    cached code)."""
    compiled = njit(cache=False, error_model="numpy")(similarity_forces_lanes.py_func)
    coeffs, kappa, alpha, fz, spin, r_eff = _lanes("reference-etrike", 8, 1)
    outputs = [np.empty(8) for _ in range(3)]
    compiled(coeffs, kappa, alpha, fz, spin, r_eff, np.ones(8), *outputs)
    ir = next(iter(compiled.inspect_llvm().values()))
    assert re.search(r"\b(fadd|fsub|fmul|fdiv) <\d+ x double>", ir)
    # no call into the C library's functions left (with them, LLVM still pairs some arithmetic, but the loop
    # over the lanes stays scalar)
    assert not re.search(r"call [^\n]*@(atan|sin|cos|tanh|exp)\(", ir)
