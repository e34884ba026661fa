"""trikedyn.model.lanes: kernels generated over a batch's lanes against the scalar generated kernels.

Each lane of a batch gets its own random state (and, in some lanes, the vehicle laden with freight: other
masses and inertias) of both reference trikes; every lane's forward dynamics and kinematics equal the scalar
generated kernels' to 1e-12 (relative, max norm). How much faster they are is ``benchmarks/lanes.py``'s.
"""

from __future__ import annotations

import importlib
from pathlib import Path

import numpy as np
import pytest

from trikedyn.model.codegen import TreeStructure, kernels_for_tree
from trikedyn.model.lanes import LANE_ARRAYS, LaneLayout, lane_kernels, lane_source
from trikedyn.model.topology import build_tree
from trikedyn.params import load_vehicle, with_freight

from .test_codegen import GRAVITY, PRESETS, random_state, rel_err

LANES = 8


def structure_of(tree) -> TreeStructure:
    return TreeStructure.of(tree.parent, tree.jtype, tree.jaxis, tree.tree_e, tree.tree_r, tree.h, tree.ibar)


@pytest.fixture(scope="module", params=PRESETS)
def batch(request):
    """A filled buffer of ``LANES`` lanes after both lane kernels, with each lane's tree and state."""
    pset = load_vehicle(request.param)
    trees = [build_tree(pset.params), build_tree(with_freight(pset, 150.0).params)]
    assert structure_of(trees[0]) == structure_of(trees[1])  # freight changes values, not the structure
    layout = LaneLayout(trees[0].n_bodies, LANES)
    module = lane_kernels(structure_of(trees[0]), LANES)
    buf = layout.buffer()
    rng = np.random.default_rng(7)
    lanes = []
    for lane in range(LANES):
        tree = trees[lane % 2]
        q, u, _, tau, fext = random_state(tree, rng)
        for name, value in (("q", q), ("u", u), ("tau", tau), ("fext", fext), ("gravity", GRAVITY),
                            ("tree_e", tree.tree_e), ("tree_r", tree.tree_r), ("mass", tree.mass), ("h", tree.h),
                            ("ibar", tree.ibar)):
            layout.view(buf, name)[..., lane] = value
        lanes.append((tree, q, u, tau, fext))
    module.forward_dynamics_lanes(buf)
    module.kinematics_lanes(buf)
    return layout, buf, lanes, kernels_for_tree(trees[0])


def test_every_lanes_forward_dynamics_equals_the_scalar_kernel(batch):
    layout, buf, lanes, scalar = batch
    for lane, (tree, q, u, tau, fext) in enumerate(lanes):
        ref = np.empty(tree.n_dof)
        scalar.forward_dynamics_into(q, u, tau, fext, tuple(GRAVITY), tree.tree_e, tree.tree_r, tree.mass, tree.h,
                                     tree.ibar, ref)
        assert rel_err(layout.view(buf, "udot")[:, lane], ref) < 1e-12
        np.testing.assert_array_equal(layout.view(buf, "udot")[:, lane], ref)  # the same arithmetic: equal


def test_every_lanes_kinematics_equal_the_scalar_kernel(batch):
    layout, buf, lanes, scalar = batch
    nb = lanes[0][0].n_bodies
    for lane, (tree, q, u, _, _) in enumerate(lanes):
        ref = {"e": np.empty((nb, 3, 3)), "r": np.empty((nb, 3)), "ew": np.empty((nb, 3, 3)), "pw": np.empty((nb, 3)),
               "v": np.empty((nb, 6))}
        scalar.kinematics_into(q, u, tree.tree_e, tree.tree_r, *ref.values())
        for name, value in ref.items():
            assert rel_err(layout.view(buf, name)[..., lane], value) < 1e-12, name


def test_every_lanes_factor_of_the_mass_matrix_equals_the_scalar_kernels(batch):
    """``forward_dynamics_factor_lanes`` keeps ``L^T D L`` as ``forward_dynamics_factor_into`` does (the entries
    it writes, to 1e-12 of the largest), and gives the same ``udot`` as ``forward_dynamics_lanes``."""
    layout, buf, lanes, scalar = batch
    module = lane_kernels(structure_of(lanes[0][0]), LANES)
    with_factor = buf.copy()
    layout.view(with_factor, "low")[...] = np.nan  # the entries it leaves alone stay NaN
    module.forward_dynamics_factor_lanes(with_factor)
    assert np.array_equal(layout.view(with_factor, "udot"), layout.view(buf, "udot"))
    for lane, (tree, q, u, tau, fext) in enumerate(lanes):
        n = tree.n_dof
        out, factor = np.empty(n), np.full((n, n), np.nan)
        scalar.forward_dynamics_factor_into(q, u, tau, fext, tuple(GRAVITY), tree.tree_e, tree.tree_r, tree.mass,
                                            tree.h, tree.ibar, out, factor)
        got = layout.view(with_factor, "low")[..., lane]
        written = ~np.isnan(factor)
        assert np.array_equal(~np.isnan(got), written)
        assert np.max(np.abs(got[written] - factor[written])) < 1e-12 * np.max(np.abs(factor[written]))


def test_a_lane_whose_mass_matrix_is_not_positive_definite_alone_gives_nan(batch):
    layout, buf, lanes, _ = batch
    tree = lanes[0][0]
    module = lane_kernels(structure_of(tree), LANES)
    bad = buf.copy()
    layout.view(bad, "mass")[:, 3] = -1.0
    module.forward_dynamics_lanes(bad)
    udot = layout.view(bad, "udot")
    assert np.isnan(udot[:, 3]).all()
    others = [lane for lane in range(LANES) if lane != 3]
    assert np.array_equal(udot[:, others], layout.view(buf, "udot")[:, others])


def test_the_layout_tiles_the_buffer_with_views():
    layout = LaneLayout(8, 4)
    buf = layout.buffer()
    rows = sorted((layout.start(name), layout.start(name) + int(np.prod(layout.shape(name))))
                  for name, _ in LANE_ARRAYS)
    assert rows[0][0] == 0 and rows[-1][1] == layout.rows and buf.size == layout.rows * 4
    assert all(a[1] == b[0] for a, b in zip(rows, rows[1:], strict=False))  # no gap, no overlap
    layout.view(buf, "ibar")[2, 1, 0, 3] = 5.0
    assert buf[layout.row("ibar", (2, 1, 0)) * 4 + 3] == 5.0
    assert layout.view(buf, "q").shape == (13, 4) and layout.view(buf, "fext").shape == (8, 6, 4)


def test_the_lane_loop_calls_no_library_function_and_has_no_branch():
    """What lets LLVM vectorise the loop: no call to libm's sine or cosine, no ``if`` statement in the body."""
    tree = build_tree(load_vehicle("reference-etrike").params)
    src = lane_source(structure_of(tree), LANES)
    body = src[src.index("def kinematics_lanes"):]
    assert "sincos(" in body
    assert "np.sin(" not in body and "np.cos(" not in body and "math." not in body
    assert not any(line.lstrip().startswith(("if ", "elif ", "else")) for line in body.splitlines())
    assert f"for l in range({LANES}):" in body  # the lane count a constant of the code


def test_lane_counts_below_one_are_refused():
    tree = build_tree(load_vehicle("reference-etrike").params)
    with pytest.raises(ValueError, match="lanes"):
        lane_kernels(structure_of(tree), 0)


def test_the_lane_benchmark_checks_lanes_against_the_scalar_kernels(monkeypatch):
    """``benchmarks/lanes.py`` runs (one pass, B = 8) and its sums agree, as ``make bench`` asserts (here, in the
    process that compiled these lane kernels, rather than in ``tests/test_benchmarks.py``'s)."""
    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parents[2] / "benchmarks"))
    lanes = importlib.import_module("lanes")
    out = lanes.measure("reference-etrike", reps=1, lanes=(LANES,))
    figures = out["lanes"][LANES]
    assert figures["dynamics_rel_diff"] < 1e-9 and figures["kinematics_rel_diff"] < 1e-9
    assert figures["dynamics_us"] > 0.0 and figures["factor_us"] > 0.0 and out["scalar_factor_us"] > 0.0
