"""Open-loop simulation: inputs as functions of time, a compiled run from equilibrium, a result.

``simulate(vehicle, duration_s=..., speed_kmh=..., steer_rad=..., drive_torque_Nm=...)`` starts the
vehicle rolling straight at ``speed_kmh`` from its static equilibrium (solved, never guessed), runs the
compiled RK4 loop and returns a :class:`~trikedyn.simulate.result.Result`. Inputs are a constant, a
function of time [s], or a pair of arrays ``(times_s, values)``; they are tabulated at the time step.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..errors import InputError, SimulationError
from ..model.statics import rolling_state, static_equilibrium
from ..model.vehicle import VehicleModel, build_model
from ..params.io import ParameterSet
from .channels import compute_channels, imu_readings
from .integrator import (
    DEFAULT_DT_S,
    OPEN_LOOP_DRIVER,
    OPEN_LOOP_PATH,
    OPEN_LOOP_SPEED,
    STATUS_OK,
    STATUS_TEXT,
)
from .result import Result
from .specialised import model_time_loop

__all__ = ["INTEGRATORS", "TyreRangeWarning", "automatic_step", "input_table", "loop_result", "loop_steps",
           "max_stable_step", "run_model", "simulate", "stop_step", "time_step"]

InputSpec = float | Callable[[np.ndarray], np.ndarray] | tuple


def input_table(duration_s: float, dt: float, steer_rad: InputSpec = 0.0, drive_torque_Nm: InputSpec = 0.0,
                brake_torque_Nm: InputSpec = 0.0) -> np.ndarray:
    """The ``(time, steer, drive, brake)`` table the compiled loop interpolates.

    Constants give a single row; functions are sampled every ``dt``; ``(times, values)`` pairs are
    resampled onto the same grid.

    Parameters
    ----------
    duration_s : float
        Simulated time [s].
    dt : float
        Sampling step [s].
    steer_rad : float, callable or (times, values)
        Steer command [rad].
    drive_torque_Nm : float, callable or (times, values)
        Total drive torque [N m].
    brake_torque_Nm : float, callable or (times, values)
        Brake torque [N m].

    Returns
    -------
    numpy.ndarray, shape (m, 4)
        Rows (time [s], steer [rad], drive [N m], brake [N m]).

    Raises
    ------
    InputError
        On non-finite inputs.
    """
    specs = (steer_rad, drive_torque_Nm, brake_torque_Nm)
    names = ("steer_rad", "drive_torque_Nm", "brake_torque_Nm")
    if all(np.isscalar(s) for s in specs):
        row = np.array([[0.0, *[float(s) for s in specs]]])
        if not np.all(np.isfinite(row)):
            raise InputError("inputs must be finite numbers", where="inputs")
        return row
    grid = np.arange(0.0, duration_s + dt, dt)
    table = np.empty((grid.size, 4))
    table[:, 0] = grid
    for col, (spec, name) in enumerate(zip(specs, names, strict=True), start=1):
        if np.isscalar(spec):
            table[:, col] = float(spec)
        elif callable(spec):
            table[:, col] = np.broadcast_to(np.asarray(spec(grid), dtype=float), grid.shape)
        else:
            try:
                times, values = (np.asarray(a, dtype=float) for a in spec)
            except (TypeError, ValueError):
                raise InputError("expected a number, a function of time or (times, values)", where=name) from None
            if times.ndim != 1 or times.shape != values.shape or times.size < 2 or np.any(np.diff(times) <= 0):
                raise InputError("(times, values) must be equal-length 1-D arrays, times increasing", where=name)
            table[:, col] = np.interp(grid, times, values)
        if not np.all(np.isfinite(table[:, col])):
            raise InputError("input has NaN or infinite values", where=name)
    return table


INTEGRATORS = ("etdrk4", "rk4")
"""The loop's integrators: ETDRK4 with the spin-slip pairs exact (default), classical RK4."""

RK4_STABILITY = 2.5
"""Largest ``|lambda| dt`` allowed: RK4 is stable to 2.78 on the real and 2.83 on the imaginary axis."""


def max_stable_step(model: VehicleModel, state: np.ndarray | None = None, *,
                    exponential: bool = True) -> tuple[float, str]:
    """The largest RK4 step [s] the model's fastest dynamics allow, with the mode that sets it.

    The fastest eigenvalue of the linearisation about ``state`` (static equilibrium by default):
    ``dt <= 2.5 / |lambda|``. With ``exponential`` (the loop's default, :mod:`trikedyn.simulate.exponential`)
    the wheels' spin-slip pairs, integrated exactly, are left out: their rows and columns of the
    linearisation are zeroed first. The bump and rebound stops, one-sided springs not engaged at
    equilibrium, are not in it: the loop splits a step near a stop into substeps (:func:`stop_step`). The
    fastest modes hardly change with speed: the limit is found at the first state asked for and kept in the
    model's cache.

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    state : numpy.ndarray, optional
        The state linearised about (static equilibrium by default).
    exponential : bool
        Leave out the spin-slip pairs integrated exactly.

    Returns
    -------
    dt : float
        The step limit [s].
    why : str
        The mode that sets it.
    """
    from ..model.linear import linearise

    if state is None:
        state = static_equilibrium(model).state
    key = ("max_stable_step", exponential)
    if key in model.cache:
        return model.cache[key]
    a, positions = linearise(model, state)
    if exponential:
        n = model.n_dof
        exact = [len(positions) + 5 + w.wheel_body for w in model.tree.wheels]
        exact += [len(positions) + n + 2 * k for k in range(len(model.tree.wheels))]
        a = a.copy()
        a[exact, :] = 0.0
        a[:, exact] = 0.0
    fastest = float(np.abs(np.linalg.eigvals(a)).max())
    model.cache[key] = (RK4_STABILITY / fastest, f"the fastest mode of the linearised model ({fastest:.0f} rad/s)")
    return model.cache[key]


def stop_step(model: VehicleModel) -> tuple[float, str]:
    """The largest RK4 step [s] while a wheel's suspension is on its bump stop, with the wheel.

    The wheel hop on the stop: the unsprung mass on the tyre's vertical stiffness and the stop's stiffness
    in parallel (the chassis held), ``omega = sqrt((k_z + k_stop) / m)``, ``dt <= 2.5 / omega``. The loop
    takes substeps of at most this only while a suspension is on or near a stop
    (:func:`~trikedyn.simulate.integrator.near_a_stop`).

    Parameters
    ----------
    model : VehicleModel
        The vehicle.

    Returns
    -------
    dt : float
        The substep limit [s].
    why : str
        The wheel and its hop frequency.
    """
    if "stop_step" in model.cache:
        return model.cache["stop_step"]
    limits = []
    for k, w in enumerate(model.tree.wheels):
        unsprung = model.tree.mass[w.wheel_body] + model.tree.mass[w.spring_body] * (1.0 if w.steer_body >= 0 else 0.5)
        kz = float(model.wheels[k]["vertical_stiffness"])
        omega = np.sqrt((kz + w.bump_stop_stiffness) / unsprung)
        limits.append((RK4_STABILITY / omega, f"{w.name} wheel hop on its bump stop ({omega:.0f} rad/s)"))
    model.cache["stop_step"] = min(limits)
    return model.cache["stop_step"]


def automatic_step(limit_s: float, bumpy: bool = False) -> float:
    """The default time step [s]: the largest of :data:`~trikedyn.simulate.DEFAULT_DT_S` / 2^k (10, 5, 2.5,
    ... ms, so that the 100 Hz output falls on steps) within the stability limit ``limit_s``
    (:func:`max_stable_step`); at most 5 ms on a ``bumpy`` road, whose bump kicks the wheel hop (24 Hz on
    the reference trike: the front load over a 5 cm bump at 30 km/h is 1.9 % of its static value off a 0.6 ms
    reference at 5 ms, 19 % at 10 ms; at 5 km/h 0.14 % and 1.7 %).

    Parameters
    ----------
    limit_s : float
        Stability limit [s].
    bumpy : bool
        A road with a bump.

    Returns
    -------
    float
        The step [s].
    """
    dt = DEFAULT_DT_S / 2 if bumpy else DEFAULT_DT_S
    while dt > limit_s and dt > 1e-5:
        dt /= 2
    return dt


def time_step(model: VehicleModel, x0: np.ndarray, dt: float | None, integrator: str = "etdrk4") -> float:
    """The run's time step [s]: ``dt`` checked against the stability limit of ``integrator`` at ``x0``
    (:class:`SimulationError` when too large), or :func:`automatic_step` for None.

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    x0 : numpy.ndarray
        Initial state.
    dt : float or None
        Requested step [s].
    integrator : str
        ``"etdrk4"`` or ``"rk4"``.

    Returns
    -------
    float
        The step [s].
    """
    if integrator not in INTEGRATORS:
        raise InputError(f"unknown integrator {integrator!r}; known: {', '.join(INTEGRATORS)}", where="integrator")
    if dt is not None and not dt > 0:
        raise InputError(f"time step must be > 0, got {dt!r}", where="dt")
    limit, why = max_stable_step(model, x0, exponential=integrator == "etdrk4")
    if dt is None:
        return automatic_step(limit, bumpy=bool(model.plant.road[0]["bump"]))
    if dt > limit:
        raise SimulationError(f"time step too large: dt = {dt:g} s, but {why} needs dt <= {limit:.2g} s", 0.0)
    return float(dt)


def run_model(model: VehicleModel, x0: np.ndarray, inputs: np.ndarray, *, duration_s: float, dt: float | None,
              output_rate_hz: float, raise_on_failure: bool = True, path=None, speed_profile=None,
              driver=None, meta=None, extra=None, manoeuvre=None, integrator: str = "etdrk4",
              kernels: str | None = None) -> Result:
    """Run the compiled loop from ``x0`` and compute the channels; raise :class:`SimulationError` on failure.

    With ``path`` (arrays ``PATH_COLUMNS``), ``speed_profile`` (``(time, speed)`` rows) and ``driver`` (a
    :func:`~trikedyn.driver.preview.driver_array`) the driver closes the loop; otherwise ``inputs`` drive it.
    ``extra(times, channels)`` returns more channels (a dict of arrays) computed from the base channels;
    ``manoeuvre`` is kept in the result. ``dt`` None: :func:`automatic_step`. ``integrator``:
    ``"etdrk4"`` (default: the wheels' spin-slip pairs exact, :mod:`trikedyn.simulate.exponential`) or
    ``"rk4"`` (classical).

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    x0 : numpy.ndarray
        Initial state.
    inputs : numpy.ndarray, shape (m, 4)
        Input table (:func:`input_table`).
    duration_s : float
        Simulated time [s].
    dt : float or None
        Time step [s]; automatic for None.
    output_rate_hz : float
        Output rate [Hz].
    raise_on_failure : bool
        Raise when the run stops early.
    path : numpy.ndarray, optional
        Path rows for the driver.
    speed_profile : numpy.ndarray, optional
        Target speed rows (time [s], speed [m/s]).
    driver : numpy.ndarray, optional
        Driver record.
    meta : dict, optional
        Metadata for the result.
    extra : callable, optional
        More channels from the base ones.
    manoeuvre : Manoeuvre, optional
        Kept in the result.
    integrator : str
        ``"etdrk4"`` or ``"rk4"``.
    kernels : str, optional
        ``"generated"`` (the loop on the kernels generated for the tree) or ``"generic"`` (the reference);
        ``$TRIKEDYN_KERNELS`` or ``"generated"`` when None (:func:`~trikedyn.simulate.specialised.time_loop`).

    Returns
    -------
    Result
        The recorded run.
    """
    dt, every, n_steps = loop_steps(model, x0, duration_s, dt, output_rate_hz, integrator)
    exponential = integrator == "etdrk4"
    closed = path is not None
    out = model_time_loop(model, kernels)(
        x0, 0.0, dt, n_steps, every, inputs,
        np.ascontiguousarray(path) if closed else OPEN_LOOP_PATH,
        np.ascontiguousarray(speed_profile) if closed else OPEN_LOOP_SPEED,
        driver if closed else OPEN_LOOP_DRIVER,
        model.plant,
        exponential,
        stop_step(model)[0],
    )
    return loop_result(model, out, dt=dt, raise_on_failure=raise_on_failure, meta=meta, extra=extra,
                       manoeuvre=manoeuvre)


def loop_steps(model: VehicleModel, x0: np.ndarray, duration_s: float, dt: float | None, output_rate_hz: float,
               integrator: str = "etdrk4") -> tuple[float, int, int]:
    """The compiled loop's step, record interval and step count for a run (:func:`run_model`).

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    x0 : numpy.ndarray
        Initial state.
    duration_s : float
        Simulated time [s].
    dt : float or None
        Requested step [s]; automatic for None (:func:`time_step`).
    output_rate_hz : float
        Output rate [Hz].
    integrator : str
        ``"etdrk4"`` or ``"rk4"``.

    Returns
    -------
    dt : float
        The step [s].
    every : int
        Steps between records.
    n_steps : int
        Steps in the run.
    """
    if duration_s <= 0:
        raise InputError("duration must be > 0", where="duration_s")
    dt = time_step(model, x0, dt, integrator)
    every = max(1, int(round(1.0 / (output_rate_hz * dt))))
    return dt, every, int(round(duration_s / dt))


def loop_result(model: VehicleModel, out: tuple, *, dt: float, raise_on_failure: bool, meta=None, extra=None,
                manoeuvre=None) -> Result:
    """The :class:`Result` of one run of the compiled loop (the tuple :func:`~trikedyn.simulate.integrator.rk4_loop`
    returns): channels, IMU readings, status; :class:`SimulationError` on failure with ``raise_on_failure``.

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    out : tuple
        ``(times, states, derivatives, wheels, commands, status, n_recorded, t_stop)``.
    dt : float
        The step [s].
    raise_on_failure : bool
        Raise when the run stopped early.
    meta, extra, manoeuvre
        As for :func:`run_model`.

    Returns
    -------
    Result
        The recorded run.
    """
    times, states, derivs, wheels, commands, status, n_rec, t_stop = out
    times, states, derivs, wheels, commands = (a[:n_rec] for a in (times, states, derivs, wheels, commands))
    _warn_if_tyre_data_left(model, wheels)
    steer = [w.steer_body for w in model.tree.wheels if w.steer_body >= 0]
    cg = model.tree.chassis_cg  # the sprung body's CG, fixed in the chassis
    base = compute_channels(states, derivs, cg, steer[0] if steer else -1, model.n_dof)
    sensor = np.array([model.params.sensor.x_m, model.params.sensor.y_m, model.params.sensor.z_m])
    imu = imu_readings(states, derivs, sensor, model.gravity, model.n_dof)
    more = None
    if extra is not None:
        from .channels import BASE_CHANNELS

        more = extra(times, {name: base[:, i] for i, name in enumerate(BASE_CHANNELS)})
    result = Result.from_arrays(model, times, states, base, wheels, commands, imu, status=STATUS_TEXT[status], dt=dt,
                                meta=meta, extra=more, manoeuvre=manoeuvre)
    if status != STATUS_OK and raise_on_failure:
        err = SimulationError(STATUS_TEXT[status], t_stop)
        err.result = result
        raise err
    return result


def _warn_if_tyre_data_left(model: VehicleModel, wheels: np.ndarray) -> None:
    """One warning per run when a wheel's tyre inputs left its ``.tir`` file's validity ranges (clamped)."""
    clamped = wheels["clamped"].astype(np.int64)
    if not clamped.any():
        return
    import warnings

    from ..tyre.models import get

    parts = []
    for k, name in enumerate(model.wheel_names):
        bits = int(np.bitwise_or.reduce(clamped[:, k]))
        if bits:
            parts.append(f"{name} ({', '.join(get(model.tyres[k].name).clamp_names(bits))})")
    warnings.warn("tyre inputs left the tyre file's validity ranges and were clamped: " + "; ".join(parts),
                  TyreRangeWarning, stacklevel=3)


class TyreRangeWarning(UserWarning):
    """A run took a tyre outside its ``.tir`` file's validity ranges (load, slip, slip angle, camber)."""


def simulate(vehicle: ParameterSet | VehicleModel, *, duration_s: float, speed_kmh: float = 0.0,
             steer_rad: InputSpec = 0.0, drive_torque_Nm: InputSpec = 0.0, brake_torque_Nm: InputSpec = 0.0,
             road=None, dt: float | None = None, output_rate_hz: float = 100.0,
             integrator: str = "etdrk4", raise_on_failure: bool = False) -> Result:
    """Simulate open-loop inputs from a straight rolling start at ``speed_kmh`` (``td.run_open_loop``).

    Parameters
    ----------
    vehicle : ParameterSet or VehicleModel
        The vehicle (with its payload).
    duration_s : float
        Simulated time [s].
    speed_kmh : float
        Initial speed, rolling straight ahead from static equilibrium [km/h].
    steer_rad, drive_torque_Nm, brake_torque_Nm : float, callable or (times, values)
        Steer command [rad] (positive left), total drive torque at the driven wheels [N m], brake torque
        per braked wheel [N m].
    road : Road, optional
        Flat by default.
    dt : float, optional
        Fixed step [s]; by default the largest of 10, 5, 2.5, ... ms the model's stability allows
        (:func:`automatic_step`).
    output_rate_hz : float
        Rate of the recorded channels [Hz].
    integrator : str
        ``"etdrk4"`` (default) or ``"rk4"`` (:data:`INTEGRATORS`).
    raise_on_failure : bool
        Raise :class:`SimulationError` when the run stops early (NaN, runaway penetration, rollover); by
        default the result says so (``success`` False, ``message``), as with :func:`~trikedyn.run` and
        :func:`~trikedyn.drive`.

    Returns
    -------
    Result
        The recorded run.

    Raises
    ------
    SimulationError
        A time step too large for the model's stiffest modes; with ``raise_on_failure``, a run that stops
        early (with ``.time_s`` and the partial ``.result``).
    """
    model = vehicle if isinstance(vehicle, VehicleModel) else build_model(vehicle, road=road)
    if road is not None and isinstance(vehicle, VehicleModel):
        model = model.with_road(road)
    if not np.isfinite(speed_kmh) or speed_kmh < 0:
        raise InputError(f"speed must be >= 0 km/h, got {speed_kmh!r}", where="speed_kmh")
    eq = static_equilibrium(model.on_flat_road())
    x0 = rolling_state(model, eq, speed_kmh / 3.6)
    dt = time_step(model, x0, dt, integrator)
    inputs = input_table(duration_s, dt, steer_rad, drive_torque_Nm, brake_torque_Nm)
    return run_model(model, x0, inputs, duration_s=duration_s, dt=dt, output_rate_hz=output_rate_hz,
                     integrator=integrator, raise_on_failure=raise_on_failure)
