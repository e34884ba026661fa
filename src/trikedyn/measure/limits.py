"""Bounds on measurement inputs: what a user may give the log readers and the suspension identification.

Each bound is checked before any array of that size is made; a breach is an
:class:`~trikedyn.errors.InputError` naming the parameter (or the file) and the range expected.

Suspension identification (:func:`trikedyn.measure.suspension.identify_suspension`)
    * ``sprung_mass_kg`` 1 .. 5000 kg: one wheel's share of anything from a bicycle trike to a 5 t vehicle.
    * ``tyre_stiffness_N_per_m`` 1e3 .. 1e7 N/m, ``tyre_damping_Ns_per_m`` 0 .. 1e4 N s/m,
      ``unsprung_mass_kg`` 0 .. 500 kg: the vehicle schema's ranges.
    * the record's sample rate (from its median time step) 1 Hz .. 10 kHz: IMUs log at 0.2-1000 Hz, a body
      mode of 1-3 Hz needs more than 2 samples a second;
    * the record at most 3600 s and :data:`MAX_RECORD_SAMPLES` samples on its uniform grid (a speed-bump
      record lasts seconds to minutes);
    * ``resample_hz`` 1 Hz .. 10 kHz (1000x a body mode), the resampled decay at most
      :data:`MAX_RESAMPLED_SAMPLES` (the automatic rate is lowered to stay within it, with a warning);
    * ``n_cycles`` 1 .. 1000.

IMU logs (:func:`trikedyn.measure.logs.read_log`)
    * files of at most :data:`MAX_LOG_BYTES`;
    * ``sample_rate_hz`` 0.01 Hz .. 10 kHz, for files that store no time.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

__all__ = [
    "MAX_LOG_BYTES", "MAX_RECORD_S", "MAX_RECORD_SAMPLES", "MAX_RESAMPLED_SAMPLES", "MAX_RESAMPLE_HZ",
    "MIN_SAMPLES", "RECORD_RATE_HZ", "LOG_RATE_HZ", "bounded", "checked_record", "checked_resample",
]

MIN_SAMPLES = 16
"""Fewest samples of a record to identify."""

MAX_RECORD_S = 3600.0
"""Longest record to identify [s]."""

MAX_RECORD_SAMPLES = 1_000_000
"""Most samples of a record to identify, on the uniform grid of its median time step."""

RECORD_RATE_HZ = (1.0, 10_000.0)
"""Sample rates of a record to identify [Hz], from its median time step."""

MAX_RESAMPLE_HZ = 10_000.0
"""Highest rate of the crest analysis [Hz]."""

MAX_RESAMPLED_SAMPLES = 2_000_000
"""Most samples of the resampled decay."""

LOG_RATE_HZ = (0.01, 10_000.0)
"""Sample rates [Hz] a user may give a log reader for a file that stores no time."""

MAX_LOG_BYTES = 256 * 2**20
"""Largest IMU log read [bytes] (256 MiB: several hours at 200 Hz)."""


def bounded(value, name: str, low: float, high: float, unit: str) -> float:
    """``value`` as a float in ``[low, high]``; an InputError naming ``name`` and the range otherwise.

    Parameters
    ----------
    value : object
        The value given.
    name : str
        Its name, for errors.
    low, high : float
        The range, in ``unit``.
    unit : str
        Its unit.

    Returns
    -------
    float
        The value.

    Raises
    ------
    InputError
        Not a number or out of range.
    """
    try:
        if isinstance(value, bool | str):
            raise TypeError
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"expected a number [{unit}], got {value!r}", where=name) from None
    if not (math.isfinite(v) and low <= v <= high):
        raise InputError(f"got {v:g}, expected {low:g} to {high:g} {unit}", where=name)
    return v


def checked_record(time_s, accel_mps2) -> tuple[np.ndarray, np.ndarray]:
    """Time [s] and acceleration as float arrays: 1-D, one length, finite, time increasing, within bounds.

    Parameters
    ----------
    time_s : array_like
        Times [s].
    accel_mps2 : array_like
        Accelerations [m/s^2].

    Returns
    -------
    time : numpy.ndarray
        [s].
    accel : numpy.ndarray
        [m/s^2].

    Raises
    ------
    InputError
        On a record that breaks a bound.
    """
    t, a = np.asarray(time_s, float), np.asarray(accel_mps2, float)
    if a.ndim != 1 or t.shape != a.shape:
        raise InputError(f"expected 1-D arrays of one length, got {t.shape}, {a.shape}", where="accel_mps2")
    if len(a) < MIN_SAMPLES:
        raise InputError(f"record too short: {len(a)} samples, need {MIN_SAMPLES}", where="accel_mps2")
    if len(a) > MAX_RECORD_SAMPLES:
        raise InputError(f"record too long: {len(a)} samples, at most {MAX_RECORD_SAMPLES}; cut it to the "
                         "speed-bump event", where="accel_mps2")
    for name, v in (("time_s", t), ("accel_mps2", a)):
        if not np.all(np.isfinite(v)):
            raise InputError(f"NaN or infinite value at sample {int(np.argmin(np.isfinite(v)))}", where=name)
    step = np.diff(t)
    if np.any(step <= 0.0):
        raise InputError(f"must increase strictly (sample {int(np.argmax(step <= 0.0)) + 1})", where="time_s")
    rate = 1.0 / float(np.median(step))
    low, high = RECORD_RATE_HZ
    if not low <= rate <= high:
        raise InputError(f"sample rate {rate:.4g} Hz (median time step), expected {low:g} to {high:g} Hz; "
                         "are the time stamps in seconds?", where="time_s")
    span = float(t[-1] - t[0])
    if not span <= MAX_RECORD_S:
        raise InputError(f"the record lasts {span:.4g} s, at most {MAX_RECORD_S:g} s; cut it to the speed-bump "
                         "event", where="time_s")
    if span * rate + 1.0 > MAX_RECORD_SAMPLES:
        raise InputError(f"{span:.4g} s at the median rate of {rate:.4g} Hz make {span * rate:.3g} samples, at most "
                         f"{MAX_RECORD_SAMPLES}; cut the record or even out its time stamps", where="time_s")
    return t, a


def checked_resample(rate_hz, span_s: float, *, given: bool) -> float:
    """The crest-analysis rate [Hz] for a decay of ``span_s``: a given one checked, an automatic one capped.

    Parameters
    ----------
    rate_hz : float
        The rate asked for, or the automatic one [Hz].
    span_s : float
        Decay length [s].
    given : bool
        Whether the user gave the rate.

    Returns
    -------
    float
        Rate [Hz].
    """
    budget = MAX_RESAMPLED_SAMPLES / max(span_s, 1e-9)
    if not given:
        return min(float(rate_hz), MAX_RESAMPLE_HZ, budget)
    rate = bounded(rate_hz, "resample_hz", 1.0, MAX_RESAMPLE_HZ, "Hz")
    if rate > budget:
        raise InputError(f"the decay after the largest excursion lasts {span_s:.4g} s: at {rate:g} Hz it would "
                         f"hold {rate * span_s:.3g} samples, at most {MAX_RESAMPLED_SAMPLES}; give a lower rate "
                         "or a shorter record", where="resample_hz")
    return rate
