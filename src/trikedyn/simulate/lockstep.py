"""The compiled lockstep loop: B lanes of one model structure advanced together, step by step.

:func:`batch_loop` runs jobs (what :func:`~trikedyn.simulate.integrator.rk4_loop` takes for one run each) on
``lanes`` lanes; a lane whose job ends is frozen or refilled. Each lane's step (:func:`advance_lane`) is one
turn of the scalar loop with the scalar loop's step functions, so that each job's record equals the scalar
loop's. The orchestration (packing, kernels, results) is :mod:`trikedyn.simulate.batch`; this module holds only
compiled code, so that numba's cache of it outlives edits there.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .._borrow import borrowed
from .._jit import jit
from ..driver.preview import DRIVER_STATE, driver_step
from ..model.packing import WHEEL_OUT, Plant
from ..model.rhs import evaluate_into, interpolate_inputs, workspace
from .exponential import BLOCK_WIDTH
from .integrator import STATUS_NAN, STATUS_OK, STATUS_PENETRATION, STATUS_ROLLOVER, etd_step, near_a_stop, run_ends

__all__ = ["advance_lane", "batch_loop", "batch_records", "lane_memory", "lane_plant", "stack_plants", "start_job"]

_PLANT_FIELDS = ("parent", "jtype", "jaxis", "tree_e", "tree_r", "mass", "h", "ibar", "wheels", "tyres", "vehicle",
                 "road")
assert Plant._fields == _PLANT_FIELDS, "lane_plant lists the Plant's fields: update it with packing.Plant"


def stack_plants(plants: Sequence[Plant]) -> Plant:
    """The plants' arrays stacked along a new first axis (one entry per plant), as one :class:`Plant`.

    Parameters
    ----------
    plants : sequence of Plant
        Plants of one structure: equal shapes and dtypes field by field.

    Returns
    -------
    Plant
        Each field of shape ``(len(plants), *shape)``.
    """
    return Plant(*(np.ascontiguousarray(np.stack([getattr(p, f) for p in plants])) for f in Plant._fields))


@jit(inline="always")
def lane_plant(s, i):
    """The plant ``i`` of the stacked plants ``s`` (:func:`stack_plants`): a view, nothing copied, that counts
    no references (:func:`~trikedyn._borrow.borrowed`: valid while ``s`` lives, as it does through a batch).

    Parameters
    ----------
    s : Plant
        The stacked plants.
    i : int
        The plant's index.

    Returns
    -------
    Plant
        Plant ``i``.
    """
    return Plant(borrowed(s.parent[i]), borrowed(s.jtype[i]), borrowed(s.jaxis[i]), borrowed(s.tree_e[i]),
                 borrowed(s.tree_r[i]), borrowed(s.mass[i]), borrowed(s.h[i]), borrowed(s.ibar[i]),
                 borrowed(s.wheels[i]), borrowed(s.tyres[i]), borrowed(s.vehicle[i]), borrowed(s.road[i]))


@jit
def advance_lane(j, x, p, dt, record_every, n_steps, rec, status, inputs, path, speeds, d, memory, delay_line,
                 stop_dt, exponential, wout, ws, u, xs, k1, k2, k3, k4, scratch, idx, mat, fn, times, states, derivs,
                 wheels, commands, step):
    """One step of job ``j``'s loop (one turn of :func:`~trikedyn.simulate.integrator.rk4_loop`'s), in place.

    Parameters
    ----------
    j : int
        The job (its row of the records).
    x : numpy.ndarray
        The lane's state, advanced in place.
    p : Plant
        The job's plant.
    dt : float
        Step [s].
    record_every, n_steps, rec, status : int
        Steps between records, the job's steps, records made, status (``STATUS_*``).
    inputs, path, speeds : numpy.ndarray
        The job's input table (time [s], steer [rad], drive [N m], brake [N m]), path rows (x [m], y [m],
        s [m], heading [rad], curvature [1/m]) and target speeds (time [s], speed [m/s]).
    d : record
        The job's :data:`~trikedyn.driver.preview.DRIVER` record.
    memory, delay_line : numpy.ndarray
        The driver's memory and past steer demands [rad], updated.
    stop_dt : float
        Largest substep near a bump or rebound stop [s].
    exponential : bool
        ETDRK4 (True) or classical RK4.
    wout, ws, u, xs, k1, k2, k3, k4, scratch, idx, mat, fn
        The lane's loop memory (wheel outputs, workspace, inputs, stages, exponential blocks), dimensionless
        containers as in :func:`~trikedyn.simulate.integrator.rk4_loop`.
    times, states, derivs, wheels, commands : numpy.ndarray
        The records of every job, row ``j`` written.
    step : int
        The lane's step count (its time is ``step * dt`` [s]).

    Returns
    -------
    rec, status : int
        Records made and status.
    done : bool
        Whether the job ended.
    t : float
        The time [s] (of the end when it ended).
    """
    nw = p.wheels.shape[0]
    n = p.parent.shape[0] + 5
    veh = p.vehicle[0]
    closed = d.on > 0.0
    t = 0.0 + step * dt
    if closed:
        u[0], u[1], u[2] = driver_step(t, dt, x[0], x[1], x[5], x[n + 2], x[n + 3], path, speeds, d, veh, memory,
                                       delay_line, inputs)
    else:
        u[0], u[1], u[2] = interpolate_inputs(t, inputs)
    evaluate_into(t, x, u, p, wout, ws, k1)
    if (step % record_every == 0 or status != STATUS_OK) and rec < times.shape[1]:
        times[j, rec] = t
        for i in range(x.shape[0]):
            states[j, rec, i] = x[i]
            derivs[j, rec, i] = k1[i]
        for k in range(nw):
            wheels[j, rec, k] = wout[k]
        commands[j, rec, 0], commands[j, rec, 1], commands[j, rec, 2] = u[0], u[1], u[2]
        rec += 1
    if run_ends(status, step, n_steps, record_every, x[0], x[1], x[5], d):
        return rec, status, True, t
    for k in range(nw):
        if wout[k].deflection > veh.penetration_limit * p.wheels[k].radius:
            return rec, STATUS_PENETRATION, True, t
    n_sub = 1
    if stop_dt > 0.0 and dt > stop_dt and near_a_stop(x, p.wheels, n, dt):
        n_sub = int(np.ceil(dt / stop_dt))
    h = dt / n_sub
    finite = True
    for i in range(n_sub):
        ts = t + i * h
        if i > 0:
            if not closed:
                u[0], u[1], u[2] = interpolate_inputs(ts, inputs)
            evaluate_into(ts, x, u, p, wout, ws, k1)
        finite = etd_step(x, ts, h, k1, u, p, closed, inputs, wout, ws, xs, k2, k3, k4, scratch, idx, mat, fn,
                          exponential)
        if not finite:
            break
    t = 0.0 + (step + 1) * dt
    if not finite:
        return rec, STATUS_NAN, True, t
    if abs(x[3]) > veh.roll_limit or abs(x[4]) > veh.roll_limit:
        status = STATUS_ROLLOVER  # recorded at the lane's next step, which then ends the job
    return rec, status, False, t


@jit
def batch_records(x0s, n_steps, record_every, nw, drivers):
    """The records of a batch's jobs (zeros) and each job's driver memory, as :func:`batch_loop` and
    :func:`~trikedyn.simulate.lane_batch.lane_batch_loop` keep them.

    Parameters
    ----------
    x0s : numpy.ndarray, shape (J, nx)
        Initial states.
    n_steps : numpy.ndarray of int, shape (J,)
        Steps of each job.
    record_every : int
        Steps between records.
    nw : int
        Wheels.
    drivers : numpy.ndarray, shape (J,), dtype DRIVER
        Each job's driver.

    Returns
    -------
    times, states, derivs, wheels, commands, status, recorded, t_stop : numpy.ndarray
        The records (see :func:`batch_loop`'s returns).
    memory, delays, delay_lines : numpy.ndarray
        Each job's driver memory, delay-line length and past steer demands [rad].
    """
    n_jobs, nx = x0s.shape
    n_rec = n_steps.max() // record_every + 1
    memory = np.zeros((n_jobs, 1), DRIVER_STATE)  # each job's driver memory, from zero
    delays = np.zeros(n_jobs, np.int64)
    for j in range(n_jobs):
        delays[j] = drivers[j].delay_steps + 2 if drivers[j].on > 0.0 else 1
    return (np.zeros((n_jobs, n_rec)), np.zeros((n_jobs, n_rec, nx)), np.zeros((n_jobs, n_rec, nx)),
            np.zeros((n_jobs, n_rec, nw), WHEEL_OUT), np.zeros((n_jobs, n_rec, 3)), np.zeros(n_jobs, np.int64),
            np.zeros(n_jobs, np.int64), np.zeros(n_jobs), memory, delays, np.zeros((n_jobs, delays.max())))


@jit
def lane_memory(n_lanes, nx, nw, n):
    """What each lane carries from step to step but its workspace: job (-1: none), state, step count, wheel
    outputs, inputs, stage vectors, exponential blocks (indices, ``L``, functions) and scratch.

    Parameters
    ----------
    n_lanes, nx, nw, n : int
        Lanes, state size, wheels, degrees of freedom.

    Returns
    -------
    job, x, step, wout, u, xs, k1, k2, k3, k4, idx, mat, fn, scratch : numpy.ndarray
        One row per lane.
    """
    return (np.full(n_lanes, -1, np.int64), np.zeros((n_lanes, nx)), np.zeros(n_lanes, np.int64),
            np.zeros((n_lanes, nw), WHEEL_OUT), np.zeros((n_lanes, 3)), np.empty((n_lanes, nx)),
            np.empty((n_lanes, nx)), np.empty((n_lanes, nx)), np.empty((n_lanes, nx)), np.empty((n_lanes, nx)),
            np.zeros((n_lanes, nw, 2), np.int64), np.zeros((n_lanes, nw, 4)), np.zeros((n_lanes, nw, BLOCK_WIDTH)),
            np.empty((n_lanes, n)))


@jit(inline="always")
def start_job(b, j, x0, blank, job, x, step, wout, u, idx, mat, fn):
    """Lane ``b`` takes job ``j`` from the state ``x0``, its memory set as the scalar loop sets it for a run (the
    step reads the last wheel outputs, ``blank`` before the first, and the blocks back).

    Parameters
    ----------
    b, j : int
        The lane and the job.
    x0 : numpy.ndarray
        The job's initial state.
    blank : numpy.ndarray, dtype WHEEL_OUT
        Zeroed wheel outputs, one per wheel.
    job, x, step, wout, u, idx, mat, fn : numpy.ndarray
        The lanes' memory (:func:`lane_memory`), row ``b`` set.
    """
    job[b] = j
    for i in range(x0.shape[0]):  # element by element: a row assignment compiles numba's shape-check error path
        x[b, i] = x0[i]
    step[b] = 0
    for k in range(blank.shape[0]):
        wout[b, k] = blank[k]
    u[b] = 0.0
    idx[b] = 0
    mat[b] = 0.0
    fn[b] = 0.0


@jit
def batch_loop(x0s, n_steps, plants, plant_of, inputs, n_inputs, paths, n_path, speeds, n_speeds, drivers,
               stop_dts, dt, record_every, exponential, lanes, refill):
    """Run the jobs in lockstep on ``lanes`` lanes, every job from ``t = 0`` with the step ``dt`` [s].

    Each job is what :func:`~trikedyn.simulate.integrator.rk4_loop` takes for one run; the tables of the jobs
    are padded along their second axis to a common length, their own lengths given.

    Parameters
    ----------
    x0s : numpy.ndarray, shape (J, nx)
        Initial states.
    n_steps : numpy.ndarray of int, shape (J,)
        Steps of each job.
    plants : Plant
        The distinct plants, stacked (:func:`stack_plants`).
    plant_of : numpy.ndarray of int, shape (J,)
        Each job's plant.
    inputs, paths, speeds : numpy.ndarray, shapes (J, m, 4), (J, k, 5), (J, s, 2)
        Each job's input table (time [s], steer [rad], drive [N m], brake [N m]), path rows (x [m], y [m],
        s [m], heading [rad], curvature [1/m]) and target speed rows (time [s], speed [m/s]), padded.
    n_inputs, n_path, n_speeds : numpy.ndarray of int, shape (J,)
        Their lengths.
    drivers : numpy.ndarray, shape (J,), dtype DRIVER
        Each job's driver (``on = 0``: open loop).
    stop_dts : numpy.ndarray, shape (J,)
        Each job's largest substep near a bump or rebound stop [s].
    dt : float
        Step [s].
    record_every : int
        Steps between records.
    exponential : bool
        ETDRK4 (True) or classical RK4.
    lanes : int
        Lanes (runs advanced together).
    refill : bool
        A lane whose job ended takes the next job waiting; otherwise the jobs run in successive batches of
        ``lanes``.

    Returns
    -------
    times : ndarray (J, r)
    states, derivatives : ndarray (J, r, nx)
    wheels : ndarray (J, r, n_wheels) of WHEEL_OUT
    commands : ndarray (J, r, 3)
    status, n_recorded : ndarray of int (J,)
    t_stop : ndarray (J,)
        As :func:`~trikedyn.simulate.integrator.rk4_loop`'s, one row per job (``r`` the longest job's records).
    """
    n_jobs, nx = x0s.shape
    nw = plants.wheels.shape[1]
    n = plants.parent.shape[1] + 5
    times, states, derivs, wheels, commands, status, recorded, t_stop, memory, delays, delay_lines = \
        batch_records(x0s, n_steps, record_every, nw, drivers)
    # what a lane carries from step to step, as the scalar loop (set afresh for each job)
    n_lanes = max(1, min(lanes, n_jobs))
    job, x, step, wout, u, xs, k1, k2, k3, k4, idx, mat, fn, scratch = lane_memory(n_lanes, nx, nw, n)
    wss = [workspace(plants.parent[0]) for _ in range(n_lanes)]
    blank = np.zeros(nw, WHEEL_OUT)
    waiting = 0
    busy = 0
    while True:
        if busy == 0 or refill:  # fill the free lanes
            for b in range(n_lanes):
                if job[b] < 0 and waiting < n_jobs:
                    start_job(b, waiting, x0s[waiting], blank, job, x, step, wout, u, idx, mat, fn)
                    wss[b] = workspace(plants.parent[0])
                    waiting += 1
                    busy += 1
        if busy == 0:
            break
        for b in range(n_lanes):
            j = job[b]
            if j < 0:
                continue
            p = lane_plant(plants, plant_of[j])
            rec, st, done, t = advance_lane(j, x[b], p, dt, record_every, n_steps[j], recorded[j], status[j],
                                        inputs[j, :n_inputs[j]], paths[j, :n_path[j]], speeds[j, :n_speeds[j]],
                                        drivers[j], memory[j], delay_lines[j, :delays[j]], stop_dts[j],
                                        exponential, wout[b], wss[b], u[b], xs[b], k1[b], k2[b], k3[b], k4[b],
                                        scratch[b], idx[b], mat[b], fn[b], times, states, derivs, wheels, commands,
                                        step[b])
            recorded[j] = rec
            status[j] = st
            step[b] += 1
            if done:
                t_stop[j] = t
                job[b] = -1
                busy -= 1
    return times, states, derivs, wheels, commands, status, recorded, t_stop


