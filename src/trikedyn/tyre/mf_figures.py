"""Figures of a Magic Formula tyre: slip stiffnesses, peak forces, relaxation lengths at a load; a plot.

Signs are ISO (:mod:`trikedyn.tyre.pac2002`): the cornering stiffness ``dFy/dalpha`` is negative for a
normal tyre; the longitudinal slip stiffness ``dFx/dkappa`` is positive.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import minimize_scalar

from . import pac2002
from .pac2002_arrays import forces
from .pac2002_pack import pack
from .tir_properties import TyreProperties

__all__ = ["PeakForces", "cornering_stiffness", "longitudinal_slip_stiffness", "peak_forces", "plot_characteristics",
           "relaxation_lengths"]

_GRID = 2001  #: points of the coarse search for a peak
_OPEN_KAPPA = 1.0  #: |kappa| searched when the file's slip range is open [1]


def _packed(tir, side):
    return tir if isinstance(tir, np.ndarray) else pack(tir, side)


def cornering_stiffness(tir: TyreProperties, fz, gamma=0.0, *, side=None):
    """Cornering stiffness ``K_ya`` [N/rad] (Pacejka 2006, 4.E25), ISO sign (negative).

    Parameters
    ----------
    tir : TyreProperties
        The tyre.
    fz : float or array_like
        Vertical load [N].
    gamma : float or array_like
        Inclination [rad].
    side : {'left', 'right', None}
        Mounting side (:func:`~trikedyn.tyre.pac2002_pack.pack`).

    Returns
    -------
    float or numpy.ndarray
        ``PKY1 F'z0 sin(PKY4 atan(Fz / ((PKY2 + PKY5 gamma*^2) F'z0))) (1 - PKY3 |gamma*|) LKY``: the slope
        ``dFy/dalpha*`` of the pure-slip side force at its shifted origin ``alpha* = -SHy`` (equal to
        ``dFy/dalpha`` at ``alpha = 0`` when the file's shifts are zero).
    """
    c = _packed(tir, side)
    out = np.vectorize(lambda f, g: pac2002.mf_stiffness(f, g, c)[1], otypes=[float])(fz, gamma)
    return out.item() if out.ndim == 0 else out


def longitudinal_slip_stiffness(tir: TyreProperties, fz, *, side=None):
    """Longitudinal slip stiffness ``K_xk = Fz (PKX1 + PKX2 dfz) exp(PKX3 dfz) LKX`` [N] (Pacejka 2006, 4.E15).

    The slope ``dFx/dkappa`` of the pure-slip longitudinal force at its shifted origin ``kappa = -SHx``.
    ``fz`` [N] may be an array.

    Parameters
    ----------
    tir : TyreProperties or numpy.ndarray
        The tyre, or its packed vector (``side`` is then ignored).
    fz : float or array_like
        Vertical load [N].
    side : {'left', 'right', None}
        Mounting side (see :func:`~trikedyn.tyre.pac2002_pack.pack`).

    Returns
    -------
    float or numpy.ndarray
        ``K_xk`` [N] (per unit slip), shaped as ``fz``.
    """
    c = _packed(tir, side)
    out = np.vectorize(lambda f: pac2002.mf_stiffness(f, 0.0, c)[0], otypes=[float])(fz)
    return out.item() if out.ndim == 0 else out


def relaxation_lengths(tir: TyreProperties, fz, gamma=0.0, *, side=None):
    """Relaxation lengths ``(sigma_kappa, sigma_alpha)`` [m] (MF 5.2 ``PTX1..3``, ``PTY1..2``; MF 6.1 from the
    carcass stiffnesses), see :func:`~trikedyn.tyre.pac2002.mf_relaxation_lengths`. ``fz`` [N] may be an array.

    Parameters
    ----------
    tir : TyreProperties or numpy.ndarray
        The tyre, or its packed vector (``side`` is then ignored).
    fz : float or array_like
        Vertical load [N].
    gamma : float or array_like
        Inclination angle [rad].
    side : {'left', 'right', None}
        Mounting side (see :func:`~trikedyn.tyre.pac2002_pack.pack`).

    Returns
    -------
    sigma_kappa, sigma_alpha : float or numpy.ndarray
        Longitudinal and lateral relaxation lengths [m].
    """
    c = _packed(tir, side)
    fn = np.vectorize(lambda f, g: pac2002.mf_relaxation_lengths(f, g, c), otypes=[float, float])
    sk, sa = fn(fz, gamma)
    return (sk.item(), sa.item()) if np.ndim(sk) == 0 else (sk, sa)


@dataclass(frozen=True)
class PeakForces:
    """Peaks of the pure-slip forces at one load, found numerically within the validity ranges (ISO signs)."""

    fz_N: float  #: load [N]
    fx_max_N: float  #: largest (driving) longitudinal force [N]
    kappa_at_fx_max: float  #: its slip [1]
    fx_min_N: float  #: most negative (braking) longitudinal force [N]
    kappa_at_fx_min: float  #: its slip [1]
    fy_max_N: float  #: largest lateral force (at a negative slip angle) [N]
    alpha_at_fy_max_rad: float  #: its slip angle [rad]
    fy_min_N: float  #: most negative lateral force [N]
    alpha_at_fy_min_rad: float  #: its slip angle [rad]

    @property
    def peak_longitudinal_N(self) -> float:
        """The larger magnitude of the two longitudinal peaks [N]."""
        return max(self.fx_max_N, -self.fx_min_N)

    @property
    def peak_lateral_N(self) -> float:
        """The larger magnitude of the two lateral peaks [N]."""
        return max(self.fy_max_N, -self.fy_min_N)

    @property
    def mu_x(self) -> float:
        """Peak longitudinal friction ``peak_longitudinal_N / Fz`` [1]."""
        return self.peak_longitudinal_N / self.fz_N

    @property
    def mu_y(self) -> float:
        """Peak lateral friction ``peak_lateral_N / Fz`` [1]."""
        return self.peak_lateral_N / self.fz_N

    def to_dict(self) -> dict:
        """The record as a JSON-ready dict, with the peaks [N] and friction coefficients (dimensionless) added.

        Returns
        -------
        dict
            The fields plus ``peak_longitudinal_N``, ``peak_lateral_N``, ``mu_x`` and ``mu_y``.
        """
        return asdict(self) | {"peak_longitudinal_N": self.peak_longitudinal_N, "peak_lateral_N": self.peak_lateral_N,
                               "mu_x": self.mu_x, "mu_y": self.mu_y}


def _extremes(f, lo: float, hi: float) -> tuple[float, float, float, float]:
    """``(x_max, f_max, x_min, f_min)`` of a smooth ``f`` on ``[lo, hi]``: a grid, then bounded Brent."""
    x = np.linspace(lo, hi, _GRID)
    y = f(x)
    found = []
    for sign in (1.0, -1.0):
        i = int(np.argmax(sign * y))
        a, b = x[max(i - 1, 0)], x[min(i + 1, _GRID - 1)]
        res = minimize_scalar(lambda s, sign=sign: -sign * float(f(np.array([s]))[0]), bounds=(a, b),
                              method="bounded", options={"xatol": 1e-12 * max(1.0, abs(hi - lo))})
        best = (res.x, -sign * res.fun) if -res.fun >= sign * y[i] else (x[i], y[i])
        found += [float(best[0]), float(best[1])]
    return tuple(found)


def peak_forces(tir: TyreProperties, fz: float, gamma: float = 0.0, *, side=None) -> PeakForces:
    """Peak pure-slip forces at a load: max/min of ``Fx0`` over ``kappa``, of ``Fy0`` over ``alpha``.

    Parameters
    ----------
    tir : TyreProperties
        The tyre.
    fz : float
        Vertical load [N], > 0.
    gamma : float
        Inclination [rad].
    side : {'left', 'right', None}
        Mounting side.

    Returns
    -------
    PeakForces
        Searched numerically over the file's slip ranges (``|kappa| <= 1`` when open; ``alpha`` within
        ``+-ALPHA_LIMIT``). With ``Cx, Cy > 1`` the peaks are ``+-Dx + SVx`` and ``+-Dy + SVy`` (4.E12),
        (4.E22), (4.E18), (4.E29).
    """
    fz = float(fz)
    if not (math.isfinite(fz) and fz > 0.0):
        raise ValueError(f"fz must be a finite load > 0 N, got {fz!r}")
    c = _packed(tir, side)
    klo = c[pac2002.KPUMIN] if math.isfinite(c[pac2002.KPUMIN]) else -_OPEN_KAPPA
    khi = c[pac2002.KPUMAX] if math.isfinite(c[pac2002.KPUMAX]) else _OPEN_KAPPA
    alo, ahi = c[pac2002.ALO], c[pac2002.AHI]
    if c[pac2002.MIRROR]:
        alo, ahi = -ahi, -alo

    def fx(k):
        """Pure-slip longitudinal force ``Fx0`` [N] at slip ratio ``k`` (at the load ``fz`` and inclination)."""
        return forces(c, fz, kappa=k, gamma=gamma, combined=False).fx

    def fy(a):
        """Pure-slip lateral force ``Fy0`` [N] at slip angle ``a`` [rad] (at the load ``fz`` and inclination)."""
        return forces(c, fz, alpha=a, gamma=gamma, combined=False).fy

    kx_max, fx_max, kx_min, fx_min = _extremes(fx, klo, khi)
    ay_max, fy_max, ay_min, fy_min = _extremes(fy, alo, ahi)
    return PeakForces(fz, fx_max, kx_max, fx_min, kx_min, fy_max, ay_max, fy_min, ay_min)


def plot_characteristics(tir: TyreProperties, loads=None, *, side=None):
    """A 2 x 2 figure of the tyre: ``Fy(alpha)``, ``Fx(kappa)``, ``Mz(alpha)`` at several loads (pure slip), and
    the combined-slip friction ellipse (``Fy`` against ``Fx`` over ``kappa``, for a few slip angles).

    Parameters
    ----------
    tir : TyreProperties
        The tyre.
    loads : sequence of float, optional
        Loads [N]; default 0.5, 1 and 1.5 ``FNOMIN`` (within the file's load range).
    side : {'left', 'right', None}
        Mounting side.

    Returns
    -------
    matplotlib.figure.Figure
        Not attached to pyplot (no display needed).
    """
    from matplotlib.figure import Figure

    c = pack(tir, side)
    fz0 = tir.fnomin
    lo, hi = c[pac2002.FZMIN], c[pac2002.FZMAX]
    if loads is None:
        loads = sorted({min(max(f * fz0, lo), hi) for f in (0.5, 1.0, 1.5)})
    alo, ahi = max(c[pac2002.ALPMIN], math.radians(-20.0)), min(c[pac2002.ALPMAX], math.radians(20.0))
    klo, khi = max(c[pac2002.KPUMIN], -0.6), min(c[pac2002.KPUMAX], 0.6)
    alpha = np.linspace(alo, ahi, 401)
    kappa = np.linspace(klo, khi, 401)
    fig = Figure(figsize=(11, 8.5), layout="constrained")
    ax_fy, ax_fx, ax_mz, ax_el = fig.subplots(2, 2).ravel()
    for fz in loads:
        pure_a = forces(c, fz, alpha=alpha, combined=False)
        pure_k = forces(c, fz, kappa=kappa, combined=False)
        label = f"Fz = {fz:.0f} N"
        ax_fy.plot(np.degrees(alpha), pure_a.fy, label=label)
        ax_mz.plot(np.degrees(alpha), pure_a.mz, label=label)
        ax_fx.plot(kappa, pure_k.fx, label=label)
    fz_e = min(max(fz0, lo), hi)
    for deg in (1.0, 2.0, 4.0, 8.0):
        a = min(max(math.radians(deg), alo), ahi)
        comb = forces(c, fz_e, kappa=kappa, alpha=a)
        ax_el.plot(comb.fx, comb.fy, label=f"alpha = {math.degrees(a):g} deg")
    for ax, title, xlabel, ylabel in (
        (ax_fy, "Lateral force, pure side slip", "slip angle alpha [deg]", "Fy [N]"),
        (ax_fx, "Longitudinal force, pure longitudinal slip", "longitudinal slip kappa [-]", "Fx [N]"),
        (ax_mz, "Aligning torque, pure side slip", "slip angle alpha [deg]", "Mz [N m]"),
        (ax_el, f"Combined slip at Fz = {fz_e:.0f} N (kappa {klo:g} to {khi:g})", "Fx [N]", "Fy [N]"),
    ):
        ax.set(title=title, xlabel=xlabel, ylabel=ylabel)
        ax.grid(True, alpha=0.3)
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.axvline(0.0, color="0.5", lw=0.6)
        ax.legend(fontsize=8)
    fig.suptitle(f"{Path(tir.path).name}: {tir.family}, measured {tir.tyre_side.lower()} "
                 "(ISO signs: alpha > 0 gives Fy < 0)")
    return fig
