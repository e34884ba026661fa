"""The free decay of a single damped mode: its least-squares fit to a record, where the fit should start, and
where the decay's one-sided spectrum peaks.

Generic to any viscously damped oscillation ``e^(-sigma t) cos(omega_d t + phi)``, with natural frequency
``f_n = sqrt(sigma^2 + omega_d^2) / 2 pi`` and damping ratio ``xi = sigma / (2 pi f_n)``; used by
:func:`~trikedyn.measure.suspension.identify_suspension`.
"""

from __future__ import annotations

import itertools
import math
from typing import NamedTuple

import numpy as np
from scipy.optimize import least_squares

from trikedyn.errors import InputError

from .signals import scalar_or_array

__all__ = ["DecayFit", "fit_decay_after_peak", "fit_free_decay", "one_sided_peak_ratio"]

START_FRACTIONS = (0.125, 0.25, 0.375, 0.5)
"""Candidate starts of the fit after the largest excursion [periods] (:func:`fit_decay_after_peak`)."""
_CHI2_99_2DOF = 9.210  # 99 % quantile of the chi-square distribution with 2 degrees of freedom


def one_sided_peak_ratio(damping_ratio):
    """Spectral peak over f_n [-] of a free decay transformed from one of its crests to its end.

    For ``e^(-sigma t) cos(omega_d t + phi)``, ``t >= 0``, ``x'(0) = 0``: ``|X|^2 ~ (r^2 + 4 xi^2) /
    ((1 - r^2)^2 + 4 xi^2 r^2)``, r = f/f_n, peaks at ``r^2 = sqrt(1 + 8 xi^2) - 4 xi^2``: 0.9944 at xi = 0.2,
    0.9327 at 0.4, between f_d/f_n (0.980, 0.917) and 1.

    Parameters
    ----------
    damping_ratio : float or array_like
        Damping ratio, dimensionless.

    Returns
    -------
    float or numpy.ndarray
        Peak frequency over f_n, dimensionless.
    """
    z2 = np.asarray(damping_ratio, float) ** 2
    return scalar_or_array(np.sqrt(np.sqrt(1.0 + 8.0 * z2) - 4.0 * z2))


class DecayFit(NamedTuple):
    """Fitted ``e^(-sigma tau) (B cos omega_d tau + D sin omega_d tau) + c``, ``tau = t - start_s`` [s].

    Call it on times [s]. ``covariance``: of (f_n [Hz], xi [-]); ``coefficients``: (B, D, c); ``noise_std``:
    the residual standard deviation.
    """

    natural_frequency_hz: float
    damping_ratio: float
    covariance: np.ndarray
    coefficients: np.ndarray
    start_s: float
    noise_std: float

    def __call__(self, time_s):
        w, z = 2.0 * math.pi * self.natural_frequency_hz, self.damping_ratio
        tau = np.asarray(time_s, float) - self.start_s
        return _decay_basis(tau, z * w, w * math.sqrt(1.0 - z * z)) @ self.coefficients


def _decay_basis(tau, sigma, omega):
    e = np.exp(-sigma * tau)
    return np.column_stack((e * np.cos(omega * tau), e * np.sin(omega * tau), np.ones_like(tau)))


def _projected_residual(p, tau, y):
    basis = _decay_basis(tau, *p)
    return basis @ np.linalg.lstsq(basis, y, rcond=None)[0] - y


def fit_free_decay(time_s, signal, frequency_guess_hz, damping_ratio_guess=None, *, max_frequency_hz=np.inf):
    """Least-squares fit of a single-mode free decay plus offset to a record starting where the decay does.

    Variable projection: amplitudes and offset are solved linearly inside a bounded nonlinear least squares
    over (sigma, omega_d), started from the best point of a grid. The model is evaluated at the sample
    instants: point sampling and aliasing are exact, and jittered time stamps are fine. The covariance is the
    Gauss-Newton one scaled by the residual variance.

    Parameters
    ----------
    time_s, signal : array_like
        The free decay: time [s] and samples [m/s^2].
    frequency_guess_hz : float
        Guess of f_n [Hz]; the grid spans +-15 %.
    damping_ratio_guess : float, optional
        Guess of xi [-], added to the grid 0.05-0.6.
    max_frequency_hz : float, optional
        Upper bound of f_d [Hz] (the Nyquist frequency).

    Returns
    -------
    DecayFit
    """
    t, y = np.asarray(time_s, float), np.asarray(signal, float)
    tau, w_max, guess = t - t[0], 2.0 * math.pi * max_frequency_hz, damping_ratio_guess
    xis = [0.05, 0.1, 0.2, 0.3, 0.45, 0.6] + ([guess] if guess is not None and 0.0 < guess < 0.9 else [])
    grid = [(z * w, min(w * math.sqrt(1.0 - z * z), 0.999 * w_max))
            for w in 2.0 * math.pi * frequency_guess_hz * np.linspace(0.85, 1.15, 7) for z in xis]
    start = min(grid, key=lambda p: float(np.sum(_projected_residual(p, tau, y) ** 2)))
    sol = least_squares(_projected_residual, start, args=(tau, y), bounds=([0.0, 0.0], [np.inf, w_max]),
                        x_scale="jac")
    sigma, omega = sol.x
    wn = math.hypot(sigma, omega)
    s2 = float(sol.fun @ sol.fun) / max(len(y) - 5, 1)
    grad = np.array([[sigma / (2 * math.pi * wn), omega / (2 * math.pi * wn)],
                     [omega**2 / wn**3, -sigma * omega / wn**3]])  # d(f_n, xi) / d(sigma, omega_d)
    cov = grad @ (s2 * np.linalg.pinv(sol.jac.T @ sol.jac)) @ grad.T
    coef = np.linalg.lstsq(_decay_basis(tau, sigma, omega), y, rcond=None)[0]
    return DecayFit(wn / (2.0 * math.pi), sigma / wn, cov, coef, float(t[0]), math.sqrt(s2))


def fit_decay_after_peak(time_s, signal, peak_time_s, frequency_guess_hz, damping_ratio_guess, rate_hz, *,
                         where="signal"):
    """:func:`fit_free_decay` from the earliest start after the largest excursion where the decay is free.

    The candidate starts are 1/8..1/2 period (:data:`START_FRACTIONS`) after ``peak_time_s``; the earliest
    whose estimates agree with the next start's (99 % chi-square on (f_n, xi), Hausman covariance) is kept.
    This drops a bump still pushing, or the wheel mode's quick transient after a release, which are not the
    body mode's free decay.

    Parameters
    ----------
    time_s, signal : array_like
        The record, offset removed: time [s] and samples [m/s^2].
    peak_time_s : float
        Time of the largest excursion [s].
    frequency_guess_hz : float
        Guess of f_n [Hz].
    damping_ratio_guess : float or None
        Guess of xi [-].
    rate_hz : float
        Sampling rate [Hz]; f_d is bounded by its Nyquist frequency.
    where : str, optional
        Names the signal in errors.

    Returns
    -------
    DecayFit
        The earliest consistent fit, else the latest one.

    Raises
    ------
    InputError
        Fewer than 8 samples after every candidate start.
    """
    t, x, fs = np.asarray(time_s, float), np.asarray(signal, float), rate_hz
    period = 1.0 / (frequency_guess_hz * math.sqrt(1.0 - min(damping_ratio_guess or 0.0, 0.9) ** 2))
    starts = sorted({int(np.searchsorted(t, peak_time_s + f * period - 1e-9 / fs)) for f in START_FRACTIONS})
    fits = [fit_free_decay(t[i:], x[i:], frequency_guess_hz, damping_ratio_guess, max_frequency_hz=fs / 2.0)
            for i in starts if len(t) - i >= 8]
    if not fits:
        raise InputError("record too short after the largest excursion", where=where)
    for early, late in itertools.pairwise(fits):
        d = np.array([early.natural_frequency_hz - late.natural_frequency_hz,
                      early.damping_ratio - late.damping_ratio])
        cov = late.covariance - early.covariance
        if np.any(np.linalg.eigvalsh(cov) <= 0.0):
            cov = late.covariance
        if d @ np.linalg.pinv(cov) @ d <= _CHI2_99_2DOF:
            return early
    return fits[-1]
