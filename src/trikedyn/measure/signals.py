"""Signal processing of a sampled record: uniform grid, band-limited resampling, wavelet denoising, the peak
of a spectrum and the crests of an oscillation.

Generic tools, with no equation of the paper: :mod:`trikedyn.measure.suspension` chains them (with the fit
of :mod:`trikedyn.measure.decay`) into the paper's identification of a suspension from a speed-bump record.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pywt
from scipy import signal as sps

from trikedyn.errors import InputError

from .limits import MAX_RESAMPLED_SAMPLES

__all__ = ["find_crests", "scalar_or_array", "spectrum_peak", "uniform_record", "upsample", "wavelet_denoise"]


def scalar_or_array(x):
    """``x`` as a float if it is 0-d, else as it is: functions of scalars return scalars.

    Parameters
    ----------
    x : float or numpy.ndarray
        A result.

    Returns
    -------
    float or numpy.ndarray
        ``x``.
    """
    return float(x) if np.ndim(x) == 0 else x


def uniform_record(time_s, signal):
    """The record on a uniform grid at its median step (linear interpolation when the steps jitter).

    Parameters
    ----------
    time_s, signal : array_like
        Time stamps [s], strictly increasing, and samples (any unit).

    Returns
    -------
    time_s, signal : ndarray
        Uniform time [s] (the input's own when its steps are uniform to 1 ppm) and samples.
    rate_hz : float
        Rate of the grid [Hz]: one over the median step.
    """
    t, x = np.asarray(time_s, float), np.asarray(signal, float)
    step = float(np.median(np.diff(t)))
    if np.max(np.abs(np.diff(t) - step)) <= 1e-6 * step:
        return t, x, 1.0 / step
    grid = t[0] + step * np.arange(math.floor((t[-1] - t[0]) / step + 1e-9) + 1)
    return grid, np.interp(grid, t, x), 1.0 / step


def upsample(time_s, signal, rate_hz, *, padtype="line"):
    """Band-limited resampling to a higher rate, as the paper did before its analysis.

    Jittered time stamps are first interpolated linearly to a uniform grid at the median rate fs, then
    :func:`scipy.signal.resample_poly` (polyphase Kaiser FIR) resamples by ``up/down ~ rate_hz / fs``.

    Parameters
    ----------
    time_s, signal : array_like
        Time stamps [s], strictly increasing, and samples (any unit).
    rate_hz : float
        Target rate [Hz]; at or below fs the uniform record is returned.
    padtype : str, optional
        Values assumed beyond the ends (see resample_poly); ``"reflect"`` suits a record that starts at its
        largest excursion.

    Returns
    -------
    time_s, signal : ndarray
        Resampled time [s] and signal, within the original time span.

    Raises
    ------
    InputError
        The resampled record would exceed :data:`~trikedyn.measure.limits.MAX_RESAMPLED_SAMPLES` samples.
    """
    t, x, fs = uniform_record(time_s, signal)
    if rate_hz <= fs * (1.0 + 1e-9):
        return t, x
    if (t[-1] - t[0]) * rate_hz > MAX_RESAMPLED_SAMPLES:
        raise InputError(f"{t[-1] - t[0]:.4g} s at {rate_hz:g} Hz make {(t[-1] - t[0]) * rate_hz:.3g} samples, at most "
                         f"{MAX_RESAMPLED_SAMPLES}", where="rate_hz")
    ratio = Fraction(float(rate_hz) / fs).limit_denominator(64)
    up, down = ratio.numerator, ratio.denominator
    y = sps.resample_poly(x, up, down, padtype=padtype)
    ty = t[0] + np.arange(len(y)) * down / (up * fs)
    keep = ty <= t[-1] + 1e-9 / fs
    return ty[keep], y[keep]


def wavelet_denoise(signal, wavelet="dmey", level=None, *, sigma=None):
    """Wavelet denoising (Discrete Meyer, as in the paper) by soft universal thresholding.

    Details of levels 1..``level`` are soft-thresholded at ``sigma sqrt(2 ln N)``; the approximation is kept.
    The finest band [fs/4, fs/2] must hold noise only and the approximation band [0, fs / 2^(level+1)] the
    oscillation: :func:`~trikedyn.measure.suspension.identify_suspension` chooses ``level`` so.

    Parameters
    ----------
    signal : array_like
        Uniformly sampled signal.
    wavelet : str, optional
        PyWavelets wavelet name.
    level : int, optional
        Levels thresholded; the deepest the length allows by default; 0 returns a copy.
    sigma : float, optional
        Noise standard deviation (signal unit); by default the MAD / 0.6745 of the finest details.

    Returns
    -------
    ndarray
        The denoised signal, same length.
    """
    x = np.asarray(signal, float)
    w = pywt.Wavelet(wavelet)
    deepest = pywt.dwt_max_level(len(x), w.dec_len)
    level = deepest if level is None else min(int(level), deepest)
    if level < 1:
        return x.copy()
    coeffs = pywt.wavedec(x, w, level=level, mode="symmetric")
    sigma = np.median(np.abs(coeffs[-1])) / 0.6745 if sigma is None else sigma
    thr = sigma * math.sqrt(2.0 * math.log(len(x)))
    coeffs = [coeffs[0]] + [pywt.threshold(c, thr, mode="soft") for c in coeffs[1:]]
    return pywt.waverec(coeffs, w, mode="symmetric")[: len(x)]


def _parabola(y_m, y_0, y_p):
    """Offset [samples] and value of the vertex of the parabola through three equally spaced points."""
    den = y_m - 2.0 * y_0 + y_p
    if den == 0.0:
        return 0.0, y_0
    p = 0.5 * (y_m - y_p) / den
    return p, y_0 - 0.25 * (y_m - y_p) * p


def spectrum_peak(signal, fs, window="hann", pad_factor=8, *, fmin=0.0, fmax=None):
    """Peak of a windowed, zero-padded FFT amplitude spectrum, refined by a parabola on the log magnitude.

    Parameters
    ----------
    signal : array_like
        Uniform samples, offset removed.
    fs : float
        Sampling rate [Hz].
    window : str, tuple or array_like, optional
        :func:`scipy.signal.get_window` spec, or the window samples themselves.
    pad_factor : int, optional
        The FFT length is the power of two at or above ``pad_factor`` times the length.
    fmin, fmax : float, optional
        Band searched [Hz].

    Returns
    -------
    peak_hz : float
        Interpolated peak frequency [Hz].
    freq_hz, magnitude : ndarray
        One-sided spectrum [Hz] and amplitude (a sine of amplitude A peaks near A).
    """
    x = np.asarray(signal, float)
    win = sps.get_window(window, len(x), fftbins=False) if isinstance(window, (str, tuple)) \
        else np.asarray(window, float)
    nfft = 1 << math.ceil(math.log2(len(x) * max(1, int(pad_factor))))
    mag = np.abs(np.fft.rfft(x * win, nfft)) * 2.0 / np.sum(win)
    freq = np.fft.rfftfreq(nfft, 1.0 / fs)
    band = np.flatnonzero((freq >= max(fmin, freq[1])) & (freq <= (fs / 2.0 if fmax is None else fmax)))
    k = band[np.argmax(mag[band])]
    inner = 0 < k < len(mag) - 1 and np.all(mag[k - 1:k + 2] > 0.0)
    p = _parabola(*np.log(mag[k - 1:k + 2]))[0] if inner else 0.0
    return (k + p) * fs / nfft, freq, mag


def find_crests(time_s, signal, min_prominence):
    """Compression crests (maxima) and extension crests (minima), alternating, vertex-refined.

    With z up a compressed suspension pushes the body up: compression crests are acceleration maxima. Of two
    successive crests of one polarity the larger is kept.

    Parameters
    ----------
    time_s, signal : array_like
        Uniform time [s] and signal.
    min_prominence : float
        Least prominence of a crest (signal unit), a few times the noise floor.

    Returns
    -------
    times, values, polarity : ndarray
        Crest times [s], values, and polarity (+1 compression, -1 extension).
    """
    t, x = np.asarray(time_s, float), np.asarray(signal, float)
    found = []
    for sign in (1.0, -1.0):
        for i in sps.find_peaks(sign * x, prominence=min_prominence)[0]:
            p, v = _parabola(*x[i - 1:i + 2]) if 0 < i < len(x) - 1 else (0.0, x[i])
            found.append((t[i] + p * (t[1] - t[0]), v, sign))
    kept = []
    for crest in sorted(found):
        if kept and kept[-1][2] == crest[2]:
            kept[-1] = max(kept[-1], crest, key=lambda c: abs(c[1]))
        else:
            kept.append(crest)
    arr = np.array(kept).reshape(-1, 3)
    return arr[:, 0], arr[:, 1], arr[:, 2]
