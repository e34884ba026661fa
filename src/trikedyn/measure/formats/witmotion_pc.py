"""``witmotion-pc``: older WitMotion PC software export (tab-separated, ``time DeviceName ChipTime ...``)."""

from ._witmotion import WitMotionText
from .base import register


class WitMotionPc(WitMotionText):
    """The older WitMotion PC software's export (see the module docstring): tab-separated, PC clock, device
    name, ``ChipTime``, the channels in g, °/s and °, temperature."""

    name = "witmotion-pc"
    description = "older WitMotion PC software export (tab-separated: time DeviceName ChipTime AccX(g)..)"
    order = 20
    pc_columns = ("time", "DeviceName")
    pc_style = "clock"

    def sniff(self, head):
        """2 when the header holds ``DeviceName`` and ``ChipTime``, else 0.

        Parameters
        ----------
        head : Head
            The file's first bytes.

        Returns
        -------
        float
            The score.
        """
        return 2.0 if {"devicename", "chiptime"} <= head.keys else 0.0


register(WitMotionPc())
