"""Sine and cosine without branches or library calls, for kernels that run over a batch's lanes.

numba compiles ``math.sin`` and ``np.cos`` to calls into the C library, and LLVM cannot vectorise a loop
that calls a function (the package registry's llvmlite has no vector math library): one such call in the
body of a loop over lanes keeps the whole loop scalar. :func:`sincos` is plain arithmetic and selects, so a
loop over lanes that uses it vectorises.

The method is that of Cephes (S. L. Moshier, *Methods and Programs for Mathematical Functions*, 1989,
``sin.c``): the argument is reduced to ``r`` in ``[-pi/4, pi/4]`` by the nearest multiple ``j`` of
``pi/2``, subtracted in three parts (Cody and Waite) so that ``r`` is exact to the last bit for ``|x|`` up
to about ``1e8``; ``sin r`` and ``cos r`` are Cephes' minimax polynomials of degree 13 and 14; the
quadrant ``j mod 4`` swaps and negates them. Measured against the C library (``tests/model/test_lane_math.py``):
within 2.3e-16 absolute of ``math.sin`` and ``math.cos`` on ``|x| <= 4`` and within 4.5e-16 up to
``|x| = 1e4`` (a wheel's spin angle after an hour at 100 km/h is about 1e5 rad: 1e-15). The functions are
IEEE arithmetic (no fast-math), so every compile of them rounds alike.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit

__all__ = ["sincos"]

_PIO2_1 = 2.0 * 7.85398125648498535156e-1  # pi/2 in three parts (Cephes DP1..DP3 doubled, exactly)
_PIO2_2 = 2.0 * 3.77489470793079817668e-8
_PIO2_3 = 2.0 * 2.69515142907905952645e-15
_TWO_OVER_PI = 0.63661977236758134308


@jit(inline="always")
def sincos(x):
    """``(sin x, cos x)`` of an angle ``x`` [rad], branch-free (see the module docstring for the accuracy).

    Parameters
    ----------
    x : float
        Angle [rad], ``|x|`` below about 1e8.

    Returns
    -------
    sin_x, cos_x : float
        Its sine and cosine, dimensionless.
    """
    j = np.floor(x * _TWO_OVER_PI + 0.5)  # the nearest quadrant
    r = ((x - j * _PIO2_1) - j * _PIO2_2) - j * _PIO2_3  # in [-pi/4, pi/4]
    z = r * r
    sin_r = r + r * z * (((((1.58962301576546568060e-10 * z - 2.50507477628578072866e-8) * z
                            + 2.75573136213857245213e-6) * z - 1.98412698295895385996e-4) * z
                          + 8.33333333332211858878e-3) * z - 1.66666666666666307295e-1)
    cos_r = 1.0 - 0.5 * z + z * z * (((((-1.13585365213876817300e-11 * z + 2.08757008419747316778e-9) * z
                                       - 2.75573141792967388112e-7) * z + 2.48015872888517045348e-5) * z
                                     - 1.38888888888730564116e-3) * z + 4.16666666666665929218e-2)
    quadrant = j - 4.0 * np.floor(j * 0.25)  # j mod 4, as a float: 0, 1, 2 or 3
    odd = (quadrant == 1.0) | (quadrant == 3.0)
    sin_q = cos_r if odd else sin_r
    cos_q = sin_r if odd else cos_r
    sin_x = -sin_q if quadrant >= 2.0 else sin_q
    cos_x = -cos_q if (quadrant == 1.0) | (quadrant == 2.0) else cos_q
    return sin_x, cos_x
