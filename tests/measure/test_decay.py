"""Tests of trikedyn.measure.decay: the fit of a single-mode free decay, where it starts, and the peak of a
decay's one-sided spectrum."""

import math

import numpy as np
import pytest

from trikedyn.errors import InputError
from trikedyn.measure import decay
from trikedyn.measure.signals import spectrum_peak


def _free_decay(t, fn=2.5, xi=0.3, amplitude=5.0, phase=0.4, offset=0.2):
    wn = 2 * np.pi * fn
    return amplitude * np.exp(-xi * wn * t) * np.cos(wn * math.sqrt(1 - xi**2) * t + phase) + offset


@pytest.mark.parametrize("xi", [0.1, 0.29, 0.4])
def test_one_sided_peak_ratio_matches_the_fft(xi):
    fs, fn = 1000.0, 3.0
    wn = 2 * np.pi * fn
    t = np.arange(int(30 * fs)) / fs
    x = np.exp(-xi * wn * t) * np.cos(wn * math.sqrt(1 - xi**2) * t + math.atan2(-xi, math.sqrt(1 - xi**2)))
    peak = spectrum_peak(x, fs, np.r_[0.5, np.ones(len(x) - 1)], 4)[0]  # trapezoidal first sample
    assert peak / fn == pytest.approx(decay.one_sided_peak_ratio(xi), rel=2e-5)
    assert decay.one_sided_peak_ratio(xi) > math.sqrt(1 - xi**2)  # between f_d and f_n


def test_fit_free_decay_exact_data():
    t = np.arange(0.0, 4.0, 0.01)
    y = _free_decay(t)
    fit = decay.fit_free_decay(t, y, 2.2)
    assert fit.natural_frequency_hz == pytest.approx(2.5, rel=1e-7)
    assert fit.damping_ratio == pytest.approx(0.3, rel=1e-7)
    np.testing.assert_allclose(fit(t), y, atol=1e-7)


def test_fit_after_the_peak_skips_what_pushes_before_the_free_decay():
    """A ramp up to the largest excursion at t = 1 s, then a free decay: the fit starts after the peak and
    finds the decay's mode, which a fit over the whole record would not."""
    t = np.arange(0.0, 5.0, 0.01)
    y = np.where(t < 1.0, 5.2 * t, _free_decay(t - 1.0, phase=0.0))
    y = y + np.random.default_rng(0).normal(0.0, 0.02, t.size)
    fit = decay.fit_decay_after_peak(t, y, 1.0, 2.4, 0.25, 100.0)
    period = 1.0 / (2.4 * math.sqrt(1 - 0.25**2))  # of the guess
    assert fit.start_s == pytest.approx(1.0 + decay.START_FRACTIONS[0] * period, abs=0.011)  # the earliest
    assert fit.natural_frequency_hz == pytest.approx(2.5, rel=0.01)
    assert fit.damping_ratio == pytest.approx(0.3, rel=0.03)
    whole = decay.fit_free_decay(t, y, 2.4, 0.25)
    assert abs(whole.damping_ratio / 0.3 - 1.0) > 0.1  # the ramp is no free decay
    with pytest.raises(InputError) as err:
        decay.fit_decay_after_peak(t[:105], y[:105], 1.0, 2.4, 0.25, 100.0, where="az_mps2")
    assert err.value.where == "az_mps2"
