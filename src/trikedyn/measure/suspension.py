"""Suspension identification from a speed-bump accelerometer record (paper, section 2.1, Eqs. 1-4).

The paper resamples a 10 Hz record of the body's vertical acceleration, denoises it (Discrete Meyer wavelet),
reads f_n off its Fourier spectrum and xi off the log decrement of both crest polarities (Eqs. 1-2), then K
and C from the sprung mass (Eqs. 3-4). This module holds those equations, the tyre-in-series correction and
:func:`identify_suspension`, which chains them with the generic signal processing of
:mod:`trikedyn.measure.signals` and the free-decay fit of :mod:`trikedyn.measure.decay`.
"""

from __future__ import annotations

import math

import numpy as np

from trikedyn.errors import InputError

# DecayFit, fit_free_decay: unused here, importable from here as before signals and decay were split off
from .decay import DecayFit, fit_decay_after_peak, fit_free_decay, one_sided_peak_ratio  # noqa: F401
from .identification import SuspensionIdentification
from .limits import MAX_RESAMPLED_SAMPLES, MIN_SAMPLES, bounded, checked_record, checked_resample  # noqa: F401
from .signals import find_crests, spectrum_peak, uniform_record, upsample, wavelet_denoise
from .signals import scalar_or_array as _out

__all__ = [
    "SuspensionIdentification", "damping_coefficient", "damping_ratio_from_log_decrement",
    "identify_suspension", "log_decrement", "sprung_mass_from_stiffness", "stiffness_from_frequency",
    "suspension_from_body_mode", "suspension_stiffness_from_series",
]


def log_decrement(x0, xn, n):
    """Eq. 1: ``delta = ln(X_0 / X_n) / n`` [-] from crest magnitudes X_0, X_n (same unit) n cycles apart.

    Parameters
    ----------
    x0, xn : float or array_like
        Crest magnitudes (any one unit).
    n : int or array_like
        Cycles between them.

    Returns
    -------
    float or numpy.ndarray
        delta, dimensionless.
    """
    x0, xn, n = (np.asarray(v, float) for v in (x0, xn, n))
    return _out(np.log(x0 / xn) / n)


def damping_ratio_from_log_decrement(delta):
    """Eq. 2: ``xi = delta / sqrt(4 pi^2 + delta^2)`` [-] from the log decrement [-].

    Parameters
    ----------
    delta : float or array_like
        Log decrement, dimensionless.

    Returns
    -------
    float or numpy.ndarray
        xi, dimensionless.
    """
    d = np.asarray(delta, float)
    return _out(d / np.sqrt(4.0 * math.pi**2 + d**2))


def stiffness_from_frequency(natural_frequency_hz, sprung_mass_kg):
    """Eq. 3: ``K = 4 pi^2 f_n^2 M_s`` [N/m] from the undamped natural frequency [Hz] and sprung mass [kg].

    Parameters
    ----------
    natural_frequency_hz : float or array_like
        f_n [Hz].
    sprung_mass_kg : float or array_like
        M_s [kg].

    Returns
    -------
    float or numpy.ndarray
        K [N/m].
    """
    f, m = np.asarray(natural_frequency_hz, float), np.asarray(sprung_mass_kg, float)
    return _out(4.0 * math.pi**2 * f**2 * m)


def sprung_mass_from_stiffness(stiffness, natural_frequency_hz):
    """Eq. 3 inverted: ``M_s = K / (4 pi^2 f_n^2)`` [kg] from K [N/m] and f_n [Hz].

    Parameters
    ----------
    stiffness : float or array_like
        K [N/m].
    natural_frequency_hz : float or array_like
        f_n [Hz].

    Returns
    -------
    float or numpy.ndarray
        M_s [kg].
    """
    k, f = np.asarray(stiffness, float), np.asarray(natural_frequency_hz, float)
    return _out(k / (4.0 * math.pi**2 * f**2))


def damping_coefficient(damping_ratio, stiffness, sprung_mass_kg):
    """Eq. 4: ``C = 2 xi sqrt(K M_s)`` [N s/m] from xi [-], K [N/m] and M_s [kg].

    Parameters
    ----------
    damping_ratio : float or array_like
        xi, dimensionless.
    stiffness : float or array_like
        K [N/m].
    sprung_mass_kg : float or array_like
        M_s [kg].

    Returns
    -------
    float or numpy.ndarray
        C [N s/m].
    """
    z, k, m = (np.asarray(v, float) for v in (damping_ratio, stiffness, sprung_mass_kg))
    return _out(2.0 * z * np.sqrt(k * m))


def suspension_stiffness_from_series(equivalent_stiffness, tyre_stiffness):
    """Suspension stiffness [N/m] of springs in series, ``1/K_eq = 1/K_s + 1/K_t`` [N/m].

    Needs ``0 < K_eq < K_t``. It ignores the damper: see :func:`suspension_from_body_mode`.

    Parameters
    ----------
    equivalent_stiffness : float or array_like
        K_eq [N/m].
    tyre_stiffness : float or array_like
        K_t [N/m].

    Returns
    -------
    float or numpy.ndarray
        K_s [N/m].

    Raises
    ------
    InputError
        Unless 0 < K_eq < K_t.
    """
    keq, kt = np.asarray(equivalent_stiffness, float), np.asarray(tyre_stiffness, float)
    if np.any(keq >= kt) or np.any(keq <= 0.0):
        raise InputError("must be positive and below the tyre stiffness", where="equivalent_stiffness")
    return _out(1.0 / (1.0 / keq - 1.0 / kt))


def suspension_from_body_mode(natural_frequency_hz, damping_ratio, sprung_mass_kg, tyre_stiffness,
                              *, tyre_damping=0.0, unsprung_mass_kg=0.0):
    """Suspension stiffness [N/m] and damping [N s/m] from the body mode of a quarter car, tyre in series.

    The series formula on complex impedances ``Z = K + lambda C`` at the body eigenvalue
    ``lambda = 2 pi f_n (-xi + i sqrt(1 - xi^2))``: ``Z_eq = -M_s lambda^2`` (Eqs. 3-4 in one),
    ``Z_t = K_t + lambda C_t + m lambda^2``, ``Z_s = 1/(1/Z_eq - 1/Z_t)``, ``C_s = Im Z_s / Im lambda``,
    ``K_s = Re Z_s - C_s Re lambda``. Exact for the two-mass quarter car given its unsprung mass m; with
    m = 0, about 1 % off on K and 2-3 % on C for 20 kg on 200 kN/m. The spring-only series over-estimates K_s
    by 5-10 % at xi = 0.2, 25-100 % at 0.4: the damper stiffens the mount.

    Parameters
    ----------
    natural_frequency_hz, damping_ratio : float or array_like
        Undamped natural frequency [Hz] and damping ratio [-] of the body mode.
    sprung_mass_kg, tyre_stiffness : float or array_like
        Sprung mass M_s [kg] and tyre stiffness K_t [N/m].
    tyre_damping, unsprung_mass_kg : float, optional
        Tyre damping C_t [N s/m] and unsprung mass m [kg], 0 by default.

    Returns
    -------
    stiffness, damping : float or ndarray
        Suspension stiffness K_s [N/m] and damping C_s [N s/m].
    """
    w = 2.0 * math.pi * np.asarray(natural_frequency_hz, float)
    z = np.asarray(damping_ratio, float)
    lam = w * (-z + 1j * np.sqrt(1.0 - z**2))
    z_t = tyre_stiffness + lam * tyre_damping + unsprung_mass_kg * lam**2
    z_s = 1.0 / (1.0 / (-np.asarray(sprung_mass_kg, float) * lam**2) - 1.0 / z_t)
    c = z_s.imag / lam.imag
    return _out(z_s.real - lam.real * c), _out(c)


def _crest_stage(tp, xp, t_peak, f_rough, floor, n_cycles):
    """Paper's method on the processed decay: crests, Eq. 1 per polarity averaged, crest period."""
    ct, cv, cp = find_crests(tp, xp, 4.0 * floor)
    after = ct > t_peak + 0.1 / f_rough
    ct, cv, cp = ct[after], cv[after], cp[after]
    if np.count_nonzero(np.abs(cv) >= 5.0 * floor) < 2:
        raise InputError("no oscillation found: fewer than 2 crests above the noise after the largest "
                         "excursion", where="accel_mps2")
    ok = (np.abs(cv) >= 10.0 * floor) & np.r_[True, np.abs(np.diff(ct) * 2.0 * f_rough - 1.0) < 0.5]
    n_ok = len(ok) if ok.all() else int(np.argmin(ok))
    ct, cv, cp = ct[:n_ok], cv[:n_ok], cp[:n_ok]
    deltas, cycles, used, notes = {}, 0, np.zeros(n_ok, bool), []
    for pol in (1.0, -1.0):
        idx = np.flatnonzero(cp == pol)[: None if n_cycles is None else int(n_cycles) + 1]
        if len(idx) >= 2:
            deltas[pol] = log_decrement(abs(cv[idx[0]]), abs(cv[idx[-1]]), len(idx) - 1)
            cycles, used[idx] = max(cycles, len(idx) - 1), True
    if deltas:
        delta = float(np.mean(list(deltas.values())))
    elif n_ok >= 2:
        delta, used[:2] = 2.0 * math.log(abs(cv[0] / cv[1])), True
        notes.append("one crest of each polarity 10x above the noise: crest log decrement over half a cycle")
    else:
        delta = math.nan
        notes.append("fewer than two crests 10x above the noise: no crest log decrement")
    fd = 0.5 / np.polyfit(np.arange(n_ok), ct, 1, w=np.abs(cv))[0] if n_ok >= 3 else math.nan
    return ct[used], cv[used], cp[used], deltas, delta, cycles, fd, notes


def identify_suspension(time_s, accel_mps2, sprung_mass_kg, *, tyre_stiffness_N_per_m=None,
                        tyre_damping_Ns_per_m=0.0, unsprung_mass_kg=None, resample_hz=None, n_cycles=None,
                        denoise=True, method="fit"):
    """Natural frequency, damping ratio, stiffness and damping of a suspension from a speed-bump record.

    1. Static offset (gravity, sensor bias): median of the final quarter of the record. The free decay
       starts at the largest excursion (the bump's peak response, or a release).
    2. Paper's method: Discrete Meyer denoising, at the input rate, of the detail bands above 2.5x the
       oscillation (noise only; none at 10 Hz, where the finest band holds the oscillation itself; after
       band-limited resampling the added bands hold no noise to estimate); band-limited resampling of the
       decay (reflected at its start so the bump or release does not ring into it); crests after the largest
       excursion; Eq. 1 over the ``n`` cycles of each polarity whose crests stand 10x above the noise,
       compression and extension averaged (their offset errors cancel); Eq. 2; FFT peak.
    3. ``method="fit"`` (default): :func:`~trikedyn.measure.decay.fit_free_decay` on the raw samples, from
       the earliest start 1/8 to 1/2 period after the largest excursion where the free-decay model holds
       (:func:`~trikedyn.measure.decay.fit_decay_after_peak`), started from step 2.
    4. Eqs. 3-4 with ``sprung_mass_kg``; with a tyre stiffness, :func:`suspension_from_body_mode`.

    ``natural_frequency_hz`` is the undamped f_n; ``damped_frequency_hz`` is f_d = f_n sqrt(1 - xi^2). The
    paper took its FFT peak as f_n, but the peak of a steady or Hann-windowed decay sits at f_d, 4.5 % below
    f_n for xi = 0.29. A Hann window also suppresses the start of a transient, where its energy is, and moves
    the peak with where the event falls in the record. The FFT here is one-sided: from the first crest used
    (the decay is its own exponential window) to where it reaches the noise; its peak is f_n times
    :func:`~trikedyn.measure.decay.one_sided_peak_ratio`, inverted with the crest xi; the crest period
    cross-checks f_d.

    Why the fit: at 10 Hz a 2.9 Hz decay has 3.4 samples per cycle and, for xi >= 0.3, much energy above
    5 Hz: resampled crests are distorted and the FFT peak moves (5-13 % on f_n, up to 30 % on xi), and Eq. 1
    on two crests is noise-limited. The fit uses every sample at its instant and the tail for the offset:
    2 % on f_n and 10 % on xi at 100 Hz, 3 % and 20 % at 10 Hz on quarter-car records (see the tests; at
    10 Hz and xi = 0.4 the f_n error has a 1 % standard deviation, about 1 record in 100 exceeds 3 %).
    ``method="paper"`` reports the FFT and crest estimates, which the result keeps either way (with a
    warning if they disagree with the fit).

    Parameters
    ----------
    time_s, accel_mps2 : array_like
        Time stamps [s] (strictly increasing, jitter allowed) and vertical acceleration, z up [m/s^2].
    sprung_mass_kg : float
        Sprung mass M_s on this suspension [kg].
    tyre_stiffness_N_per_m, tyre_damping_Ns_per_m, unsprung_mass_kg : float, optional
        Tyre stiffness [N/m] (then K, C are the suspension's), tyre damping [N s/m], unsprung mass [kg].
    resample_hz : float, optional
        Rate of the crest analysis [Hz]; default: the input rate if >= 50 Hz and 20x the oscillation, else
        max(200 Hz, 20x), lowered (with a warning) to keep the resampled decay within bounds.
    n_cycles : int, optional
        Cycles of Eq. 1 per polarity (1 to 1000); default: all whose crests stand 10x above the noise.
    denoise : bool, optional
        Apply the wavelet denoising.
    method : {"fit", "paper"}, optional
        Source of the reported f_n and xi.

    Returns
    -------
    SuspensionIdentification

    Raises
    ------
    InputError
        NaN, bad time stamps, too short a record, no oscillation; an input outside the bounds of
        :mod:`trikedyn.measure.limits` (masses, stiffness, rates, record length), naming the parameter.
    """
    ms = bounded(sprung_mass_kg, "sprung_mass_kg", 1.0, 5000.0, "kg")
    kt = None if tyre_stiffness_N_per_m is None else bounded(tyre_stiffness_N_per_m, "tyre_stiffness_N_per_m",
                                                              1e3, 1e7, "N/m")
    ct_tyre = bounded(tyre_damping_Ns_per_m, "tyre_damping_Ns_per_m", 0.0, 1e4, "N s/m")
    mu = bounded(unsprung_mass_kg or 0.0, "unsprung_mass_kg", 0.0, 500.0, "kg")
    if resample_hz is not None:
        bounded(resample_hz, "resample_hz", 1.0, 1e4, "Hz")
    if n_cycles is not None and (isinstance(n_cycles, bool) or not isinstance(n_cycles, int | np.integer)
                                 or not 1 <= n_cycles <= 1000):
        raise InputError(f"got {n_cycles!r}, expected a whole number of cycles, 1 to 1000", where="n_cycles")
    if method not in ("fit", "paper"):
        raise InputError(f"unknown method {method!r}, expected 'fit' or 'paper'", where="method")
    t_raw, a_raw = checked_record(time_s, accel_mps2)
    t, a, fs0 = uniform_record(t_raw, a_raw)
    tail = a[-max(len(a) // 4, 8):]
    offset = float(np.median(tail))
    x = a - offset
    noise = 1.4826 * float(np.median(np.abs(tail - offset)))
    i_max = int(np.argmax(np.abs(x)))
    if abs(x[i_max]) <= 10.0 * noise:
        raise InputError("no oscillation found: largest excursion within 10x the noise of the final quarter",
                         where="accel_mps2")
    fmin = max(0.2, 2.0 / (t[-1] - t[0]))
    f_rough = spectrum_peak(x, fs0, "hann", 8, fmin=fmin)[0]
    if (t[-1] - t[i_max]) * f_rough < 2.0:
        raise InputError("record too short: under 2 cycles after the largest excursion", where="accel_mps2")

    level = 0
    while denoise and fs0 / 2 ** (level + 2) >= 2.5 * f_rough:
        level += 1
    xd = wavelet_denoise(x, level=level) if level else x
    auto = fs0 if fs0 >= max(50.0, 20.0 * f_rough) else max(200.0, 10.0 * math.ceil(2.0 * f_rough))
    rate = checked_resample(auto if resample_hz is None else resample_hz, t[-1] - t[i_max],
                            given=resample_hz is not None)
    tp, xp = upsample(t[i_max:], xd[i_max:], rate, padtype="reflect")
    fs = 1.0 / (tp[1] - tp[0])
    ptail = xp[-max(len(xp) // 4, 8):]
    floor = max(1.4826 * float(np.median(np.abs(ptail - np.median(ptail)))), 1e-9 * abs(x[i_max]))
    crests = _crest_stage(tp, xp, t[i_max], f_rough, floor, n_cycles)
    ct, cv, cp, deltas, delta_c, cycles, fd_crest, notes = crests
    xi_c = damping_ratio_from_log_decrement(delta_c) if delta_c > 0 else math.nan
    # One-sided FFT from the first crest until the decay reaches the noise floor (pure noise after it).
    i_seg = int(np.searchsorted(tp, ct[0])) if len(ct) else 0
    to_floor = math.log(abs(cv[0]) / floor) / delta_c + 1.0 if len(ct) and delta_c > 0 else np.inf
    i_end = max(int(np.searchsorted(tp, tp[i_seg] + max(to_floor, 2.0) / f_rough)), i_seg + 8)
    win = np.r_[0.5, np.ones(len(xp[i_seg:i_end]) - 1)]  # trapezoidal rule: the transform starts at a crest
    pad = 8 * max(1, len(tp) // (i_end - i_seg))
    f_peak, freq, mag = spectrum_peak(xp[i_seg:i_end], fs, win, pad, fmin=fmin)
    f_spec = f_peak if math.isnan(xi_c) else f_peak / one_sided_peak_ratio(xi_c)

    i_raw = int(np.argmax(np.abs(a_raw - offset)))
    fit = fit_decay_after_peak(t_raw, a_raw - offset, t_raw[i_raw], f_spec,
                               None if math.isnan(xi_c) else xi_c, fs0, where="accel_mps2")
    if method == "fit":
        f_n, xi = fit.natural_frequency_hz, fit.damping_ratio
        f_std, xi_std = (float(v) for v in np.sqrt(np.diag(fit.covariance)))
        if not (abs(f_spec / f_n - 1.0) <= 0.05 and abs(xi_c / xi - 1.0) <= 0.25):
            notes.append(f"paper's method (FFT {f_spec:.3f} Hz, crest xi {xi_c:.3f}) differs from the fit "
                         f"({f_n:.3f} Hz, xi {xi:.3f})")
        if fit.noise_std > 3.0 * noise > 0.0:
            notes.append("fit residual above 3x the noise of the final quarter: not a single-mode decay?")
    else:
        f_n, xi, f_std, xi_std = f_spec, xi_c, math.nan, math.nan
    if not (0.0 < xi < 1.0 and 0.0 < f_n < fs0):
        raise InputError(f"no decaying oscillation found (f_n = {f_n:.3g} Hz, xi = {xi:.3g})",
                         where="accel_mps2")
    f_d = f_n * math.sqrt(1.0 - xi**2)
    if fs0 < 4.0 * f_d:
        consequence = ("the oscillation may be an alias; frequency and crests are unreliable"
                       if fs0 < 2.5 * f_d else "crest amplitudes rest on the resampling and are unreliable")
        notes.append(f"Nyquist: the {fs0:.3g} Hz record has {fs0 / f_d:.2f} samples per cycle of the "
                     f"{f_d:.3g} Hz found (Nyquist needs more than 2, crests 4): {consequence}")

    k_eq = stiffness_from_frequency(f_n, ms)
    c_eq = damping_coefficient(xi, k_eq, ms)
    k_s, c_s = k_eq, c_eq
    if rate < auto and resample_hz is None:
        notes.append(f"crest analysis at {rate:.4g} Hz, not {auto:.4g} Hz: the resampled decay is kept within "
                     f"{MAX_RESAMPLED_SAMPLES} samples")
    if kt is not None:
        k_s, c_s = suspension_from_body_mode(f_n, xi, ms, kt, tyre_damping=ct_tyre, unsprung_mass_kg=mu)
        if not (k_s > 0.0 and c_s >= 0.0):
            raise InputError(f"too soft for the body mode found (K_eq = {k_eq:.0f} N/m): no suspension fits",
                             where="tyre_stiffness_N_per_m")
    comp, ext = cp > 0, cp < 0
    return SuspensionIdentification(
        f_n, f_d, xi, 2.0 * math.pi * xi / math.sqrt(1.0 - xi**2), deltas.get(1.0, math.nan),
        deltas.get(-1.0, math.nan), k_s, k_eq, c_s, c_eq, cycles, fs0, fs, ms, kt, ct_tyre, mu, method, f_std, xi_std,
        f_peak, f_spec, fd_crest, xi_c, offset, noise, fit.start_s, tuple(notes), tp, xp,
        np.where(tp >= fit.start_s, fit(tp), np.nan), t_raw, a_raw - offset, ct[comp], cv[comp], ct[ext],
        cv[ext], freq, mag)
