"""Energy and momentum of the model, computed independently of the equations of motion (test helper)."""

import numpy as np

from trikedyn.model.dynamics import crba
from trikedyn.model.kinematics import joint_transforms, world_transforms
from trikedyn.model.statics import state_derivative


def kinetic_energy(model, x):
    n = model.n_dof
    u = x[n : 2 * n]
    return 0.5 * u @ crba(x[:n], *model.tree.arrays()) @ u


def potential_energy(model, x):
    """Gravity, suspension springs (with preload), bump stops, tyre springs and the steering servo."""
    n = model.n_dof
    q = x[:n]
    tree = model.tree
    e, r = joint_transforms(q, tree.parent, tree.jtype, tree.jaxis, tree.tree_e, tree.tree_r)
    ew, pw = world_transforms(tree.parent, e, r)
    g = model.gravity
    energy = 0.0
    for i in range(tree.n_bodies):
        cg_world = pw[i] + ew[i].T @ (tree.h[i] / tree.mass[i])
        energy += tree.mass[i] * g * cg_world[2]
    _, wout = state_derivative(model, x)
    for k, w in enumerate(tree.wheels):
        z = q[5 + w.spring_body]
        energy += w.preload * z + 0.5 * w.stiffness * z * z
        travel = w.motion_ratio * z
        if travel > w.bump_travel:
            energy += 0.5 * w.bump_stop_stiffness * (travel - w.bump_travel) ** 2
        elif travel < -w.rebound_travel:
            energy += 0.5 * w.bump_stop_stiffness * (travel + w.rebound_travel) ** 2
        d = wout[k]["deflection"]
        if d > 0:
            energy += 0.5 * model.wheels[k]["vertical_stiffness"] * d * d
        if w.steer_body >= 0:
            delta = q[5 + w.steer_body]
            energy += 0.5 * model.wheels[k]["steer_kp"] * delta * delta
    return energy


def momenta(model, x):
    """Linear momentum and angular momentum about the world origin, in world axes."""
    n = model.n_dof
    q, u = x[:n], x[n : 2 * n]
    tree = model.tree
    e, r = joint_transforms(q, tree.parent, tree.jtype, tree.jaxis, tree.tree_e, tree.tree_r)
    ew, pw = world_transforms(tree.parent, e, r)
    from trikedyn.model.kinematics import body_velocities_into

    v = np.empty((tree.n_bodies, 6))
    body_velocities_into(e, r, u, tree.parent, tree.jtype, tree.jaxis, v)
    lin = np.zeros(3)
    ang = np.zeros(3)
    for i in range(tree.n_bodies):
        m = tree.mass[i]
        c = tree.h[i] / m
        ic = tree.ibar[i] - m * (c @ c * np.eye(3) - np.outer(c, c))
        w_body, v_body = v[i, :3], v[i, 3:]
        vc_body = v_body + np.cross(w_body, c)
        rot = ew[i].T
        vc = rot @ vc_body
        cw = pw[i] + rot @ c
        lin += m * vc
        ang += rot @ (ic @ w_body) + m * np.cross(cw, vc)
    return lin, ang
