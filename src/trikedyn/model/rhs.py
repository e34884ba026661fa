"""The compiled right-hand side of the trike: forces, then exact multibody accelerations.

State ``x = (q, u)`` (see :mod:`trikedyn.model.dynamics`). Per evaluation:

1. kinematics of the tree and the body velocities;
2. per wheel: disc-on-road contact (the lowest point of the wheel disc along the road normal),
   tyre deflection and its rate, tyre axes, slips and the tyre forces
   (:mod:`trikedyn.tyre.magic_formula`), applied at the contact point as an external force on the wheel;
3. joint forces: suspension springs with preload, dampers and one-sided bump stops (wheel rates through
   the motion ratio); the steering servo ``kp (delta_cmd - delta) - kd delta'``; drive torque split
   equally over the driven wheels (open differential), limited by torque and power; brakes;
   Slips are transient (first-order relaxation, Pacejka 2006 ch. 7): per wheel two states, the
   longitudinal slip ``kappa'`` and the lateral slip ``s_y' = tan(alpha')``, with
   ``sigma_x dkappa'/dt = (omega R_e - v_x) - v_ref kappa'`` and ``sigma_y ds_y'/dt = -v_y - v_ref s_y'``
   (``v_ref`` the regularised speed of :func:`~trikedyn.tyre.magic_formula.slip_quantities`); in steady
   state they equal the slips. This keeps the wheel-spin mode a well-damped oscillation at every speed
   instead of a stiff mode whose rate grows as 1/v;
4. aerodynamic drag at the chassis CG, ``-0.5 rho Cd A |v_x| v_x`` along the chassis x axis;
5. ``du/dt = H^-1 (tau - C(q, u, f_ext))`` with gravity in ``C`` (RNEA, CRBA, Cholesky).

Inputs are a table ``(time [s], steer command [rad], drive torque [N m], brake torque per wheel [N m])``
interpolated linearly in time.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit
from ..tyre.magic_formula import combined_forces, rolling_resistance_moment, vertical_force
from .dynamics import (
    W_BIAS,
    W_E,
    W_EW,
    W_FEXT,
    W_HMAT,
    W_LOW,
    W_PW,
    W_R,
    W_T33,
    W_TAU,
    W_V,
    W_VEC,
    W_ZERO,
    body_velocities_into,
    cholesky_solve_into,
    crba_into,
    euler_rates_into,
    joint_transforms_into,
    rnea_into,
    workspace,
    world_transforms_into,
)
from .vehicle import (
    R_HEIGHT,
    R_KIND,
    R_LENGTH,
    R_X0,
    R_YMAX,
    R_YMIN,
    ROAD_BUMP,
    S_AERO,
    S_AERO_Z,
    S_G,
    S_MAX_BRAKE,
    S_MAX_POWER,
    S_MAX_STEER,
    S_MAX_TORQUE,
    S_N_DRIVEN,
    S_SIGMA_X,
    S_SIGMA_Y,
    S_SLIP_FORCES,
    S_STEER_KD,
    S_STEER_KP,
    S_V_LOW,
    S_W_LOW,
    WF_BUMP,
    WF_C,
    WF_K,
    WF_KSTOP,
    WF_MR,
    WF_PRELOAD,
    WF_RADIUS,
    WF_REBOUND,
    WI_BRAKED,
    WI_DRIVEN,
    WI_SPRING,
    WI_STEER,
    WI_WHEEL,
)

__all__ = ["N_WOUT", "W_FX", "W_FY", "W_FZ", "evaluate", "evaluate_into", "interpolate_inputs", "road_height", "workspace"]

# per-wheel outputs of :func:`evaluate`
W_FX, W_FY, W_FZ, W_KAPPA, W_ALPHA, W_DEFLECTION, W_TRAVEL, W_SPIN, W_VX = range(9)
N_WOUT = 9


@jit(inline="always")
def road_height(x, y, road):
    """Road height [m] and its slopes ``dh/dx``, ``dh/dy`` at ``(x, y)``."""
    if road[R_KIND] == ROAD_BUMP and road[R_YMIN] <= abs(y) <= road[R_YMAX]:
        s = (x - road[R_X0]) / road[R_LENGTH]
        if 0.0 < s < 1.0:
            height = road[R_HEIGHT]
            return (
                0.5 * height * (1.0 - math.cos(2.0 * math.pi * s)),
                height * math.pi / road[R_LENGTH] * math.sin(2.0 * math.pi * s),
                0.0,
            )
    return 0.0, 0.0, 0.0


@jit(inline="always")
def interpolate_inputs(t, inputs):
    """Steer command [rad], drive torque [N m], brake torque [N m] at time ``t``.

    ``inputs`` is one row (constant inputs) or a table on a *uniform* time grid (see
    :func:`trikedyn.simulate.run.input_table`): the row is found by division, not by search, and held
    beyond the ends.
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
def _tyre(k, wheel_f, wheel_i, tyre, sc, road, ew, pw, v, slip, xdot, slip_off, fext, wout):
    """Contact and tyre forces of wheel ``k``: fills ``fext`` of its body, its slip rates and ``wout``."""
    wb = wheel_i[k, WI_WHEEL]
    radius = wheel_f[k, WF_RADIUS]
    e = ew[wb]
    cx, cy, cz = pw[wb, 0], pw[wb, 1], pw[wb, 2]
    ax, ay, az = e[1, 0], e[1, 1], e[1, 2]  # wheel spin axis in world coordinates
    flat = road[R_KIND] != ROAD_BUMP
    if flat:
        hx, hy = 0.0, 0.0
    else:
        _, hx, hy = road_height(cx, cy, road)
    nn = 1.0 / math.sqrt(hx * hx + hy * hy + 1.0)
    nx, ny, nz = -hx * nn, -hy * nn, nn
    dot = nx * ax + ny * ay + nz * az
    dx, dy, dz = nx - dot * ax, ny - dot * ay, nz - dot * az
    dn = -radius / math.sqrt(dx * dx + dy * dy + dz * dz)
    rx, ry, rz = dx * dn, dy * dn, dz * dn  # centre -> contact point
    px, py, pz = cx + rx, cy + ry, cz + rz
    if flat:
        hp, hpx, hpy = 0.0, 0.0, 0.0
    else:
        hp, hpx, hpy = road_height(px, py, road)
    deflection = (hp - pz) * nz
    # wheel angular velocity and centre velocity in world coordinates
    vb = v[wb]
    wx = e[0, 0] * vb[0] + e[1, 0] * vb[1] + e[2, 0] * vb[2]
    wy = e[0, 1] * vb[0] + e[1, 1] * vb[1] + e[2, 1] * vb[2]
    wz = e[0, 2] * vb[0] + e[1, 2] * vb[1] + e[2, 2] * vb[2]
    vcx = e[0, 0] * vb[3] + e[1, 0] * vb[4] + e[2, 0] * vb[5]
    vcy = e[0, 1] * vb[3] + e[1, 1] * vb[4] + e[2, 1] * vb[5]
    vcz = e[0, 2] * vb[3] + e[1, 2] * vb[4] + e[2, 2] * vb[5]
    rate = (hpx * vcx + hpy * vcy - vcz) * nz
    # tyre axes: ex = axle x n (forward), ey = n x ex
    exx, exy, exz = ay * nz - az * ny, az * nx - ax * nz, ax * ny - ay * nx
    en = 1.0 / math.sqrt(exx * exx + exy * exy + exz * exz)
    exx, exy, exz = exx * en, exy * en, exz * en
    eyx, eyy, eyz = ny * exz - nz * exy, nz * exx - nx * exz, nx * exy - ny * exx
    vx = vcx * exx + vcy * exy + vcz * exz
    vy = vcx * eyx + vcy * eyy + vcz * eyz
    spin = wx * ax + wy * ay + wz * az
    r_eff = radius - deflection / 3.0
    v_low = sc[S_V_LOW]
    v_ref = math.sqrt(math.sqrt(vx * vx * vx * vx + v_low * v_low * v_low * v_low))
    kappa = slip[2 * k]
    tan_alpha = slip[2 * k + 1]
    alpha = math.atan(tan_alpha)
    xdot[slip_off + 2 * k] = (spin * r_eff - vx - v_ref * kappa) / sc[S_SIGMA_X]
    xdot[slip_off + 2 * k + 1] = (-vy - v_ref * tan_alpha) / sc[S_SIGMA_Y]
    fz = vertical_force(deflection, rate, tyre)
    fx = 0.0
    fy = 0.0
    my = 0.0
    if fz > 0.0 and sc[S_SLIP_FORCES] > 0.0:
        fx, fy = combined_forces(kappa, alpha, fz, tyre)
        my = rolling_resistance_moment(fz, spin, r_eff, tyre, sc[S_W_LOW])
    fwx = fx * exx + fy * eyx + fz * nx
    fwy = fx * exy + fy * eyy + fz * ny
    fwz = fx * exz + fy * eyz + fz * nz
    mwx = ry * fwz - rz * fwy + my * ax
    mwy = rz * fwx - rx * fwz + my * ay
    mwz = rx * fwy - ry * fwx + my * az
    for i in range(3):
        fext[wb, i] = e[i, 0] * mwx + e[i, 1] * mwy + e[i, 2] * mwz
        fext[wb, 3 + i] = e[i, 0] * fwx + e[i, 1] * fwy + e[i, 2] * fwz
    wout[k, W_FX] = fx
    wout[k, W_FY] = fy
    wout[k, W_FZ] = fz
    wout[k, W_KAPPA] = kappa
    wout[k, W_ALPHA] = alpha
    wout[k, W_DEFLECTION] = deflection
    wout[k, W_SPIN] = spin
    wout[k, W_VX] = vx


@jit
def evaluate_into(t, x, inputs, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar,
                  wheel_f, wheel_i, tyre, sc, road, wout, ws, xdot):
    """``xdot = dx/dt`` at ``(t, x)``; fills ``wout`` (n_wheels, N_WOUT); ``ws`` from :func:`workspace`."""
    nb = parent.shape[0]
    n = nb + 5
    nw = wheel_f.shape[0]
    q = x[:n]
    u = x[n : 2 * n]
    slip = x[2 * n :]
    e, r, ew, pw, v, fext = ws[W_E], ws[W_R], ws[W_EW], ws[W_PW], ws[W_V], ws[W_FEXT]
    joint_transforms_into(q, parent, jtype, jaxis, tree_e, tree_r, e, r, ws[W_T33])
    world_transforms_into(parent, e, r, ew, pw)
    body_velocities_into(e, r, u, parent, jtype, jaxis, v)
    fext[:, :] = 0.0
    tau = ws[W_TAU]
    tau[:] = 0.0
    steer_cmd, drive_cmd, brake_cmd = interpolate_inputs(t, inputs)

    drive = min(max(drive_cmd, -sc[S_MAX_TORQUE]), sc[S_MAX_TORQUE])
    spin_sum = 0.0
    for k in range(nw):
        if wheel_i[k, WI_DRIVEN] == 1:
            spin_sum += abs(u[5 + wheel_i[k, WI_WHEEL]])
    spin_mean = spin_sum / sc[S_N_DRIVEN]
    if abs(drive) * spin_mean > sc[S_MAX_POWER]:
        drive = math.copysign(sc[S_MAX_POWER] / spin_mean, drive)
    brake = min(max(brake_cmd, 0.0), sc[S_MAX_BRAKE])

    for k in range(nw):
        _tyre(k, wheel_f, wheel_i, tyre, sc, road, ew, pw, v, slip, xdot, 2 * n, fext, wout)
        sb = wheel_i[k, WI_SPRING]
        z = q[5 + sb]
        zd = u[5 + sb]
        mr = wheel_f[k, WF_MR]
        travel = mr * z
        force = -wheel_f[k, WF_PRELOAD] - wheel_f[k, WF_K] * z - wheel_f[k, WF_C] * zd
        if travel > wheel_f[k, WF_BUMP]:
            force -= wheel_f[k, WF_KSTOP] * (travel - wheel_f[k, WF_BUMP]) * mr
        elif travel < -wheel_f[k, WF_REBOUND]:
            force += wheel_f[k, WF_KSTOP] * (-wheel_f[k, WF_REBOUND] - travel) * mr
        tau[5 + sb] += force
        wout[k, W_TRAVEL] = travel
        hb = wheel_i[k, WI_STEER]
        if hb >= 0:
            cmd = min(max(steer_cmd, -sc[S_MAX_STEER]), sc[S_MAX_STEER])
            tau[5 + hb] += sc[S_STEER_KP] * (cmd - q[5 + hb]) - sc[S_STEER_KD] * u[5 + hb]
        wb = wheel_i[k, WI_WHEEL]
        if wheel_i[k, WI_DRIVEN] == 1:
            tau[5 + wb] += drive / sc[S_N_DRIVEN]
        if wheel_i[k, WI_BRAKED] == 1 and brake > 0.0:
            tau[5 + wb] -= brake * math.tanh(u[5 + wb] / sc[S_W_LOW])

    if sc[S_AERO] > 0.0:
        pz = sc[S_AERO_Z]  # drag acts at (S_AERO_X, 0, pz); its x does not change the moment
        vax = v[0, 3] + (v[0, 1] * pz)  # x component of v + w x p
        drag = -sc[S_AERO] * abs(vax) * vax
        fext[0, 1] += pz * drag  # p x (drag, 0, 0) = (0, pz drag, 0)
        fext[0, 3] += drag

    gravity = (0.0, 0.0, -sc[S_G])
    bias = ws[W_BIAS]
    rnea_into(e, r, u, ws[W_ZERO], fext, gravity, parent, jtype, jaxis, mass, h, ibar, ws, bias, True)
    crba_into(e, r, parent, jtype, jaxis, mass, h, ibar, ws)
    for i in range(n):
        tau[i] -= bias[i]
    cholesky_solve_into(ws[W_HMAT], tau, ws[W_LOW], ws[W_VEC], xdot[n : 2 * n])
    euler_rates_into(q, u, e[0], xdot[:n])


@jit
def evaluate(t, x, inputs, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar, wheel_f, wheel_i, tyre, sc, road, wout):
    """``dx/dt`` at ``(t, x)`` (allocating; see :func:`evaluate_into`)."""
    ws = workspace(parent)
    xdot = np.empty(x.shape[0])
    evaluate_into(t, x, inputs, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar,
                  wheel_f, wheel_i, tyre, sc, road, wout, ws, xdot)
    return xdot


def _body_velocities_py(e, r, u, tree):
    """Body spatial velocities (for tests and post-processing; allocating)."""
    v = np.empty((tree.n_bodies, 6))
    body_velocities_into(e, r, u, tree.parent, tree.jtype, tree.jaxis, v)
    return v
