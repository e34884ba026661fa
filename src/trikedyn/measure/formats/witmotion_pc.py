"""``witmotion-pc``: older WitMotion PC software export (tab-separated, ``time DeviceName ChipTime ...``)."""

from ._witmotion import WitMotionText
from .base import register


class WitMotionPc(WitMotionText):
    name = "witmotion-pc"
    description = "older WitMotion PC software export (tab-separated: time DeviceName ChipTime AccX(g)..)"
    order = 20
    pc_columns = ("time", "DeviceName")
    pc_style = "clock"

    def sniff(self, head):
        return 2.0 if {"devicename", "chiptime"} <= head.keys else 0.0


register(WitMotionPc())
