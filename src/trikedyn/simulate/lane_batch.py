"""The lockstep batch on the lane kernels: each stage of a step evaluated for every lane at once.

:func:`~trikedyn.simulate.lockstep.batch_loop` advances its lanes one after the other through the scalar
step. :func:`lane_batch_loop` takes the same jobs and returns the same records, but goes through a step stage
by stage across the lanes: every lane's driver, then every lane's first right-hand side (:func:`evaluate_lanes`:
the kinematics and forward dynamics of all lanes by the lane kernels of :mod:`trikedyn.model.lanes`, two thirds
of a right-hand side, vectorised; each lane's tyres, springs and drive its own), every lane's health watch,
then the exponential step's three other stages (:func:`etd_lanes`), each an evaluation over the lanes.

Every lane does the arithmetic of its scalar run in the same order: the lane kernels are the scalar kernels'
code over the lanes (both take their sines and cosines from :func:`~trikedyn.model.lane_math.sincos`), and
:func:`etd_lanes` is :func:`~trikedyn.simulate.integrator.etd_step` stage by stage. A lane's record is
therefore its scalar run's, bit for bit (``tests/simulate/test_specialised.py``). A lane whose step needs substeps
(a suspension near its stop, :func:`~trikedyn.simulate.integrator.near_a_stop`) takes them alone, each the
same lane step, at the times the scalar loop takes them.

Each lane's rows of the stacked arrays are views that count no references (:func:`~trikedyn._borrow.borrowed`):
taken a dozen times a lane and a stage, counted views were 12 % of a profile of the batch, 3 % after (and the
batch of 8 176-192 runs/core-s against 158-174: 32 closed-loop 10 s double lane changes at 20-40 km/h,
alternated).

The functions run only in a module generated for one tree structure (:func:`trikedyn.simulate.batch.batch_source`),
which binds the lane kernels and their buffer's layout; here those names hold neutral values (never run).
"""

from __future__ import annotations

import numpy as np

from .._borrow import borrowed
from .._jit import jit
from ..driver.preview import driver_step
from ..model.inverse_mass import dof_parent
from ..model.lane_workspace import stacked_workspace
from ..model.packing import WHEEL_OUT
from ..model.rhs import euler_rates_into, interpolate_inputs, wrenches_into
from .exponential import (
    block_functions,
    spin_slip_blocks_ltdl,
    stage_pairs,
    subtract_blocks,
    third_stage_pairs,
    update_pairs,
)
from .integrator import STATUS_NAN, STATUS_OK, STATUS_PENETRATION, STATUS_ROLLOVER, near_a_stop, run_ends
from .lockstep import batch_records, lane_memory, lane_plant, start_job

__all__ = ["LANE_GLOBALS", "etd_lanes", "evaluate_lanes", "lane_batch_loop", "set_lane_plant"]

# set by each generated module: the lane count, each array's first row in the buffer, the lane kernels
LANES = ROWS = 1
R_Q = R_U = R_TAU = R_FEXT = R_GRAVITY = R_TREE_E = R_TREE_R = R_MASS = R_H = R_IBAR = R_UDOT = R_E = R_EW = R_PW = 0
R_V = R_LOW = 0
kinematics_lanes = forward_dynamics_lanes = forward_dynamics_factor_lanes = None

LANE_GLOBALS = {"LANES": None, "ROWS": None, "R_Q": "q", "R_U": "u", "R_TAU": "tau", "R_FEXT": "fext",
                "R_GRAVITY": "gravity", "R_TREE_E": "tree_e", "R_TREE_R": "tree_r", "R_MASS": "mass", "R_H": "h",
                "R_IBAR": "ibar", "R_UDOT": "udot", "R_E": "e", "R_EW": "ew", "R_PW": "pw", "R_V": "v",
                "R_LOW": "low"}
"""The constants a generated module defines for these functions: ``LANES``, ``ROWS`` and each ``R_*``, the
first row of its array of :data:`~trikedyn.model.lanes.LANE_ARRAYS`."""


@jit(inline="always")
def _at(row, lane):
    """The buffer index of ``row`` at ``lane`` (of its group)."""
    return row * LANES + lane


@jit
def set_lane_plant(buf, k, p):
    """The tree's values of plant ``p`` and its gravity [m/s^2] into lane ``k`` of the buffer ``buf``.

    Parameters
    ----------
    buf : numpy.ndarray
        A lane buffer.
    k : int
        The lane in the buffer.
    p : Plant
        The plant.
    """
    nb = p.parent.shape[0]
    for b in range(nb):
        for i in range(3):
            for j in range(3):
                buf[_at(R_TREE_E + 9 * b + 3 * i + j, k)] = p.tree_e[b, i, j]
                buf[_at(R_IBAR + 9 * b + 3 * i + j, k)] = p.ibar[b, i, j]
            buf[_at(R_TREE_R + 3 * b + i, k)] = p.tree_r[b, i]
            buf[_at(R_H + 3 * b + i, k)] = p.h[b, i]
        buf[_at(R_MASS + b, k)] = p.mass[b]
    buf[_at(R_GRAVITY, k)] = 0.0
    buf[_at(R_GRAVITY + 1, k)] = 0.0
    buf[_at(R_GRAVITY + 2, k)] = -p.vehicle[0].g


@jit
def evaluate_lanes(bufs, on, n_on, ts, xs, u, plants, plant_of, job, wout, ws, xdot, keep_factor):
    """``xdot[l] = f(ts[l], xs[l], u[l])`` for each lane ``l`` of ``on[:n_on]``: the generated evaluation of
    the scalar loop (kinematics, :func:`~trikedyn.model.rhs.wrenches_into`, forward dynamics, Euler rates)
    with the kinematics and the forward dynamics over the lanes.

    Parameters
    ----------
    bufs : numpy.ndarray, shape (groups, ROWS * LANES)
        The lane buffers; lane ``l`` is lane ``l % LANES`` of buffer ``l // LANES``.
    on : numpy.ndarray of int
        The lanes evaluated (the first ``n_on``).
    n_on : int
    ts : numpy.ndarray
        Each lane's time [s].
    xs, u : numpy.ndarray, shapes (lanes, nx), (lanes, 3)
        Each lane's state and inputs.
    plants, plant_of, job : Plant, numpy.ndarray
        The stacked plants, each job's plant and each lane's job.
    wout : numpy.ndarray, shape (lanes, n_wheels), dtype WHEEL_OUT
        Written with each lane's wheel outputs.
    ws : Workspace
        The lanes' workspaces, stacked (:func:`~trikedyn.model.lane_workspace.stacked_workspace`): each lane's
        ``e[0]``, ``tau``, the chassis' and the wheels' rows of ``ew``, ``pw``, ``v`` and ``fext`` written, and with
        ``keep_factor`` the factor of the mass matrix in ``low`` (the entries the scalar kernel writes).
    xdot : numpy.ndarray, shape (lanes, nx)
        Written with each lane's ``dx/dt``.
    keep_factor : bool
        Keep the factor of the mass matrix (the first stage of a step).
    """
    nb = plants.parent.shape[1]
    n = nb + 5
    for a in range(n_on):
        lane = on[a]
        g, k = lane // LANES, lane % LANES
        for i in range(n):
            bufs[g, _at(R_Q + i, k)] = xs[lane, i]
            bufs[g, _at(R_U + i, k)] = xs[lane, n + i]
    for g in range(bufs.shape[0]):
        kinematics_lanes(bufs[g])
    for a in range(n_on):
        lane = on[a]
        g, k = lane // LANES, lane % LANES
        ew, pw, v = borrowed(ws.ew[lane]), borrowed(ws.pw[lane]), borrowed(ws.v[lane])
        fext, tau = borrowed(ws.fext[lane]), borrowed(ws.tau[lane])
        pj = plant_of[job[lane]]
        wheels = borrowed(plants.wheels[pj])
        nw = wheels.shape[0]
        # only the bodies wrenches_into reads and loads: the chassis (its drag) and each wheel (its tyre); the
        # buffer's other external wrenches stay zero (a force on another body breaks the lanes' equality with
        # the scalar runs, which tests/simulate/test_specialised.py asserts)
        for c in range(nw + 1):
            b = 0 if c == nw else wheels[c].wheel_body
            for i in range(3):
                for j in range(3):
                    ew[b, i, j] = bufs[g, _at(R_EW + 9 * b + 3 * i + j, k)]
                pw[b, i] = bufs[g, _at(R_PW + 3 * b + i, k)]
            for i in range(6):
                v[b, i] = bufs[g, _at(R_V + 6 * b + i, k)]
        for i in range(3):
            for j in range(3):
                ws.e[lane, 0, i, j] = bufs[g, _at(R_E + 3 * i + j, k)]
        wrenches_into(ts[lane], borrowed(xs[lane]), borrowed(u[lane]), wheels, borrowed(plants.tyres[pj]),
                      borrowed(plants.vehicle[pj]), borrowed(plants.road[pj]), borrowed(wout[lane]), ew, pw, v, fext,
                      tau, borrowed(xdot[lane]))
        for i in range(n):
            bufs[g, _at(R_TAU + i, k)] = tau[i]
        for c in range(nw + 1):
            b = 0 if c == nw else wheels[c].wheel_body
            for i in range(6):
                bufs[g, _at(R_FEXT + 6 * b + i, k)] = fext[b, i]
    for g in range(bufs.shape[0]):
        if keep_factor:
            forward_dynamics_factor_lanes(bufs[g])
        else:
            forward_dynamics_lanes(bufs[g])
    parent = plants.parent[0]
    for a in range(n_on):
        lane = on[a]
        g, k = lane // LANES, lane % LANES
        for i in range(n):
            xdot[lane, n + i] = bufs[g, _at(R_UDOT + i, k)]
        euler_rates_into(borrowed(xs[lane, :n]), borrowed(xs[lane, n : 2 * n]), borrowed(ws.e[lane, 0]),
                         borrowed(xdot[lane, :n]))
        if keep_factor:
            for i in range(n):
                j = i
                while j != -1:
                    ws.low[lane, i, j] = bufs[g, _at(R_LOW + n * i + j, k)]
                    j = dof_parent(parent, j)


@jit
def etd_lanes(bufs, on, n_on, tl, h, x, k1, k2, k3, k4, xs, ts, u, plants, plant_of, job, drivers, inputs, n_inputs,
              wout, ws, scratch, idx, mat, fn, m_blocks, exponential, finite):
    """:func:`~trikedyn.simulate.integrator.etd_step` of ``h`` [s] for each lane of ``on[:n_on]``, the three
    later stages evaluated over the lanes (:func:`evaluate_lanes`), in place.

    Parameters
    ----------
    bufs : numpy.ndarray
        The lane buffers (:func:`evaluate_lanes`).
    on : numpy.ndarray of int
        The lanes stepped (the first ``n_on``).
    n_on : int
    tl : numpy.ndarray
        Each lane's time at the start of the step [s].
    h : float
        Step [s].
    x : numpy.ndarray, shape (lanes, nx)
        Each lane's state, advanced in place.
    k1 : numpy.ndarray, shape (lanes, nx)
        Each lane's first stage ``f(tl, x)``, evaluated (with ``wout`` and the factor in ``ws.low``).
    k2, k3, k4, xs, ts : numpy.ndarray
        The other stages, the stage states and the stage times [s]: scratch.
    u : numpy.ndarray, shape (lanes, 3)
        Each lane's inputs (steer [rad], drive [N m], brake [N m]); an open-loop lane's are interpolated at the
        stage times.
    plants, plant_of, job, drivers : Plant, numpy.ndarray
        The stacked plants, each job's plant, each lane's job, each job's driver (``on = 0``: open loop).
    inputs, n_inputs : numpy.ndarray
        Each job's input table and its length.
    wout, ws, scratch, idx, mat, fn, m_blocks
        Each lane's wheel outputs, stacked workspace and exponential blocks (their state indices, ``L`` [1/s],
        functions, count), as :func:`lane_batch_loop` holds them.
    exponential : bool
        ETDRK4 (True) or classical RK4.
    finite : numpy.ndarray of bool
        Written: whether each lane's new state is finite.
    """
    nx = x.shape[1]
    half = 0.5 * h
    no_factor = np.bool_(False)  # typed, not a literal: each literal argument value would compile the callee again
    for a in range(n_on):
        lane = on[a]
        j = job[lane]
        x_, xs_, k1_ = borrowed(x[lane]), borrowed(xs[lane]), borrowed(k1[lane])
        fn_, idx_, mat_ = borrowed(fn[lane]), borrowed(idx[lane]), borrowed(mat[lane])
        m = 0
        if exponential:
            m = spin_slip_blocks_ltdl(lane_plant(plants, plant_of[j]), borrowed(wout[lane]), borrowed(ws.low[lane]),
                                      borrowed(scratch[lane]), idx_, mat_)
        m_blocks[lane] = m
        block_functions(mat_, m, h, fn_)
        for i in range(nx):  # a = x + h/2 phi1(hL/2) N_n
            xs_[i] = x_[i] + half * k1_[i]
        stage_pairs(fn_, idx_, m, x_, k1_, half, xs_)
        if drivers[j].on <= 0.0:
            u[lane, 0], u[lane, 1], u[lane, 2] = interpolate_inputs(tl[lane] + half,
                                                                    borrowed(inputs[j, :n_inputs[j]]))
        ts[lane] = tl[lane] + half
    evaluate_lanes(bufs, on, n_on, ts, xs, u, plants, plant_of, job, wout, ws, k2, no_factor)
    for a in range(n_on):
        lane = on[a]
        m = m_blocks[lane]
        x_, xs_, k2_, idx_ = borrowed(x[lane]), borrowed(xs[lane]), borrowed(k2[lane]), borrowed(idx[lane])
        subtract_blocks(borrowed(mat[lane]), idx_, m, xs_, x_, k2_)
        for i in range(nx):  # b = x + h/2 phi1(hL/2) N_a
            xs_[i] = x_[i] + half * k2_[i]
        stage_pairs(borrowed(fn[lane]), idx_, m, x_, k2_, half, xs_)
    evaluate_lanes(bufs, on, n_on, ts, xs, u, plants, plant_of, job, wout, ws, k3, no_factor)
    for a in range(n_on):
        lane = on[a]
        j = job[lane]
        m = m_blocks[lane]
        x_, xs_, k3_, idx_ = borrowed(x[lane]), borrowed(xs[lane]), borrowed(k3[lane]), borrowed(idx[lane])
        subtract_blocks(borrowed(mat[lane]), idx_, m, xs_, x_, k3_)
        for i in range(nx):  # c = x + exp(hL/2) (a - x) + h/2 phi1(hL/2) (2 N_b - N_n)
            xs_[i] = x_[i] + h * k3_[i]
        third_stage_pairs(borrowed(fn[lane]), idx_, m, x_, borrowed(k1[lane]), k3_, half, xs_)
        if drivers[j].on <= 0.0:
            u[lane, 0], u[lane, 1], u[lane, 2] = interpolate_inputs(tl[lane] + h, borrowed(inputs[j, :n_inputs[j]]))
        ts[lane] = tl[lane] + h
    evaluate_lanes(bufs, on, n_on, ts, xs, u, plants, plant_of, job, wout, ws, k4, no_factor)
    for a in range(n_on):
        lane = on[a]
        m = m_blocks[lane]
        x_, xs_, k1_ = borrowed(x[lane]), borrowed(xs[lane]), borrowed(k1[lane])
        k2_, k3_, k4_ = borrowed(k2[lane]), borrowed(k3[lane]), borrowed(k4[lane])
        subtract_blocks(borrowed(mat[lane]), borrowed(idx[lane]), m, xs_, x_, k4_)
        # x + h (W1 N_n + W2 (N_a + N_b) + W3 N_c), the weights 1/6, 1/3, 1/6 outside the blocks
        for i in range(nx):
            xs_[i] = x_[i] + h * (k1_[i] / 6.0 + (k2_[i] + k3_[i]) / 3.0 + k4_[i] / 6.0)
        update_pairs(borrowed(fn[lane]), borrowed(idx[lane]), m, x_, k1_, k2_, k3_, k4_, h, xs_)
        ok = True
        for i in range(nx):
            x_[i] = xs_[i]
            if not np.isfinite(x_[i]):
                ok = False
        finite[lane] = ok


@jit
def lane_batch_loop(x0s, n_steps, plants, plant_of, inputs, n_inputs, paths, n_path, speeds, n_speeds, drivers,
                    stop_dts, dt, record_every, exponential, lanes, refill):
    """:func:`~trikedyn.simulate.lockstep.batch_loop` with each stage of a step evaluated over the lanes (see the
    module docstring): the same arguments, the same returns, each job's record its scalar run's bit for bit.

    Parameters
    ----------
    x0s, n_steps, plants, plant_of, inputs, n_inputs, paths, n_path, speeds, n_speeds, drivers, stop_dts
        The jobs, as :func:`~trikedyn.simulate.lockstep.batch_loop` takes them (states, steps, stacked plants,
        input tables, path rows, target speeds, drivers, largest substeps near a stop [s]).
    dt : float
        Step [s].
    record_every : int
        Steps between records.
    exponential : bool
        ETDRK4 (True) or classical RK4.
    lanes : int
        Lanes (runs advanced together); the lane kernels run on groups of ``LANES``.
    refill : bool
        A lane whose job ended takes the next job waiting.

    Returns
    -------
    times, states, derivatives, wheels, commands, status, n_recorded, t_stop
        As :func:`~trikedyn.simulate.lockstep.batch_loop`'s.
    """
    n_jobs, nx = x0s.shape
    nw = plants.wheels.shape[1]
    n = plants.parent.shape[1] + 5
    times, states, derivs, wheels, commands, status, recorded, t_stop, memory, delays, delay_lines = \
        batch_records(x0s, n_steps, record_every, nw, drivers)
    n_lanes = max(1, min(lanes, n_jobs))
    # the lane buffers: an idle lane computes on the first plant's values (finite arithmetic, result unread)
    bufs = np.zeros((-(-n_lanes // LANES), ROWS * LANES))
    for lane in range(bufs.shape[0] * LANES):
        set_lane_plant(bufs[lane // LANES], lane % LANES, lane_plant(plants, 0))
    # what a lane carries from step to step, as batch_loop, the workspaces stacked
    job, x, step, wout, u, xs, k1, k2, k3, k4, idx, mat, fn, scratch = lane_memory(n_lanes, nx, nw, n)
    ws = stacked_workspace(plants.parent[0], n_lanes)
    blank = np.zeros(nw, WHEEL_OUT)
    # the lanes of this step (busy, then those on the lane step), their times and outcomes
    on = np.empty(n_lanes, np.int64)
    regular = np.empty(n_lanes, np.int64)
    tl = np.zeros(n_lanes)
    ts = np.zeros(n_lanes)
    m_blocks = np.zeros(n_lanes, np.int64)
    finite = np.ones(n_lanes, np.bool_)
    alone = np.zeros(1, np.int64)
    one, keep_factor = np.int64(1), np.bool_(True)  # typed, not literals (each literal value: another compilation)
    tsub = np.zeros(n_lanes)
    waiting = 0
    busy = 0
    while True:
        if busy == 0 or refill:  # fill the free lanes
            for b in range(n_lanes):
                if job[b] < 0 and waiting < n_jobs:
                    start_job(b, waiting, x0s[waiting], blank, job, x, step, wout, u, idx, mat, fn)
                    set_lane_plant(bufs[b // LANES], b % LANES, lane_plant(plants, plant_of[waiting]))
                    waiting += 1
                    busy += 1
        if busy == 0:
            break
        # the commands, then the first stage, of every busy lane
        n_on = 0
        for b in range(n_lanes):
            j = job[b]
            if j < 0:
                continue
            on[n_on] = b
            n_on += 1
            t = 0.0 + step[b] * dt
            tl[b] = t
            d = drivers[j]
            if d.on > 0.0:
                veh = plants.vehicle[plant_of[j], 0]
                u[b, 0], u[b, 1], u[b, 2] = driver_step(t, dt, x[b, 0], x[b, 1], x[b, 5], x[b, n + 2], x[b, n + 3],
                                                        paths[j, :n_path[j]], speeds[j, :n_speeds[j]], d, veh,
                                                        memory[j], delay_lines[j, :delays[j]], inputs[j, :n_inputs[j]])
            else:
                u[b, 0], u[b, 1], u[b, 2] = interpolate_inputs(t, inputs[j, :n_inputs[j]])
        evaluate_lanes(bufs, on, np.int64(n_on), tl, x, u, plants, plant_of, job, wout, ws, k1, keep_factor)
        # records and the health watch; a lane near a stop takes its substeps alone
        n_regular = 0
        for a in range(n_on):
            b = on[a]
            j = job[b]
            pj = plant_of[j]
            t = tl[b]
            rec = recorded[j]
            if (step[b] % record_every == 0 or status[j] != STATUS_OK) and rec < times.shape[1]:
                times[j, rec] = t
                for i in range(nx):
                    states[j, rec, i] = x[b, i]
                    derivs[j, rec, i] = k1[b, i]
                for k in range(nw):
                    wheels[j, rec, k] = wout[b, k]
                commands[j, rec, 0], commands[j, rec, 1], commands[j, rec, 2] = u[b, 0], u[b, 1], u[b, 2]
                recorded[j] = rec + 1
            ended = run_ends(status[j], step[b], n_steps[j], record_every, x[b, 0], x[b, 1], x[b, 5], drivers[j])
            if not ended:
                for k in range(nw):
                    if wout[b, k].deflection > plants.vehicle[pj, 0].penetration_limit * plants.wheels[pj, k].radius:
                        status[j] = STATUS_PENETRATION
                        ended = True
                        break
            if ended:
                t_stop[j] = t
                job[b] = -1
                busy -= 1
                continue
            n_sub = 1
            if stop_dts[j] > 0.0 and dt > stop_dts[j] and near_a_stop(x[b], plants.wheels[pj], n, dt):
                n_sub = int(np.ceil(dt / stop_dts[j]))
            if n_sub == 1:
                regular[n_regular] = b
                n_regular += 1
                continue
            # near a stop: substeps of this lane alone, each the same lane step (the step's first stage is k1)
            h = dt / n_sub
            alone[0] = b
            for i in range(n_sub):
                tsub[b] = t + i * h
                if i > 0:
                    if drivers[j].on <= 0.0:
                        u[b, 0], u[b, 1], u[b, 2] = interpolate_inputs(tsub[b], inputs[j, :n_inputs[j]])
                    evaluate_lanes(bufs, alone, one, tsub, x, u, plants, plant_of, job, wout, ws, k1, keep_factor)
                etd_lanes(bufs, alone, one, tsub, h, x, k1, k2, k3, k4, xs, ts, u, plants, plant_of, job, drivers, inputs,
                          n_inputs, wout, ws, scratch, idx, mat, fn, m_blocks, exponential, finite)
                if not finite[b]:
                    break
        if n_regular > 0:
            etd_lanes(bufs, regular, np.int64(n_regular), tl, dt, x, k1, k2, k3, k4, xs, ts, u, plants, plant_of, job, drivers,
                      inputs, n_inputs, wout, ws, scratch, idx, mat, fn, m_blocks, exponential, finite)
        for a in range(n_on):
            b = on[a]
            j = job[b]
            if j < 0:
                continue
            step[b] += 1
            t = 0.0 + step[b] * dt
            if not finite[b]:
                status[j] = STATUS_NAN
                t_stop[j] = t
                job[b] = -1
                busy -= 1
            elif max(abs(x[b, 3]), abs(x[b, 4])) > plants.vehicle[plant_of[j], 0].roll_limit:
                status[j] = STATUS_ROLLOVER  # recorded at the lane's next step, which then ends the job
    return times, states, derivs, wheels, commands, status, recorded, t_stop
