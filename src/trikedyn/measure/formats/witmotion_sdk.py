"""``witmotion-sdk``: text export of WitMotion's Python SDK (tab-separated, GBK ``°``, ``\\r\\r\\n``)."""

from ._witmotion import WitMotionText
from .base import register


class WitMotionSdk(WitMotionText):
    name = "witmotion-sdk"
    description = "WitMotion Python SDK text export (tab-separated, GBK, one row per packet)"
    order = 10
    chip_style = "sdk"
    encoding = "gbk"
    line_end = "\r\r\n"

    def sniff(self, head):
        return 1.0 if "chiptime" in head.keys else 0.0


register(WitMotionSdk())
