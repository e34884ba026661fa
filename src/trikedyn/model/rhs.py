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
from numba import njit

from ..tyre.magic_formula import combined_forces, rolling_resistance_moment, vertical_force
from .dynamics import cholesky_solve, crba_er, euler_rates, joint_transforms, rnea_er, world_transforms
from .spatial import cross, xform_motion
from .vehicle import (
    R_HEIGHT,
    R_KIND,
    R_LENGTH,
    R_X0,
    ROAD_BUMP,
    S_AERO,
    S_AERO_X,
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

__all__ = ["road_height", "interpolate_inputs", "evaluate", "W_FX", "W_FY", "W_FZ", "N_WOUT"]

# per-wheel outputs of :func:`evaluate`
W_FX, W_FY, W_FZ, W_KAPPA, W_ALPHA, W_DEFLECTION, W_TRAVEL, W_SPIN, W_VX = range(9)
N_WOUT = 9


@njit(cache=True)
def road_height(x, y, road):
    """Road height [m] and its slopes ``dh/dx``, ``dh/dy`` at ``(x, y)``."""
    if road[R_KIND] == ROAD_BUMP:
        s = (x - road[R_X0]) / road[R_LENGTH]
        if 0.0 < s < 1.0:
            height = road[R_HEIGHT]
            return (
                0.5 * height * (1.0 - math.cos(2.0 * math.pi * s)),
                height * math.pi / road[R_LENGTH] * math.sin(2.0 * math.pi * s),
                0.0,
            )
    return 0.0, 0.0, 0.0


@njit(cache=True)
def interpolate_inputs(t, inputs):
    """Steer command [rad], drive torque [N m], brake torque [N m] at time ``t``."""
    if inputs.shape[0] == 1:
        return inputs[0, 1], inputs[0, 2], inputs[0, 3]
    times = inputs[:, 0]
    return np.interp(t, times, inputs[:, 1]), np.interp(t, times, inputs[:, 2]), np.interp(t, times, inputs[:, 3])


@njit(cache=True)
def _body_velocities(e, r, u, parent, jtype, jaxis):
    nb = parent.shape[0]
    v = np.empty((nb, 6))
    tmp = np.empty(6)
    v[0] = u[:6]
    for i in range(1, nb):
        xform_motion(e[i], r[i], v[parent[i]], tmp)
        if jtype[i] == 1:
            tmp[:3] += jaxis[i] * u[5 + i]
        else:
            tmp[3:] += jaxis[i] * u[5 + i]
        v[i] = tmp
    return v


@njit(cache=True)
def _tyre(k, wheel_f, wheel_i, tyre, sc, road, ew, pw, v, slip, slip_dot, fext, wout):
    """Contact and tyre forces of wheel ``k``: fills ``fext`` of its body, its slip rates and ``wout``."""
    wb = wheel_i[k, WI_WHEEL]
    radius = wheel_f[k, WF_RADIUS]
    ew_k = ew[wb]
    centre = pw[wb]
    axle = ew_k[1].copy()  # wheel y axis in world coordinates
    _, hx, hy = road_height(centre[0], centre[1], road)
    nrm = np.array([-hx, -hy, 1.0])
    nrm /= math.sqrt(nrm @ nrm)
    down = nrm - (nrm @ axle) * axle
    cos_camber = math.sqrt(down @ down)
    down /= -cos_camber
    contact = centre + radius * down
    hp, hpx, hpy = road_height(contact[0], contact[1], road)
    deflection = (hp - contact[2]) * nrm[2]
    omega_w = ew_k.T @ v[wb, :3]
    vel_c = ew_k.T @ v[wb, 3:]
    rate = (hpx * vel_c[0] + hpy * vel_c[1] - vel_c[2]) * nrm[2]
    ex = cross(axle, nrm)
    ex /= math.sqrt(ex @ ex)
    ey = cross(nrm, ex)
    vx = vel_c @ ex
    vy = vel_c @ ey
    spin = omega_w @ axle
    r_eff = radius - deflection / 3.0
    v_low = sc[S_V_LOW]
    v_ref = math.sqrt(math.sqrt(vx * vx * vx * vx + v_low * v_low * v_low * v_low))
    kappa = slip[2 * k]
    alpha = math.atan(slip[2 * k + 1])
    slip_dot[2 * k] = (spin * r_eff - vx - v_ref * kappa) / sc[S_SIGMA_X]
    slip_dot[2 * k + 1] = (-vy - v_ref * slip[2 * k + 1]) / sc[S_SIGMA_Y]
    fz = vertical_force(deflection, rate, tyre)
    fx = 0.0
    fy = 0.0
    my = 0.0
    if fz > 0.0 and sc[S_SLIP_FORCES] > 0.0:
        fx, fy = combined_forces(kappa, alpha, fz, tyre)
        my = rolling_resistance_moment(fz, spin, r_eff, tyre, sc[S_W_LOW])
    force = fx * ex + fy * ey + fz * nrm
    moment = cross(contact - centre, force) + my * axle
    fext[wb, :3] = ew_k @ moment
    fext[wb, 3:] = ew_k @ force
    wout[k, W_FX] = fx
    wout[k, W_FY] = fy
    wout[k, W_FZ] = fz
    wout[k, W_KAPPA] = kappa
    wout[k, W_ALPHA] = alpha
    wout[k, W_DEFLECTION] = deflection
    wout[k, W_SPIN] = spin
    wout[k, W_VX] = vx


@njit(cache=True)
def evaluate(t, x, inputs, parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar,
             wheel_f, wheel_i, tyre, sc, road, wout):
    """``dx/dt`` at ``(t, x)``; fills ``wout`` (n_wheels, N_WOUT) with the per-wheel outputs."""
    n = parent.shape[0] + 5
    nw = wheel_f.shape[0]
    q = x[:n]
    u = x[n : 2 * n]
    slip = x[2 * n :]
    xdot = np.empty(2 * n + 2 * nw)
    e, r = joint_transforms(q, parent, jtype, jaxis, tree_e, tree_r)
    ew, pw = world_transforms(parent, e, r)
    v = _body_velocities(e, r, u, parent, jtype, jaxis)
    fext = np.zeros((parent.shape[0], 6))
    tau = np.zeros(n)
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
        _tyre(k, wheel_f, wheel_i, tyre, sc, road, ew, pw, v, slip, xdot[2 * n :], fext, wout)
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
        point = np.array([sc[S_AERO_X], 0.0, sc[S_AERO_Z]])
        vel = v[0, 3:] + cross(v[0, :3], point)
        drag = np.array([-sc[S_AERO] * abs(vel[0]) * vel[0], 0.0, 0.0])
        fext[0, :3] += cross(point, drag)
        fext[0, 3:] += drag

    gravity = np.array([0.0, 0.0, -sc[S_G]])
    bias = rnea_er(e, r, u, np.zeros(n), fext, gravity, parent, jtype, jaxis, mass, h, ibar, np.empty((parent.shape[0], 6)))
    hmat = crba_er(e, r, parent, jtype, jaxis, mass, h, ibar)
    xdot[:n] = euler_rates(q, u)
    xdot[n : 2 * n] = cholesky_solve(hmat, tau - bias)
    return xdot
