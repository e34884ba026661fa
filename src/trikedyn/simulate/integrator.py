"""The compiled fixed-step time loop (RK4, with the wheels' spin-slip pairs exact) and its health watch.

The whole loop runs in numba: no Python per step. Every ``record_every`` steps it stores the state.
It stops early, with a status code and the time, on NaN, runaway tyre penetration or rollover.

By default the step is an exponential RK4 (ETDRK4, :mod:`trikedyn.simulate.exponential`): each wheel's
spin against its longitudinal slip, the fastest and stiffest motion (~300 rad/s), is integrated exactly
over the step, so the step is set by the body, steering and wheel hop (10 ms on a flat road,
:data:`~trikedyn.simulate.DEFAULT_DT_S`). ``exponential=False`` gives the classical RK4 (about 5 ms).
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from ..driver.preview import DRIVER_STATE, driver_step, open_loop_driver, past_end_gate
from ..model.packing import WHEEL_OUT
from ..model.rhs import evaluate_into, evaluate_stage_into, interpolate_inputs, workspace
from .defaults import DEFAULT_DT_S
from .exponential import (
    BLOCK_WIDTH,
    block_functions,
    spin_slip_blocks,
    stage_pairs,
    subtract_blocks,
    third_stage_pairs,
    update_pairs,
)

__all__ = ["DEFAULT_DT_S", "STATUS_NAN", "STATUS_OK", "STATUS_PENETRATION", "STATUS_ROLLOVER", "STATUS_TEXT", "rk4_loop"]

STATUS_OK, STATUS_NAN, STATUS_PENETRATION, STATUS_ROLLOVER = 0, 1, 2, 3
STATUS_TEXT = {
    STATUS_OK: "ok",
    STATUS_NAN: "the state became NaN or infinite (time step too large or a diverging model)",
    STATUS_PENETRATION: "runaway tyre penetration (a wheel sank into the road by over half its radius)",
    STATUS_ROLLOVER: "the vehicle rolled over (roll or pitch angle beyond the limit)",
}


OPEN_LOOP_PATH = np.zeros((0, 5))
OPEN_LOOP_SPEED = np.zeros((1, 2))
OPEN_LOOP_DRIVER = open_loop_driver()
OPEN_LOOP = (OPEN_LOOP_PATH, OPEN_LOOP_SPEED, OPEN_LOOP_DRIVER)
"""Pass ``*OPEN_LOOP`` for the path, speed profile and driver arguments of an open-loop run."""


@jit(inline="always")
def near_a_stop(x, wheels, n, dt):
    """Whether a suspension is on a bump or rebound stop, or within reach of one over a step of ``dt`` [s]
    at twice its present travel rate (a stop is a stiff one-sided spring: its wheel hop is the fastest mode).
    It takes the plant's ``wheels``, not the plant: an inlined function's tuple argument costs a reference
    count on every array of the tuple (:mod:`trikedyn.simulate.specialised`)."""
    for k in range(wheels.shape[0]):
        w = wheels[k]
        sb = w.spring_body
        travel = w.motion_ratio * x[5 + sb]
        reach = 2.0 * abs(w.motion_ratio * x[n + 5 + sb]) * dt + 1e-3
        if travel + reach > w.bump_travel or travel - reach < -w.rebound_travel:
            return True
    return False


@jit(inline="always")
def run_ends(status, step, n_steps, record_every, px, py, yaw, d):
    """Whether a run ends at ``step`` (once that step is recorded): it stopped (``status``), it made its
    ``n_steps``, or it ends at a gate (:func:`~trikedyn.driver.preview.past_end_gate`, from the chassis origin
    ``(px, py)`` [m] and heading ``yaw`` [rad]) and the CG is past it at a record step. The scalar loop and
    both batch loops end their runs here."""
    return status != STATUS_OK or step == n_steps or step % record_every == 0 and past_end_gate(px, py, yaw, d)


@jit(inline="always")
def etd_step(x, t, h, k1, u, p, closed, inputs, wout, ws, xs, k2, k3, k4, scratch, idx, mat, fn, exponential):
    """One step of ``h`` [s] from ``x`` at ``t`` (``k1 = f(t, x)`` evaluated, ``wout`` and the factor of the
    mass matrix in ``ws.low`` from it), in place; False when the new state is not finite. The other three
    stages are :func:`~trikedyn.model.rhs.evaluate_stage_into` (their factor of the mass matrix is not read).

    ETDRK4 about ``x`` with the wheels' spin-slip pairs exact (:mod:`trikedyn.simulate.exponential`), on the
    entries outside the blocks classical RK4 (and everywhere without ``exponential``).
    """
    nx = x.shape[0]
    half = 0.5 * h
    m = spin_slip_blocks(p, wout, ws.low, scratch, idx, mat) if exponential else 0
    block_functions(mat, m, h, fn)
    for i in range(nx):  # a = x + h/2 phi1(hL/2) N_n
        xs[i] = x[i] + half * k1[i]
    stage_pairs(fn, idx, m, x, k1, half, xs)
    if not closed:
        u[0], u[1], u[2] = interpolate_inputs(t + half, inputs)
    evaluate_stage_into(t + half, xs, u, p, wout, ws, k2)
    subtract_blocks(mat, idx, m, xs, x, k2)
    for i in range(nx):  # b = x + h/2 phi1(hL/2) N_a
        xs[i] = x[i] + half * k2[i]
    stage_pairs(fn, idx, m, x, k2, half, xs)
    evaluate_stage_into(t + half, xs, u, p, wout, ws, k3)
    subtract_blocks(mat, idx, m, xs, x, k3)
    for i in range(nx):  # c = x + exp(hL/2) (a - x) + h/2 phi1(hL/2) (2 N_b - N_n)
        xs[i] = x[i] + h * k3[i]
    third_stage_pairs(fn, idx, m, x, k1, k3, half, xs)
    if not closed:
        u[0], u[1], u[2] = interpolate_inputs(t + h, inputs)
    evaluate_stage_into(t + h, xs, u, p, wout, ws, k4)
    subtract_blocks(mat, idx, m, xs, x, k4)
    # x + h (W1 N_n + W2 (N_a + N_b) + W3 N_c), the weights 1/6, 1/3, 1/6 outside the blocks
    for i in range(nx):
        xs[i] = x[i] + h * (k1[i] / 6.0 + (k2[i] + k3[i]) / 3.0 + k4[i] / 6.0)
    update_pairs(fn, idx, m, x, k1, k2, k3, k4, h, xs)
    finite = True
    for i in range(nx):
        x[i] = xs[i]
        if not np.isfinite(x[i]):
            finite = False
    return finite


@jit
def rk4_loop(x0, t0, dt, n_steps, record_every, inputs, path, speed_profile, drv, p, exponential, stop_dt):
    """Integrate ``n_steps`` RK4 steps of ``dt`` [s] from ``x0`` at ``t0`` on the plant ``p``.

    With ``exponential`` the steps are ETDRK4 steps with the wheels' spin-slip pairs exact
    (:mod:`trikedyn.simulate.exponential`); without, classical RK4. With ``stop_dt`` > 0 [s], a step taken
    while a suspension is on (or within reach of) a bump or rebound stop is split into substeps of at most
    ``stop_dt``: the stop's stiff wheel hop then sets the step only while it acts (:func:`near_a_stop`).
    Both are required (no defaults): an omitted argument is another type to numba, so another compilation
    of the whole loop.

    Open loop (``drv[0].on == 0``): the inputs come from the ``inputs`` table. Closed loop: the driver
    (:func:`~trikedyn.driver.preview.driver_step`) holds the target speeds of ``speed_profile``
    ``(time, speed)`` and steers along ``path`` (or, in its open-loop steering mode, takes the steer column
    of ``inputs``); it runs once per step and holds its commands over the step.
    Every ``record_every`` steps (and at ``t0``) the loop records the state, its derivative, the per-wheel
    outputs and the commands; the derivative is the first RK stage of the next step, so recording costs no
    extra evaluation.

    Parameters
    ----------
    x0 : numpy.ndarray
        Initial state.
    t0 : float
        Initial time [s].
    dt : float
        Step [s].
    n_steps : int
        Number of steps.
    record_every : int
        Steps between records.
    inputs : numpy.ndarray, shape (m, 4)
        Input table (time [s], steer [rad], drive [N m], brake [N m]).
    path : numpy.ndarray, shape (k, 5)
        Path rows (x [m], y [m], s [m], heading [rad], curvature [1/m]).
    speed_profile : numpy.ndarray, shape (j, 2)
        Target speed rows (time [s], speed [m/s]).
    drv : numpy.ndarray, shape (1,), dtype DRIVER
        The driver record.
    p : Plant
        The compiled vehicle.
    exponential : bool
        ETDRK4 (True) or classical RK4.
    stop_dt : float
        Largest substep near a bump or rebound stop [s]; 0 for none.

    Returns
    -------
    times : ndarray (m,)
    states, derivatives : ndarray (m, len(x0))
    wheels : ndarray (m, n_wheels) of :data:`~trikedyn.model.packing.WHEEL_OUT`
    commands : ndarray (m, 3)
        Steer command [rad], drive torque [N m], brake torque per wheel [N m].
    status : int
        ``STATUS_*``.
    n_recorded : int
        Rows filled.
    t_stop : float
        Time at which the loop stopped [s].
    """
    nx = x0.shape[0]
    n_rec = n_steps // record_every + 1
    times = np.empty(n_rec)
    states = np.empty((n_rec, nx))
    derivs = np.empty((n_rec, nx))
    nw = p.wheels.shape[0]
    wheels = np.empty((n_rec, nw), WHEEL_OUT)
    commands = np.empty((n_rec, 3))
    d = drv[0]
    veh = p.vehicle[0]
    plant_wheels = p.wheels  # taken out of the plant once, not at every step
    closed = d.on > 0.0
    dstate = np.zeros(1, DRIVER_STATE)  # the driver's memory: an array the loop owns (not a bare record)
    delay_line = np.zeros(d.delay_steps + 2) if closed else np.zeros(1)
    wout = np.zeros(nw, WHEEL_OUT)
    x = x0.copy()
    xs = np.empty(nx)
    k1 = np.empty(nx)
    k2 = np.empty(nx)
    k3 = np.empty(nx)
    k4 = np.empty(nx)
    u = np.zeros(3)
    ws = workspace(p.parent)
    n = p.parent.shape[0] + 5
    idx = np.zeros((nw, 2), np.int64)  # the exponential blocks: state indices, L, their functions
    mat = np.zeros((nw, 4))
    fn = np.zeros((nw, BLOCK_WIDTH))
    scratch = np.empty(n)
    t = t0
    rec = 0
    status = STATUS_OK
    step = 0
    while True:
        if closed:
            u[0], u[1], u[2] = driver_step(t, dt, x[0], x[1], x[5], x[n + 2], x[n + 3], path, speed_profile, d, veh,
                                           dstate, delay_line, inputs)
        else:
            u[0], u[1], u[2] = interpolate_inputs(t, inputs)
        evaluate_into(t, x, u, p, wout, ws, k1)
        if (step % record_every == 0 or status != STATUS_OK) and rec < n_rec:
            times[rec] = t
            for i in range(nx):  # element by element: a row assignment compiles numba's shape check (~2 s)
                states[rec, i] = x[i]
                derivs[rec, i] = k1[i]
            for k in range(nw):
                wheels[rec, k] = wout[k]
            commands[rec, 0], commands[rec, 1], commands[rec, 2] = u[0], u[1], u[2]
            rec += 1
        if run_ends(status, step, n_steps, record_every, x[0], x[1], x[5], d):
            break
        for k in range(nw):
            if wout[k].deflection > veh.penetration_limit * plant_wheels[k].radius:
                return times, states, derivs, wheels, commands, STATUS_PENETRATION, rec, t
        n_sub = 1
        if stop_dt > 0.0 and dt > stop_dt and near_a_stop(x, plant_wheels, n, dt):
            n_sub = int(np.ceil(dt / stop_dt))
        h = dt / n_sub
        finite = True
        for j in range(n_sub):
            ts = t + j * h
            if j > 0:  # the substep's first stage (the step's first is k1, recorded above)
                if not closed:
                    u[0], u[1], u[2] = interpolate_inputs(ts, inputs)
                evaluate_into(ts, x, u, p, wout, ws, k1)
            finite = etd_step(x, ts, h, k1, u, p, closed, inputs, wout, ws, xs, k2, k3, k4, scratch, idx, mat, fn,
                              exponential)
            if not finite:
                break
        step += 1
        t = t0 + step * dt
        if not finite:
            return times, states, derivs, wheels, commands, STATUS_NAN, rec, t
        if abs(x[3]) > veh.roll_limit or abs(x[4]) > veh.roll_limit:
            status = STATUS_ROLLOVER  # recorded at the top of the loop, then the loop ends
    return times, states, derivs, wheels, commands, status, rec, t
