"""``phyphox``: the CSV export of the phyphox phone app (RWTH Aachen): quoted headers with units,
``"Time (s)","Acceleration x (m/s^2)",...``, comma-separated with a decimal point, or (its "semicolon,
decimal comma" export) ``;`` with a decimal comma, or tab-separated.

``Acceleration x/y/z`` (the "Acceleration with g" experiment) is what an accelerometer reads, gravity
included: ``ax_mps2 ay_mps2 az_mps2``. ``Linear Acceleration x/y/z`` (gravity removed by the phone) is read
into the same columns, with a note: it reads 0 at rest, not +9.81 m/s². ``Gyroscope x/y/z (rad/s)`` is
``wx_radps wy_radps wz_radps``. The axes are the phone's (x to the right of the screen, y up along it, z out
of it): mount the phone so that they are the vehicle's, or map the columns (``columns=``, ``--column``).
Other columns (``Absolute acceleration``, ...) are kept as extras.
"""

from __future__ import annotations

import csv

from .._log_tables import _norm
from ..imu_log import TIME
from .base import register
from .generic_csv import GenericCsv

HEADERS = {
    "time(s)": TIME,
    "accelerationx(m/s^2)": "ax_mps2", "accelerationy(m/s^2)": "ay_mps2", "accelerationz(m/s^2)": "az_mps2",
    "linearaccelerationx(m/s^2)": "ax_mps2", "linearaccelerationy(m/s^2)": "ay_mps2",
    "linearaccelerationz(m/s^2)": "az_mps2",
    "gyroscopex(rad/s)": "wx_radps", "gyroscopey(rad/s)": "wy_radps", "gyroscopez(rad/s)": "wz_radps",
}
"""phyphox headers (reduced: lower case, no spaces) -> SI names."""


def _key(header: str) -> str:
    return _norm(header.strip().strip('"'))


class Phyphox(GenericCsv):
    """The phyphox app's CSV export (see the module docstring)."""

    name = "phyphox"
    description = "phyphox phone app CSV export: \"Time (s)\", \"Acceleration x (m/s^2)\", ..., any separator"
    order = 55

    def sniff(self, head):
        """3 when the header holds ``Time (s)`` and a phyphox acceleration or gyroscope column.

        Parameters
        ----------
        head : Head
            The file's first bytes.

        Returns
        -------
        float
            3 or 0.
        """
        keys = {_key(h) for h in head.first.split(head.sep)} if head.sep else set()
        return 3.0 if "time(s)" in keys and len(keys & set(HEADERS)) >= 2 else 0.0

    def default_columns(self, header):
        """The phyphox headers found, by their SI names (the first of each), and headers that are SI names.

        Parameters
        ----------
        header : list of str
            The table's headers.

        Returns
        -------
        dict of str to str
            SI name -> header.
        """
        found = super().default_columns(header)
        for h in header:
            si = HEADERS.get(_key(h))
            if si is not None and si not in found:
                found[si] = h
        return found

    def read(self, raw, path, options):
        """As :class:`~trikedyn.measure.formats.generic_csv.GenericCsv`, with the phyphox headers mapped.

        Parameters
        ----------
        raw : bytes
            The file's bytes.
        path : Path
            The file, for errors.
        options : ReadOptions
            What the caller asked for (sensor, rate [Hz], columns, units, ...).

        Returns
        -------
        ImuLog
            The log, SI columns (time [s], accelerations [m/s^2], rates [rad/s], angles [rad]).
        """
        log = super().read(raw, path, options)
        linear = [c for c, h in log.original_columns.items() if _key(h).startswith("linearacceleration")]
        if linear:
            from dataclasses import replace

            note = (f"{', '.join(linear)} from phyphox's linear acceleration (gravity removed by the phone): 0 at "
                    "rest, not +9.81 m/s2")
            log = replace(log, notes=(*log.notes, note))
        return log


    def write(self, data, path):
        """phyphox's headers (quoted, comma-separated, decimal point; the numbers in full) for the time,
        acceleration and gyroscope columns, the others under their own names.

        Parameters
        ----------
        data : pandas.DataFrame
            SI columns (``time_s`` [s] increasing, ...).
        path : Path
            The file to write.
        """
        names = {si: header for header, si in _WRITTEN.items()}
        table = data.rename(columns={c: names.get(c, c) for c in data.columns})
        table.to_csv(path, index=False, quoting=csv.QUOTE_NONNUMERIC)


_WRITTEN = {"Time (s)": TIME, "Acceleration x (m/s^2)": "ax_mps2", "Acceleration y (m/s^2)": "ay_mps2",
            "Acceleration z (m/s^2)": "az_mps2", "Gyroscope x (rad/s)": "wx_radps", "Gyroscope y (rad/s)": "wy_radps",
            "Gyroscope z (rad/s)": "wz_radps"}

register(Phyphox())
