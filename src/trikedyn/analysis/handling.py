"""Handling figures from time histories: ISO 7401 transients, ISO 7975 braking in a turn (and ISO 4138).

Pure array algorithms (NumPy/SciPy), no vehicle model; SI signals in ISO 8855 axes (a left turn has
positive lateral acceleration, yaw rate and steer). The standards' text was not at hand: the definitions are
the commonly published ones (SAE J266; ISO 4138, 7401, 7975 as summarised in the literature), stated by each
function. The ISO 4138 handling diagram is :mod:`trikedyn.analysis.steady_state`'s (re-exported here).
Results are frozen dataclasses; ``to_dict()`` gives JSON-safe plain values (None for NaN). Bad
input raises :class:`~trikedyn.errors.InputError`, a :class:`ValueError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import signal

from ..errors import InputError
from ..manoeuvres.steer import sine_sweep  # the sweep steer signal, re-exported
from ._series import PlainResult, as_time, as_values, crossing, positive
from .steady_state import HandlingDiagram, handling_diagram  # ISO 4138, re-exported

__all__ = ["BrakingInTurn", "FrequencyResponse", "HandlingDiagram", "StepResponse", "braking_in_turn",
           "frequency_response", "handling_diagram", "sine_sweep", "step_response"]

STEADY_WINDOW_S = 1.0  # default final window of a step-steer record averaged as the steady state [s]
OVERSHOOT_MIN = 0.005  # a step response has a peak if it exceeds its steady value by more than this [-]
SEGMENT_S = 10.0  # default Welch segment [s] (resolution 0.1 Hz), at most a quarter of the record
COHERENCE_MIN = 0.95  # default least coherence of a frequency kept in a frequency response [-]
ENERGY_FRACTION = 0.03  # default least steer auto-spectral density kept, fraction of its maximum [-]


# ------------------------------------------------------------------------------ ISO 7401 step steer
@dataclass(frozen=True)
class StepResponse(PlainResult):
    """ISO 7401 step-steer figures of one response channel, as defined in :func:`step_response`.

    Attributes
    ----------
    steer_step, steady_state_value, peak_value : float
        Steer change [steer unit]; steady and peak response [response unit] (no peak: the steady one).
    steady_state_gain, overshoot : float
        Response change over steer change [response unit / steer unit]; (peak - steady) / steady [-].
    steer_50_time_s, response_time_s, rise_time_s, peak_response_time_s : float
        Time of 50 % steer; from it to 90 % response; from 10 % to 90 % response; from 50 % steer to
        the peak (NaN if no peak) [s].
    """

    steer_step: float
    steady_state_value: float
    steady_state_gain: float
    steer_50_time_s: float
    response_time_s: float
    rise_time_s: float
    peak_response_time_s: float
    peak_value: float
    overshoot: float


def step_response(time_s, steer, response, *, steer_start_s=None, steady_window_s=STEADY_WINDOW_S) -> StepResponse:
    """ISO 7401 step-steer response figures (SAE J266 definitions).

    Initial levels: the first sample of steer and response, or their means over ``t <= steer_start_s``.
    Steady levels: their means over the last ``steady_window_s`` seconds (default 1 s), or over the
    interval ``(start, end)`` if a pair is given. The response is normalised, ``y = (r - r_0) / (r_ss -
    r_0)``, so a negative step or gain gives the same times and overshoot. Crossing times are interpolated
    linearly between samples. Response time: from the steer's 50 % instant to the first ``y >= 0.9``
    (ISO 7401); rise time: first ``y >= 0.1`` to first ``y >= 0.9``. Peak: the largest ``y`` after the 50 %
    steer instant, refined by a parabola through three samples; it counts if it lies before the steady
    window and exceeds 1 by more than 0.5 %: then overshoot = ``y_peak - 1`` = (peak - steady) / steady
    and the peak response time runs from 50 % steer; otherwise overshoot is 0 and the peak time NaN.

    Parameters
    ----------
    time_s : array_like
        Time [s], strictly increasing.
    steer, response : array_like
        Steer input (road-wheel angle [rad]) and response (yaw rate [rad/s] or lateral acc. [m/s^2]).
    steer_start_s : float, optional
        End of the initial state [s].
    steady_window_s : float or (float, float)
        Length [s] of the final steady window, or its (start, end) times [s].

    Returns
    -------
    StepResponse
        Levels, response and rise times [s], overshoot (dimensionless) and peak time [s].

    Raises
    ------
    InputError
        If the steer has no step (it changes by less than half its range) or its step does not end
        before the steady window, or if the response does not change.
    """
    t = as_time(time_s)
    s, r = as_values(steer, t.size, "steer"), as_values(response, t.size, "response")
    if steer_start_s is None:
        s0, r0, start = s[0], r[0], 0
    else:
        pre = t <= float(steer_start_s)
        if not pre.any():
            raise InputError(f"no sample at or before {steer_start_s} s", "steer_start_s")
        s0, r0, start = s[pre].mean(), r[pre].mean(), int(np.flatnonzero(pre)[-1])
    if np.ndim(steady_window_s) == 0:
        window = (t[-1] - positive(steady_window_s, "steady_window_s"), t[-1])
    else:
        window = tuple(float(v) for v in steady_window_s)
    ss = (t >= window[0] - 1e-12) & (t <= window[1] + 1e-12)
    if not ss.any():
        raise InputError(f"no sample in the steady window {window}", "steady_window_s")
    ds, dr = s[ss].mean() - s0, r[ss].mean() - r0
    if not abs(ds) > 0.5 * np.ptp(s) + 1e-12 * np.abs(s).max():
        raise InputError("the steer has no step: its final level differs from its initial one by less than "
                         "half its range", "steer")
    t50 = crossing(t, (s - s0) / ds, 0.5, start)
    if not math.isfinite(t50) or t50 >= window[0]:
        raise InputError("the steer step is not complete before the steady window; record longer", "time_s")
    if not abs(dr) > 1e-9 * np.ptp(r):
        raise InputError("the response does not change with the steer", "response")
    y = (r - r0) / dr
    t10, t90 = crossing(t, y, 0.1, start), crossing(t, y, 0.9, start)
    after = np.flatnonzero(t >= t50)
    k = int(after[np.argmax(y[after])])
    y_pk, t_pk = y[k], t[k]
    if 0 < k < t.size - 1 and y[k - 1] - 2 * y[k] + y[k + 1] < 0:  # vertex of the parabola
        d = 0.5 * (y[k - 1] - y[k + 1]) / (y[k - 1] - 2 * y[k] + y[k + 1])
        y_pk, t_pk = y[k] - 0.25 * (y[k - 1] - y[k + 1]) * d, t[k] + d * (t[k + 1] - t[k - 1]) / 2
    peak = t_pk < window[0] and y_pk > 1 + OVERSHOOT_MIN
    return StepResponse(
        steer_step=float(ds), steady_state_value=float(r0 + dr), steady_state_gain=float(dr / ds),
        steer_50_time_s=t50, response_time_s=t90 - t50, rise_time_s=t90 - t10,
        peak_response_time_s=float(t_pk - t50) if peak else math.nan,
        peak_value=float(r0 + dr * (y_pk if peak else 1.0)), overshoot=float(y_pk - 1) if peak else 0.0)


# ------------------------------------------------------------------------------ ISO 7401 frequency response
@dataclass(frozen=True, eq=False)
class FrequencyResponse(PlainResult):
    """H1 frequency response of one response channel to the steer, over its reliable band.

    Attributes
    ----------
    frequency_hz, gain, phase_deg, coherence : ndarray
        Frequencies of the band [Hz]; ``|H1|`` [response unit / steer unit]; ``arg H1`` unwrapped along
        the band [deg] (negative: the response lags); magnitude-squared coherence [-].
    nperseg : int
        Welch segment length [samples].
    """

    frequency_hz: np.ndarray
    gain: np.ndarray
    phase_deg: np.ndarray
    coherence: np.ndarray
    nperseg: int

    def _at(self, values, f):
        f = np.asarray(f, dtype=float)
        if np.any((f < self.frequency_hz[0]) | (f > self.frequency_hz[-1])):
            raise InputError(f"outside the band [{self.frequency_hz[0]:.4g}, {self.frequency_hz[-1]:.4g}] Hz",
                             "frequency_hz")
        out = np.interp(f, self.frequency_hz, values)
        return float(out) if out.ndim == 0 else out

    def gain_at(self, f_hz):
        """Gain at ``f_hz`` [Hz], interpolated linearly along the band [response unit / steer unit].

        Parameters
        ----------
        f_hz : float or array_like
            Frequency [Hz].

        Returns
        -------
        float or numpy.ndarray
            Gain [response unit / steer unit].
        """
        return self._at(self.gain, f_hz)

    def phase_at(self, f_hz):
        """Phase at ``f_hz`` [Hz], interpolated linearly along the band [deg].

        Parameters
        ----------
        f_hz : float or array_like
            Frequency [Hz].

        Returns
        -------
        float or numpy.ndarray
            Phase [deg].
        """
        return self._at(self.phase_deg, f_hz)

    def plot(self):
        """Bode diagram: gain, phase [deg] and coherence against frequency [Hz] (log axis); the Figure.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(3, 1, sharex=True, figsize=(6, 7), gridspec_kw={"height_ratios": [3, 3, 1]})
        axes[0].loglog(self.frequency_hz, self.gain, color="k")
        axes[1].semilogx(self.frequency_hz, self.phase_deg, color="k")
        axes[2].semilogx(self.frequency_hz, self.coherence, color="0.4")
        for ax, label in zip(axes, ("gain [response / steer]", "phase [deg]", "coherence [-]"), strict=True):
            ax.set_ylabel(label)
            ax.grid(alpha=0.3, which="both")
        axes[2].set_ylim(0, 1.05)
        axes[2].set_xlabel("frequency [Hz]")
        fig.tight_layout()
        return fig


def frequency_response(time_s, steer, response, *, f_min_hz=None, f_max_hz=None, nperseg=None,
                       coherence_min=COHERENCE_MIN, energy_fraction=ENERGY_FRACTION) -> FrequencyResponse:
    """ISO 7401 frequency response (sine sweep or random steer) by the H1 estimator.

    ``H1 = G_xy / G_xx``, cross-spectral density of steer ``x`` and response ``y``
    (:func:`scipy.signal.csd`) over the steer's auto-spectral density (:func:`scipy.signal.welch`);
    coherence ``|G_xy|^2 / (G_xx G_yy)``. H1 is not biased by noise on the response. Welch: Hann window,
    75 % overlap (the overlapped squared windows sum to a constant, which keeps a sweep, passing each
    frequency once, from being weighted by where in a segment it passes), segment mean removed.
    Band kept: ``0 < f``, within ``[f_min_hz, f_max_hz]``, where ``G_xx >= energy_fraction max G_xx``
    (3 %) less the outermost bin at each end of each such run (its estimate is mostly window leakage),
    and the coherence is at least ``coherence_min`` (0.95).

    Parameters
    ----------
    time_s : array_like
        Time [s], uniformly sampled (to 1 % of the step).
    steer, response : array_like
        Steer input and response channel.
    f_min_hz, f_max_hz : float, optional
        Limits of the band [Hz].
    nperseg : int, optional
        Welch segment [samples]; default 10 s, at most a quarter of the record.
    coherence_min, energy_fraction : float
        Thresholds of the band [-].

    Returns
    -------
    FrequencyResponse
        Frequency [Hz], gain, phase [deg] and coherence (dimensionless) over the band kept.
    """
    t = as_time(time_s, min_samples=64)
    x, y = as_values(steer, t.size, "steer"), as_values(response, t.size, "response")
    dt = np.diff(t)
    if np.ptp(dt) > 0.01 * dt.mean():
        raise InputError("the sampling is not uniform; resample onto a uniform time base first", "time_s")
    fs = 1.0 / dt.mean()
    nperseg = int(min(round(SEGMENT_S * fs), t.size // 4) if nperseg is None else nperseg)
    if not 16 <= nperseg <= t.size:
        raise InputError(f"must lie in [16, {t.size}], got {nperseg}", "nperseg")
    kw = dict(fs=fs, window="hann", nperseg=nperseg, noverlap=3 * nperseg // 4, detrend="constant")
    f, pxx = signal.welch(x, **kw)
    _, pyy = signal.welch(y, **kw)
    _, pxy = signal.csd(x, y, **kw)
    with np.errstate(invalid="ignore", divide="ignore"):
        coh, h = np.abs(pxy) ** 2 / (pxx * pyy), pxy / pxx
    energy = pxx >= energy_fraction * pxx.max()
    energy[1:-1] &= energy[:-2] & energy[2:]
    keep = (f > 0) & energy & (np.nan_to_num(coh) >= coherence_min) & (pxx.max() > 0)
    keep &= (f >= (f_min_hz or 0.0)) & (f <= (np.inf if f_max_hz is None else f_max_hz))
    if not keep.any():
        raise InputError("no frequency where the steer has energy and the coherence is high enough; check the "
                         "input, the band or the thresholds", "steer")
    return FrequencyResponse(frequency_hz=f[keep], gain=np.abs(h[keep]),
                             phase_deg=np.degrees(np.unwrap(np.angle(h[keep]))), coherence=coh[keep],
                             nperseg=nperseg)


# ------------------------------------------------------------------------------ ISO 7975 braking in a turn
@dataclass(frozen=True)
class BrakingInTurn(PlainResult):
    """ISO 7975 braking-in-a-turn figures, as defined in :func:`braking_in_turn`.

    Attributes
    ----------
    speed_initial_mps, yaw_rate_initial_radps, lateral_acceleration_initial_mps2 : float
        Values at brake start ``t0`` [m/s, rad/s, m/s^2].
    path_deviation_m, initial_path_deviation_m, path_deviation_max_m : float
        Path deviation at ``t1``, at ``t0``, and of largest magnitude after ``t0`` [m].
    yaw_rate_ratio, lateral_acceleration_ratio : float
        Values at ``t1`` over values at ``t0`` [-].
    yaw_rate_excess_radps, yaw_rate_excess_max_radps, mean_deceleration_mps2 : float
        Yaw-rate excess at ``t1`` and of largest magnitude after ``t0`` [rad/s]; mean deceleration [m/s^2].
    """

    speed_initial_mps: float
    yaw_rate_initial_radps: float
    lateral_acceleration_initial_mps2: float
    path_deviation_m: float
    initial_path_deviation_m: float
    path_deviation_max_m: float
    yaw_rate_ratio: float
    lateral_acceleration_ratio: float
    yaw_rate_excess_radps: float
    yaw_rate_excess_max_radps: float
    mean_deceleration_mps2: float


def braking_in_turn(time_s, x_m, y_m, yaw_rate_radps, speed_mps, lateral_acceleration_mps2, *, brake_start_s,
                    circle_centre_xy, radius_m, eval_after_s=1.0) -> BrakingInTurn:
    """ISO 7975 braking in a turn (open loop), against the steady circle driven before braking.

    ``t0`` is the brake start, ``t1 = t0 + eval_after_s``. Definitions chosen: path deviation ``d(t) = |p(t) - c| - R`` [m], the radial distance from the
    initial circle (positive outside: running wide; negative: turning in); yaw-rate ratio ``psi_dot(t1) /
    psi_dot(t0)`` (a vehicle keeping its path has the speed ratio); yaw-rate excess ``dir psi_dot(t) -
    v(t) / R``, ``dir = sign psi_dot(t0)``: the yaw rate beyond that of a vehicle keeping the initial
    curvature at the actual speed; lateral-acceleration ratio ``a_y(t1) / a_y(t0)``; mean deceleration
    ``(v(t0) - v(t1)) / (t1 - t0)``. Maxima are the signed values of largest magnitude from ``t0`` to the
    end of the record (end it when braking ends or the vehicle stops). Values between samples are
    interpolated linearly.

    Parameters
    ----------
    time_s : array_like
        Time [s], strictly increasing.
    x_m, y_m, yaw_rate_radps, speed_mps, lateral_acceleration_mps2 : array_like
        Position of the CG in the ground frame [m], yaw rate [rad/s], speed [m/s], lateral acceleration
        [m/s^2].
    brake_start_s : float
        Brake start ``t0`` [s].
    circle_centre_xy, radius_m : (float, float), float
        Centre and radius of the initial circle [m].
    eval_after_s : float
        ``t1 - t0`` [s]; ISO 7975 uses 1 s.

    Returns
    -------
    BrakingInTurn
        The figures: deviations [m], yaw-rate ratio and excess [rad/s], lateral-acceleration ratio (dimensionless), mean deceleration [m/s^2].
    """
    t = as_time(time_s)
    x, y, wz, v, ay = (as_values(a, t.size, w) for a, w in (
        (x_m, "x_m"), (y_m, "y_m"), (yaw_rate_radps, "yaw_rate_radps"), (speed_mps, "speed_mps"),
        (lateral_acceleration_mps2, "lateral_acceleration_mps2")))
    radius = positive(radius_m, "radius_m")
    t0 = float(brake_start_s)
    t1 = t0 + positive(eval_after_s, "eval_after_s")
    if not t[0] <= t0 < t1 <= t[-1]:
        raise InputError(f"brake start {t0} s and evaluation time {t1} s must lie within the record "
                         f"[{t[0]}, {t[-1]}] s", "brake_start_s")
    cx, cy = (float(c) for c in circle_centre_xy)
    wz0 = float(np.interp(t0, t, wz))
    if wz0 == 0:
        raise InputError("the yaw rate at brake start is zero: the vehicle is not turning", "yaw_rate_radps")
    dev, excess = np.hypot(x - cx, y - cy) - radius, math.copysign(1.0, wz0) * wz - v / radius

    def at(sig, time):
        """``sig`` at ``time``, interpolated linearly."""
        return float(np.interp(time, t, sig))

    def extreme(sig):
        """The signed value of ``sig`` of largest magnitude from ``t0`` on."""
        window = np.concatenate([[at(sig, t0)], sig[t > t0]])
        return float(window[np.argmax(np.abs(window))])

    ay0 = at(ay, t0)
    return BrakingInTurn(
        speed_initial_mps=at(v, t0), yaw_rate_initial_radps=wz0, lateral_acceleration_initial_mps2=ay0,
        path_deviation_m=at(dev, t1), initial_path_deviation_m=at(dev, t0), path_deviation_max_m=extreme(dev),
        yaw_rate_ratio=at(wz, t1) / wz0, lateral_acceleration_ratio=at(ay, t1) / ay0 if ay0 else math.nan,
        yaw_rate_excess_radps=at(excess, t1), yaw_rate_excess_max_radps=extreme(excess),
        mean_deceleration_mps2=(at(v, t0) - at(v, t1)) / (t1 - t0))
