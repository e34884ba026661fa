"""Kernels generated for the tree (trikedyn.model.codegen) against the generic ones they specialise.

The generic RNEA, CRBA and Cholesky solve of trikedyn.model.dynamics are the reference: on random states
(coordinates, velocities, applied forces, external wrenches) of both reference trikes the generated kernels
give the same accelerations, bias forces and mass matrices to 1e-12 (relative, max norm). The generated
module is cached on disk and a fresh process loads it, and numba's compiled code, without regenerating.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from trikedyn.model import dynamics
from trikedyn.model.codegen import TreeStructure, generate_source, kernels_for_tree
from trikedyn.model.topology import build_tree
from trikedyn.params import load_vehicle, with_freight

PRESETS = ["reference-etrike", "reference-tadpole"]
GRAVITY = np.array([0.0, 0.0, -9.81])


def random_state(tree, rng):
    """A random (q, u, udot, tau, fext) of ``tree``: angles within +-0.6 rad, sliders within +-5 cm."""
    n, nb = tree.n_dof, tree.n_bodies
    q = np.empty(n)
    q[:3] = rng.normal(0.0, 5.0, 3)
    q[3:6] = rng.uniform(-0.6, 0.6, 3)
    for b in range(1, nb):
        q[5 + b] = rng.uniform(-0.05, 0.05) if tree.jtype[b] == dynamics.JOINT_PRISMATIC else rng.uniform(-3, 3)
    u = rng.normal(0.0, 2.0, n)
    u[3:6] *= 5.0
    for w in tree.wheels:  # wheels spin fast
        u[5 + w.wheel_body] = rng.normal(0.0, 30.0)
    udot = rng.normal(0.0, 3.0, n)
    tau = rng.normal(0.0, 200.0, n)
    fext = rng.normal(0.0, 500.0, (nb, 6))
    return q, u, udot, tau, fext


def rel_err(a, b):
    """Max-norm error of ``a`` relative to the max norm of ``b``."""
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def values(tree):
    """The run-time arguments of the generated kernels."""
    return tree.tree_e, tree.tree_r, tree.mass, tree.h, tree.ibar


@pytest.fixture(scope="module", params=PRESETS)
def tree_and_kernels(request):
    tree = build_tree(load_vehicle(request.param).params)
    return tree, kernels_for_tree(tree)


def test_forward_dynamics_equals_generic(tree_and_kernels):
    tree, k = tree_and_kernels
    rng = np.random.default_rng(25)
    worst = 0.0
    for _ in range(60):
        q, u, _, tau, fext = random_state(tree, rng)
        ref = dynamics.forward_dynamics(q, u, tau, fext, GRAVITY, *tree.arrays())
        got = k.forward_dynamics_generated(q, u, tau, fext, GRAVITY, *values(tree))
        assert np.all(np.isfinite(ref))
        worst = max(worst, rel_err(got, ref))
    assert worst < 1e-12


def test_kinematics_equal_generic(tree_and_kernels):
    """The generated kinematics kernel writes the generic joint transforms, world poses and body velocities
    (the arrays the tyres read) to 1e-12 of each array's largest entry, every entry of every body."""
    from trikedyn.model.kinematics import body_velocities_into, world_transforms_into

    tree, k = tree_and_kernels
    parent, jtype, jaxis, tree_e, tree_r = tree.arrays()[:5]
    nb = tree.n_bodies
    rng = np.random.default_rng(7)
    worst = {}
    for _ in range(60):
        q, u, _, _, _ = random_state(tree, rng)
        ref = {"e": np.empty((nb, 3, 3)), "r": np.empty((nb, 3)), "ew": np.empty((nb, 3, 3)), "pw": np.empty((nb, 3)),
               "v": np.empty((nb, 6))}
        dynamics.joint_transforms_into(q, parent, jtype, jaxis, tree_e, tree_r, ref["e"], ref["r"], np.empty((3, 3)))
        world_transforms_into(parent, ref["e"], ref["r"], ref["ew"], ref["pw"])
        body_velocities_into(ref["e"], ref["r"], u, parent, jtype, jaxis, ref["v"])
        got = {name: np.full_like(a, np.nan) for name, a in ref.items()}
        k.kinematics_into(q, u, tree_e, tree_r, got["e"], got["r"], got["ew"], got["pw"], got["v"])
        for name, a in ref.items():
            assert np.all(np.isfinite(got[name])), name  # every entry written
            worst[name] = max(worst.get(name, 0.0), rel_err(got[name], a))
    assert max(worst.values()) < 1e-12, worst


def test_forward_dynamics_into_writes_out(tree_and_kernels):
    tree, k = tree_and_kernels
    q, u, _, tau, fext = random_state(tree, np.random.default_rng(1))
    out = np.full(tree.n_dof, 7.0)
    k.forward_dynamics_into(q, u, tau, fext, (0.0, 0.0, -9.81), *values(tree), out)
    ref = dynamics.forward_dynamics(q, u, tau, fext, GRAVITY, *tree.arrays())
    assert rel_err(out, ref) < 1e-12


def test_rnea_and_mass_matrix_equal_generic(tree_and_kernels):
    tree, k = tree_and_kernels
    rng = np.random.default_rng(3)
    for _ in range(50):
        q, u, udot, _, fext = random_state(tree, rng)
        ref_tau = dynamics.rnea(q, u, udot, fext, GRAVITY, *tree.arrays())
        assert rel_err(k.rnea(q, u, udot, fext, GRAVITY, *values(tree)), ref_tau) < 1e-12
        ref_h = dynamics.crba(q, *tree.arrays())
        got_h = k.mass_matrix(q, *values(tree))
        assert rel_err(got_h, ref_h) < 1e-12
        assert np.array_equal(got_h, got_h.T)


def test_not_positive_definite_gives_nan(tree_and_kernels):
    tree, k = tree_and_kernels
    q, u, _, tau, fext = random_state(tree, np.random.default_rng(5))
    mass = tree.mass.copy()
    mass[tree.wheels[0].wheel_body] = -500.0  # a negative mass: H is not positive definite
    args = (tree.tree_e, tree.tree_r, mass, tree.h, tree.ibar)
    assert np.all(np.isnan(dynamics.forward_dynamics(q, u, tau, fext, GRAVITY, tree.parent, tree.jtype,
                                                     tree.jaxis, *args)))
    assert np.all(np.isnan(k.forward_dynamics_generated(q, u, tau, fext, GRAVITY, *args)))


def test_one_kernel_serves_every_vehicle_of_the_structure():
    base = build_tree(load_vehicle("reference-etrike").params)
    laden = build_tree(with_freight(load_vehicle("reference-etrike"), 120.0).params)
    tadpole = build_tree(load_vehicle("reference-tadpole").params)

    def structure(t):
        return TreeStructure.of(t.parent, t.jtype, t.jaxis, t.tree_e, t.tree_r, t.h, t.ibar)

    assert structure(laden).key() == structure(base).key()
    assert structure(tadpole).key() != structure(base).key()
    assert not np.allclose(laden.mass, base.mass)
    k = kernels_for_tree(base)
    assert kernels_for_tree(laden) is k
    q, u, _, tau, fext = random_state(laden, np.random.default_rng(7))
    ref = dynamics.forward_dynamics(q, u, tau, fext, GRAVITY, *laden.arrays())
    assert rel_err(k.forward_dynamics_generated(q, u, tau, fext, GRAVITY, *values(laden)), ref) < 1e-12
    unladen = dynamics.forward_dynamics(q, u, tau, fext, GRAVITY, *base.arrays())
    assert rel_err(unladen, ref) > 1e-6  # the values, not the kernel, carry the freight


def test_structure_is_folded_into_straight_line_code():
    tree = build_tree(load_vehicle("reference-etrike").params)
    src = generate_source(TreeStructure.of(tree.parent, tree.jtype, tree.jaxis, tree.tree_e, tree.tree_r, tree.h,
                                           tree.ibar))
    body = src[src.index("def forward_dynamics_into"):src.index("def rnea(")]
    assert "for " not in body and "while " not in body  # unrolled, no loop over bodies or a dense factor
    wheel = tree.wheels[0].wheel_body
    assert tree.jtype[wheel] == dynamics.JOINT_ROTOR
    assert f"tree_e[{wheel}," not in body  # a rotor's identity frame folds out
    assert f"h[{wheel}," not in body  # a wheel's centred mass has no first moment
    assert f"tree_e[{tree.wheels[0].steer_body}," in body  # the raked steering head's rotation is a value
    compile(src, "generated", "exec")


_PROBE = textwrap.dedent("""
    import json, os
    import numpy as np
    from trikedyn.model.codegen import kernels_for_tree
    from trikedyn.model.topology import build_tree
    from trikedyn.params import load_vehicle
    tree = build_tree(load_vehicle("reference-etrike").params)
    k = kernels_for_tree(tree)
    n, nb = tree.n_dof, tree.n_bodies
    out = k.forward_dynamics_generated(np.full(n, 0.1), np.full(n, 0.2), np.full(n, 3.0), np.ones((nb, 6)),
                                       np.array([0.0, 0.0, -9.81]), tree.tree_e, tree.tree_r, tree.mass, tree.h,
                                       tree.ibar)
    stats = k.forward_dynamics_generated.stats
    print(json.dumps({"generated": k.GENERATED_NOW, "file": k.__file__, "mtime": os.stat(k.__file__).st_mtime_ns,
                      "hits": sum(stats.cache_hits.values()), "misses": sum(stats.cache_misses.values()),
                      "out": out.tolist()}))
""")


def test_cache_is_reused_by_a_fresh_process(tmp_path):
    env = {**os.environ, "TRIKEDYN_CACHE_DIR": str(tmp_path), "NUMBA_CACHE_DIR": str(tmp_path / "numba")}

    def probe():
        done = subprocess.run([sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stderr
        return json.loads(done.stdout.strip().splitlines()[-1])

    first, second = probe(), probe()
    assert first["generated"] and first["misses"] >= 1 and first["hits"] == 0
    assert first["file"].startswith(str(tmp_path))
    assert not second["generated"]
    assert second["file"] == first["file"] and second["mtime"] == first["mtime"]
    assert second["hits"] >= 1 and second["misses"] == 0  # numba loaded the compiled kernel
    # the same kernel, bit for bit (IEEE arithmetic, no fast-math: the compiled code does not depend on where it
    # was compiled or whether it came from the cache)
    assert np.array_equal(second["out"], first["out"]) and np.all(np.isfinite(first["out"]))
    assert [p.name for p in tmp_path.glob("generated/*.tmp")] == []
    assert any((tmp_path / "numba").rglob("*.nbi"))  # numba's index of the compiled kernel, where we said


def test_two_processes_racing_to_generate_agree(tmp_path):
    env = {**os.environ, "TRIKEDYN_CACHE_DIR": str(tmp_path), "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    procs = [subprocess.Popen([sys.executable, "-c", _PROBE], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True) for _ in range(2)]
    outs = []
    for proc in procs:
        stdout, stderr = proc.communicate(timeout=300)
        assert proc.returncode == 0, stderr
        outs.append(json.loads(stdout.strip().splitlines()[-1]))
    assert outs[0]["file"] == outs[1]["file"]
    assert outs[0]["generated"] or outs[1]["generated"]
    assert np.allclose(outs[0]["out"], outs[1]["out"], rtol=1e-12, atol=0.0)
    files = sorted(p.name for p in (tmp_path / "generated").iterdir())
    assert files == [os.path.basename(outs[0]["file"])]  # one module, no temporary left behind
    with open(outs[0]["file"]) as fh:
        compile(fh.read(), "generated", "exec")  # whole, not torn


def test_cache_dir_follows_the_environment(tmp_path, monkeypatch):
    from trikedyn.model.codegen import cache_dir

    monkeypatch.setenv("TRIKEDYN_CACHE_DIR", str(tmp_path / "mine"))
    assert cache_dir() == tmp_path / "mine" / "generated" and cache_dir().is_dir()
    monkeypatch.delenv("TRIKEDYN_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_dir() == tmp_path / "xdg" / "trikedyn" / "generated"


def random_tree(rng, nb=7):
    """A made-up tree: random parents, joint types (revolute, prismatic, rotor), oblique axes and fixed
    rotations, physical inertias; the general paths of the generator that the presets' aligned axes skip."""
    from scipy.spatial.transform import Rotation

    parent = np.array([-1] + [int(rng.integers(0, b)) for b in range(1, nb)], dtype=np.int64)
    kinds = [dynamics.JOINT_REVOLUTE, dynamics.JOINT_PRISMATIC, dynamics.JOINT_ROTOR]
    jtype = np.array([0] + [kinds[b % 3] for b in range(1, nb)], dtype=np.int64)
    jaxis = rng.normal(size=(nb, 3))
    jaxis /= np.linalg.norm(jaxis, axis=1)[:, None]
    tree_e = Rotation.random(nb, random_state=int(rng.integers(1 << 31))).as_matrix()
    tree_r = rng.normal(0.0, 0.4, (nb, 3))
    mass = rng.uniform(1.0, 50.0, nb)
    cg = rng.normal(0.0, 0.2, (nb, 3))
    ibar = np.empty((nb, 3, 3))
    for b in range(nb):
        a = rng.normal(0.0, 0.3, (3, 3))
        ibar[b] = a @ a.T + 0.05 * np.eye(3) + mass[b] * (cg[b] @ cg[b] * np.eye(3) - np.outer(cg[b], cg[b]))
    return parent, jtype, jaxis, tree_e, tree_r, mass, mass[:, None] * cg, ibar


@pytest.mark.slow
def test_a_made_up_tree_with_oblique_axes_equals_generic():
    from trikedyn.model.codegen import kernels

    rng = np.random.default_rng(2025)
    parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar = random_tree(rng)
    assert set(jtype[1:].tolist()) == {dynamics.JOINT_REVOLUTE, dynamics.JOINT_PRISMATIC, dynamics.JOINT_ROTOR}
    assert len(set(parent[1:].tolist())) > 1  # branches, not a chain
    k = kernels(TreeStructure.of(parent, jtype, jaxis, tree_e, tree_r, h, ibar))
    n, nb = len(parent) + 5, len(parent)
    for _ in range(50):
        q = rng.uniform(-1.0, 1.0, n)
        u, udot, tau = rng.normal(size=n), rng.normal(size=n), rng.normal(0.0, 50.0, n)
        fext = rng.normal(0.0, 50.0, (nb, 6))
        generic = (parent, jtype, jaxis, tree_e, tree_r, mass, h, ibar)
        vals = (tree_e, tree_r, mass, h, ibar)
        ref = dynamics.forward_dynamics(q, u, tau, fext, GRAVITY, *generic)
        assert rel_err(k.forward_dynamics_generated(q, u, tau, fext, GRAVITY, *vals), ref) < 1e-12
        assert rel_err(k.rnea(q, u, udot, fext, GRAVITY, *vals), dynamics.rnea(q, u, udot, fext, GRAVITY, *generic)) < 1e-12
        assert rel_err(k.mass_matrix(q, *vals), dynamics.crba(q, *generic)) < 1e-12
