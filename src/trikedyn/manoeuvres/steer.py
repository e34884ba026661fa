"""Open-loop steering inputs.

``step_steer`` follows ISO 7401:2011 (lateral transient response, step input): the steering is turned
"as quickly as possible" to a preselected angle and held; the standard asks a rise time (10 % to 90 %)
of at most 0.15 s, here a linear ramp of ``ramp_s`` (default 0.15 s) starting at ``start_s``. The angle is
about the steering axis [rad], as the model's steering servo takes it.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

__all__ = ["step_steer", "sine_steer", "sine_sweep"]


def step_steer(angle_rad: float, *, start_s: float = 1.0, ramp_s: float = 0.15):
    """Steer command ``delta(t)`` [rad] of an ISO 7401 step: 0 until ``start_s``, a ramp, then held.

    Parameters
    ----------
    angle_rad : float
        Final steer angle [rad].
    start_s : float
        Start of the ramp [s].
    ramp_s : float
        Ramp duration [s].

    Returns
    -------
    callable
        ``steer(t)``: steer command [rad] at times ``t`` [s].

    Raises
    ------
    InputError
        On a non-finite angle, a ramp not > 0 or a negative start.
    """
    if not np.isfinite(angle_rad):
        raise InputError(f"must be finite, got {angle_rad!r}", where="angle_rad")
    if ramp_s <= 0 or start_s < 0:
        raise InputError("ramp_s must be > 0 and start_s >= 0", where="step_steer")

    def steer(t):
        """Steer command [rad] at times ``t`` [s]: 0 before ``start_s``, a linear ramp over ``ramp_s``, then
        ``angle_rad``."""
        return angle_rad * np.clip((np.asarray(t, dtype=float) - start_s) / ramp_s, 0.0, 1.0)

    return steer


def sine_steer(amplitude_rad: float, frequency_hz: float, *, start_s: float = 0.0, periods: float | None = None):
    """A sine steer ``A sin(2 pi f (t - start))`` [rad], for ``periods`` periods (all the run if None).

    Parameters
    ----------
    amplitude_rad : float
        Amplitude [rad].
    frequency_hz : float
        Frequency [Hz], > 0.
    start_s : float
        Start time [s].
    periods : float, optional
        Number of periods; the whole run if None.

    Returns
    -------
    callable
        ``steer(t)``: steer command [rad] at times ``t`` [s].

    Raises
    ------
    InputError
        On a frequency that is not positive.
    """
    if frequency_hz <= 0:
        raise InputError(f"must be > 0, got {frequency_hz!r}", where="frequency_hz")
    end = np.inf if periods is None else start_s + periods / frequency_hz

    def steer(t):
        """Steer command [rad] at times ``t`` [s]: the sine from ``start_s`` for ``periods`` periods, 0 outside."""
        t = np.asarray(t, dtype=float)
        active = (t >= start_s) & (t <= end)
        return np.where(active, amplitude_rad * np.sin(2 * np.pi * frequency_hz * (t - start_s)), 0.0)

    return steer


def sine_sweep(t, amplitude, f_start_hz, f_end_hz, duration_s, start_s=0.0, *, method="linear", taper_s=None):
    """Sine-sweep (chirp) steer for the ISO 7401 frequency-response test.

    ``amplitude w(tau) sin(phi(tau))`` for ``0 <= tau = t - start_s <= duration_s``, zero outside; phase
    ``2 pi (f0 tau + (f1 - f0) tau^2 / (2 D))`` (linear) or ``2 pi f0 D (k^(tau/D) - 1) / ln k``, ``k = f1 /
    f0`` (logarithmic: equal time per octave). ``w`` is a raised-cosine taper over ``taper_s`` at each end
    (default: one period of ``f_start_hz``, at most 10 % of the duration): steer and steer rate start and
    end at zero.

    Parameters
    ----------
    t : array_like
        Time [s].
    amplitude : float
        Steer amplitude [steer unit, e.g. rad]; the result has that unit, one value per ``t``.
    f_start_hz, f_end_hz : float
        Frequency at the start and at the end of the sweep [Hz].
    duration_s, start_s, taper_s : float
        Duration, start and length of each taper (optional) of the sweep [s].
    method : {"linear", "logarithmic"}

    Returns
    -------
    numpy.ndarray
        The steer, in the unit of ``amplitude``, one value per ``t``.
    """
    t = np.asarray(t, dtype=float)
    f0, f1, dur = (float(v) for v in (f_start_hz, f_end_hz, duration_s))
    for value, where in ((f0, "f_start_hz"), (f1, "f_end_hz"), (dur, "duration_s")):
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"must be a finite number > 0, got {value!r}", where=where)
    taper = min(1.0 / f0, 0.1 * dur) if taper_s is None else float(taper_s)
    if not 0 <= taper <= dur / 2:
        raise InputError(f"must lie in [0, duration_s / 2], got {taper}", where="taper_s")
    tau = np.clip(t - float(start_s), 0.0, dur)
    if method == "linear":
        phase = 2 * np.pi * (f0 * tau + (f1 - f0) * tau**2 / (2 * dur))
    elif method == "logarithmic":
        k = f1 / f0
        phase = 2 * np.pi * f0 * tau if k == 1 else 2 * np.pi * f0 * dur * (k ** (tau / dur) - 1) / math.log(k)
    else:
        raise InputError(f"unknown method {method!r}; expected 'linear' or 'logarithmic'", where="method")
    edge = np.minimum(tau, dur - tau)
    w = np.where(edge < taper, 0.5 * (1 - np.cos(np.pi * edge / max(taper, 1e-300))), 1.0)
    inside = (t >= float(start_s)) & (t <= float(start_s) + dur)
    return np.where(inside, float(amplitude) * w * np.sin(phase), 0.0)
