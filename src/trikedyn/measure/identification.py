"""The result of a suspension identification (:func:`trikedyn.measure.suspension.identify_suspension`).

Kept apart from the identification itself: the scalars (JSON-safe), the arrays of the paper's Fig. 2c-d
and the figure.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

__all__ = ["AXIS_NAMES", "SuspensionIdentification"]

#: Accelerometer axis -> the word in the figure labels.
AXIS_NAMES = {"x": "longitudinal", "y": "lateral", "z": "vertical"}


@dataclass(frozen=True)
class SuspensionIdentification:
    """Result of :func:`~trikedyn.measure.suspension.identify_suspension`: SI scalars, ``warnings`` and the arrays of the Fig. 2c-d plot.

    f_n (undamped) and xi come from ``method``; ``spectrum_natural_frequency_hz`` and ``crest_damping_ratio``
    are the paper's estimates, ``crest_damped_frequency_hz`` the crest-period cross-check, ``*_std`` the fit's
    standard errors. K and C are the suspension's own (the tyre in series taken out) when a tyre stiffness was
    given, with the tyre damping and the unsprung mass used, else Eqs. 3-4's; ``equivalent_*`` are always
    Eqs. 3-4's (the paper's, the tyre taken as rigid: tyre-inclusive). A vehicle file takes the suspension's
    own (:mod:`trikedyn.params.springs`).
    """

    natural_frequency_hz: float
    damped_frequency_hz: float
    damping_ratio: float
    log_decrement: float
    log_decrement_compression: float
    log_decrement_extension: float
    stiffness_N_per_m: float
    equivalent_stiffness_N_per_m: float
    damping_Ns_per_m: float
    equivalent_damping_Ns_per_m: float
    cycles_used: int
    sample_rate_hz: float
    processed_rate_hz: float
    sprung_mass_kg: float
    tyre_stiffness_N_per_m: float | None
    tyre_damping_Ns_per_m: float
    unsprung_mass_kg: float
    method: str
    natural_frequency_std_hz: float
    damping_ratio_std: float
    spectrum_peak_hz: float
    spectrum_natural_frequency_hz: float
    crest_damped_frequency_hz: float
    crest_damping_ratio: float
    offset_mps2: float
    noise_std_mps2: float
    decay_start_s: float
    warnings: tuple
    time_s: np.ndarray
    signal_mps2: np.ndarray
    model_mps2: np.ndarray
    record_time_s: np.ndarray
    record_mps2: np.ndarray
    compression_crest_time_s: np.ndarray
    compression_crest_mps2: np.ndarray
    extension_crest_time_s: np.ndarray
    extension_crest_mps2: np.ndarray
    spectrum_freq_hz: np.ndarray
    spectrum_magnitude: np.ndarray

    def to_dict(self, include_arrays=False):
        """JSON-safe dict: scalars (NaN as None), ``warnings`` as a list, arrays as lists on request.

        Parameters
        ----------
        include_arrays : bool
            Include the record and spectrum arrays.

        Returns
        -------
        dict
            The identification (SI units).
        """
        out = {}
        for key, value in asdict(self).items():
            if isinstance(value, np.ndarray):
                if include_arrays:
                    out[key] = [float(v) if np.isfinite(v) else None for v in value]
            elif isinstance(value, tuple):
                out[key] = list(value)
            else:
                out[key] = None if isinstance(value, float) and not math.isfinite(value) else value
        return out

    def to_pandas(self):
        """The scalars as a :class:`pandas.Series`.

        Returns
        -------
        pandas.Series
            The scalars.
        """
        import pandas as pd
        return pd.Series(self.to_dict())

    def decay_window(self, periods_before=1.0, envelope_fraction=0.03, min_periods=3.0, max_periods=10.0):
        """Time span [s] of the bump response: ``(start, end)`` for the zoomed panel of :meth:`plot`.

        Starts ``periods_before`` damped periods before the response rises above a few % of its peak (or
        before ``decay_start_s``, whichever is earlier) and ends when the fitted envelope has fallen to
        ``envelope_fraction`` of its start, kept between ``min_periods`` and ``max_periods`` periods after
        the decay start and never before the last crest used. The whole record if the fit failed.

        Parameters
        ----------
        periods_before : float
            Damped periods shown before the response, dimensionless.
        envelope_fraction : float
            Envelope level that ends it, dimensionless.
        min_periods, max_periods : float
            Bounds on the periods shown after the decay start, dimensionless.

        Returns
        -------
        start, end : float
            Times [s].
        """
        t = np.asarray(self.record_time_s, float)
        full = (float(t[0]), float(t[-1])) if t.size else (0.0, 1.0)
        fd, fn, xi, t0 = self.damped_frequency_hz, self.natural_frequency_hz, self.damping_ratio, self.decay_start_s
        if not all(math.isfinite(v) for v in (fd, fn, xi, t0)) or fd <= 0 or fn <= 0:
            return full
        period = 1.0 / fd
        y = np.abs(np.asarray(self.record_mps2, float))
        finite = np.isfinite(y)
        onset = t0
        if finite.any():
            level = max(0.05 * float(np.max(y[finite])), 4.0 * (self.noise_std_mps2 if math.isfinite(self.noise_std_mps2) else 0.0))
            above = np.flatnonzero(finite & (y > level) & (t <= t0))
            if above.size:
                # the first excursion of the run of samples that ends at the decay start
                gaps = np.flatnonzero(np.diff(t[above]) > 2.0 * period)
                onset = float(t[above[gaps[-1] + 1]] if gaps.size else t[above[0]])
        start = min(onset, t0) - periods_before * period
        decay = math.log(1.0 / envelope_fraction) / (2 * math.pi * fn * max(xi, 1e-6))
        end = t0 + min(max(decay, min_periods * period), max_periods * period)
        crests = np.concatenate([self.compression_crest_time_s, self.extension_crest_time_s])
        crests = crests[np.isfinite(crests)]
        if crests.size:
            end = max(end, float(crests.max()) + 0.5 * period)
        start, end = max(start, full[0]), min(end, full[1])
        return (start, end) if end > start else full

    def plot(self, ax=None, axis="z"):
        """Fig. 2c-d: bump response (zoomed, the full record inset), crests and fit; spectrum to Nyquist.

        ``ax``: None, one or two Axes (the time panel, then the spectrum). ``axis``: the accelerometer axis
        identified, ``"x"``, ``"y"`` or ``"z"``, for the labels.

        Parameters
        ----------
        ax : matplotlib.axes.Axes or sequence of two, optional
            Where to draw.
        axis : {"x", "y", "z"}
            Accelerometer axis, for the labels.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        import matplotlib.pyplot as plt
        if axis not in AXIS_NAMES:
            raise ValueError(f"axis must be one of {sorted(AXIS_NAMES)}, got {axis!r}")
        quantity = f"{AXIS_NAMES[axis]} acceleration"
        if ax is None:
            fig, axes = plt.subplots(2, 1, figsize=(7.0, 6.5), constrained_layout=True,
                                     gridspec_kw={"height_ratios": [1.4, 1.0]})
        else:
            axes = list(np.atleast_1d(ax))
            fig = axes[0].figure
        lo, hi = self.decay_window()
        a = axes[0]
        a.plot(self.record_time_s, self.record_mps2, ".", ms=4, color="0.6", label="record - offset")
        a.plot(self.time_s, self.signal_mps2, "-", lw=1, label="processed")
        a.plot(self.time_s, self.model_mps2, "--", lw=1, label="free-decay fit")
        a.plot(self.compression_crest_time_s, self.compression_crest_mps2, "^", label="compression crests")
        a.plot(self.extension_crest_time_s, self.extension_crest_mps2, "v", label="extension crests")
        if math.isfinite(self.decay_start_s):
            a.axvline(self.decay_start_s, ls=":", color="k", lw=0.8, label="decay start")
        a.set_xlim(lo, hi)
        inside = (self.record_time_s >= lo) & (self.record_time_s <= hi) & np.isfinite(self.record_mps2)
        if inside.any():
            peak = float(np.max(np.abs(self.record_mps2[inside])))
            if peak > 0:
                a.set_ylim(-1.15 * peak, 1.6 * peak)  # head room for the inset
        a.set(xlabel="time [s]", ylabel=f"{quantity} [m/s$^2$]",
              title=f"$f_n$ = {self.natural_frequency_hz:.3f} Hz, $\\xi$ = {self.damping_ratio:.3f}")
        a.legend(fontsize="x-small", loc="lower right", ncol=2)
        full = (float(self.record_time_s[0]), float(self.record_time_s[-1])) if len(self.record_time_s) else (lo, hi)
        if hi - lo < 0.8 * (full[1] - full[0]):
            inset = a.inset_axes([0.6, 0.68, 0.38, 0.28])
            inset.plot(self.record_time_s, self.record_mps2, "-", lw=0.6, color="0.4")
            inset.axvspan(lo, hi, color="C1", alpha=0.3, lw=0)
            inset.set_xlim(*full)
            inset.set_title("full record", fontsize="x-small", pad=2)
            inset.tick_params(labelsize="xx-small", length=2, pad=1)
        if len(axes) > 1:
            nyquist = self.sample_rate_hz / 2
            keep = self.spectrum_freq_hz <= nyquist * (1 + 1e-9)
            s = axes[1]
            s.plot(self.spectrum_freq_hz[keep], self.spectrum_magnitude[keep], "-", label="spectrum")
            s.axvline(self.spectrum_peak_hz, ls=":", color="k", label=f"peak {self.spectrum_peak_hz:.3f} Hz")
            if math.isfinite(self.natural_frequency_hz) and self.natural_frequency_hz <= nyquist:
                s.axvline(self.natural_frequency_hz, ls="--", color="C3",
                          label=f"identified $f_n$ {self.natural_frequency_hz:.3f} Hz")
            s.set(xlabel="frequency [Hz]", ylabel=f"{quantity} amplitude [m/s$^2$]", xlim=(0.0, nyquist),
                  title=f"spectrum up to Nyquist ({nyquist:.3g} Hz at {self.sample_rate_hz:.3g} Hz sampling)")
            s.legend(fontsize="small")
        return fig
