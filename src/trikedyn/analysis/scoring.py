"""The verdict of a comparison: error metrics per channel and the :class:`Comparison` that holds two aligned
records with them.

Per channel, the measured side being the reference and the difference simulated minus measured
(:func:`channel_metrics`): the root-mean-square difference, the same over the measured range, the largest
difference and Pearson's correlation. :func:`trikedyn.analysis.compare.compare` aligns and resamples the two
records (:mod:`trikedyn.analysis.alignment`) and returns a :class:`Comparison`: its metrics, the aligned
records (:meth:`Comparison.to_pandas`), a JSON-safe summary (:meth:`Comparison.to_dict`) and a figure
(:meth:`Comparison.plot`, as the paper's Figs. 7-8).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import InputError, did_you_mean
from .alignment import DEFAULT_ALIGN, TIME

__all__ = ["ChannelComparison", "Comparison", "channel_metrics"]


@dataclass(frozen=True)
class ChannelComparison:
    """Error metrics of one channel; the difference is simulated minus measured.

    Attributes
    ----------
    channel : str
        Channel name (its unit is the name's suffix).
    rmse : float
        Root-mean-square difference [channel unit].
    nrmse : float
        ``rmse`` over the range (max - min) of the measured (reference) channel [-]; NaN if that range is 0.
    peak_error : float
        Largest absolute difference [channel unit].
    correlation : float
        Pearson correlation coefficient [-]; NaN if either side is constant.
    n_samples : int
        Number of samples of the common time base the metrics use.
    """

    channel: str
    rmse: float
    nrmse: float
    peak_error: float
    correlation: float
    n_samples: int


@dataclass(frozen=True)
class Comparison:
    """Two tables aligned in time, resampled onto a common base, and their per-channel metrics.

    Attributes
    ----------
    offset_s : float
        Time shift [s]: measured time + ``offset_s`` = simulated time (an event at measured time ``t``
        happens at simulated time ``t + offset_s``).
    rate_hz : float
        Rate of the common time base [Hz].
    channels : tuple of ChannelComparison
        Metrics, one per compared channel.
    time_s : ndarray
        Common time base [s], in the simulated clock.
    measured, simulated : dict of str to ndarray
        Each compared channel resampled onto ``time_s`` (the measured one shifted by ``offset_s``).
    align_on : str or None
        Channel the offset was found on; None if no alignment was made.
    labels : tuple of str
        Names of the two sides (legend of :meth:`plot`).
    """

    offset_s: float
    rate_hz: float
    channels: tuple[ChannelComparison, ...]
    time_s: np.ndarray
    measured: dict[str, np.ndarray]
    simulated: dict[str, np.ndarray]
    align_on: str | None = DEFAULT_ALIGN
    labels: tuple[str, str] = ("measured", "simulated")

    def __getitem__(self, channel: str) -> ChannelComparison:
        """The metrics of ``channel``; InputError naming the compared channels if it was not compared."""
        for c in self.channels:
            if c.channel == channel:
                return c
        raise InputError(unknown_channel(channel, [c.channel for c in self.channels], "compared"), where="channel")

    def to_dict(self) -> dict:
        """JSON-safe summary: ``offset_s``, ``rate_hz``, ``align_on`` and per channel the metrics.

        NaN and infinite values become None.

        Returns
        -------
        dict
            The summary.
        """
        return {
            "offset_s": _json_float(self.offset_s),
            "rate_hz": _json_float(self.rate_hz),
            "align_on": self.align_on,
            "channels": {c.channel: {"rmse": _json_float(c.rmse), "nrmse": _json_float(c.nrmse),
                                     "peak_error": _json_float(c.peak_error),
                                     "correlation": _json_float(c.correlation), "n_samples": int(c.n_samples)}
                         for c in self.channels},
        }

    def to_pandas(self) -> pd.DataFrame:
        """The aligned records: ``time_s`` [s] (simulated clock), then ``measured_<channel>`` and
        ``simulated_<channel>`` per channel; ``attrs`` hold ``offset_s``, ``rate_hz`` and ``align_on``.

        Returns
        -------
        pandas.DataFrame
            The aligned records.
        """
        data = {TIME: self.time_s}
        for c in self.channels:
            data[f"measured_{c.channel}"] = self.measured[c.channel]
            data[f"simulated_{c.channel}"] = self.simulated[c.channel]
        frame = pd.DataFrame(data)
        frame.attrs.update(offset_s=self.offset_s, rate_hz=self.rate_hz, align_on=self.align_on)
        return frame

    def plot(self, channels=None):
        """Measured over simulated, one axis per channel (as the paper's Figs. 7-8); returns the Figure.

        Parameters
        ----------
        channels : sequence of str, optional
            Channels to draw (default: all compared ones).

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        import matplotlib.pyplot as plt

        names = [c.channel for c in self.channels] if channels is None else list(channels)
        metrics = [self[name] for name in names]
        if not metrics:
            raise InputError("no channel to plot; pass one or more compared channels", where="channels")
        fig, axes = plt.subplots(len(metrics), 1, sharex=True, figsize=(7, 2.0 * len(metrics)), squeeze=False)
        for ax, m in zip(axes[:, 0], metrics, strict=True):
            ax.plot(self.time_s, self.measured[m.channel], label=self.labels[0], color="k", lw=1.0)
            ax.plot(self.time_s, self.simulated[m.channel], label=self.labels[1], color="tab:red", lw=1.2,
                    ls="--")
            ax.set_ylabel(m.channel)
            ax.set_title(f"RMSE {m.rmse:.3g}, NRMSE {m.nrmse:.1%}, r = {m.correlation:.3f}", fontsize=8,
                         loc="right")
            ax.grid(alpha=0.3)
        axes[0, 0].legend(loc="upper left", fontsize=8)
        axes[-1, 0].set_xlabel(f"time [s] ({self.labels[1]} clock; {self.labels[0]} shifted by "
                               f"{self.offset_s:+.3f} s)")
        fig.tight_layout()
        return fig


def channel_metrics(measured, simulated, *, channel: str = "") -> ChannelComparison:
    """Error metrics of two equally long records on the same time base; measured is the reference.

    Parameters
    ----------
    measured, simulated : array_like
        Values [channel unit] at the same times.
    channel : str
        Name stored in the result.

    Returns
    -------
    ChannelComparison
        ``rmse = sqrt(mean((s - m)^2))``, ``nrmse = rmse / (max(m) - min(m))`` (NaN if that range is 0),
        ``peak_error = max|s - m|``, ``correlation`` = Pearson's r (NaN if either side is constant),
        ``n_samples``.
    """
    m = np.asarray(measured, dtype=float)
    s = np.asarray(simulated, dtype=float)
    if m.shape != s.shape or m.ndim != 1 or m.size == 0:
        raise InputError(f"measured and simulated must be 1-D of equal, non-zero length; got {m.shape} and "
                         f"{s.shape}", where=f"channel {channel!r}" if channel else None)
    diff = s - m
    rmse = float(np.sqrt(np.mean(diff * diff)))
    span = float(m.max() - m.min())
    nrmse = rmse / span if span > 0 else math.nan
    dm, ds = m - m.mean(), s - s.mean()
    den = math.sqrt(float(dm @ dm) * float(ds @ ds))
    corr = float(np.clip((dm @ ds) / den, -1.0, 1.0)) if den > 0 else math.nan
    return ChannelComparison(channel, rmse, nrmse, float(np.max(np.abs(diff))), corr, int(m.size))


def _json_float(value: float) -> float | None:
    value = float(value)
    return value if math.isfinite(value) else None


def unknown_channel(name: str, choices: list[str], what: str) -> str:
    """'unknown channel NAME; WHAT channels: ...; did you mean ...?' for an error message."""
    return f"unknown channel {name!r}; {what} channels: {', '.join(choices) or 'none'}{did_you_mean(name, choices)}"
