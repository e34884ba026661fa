"""``witmotion-2025``: the 2025 WitMotion PC software's CSV (``Time, Device name, Chip Time(), ...``)."""

from ._witmotion import WitMotionText
from .base import register


class WitMotion2025(WitMotionText):
    """The 2025 WitMotion PC software's CSV (see the module docstring): PC time, device name, ``Chip Time()``,
    the channels in g, °/s and °, temperature."""

    name = "witmotion-2025"
    description = "WitMotion PC software 2025 CSV (Time, Device name, Chip Time(), Acceleration X(g)..)"
    order = 30
    sep = ","
    pc_columns = ("Time", "Device name")

    def sniff(self, head):
        """2 when the header holds ``Device name`` and ``Chip Time()``, else 0.

        Parameters
        ----------
        head : Head
            The file's first bytes.

        Returns
        -------
        float
            The score.
        """
        return 2.0 if {"devicename", "chiptime()"} <= head.keys else 0.0


register(WitMotion2025())
