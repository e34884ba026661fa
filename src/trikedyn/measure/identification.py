"""The result of a suspension identification (:func:`trikedyn.measure.suspension.identify_suspension`).

Kept apart from the identification itself: the scalars (JSON-safe), the arrays of the paper's Fig. 2c-d
and the figure.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

__all__ = ["SuspensionIdentification"]


@dataclass(frozen=True)
class SuspensionIdentification:
    """Result of :func:`~trikedyn.measure.suspension.identify_suspension`: SI scalars, ``warnings`` and the arrays of the Fig. 2c-d plot.

    f_n (undamped) and xi come from ``method``; ``spectrum_natural_frequency_hz`` and ``crest_damping_ratio``
    are the paper's estimates, ``crest_damped_frequency_hz`` the crest-period cross-check, ``*_std`` the fit's
    standard errors. K and C are the suspension's (tyre-corrected if asked), ``equivalent_*`` Eqs. 3-4's.
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
        """JSON-safe dict: scalars (NaN as None), ``warnings`` as a list, arrays as lists on request."""
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
        """The scalars as a :class:`pandas.Series`."""
        import pandas as pd
        return pd.Series(self.to_dict())

    def plot(self, ax=None):
        """Fig. 2c-d: record, crests used and fit; spectrum and its peak. ``ax``: None, one or two Axes."""
        import matplotlib.pyplot as plt
        if ax is None:
            fig, axes = plt.subplots(2, 1, figsize=(7.0, 6.0), constrained_layout=True)
        else:
            axes = list(np.atleast_1d(ax))
            fig = axes[0].figure
        a = axes[0]
        a.plot(self.record_time_s, self.record_mps2, ".", ms=3, color="0.6", label="record - offset")
        a.plot(self.time_s, self.signal_mps2, "-", lw=1, label="processed")
        a.plot(self.time_s, self.model_mps2, "--", lw=1, label="free-decay fit")
        a.plot(self.compression_crest_time_s, self.compression_crest_mps2, "^", label="compression crests")
        a.plot(self.extension_crest_time_s, self.extension_crest_mps2, "v", label="extension crests")
        a.set(xlabel="time [s]", ylabel="vertical acceleration [m/s$^2$]",
              title=f"$f_n$ = {self.natural_frequency_hz:.3f} Hz, $\\xi$ = {self.damping_ratio:.3f}")
        a.legend(fontsize="small")
        if len(axes) > 1:
            axes[1].plot(self.spectrum_freq_hz, self.spectrum_magnitude, "-")
            axes[1].axvline(self.spectrum_peak_hz, ls=":", color="k",
                            label=f"peak {self.spectrum_peak_hz:.3f} Hz")
            axes[1].set(xlabel="frequency [Hz]", ylabel="amplitude [m/s$^2$]",
                        xlim=(0.0, min(10.0, self.processed_rate_hz / 2)))
            axes[1].legend(fontsize="small")
        return fig
