"""The compiled right-hand side of the trike: forces, then exact multibody accelerations.

``f(t, x, u, p)``: the state ``x = (q, u, slips)`` (labels: :func:`trikedyn.model.packing.state_labels`,
``VehicleModel.state_names``), the inputs ``u = (steer [rad], drive torque [N m], brake torque per braked
wheel [N m])`` (:data:`~trikedyn.model.packing.INPUT_NAMES`), the plant ``p`` (a
:class:`~trikedyn.model.packing.Plant`, ``VehicleModel.plant``). Per evaluation:

1. kinematics of the tree and the body velocities;
2. per wheel: the tyre (:func:`trikedyn.tyre.interface.wheel_wrench`: contact, transient slips, the
   wheel's tyre model), applied as an external force and moment on the wheel;
3. joint forces: suspension springs with preload, dampers and one-sided bump stops (wheel rates through
   the motion ratio); per steering head a servo ``kp (delta_k - delta) - kd delta'`` on its own inertia,
   toward the angle the steering linkage gives that wheel (:func:`linkage_angle`: Ackermann geometry of a
   steered pair, by its Ackermann fraction; a single steered wheel takes the command); drive torque split
   equally over the driven wheels (open differential), limited by torque and power; brakes;
4. aerodynamic drag at the chassis CG, ``-0.5 rho Cd A |v_x| v_x`` along the chassis x axis;
5. ``du/dt = H^-1 (tau - C(q, u, f_ext))`` with gravity in ``C`` (RNEA, CRBA, Cholesky).

The time loop tabulates its inputs as ``(time [s], steer [rad], drive [N m], brake [N m])`` rows and
interpolates them linearly (:func:`interpolate_inputs`).
"""

from __future__ import annotations

import math

import numpy as np

from .._borrow import borrowed
from .._jit import jit
from ..tyre.interface import wheel_wrench
from .cholesky import cholesky_solve_into
from .dynamics import crba_into, joint_transforms_into, rnea_into, workspace
from .kinematics import body_velocities_into, euler_rates_into, world_transforms_into
from .packing import WHEEL_OUT

__all__ = ["evaluate_into", "evaluate_stage_into", "f", "f_with_outputs", "forces_into", "interpolate_inputs", "linkage_angle", "workspace",
           "wrenches_into"]


@jit(inline="always")
def interpolate_inputs(t, inputs):
    """Steer command [rad], drive torque [N m], brake torque [N m] at time ``t``.

    ``inputs`` is one row (constant inputs) or a table on a *uniform* time grid (see
    :func:`trikedyn.simulate.run.input_table`): the row is found by division, not by search, and held
    beyond the ends.

    Parameters
    ----------
    t : float
        Time [s].
    inputs : numpy.ndarray, shape (m, 4)
        Rows (time [s], steer [rad], drive [N m], brake [N m]).

    Returns
    -------
    steer, drive, brake : float
        Steer command [rad], drive torque [N m], brake torque [N m], linearly interpolated.
    """
    m = inputs.shape[0]
    if m == 1:
        return inputs[0, 1], inputs[0, 2], inputs[0, 3]
    t0 = inputs[0, 0]
    step = inputs[1, 0] - t0
    pos = (t - t0) / step
    if pos <= 0.0:
        return inputs[0, 1], inputs[0, 2], inputs[0, 3]
    i = int(pos)
    if i >= m - 1:
        return inputs[m - 1, 1], inputs[m - 1, 2], inputs[m - 1, 3]
    w = pos - i
    return (
        inputs[i, 1] + w * (inputs[i + 1, 1] - inputs[i, 1]),
        inputs[i, 2] + w * (inputs[i + 1, 2] - inputs[i, 2]),
        inputs[i, 3] + w * (inputs[i + 1, 3] - inputs[i, 3]),
    )


@jit(inline="always")
def linkage_angle(command, steer_y, veh):
    """The steer angle of one steered wheel [rad, about its steering axis] for a steer command [rad].

    The command is the angle of a single wheel on the centre line. A head turned by ``theta`` about a
    steering axis raked by ``epsilon`` points its wheel at the road angle ``delta`` with ``tan(delta) =
    cos(epsilon) tan(theta)``. A wheel ``steer_y`` [m] off the centre line, on a linkage with Ackermann
    fraction ``f``, takes the road angle ``delta + f (delta_A - delta)``, where ``tan(delta_A) = L
    tan(delta) / (L - y tan(delta))`` points it at the turn centre on the rear axle line (``L`` the
    wheelbase): the inner wheel steers more. A wheel on the centre line, or ``f = 0`` (parallel steer),
    takes the command unchanged.

    Parameters
    ----------
    command : float
        Steer command [rad] (a centre-line wheel's angle about the steering axis).
    steer_y : float
        Lateral position of the wheel [m].
    veh : record
        The vehicle record (``cos_rake``, ``ackermann``, ``wheelbase`` [m]).

    Returns
    -------
    float
        The wheel's steer angle about its steering axis [rad].
    """
    if steer_y == 0.0 or veh.ackermann == 0.0:
        return command
    tan_road = veh.cos_rake * math.tan(command)
    road = math.atan(tan_road)
    wheelbase = veh.wheelbase
    den = max(wheelbase - steer_y * tan_road, 0.05 * wheelbase)
    ackermann = math.atan(wheelbase * tan_road / den)
    return math.atan(math.tan(road + veh.ackermann * (ackermann - road)) / veh.cos_rake)


@jit
def forces_into(t, x, u, p, wout, ws, xdot):
    """Everything of ``f(t, x, u, p)`` but the multibody accelerations: steps 1-4 of the module docstring.

    Writes the joint transforms, world poses and body velocities into ``ws`` (``e``, ``r``, ``ew``, ``pw``,
    ``v``), the joint forces into ``ws.tau`` [N, N m], the external wrenches on the bodies (as
    the RNEA takes them) into ``ws.fext`` and the slip rates into ``xdot[2 n:]``; :func:`evaluate_into` then
    adds the accelerations. The generic kinematics, then :func:`wrenches_into` (compiled on its own, not
    inlined: the tyres are compiled once and shared by the generic loop and every generated one, whose
    kinematics are generated).

    Parameters
    ----------
    t : float
        Time [s].
    x : numpy.ndarray
        State (``VehicleModel.state_names``).
    u : numpy.ndarray, shape (3,)
        Inputs: steer command [rad], drive torque [N m], brake torque [N m].
    p : Plant
        The compiled vehicle (``VehicleModel.plant``).
    wout : numpy.ndarray, dtype WHEEL_OUT
        Written with the per-wheel outputs (loads [N], slips, deflection [m] ...).
    ws : Workspace
        Scratch arrays from :func:`~trikedyn.model.dynamics.workspace`.
    xdot : numpy.ndarray
        Written with ``dx/dt``.
    """
    n = p.parent.shape[0] + 5
    q = x[:n]
    qd = x[n : 2 * n]
    e = ws.e
    joint_transforms_into(q, p.parent, p.jtype, p.jaxis, p.tree_e, p.tree_r, e, ws.r, ws.t33)
    world_transforms_into(p.parent, e, ws.r, ws.ew, ws.pw)
    body_velocities_into(e, ws.r, qd, p.parent, p.jtype, p.jaxis, ws.v)
    wrenches_into(t, x, u, p.wheels, p.tyres, p.vehicle, p.road, wout, ws.ew, ws.pw, ws.v, ws.fext, ws.tau, xdot)


@jit
def wrenches_into(t, x, u, wheels, tyres, vehicle, road, wout, ew, pw, v, fext, tau, xdot):
    """:func:`forces_into` after the kinematics: the tyres, springs, steering servo, drive, brakes and drag
    from the world poses and body velocities already computed; the generated loops
    (:mod:`trikedyn.simulate.specialised`) compute those by their own kinematics kernel, then call this.

    It takes the arrays it reads rather than the plant and the workspace: numba passes every array of a
    tuple argument member by member, and a call with the whole plant and workspace cost ~0.2 us more
    (``python benchmarks/step_parts.py``).

    Parameters
    ----------
    t : float
        Time [s].
    x : numpy.ndarray
        State.
    u : numpy.ndarray, shape (3,)
        Inputs: steer command [rad], drive torque [N m], brake torque [N m].
    wheels, tyres, vehicle, road : numpy.ndarray
        The plant's ``wheels``, ``tyres``, ``vehicle`` and ``road`` (:class:`~trikedyn.model.packing.Plant`).
    wout : numpy.ndarray, dtype WHEEL_OUT
        Written with the per-wheel outputs.
    ew, pw, v : numpy.ndarray
        World -> body rotations (nb, 3, 3), body origins in the world (nb, 3) [m], body velocities (nb, 6)
        [rad/s, m/s] (the workspace's ``ew``, ``pw``, ``v``).
    fext, tau : numpy.ndarray
        Written with the external wrenches on the bodies (nb, 6) [N m, N] and the joint forces [N, N m].
    xdot : numpy.ndarray
        Written with the slip rates (``xdot[2 n:]``).
    """
    nb = ew.shape[0]
    n = nb + 5
    nw = wheels.shape[0]
    veh = vehicle[0]
    q = borrowed(x[:n])
    qd = borrowed(x[n : 2 * n])
    slip = borrowed(x[2 * n :])
    fext[:, :] = 0.0
    tau[:] = 0.0
    steer_cmd, drive_cmd, brake_cmd = u[0], u[1], u[2]

    drive = min(max(drive_cmd, -veh.max_torque), veh.max_torque)
    spin_sum = 0.0
    for k in range(nw):
        if wheels[k].driven == 1:
            spin_sum += abs(qd[5 + wheels[k].wheel_body])
    spin_mean = spin_sum / veh.n_driven
    if abs(drive) * spin_mean > veh.max_power:
        drive = math.copysign(veh.max_power / spin_mean, drive)
    brake = min(max(brake_cmd, 0.0), veh.max_brake)
    steer = min(max(steer_cmd, -veh.max_steer), veh.max_steer)

    slip_off = 2 * n
    for k in range(nw):
        w = wheels[k]
        wb = w.wheel_body
        out = wout[k]
        fwx, fwy, fwz, mwx, mwy, mwz, dkappa, dtan = wheel_wrench(
            w, borrowed(tyres[k]), veh, road[0], borrowed(ew[wb]), pw[wb, 0], pw[wb, 1], pw[wb, 2], borrowed(v[wb]),
            slip[2 * k], slip[2 * k + 1], out)
        xdot[slip_off + 2 * k] = dkappa
        xdot[slip_off + 2 * k + 1] = dtan
        eb = borrowed(ew[wb])
        for i in range(3):
            fext[wb, i] = eb[i, 0] * mwx + eb[i, 1] * mwy + eb[i, 2] * mwz
            fext[wb, 3 + i] = eb[i, 0] * fwx + eb[i, 1] * fwy + eb[i, 2] * fwz
        sb = w.spring_body
        z = q[5 + sb]
        zd = qd[5 + sb]
        mr = w.motion_ratio
        travel = mr * z
        force = -w.preload - w.stiffness * z - w.damping * zd
        if travel > w.bump_travel:
            force -= w.bump_stop_stiffness * (travel - w.bump_travel) * mr
        elif travel < -w.rebound_travel:
            force += w.bump_stop_stiffness * (-w.rebound_travel - travel) * mr
        tau[5 + sb] += force
        out.travel = travel
        hb = w.steer_body
        if hb >= 0:
            target = linkage_angle(steer, w.steer_y, veh)
            tau[5 + hb] += w.steer_kp * (target - q[5 + hb]) - w.steer_kd * qd[5 + hb]
        if w.driven == 1:
            tau[5 + wb] += drive / veh.n_driven
        if w.braked == 1 and brake > 0.0:
            tau[5 + wb] -= brake * math.tanh(qd[5 + wb] / veh.w_low)

    if veh.aero > 0.0:
        pz = veh.aero_z  # drag acts at (aero_x, 0, pz); its x does not change the moment
        vax = v[0, 3] + (v[0, 1] * pz)  # x component of v + w x p
        drag = -veh.aero * abs(vax) * vax
        fext[0, 1] += pz * drag  # p x (drag, 0, 0) = (0, pz drag, 0)
        fext[0, 3] += drag



@jit
def evaluate_into(t, x, u, p, wout, ws, xdot):
    """``xdot = f(t, x, u, p)`` into ``xdot``; fills ``wout`` (:data:`WHEEL_OUT` per wheel); ``ws`` from
    :func:`workspace`. The forces (:func:`forces_into`), then ``du/dt`` by the generic RNEA, CRBA and a
    Cholesky solve (its factor stays in ``ws.low``), then ``dq/dt``.

    Parameters
    ----------
    t : float
        Time [s].
    x : numpy.ndarray
        State (``VehicleModel.state_names``).
    u : numpy.ndarray, shape (3,)
        Inputs: steer command [rad], drive torque [N m], brake torque [N m].
    p : Plant
        The compiled vehicle (``VehicleModel.plant``).
    wout : numpy.ndarray, dtype WHEEL_OUT
        Written with the per-wheel outputs (loads [N], slips, deflection [m] ...).
    ws : Workspace
        Scratch arrays from :func:`~trikedyn.model.dynamics.workspace`.
    xdot : numpy.ndarray
        Written with ``dx/dt``.
    """
    forces_into(t, x, u, p, wout, ws, xdot)
    n = p.parent.shape[0] + 5
    q = x[:n]
    qd = x[n : 2 * n]
    tau, e = ws.tau, ws.e
    gravity = (0.0, 0.0, -p.vehicle[0].g)
    bias = ws.bias
    rnea_into(e, ws.r, qd, ws.zero, ws.fext, gravity, p.parent, p.jtype, p.jaxis, p.mass, p.h, p.ibar, ws, bias, True)
    crba_into(e, ws.r, p.parent, p.jtype, p.jaxis, p.mass, p.h, p.ibar, ws)
    for i in range(n):
        tau[i] -= bias[i]
    cholesky_solve_into(ws.hmat, tau, ws.low, ws.vec, xdot[n : 2 * n])
    euler_rates_into(q, qd, e[0], xdot[:n])


evaluate_stage_into = evaluate_into
"""The right-hand side at an inner stage of a step (the second to fourth of
:func:`~trikedyn.simulate.integrator.etd_step`): :func:`evaluate_into`'s arguments and results, except that
``ws.low`` need not hold the factor of the mass matrix afterwards (only the first stage's factor is read, by
the exponential blocks). Here the same function (the Cholesky factor is the solve's by-product); the
generated kernels (:mod:`trikedyn.simulate.specialised`) bind a right-hand side that skips storing it."""


@jit
def f(t, x, u, p):
    """The right-hand side ``dx/dt = f(t, x, u, p)`` (allocating; for tests and scipy's solvers).

    Parameters
    ----------
    t : float
        Time [s] (the model is autonomous: unused but for the signature).
    x : ndarray
        State (``VehicleModel.state_names``).
    u : ndarray (3,)
        Inputs (:data:`~trikedyn.model.packing.INPUT_NAMES`).
    p : Plant
        ``VehicleModel.plant``.

    Returns
    -------
    ndarray
        ``dx/dt``. ``scipy.integrate.solve_ivp(f, span, x0, args=(u, model.plant))`` integrates it.
    """
    ws = workspace(p.parent)
    xdot = np.empty(x.shape[0])
    wout = np.zeros(p.wheels.shape[0], WHEEL_OUT)
    evaluate_into(t, x, u, p, wout, ws, xdot)
    return xdot


@jit
def f_with_outputs(t, x, u, p):
    """:func:`f` and the per-wheel outputs (a :data:`WHEEL_OUT` array).

    Parameters
    ----------
    t : float
        Time [s].
    x : numpy.ndarray
        State (``VehicleModel.state_names``).
    u : numpy.ndarray, shape (3,)
        Inputs: steer command [rad], drive torque [N m], brake torque [N m].
    p : Plant
        The compiled vehicle (``VehicleModel.plant``).

    Returns
    -------
    xdot : numpy.ndarray
        ``dx/dt``.
    wout : numpy.ndarray, dtype WHEEL_OUT
        Per-wheel outputs.
    """
    ws = workspace(p.parent)
    xdot = np.empty(x.shape[0])
    wout = np.zeros(p.wheels.shape[0], WHEEL_OUT)
    evaluate_into(t, x, u, p, wout, ws, xdot)
    return xdot, wout
