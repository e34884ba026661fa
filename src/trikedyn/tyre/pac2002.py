"""The full Magic Formula (PAC2002 / MF 5.2; MF 6.1 at nominal pressure), compiled with numba.

Equations: Pacejka, *Tyre and Vehicle Dynamics*, 2nd ed. (2006), section 4.3.2, eqs. (4.E1)-(4.E78), as
the PAC2002 / MF-Tyre 5.2 property files use them (ISO slips ``alpha* = tan(alpha) sgn(Vcx)``, ``gamma* =
sin(gamma)``; book-style equivalent slip angles (4.E77), (4.E78)). MF 6.1/6.2 files (3rd ed., 2012, and the
TNO MF-Tyre 6.1 equations; evaluated with ``sin(gamma)`` throughout) get the MF 6.1 forms of the lateral
camber terms (``PKY4..7``, ``PEY5``, ``SHy`` and ``SVy`` through the camber stiffness), the combined-slip
camber terms (``RBX3``, ``RBY4``), the residual-torque camber terms (``QDZ10``, ``QDZ11``), the aligning
torque on the zero-camber side force, the full overturning couple (``QSX1..14``) and the MF 6.1 rolling
resistance (``QSY1..7``), all at the nominal inflation pressure (every pressure term drops out).

Sign convention: ISO (the TYDEX W-axis system the property files are written in)
--------------------------------------------------------------------------------
Axes at the contact point: ``x`` forward along the wheel plane, ``y`` to the left, ``z`` up: the axes of
ISO 8855 and of the rest of trikedyn. Inputs: ``kappa = -Vsx / |Vcx|`` (positive when driving, gives
``Fx > 0``); slip angle ``alpha`` with ``tan(alpha) = Vcy / |Vcx|`` (positive when the contact centre
slides to the *left*: it gives a *negative* ``Fy``, to the right, and a positive aligning torque ``Mz``;
the cornering stiffness ``dFy/dalpha`` is negative, as ``PKY1`` is); inclination ``gamma`` positive about
``+x`` (the wheel top leaning to the right). Outputs: ``Fx``, ``Fy`` [N] and ``Mx``, ``My``, ``Mz`` [N m]
on the wheel along/about ``x``, ``y``, ``z``; ``My`` opposes forward rolling (negative for ``Vcx > 0``).

To trikedyn's :mod:`~trikedyn.tyre.magic_formula` convention (same axes, ``tan(alpha_td) = -vy / |vx|``):
pass ``alpha = -alpha_td``; ``kappa``, ``gamma`` and every output map unchanged.

Validity ranges and mirroring
-----------------------------
``kappa``, ``alpha`` and ``gamma`` are clamped to the file's ranges (``alpha`` also to ``|alpha| <=
ALPHA_LIMIT``, below 90 deg, where ``tan`` is finite); a load outside ``[FZMIN, FZMAX]`` is evaluated at the
nearest bound and every force and moment scaled by ``Fz / Fz_bound`` (friction coefficients and normalised
stiffnesses frozen at the bound: forces vanish continuously as ``Fz -> 0``); ``Fz <= 0`` gives zeros. The
kernels return a bit mask of what was clamped (``CLAMPED_FZ | CLAMPED_KAPPA | CLAMPED_ALPHA |
CLAMPED_GAMMA``). A tyre used on the other side than its ``TYRESIDE`` is mirrored: evaluated at
``(-alpha, -gamma)`` with ``Fy``, ``Mx``, ``Mz`` negated.

Not modelled: turn slip, the low-speed model of MF-Tyre (``VXLOW``; trikedyn regularises slips itself,
:func:`~trikedyn.tyre.magic_formula.slip_quantities`), transient (relaxation) dynamics beyond the lengths,
reversed rolling beyond ``alpha* = tan(alpha) sgn(Vcx)`` (4.E3) and the sign of ``My``, pressure changes.

A tyre file is packed into the vector these kernels read by :func:`~trikedyn.tyre.pac2002_pack.pack`; forces over
arrays of inputs are :func:`~trikedyn.tyre.pac2002_arrays.forces` and :func:`~trikedyn.tyre.pac2002_arrays.pure_forces`.
"""

from __future__ import annotations

import math

from .._jit import jit

__all__ = [
    "ALPHA_LIMIT", "CLAMPED_ALPHA", "CLAMPED_FZ", "CLAMPED_GAMMA", "CLAMPED_KAPPA", "LAYOUT", "N_PACKED",
    "clamped_names", "mf_forces", "mf_forces_into", "mf_pure_forces", "mf_relaxation_lengths", "mf_stiffness",
    "mf_vertical_force",
]

# ---- the packed coefficient vector: its layout (names as in the .tir file; the last five derived) ----------
LAYOUT = (
    "FNOMIN UNLOADED_RADIUS LFZO LONGVL VERTICAL_STIFFNESS VERTICAL_DAMPING FZMIN FZMAX KPUMIN KPUMAX "
    "ALPMIN ALPMAX CAMMIN CAMMAX LCX LMUX LEX LKX LHX LVX LGAX LCY LMUY LEY LKY LHY LVY LGAY LTR LRES LGAZ "
    "LXAL LYKA LVYKA LS LSGKP LSGAL LMX LVMX LMY LKYC LKZC "
    "PCX1 PDX1 PDX2 PDX3 PEX1 PEX2 PEX3 PEX4 PKX1 PKX2 PKX3 PHX1 PHX2 PVX1 PVX2 RBX1 RBX2 RBX3 RCX1 REX1 REX2 "
    "RHX1 PTX1 PTX2 PTX3 QSX1 QSX2 QSX3 QSX4 QSX5 QSX6 QSX7 QSX8 QSX9 QSX10 QSX11 QSX12 QSX13 QSX14 "
    "PCY1 PDY1 PDY2 PDY3 PEY1 PEY2 PEY3 PEY4 PEY5 PKY1 PKY2 PKY3 PKY4 PKY5 PKY6 PKY7 PHY1 PHY2 PHY3 "
    "PVY1 PVY2 PVY3 PVY4 RBY1 RBY2 RBY3 RBY4 RCY1 REY1 REY2 RHY1 RHY2 RVY1 RVY2 RVY3 RVY4 RVY5 RVY6 PTY1 PTY2 "
    "QSY1 QSY2 QSY3 QSY4 QSY5 QSY6 QSY7 QBZ1 QBZ2 QBZ3 QBZ4 QBZ5 QBZ9 QBZ10 QCZ1 QDZ1 QDZ2 QDZ3 QDZ4 "
    "QDZ6 QDZ7 QDZ8 QDZ9 QDZ10 QDZ11 QEZ1 QEZ2 QEZ3 QEZ4 QEZ5 QHZ1 QHZ2 QHZ3 QHZ4 SSZ1 SSZ2 SSZ3 SSZ4 "
    "LONGITUDINAL_STIFFNESS LATERAL_STIFFNESS PCFX1 PCFX2 PCFY1 PCFY2 "
    "FZ0P MIRROR MF6 ALO AHI"
).split()
"""Names of the packed vector's entries, in order (:func:`~trikedyn.tyre.pac2002_pack.pack` writes it)."""
# fmt: off
(FNOMIN, UNLOADED_RADIUS, LFZO, LONGVL, VERTICAL_STIFFNESS, VERTICAL_DAMPING, FZMIN, FZMAX, KPUMIN, KPUMAX,
 ALPMIN, ALPMAX, CAMMIN, CAMMAX, LCX, LMUX, LEX, LKX, LHX, LVX, LGAX, LCY, LMUY, LEY, LKY, LHY, LVY, LGAY, LTR,
 LRES, LGAZ, LXAL, LYKA, LVYKA, LS, LSGKP, LSGAL, LMX, LVMX, LMY, LKYC, LKZC,
 PCX1, PDX1, PDX2, PDX3, PEX1, PEX2, PEX3, PEX4, PKX1, PKX2, PKX3, PHX1, PHX2, PVX1, PVX2, RBX1, RBX2, RBX3,
 RCX1, REX1, REX2, RHX1, PTX1, PTX2, PTX3, QSX1, QSX2, QSX3, QSX4, QSX5, QSX6, QSX7, QSX8, QSX9, QSX10, QSX11,
 QSX12, QSX13, QSX14, PCY1, PDY1, PDY2, PDY3, PEY1, PEY2, PEY3, PEY4, PEY5, PKY1, PKY2, PKY3, PKY4, PKY5, PKY6,
 PKY7, PHY1, PHY2, PHY3, PVY1, PVY2, PVY3, PVY4, RBY1, RBY2, RBY3, RBY4, RCY1, REY1, REY2, RHY1, RHY2, RVY1,
 RVY2, RVY3, RVY4, RVY5, RVY6, PTY1, PTY2, QSY1, QSY2, QSY3, QSY4, QSY5, QSY6, QSY7, QBZ1, QBZ2, QBZ3, QBZ4,
 QBZ5, QBZ9, QBZ10, QCZ1, QDZ1, QDZ2, QDZ3, QDZ4, QDZ6, QDZ7, QDZ8, QDZ9, QDZ10, QDZ11, QEZ1, QEZ2, QEZ3, QEZ4,
 QEZ5, QHZ1, QHZ2, QHZ3, QHZ4, SSZ1, SSZ2, SSZ3, SSZ4, LONGITUDINAL_STIFFNESS, LATERAL_STIFFNESS, PCFX1, PCFX2,
 PCFY1, PCFY2, FZ0P, MIRROR, MF6, ALO, AHI) = range(len(LAYOUT))
# fmt: on
N_PACKED = len(LAYOUT)  #: length of the packed vector
assert all(globals()[name] == i for i, name in enumerate(LAYOUT))  # the names above match the layout

ALPHA_LIMIT = 1.5707  #: largest |slip angle| evaluated [rad] (89.99 deg; tan(alpha) ~ 1e4)
CLAMPED_FZ, CLAMPED_KAPPA, CLAMPED_ALPHA, CLAMPED_GAMMA = 1, 2, 4, 8  #: bits of the clamp mask
_EPS = 1e-9  #: keeps B = K / (C D) finite when D = 0 [N]


# ---- compiled kernels ----------------------------------------------------------------------------------
@jit(inline="always")
def _sgn(x):
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


@jit(inline="always")
def _mf_arg(b, x, e):
    """``atan(B x - E (B x - atan(B x)))``: the Magic Formula's inner angle [rad]."""
    bx = b * x
    return math.atan(bx - e * (bx - math.atan(bx)))


@jit(inline="always")
def _clamp(x, lo, hi):
    """``x`` within ``[lo, hi]`` (NaN stays NaN) and whether it moved."""
    if x < lo:
        return lo, True
    if x > hi:
        return hi, True
    return x, False


@jit(inline="always")
def _inputs(fz, kappa, alpha, gamma, c):
    """Mirrored and clamped inputs, the load scale and the clamp mask."""
    if c[MIRROR] != 0.0:
        alpha, gamma = -alpha, -gamma
    fz_c, m_fz = _clamp(fz, c[FZMIN], c[FZMAX])
    kappa, m_k = _clamp(kappa, c[KPUMIN], c[KPUMAX])
    alpha, m_a = _clamp(alpha, c[ALO], c[AHI])
    gamma, m_g = _clamp(gamma, c[CAMMIN], c[CAMMAX])
    mask = CLAMPED_FZ * m_fz + CLAMPED_KAPPA * m_k + CLAMPED_ALPHA * m_a + CLAMPED_GAMMA * m_g
    return fz_c, fz / fz_c, kappa, alpha, gamma, mask


@jit(inline="always")
def _lateral(fz, dfz, a, gy, c):
    """Pure side slip (4.E19)-(4.E30): Fy0, muy, Kya, K'ya, By, Cy, SHy, SVy at ``alpha* = a``, ``gamma_y``."""
    fz0p = c[FZ0P]
    cy = c[PCY1] * c[LCY]  # (4.E21)
    muy = (c[PDY1] + c[PDY2] * dfz) * (1.0 - c[PDY3] * gy * gy) * c[LMUY]  # (4.E23)
    dy = muy * fz  # (4.E22)
    kya = (c[PKY1] * fz0p * math.sin(c[PKY4] * math.atan(fz / ((c[PKY2] + c[PKY5] * gy * gy) * fz0p)))
           * (1.0 - c[PKY3] * abs(gy)) * c[LKY])  # (4.E25)
    kyap = kya + math.copysign(_EPS, kya)  # (4.E39)
    if c[MF6] != 0.0:  # MF 6.1: camber through the camber stiffness (4.E28), (4.E30)
        kyg0 = fz * (c[PKY6] + c[PKY7] * dfz) * c[LKYC]
        svyg = fz * (c[PVY3] + c[PVY4] * dfz) * gy * c[LKYC] * c[LMUY]
        shy = (c[PHY1] + c[PHY2] * dfz) * c[LHY] + (kyg0 * gy - svyg) / kyap  # (4.E27)
        svy = fz * (c[PVY1] + c[PVY2] * dfz) * c[LVY] * c[LMUY] + svyg  # (4.E29)
    else:  # PAC2002 / MF 5.2
        shy = (c[PHY1] + c[PHY2] * dfz) * c[LHY] + c[PHY3] * gy
        svy = fz * ((c[PVY1] + c[PVY2] * dfz) * c[LVY] + (c[PVY3] + c[PVY4] * dfz) * gy) * c[LMUY]
    ay = a + shy  # (4.E20)
    ey = min((c[PEY1] + c[PEY2] * dfz) * (1.0 + c[PEY5] * gy * gy - (c[PEY3] + c[PEY4] * gy) * _sgn(ay))
             * c[LEY], 1.0)  # (4.E24)
    by = kya / (cy * dy + math.copysign(_EPS, cy * dy))  # (4.E26)
    fy0 = dy * math.sin(cy * _mf_arg(by, ay, ey)) + svy  # (4.E19)
    return fy0, muy, kya, kyap, by, cy, shy, svy


@jit(inline="always")
def _residual(dr, br, ar, cos_a):
    """Residual torque ``Mzr = Dr cos(atan(Br alpha_r)) cos(alpha)`` [N m] (4.E36), (4.E75); ``Cr = 1``."""
    return dr / math.sqrt(1.0 + (br * ar) ** 2) * cos_a


@jit
def _evaluate(fz, kappa, alpha, gamma, vcx, c, combined):
    """Fx, Fy, Mz, Mx, My and the clamp mask; combined slip (4.E50)-(4.E78) or pure slip."""
    if fz <= 0.0:  # out of contact (NaN goes on, to be seen)
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0
    fz, scale, kappa, alpha, gamma, mask = _inputs(fz, kappa, alpha, gamma, c)
    fz0p, r0, fnom = c[FZ0P], c[UNLOADED_RADIUS], c[FNOMIN]
    dfz = (fz - fz0p) / fz0p  # (4.E2)
    sv = 1.0 if vcx >= 0.0 else -1.0
    a = math.tan(alpha) * sv  # alpha* (4.E3)
    g = math.sin(gamma)  # gamma* (4.E4)
    cos_a = math.cos(alpha)
    # pure longitudinal slip (4.E9)-(4.E18)
    gx = g * c[LGAX]
    cx = c[PCX1] * c[LCX]
    dx = (c[PDX1] + c[PDX2] * dfz) * (1.0 - c[PDX3] * gx * gx) * c[LMUX] * fz
    kx = fz * (c[PKX1] + c[PKX2] * dfz) * math.exp(c[PKX3] * dfz) * c[LKX]
    bx = kx / (cx * dx + math.copysign(_EPS, cx * dx))
    kxs = kappa + (c[PHX1] + c[PHX2] * dfz) * c[LHX]
    ex = min((c[PEX1] + c[PEX2] * dfz + c[PEX3] * dfz * dfz) * (1.0 - c[PEX4] * _sgn(kxs)) * c[LEX], 1.0)
    fx0 = dx * math.sin(cx * _mf_arg(bx, kxs, ex)) + fz * (c[PVX1] + c[PVX2] * dfz) * c[LVX] * c[LMUX]
    # pure side slip
    gy = g * c[LGAY]
    fy0, muy, kya, kyap, by, cy, shy, svy = _lateral(fz, dfz, a, gy, c)
    fy0_trail = fy0
    if c[MF6] != 0.0:  # MF 6.1: the trail acts on the zero-camber side force (4.E32)
        fy0_trail = _lateral(fz, dfz, a, 0.0, c)[0]
    # aligning torque, pure slip quantities (4.E31)-(4.E49)
    gz = g * c[LGAZ]
    at = a + c[QHZ1] + c[QHZ2] * dfz + (c[QHZ3] + c[QHZ4] * dfz) * gz  # (4.E34), (4.E35)
    ar = a + shy + svy / kyap  # (4.E37), (4.E38)
    bt = ((c[QBZ1] + c[QBZ2] * dfz + c[QBZ3] * dfz * dfz) * (1.0 + c[QBZ4] * gz + c[QBZ5] * abs(gz))
          * c[LKY] / c[LMUY])  # (4.E40)
    ct = c[QCZ1]  # (4.E41)
    dt = fz * (c[QDZ1] + c[QDZ2] * dfz) * (1.0 + c[QDZ3] * gz + c[QDZ4] * gz * gz) * r0 / fz0p * c[LTR]  # (4.E42)
    et = min((c[QEZ1] + c[QEZ2] * dfz + c[QEZ3] * dfz * dfz)
             * (1.0 + (c[QEZ4] + c[QEZ5] * gz) * (2.0 / math.pi) * math.atan(bt * ct * at)), 1.0)  # (4.E44)
    br = c[QBZ9] * c[LKY] / c[LMUY] + c[QBZ10] * by * cy  # (4.E45)
    dr = (fz * r0 * ((c[QDZ6] + c[QDZ7] * dfz) * c[LRES]
                     + ((c[QDZ8] + c[QDZ9] * dfz) + (c[QDZ10] + c[QDZ11] * dfz) * abs(gz)) * gz * c[LKZC])
          * c[LMUY])  # (4.E47)
    if combined:
        # Fx: weighting by alpha (4.E50)-(4.E57); cos(atan(x)) = 1/sqrt(1 + x^2)
        bxa = (c[RBX1] + c[RBX3] * g * g) / math.sqrt(1.0 + (c[RBX2] * kappa) ** 2) * c[LXAL]
        exa = min(c[REX1] + c[REX2] * dfz, 1.0)
        fx = (math.cos(c[RCX1] * _mf_arg(bxa, a + c[RHX1], exa))
              / math.cos(c[RCX1] * _mf_arg(bxa, c[RHX1], exa))) * fx0
        # Fy: weighting by kappa and kappa-induced side force (4.E58)-(4.E67)
        byk = (c[RBY1] + c[RBY4] * g * g) / math.sqrt(1.0 + (c[RBY2] * (a - c[RBY3])) ** 2) * c[LYKA]
        eyk = min(c[REY1] + c[REY2] * dfz, 1.0)
        shyk = c[RHY1] + c[RHY2] * dfz
        gyk = math.cos(c[RCY1] * _mf_arg(byk, kappa + shyk, eyk)) / math.cos(c[RCY1] * _mf_arg(byk, shyk, eyk))
        dvyk = muy * fz * (c[RVY1] + c[RVY2] * dfz + c[RVY3] * g) / math.sqrt(1.0 + (c[RVY4] * a) ** 2)
        fy = gyk * fy0 + dvyk * math.sin(c[RVY5] * math.atan(c[RVY6] * kappa)) * c[LVYKA]
        # Mz: equivalent slip angles (4.E77), (4.E78), arm of Fx (4.E76), (4.E71)
        k2 = (kx / kyap) ** 2 * kappa * kappa
        at_eq = math.sqrt(at * at + k2) * _sgn(at)
        ar_eq = math.sqrt(ar * ar + k2) * _sgn(ar)
        t = dt * math.cos(ct * _mf_arg(bt, at_eq, et)) * cos_a  # (4.E73)
        mzr = _residual(dr, br, ar_eq, cos_a)
        s = r0 * (c[SSZ1] + c[SSZ2] * fy / fz0p + (c[SSZ3] + c[SSZ4] * dfz) * g) * c[LS]
        mz = -t * gyk * fy0_trail + mzr + s * fx  # F'y = Fy - SVyk = Gyk Fy0 (4.E74)
    else:
        fx, fy = fx0, fy0
        t = dt * math.cos(ct * _mf_arg(bt, at, et)) * cos_a  # (4.E33)
        mz = -t * fy0_trail + _residual(dr, br, ar, cos_a)  # (4.E31)
    # overturning couple (4.E69, with the MF 6.1 terms) and rolling resistance (4.E70)
    mx = r0 * fz * c[LMX] * (c[QSX1] * c[LVMX] - c[QSX2] * g + c[QSX3] * fy / fnom)
    if c[MF6] != 0.0:
        mx += r0 * c[LMX] * (fz * (c[QSX4] * math.cos(c[QSX5] * math.atan((c[QSX6] * fz / fnom) ** 2))
                                   * math.sin(c[QSX7] * g + c[QSX8] * math.atan(c[QSX9] * fy / fnom))
                                   + c[QSX10] * math.atan(c[QSX11] * fz / fnom) * g)
                             + fy * (c[QSX13] + c[QSX14] * abs(g)) - fz * c[QSX12] * g * abs(g))
    vr = vcx / c[LONGVL]
    roll = c[QSY1] + c[QSY2] * fx / fnom + c[QSY3] * abs(vr) + c[QSY4] * vr ** 4
    if c[MF6] != 0.0:
        my = -r0 * fnom * c[LMY] * (roll + (c[QSY5] + c[QSY6] * fz / fnom) * g * g) * (fz / fnom) ** c[QSY7]
    else:
        my = -r0 * fz * c[LMY] * roll
    my *= _sgn(vcx)
    m = -1.0 if c[MIRROR] != 0.0 else 1.0
    return fx * scale, m * fy * scale, m * mz * scale, m * mx * scale, my * scale, mask


@jit
def mf_forces(fz, kappa, alpha, gamma, vcx, c):
    """Tyre forces and moments in combined slip (USE_MODE 4), ISO axes.

    Parameters
    ----------
    fz : float
        Vertical load [N]; zeros for ``fz <= 0``.
    kappa : float
        Longitudinal slip [1], positive driving.
    alpha : float
        Slip angle [rad], ISO: ``tan(alpha) = Vcy / |Vcx|``.
    gamma : float
        Inclination angle [rad], ISO (about ``+x``).
    vcx : float
        Forward speed of the wheel centre [m/s]: the sign of ``alpha*`` (4.E3), rolling resistance.
    c : numpy.ndarray
        Packed coefficients (:func:`~trikedyn.tyre.pac2002_pack.pack`).

    Returns
    -------
    fx, fy, mz, mx, my : float
        [N], [N], [N m], [N m], [N m].
    mask : int
        ``CLAMPED_*`` bits of the inputs that left the validity ranges.
    """
    return _evaluate(fz, kappa, alpha, gamma, vcx, c, True)


@jit
def mf_pure_forces(fz, kappa, alpha, gamma, vcx, c):
    """As :func:`mf_forces`, uncombined (USE_MODE 3): ``Fx0(kappa)``, ``Fy0(alpha)``, ``Mz0(alpha)``.

    Parameters
    ----------
    fz : float
        Vertical load [N].
    kappa : float
        Longitudinal slip, dimensionless.
    alpha : float
        Slip angle [rad], ISO.
    gamma : float
        Inclination angle [rad], ISO.
    vcx : float
        Forward speed of the wheel centre [m/s].
    c : numpy.ndarray
        Packed coefficients (:func:`~trikedyn.tyre.pac2002_pack.pack`).

    Returns
    -------
    fx, fy, mz, mx, my : float
        Forces [N] and moments [N m], as :func:`mf_forces`.
    mask : int
        The clamp flags.
    """
    return _evaluate(fz, kappa, alpha, gamma, vcx, c, False)


@jit
def mf_stiffness(fz, gamma, c):
    """Slip stiffnesses ``(Kxk, Kya)`` [N], [N/rad] (4.E15), (4.E25): slopes at the shifted origin, ISO sign.

    Parameters
    ----------
    fz : float
        Vertical load [N].
    gamma : float
        Inclination angle [rad].
    c : numpy.ndarray
        Packed coefficients (:func:`~trikedyn.tyre.pac2002_pack.pack`).

    Returns
    -------
    kxk : float
        Longitudinal slip stiffness [N].
    kya : float
        Cornering stiffness [N/rad], ISO sign.
    """
    if fz <= 0.0:
        return 0.0, 0.0
    fz, scale, _, _, gamma, _ = _inputs(fz, 0.0, 0.0, gamma, c)
    dfz = (fz - c[FZ0P]) / c[FZ0P]
    g = math.sin(gamma) * c[LGAY]
    kx = fz * (c[PKX1] + c[PKX2] * dfz) * math.exp(c[PKX3] * dfz) * c[LKX]
    kya = (c[PKY1] * c[FZ0P] * math.sin(c[PKY4] * math.atan(fz / ((c[PKY2] + c[PKY5] * g * g) * c[FZ0P])))
           * (1.0 - c[PKY3] * abs(g)) * c[LKY])
    return kx * scale, kya * scale


@jit
def mf_relaxation_lengths(fz, gamma, c):
    """Relaxation lengths ``(sigma_kappa, sigma_alpha)`` [m] at a load [N] and inclination [rad].

    PAC2002 / MF 5.2: ``sigma_kappa = Fz (PTX1 + PTX2 dfz) exp(-PTX3 dfz) R0 / Fz0 LSGKP``,
    ``sigma_alpha = PTY1 sin(2 atan(Fz / (PTY2 F'z0))) (1 - PKY3 |gamma|) R0 LFZO LSGAL``. MF 6.1:
    ``|Kxk / Cx|``, ``|Kya / Cy|`` with the carcass stiffnesses ``Cx = LONGITUDINAL_STIFFNESS (1 + PCFX1 dfz
    + PCFX2 dfz^2)``, ``Cy`` likewise. NaN when the file lacks the data (no ``PTX1``/``PTX2``, no ``PTY1`` or
    ``PTY2``; no carcass stiffness).

    Parameters
    ----------
    fz : float
        Vertical load [N].
    gamma : float
        Inclination angle [rad].
    c : numpy.ndarray
        Packed coefficients (:func:`~trikedyn.tyre.pac2002_pack.pack`).

    Returns
    -------
    sigma_kappa, sigma_alpha : float
        Relaxation lengths [m] (0 for ``fz <= 0``, NaN without data).
    """
    if fz <= 0.0:
        return 0.0, 0.0
    fz, _, _, _, gamma, _ = _inputs(fz, 0.0, 0.0, gamma, c)
    dfz = (fz - c[FZ0P]) / c[FZ0P]
    if c[MF6] != 0.0:
        kx, kya = mf_stiffness(fz, gamma, c)
        cx = c[LONGITUDINAL_STIFFNESS] * (1.0 + c[PCFX1] * dfz + c[PCFX2] * dfz * dfz)
        cy = c[LATERAL_STIFFNESS] * (1.0 + c[PCFY1] * dfz + c[PCFY2] * dfz * dfz)
        sk = abs(kx / (cx if cx > 0.0 else 1.0))  # no division by zero, not even a speculated one
        sa = abs(kya / (cy if cy > 0.0 else 1.0))
        return (sk if cx > 0.0 else math.nan), (sa if cy > 0.0 else math.nan)
    r0 = c[UNLOADED_RADIUS]
    sk = math.nan  # a file without PTX / PTY data has no relaxation lengths
    if c[PTX1] != 0.0 or c[PTX2] != 0.0:
        sk = fz * (c[PTX1] + c[PTX2] * dfz) * math.exp(-c[PTX3] * dfz) * r0 / c[FNOMIN] * c[LSGKP]
    sa = math.nan
    if c[PTY1] != 0.0 and c[PTY2] != 0.0:
        sa = (c[PTY1] * math.sin(2.0 * math.atan(fz / (c[PTY2] * c[FZ0P]))) * (1.0 - c[PKY3] * abs(gamma * c[LGAY]))
              * r0 * c[LFZO] * c[LSGAL])
    return sk, sa


@jit
def mf_vertical_force(deflection, rate, c):
    """``max(0, VERTICAL_STIFFNESS d + VERTICAL_DAMPING d')`` [N] for a deflection ``d`` [m] > 0, else 0.

    Parameters
    ----------
    deflection : float
        Tyre deflection [m].
    rate : float
        Deflection rate [m/s].
    c : numpy.ndarray
        Packed coefficients (:func:`~trikedyn.tyre.pac2002_pack.pack`).

    Returns
    -------
    float
        Vertical force [N].
    """
    if not deflection > 0.0:
        return 0.0
    return max(c[VERTICAL_STIFFNESS] * deflection + c[VERTICAL_DAMPING] * rate, 0.0)


@jit
def mf_forces_into(fz, kappa, alpha, gamma, vcx, c, combined, out, mask):
    """Forces and moments over flat arrays of inputs, into ``out`` and ``mask`` (for :mod:`~trikedyn.tyre.pac2002_arrays`).

    Parameters
    ----------
    fz, kappa, alpha, gamma, vcx : numpy.ndarray, shape (n,)
        Vertical load [N], longitudinal slip [1], slip angle [rad], inclination [rad], forward speed [m/s].
    c : numpy.ndarray
        Packed coefficients (:func:`~trikedyn.tyre.pac2002_pack.pack`).
    combined : bool
        Combined slip (:func:`mf_forces`) or pure slip (:func:`mf_pure_forces`).
    out : numpy.ndarray, shape (5, n)
        Written with ``Fx, Fy, Mz, Mx, My`` [N, N, N m, N m, N m].
    mask : numpy.ndarray of int64, shape (n,)
        Written with the clamp masks.
    """
    for i in range(fz.size):
        fx, fy, mz, mx, my, m = _evaluate(fz[i], kappa[i], alpha[i], gamma[i], vcx[i], c, combined)
        out[0, i], out[1, i], out[2, i], out[3, i], out[4, i], mask[i] = fx, fy, mz, mx, my, m


# ---- the clamp mask in words -------------------------------------------------------------------------------
def clamped_names(mask: int) -> list[str]:
    """Names (``fz``, ``kappa``, ``alpha``, ``gamma``) of the bits set in a clamp mask.

    Parameters
    ----------
    mask : int
        Bit mask of ``CLAMPED_*`` flags.

    Returns
    -------
    list of str
        The names, in the order fz, kappa, alpha, gamma.
    """
    bits = ((CLAMPED_FZ, "fz"), (CLAMPED_KAPPA, "kappa"), (CLAMPED_ALPHA, "alpha"), (CLAMPED_GAMMA, "gamma"))
    return [name for bit, name in bits if int(mask) & bit]
