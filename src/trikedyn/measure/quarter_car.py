"""Two-mass quarter-car model: the reference for suspension identification (paper, section 2.1).

The paper reduces its speed-bump records with a quarter car of sprung mass ``M_s`` (body share on one
wheel) and unsprung mass ``m`` (wheel, hub, fork or swing arm), joined by the suspension stiffness ``K``
and damping ``C``; the tyre, of stiffness ``K_t`` (and damping ``C_t``), joins the unsprung mass to the
road. This module gives its matrices, its two modes and an exact simulation of the sprung-mass
acceleration as an accelerometer on the body reads it, to test :mod:`trikedyn.measure.suspension`.

Coordinates ``q = [z_s, z_u]`` are vertical displacements [m] of the sprung and unsprung masses from
static equilibrium, positive up (ISO 8855). Gravity only sets the static equilibrium: it does not enter
the (linear) equations of motion, and it appears in the accelerometer reading on request.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm

from trikedyn.errors import InputError
from trikedyn.units import STANDARD_GRAVITY

__all__ = ["QuarterCarModes", "quarter_car_free_decay", "quarter_car_matrices", "quarter_car_modes",
           "sprung_mass_for_frequency"]


def _positive(value, name, allow_zero=False):
    value = float(value)
    if not np.isfinite(value) or value < 0.0 or (value == 0.0 and not allow_zero):
        expected = "a finite value >= 0" if allow_zero else "a finite value > 0"
        raise InputError(f"got {value!r}, expected {expected}", where=name)
    return value


def quarter_car_matrices(sprung_mass, unsprung_mass, stiffness, damping, tyre_stiffness, tyre_damping=0.0):
    """Mass, damping and stiffness matrices of the two-mass quarter car.

    ``M q'' + C q' + K q = f_road`` with ``q = [z_s, z_u]`` [m] and
    ``f_road = [0, K_t z_r + C_t z_r']`` [N] for a road height ``z_r`` [m].

    Parameters
    ----------
    sprung_mass : float
        Sprung mass ``M_s`` carried by the wheel [kg].
    unsprung_mass : float
        Unsprung mass ``m`` [kg].
    stiffness : float
        Suspension stiffness ``K_s`` at the wheel [N/m].
    damping : float
        Suspension damping coefficient ``C_s`` at the wheel [N s/m].
    tyre_stiffness : float
        Tyre vertical stiffness ``K_t`` [N/m] (200 kN/m in the paper).
    tyre_damping : float, optional
        Tyre vertical damping ``C_t`` [N s/m] (75 N s/m in the paper; 0 by default).

    Returns
    -------
    M, C, K : ndarray, shape (2, 2)
        Mass [kg], damping [N s/m] and stiffness [N/m] matrices.
    """
    ms = _positive(sprung_mass, "sprung_mass")
    mu = _positive(unsprung_mass, "unsprung_mass")
    k = _positive(stiffness, "stiffness")
    c = _positive(damping, "damping", allow_zero=True)
    kt = _positive(tyre_stiffness, "tyre_stiffness")
    ct = _positive(tyre_damping, "tyre_damping", allow_zero=True)
    m_mat = np.diag([ms, mu])
    c_mat = np.array([[c, -c], [-c, c + ct]])
    k_mat = np.array([[k, -k], [-k, k + kt]])
    return m_mat, c_mat, k_mat


def _state_matrix(m_mat, c_mat, k_mat):
    """First-order system matrix ``A`` for the state ``[q, q']``."""
    m_inv = np.linalg.inv(m_mat)
    return np.block([[np.zeros((2, 2)), np.eye(2)], [-m_inv @ k_mat, -m_inv @ c_mat]])


@dataclass(frozen=True)
class QuarterCarModes:
    """The two modes of the quarter car, sorted by undamped natural frequency (body mode first).

    Attributes
    ----------
    natural_frequency_hz : ndarray, shape (2,)
        Undamped natural frequency ``|lambda| / 2 pi`` of each mode [Hz].
    damping_ratio : ndarray, shape (2,)
        Damping ratio ``-Re(lambda) / |lambda|`` of each mode [-] (>= 1 for an overdamped pair, computed
        from the pair's product and sum).
    eigenvalues : ndarray, shape (4,)
        Eigenvalues of the first-order system [1/s], in the order of the modes (two per mode).
    """

    natural_frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    eigenvalues: np.ndarray

    @property
    def sprung_frequency_hz(self) -> float:
        """Undamped natural frequency of the sprung (body, lower) mode [Hz]."""
        return float(self.natural_frequency_hz[0])

    @property
    def sprung_damping_ratio(self) -> float:
        """Damping ratio of the sprung (body, lower) mode [-]."""
        return float(self.damping_ratio[0])

    @property
    def unsprung_frequency_hz(self) -> float:
        """Undamped natural frequency of the unsprung (wheel-hop, upper) mode [Hz]."""
        return float(self.natural_frequency_hz[1])

    @property
    def unsprung_damping_ratio(self) -> float:
        """Damping ratio of the unsprung (wheel-hop, upper) mode [-]."""
        return float(self.damping_ratio[1])


def quarter_car_modes(sprung_mass, unsprung_mass, stiffness, damping, tyre_stiffness, tyre_damping=0.0):
    """Undamped natural frequencies and damping ratios of the quarter car's two modes.

    From the eigenvalues ``lambda`` of the first-order system ``x' = A x``: a complex pair gives
    ``f_n = |lambda| / 2 pi`` and ``xi = -Re(lambda) / |lambda|``; an overdamped (real) pair
    ``lambda_1, lambda_2`` gives ``omega_n = sqrt(lambda_1 lambda_2)`` and
    ``xi = -(lambda_1 + lambda_2) / (2 omega_n)``. With the tyre in series, the body mode's frequency is
    *not* ``sqrt(K_s / M_s) / 2 pi``: it is close to ``sqrt(K_eq / M_s) / 2 pi`` with
    ``1/K_eq = 1/K_s + 1/K_t``, shifted further by the unsprung mass and the damping.

    Parameters
    ----------
    sprung_mass : float
        Sprung mass ``M_s`` carried by the wheel [kg].
    unsprung_mass : float
        Unsprung mass ``m`` [kg].
    stiffness : float
        Suspension stiffness ``K_s`` at the wheel [N/m].
    damping : float
        Suspension damping coefficient ``C_s`` at the wheel [N s/m].
    tyre_stiffness : float
        Tyre vertical stiffness ``K_t`` [N/m].
    tyre_damping : float, optional
        Tyre vertical damping ``C_t`` [N s/m].

    Returns
    -------
    QuarterCarModes
        The two modes sorted by frequency; the sprung (body) mode is the lower one (index 0).
    """
    a_mat = _state_matrix(*quarter_car_matrices(sprung_mass, unsprung_mass, stiffness, damping,
                                                tyre_stiffness, tyre_damping))
    lam = np.linalg.eigvals(a_mat)
    cplx = lam[lam.imag > 1e-9 * np.abs(lam).max()]
    real = np.sort(lam[np.abs(lam.imag) <= 1e-9 * np.abs(lam).max()].real)
    pairs = [(z, np.conj(z)) for z in cplx]
    pairs += [(complex(real[i]), complex(real[i + 1])) for i in range(0, len(real) - 1, 2)]
    omega = np.array([np.sqrt(abs(a * b)) for a, b in pairs])
    zeta = np.array([-(a + b).real / (2.0 * w) for (a, b), w in zip(pairs, omega, strict=False)])
    order = np.argsort(omega)
    eig = np.array([z for i in order for z in pairs[i]])
    return QuarterCarModes(omega[order] / (2.0 * np.pi), zeta[order], eig)


def sprung_mass_for_frequency(natural_frequency_hz, unsprung_mass, stiffness, damping, tyre_stiffness,
                              tyre_damping=0.0):
    """The sprung mass [kg] whose body mode has the undamped natural frequency ``natural_frequency_hz``.

    Eq. 3 with the tyre in series: the inverse of :func:`quarter_car_modes`' ``sprung_frequency_hz`` in
    ``M_s`` (the body frequency falls as ``M_s`` grows), found by bisection on ``log M_s`` over
    1e-6 .. 1e6 kg to 1e-12 relative. With a rigid, massless tyre it is Eq. 3 inverted,
    ``M_s = K / (2 pi f_n)^2``; with the tyre in series it is close to ``K_eq / (2 pi f_n)^2``,
    ``1/K_eq = 1/K + 1/K_t``.

    Parameters
    ----------
    natural_frequency_hz : float
        Undamped natural frequency of the body mode [Hz].
    unsprung_mass, stiffness, damping, tyre_stiffness, tyre_damping : float
        As in :func:`quarter_car_matrices` [kg, N/m, N s/m, N/m, N s/m].

    Returns
    -------
    float or None
        ``M_s`` [kg]; None when no sprung mass in that range gives the frequency (above the wheel on its
        tyre, about ``sqrt(K_t / m) / 2 pi``).
    """
    from scipy.optimize import brentq

    target = _positive(natural_frequency_hz, "natural_frequency_hz")

    def _gap(log_mass):
        modes = quarter_car_modes(np.exp(log_mass), unsprung_mass, stiffness, damping, tyre_stiffness,
                                  tyre_damping)
        return np.log(modes.sprung_frequency_hz / target)

    low, high = np.log(1e-6), np.log(1e6)
    if _gap(low) < 0.0 or _gap(high) > 0.0:
        return None
    return float(np.exp(brentq(_gap, low, high, xtol=1e-12, rtol=1e-12)))


def quarter_car_free_decay(sprung_mass, unsprung_mass, stiffness, damping, tyre_stiffness, tyre_damping=0.0,
                           *, duration_s, sample_rate_hz, initial_displacement_m=None, bump=None,
                           event_time_s=0.0, noise_std_mps2=0.0, bias_mps2=0.0, seed=None,
                           include_gravity=False):
    """Sprung-mass vertical acceleration after a release or a speed bump, as a body accelerometer reads it.

    The linear system is integrated *exactly* (zero integration error): the state is propagated from
    sample to sample with the matrix exponential of the system matrix, augmented for the bump with an
    exact harmonic oscillator that generates the road profile. The output is *point-sampled* at
    ``t_k = k / sample_rate_hz``: no anti-alias filter, as with an IMU whose output rate is its sampling
    rate, so components above the Nyquist frequency (e.g. wheel hop seen at 10 Hz) alias.

    Parameters
    ----------
    sprung_mass, unsprung_mass, stiffness, damping, tyre_stiffness, tyre_damping : float
        As in :func:`quarter_car_matrices` [kg, kg, N/m, N s/m, N/m, N s/m].
    duration_s : float
        Record length [s].
    sample_rate_hz : float
        Output sampling rate [Hz].
    initial_displacement_m : float, optional
        Free decay: the body is held at rest ``initial_displacement_m`` [m] (positive up) from static
        equilibrium, with the unsprung mass at its quasi-static position (spring and tyre forces
        balanced), and released at ``event_time_s``. Before the release it reads zero acceleration.
    bump : tuple of float, optional
        Speed bump ``(height_m, length_m, speed_mps)``: a ``(1 - cos) / 2`` profile of height [m] and
        length [m] crossed at constant speed [m/s], reached by the tyre at ``event_time_s``.
        Exactly one of ``initial_displacement_m`` and ``bump`` must be given.
    event_time_s : float, optional
        Time of the release or of the start of the bump [s].
    noise_std_mps2 : float, optional
        Standard deviation of white Gaussian measurement noise [m/s^2].
    bias_mps2 : float, optional
        Constant sensor bias [m/s^2].
    seed : int or numpy.random.Generator, optional
        Seed of :func:`numpy.random.default_rng` for the noise.
    include_gravity : bool, optional
        Add ``+g`` (:data:`trikedyn.units.STANDARD_GRAVITY`): a z-up accelerometer at rest reads +g.

    Returns
    -------
    time_s : ndarray
        Sample times [s].
    accel_mps2 : ndarray
        Sprung-mass vertical acceleration reading [m/s^2].
    """
    duration_s = _positive(duration_s, "duration_s")
    fs = _positive(sample_rate_hz, "sample_rate_hz")
    t_event = _positive(event_time_s, "event_time_s", allow_zero=True)
    _positive(noise_std_mps2, "noise_std_mps2", allow_zero=True)
    if (initial_displacement_m is None) == (bump is None):
        raise InputError("give exactly one of initial_displacement_m and bump",
                         where="initial_displacement_m")
    m_mat, c_mat, k_mat = quarter_car_matrices(sprung_mass, unsprung_mass, stiffness, damping,
                                               tyre_stiffness, tyre_damping)
    n = round(duration_s * fs)
    if n < 2:
        raise InputError(f"{n} sample(s) at {fs} Hz over {duration_s} s; expected at least 2",
                         where="duration_s")
    time = np.arange(n) / fs
    ks, kt, ct = k_mat[0, 0], k_mat[1, 1] - k_mat[0, 0], c_mat[1, 1] - c_mat[0, 0]

    # State [z_s, z_u, v_s, v_u, c, s, b] with road z_r = h/2 (b - c), z_r' = h/2 Omega s.
    a_free = np.zeros((7, 7))
    a_free[:4, :4] = _state_matrix(m_mat, c_mat, k_mat)
    segments = []  # (start time, system matrix, state reset or None)
    x0 = np.zeros(7)
    if bump is not None:
        if np.ndim(bump) != 1 or len(bump) != 3:
            raise InputError("expected (height_m, length_m, speed_mps)", where="bump")
        height = float(bump[0])
        length = _positive(bump[1], "bump")
        speed = _positive(bump[2], "bump")
        omega = 2.0 * np.pi * speed / length
        a_bump = a_free.copy()
        a_bump[4, 5], a_bump[5, 4] = -omega, omega
        a_bump[3, 6] = kt * height / 2.0 / m_mat[1, 1]
        a_bump[3, 4] = -kt * height / 2.0 / m_mat[1, 1]
        a_bump[3, 5] = ct * height * omega / 2.0 / m_mat[1, 1]
        segments = [(0.0, a_free, None), (t_event, a_bump, np.array([1.0, 0.0, 1.0])),
                    (t_event + length / speed, a_free, np.zeros(3))]
        held_until = -np.inf
    else:
        x0[0] = float(initial_displacement_m)
        x0[1] = x0[0] * ks / (ks + kt)
        segments = [(0.0, a_free, None)]
        held_until = t_event

    states = np.empty((n, 7))
    step_cache = {}
    x, tc, seg = x0.copy(), max(0.0, held_until), 0
    for i, t in enumerate(time):
        if t < held_until:
            states[i] = x0
            continue
        while seg + 1 < len(segments) and segments[seg + 1][0] <= t:
            t_b, _, reset = segments[seg + 1]
            x = expm(segments[seg][1] * (t_b - tc)) @ x
            if reset is not None:
                x[4:] = reset
            tc, seg = t_b, seg + 1
        dt = t - tc
        key = (seg, round(dt * fs, 9))
        if key not in step_cache:
            step_cache[key] = expm(segments[seg][1] * dt)
        x = step_cache[key] @ x if dt > 0.0 else x
        tc = t
        states[i] = x

    accel = (a_free[2, :4] @ states[:, :4].T)
    accel[time < held_until] = 0.0
    if include_gravity:
        accel = accel + STANDARD_GRAVITY
    rng = np.random.default_rng(seed)
    if noise_std_mps2 > 0.0:
        accel = accel + rng.normal(0.0, noise_std_mps2, n)
    return time, accel + float(bias_mps2)
