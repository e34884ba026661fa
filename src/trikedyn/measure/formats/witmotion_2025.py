"""``witmotion-2025``: the 2025 WitMotion PC software's CSV (``Time, Device name, Chip Time(), ...``)."""

from ._witmotion import WitMotionText
from .base import register


class WitMotion2025(WitMotionText):
    name = "witmotion-2025"
    description = "WitMotion PC software 2025 CSV (Time, Device name, Chip Time(), Acceleration X(g)..)"
    order = 30
    sep = ","
    pc_columns = ("Time", "Device name")

    def sniff(self, head):
        return 2.0 if {"devicename", "chiptime()"} <= head.keys else 0.0


register(WitMotion2025())
