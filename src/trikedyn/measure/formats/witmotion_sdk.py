"""``witmotion-sdk``: text export of WitMotion's Python SDK (tab-separated, GBK ``°``, ``\\r\\r\\n``)."""

from ._witmotion import WitMotionText
from .base import register


class WitMotionSdk(WitMotionText):
    """The text export of WitMotion's Python SDK (see the module docstring): tab-separated, GBK, ``\\r\\r\\n``
    line ends, one row per packet, ``Chiptime`` and the channels in g, deg/s and deg."""

    name = "witmotion-sdk"
    description = "WitMotion Python SDK text export (tab-separated, GBK, one row per packet)"
    order = 10
    chip_style = "sdk"
    encoding = "gbk"
    line_end = "\r\r\n"

    def sniff(self, head):
        """1 when the header holds ``Chiptime`` (a weaker claim than the PC export's 2, whose header holds it too),
        else 0.

        Parameters
        ----------
        head : Head
            The file's first bytes.

        Returns
        -------
        float
            The score.
        """
        return 1.0 if "chiptime" in head.keys else 0.0


register(WitMotionSdk())
