"""The dossier's transient handling: the ISO 7401 step steer and sine-sweep frequency response at one speed.

Each run is the one ``trikedyn simulate NAME --manoeuvre step|sweep --speed V`` drives (the driver holds the
speed, the manoeuvre's own duration) and its figures are those the command prints under ``figures``
(:func:`trikedyn.analysis.handling_tests.manoeuvre_figures`). The sweep's figures are summed up by
:func:`sweep_summary` (gain at the lowest frequency, the -3 dB frequency, gain and phase at 1 Hz).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["TRANSIENT_SETTINGS", "RESPONSES", "transient_speed", "step_response", "frequency_response",
           "sweep_summary"]

TRANSIENT_SETTINGS = {"speed_kmh": 30.0, "dlc_fraction": 0.8, "speed_control": "driver"}
"""The speed of both tests: ``speed_kmh`` [km/h], lowered to ``dlc_fraction`` of the DLC course threshold
(rounded down to 1 km/h) when that is lower; the speed control as ``trikedyn simulate``'s default."""

RESPONSES = {"yaw_rate": ("yaw rate", "yaw_rate_radps", "deg/s", math.degrees(1.0), "1/s"),
             "lateral_acceleration": ("lateral acceleration", "ay_mps2", "m/s²", 1.0, "m/s² per rad")}
"""Response name -> (words, run channel, plotted unit, factor from the channel's SI unit to it, unit of the
gain per rad of road-wheel steer)."""


def transient_speed(thresholds: dict) -> float:
    """The speed of the step and sweep tests for a state.

    Parameters
    ----------
    thresholds : dict
        The state's thresholds (:func:`trikedyn.assess.runs.thresholds`); ``dlc`` -> ``course_kmh`` [km/h].

    Returns
    -------
    float
        ``TRANSIENT_SETTINGS["speed_kmh"]``, or ``dlc_fraction`` of the DLC course threshold rounded down to
        1 km/h when that is lower (and at least 1 km/h) [km/h].
    """
    s = TRANSIENT_SETTINGS
    course = (thresholds.get("dlc") or {}).get("course_kmh")
    if course is None or not math.isfinite(course):
        return s["speed_kmh"]
    return float(min(s["speed_kmh"], max(1.0, math.floor(s["dlc_fraction"] * course))))


def _run(pset, manoeuvre: str, speed_kmh: float):
    """The run and its figures as ``trikedyn simulate --json`` gives them (``figures`` or ``failure``)."""
    from ..analysis.handling_tests import manoeuvre_figures
    from ..errors import InputError
    from ..simulate.closed_loop import run

    result = run(pset, manoeuvre, speed_kmh=speed_kmh, duration_s=None,
                 speed_control=TRANSIENT_SETTINGS["speed_control"])
    data = {"manoeuvre": manoeuvre, "speed_kmh": speed_kmh, "options": dict(result.manoeuvre.parameters),
            "figures": None, "failure": None}
    if not result.success:
        data["failure"] = result.message
        return data, result
    try:
        data["figures"] = manoeuvre_figures(result)
    except InputError as exc:
        data["failure"] = str(exc)
    if data["figures"] is None and data["failure"] is None:
        data["failure"] = "no judged window"
    return data, result


def _failed_figure(title: str, why: str):
    from ..report.figures import _plt

    fig, ax = _plt().subplots(figsize=(7.0, 2.0))
    ax.axis("off")
    ax.text(0.5, 0.5, f"{title}: no figures ({why})", ha="center", va="center", wrap=True)
    return fig


def step_response(pset, speed_kmh: float):
    """ISO 7401 step steer at ``speed_kmh``, as ``trikedyn simulate --manoeuvre step --speed V --json``.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle, with its payload.
    speed_kmh : float
        Target speed [km/h].

    Returns
    -------
    data : dict
        ``manoeuvre``, ``speed_kmh`` [km/h], ``options`` (the step's: ``steer_deg`` [deg], ``start_s``,
        ``ramp_s``, ``hold_s`` [s]), ``figures`` (``yaw_rate`` and ``lateral_acceleration`` step
        responses: gains, response and peak response times [s], overshoot [1]; ``speed_drift_kmh``) or
        ``failure`` (why there are none).
    figure : matplotlib.figure.Figure
        Yaw rate [deg/s] and lateral acceleration [m/s²] against time [s], the steady value and the peak marked.
    """
    data, result = _run(pset, "step", speed_kmh)
    title = f"ISO 7401 step steer at {speed_kmh:g} km/h"
    if data["figures"] is None:
        return data, _failed_figure(title, data["failure"])
    from ..report.figures import _plt

    start = result.manoeuvre.parameters["start_s"]
    keep = result.time_s >= start - 0.5
    t = result.time_s[keep]
    fig, axes = _plt().subplots(2, 1, figsize=(7.0, 5.0), sharex=True)
    for ax, (key, (words, channel, unit, factor, _gain)) in zip(axes, RESPONSES.items(), strict=True):
        f = data["figures"][key]
        ax.plot(t, np.asarray(result[channel])[keep] * factor, color="C0", lw=1.2)
        ax.axhline(f["steady_state_value"] * factor, color="0.4", lw=0.8, ls="--", label="steady state")
        ax.plot([f["steer_50_time_s"] + f["peak_response_time_s"]], [f["peak_value"] * factor], "o", color="C3", ms=4,
                label=f"peak ({100 * f['overshoot']:.1f} % overshoot)")
        ax.axvline(start, color="0.6", lw=0.8, ls=":")
        ax.set_ylabel(f"{words} [{unit}]")
        ax.legend(loc="lower right", fontsize=8)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s] (dotted: steer step starts)")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return data, fig


def sweep_summary(response: dict) -> dict:
    """Key figures of one frequency response.

    Parameters
    ----------
    response : dict
        A :class:`~trikedyn.analysis.handling.FrequencyResponse` as ``to_dict()`` gives it: ``frequency_hz``
        [Hz], ``gain`` (response per road-wheel steer [unit/rad]), ``phase_deg`` [deg].

    Returns
    -------
    dict
        ``low_frequency_hz`` [Hz] and ``low_frequency_gain`` (at the lowest frequency), ``peak_gain_ratio``
        (highest gain over it) [1], ``minus_3db_hz`` (first frequency where the gain falls below the low one
        over sqrt 2, interpolated; None within the band) [Hz], ``gain_1hz`` and ``phase_1hz_deg`` [deg]
        (interpolated; None outside the band).
    """
    f, gain, phase = (np.asarray(response[k], dtype=float) for k in ("frequency_hz", "gain", "phase_deg"))
    if f.size == 0:
        return {"low_frequency_hz": None, "low_frequency_gain": None, "peak_gain_ratio": None, "minus_3db_hz": None,
                "gain_1hz": None, "phase_1hz_deg": None}
    low = float(gain[0])
    below = np.flatnonzero(gain < low / math.sqrt(2.0))
    minus_3db = None
    if below.size:
        i = int(below[0])
        level = low / math.sqrt(2.0)
        minus_3db = float(f[i - 1] + (level - gain[i - 1]) * (f[i] - f[i - 1]) / (gain[i] - gain[i - 1]))
    inside = f[0] <= 1.0 <= f[-1]
    return {"low_frequency_hz": float(f[0]), "low_frequency_gain": low, "peak_gain_ratio": float(gain.max() / low),
            "minus_3db_hz": minus_3db, "gain_1hz": float(np.interp(1.0, f, gain)) if inside else None,
            "phase_1hz_deg": float(np.interp(1.0, f, phase)) if inside else None}


def frequency_response(pset, speed_kmh: float):
    """ISO 7401 sine-sweep frequency response at ``speed_kmh``, as ``trikedyn simulate --manoeuvre sweep
    --speed V --json``.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle, with its payload.
    speed_kmh : float
        Target speed [km/h].

    Returns
    -------
    data : dict
        ``manoeuvre``, ``speed_kmh`` [km/h], ``options`` (the sweep's: ``amplitude_deg`` [deg],
        ``f_start_hz``, ``f_end_hz`` [Hz], ``sweep_s`` [s], ...), ``figures`` (``yaw_rate`` and
        ``lateral_acceleration``: frequency
        [Hz], gain per road-wheel steer, phase [deg], coherence) or ``failure``, and ``summary`` (per response,
        :func:`sweep_summary`).
    figure : matplotlib.figure.Figure
        Gain and phase [deg] of both responses against frequency [Hz].
    """
    data, _ = _run(pset, "sweep", speed_kmh)
    title = f"ISO 7401 frequency response (sine sweep) at {speed_kmh:g} km/h"
    data["summary"] = None
    if data["figures"] is None:
        return data, _failed_figure(title, data["failure"])
    data["summary"] = {key: sweep_summary(data["figures"][key]) for key in RESPONSES}
    from ..report.figures import _plt

    fig, axes = _plt().subplots(2, 2, figsize=(8.0, 5.0), sharex=True)
    for col, (key, (words, _channel, _unit, _factor, gain_unit)) in enumerate(RESPONSES.items()):
        r, s = data["figures"][key], data["summary"][key]
        gain_ax, phase_ax = axes[0, col], axes[1, col]
        gain_ax.plot(r["frequency_hz"], r["gain"], "o-", color="C0", ms=3)
        gain_ax.set_ylim(bottom=0.0)
        if s["minus_3db_hz"] is not None:
            gain_ax.axvline(s["minus_3db_hz"], color="C3", lw=0.8, ls="--", label="-3 dB")
            gain_ax.legend(fontsize=8)
        gain_ax.set_title(words, fontsize=9)
        gain_ax.set_ylabel(f"gain [{gain_unit}]")
        phase_ax.plot(r["frequency_hz"], r["phase_deg"], "o-", color="C1", ms=3)
        phase_ax.set_ylabel("phase [deg]")
        phase_ax.set_xlabel("frequency [Hz]")
        for ax in (gain_ax, phase_ax):
            ax.grid(alpha=0.3)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return data, fig
