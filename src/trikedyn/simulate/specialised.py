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
  dynamics' 0.52 us, three times a step). The loop's first stage inlines ``evaluate_into`` (numba passes a
  tuple argument's every array member by member, and ``p`` and ``ws`` are tuples of arrays: calling it cost
  the loop 9-11 %);
* ``etd_step``: the source of :func:`~trikedyn.simulate.integrator.etd_step` with four edits
  (:func:`_step_source`; the step's arithmetic stays the integrator's text): compiled on its own (one call a
  step), the plant's and the workspace's arrays taken out of their tuples once (:data:`_HOIST`), the spin-slip
  blocks (:data:`_BLOCKS`) and the three inner right-hand sides (:func:`_stage`) written out in place, not
  inlined. numba counts references to arrays: an inlined function binds each array argument, every member of
  a tuple argument included, to a new variable and so increments and later decrements its count (two atomic
  instructions), and LLVM's reference-count pruning removes few of these pairs in a function as branchy as a
  step. With ``evaluate_stage_into`` inlined three times a step, ``NRT_incref``/``NRT_decref`` were 13 % of a
  profile of the loop (``perf``, the 10 s lane change); written out, 6 %, and the loop 6.14-6.20 ms against
  6.59-6.69 (best of 25, alternated, identical to the last bit). The arrays taken out of the tuples and the
  slices of the state are views that count no references (:func:`~trikedyn._borrow.borrowed`; so are the
  views :func:`~trikedyn.model.rhs.wrenches_into` takes): 2.4 % of the profile left;
* ``spin_slip_blocks`` bound to :func:`~trikedyn.simulate.exponential.spin_slip_blocks_ltdl` (the
  exponential integrator's ``(H^-1)_ss`` from that factor; the batch's generated module imports it);
* the source of :func:`~trikedyn.simulate.integrator.rk4_loop` copied verbatim, its other globals imported from
  their own modules.

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
import re
import threading

from ..errors import InputError
from ..model.codegen import TreeStructure, generate_source, load_module
from . import integrator

__all__ = ["KERNELS", "KERNELS_ENV", "kernel_choice", "loop_module", "loop_source", "model_time_loop",
           "structure_loop_module", "time_loop"]

KERNELS_ENV = "TRIKEDYN_KERNELS"
"""The environment variable that selects the kernels when no argument does."""

_COPIED = (integrator.rk4_loop,)
"""The loop functions compiled again in each generated module."""

_REBOUND = {"evaluate_into", "evaluate_stage_into", "spin_slip_blocks", "etd_step", "rk4_loop"}
"""The globals the generated module defines itself (the rest are imported)."""

_HOIST = """\
    tree_e, tree_r, mass, hh, ibar = borrowed(p.tree_e), borrowed(p.tree_r), borrowed(p.mass), borrowed(p.h), borrowed(p.ibar)
    wheels, tyres, vehicle, road, parent = borrowed(p.wheels), borrowed(p.tyres), borrowed(p.vehicle), borrowed(p.road), borrowed(p.parent)
    e, r, ew, pw, v = borrowed(ws.e), borrowed(ws.r), borrowed(ws.ew), borrowed(ws.pw), borrowed(ws.v)
    fext, tau, low = borrowed(ws.fext), borrowed(ws.tau), borrowed(ws.low)
    gravity = (0.0, 0.0, -vehicle[0].g)
"""
"""The plant's and the workspace's arrays a right-hand side reads, taken out of their tuples once."""


def _stage(t: str, x: str, out: str, factor: bool) -> str:
    """The text of one right-hand side ``out = f(t, x)`` on the generated kernels, written out in place: the
    kinematics, :func:`~trikedyn.model.rhs.wrenches_into`, the forward dynamics (keeping the ``L^T D L`` factor
    in ``low`` with ``factor``), the Euler rates."""
    q, qd = f"borrowed({x}[:N_DOF])", f"borrowed({x}[N_DOF : 2 * N_DOF])"
    dynamics = (f"forward_dynamics_factor_into({q}, {qd}, tau, fext, gravity, tree_e, tree_r, mass, hh, ibar, "
                f"borrowed({out}[N_DOF : 2 * N_DOF]), low)" if factor else
                f"forward_dynamics_into({q}, {qd}, tau, fext, gravity, tree_e, tree_r, mass, hh, ibar, "
                f"borrowed({out}[N_DOF : 2 * N_DOF]))")
    return (f"    kinematics_into({q}, {qd}, tree_e, tree_r, e, r, ew, pw, v)\n"
            f"    wrenches_into({t}, {x}, u, wheels, tyres, vehicle, road, wout, ew, pw, v, fext, tau, {out})\n"
            f"    {dynamics}\n"
            f"    euler_rates_into({q}, {qd}, borrowed(e[0]), borrowed({out}[:N_DOF]))\n")


_GLUE = f'''

# ---- the right-hand side and the step on these kernels (trikedyn.simulate.specialised) ----------------


@jit(inline="always")
def evaluate_into(t, x, u, p, wout, ws, xdot):
    """``xdot = f(t, x, u, p)``: the generated kinematics, the forces of :func:`trikedyn.model.rhs.wrenches_into`,
    then ``du/dt`` by the generated kernel (its ``L^T D L`` factor into ``ws.low``), then ``dq/dt``."""
{_HOIST}{_stage("t", "x", "xdot", True)}

@jit(inline="always")
def evaluate_stage_into(t, x, u, p, wout, ws, xdot):
    """``evaluate_into`` without storing the factor of the mass matrix (an inner stage of a step: only the
    first stage's factor is read)."""
{_HOIST}{_stage("t", "x", "xdot", False)}

spin_slip_blocks = spin_slip_blocks_ltdl
'''

_BLOCKS = """\
    m = 0
    if exponential:
        for k in range(wheels.shape[0]):
            spin_slip_block(wheels, tyres, vehicle, parent.shape[0] + 5, k, wout[k],
                            ltdl_inverse_diagonal(low, parent, 5 + wheels[k].wheel_body, scratch), idx, mat)
        m = wheels.shape[0]
"""
"""``spin_slip_blocks`` written out on the arrays taken out of the plant (its tuple argument, inlined, would count a
reference to each of the plant's arrays every step)."""

_STAGE_CALL = re.compile(r"^    evaluate_stage_into\((?P<t>[^,]+), xs, u, p, wout, ws, (?P<k>k[234])\)\n", re.M)


def _step_source() -> str:
    """:func:`~trikedyn.simulate.integrator.etd_step`'s source made this module's ``etd_step`` (see the module
    docstring): compiled on its own instead of inlined, the arrays taken out of the tuples first
    (:data:`_HOIST`), the spin-slip blocks (:data:`_BLOCKS`) and the three inner right-hand sides (:func:`_stage`)
    written out in place; the rest, the step's arithmetic, is the integrator's own text.

    Raises
    ------
    RuntimeError
        When the integrator's step no longer has the lines this replaces.
    """
    source = inspect.getsource(integrator.etd_step.py_func)
    start = source.index('"""')
    end = source.index('"""', start + 3) + 4  # decorator, signature and docstring, then the code
    header, code = source[:end], source[end:]
    blocks = "    m = spin_slip_blocks(p, wout, ws.low, scratch, idx, mat) if exponential else 0\n"
    inlined = '@jit(inline="always")\n'
    if not header.startswith(inlined) or code.count(blocks) != 1 or len(_STAGE_CALL.findall(code)) != 3:
        raise RuntimeError("trikedyn.simulate.integrator.etd_step changed: update specialised._step_source")
    code = _STAGE_CALL.sub(lambda m: _stage(m["t"], "xs", m["k"], False), code.replace(blocks, _BLOCKS))
    return "\n\n" + header.replace(inlined, "@jit\n", 1) + _HOIST + code


_GLUE_IMPORTS = {
    "borrowed": "trikedyn._borrow",
    "wrenches_into": "trikedyn.model.rhs",
    "euler_rates_into": "trikedyn.model.rhs",
    "ltdl_inverse_diagonal": "trikedyn.model.inverse_mass",
    "spin_slip_blocks_ltdl": "trikedyn.simulate.exponential",
    "spin_slip_block": "trikedyn.simulate.exponential",
}

_LOCK = threading.Lock()
_BY_STRUCTURE: dict = {}


def _imports(defined: set) -> list[str]:
    """``from module import name`` lines for the globals of the glue and of the copied functions."""
    wanted: dict[str, set] = {}
    for name, module in _GLUE_IMPORTS.items():
        wanted.setdefault(module, set()).add(name)
    for func in (integrator.etd_step, *_COPIED):
        py = func.py_func
        for name in py.__code__.co_names:
            if name in py.__globals__ and name not in _REBOUND and name not in _GLUE_IMPORTS and name != "np":
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
    parts = [kernels, "\n", "\n".join(_imports(defined)), _GLUE, _step_source()]
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


def model_time_loop(model, kernels: str | None = None):
    """:func:`time_loop` of a model's plant, kept in ``model.cache`` (the loop depends on the tree's structure
    only, which a model and the variants sharing its cache keep; looking it up costs ~30 us a run).

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    kernels : str, optional
        As for :func:`time_loop`.

    Returns
    -------
    callable
        The loop.
    """
    key = ("time_loop", kernel_choice(kernels))
    if key not in model.cache:
        model.cache[key] = time_loop(model.plant, key[1])
    return model.cache[key]
