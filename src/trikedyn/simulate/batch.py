"""Lockstep batches: several runs of one compiled model structure advanced together, step by step.

A batch is B *lanes*, each running one *job* (a prepared run:
:func:`~trikedyn.simulate.closed_loop.prepare_run`, or an open-loop table): a speed, a parameter variant of
the same topology and tyre model, a manoeuvre of its own. One compiled call
(:func:`~trikedyn.simulate.lockstep.batch_loop`) advances every busy lane by one step in turn, with the very
step functions of the scalar loop (:func:`~trikedyn.simulate.integrator.etd_step`, the driver's
:func:`~trikedyn.driver.preview.driver_step` with its own memory and path search per lane, the same health
watch), so that each job's record equals :func:`~trikedyn.simulate.integrator.rk4_loop`'s. A lane whose job
ends (its last step, NaN, runaway penetration, rollover) is frozen and, with ``refill``, takes the next
job waiting; the batch ends when every job is done.

Layout: what a lane carries (its state, step count, stage vectors, wheel outputs, exponential blocks,
right-hand-side workspace) is held per lane, structure of arrays, the lane index first so that each lane's
vectors are contiguous rows for the scalar kernels; all of it is set afresh for each job as the scalar loop
sets it (the step reads some of it back: the last wheel outputs, the blocks). The parameter vectors
of the lanes' plants are stacked along a first axis and a lane's :class:`~trikedyn.model.packing.Plant` is
a view of one slice. The loop runs on the kernels the scalar loop runs on
(:mod:`trikedyn.simulate.specialised`: generated for the tree by default, compiled again with them,
:func:`batch_source`), so a lane's record equals the scalar run's. On the generated kernels it goes through
each step stage by stage across the lanes, the kinematics and forward dynamics of all lanes in one call of the
lane kernels (:mod:`trikedyn.simulate.lane_batch`, :mod:`trikedyn.model.lanes`); on the generic ones each lane
goes through the scalar step in turn (:func:`~trikedyn.simulate.lockstep.batch_loop`), at the scalar loop's
speed per lane.
"""

from __future__ import annotations

import hashlib
import inspect
import threading
from collections.abc import Sequence

import numba
import numpy as np

from ..driver.preview import DRIVER
from ..model.packing import Plant
from . import lane_batch
from .integrator import OPEN_LOOP_DRIVER, OPEN_LOOP_PATH, OPEN_LOOP_SPEED
from .lockstep import advance_lane, batch_loop, stack_plants
from .result import Result
from .run import loop_result, loop_steps, stop_step
from .specialised import kernel_choice, structure_loop_module, time_loop

__all__ = ["BATCH_KERNELS", "DEFAULT_LANES", "FEWEST_LANES", "batch_source", "plan", "run_batch", "run_prepared"]

DEFAULT_LANES = 8
"""Lanes of a batch by default."""


LANE_WIDTH = 8
"""Lanes of one call of the lane kernels (a constant of their code): a batch of more lanes runs them in groups
of this many, one of fewer leaves the rest of its group idle. 8 doubles are an AVX-512 register; 16 lanes
measured no faster per lane than 8 (:mod:`trikedyn.model.lanes`)."""

FEWEST_LANES = 4
"""Fewest runs that go through the lane loop together: a lane step computes the kernels of all
:data:`LANE_WIDTH` lanes, so a batch of fewer runs than this is run by the scalar loop, one run after the other
(the same records, bit for bit). Measured (``python benchmarks/batch.py``): a batch costs about 6.8 ms plus
4.8 ms per busy lane for 10 s runs, the scalar loop about 6.5 ms a run: they break even at about 4 runs."""

_COPIED = (advance_lane, batch_loop, lane_batch._at, lane_batch.set_lane_plant, lane_batch.evaluate_lanes,
           lane_batch.etd_lanes, lane_batch.lane_batch_loop)
"""The batch functions compiled again on the generated kernels (:func:`batch_source`)."""

_LANE_KERNELS = ("kinematics_lanes", "forward_dynamics_lanes", "forward_dynamics_factor_lanes")

_FROM_LOOP = {"evaluate_into", "evaluate_stage_into", "spin_slip_blocks", "etd_step"}
"""Globals of the copied functions taken from the scalar loop's generated module (its right-hand side on the
generated kernels, the step)."""

_REBOUND = {*_FROM_LOOP, *(f.__name__ for f in _COPIED), *lane_batch.LANE_GLOBALS, *_LANE_KERNELS}
"""Globals the generated module defines or imports from the generated modules."""

_LOCK = threading.Lock()
_BY_STRUCTURE: dict = {}


def _structure(plant):
    """The tree structure of ``plant`` the generated kernels are specialised to."""
    from ..model.codegen import TreeStructure

    return TreeStructure.of(plant.parent, plant.jtype, plant.jaxis, plant.tree_e, plant.tree_r, plant.h, plant.ibar)


def batch_source(structure) -> str:
    """The source of the batch loops on the kernels generated for ``structure``.

    The module imports the scalar loop's module (:func:`~trikedyn.simulate.specialised.structure_loop_module`:
    the generated kernels, ``evaluate_into``, ``etd_step``...) and the lane kernels over :data:`LANE_WIDTH`
    lanes (:func:`~trikedyn.model.lanes.lane_kernels`), both generated and imported first, so that each kernel
    is compiled (and cached) once, in its own module; it defines the lane buffer's layout (the constants of
    :data:`~trikedyn.simulate.lane_batch.LANE_GLOBALS`), then :func:`~trikedyn.simulate.lockstep.advance_lane`,
    :func:`~trikedyn.simulate.lockstep.batch_loop` and the functions of :mod:`trikedyn.simulate.lane_batch`
    copied verbatim, their other globals imported from their modules.

    Parameters
    ----------
    structure : TreeStructure
        The tree's structure (:class:`~trikedyn.model.codegen.TreeStructure`).

    Returns
    -------
    str
        The module's text.
    """
    from ..model.lanes import LaneLayout, lane_kernels

    loop = structure_loop_module(structure)
    lanes = lane_kernels(structure, LANE_WIDTH)
    layout = LaneLayout(len(structure.parent), LANE_WIDTH)
    wanted: dict[str, set] = {loop.__name__: _FROM_LOOP, lanes.__name__: set(_LANE_KERNELS)}
    seen = set(_REBOUND)
    for func in _COPIED:
        py = func.py_func
        names = {n for n in py.__code__.co_names if n in py.__globals__ and n not in seen and n != "np"}
        wanted.setdefault(py.__module__, set()).update(names)
        seen |= names
    imports = [f"from {module} import {', '.join(sorted(names))}  # noqa: F401"
               for module, names in sorted(wanted.items()) if names]
    constants = [f"LANES = {layout.lanes}", f"ROWS = {layout.rows}"]
    constants += [f"{name} = {layout.start(array)}" for name, array in lane_batch.LANE_GLOBALS.items() if array]
    header = (f'"""Generated by trikedyn.simulate.batch: the lockstep batches of one tree structure (key '
              f'{structure.key()}) on {loop.__name__} and {lanes.__name__}: do not edit."""\n\n'
              "import numpy as np\n\nfrom trikedyn._jit import jit\n")
    parts = [header, "\n".join(imports), "\n\n", "\n".join(constants), "\n"]
    parts += ["\n\n" + inspect.getsource(func.py_func) for func in _COPIED]
    return "".join(parts)


def _module(plant):
    """The batch module of ``plant``'s tree structure (:func:`batch_source`), written and compiled at first use."""
    from ..model.codegen import load_module

    structure = _structure(plant)
    with _LOCK:
        module = _BY_STRUCTURE.get(structure)
    if module is None:
        source = batch_source(structure)
        module = load_module("batch" + hashlib.sha256(source.encode()).hexdigest()[:24], lambda: source)
        with _LOCK:
            _BY_STRUCTURE[structure] = module
    return module


BATCH_KERNELS = {"generated": lambda plant: _module(plant).lane_batch_loop,
                 "generated-scalar": lambda plant: _module(plant).batch_loop,
                 "generic": lambda plant: batch_loop}
"""The batch loop by kernel (the keys of :data:`~trikedyn.simulate.specialised.KERNELS`): on the kernels
generated for the tree, with each stage over the lanes (:mod:`trikedyn.simulate.lane_batch`: the default, as the
scalar loop's kernels), or on the generic ones. ``"generated-scalar"`` is the batch of the generated kernels
that steps its lanes one after the other through the scalar step (the lane loop's reference, and the
benchmark's)."""


def _padded(tables: list[np.ndarray], width: int) -> tuple[np.ndarray, np.ndarray]:
    """The tables stacked, each padded with zeros to the longest; and their lengths."""
    lengths = np.array([t.shape[0] for t in tables], np.int64)
    out = np.zeros((len(tables), max(int(lengths.max()), 1), width))
    for j, t in enumerate(tables):
        out[j, : t.shape[0]] = t
    return out, lengths


def _same_plant(a: Plant, b: Plant) -> bool:
    """Whether two plants hold the same values (an ideal-drive model is rebuilt for each run)."""
    return a is b or all(np.array_equal(getattr(a, f), getattr(b, f)) for f in Plant._fields)


def _group_key(model, dt: float, every: int, exponential: bool) -> tuple:
    """Jobs that can share a batch: one step, record interval and integrator, plants of one numba type
    and shape (one topology and tyre model)."""
    if "batch_signature" not in model.cache:  # numba's type of a plant of records takes ~0.5 ms: once a model
        shapes = tuple((f, getattr(model.plant, f).shape) for f in Plant._fields)
        model.cache["batch_signature"] = (numba.typeof(model.plant), shapes, _structure(model.plant))
    return (dt, every, exponential, *model.cache["batch_signature"])


def plan(specs: Sequence[dict], output_rate_hz: float = 100.0) -> tuple[list[dict], list[tuple]]:
    """Group prepared runs into batches and pack each batch's arrays for the compiled loop.

    Parameters
    ----------
    specs : sequence of dict
        As for :func:`run_prepared`.
    output_rate_hz : float
        Output rate [Hz].

    Returns
    -------
    jobs : list of dict
        Per spec: ``model``, ``dt`` [s], ``n_steps``, ``every``, ``exponential``, ``stop_dt`` [s], ...
    batches : list of tuple
        ``(plant, arguments, members)``: a plant of the batch (its kernels), the arguments of
        :func:`~trikedyn.simulate.lockstep.batch_loop` but ``lanes`` and ``refill``, the specs' indices.
    """
    jobs, groups = [], {}
    for i, spec in enumerate(specs):
        model, x0 = spec["model"], np.ascontiguousarray(spec["x0"], dtype=float)
        integrator = spec.get("integrator", "etdrk4")
        dt, every, n_steps = loop_steps(model, x0, spec["duration_s"], spec.get("dt"), output_rate_hz, integrator)
        closed = spec.get("path") is not None
        jobs.append({"model": model, "x0": x0, "dt": dt, "n_steps": n_steps, "inputs": np.asarray(spec["inputs"], float),
                     "path": np.asarray(spec["path"], float) if closed else OPEN_LOOP_PATH,
                     "speeds": np.asarray(spec["speed_profile"], float) if closed else OPEN_LOOP_SPEED,
                     "driver": spec["driver"] if closed else OPEN_LOOP_DRIVER, "every": every,
                     "exponential": integrator == "etdrk4", "stop_dt": stop_step(model)[0]})
        groups.setdefault(_group_key(model, dt, every, integrator == "etdrk4"), []).append(i)
    batches = []
    for (dt, every, exponential, *_), members in groups.items():
        part = [jobs[i] for i in members]
        plants, plant_of = [], []
        for job in part:
            known = [k for k, p in enumerate(plants) if _same_plant(p, job["model"].plant)]
            if not known:
                plants.append(job["model"].plant)
            plant_of.append(known[0] if known else len(plants) - 1)
        inputs, n_inputs = _padded([job["inputs"] for job in part], 4)
        paths, n_path = _padded([job["path"] for job in part], 5)
        speeds, n_speeds = _padded([job["speeds"] for job in part], 2)
        drivers = np.concatenate([np.asarray(job["driver"], DRIVER).reshape(1) for job in part])
        arguments = (np.stack([job["x0"] for job in part]), np.array([job["n_steps"] for job in part], np.int64),
                     stack_plants(plants), np.array(plant_of, np.int64), inputs, n_inputs, paths, n_path, speeds,
                     n_speeds, drivers, np.array([job["stop_dt"] for job in part]), dt, every, exponential)
        batches.append((plants[0], arguments, members))
    return jobs, batches


def run_prepared(specs: Sequence[dict], *, lanes: int = DEFAULT_LANES, output_rate_hz: float = 100.0,
                 raise_on_failure: bool = False, refill: bool = True, kernels: str | None = None) -> list[Result]:
    """Run prepared runs in lockstep batches and return one :class:`Result` each, in order.

    Runs that cannot share a batch (another step, topology or tyre model) go in batches of their own
    (:func:`plan`); on the generated kernels, a batch of fewer than :data:`FEWEST_LANES` runs (or ``lanes``)
    goes through the scalar loop, run after run.

    Parameters
    ----------
    specs : sequence of dict
        :func:`~trikedyn.simulate.closed_loop.prepare_run`'s dicts (``path``, ``speed_profile`` and
        ``driver`` None, or missing, for an open-loop run on its ``inputs``).
    lanes : int
        Runs advanced together (>= 1).
    output_rate_hz : float
        Output rate [Hz].
    raise_on_failure : bool
        Raise :class:`~trikedyn.errors.SimulationError` for the first run (in order) that stopped early.
    refill : bool
        Refill a lane as soon as its run ends.
    kernels : str, optional
        A key of :data:`BATCH_KERNELS`; as the scalar loop's when None
        (:func:`~trikedyn.simulate.specialised.kernel_choice`).

    Returns
    -------
    list of Result
        Equal to :func:`~trikedyn.simulate.run.run_model`'s for each spec.
    """
    from ..errors import InputError

    if int(lanes) < 1:
        raise InputError(f"lanes must be >= 1, got {lanes!r}", where="lanes")
    choice = kernels if kernels in BATCH_KERNELS else kernel_choice(kernels)
    jobs, batches = plan(specs, output_rate_hz)
    outs: list = [None] * len(jobs)
    for plant, arguments, members in batches:
        if choice == "generated" and min(int(lanes), len(members)) < FEWEST_LANES:
            for i in members:
                outs[i] = _scalar_run(jobs[i])
            continue
        res = BATCH_KERNELS[choice](plant)(*arguments, int(lanes), bool(refill))
        times, states, derivs, wheels, commands, status, recorded, t_stop = res
        for row, i in enumerate(members):  # views of the batch's records: each Result copies what it keeps
            m = int(recorded[row])
            outs[i] = (times[row, :m], states[row, :m], derivs[row, :m], wheels[row, :m], commands[row, :m],
                       int(status[row]), m, float(t_stop[row]))
    return [loop_result(spec["model"], out, dt=jobs[i]["dt"], raise_on_failure=raise_on_failure,
                        meta=spec.get("meta"), extra=spec.get("extra"), manoeuvre=spec.get("manoeuvre"))
            for i, (spec, out) in enumerate(zip(specs, outs, strict=True))]


def _scalar_run(job: dict) -> tuple:
    """One job of :func:`plan` by the scalar loop on the generated kernels (a batch under :data:`FEWEST_LANES`)."""
    plant = job["model"].plant
    return time_loop(plant, "generated")(job["x0"], 0.0, job["dt"], job["n_steps"], job["every"], job["inputs"],
                                         np.ascontiguousarray(job["path"]), np.ascontiguousarray(job["speeds"]),
                                         job["driver"], plant, job["exponential"], job["stop_dt"])


def run_batch(vehicle, manoeuvre="dlc", speeds_kmh: float | Sequence[float] = 30.0, *, driver=None,
              dt: float | None = None, output_rate_hz: float = 100.0, duration_s: float | None = None,
              integrator: str = "etdrk4", speed_control: str = "driver", lanes: int = DEFAULT_LANES,
              raise_on_failure: bool = False, kernels: str | None = None, **options) -> list[Result]:
    """Drive a manoeuvre at several speeds and/or with several vehicles, in lockstep batches.

    One run per entry of ``speeds_kmh`` and of ``vehicle`` (a vehicle, or a sequence of them with one
    topology and tyre model), broadcast against each other; each result equals
    :func:`~trikedyn.simulate.closed_loop.run`'s with the same arguments.

    Parameters
    ----------
    vehicle : ParameterSet, VehicleModel or sequence of them
        The vehicle(s).
    manoeuvre : str or Manoeuvre
        A registered name (built at each speed with ``options``) or a built manoeuvre (then one speed).
    speeds_kmh : float or sequence of float
        Target speeds [km/h].
    driver, dt, output_rate_hz, duration_s, integrator, speed_control, raise_on_failure, **options
        As for :func:`~trikedyn.simulate.closed_loop.run` (``dt`` [s], ``output_rate_hz`` [Hz],
        ``duration_s`` [s]).
    lanes : int
        Runs advanced together.
    kernels : str, optional
        ``"generated"`` or ``"generic"``; as the scalar loop's when None.

    Returns
    -------
    list of Result
        In the order of the broadcast (vehicle, speed) pairs.
    """
    from ..model.vehicle import VehicleModel, build_model
    from .closed_loop import prepare_run

    many = isinstance(vehicle, (list, tuple))
    vehicles = list(vehicle) if many else [vehicle]
    speeds = list(np.atleast_1d(np.asarray(speeds_kmh, dtype=float)))
    if len(vehicles) != len(speeds) and 1 not in (len(vehicles), len(speeds)):
        from ..errors import InputError

        raise InputError(f"{len(vehicles)} vehicles and {len(speeds)} speeds do not broadcast", where="run_batch")
    count = max(len(vehicles), len(speeds))
    models = [v if isinstance(v, VehicleModel) else build_model(v) for v in vehicles]
    specs = [prepare_run(models[i % len(models)], manoeuvre, speed_kmh=float(speeds[i % len(speeds)]), driver=driver,
                         dt=dt, duration_s=duration_s, integrator=integrator, speed_control=speed_control, **options)
             for i in range(count)]
    return run_prepared(specs, lanes=lanes, output_rate_hz=output_rate_hz, raise_on_failure=raise_on_failure,
                        kernels=kernels)
