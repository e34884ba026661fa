"""An IMU log in SI units (:class:`ImuLog`) and the names of its columns.

The bottom of the log readers: :mod:`trikedyn.measure.logs` (read, write, detect) and every layout of
:mod:`trikedyn.measure.formats` build on it, and it imports neither.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import LogFormatError, did_you_mean

__all__ = ["CHANNELS", "TEMP", "TIME", "ImuLog"]

TIME = "time_s"
"""The time column [s]."""
CHANNELS = ("ax_mps2", "ay_mps2", "az_mps2", "wx_radps", "wy_radps", "wz_radps",
            "roll_rad", "pitch_rad", "yaw_rad")
"""The nine channels, SI units, in the order of a log's columns."""
TEMP = "temperature_degC"
"""The temperature column [°C]."""


@dataclass(frozen=True, eq=False)
class ImuLog:
    """An IMU log in SI units.

    Attributes
    ----------
    data : pandas.DataFrame
        ``time_s`` [s] first (from the first sample, strictly increasing), then any of ``ax_mps2 ay_mps2
        az_mps2`` [m/s^2], ``wx_radps wy_radps wz_radps`` [rad/s], ``roll_rad pitch_rad yaw_rad`` [rad],
        then extras as the file has them (``temperature_degC`` [°C], ...).
    source : str
        Path of the file read.
    format : str
        A key of :data:`FORMATS`.
    original_columns : dict
        Column of ``data`` -> header (or frame field) in the file.
    notes : tuple of str
        What the reader did that a user should know.
    """

    data: pd.DataFrame
    source: str
    format: str
    original_columns: dict[str, str]
    notes: tuple[str, ...] = ()

    @property
    def sample_rate_hz(self) -> float:
        """Median sample rate [Hz] (NaN with fewer than two samples)."""
        dt = np.diff(self.data[TIME].to_numpy(float))
        return float(np.median(1.0 / dt)) if dt.size else float("nan")

    def to_pandas(self) -> pd.DataFrame:
        """A copy of :attr:`data`.

        Returns
        -------
        pandas.DataFrame
            The copy.
        """
        return self.data.copy()

    def channel(self, name: str) -> np.ndarray:
        """The values of column ``name`` (SI units) as a float array; LogFormatError if absent.

        Parameters
        ----------
        name : str
            A column (``ax_mps2``, ...).

        Returns
        -------
        numpy.ndarray
            Its values, SI units.
        """
        if name not in self.data.columns:
            present = list(self.data.columns)
            raise LogFormatError(f"no channel {name!r}; channels present: {', '.join(present)}"
                                 f"{did_you_mean(name, present)}", where=self.source)
        return self.data[name].to_numpy(dtype=float, copy=True)
