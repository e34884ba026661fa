"""The compiled fixed-step time loop (classical Runge-Kutta, RK4) with a health watch.

The whole loop runs in numba: no Python per step. Every ``record_every`` steps it stores the state.
It stops early, with a status code and the time, on NaN, runaway tyre penetration or rollover.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from ..driver.preview import D_DELAY_STEPS, D_ON, N_DRIVER, N_DRIVER_STATE, driver_step
from ..model.rhs import N_WOUT, W_DEFLECTION, evaluate_into, interpolate_inputs, workspace
from ..model.vehicle import S_PENETRATION_LIMIT, S_ROLL_LIMIT, WF_RADIUS, WI_BRAKED

__all__ = ["STATUS_NAN", "STATUS_OK", "STATUS_PENETRATION", "STATUS_ROLLOVER", "STATUS_TEXT", "rk4_loop"]

STATUS_OK, STATUS_NAN, STATUS_PENETRATION, STATUS_ROLLOVER = 0, 1, 2, 3
STATUS_TEXT = {
    STATUS_OK: "ok",
    STATUS_NAN: "the state became NaN or infinite (time step too large or a diverging model)",
    STATUS_PENETRATION: "runaway tyre penetration (a wheel sank into the road by over half its radius)",
    STATUS_ROLLOVER: "the vehicle rolled over (roll or pitch angle beyond the limit)",
}


OPEN_LOOP_PATH = np.zeros((0, 5))
OPEN_LOOP_SPEED = np.zeros((1, 2))
OPEN_LOOP_DRIVER = np.zeros(N_DRIVER)
OPEN_LOOP = (OPEN_LOOP_PATH, OPEN_LOOP_SPEED, OPEN_LOOP_DRIVER)
"""Pass ``*OPEN_LOOP`` for the path, speed profile and driver arguments of an open-loop run."""


@jit
def rk4_loop(x0, t0, dt, n_steps, record_every, inputs, path, speed_profile, drv,
             parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar, wheel_f, wheel_i, tyre, sc, road):
    """Integrate ``n_steps`` RK4 steps of ``dt`` [s] from ``x0`` at ``t0``.

    Open loop (``drv[0] == 0``): the inputs come from the ``inputs`` table. Closed loop: the driver
    (:func:`~trikedyn.driver.preview.driver_step`) holds the target speeds of ``speed_profile``
    ``(time, speed)`` and steers along ``path`` (or, in its open-loop steering mode, takes the steer column
    of ``inputs``); it runs once per step and holds its commands over the step.
    Every ``record_every`` steps (and at ``t0``) the loop records the state, its derivative, the per-wheel
    outputs and the commands; the derivative is the first RK stage of the next step, so recording costs no
    extra evaluation.

    Returns
    -------
    times : ndarray (m,)
    states, derivatives : ndarray (m, len(x0))
    wheels : ndarray (m, n_wheels, N_WOUT)
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
    nw = wheel_f.shape[0]
    wheels = np.empty((n_rec, nw, N_WOUT))
    commands = np.empty((n_rec, 3))
    closed = drv[D_ON] > 0.0
    step_inputs = np.zeros((1, 4))
    stage_inputs = step_inputs if closed else inputs
    dstate = np.zeros(N_DRIVER_STATE)
    delay_line = np.zeros(int(drv[D_DELAY_STEPS]) + 2) if closed else np.zeros(1)
    n_braked = 0
    for k in range(nw):
        n_braked += wheel_i[k, WI_BRAKED]
    n = parent.shape[0] + 5
    wout = np.empty((nw, N_WOUT))
    x = x0.copy()
    xs = np.empty(nx)
    k1 = np.empty(nx)
    k2 = np.empty(nx)
    k3 = np.empty(nx)
    k4 = np.empty(nx)
    ws = workspace(parent)
    t = t0
    rec = 0
    status = STATUS_OK
    arrays = (parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar, wheel_f, wheel_i, tyre, sc, road)
    half = 0.5 * dt
    step = 0
    while True:
        if closed:
            steer, drive, brake = driver_step(t, dt, x[0], x[1], x[5], x[n + 2], x[n + 3], path, speed_profile, drv,
                                              dstate, delay_line, n_braked, inputs)
            step_inputs[0, 1] = steer
            step_inputs[0, 2] = drive
            step_inputs[0, 3] = brake
        evaluate_into(t, x, stage_inputs, *arrays, wout, ws, k1)
        if (step % record_every == 0 or status != STATUS_OK) and rec < n_rec:
            times[rec] = t
            states[rec] = x
            derivs[rec] = k1
            wheels[rec] = wout
            commands[rec, 0], commands[rec, 1], commands[rec, 2] = interpolate_inputs(t, stage_inputs)
            rec += 1
        if status != STATUS_OK or step == n_steps:
            break
        for k in range(nw):
            if wout[k, W_DEFLECTION] > sc[S_PENETRATION_LIMIT] * wheel_f[k, WF_RADIUS]:
                return times, states, derivs, wheels, commands, STATUS_PENETRATION, rec, t
        for i in range(nx):
            xs[i] = x[i] + half * k1[i]
        evaluate_into(t + half, xs, stage_inputs, *arrays, wout, ws, k2)
        for i in range(nx):
            xs[i] = x[i] + half * k2[i]
        evaluate_into(t + half, xs, stage_inputs, *arrays, wout, ws, k3)
        for i in range(nx):
            xs[i] = x[i] + dt * k3[i]
        evaluate_into(t + dt, xs, stage_inputs, *arrays, wout, ws, k4)
        finite = True
        for i in range(nx):
            x[i] += (dt / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            if not np.isfinite(x[i]):
                finite = False
        step += 1
        t = t0 + step * dt
        if not finite:
            return times, states, derivs, wheels, commands, STATUS_NAN, rec, t
        if abs(x[3]) > sc[S_ROLL_LIMIT] or abs(x[4]) > sc[S_ROLL_LIMIT]:
            status = STATUS_ROLLOVER  # recorded at the top of the loop, then the loop ends
    return times, states, derivs, wheels, commands, status, rec, t
