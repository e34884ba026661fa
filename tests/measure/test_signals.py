"""Tests of trikedyn.measure.signals: spectral peak, band-limited resampling, wavelet denoising, crests.

Generic signal processing, on pure tones and exact decays whose answers are known in closed form.
"""

import math

import numpy as np
import pytest

from trikedyn.measure import signals
from trikedyn.measure.suspension import log_decrement


@pytest.mark.parametrize("f0", [2.9, 3.123, 7.77])
def test_spectrum_peak_pure_tone(f0):
    fs, n = 100.0, 500
    t = np.arange(n) / fs
    peak, freq, mag = signals.spectrum_peak(np.sin(2 * np.pi * f0 * t + 0.3), fs)
    assert abs(peak - f0) < 1e-3 * fs / n  # 0.1 % of the FFT bin
    assert mag.max() == pytest.approx(1.0, abs=0.03) and freq[-1] == pytest.approx(fs / 2)


def test_uniform_record_keeps_a_uniform_record_and_regrids_a_jittered_one():
    t = np.arange(50) / 10.0
    tu, xu, fs = signals.uniform_record(t, 2.0 * t)
    assert fs == pytest.approx(10.0)
    np.testing.assert_array_equal(tu, t)
    np.testing.assert_array_equal(xu, 2.0 * t)
    jitter = t + np.r_[0.0, np.random.default_rng(0).uniform(-0.003, 0.003, len(t) - 2), 0.0]
    tj, xj, fj = signals.uniform_record(jitter, 2.0 * jitter)
    np.testing.assert_allclose(np.diff(tj), 1.0 / fj, rtol=1e-9)
    np.testing.assert_allclose(xj, 2.0 * tj, atol=1e-12)  # linear interpolation of a line is exact


def test_upsample_band_limited_and_irregular():
    t = np.arange(200) / 10.0
    tu, xu = signals.upsample(t, np.sin(2 * np.pi * 2.9 * t), 200.0)
    assert tu[1] - tu[0] == pytest.approx(0.005) and tu[-1] <= t[-1]
    inner = (tu > 2.0) & (tu < 18.0)
    assert np.abs(xu - np.sin(2 * np.pi * 2.9 * tu))[inner].max() < 0.02
    jitter = t + np.random.default_rng(0).uniform(-0.002, 0.002, len(t))
    tj, xj = signals.upsample(jitter, np.sin(2 * np.pi * 0.5 * jitter), 100.0)
    np.testing.assert_allclose(np.diff(tj), np.diff(tj)[0], rtol=1e-9)  # uniform, at about 100 Hz
    assert np.diff(tj)[0] == pytest.approx(0.01, rel=2e-3)
    assert np.abs(xj - np.sin(2 * np.pi * 0.5 * tj))[(tj > 2) & (tj < 18)].max() < 0.02


def test_wavelet_denoise_keeps_the_oscillation():
    fs = 100.0
    t = np.arange(600) / fs
    clean = 5.0 * np.exp(-3.0 * t) * np.cos(2 * np.pi * 2.5 * t)
    noisy = clean + np.random.default_rng(1).normal(0.0, 0.1, len(t))
    den = signals.wavelet_denoise(noisy, level=2)  # approximation band 0-12.5 Hz kept
    assert np.std(den - clean) < 0.6 * np.std(noisy - clean)
    np.testing.assert_array_equal(signals.wavelet_denoise(noisy, level=0), noisy)


def test_find_crests_and_log_decrement():
    fs, fd, sigma = 1000.0, 2.5, 1.5
    t = np.arange(4000) / fs
    x = np.exp(-sigma * t) * np.cos(2 * np.pi * fd * t)
    times, values, polarity = signals.find_crests(t, x, 1e-3)
    np.testing.assert_array_equal(polarity[:4], [-1.0, 1.0, -1.0, 1.0])  # the maximum at t = 0 is an end
    np.testing.assert_allclose(np.diff(times), 0.5 / fd, rtol=1e-4)
    delta = log_decrement(-values[0], -values[2], 1)  # extension crests, one cycle apart (Eq. 1)
    assert delta == pytest.approx(sigma / fd, rel=1e-4)


def test_scalar_or_array():
    assert isinstance(signals.scalar_or_array(np.float64(2.0)), float)
    assert isinstance(signals.scalar_or_array(np.array(2.0)), float)
    assert signals.scalar_or_array(np.array([1.0, 2.0])).tolist() == [1.0, 2.0]
    assert math.isnan(signals.scalar_or_array(np.nan))
