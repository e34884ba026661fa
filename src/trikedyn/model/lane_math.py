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

:func:`arctan`, :func:`arcsin`, :func:`tanh` and :func:`tan` are the same kind, for the tyres over lanes (the
slip angle and the Magic Formula's arctangents, the camber's arcsine, the smoothed signs of the brake and the
rolling resistance, the steering linkage): Cephes' ``atan.c``, ``asin.c`` and ``tanh.c`` (rational
approximations on reduced ranges) with every branch computed and the result selected, and ``exp.c`` with its
power of two built from exact products (no ``ldexp``). Measured against the C library over 10^6 random
arguments each (``tests/model/test_lane_math.py``, which asserts these figures): :func:`arctan` and :func:`arcsin`
within 1 unit in the last place (ulp), :func:`tanh` within 2, :func:`tan` within 3 (|x| <= 1.5; it is
``sin / cos``). A run that does not roll over hardly feels such differences (a bias of 3e-14 on every tyre force
moved 10 s lane changes of both presets by at most 1e-12 of their states); one that rolls over grows them past
1e-9 (``docs/physics.md``, *Speed*, *Lanes that round differently*).
"""

from __future__ import annotations

import numpy as np

from .._jit import jit

__all__ = ["arcsin", "arctan", "sincos", "tan", "tanh"]

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


_PIO2 = 1.57079632679489661923
_PIO4 = 7.85398163397448309616e-1
_T3P8 = 2.41421356237309504880  # tan(3 pi / 8)
_MOREBITS = 6.123233995736765886130e-17  # pi/2 less its double


@jit(inline="always")
def arctan(x):
    """``atan x`` [rad] of a ratio ``x``, branch-free (Cephes ``atan.c``; within 1 ulp of the C library).

    Parameters
    ----------
    x : float
        Any float; NaN gives NaN.

    Returns
    -------
    float
        In ``[-pi/2, pi/2]`` [rad].
    """
    a = abs(x)
    big = a > _T3P8
    mid = (a > 0.66) & (a <= _T3P8)
    # the reduced argument as one quotient: -1/a, (a - 1)/(a + 1) or a/1
    num = -1.0 if big else (a - 1.0 if mid else a)
    den = a if big else (a + 1.0 if mid else 1.0)
    r = num / den
    z = r * r
    p = (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z - 7.500855792314704667340e1) * z
         - 1.228866684490136173410e2) * z - 6.485021904942025371773e1
    q = ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z + 4.328810604912902668951e2) * z
         + 4.853903996359136964868e2) * z + 1.945506571482613964425e2
    w = r * (z * p / q) + r
    w = w + (_MOREBITS if big else (0.5 * _MOREBITS if mid else 0.0))
    y = (_PIO2 if big else (_PIO4 if mid else 0.0)) + w
    y = -y if x < 0.0 else y
    return x if a == 0.0 else y  # the sign of a zero kept


@jit(inline="always")
def arcsin(x):
    """``asin x`` [rad] of ``x`` in ``[-1, 1]``, branch-free (Cephes ``asin.c``; within 1 ulp of the C library).

    Parameters
    ----------
    x : float
        In ``[-1, 1]``; outside it (or NaN) NaN.

    Returns
    -------
    float
        In ``[-pi/2, pi/2]`` [rad].
    """
    a = abs(x)
    # near 1: pi/2 - 2 asin(sqrt((1 - a) / 2)), by a rational function of 1 - a
    zz = 1.0 - a
    r = ((((2.967721961301243206100e-3 * zz - 5.634242780008963776856e-1) * zz + 6.968710824104713396794e0) * zz
          - 2.556901049652824852289e1) * zz + 2.853665548261061424989e1)
    s = ((((zz - 2.194779531642920639778e1) * zz + 1.470656354026814941758e2) * zz - 3.838770957603691357202e2) * zz
         + 3.424398657913078477438e2)
    p_near = zz * r / s
    root = np.sqrt(zz + zz)  # NaN for a > 1, as it should be
    near = ((_PIO4 - root) - (root * p_near - _MOREBITS)) + _PIO4
    # elsewhere: a + a^3 P(a^2) / Q(a^2)
    z2 = a * a
    p = (((((4.253011369004428248960e-3 * z2 - 6.019598008014123785661e-1) * z2 + 5.444622390564711410273e0) * z2
           - 1.626247967210700244449e1) * z2 + 1.956261983317594739197e1) * z2 - 8.198089802484824371615e0)
    q = (((((z2 - 1.474091372988853791896e1) * z2 + 7.049610280856842141659e1) * z2 - 1.471791292232726029859e2)
          * z2 + 1.395105614657485689735e2) * z2 - 4.918853881490881290097e1)
    far = a * (z2 * p / q) + a
    y = near if a > 0.625 else far
    y = -y if x < 0.0 else y
    return x if a == 0.0 else y  # the sign of a zero kept


@jit(inline="always")
def _exp_reduced(x):
    """``e^x`` for ``x`` in ``[0, 41]``, branch-free (Cephes ``exp.c``: ``e^r 2^n``, the power of two an exact
    product of selected powers, so no ``ldexp``)."""
    n = np.floor(1.4426950408889634073599 * x + 0.5)
    r = (x - n * 6.93145751953125e-1) - n * 1.42860682030941723212e-6
    rr = r * r
    p = r * ((1.26177193074810590878e-4 * rr + 3.02994407707441961300e-2) * rr + 9.99999999999999999910e-1)
    q = ((3.00198505138664455042e-6 * rr + 2.52448340349684104192e-3) * rr + 2.27265548208155028766e-1) * rr \
        + 2.00000000000000000009e0
    e = 1.0 + 2.0 * (p / (q - p))
    scale = 1.0  # 2^n, n in [0, 63], bit by bit (each factor exact)
    for bit, power in ((32.0, 4294967296.0), (16.0, 65536.0), (8.0, 256.0), (4.0, 16.0), (2.0, 4.0), (1.0, 2.0)):
        take = n >= bit
        scale *= power if take else 1.0
        n -= bit if take else 0.0
    return e * scale


@jit(inline="always")
def tanh(x):
    """``tanh x`` of ``x``, branch-free (Cephes ``tanh.c``; within 2 ulp of the C library).

    Parameters
    ----------
    x : float
        Any float; NaN gives NaN.

    Returns
    -------
    float
        In ``[-1, 1]``.
    """
    a = abs(x)
    # |x| >= 0.625: 1 - 2 / (e^(2|x|) + 1); beyond |x| = 20 that is 1 to the last bit
    far = 1.0 - 2.0 / (_exp_reduced(2.0 * min(a, 20.0)) + 1.0)
    far = -far if x < 0.0 else far
    s = x * x
    p = (-9.64399179425052238628e-1 * s - 9.92877231001918586564e1) * s - 1.61468768441708447952e3
    q = ((s + 1.12811678491632931402e2) * s + 2.23548839060100448583e3) * s + 4.84406305325125486048e3
    near = x + x * (s * p / q)
    near = x if a == 0.0 else near  # the sign of a zero kept
    return far if a >= 0.625 else near


@jit(inline="always")
def tan(x):
    """``tan x`` of an angle ``x`` [rad], as ``sin x / cos x`` of :func:`sincos` (within 3 ulp of the C library for
    ``|x| <= 1.5``).

    Parameters
    ----------
    x : float
        Angle [rad].

    Returns
    -------
    float
        Its tangent, dimensionless.
    """
    s, c = sincos(x)
    return s / c
