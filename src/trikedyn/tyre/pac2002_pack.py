"""The one packing of a ``.tir`` file's coefficients into the vector the compiled Magic Formula reads.

:func:`pack` writes every coefficient the kernels of :mod:`trikedyn.tyre.pac2002` read, by the names of the
file, in the order of :data:`~trikedyn.tyre.pac2002.LAYOUT`, and derives the last five entries (``F'z0``, the
mirroring flag, the MF 6.1 flag and the slip-angle range). A key of the other family (PAC2002 / MF 6.1) is
set to its neutral value.
"""

from __future__ import annotations

import numpy as np

from .pac2002 import AHI, ALO, ALPHA_LIMIT, ALPMAX, ALPMIN, FNOMIN, FZ0P, LAYOUT, LFZO, MF6, MIRROR, N_PACKED
from .tir import TyreProperties

__all__ = ["pack"]

_MF6_NEUTRAL = {"LKYC": 1.0, "LKZC": 1.0, "PKY4": 2.0, "LONGITUDINAL_STIFFNESS": 0.0, "LATERAL_STIFFNESS": 0.0}
"""The MF 6.1 keys' values that leave a PAC2002 file's equations as they are."""


def pack(tir: TyreProperties, side: str | None = None) -> np.ndarray:
    """The one packing of a tyre's coefficients into the float64 vector the compiled kernels read.

    Parameters
    ----------
    tir : TyreProperties
        The tyre (:func:`~trikedyn.tyre.tir.read_tir`).
    side : {'left', 'right', None}
        The vehicle side the tyre is mounted on; mirrored when it differs from ``tir.tyre_side`` (never for
        ``SYMMETRIC``). None: as measured.

    Returns
    -------
    numpy.ndarray
        float64 vector of length ``N_PACKED``; the module constants (``FNOMIN``, ``PKY1``, ...) index it.
        Keys of the other family are neutral (PAC2002: no MF 6.1 terms; MF 6.1: ``LGAX = LGAY = LGAZ = 1``,
        no ``PHY3``, no ``PTX``/``PTY`` lengths).
    """
    c = np.zeros(N_PACKED, dtype=np.float64)
    coefficients = dict(_MF6_NEUTRAL) | {"LGAX": 1.0, "LGAY": 1.0, "LGAZ": 1.0, "LSGKP": 1.0, "LSGAL": 1.0}
    coefficients |= {k: v for k, v in tir.coefficients.items() if k in LAYOUT}
    if not tir.mf6:
        coefficients |= _MF6_NEUTRAL | {"PEY5": 0.0, "PKY5": 0.0, "PKY6": 0.0, "PKY7": 0.0}
    for i, name in enumerate(LAYOUT[:FZ0P]):
        c[i] = coefficients.get(name, 0.0)
    c[FZ0P] = c[FNOMIN] * c[LFZO]  # F'z0 (4.E1)
    if side is not None:
        side = side.strip().upper()
        if side not in ("LEFT", "RIGHT"):
            raise ValueError(f"side must be 'left', 'right' or None, got {side!r}")
        c[MIRROR] = float(tir.tyre_side != "SYMMETRIC" and side != tir.tyre_side)
    c[MF6] = float(tir.mf6)
    c[ALO], c[AHI] = max(c[ALPMIN], -ALPHA_LIMIT), min(c[ALPMAX], ALPHA_LIMIT)
    return c
