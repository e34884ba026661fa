"""The time loop specialised to the vehicle's tree: the compiled loop bound to the generated kernels.

numba resolves a compiled function's globals when it compiles it, so the same loop source compiled in a
module whose global ``evaluate_into`` is another right-hand side is a loop over that right-hand side. For each
tree structure (:class:`~trikedyn.model.codegen.TreeStructure`) this module writes one module:

* the structure's kernels (:func:`~trikedyn.model.codegen.generate_source`);
* ``evaluate_into``: the generated ``kinematics_into``, the forces of :func:`~trikedyn.model.rhs.wrenches_into`,
  then ``du/dt`` by the generated ``forward_dynamics_factor_into`` (which keeps the ``L^T D L`` factor of the
  mass matrix in ``ws.low``; reading the kinematics kernel's transforms instead of computing them again was
  measured no faster: 0.418 against 0.408 us), then the Euler rates: the generic :func:`~trikedyn.model.rhs.evaluate_into` with
  its kinematics and dynamics replaced; and ``evaluate_stage_into``, the same on ``forward_dynamics_into``
  (no factor kept: the inner stages of a step, whose factor nobody reads; storing it cost ~0.19 us of the
  dynamics' 0.52 us, three times a step); both inlined where the loop calls them (numba passes a tuple
  argument's every array member by member, and ``p`` and ``ws`` are tuples of arrays: the loop ran 9-11 %
  faster inlined, identical to the last bit, for 1-6 s more of its ~45 s cold compile per tree structure);
* ``spin_slip_blocks`` bound to :func:`~trikedyn.simulate.exponential.spin_slip_blocks_ltdl` (the
  exponential integrator's ``(H^-1)_ss`` from that factor);
* the source of :func:`~trikedyn.simulate.integrator.etd_step` and :func:`~trikedyn.simulate.integrator.rk4_loop`
  copied verbatim, their other globals imported from their own modules.

It goes to the generated kernels' cache folder (:func:`~trikedyn.model.codegen.cache_dir`) as
``loop<hash of its text>.py``, so an edited integrator or generator is another file, and compiles with
``cache=True``: the first run of a structure in a fresh cache generates and compiles the loop, later processes
load it from numba's cache. The generated loop takes the arguments of
:func:`~trikedyn.simulate.integrator.rk4_loop` and returns what it returns.

The generic loop stays the reference: :func:`time_loop` with ``kernels="generic"``, or the environment
variable ``TRIKEDYN_KERNELS=generic``, selects it.
"""

from __future__ import annotations

import hashlib
import inspect
import os
import threading

from ..errors import InputError
from ..model.codegen import TreeStructure, generate_source, load_module
from . import integrator

__all__ = ["KERNELS", "KERNELS_ENV", "kernel_choice", "loop_module", "loop_source", "structure_loop_module", "time_loop"]

KERNELS_ENV = "TRIKEDYN_KERNELS"
"""The environment variable that selects the kernels when no argument does."""

_COPIED = (integrator.etd_step, integrator.rk4_loop)
"""The loop functions compiled again in each generated module, in this order."""

_REBOUND = {"evaluate_into", "evaluate_stage_into", "spin_slip_blocks", "etd_step", "rk4_loop"}
"""The globals the generated module defines itself (the rest are imported)."""

_GLUE = '''

# ---- the right-hand side and the loop on these kernels (trikedyn.simulate.specialised) ----------------


@jit(inline="always")
def evaluate_into(t, x, u, p, wout, ws, xdot):
    """``xdot = f(t, x, u, p)``: the generated kinematics, the forces of :func:`trikedyn.model.rhs.wrenches_into`,
    then ``du/dt`` by the generated kernel (its ``L^T D L`` factor into ``ws.low``), then ``dq/dt``."""
    q = x[:N_DOF]
    qd = x[N_DOF : 2 * N_DOF]
    kinematics_into(q, qd, p.tree_e, p.tree_r, ws.e, ws.r, ws.ew, ws.pw, ws.v)
    wrenches_into(t, x, u, p.wheels, p.tyres, p.vehicle, p.road, wout, ws.ew, ws.pw, ws.v, ws.fext, ws.tau, xdot)
    forward_dynamics_factor_into(q, qd, ws.tau, ws.fext, (0.0, 0.0, -p.vehicle[0].g), p.tree_e, p.tree_r, p.mass,
                                 p.h, p.ibar, xdot[N_DOF : 2 * N_DOF], ws.low)
    euler_rates_into(q, qd, ws.e[0], xdot[:N_DOF])


@jit(inline="always")
def evaluate_stage_into(t, x, u, p, wout, ws, xdot):
    """``evaluate_into`` without storing the factor of the mass matrix (an inner stage of a step: only the
    first stage's factor is read)."""
    q = x[:N_DOF]
    qd = x[N_DOF : 2 * N_DOF]
    kinematics_into(q, qd, p.tree_e, p.tree_r, ws.e, ws.r, ws.ew, ws.pw, ws.v)
    wrenches_into(t, x, u, p.wheels, p.tyres, p.vehicle, p.road, wout, ws.ew, ws.pw, ws.v, ws.fext, ws.tau, xdot)
    forward_dynamics_into(q, qd, ws.tau, ws.fext, (0.0, 0.0, -p.vehicle[0].g), p.tree_e, p.tree_r, p.mass, p.h,
                          p.ibar, xdot[N_DOF : 2 * N_DOF])
    euler_rates_into(q, qd, ws.e[0], xdot[:N_DOF])


spin_slip_blocks = spin_slip_blocks_ltdl
'''

_GLUE_IMPORTS = {
    "wrenches_into": "trikedyn.model.rhs",
    "euler_rates_into": "trikedyn.model.rhs",
    "spin_slip_blocks_ltdl": "trikedyn.simulate.exponential",
}

_LOCK = threading.Lock()
_BY_STRUCTURE: dict = {}


def _imports(defined: set) -> list[str]:
    """``from module import name`` lines for the globals of the glue and of the copied functions."""
    wanted: dict[str, set] = {}
    for name, module in _GLUE_IMPORTS.items():
        wanted.setdefault(module, set()).add(name)
    for func in _COPIED:
        py = func.py_func
        for name in py.__code__.co_names:
            if name in py.__globals__ and name not in _REBOUND and name != "np":
                if name in defined:
                    raise RuntimeError(f"the generated kernels define {name!r}, a global of {py.__name__}")
                wanted.setdefault(py.__module__, set()).add(name)
    return [f"from {module} import {', '.join(sorted(names))}  # noqa: F401" for module, names in sorted(wanted.items())]


def loop_source(structure: TreeStructure) -> str:
    """The source of the loop module of ``structure`` (see the module docstring).

    Parameters
    ----------
    structure : TreeStructure
        The tree's structure.

    Returns
    -------
    str
        The module's text: the kernels, the imports, the right-hand side and the copied loop.
    """
    kernels = generate_source(structure)
    defined = {line.split("(")[0][4:] for line in kernels.splitlines() if line.startswith("def ")}
    defined |= {"N_DOF", "jit"}
    parts = [kernels, "\n", "\n".join(_imports(defined)), _GLUE]
    for func in _COPIED:
        parts.append("\n\n" + inspect.getsource(func.py_func))
    return "".join(parts)


def loop_module(plant):
    """The generated loop module of ``plant``'s tree structure: generated, written and imported at first use.

    Parameters
    ----------
    plant : Plant
        The compiled vehicle (``VehicleModel.plant``), or anything with the tree's arrays.

    Returns
    -------
    module
        Its ``rk4_loop`` is :func:`trikedyn.simulate.integrator.rk4_loop` on the generated kernels.
    """
    return structure_loop_module(TreeStructure.of(plant.parent, plant.jtype, plant.jaxis, plant.tree_e, plant.tree_r,
                                                  plant.h, plant.ibar))


def structure_loop_module(structure: TreeStructure):
    """:func:`loop_module` of a tree structure.

    Parameters
    ----------
    structure : TreeStructure
        The tree's structure.

    Returns
    -------
    module
        The loop module (see :func:`loop_source`).
    """
    with _LOCK:
        module = _BY_STRUCTURE.get(structure)
    if module is None:
        source = loop_source(structure)
        module = load_module("loop" + hashlib.sha256(source.encode()).hexdigest()[:24], lambda: source)
        with _LOCK:
            _BY_STRUCTURE[structure] = module
    return module


KERNELS = {
    "generated": lambda plant: loop_module(plant).rk4_loop,
    "generic": lambda plant: integrator.rk4_loop,
}
"""The time loops by kernel: the loop on the kernels generated for the tree (the default), or the generic
loop (the reference)."""


def kernel_choice(kernels: str | None = None) -> str:
    """The kernels to run on: ``kernels`` if given, else ``$TRIKEDYN_KERNELS``, else ``"generated"``.

    Parameters
    ----------
    kernels : str, optional
        A key of :data:`KERNELS`.

    Returns
    -------
    str
        A key of :data:`KERNELS`.

    Raises
    ------
    InputError
        For a name that is not one.
    """
    where = "kernels"
    if kernels is None:
        kernels, where = os.environ.get(KERNELS_ENV) or "generated", KERNELS_ENV
    if kernels not in KERNELS:
        raise InputError(f"unknown kernels {kernels!r}: expected one of {', '.join(sorted(KERNELS))}", where=where)
    return kernels


def time_loop(plant, kernels: str | None = None):
    """The compiled time loop for ``plant``: :func:`~trikedyn.simulate.integrator.rk4_loop`'s arguments and
    returns, on the kernels :func:`kernel_choice` selects.

    Parameters
    ----------
    plant : Plant
        The compiled vehicle.
    kernels : str, optional
        ``"generated"`` or ``"generic"``; ``$TRIKEDYN_KERNELS`` or ``"generated"`` when None.

    Returns
    -------
    callable
        The loop.
    """
    return KERNELS[kernel_choice(kernels)](plant)
