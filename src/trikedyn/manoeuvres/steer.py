"""Open-loop steering inputs.

``step_steer`` follows ISO 7401:2011 (lateral transient response, step input): the steering is turned
"as quickly as possible" to a preselected angle and held; the standard asks a rise time (10 % to 90 %)
of at most 0.15 s, here a linear ramp of ``ramp_s`` (default 0.15 s) starting at ``start_s``. The angle is
about the steering axis [rad], as the model's steering servo takes it.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["step_steer", "sine_steer", "sweep_steer"]


def step_steer(angle_rad: float, *, start_s: float = 1.0, ramp_s: float = 0.15):
    """Steer command ``delta(t)`` [rad] of an ISO 7401 step: 0 until ``start_s``, a ramp, then held."""
    if not np.isfinite(angle_rad):
        raise InputError(f"must be finite, got {angle_rad!r}", where="angle_rad")
    if ramp_s <= 0 or start_s < 0:
        raise InputError("ramp_s must be > 0 and start_s >= 0", where="step_steer")

    def steer(t):
        return angle_rad * np.clip((np.asarray(t, dtype=float) - start_s) / ramp_s, 0.0, 1.0)

    return steer


def sine_steer(amplitude_rad: float, frequency_hz: float, *, start_s: float = 0.0, periods: float | None = None):
    """A sine steer ``A sin(2 pi f (t - start))`` [rad], for ``periods`` periods (all the run if None)."""
    if frequency_hz <= 0:
        raise InputError(f"must be > 0, got {frequency_hz!r}", where="frequency_hz")
    end = np.inf if periods is None else start_s + periods / frequency_hz

    def steer(t):
        t = np.asarray(t, dtype=float)
        active = (t >= start_s) & (t <= end)
        return np.where(active, amplitude_rad * np.sin(2 * np.pi * frequency_hz * (t - start_s)), 0.0)

    return steer


def sweep_steer(amplitude_rad: float, f_start_hz: float, f_end_hz: float, duration_s: float, *,
                start_s: float = 0.0, taper_s: float | None = None):
    """A logarithmic sine sweep ``A w(t) sin(phi(t))`` [rad] from ``f_start_hz`` to ``f_end_hz``.

    ``phi`` grows with the instantaneous frequency ``f(t) = f0 (f1/f0)^(t/T)``; ``w`` is a cosine taper over
    ``taper_s`` (one period of the start frequency by default) at both ends, so the steer starts and ends
    at zero without a jump in rate.
    """
    if not (0 < f_start_hz < f_end_hz) or duration_s <= 0:
        raise InputError("needs 0 < f_start_hz < f_end_hz and duration_s > 0", where="sweep_steer")
    if not np.isfinite(amplitude_rad):
        raise InputError(f"must be finite, got {amplitude_rad!r}", where="amplitude_rad")
    ratio = np.log(f_end_hz / f_start_hz)
    taper = min(1.0 / f_start_hz, 0.25 * duration_s) if taper_s is None else taper_s

    def steer(t):
        tau = np.clip(np.asarray(t, dtype=float) - start_s, 0.0, duration_s)
        phase = 2 * np.pi * f_start_hz * duration_s / ratio * (np.exp(ratio * tau / duration_s) - 1.0)
        edge = np.minimum(tau, duration_s - tau)
        window = np.where(edge < taper, 0.5 * (1 - np.cos(np.pi * np.clip(edge / taper, 0, 1))), 1.0)
        return amplitude_rad * window * np.sin(phase)

    return steer
