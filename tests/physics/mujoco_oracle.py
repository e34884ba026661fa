"""Test-only oracle: the same tree built in MuJoCo from the same arrays (an independent implementation).

MuJoCo's free joint uses ``qpos = (position, quaternion)``, ``qvel = (linear velocity of the body origin
in world axes, angular velocity in body axes)`` and ``qfrc = (force in world axes, moment in body axes)``;
trikedyn uses ``(omega_body, v_body)``. ``velocity_map`` gives ``T`` with ``qvel = T u``; by power
equivalence the generalised forces map as ``tau = T^T qfrc`` and the mass matrices as ``H = T^T M T``.
"""

import numpy as np

mujoco = __import__("pytest").importorskip("mujoco")


def _fmt(v):
    return " ".join(f"{x:.17g}" for x in np.ravel(v))


def mjcf_from_tree(tree, gravity=(0.0, 0.0, -9.80665)):
    children = {i: [] for i in range(tree.n_bodies)}
    for i in range(1, tree.n_bodies):
        children[int(tree.parent[i])].append(i)

    def inertial(i):
        m = tree.mass[i]
        c = tree.h[i] / m
        ic = tree.ibar[i] - m * (c @ c * np.eye(3) - np.outer(c, c))
        full = [ic[0, 0], ic[1, 1], ic[2, 2], ic[0, 1], ic[0, 2], ic[1, 2]]
        return f'<inertial pos="{_fmt(c)}" mass="{m:.17g}" fullinertia="{_fmt(full)}"/>'

    def body(i):
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, np.ascontiguousarray(tree.tree_e[i].T).ravel())
        kind = "slide" if tree.jtype[i] == 2 else "hinge"  # revolute and rotor joints are hinges
        inner = "".join(body(c) for c in children[i])
        return (
            f'<body name="{tree.body_names[i]}" pos="{_fmt(tree.tree_r[i])}" quat="{_fmt(quat)}">'
            f'{inertial(i)}<joint type="{kind}" axis="{_fmt(tree.jaxis[i])}" damping="0" armature="0"/>{inner}</body>'
        )

    inner = "".join(body(c) for c in children[0])
    return (
        f'<mujoco><option gravity="{_fmt(gravity)}" timestep="0.001"><flag contact="disable"/></option>'
        f'<worldbody><body name="chassis"><freejoint/>{inertial(0)}{inner}</body></worldbody></mujoco>'
    )


def model_and_data(tree, gravity=(0.0, 0.0, -9.80665)):
    model = mujoco.MjModel.from_xml_string(mjcf_from_tree(tree, gravity))
    return model, mujoco.MjData(model)


def rotation(q):
    from trikedyn.model.spatial import euler_zyx_to_matrix

    return euler_zyx_to_matrix(q[3], q[4], q[5])


def velocity_map(q, n):
    """``T`` with ``qvel_mujoco = T u``."""
    t = np.eye(n)
    t[:6, :6] = 0.0
    t[:3, 3:6] = rotation(q)  # world linear velocity = R v_body
    t[3:6, :3] = np.eye(3)  # body angular velocity
    return t


def set_state(model, data, q, u):
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(rotation(q)).ravel())
    data.qpos[:3] = q[:3]
    data.qpos[3:7] = quat
    data.qpos[7:] = q[6:]
    data.qvel[:] = velocity_map(q, len(u)) @ u


def mass_matrix(model, data):
    mujoco.mj_forward(model, data)
    full = np.zeros((model.nv, model.nv))
    try:  # MuJoCo >= 3.3 takes the data; older versions the sparse qM
        mujoco.mj_fullM(model, data, full)
    except TypeError:
        mujoco.mj_fullM(model, full, data.qM)
    return full


def accelerations(model, data, q, u, qfrc):
    """Our ``du/dt`` from MuJoCo's ``qacc`` for applied ``qfrc`` (MuJoCo's coordinates)."""
    data.qfrc_applied[:] = qfrc
    mujoco.mj_forward(model, data)
    qacc = data.qacc.copy()
    out = qacc.copy()
    rmat = rotation(q)
    w, v = u[:3], u[3:6]
    # qacc_lin = d/dt (R v) = R (dv/dt + w x v); qacc_ang = dw/dt (body axes)
    out[:3] = qacc[3:6]
    out[3:6] = rmat.T @ qacc[:3] - np.cross(w, v)
    return out
