"""The stiff part of the time loop, integrated exactly: each wheel's spin against its longitudinal slip.

The fastest motion of a trike on its tyres is a wheel spinning against its own longitudinal slip: the slip
``kappa`` relaxes at ``v_ref / sigma_x`` and pulls the spin through the slip stiffness ``C_kappa``, an
oscillation of ``sqrt(C_kappa R^2 / (I_w sigma_x))``, about 300 rad/s on the reference trike at any speed
(lightly damped at walking pace). An explicit RK4 step must stay below ``2.8 / 300`` s to be stable, while
the body and the wheel hop need only about half of that. :func:`~trikedyn.simulate.integrator.rk4_loop`
therefore takes exponential Runge-Kutta steps (ETDRK4, Cox & Matthews, *J. Comput. Phys.* 176, 2002;
Hochbruck & Ostermann, *Acta Numerica* 19, 2010), written about the step's start ``x_n``:

``w = x - x_n``, ``dw/dt = L w + N(x)``, ``N(x) = f(x) - L (x - x_n)``,

where ``L`` is block-diagonal with one 2x2 block per wheel on its (spin rate, ``kappa``) pair, taken at
``x_n`` and held over the step:

``L_k = [[0, -(H^-1)_ss R_c C_kappa], [R_e / sigma_x, -v_ref / sigma_x]]``

with ``(H^-1)_ss`` the spin joint's diagonal of the inverse mass matrix (from the factor of the mass matrix
of the step's first evaluation, :mod:`trikedyn.model.inverse_mass`), ``R_c`` the loaded radius (the lever of
the longitudinal force about the axle), ``R_e`` the effective rolling radius and ``C_kappa = dFx/dkappa`` of the wheel's own
tyre model at its current load, slip angle and camber (a finite difference: any tyre model, saturation
included). The stages and the update use ``exp(h L / 2)`` and the functions ``phi_1``, ``phi_2``,
``phi_3`` of each block, in closed form (:func:`block_functions`); ``N`` is integrated to fourth order.
With ``L = 0`` the step is the classical RK4; for any ``L`` held over a step the method is exact on
``dw/dt = L w + const``, so that the couplings left in ``N`` (the fork, the other wheels, the body) stay
stable even where the spin-slip mode is hardly damped (at 5 km/h, where Lawson's integrating-factor RK4
with the same blocks grows by 5 % a step at 10 ms). :func:`~trikedyn.simulate.run.max_stable_step` leaves
the exponential pairs out of its eigenvalues.
"""

from __future__ import annotations

import cmath
import math

from .._jit import jit
from ..model.inverse_mass import inverse_mass_diagonal, ltdl_inverse_diagonal
from ..tyre.interface import tyre_forces

__all__ = ["BLOCK_WIDTH", "block_functions", "expm2", "inverse_mass_diagonal", "ltdl_inverse_diagonal", "phi_functions",
           "spin_slip_block", "spin_slip_blocks", "spin_slip_blocks_ltdl", "stage_pairs", "subtract_blocks",
           "third_stage_pairs", "update_pairs"]

SLIP_STEP = 1e-5
"""Finite-difference step in ``kappa`` for the slip stiffness ``dFx/dkappa`` [1]."""


@jit(inline="always")
def expm2(a, b, c, d, h):
    """``exp(h M)`` of ``M = [[a, b], [c, d]]`` (closed form), as ``(e11, e12, e21, e22)``.

    With ``s = (a + d) / 2`` and ``q^2 = ((a - d) / 2)^2 + b c``:
    ``exp(h M) = e^(h s) [cosh(q h) I + sinh(q h) / q (M - s I)]`` (``cos``/``sin`` for ``q^2 < 0``).

    Parameters
    ----------
    a, b, c, d : float
        The matrix entries [1/s].
    h : float
        Time step [s].

    Returns
    -------
    tuple of float
        ``(e11, e12, e21, e22)``, dimensionless.
    """
    s = 0.5 * (a + d)
    disc = 0.25 * (a - d) * (a - d) + b * c
    es = math.exp(h * s)
    if disc > 0.0:
        q = math.sqrt(disc)
        qh = q * h
        ch = math.cosh(qh)
        sh = math.sinh(qh) / q if qh > 1e-8 else h
    elif disc < 0.0:
        q = math.sqrt(-disc)
        qh = q * h
        ch = math.cos(qh)
        sh = math.sin(qh) / q if qh > 1e-8 else h
    else:
        ch = 1.0
        sh = h
    return es * (ch + sh * (a - s)), es * sh * b, es * sh * c, es * (ch + sh * (d - s))


@jit(inline="always")
def spin_slip_blocks(p, wout, low, scratch, idx, mat):
    """Each wheel's (spin rate, ``kappa``) block of ``L`` (see the module docstring) at the current state.

    Parameters
    ----------
    p : Plant
    wout : ndarray of WHEEL_OUT
        The wheels' outputs of the evaluation at the current state.
    low : ndarray (n, n)
        The Cholesky factor of that evaluation's mass matrix.
    scratch : ndarray (n,)
    idx : ndarray (n_wheels, 2) of int
        Filled with the state indices of each block.
    mat : ndarray (n_wheels, 4)
        Filled with each block, row-major.

    Returns
    -------
    int
        The number of blocks.
    """
    for k in range(p.wheels.shape[0]):
        spin_slip_block(p.wheels, p.tyres, p.vehicle, p.parent.shape[0] + 5, k, wout[k],
                        inverse_mass_diagonal(low, 5 + p.wheels[k].wheel_body, scratch), idx, mat)
    return p.wheels.shape[0]


@jit(inline="always")
def spin_slip_blocks_ltdl(p, wout, factor, scratch, idx, mat):
    """:func:`spin_slip_blocks` from the leaves-first factorisation ``H = L^T D L`` of the generated kernels
    (``forward_dynamics_factor_into`` of :mod:`trikedyn.model.codegen`) instead of a Cholesky factor.

    Parameters
    ----------
    p : Plant
    wout : ndarray of WHEEL_OUT
        The wheels' outputs of the evaluation at the current state.
    factor : ndarray (n, n)
        That evaluation's factor (:func:`ltdl_inverse_diagonal`).
    scratch : ndarray (n,)
    idx : ndarray (n_wheels, 2) of int
        Filled with the state indices of each block.
    mat : ndarray (n_wheels, 4)
        Filled with each block, row-major.

    Returns
    -------
    int
        The number of blocks.
    """
    for k in range(p.wheels.shape[0]):
        spin_slip_block(p.wheels, p.tyres, p.vehicle, p.parent.shape[0] + 5, k, wout[k],
                        ltdl_inverse_diagonal(factor, p.parent, 5 + p.wheels[k].wheel_body, scratch), idx, mat)
    return p.wheels.shape[0]


@jit
def spin_slip_block(wheels, tyres, vehicle, n, k, o, inverse_mass, idx, mat):
    """Wheel ``k``'s (spin rate, ``kappa``) block of ``L`` into ``idx[k]`` and ``mat[k]`` (compiled on its own,
    not inlined: its tyre model is compiled once for every loop; it takes the plant's arrays it reads, not the
    plant: numba passes a tuple argument's every array member by member).

    Parameters
    ----------
    wheels, tyres, vehicle : numpy.ndarray
        The plant's ``wheels``, ``tyres`` and ``vehicle`` (:class:`~trikedyn.model.packing.Plant`).
    n : int
        Degrees of freedom.
    k : int
        The wheel.
    o : record of WHEEL_OUT
        The wheel's outputs at the current state.
    inverse_mass : float
        ``(H^-1)_ss`` of the wheel's spin joint [1/(kg m^2)].
    idx : ndarray (n_wheels, 2) of int
    mat : ndarray (n_wheels, 4)
    """
    veh = vehicle[0]
    v_low4 = veh.v_low * veh.v_low * veh.v_low * veh.v_low
    w = wheels[k]
    v_ref = math.sqrt(math.sqrt(o.vx * o.vx * o.vx * o.vx + v_low4))
    r_eff = w.radius - o.deflection / 3.0
    slip_stiffness = 0.0
    if o.fz > 0.0 and veh.slip_forces > 0.0:
        shifted = tyre_forces(w.tyre_model, tyres[k], o.kappa + SLIP_STEP, o.alpha, o.camber, o.fz, o.vx, v_ref,
                              o.spin, r_eff, veh.v_low, veh.w_low)[0]
        slip_stiffness = (shifted - o.fx) / SLIP_STEP
    idx[k, 0] = n + 5 + w.wheel_body
    idx[k, 1] = 2 * n + 2 * k
    mat[k, 0] = 0.0
    mat[k, 1] = -inverse_mass * (w.radius - o.deflection) * slip_stiffness
    mat[k, 2] = r_eff / w.relaxation_x
    mat[k, 3] = -v_ref / w.relaxation_x


@jit(inline="always")
def subtract_blocks(mat, idx, m, x, xn, k):
    """``k <- k - L (x - xn)``: the nonlinear remainder ``N`` from a stage derivative.

    Parameters
    ----------
    mat : numpy.ndarray, shape (m_blocks, 4)
        The blocks ``L`` [1/s].
    idx : numpy.ndarray of int, shape (m_blocks, 2)
        State indices of each block's pair (spin, slip).
    m : int
        Number of blocks in use.
    x : numpy.ndarray
        The stage's state.
    xn : numpy.ndarray
        The state ``L`` was taken at.
    k : numpy.ndarray
        The stage derivative, updated on the pairs.
    """
    for j in range(m):
        i0, i1 = idx[j, 0], idx[j, 1]
        a, b = x[i0] - xn[i0], x[i1] - xn[i1]
        k[i0] -= mat[j, 0] * a + mat[j, 1] * b
        k[i1] -= mat[j, 2] * a + mat[j, 3] * b


BLOCK_WIDTH = 20
"""Numbers kept per block and step: ``exp(h L / 2)``, ``phi_1(h L / 2)``, and the ETDRK4 weights
``phi_1 - 3 phi_2 + 4 phi_3``, ``2 phi_2 - 4 phi_3``, ``4 phi_3 - phi_2`` of ``h L``, each 2x2 row-major."""

TAYLOR_RADIUS = 0.5
"""Below this ``|z|`` the phi functions are summed as Taylor series (their recurrence cancels) [1]."""


@jit(inline="always")
def _small(z):
    """``|z| < TAYLOR_RADIUS``, compared squared (no ``hypot``)."""
    return z.real * z.real + z.imag * z.imag < TAYLOR_RADIUS * TAYLOR_RADIUS


@jit(inline="always")
def _phis_with(z, e):
    """:func:`phi_functions` of ``z`` given ``e = e^z`` (used only where ``|z|`` is not small)."""
    if _small(z):
        p4 = 0j
        term = 1.0 / 24.0  # 1/4!
        power = 1.0 + 0j
        for j in range(18):
            p4 += power * term
            term /= j + 5.0
            power *= z
        p3 = 1.0 / 6.0 + z * p4
        p2 = 0.5 + z * p3
        p1 = 1.0 + z * p2
        return 1.0 + z * p1, p1, p2, p3, p4
    p1 = (e - 1.0) / z
    p2 = (p1 - 1.0) / z
    p3 = (p2 - 0.5) / z
    return e, p1, p2, p3, (p3 - 1.0 / 6.0) / z


@jit(inline="always")
def phi_functions(z):
    """``(e^z, phi_1(z), phi_2(z), phi_3(z), phi_4(z))`` of a complex ``z``;
    ``phi_k(z) = sum_j z^j / (j + k)!``, ``phi_(k+1)(z) = (phi_k(z) - 1 / k!) / z``.

    Parameters
    ----------
    z : complex
        Argument, dimensionless (``h`` times an eigenvalue).

    Returns
    -------
    tuple of complex
        ``e^z, phi_1(z) ... phi_4(z)`` (a Taylor series for small ``|z|``).
    """
    return _phis_with(z, 0j if _small(z) else cmath.exp(z))


@jit(inline="always")
def _phis_half_and_full(z):
    """:func:`phi_functions` at ``z / 2`` and at ``z`` from one exponential: ``e^z = (e^(z/2))^2``."""
    half = 0.5 * z
    eh = 0j if _small(z) else cmath.exp(half)
    return _phis_with(half, eh), _phis_with(z, eh * eh)


@jit(inline="always")
def _matrix_function(g1, g2, dg, close, a, b, c, d, s, q, out, col):
    """``g(M)`` of the 2x2 ``M = [[a, b], [c, d]]`` with eigenvalues ``s +- q`` from ``g`` at them:
    ``(g1 + g2) / 2 I + (g1 - g2) / (2 q) (M - s I)`` (``dg = g'(s)`` for the divided difference when
    the eigenvalues nearly coincide). Real entries into ``out[col:col + 4]``."""
    mean = 0.5 * (g1 + g2)
    slope = dg if close else (g1 - g2) / (2.0 * q)
    out[col] = (mean + slope * (a - s)).real
    out[col + 1] = (slope * b).real
    out[col + 2] = (slope * c).real
    out[col + 3] = (mean + slope * (d - s)).real


@jit(inline="always")
def _phis_at_pair(s, q, close, conjugate):
    """The phi functions at the eigenvalues ``s + q`` and ``s - q`` of ``h L`` and at their halves (those of
    ``h L / 2``), and at ``s`` (and ``s / 2``) when the two nearly coincide (for the derivatives
    ``phi_k' = phi_k - k phi_(k+1)``; else zeros). A complex pair needs one evaluation: the other is its
    conjugate. Each eigenvalue takes one exponential, at its half, squared for the whole."""
    h1, f1 = _phis_half_and_full(s + q)
    if conjugate:
        h2 = (h1[0].conjugate(), h1[1].conjugate(), h1[2].conjugate(), h1[3].conjugate(), h1[4].conjugate())
        f2 = (f1[0].conjugate(), f1[1].conjugate(), f1[2].conjugate(), f1[3].conjugate(), f1[4].conjugate())
    else:
        h2, f2 = _phis_half_and_full(s - q)
    hd, fd = (0j, 0j, 0j, 0j, 0j), (0j, 0j, 0j, 0j, 0j)
    if close:
        hd, fd = _phis_half_and_full(s)
    return h1, h2, hd, f1, f2, fd


@jit
def block_functions(mat, m, h, out):
    """For each of the first ``m`` blocks ``L`` of ``mat``: :data:`BLOCK_WIDTH` numbers into ``out``
    (``exp(h L / 2)``, ``phi_1(h L / 2)``, then the three ETDRK4 weights of ``h L``).

    Parameters
    ----------
    mat : numpy.ndarray, shape (m_blocks, 4)
        Each block ``L = [[a, b], [c, d]]`` row-wise [1/s].
    m : int
        Number of blocks in use.
    h : float
        Step [s].
    out : numpy.ndarray, shape (m_blocks, BLOCK_WIDTH)
        Written with the functions, dimensionless (the weights carry no ``h``).
    """
    for j in range(m):
        a, b, c, d = h * mat[j, 0], h * mat[j, 1], h * mat[j, 2], h * mat[j, 3]
        s = 0.5 * (a + d)
        disc = 0.25 * (a - d) * (a - d) + b * c
        q = cmath.sqrt(complex(disc, 0.0))
        bound = 1e-7 * (1.0 + abs(s))
        close = q.real * q.real + q.imag * q.imag < bound * bound  # |q| small, compared squared (no hypot)
        conjugate = disc < 0.0 and not close
        row = out[j]
        h1, h2, hd, f1, f2, fd = _phis_at_pair(complex(s, 0.0), q, close, conjugate)
        # h L / 2: eigenvalues (s +- q) / 2; the derivatives phi_k' = phi_k - k phi_(k+1) at s / 2
        _matrix_function(h1[0], h2[0], hd[0], close, 0.5 * a, 0.5 * b, 0.5 * c, 0.5 * d, 0.5 * s, 0.5 * q, row, 0)
        _matrix_function(h1[1], h2[1], hd[1] - hd[2], close, 0.5 * a, 0.5 * b, 0.5 * c, 0.5 * d, 0.5 * s, 0.5 * q,
                         row, 4)
        # h L: eigenvalues s +- q
        d1, d2, d3 = fd[1] - fd[2], fd[2] - 2.0 * fd[3], fd[3] - 3.0 * fd[4]
        _matrix_function(f1[1] - 3.0 * f1[2] + 4.0 * f1[3], f2[1] - 3.0 * f2[2] + 4.0 * f2[3],
                         d1 - 3.0 * d2 + 4.0 * d3, close, a, b, c, d, s, q, row, 8)
        _matrix_function(2.0 * f1[2] - 4.0 * f1[3], 2.0 * f2[2] - 4.0 * f2[3], 2.0 * d2 - 4.0 * d3, close, a, b, c,
                         d, s, q, row, 12)
        _matrix_function(4.0 * f1[3] - f1[2], 4.0 * f2[3] - f2[2], 4.0 * d3 - d2, close, a, b, c, d, s, q, row, 16)


@jit(inline="always")
def _times(r, col, a, b):
    """The 2x2 at ``r[col:col + 4]`` (row-major) times ``(a, b)``."""
    return r[col] * a + r[col + 1] * b, r[col + 2] * a + r[col + 3] * b


@jit(inline="always")
def stage_pairs(fn, idx, m, x, k, half, out):
    """The first two stages on each block's pair: ``out = x + h/2 phi_1(h L / 2) k``.

    Parameters
    ----------
    fn : numpy.ndarray, shape (m_blocks, BLOCK_WIDTH)
        The block functions (:func:`block_functions`).
    idx : numpy.ndarray of int, shape (m_blocks, 2)
        State indices of each block's pair (spin, slip).
    m : int
        Number of blocks in use.
    x : numpy.ndarray
        State at the start of the step.
    k : numpy.ndarray
        Stage derivative (its nonlinear remainder on the pairs).
    half : float
        Half the step [s].
    out : numpy.ndarray
        Written on the pairs' entries.
    """
    for j in range(m):
        i0, i1 = idx[j, 0], idx[j, 1]
        a, b = _times(fn[j], 4, k[i0], k[i1])
        out[i0], out[i1] = x[i0] + half * a, x[i1] + half * b


@jit(inline="always")
def third_stage_pairs(fn, idx, m, x, k1, k3, half, out):
    """The third stage on each block's pair: ``out = x + exp(h L / 2) (a - x) + h/2 phi_1(h L / 2)
    (2 k3 - k1)`` with ``a - x = h/2 phi_1(h L / 2) k1`` (the first stage).

    Parameters
    ----------
    fn : numpy.ndarray, shape (m_blocks, BLOCK_WIDTH)
        The block functions (:func:`block_functions`).
    idx : numpy.ndarray of int, shape (m_blocks, 2)
        State indices of each block's pair (spin, slip).
    m : int
        Number of blocks in use.
    x : numpy.ndarray
        State at the start of the step.
    k1, k3 : numpy.ndarray
        First and third stage derivatives (remainders).
    half : float
        Half the step [s].
    out : numpy.ndarray
        Written on the pairs' entries.
    """
    for j in range(m):
        i0, i1 = idx[j, 0], idx[j, 1]
        r = fn[j]
        a0, a1 = _times(r, 4, k1[i0], k1[i1])
        e0, e1 = _times(r, 0, half * a0, half * a1)
        c0, c1 = _times(r, 4, 2.0 * k3[i0] - k1[i0], 2.0 * k3[i1] - k1[i1])
        out[i0], out[i1] = x[i0] + e0 + half * c0, x[i1] + e1 + half * c1


@jit(inline="always")
def update_pairs(fn, idx, m, x, k1, k2, k3, k4, h, out):
    """The step on each block's pair: ``out = x + h (W1 k1 + W2 (k2 + k3) + W3 k4)``, the ETDRK4 weights
    of :func:`block_functions` (RK4's 1/6, 1/3, 1/6 when ``L = 0``).

    Parameters
    ----------
    fn : numpy.ndarray, shape (m_blocks, BLOCK_WIDTH)
        The block functions (:func:`block_functions`).
    idx : numpy.ndarray of int, shape (m_blocks, 2)
        State indices of each block's pair (spin, slip).
    m : int
        Number of blocks in use.
    x : numpy.ndarray
        State at the start of the step.
    k1, k2, k3, k4 : numpy.ndarray
        The four stage derivatives (remainders).
    h : float
        Step [s].
    out : numpy.ndarray
        Written on the pairs' entries.
    """
    for j in range(m):
        i0, i1 = idx[j, 0], idx[j, 1]
        r = fn[j]
        w10, w11 = _times(r, 8, k1[i0], k1[i1])
        w20, w21 = _times(r, 12, k2[i0] + k3[i0], k2[i1] + k3[i1])
        w30, w31 = _times(r, 16, k4[i0], k4[i1])
        out[i0], out[i1] = x[i0] + h * (w10 + w20 + w30), x[i1] + h * (w11 + w21 + w31)
