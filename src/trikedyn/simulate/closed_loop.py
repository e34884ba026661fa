"""Driving a manoeuvre: ``run(vehicle, manoeuvre, ...)``, the one entry point.

``run`` starts the vehicle at the start of the manoeuvre, rolling straight at the target speed from static
equilibrium, lets the driver (:mod:`trikedyn.driver.preview`) hold the speed and steer along the path (or,
for an open-loop test, take the manoeuvre's steer command) inside the compiled loop, and returns a
:class:`~trikedyn.simulate.result.Result`. With a path it records the CG's progress along it
(``path_s_m``) and its lateral error (``path_error_m``); ``judged`` marks the manoeuvre's window. The
figures a run is judged by come from :mod:`trikedyn.analysis.metrics`.

``drive(vehicle, path, speed)`` is the older call for a bare :class:`~trikedyn.manoeuvres.paths.Path`.
"""

from __future__ import annotations

import numpy as np

from ..driver.preview import DriverSettings, driver_array, with_end_gate, with_steering
from ..errors import InputError
from ..manoeuvres.base import Manoeuvre
from ..model.statics import rolling_state, static_equilibrium
from ..model.vehicle import VehicleModel, build_model
from ..params.io import ParameterSet
from .defaults import SPEED_CONTROLS  # noqa: F401  (re-exported: where the callers find it)
from .result import Result
from .run import run_model, time_step

__all__ = ["GATE_MARGIN_M", "SPEED_CONTROLS", "run", "drive", "exit_gate", "footprint", "prepare_run"]

GATE_MARGIN_M = 0.5
"""How far past its exit gate (along the path) a run that ends there has its CG at its last record [m]."""


def footprint(params) -> tuple[float, float, float]:
    """The vehicle's plan-view rectangle about the rear-axle centre: (x_rear, x_front, half width) [m].

    The overhangs split the overall length beyond the wheelbase evenly (the parameter set gives only the
    overall length).

    Parameters
    ----------
    params : VehicleParameters
        The vehicle (wheelbase, overall length and width).

    Returns
    -------
    tuple of float
        ``(x_rear, x_front, half_width)`` [m].
    """
    overhang = max(params.body.overall_length_m - params.wheelbase_m, 0.0) / 2
    return -overhang, params.wheelbase_m + overhang, params.body.overall_width_m / 2


def exit_gate(manoeuvre: Manoeuvre) -> tuple[float, float, float, float] | None:
    """The line a run that ends at its exit gate ends beyond (``prepare_run(end_at_exit=True)``): square to the
    path ``GATE_MARGIN_M`` past the exit gate, as ``(x, y, cos, sin)`` (a point [m] and the path's direction).

    Past it the CG's arc length along the path (``path_s_m``, its nearest point) is beyond the exit gate, so
    the run's judged samples (up to the exit gate: the window, the run-in, the margins) are all recorded, and
    are those of the whole run. That holds where the path is straight around the gate (``path_s_m`` is then
    the distance along it); elsewhere, and for a window by time, None: the run lasts its whole duration.

    Parameters
    ----------
    manoeuvre : Manoeuvre
        The manoeuvre.

    Returns
    -------
    tuple of float or None
        The gate's line, or None.
    """
    path, window = manoeuvre.path, manoeuvre.window
    if path is None or window.kind != "distance" or not manoeuvre.closed_loop:
        return None
    s, at = path.s_m, window.end + GATE_MARGIN_M
    near = (s >= window.end - 1.0) & (s <= at + 1.0)
    if at + 1.0 > s[-1] or not near.any() or np.any(np.abs(path.curvature_per_m[near]) > 1e-9):
        return None
    heading = float(np.interp(at, s, path.heading_rad))
    return float(np.interp(at, s, path.x_m)), float(np.interp(at, s, path.y_m)), np.cos(heading), np.sin(heading)


def cg_track(params, x, y, yaw) -> tuple[np.ndarray, np.ndarray]:
    """Plan-view position of the vehicle's CG from the chassis origin's position and heading [m]."""
    cx, cy = params.mass.cg_x_m, params.mass.cg_y_m
    cos, sin = np.cos(yaw), np.sin(yaw)
    return x + cx * cos - cy * sin, y + cx * sin + cy * cos


def _judging_channels(params, manoeuvre: Manoeuvre):
    """``extra`` for :func:`run_model`: path progress and error of the CG, and the judged window."""

    def extra(times, base):
        """The judging channels of a run at ``times`` [s] from its ``base`` channels: the CG's ``path_s_m`` and
        ``path_error_m`` [m] (with a path) and ``judged`` (1 inside the judged window, else 0)."""
        out = {}
        if manoeuvre.path is not None:
            cx, cy = cg_track(params, base["x_m"], base["y_m"], base["yaw_rad"])
            s, offset = manoeuvre.path.track(cx, cy)
            out["path_s_m"], out["path_error_m"] = s, offset
        w = manoeuvre.window
        at = out["path_s_m"] if w.kind == "distance" else times
        inside = (at >= w.start) & (at <= w.end)
        if w.kind == "distance":  # once past the exit gate, stay out (a lap later the same s would return)
            passed = np.maximum.accumulate(at) > w.end
            inside &= ~passed
        out["judged"] = inside.astype(float)
        return out

    return extra


def run(vehicle: ParameterSet | VehicleModel, manoeuvre: Manoeuvre | str = "dlc", *, speed_kmh: float | None = None,
        driver: DriverSettings | None = None, dt: float | None = None, output_rate_hz: float = 100.0,
        raise_on_failure: bool = False, duration_s: float | None = None, integrator: str = "etdrk4",
        speed_control: str = "driver", end_at_exit: bool = False, **options) -> Result:
    """Drive a manoeuvre and return the recorded run.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleModel
        The vehicle with its payload.
    manoeuvre : Manoeuvre or str
        A built :class:`~trikedyn.manoeuvres.base.Manoeuvre`, or a registered name (``trikedyn manoeuvres``
        lists them) or a path ``.csv`` file, built here at ``speed_kmh`` with ``options``.
    speed_kmh : float, optional
        Target speed [km/h]; needed when ``manoeuvre`` is a name.
    driver : DriverSettings, optional
        The driver's parameters; defaults otherwise.
    dt : float, optional
        Time step [s]; by default the largest of 10, 5, 2.5, ... ms the vehicle's stability allows
        (:func:`~trikedyn.simulate.run.automatic_step`).
    output_rate_hz : float
        Output rate [Hz].
    integrator : str
        ``"etdrk4"`` (default) or ``"rk4"`` (:data:`~trikedyn.simulate.run.INTEGRATORS`).
    speed_control : {"driver", "ideal"}
        ``"driver"`` (default): the driver holds the speed with the vehicle's own drive and brakes, within
        their limits (a target beyond the top speed is not held); ``"ideal"``: with a drive and brakes
        without limits (:data:`SPEED_CONTROLS`).
    raise_on_failure : bool
        Raise :class:`~trikedyn.errors.SimulationError` (with the partial ``.result``) when the run stops
        early; by default the result says so (``success``, ``message``).
    duration_s : float, optional
        Simulated time [s]; the manoeuvre's own by default.
    end_at_exit : bool
        End the run at the first record with the CG beyond its exit gate (:func:`exit_gate`), where the judging
        ends, instead of ``AFTER_EXIT_S`` later (a threshold search's runs; the records before are the same).
    **options
        The manoeuvre's options (see its entry in ``trikedyn manoeuvres``) when it is given by name.

    Returns
    -------
    Result
        With ``manoeuvre`` set, ``path_s_m``/``path_error_m`` when it has a path, and ``judged``.
    """
    spec = prepare_run(vehicle, manoeuvre, speed_kmh=speed_kmh, driver=driver, dt=dt, duration_s=duration_s,
                       integrator=integrator, speed_control=speed_control, end_at_exit=end_at_exit, **options)
    return run_model(**spec, output_rate_hz=output_rate_hz, raise_on_failure=raise_on_failure)


def prepare_run(vehicle: ParameterSet | VehicleModel, manoeuvre: Manoeuvre | str = "dlc", *,
                speed_kmh: float | None = None, driver: DriverSettings | None = None, dt: float | None = None,
                duration_s: float | None = None, integrator: str = "etdrk4", speed_control: str = "driver",
                end_at_exit: bool = False, **options) -> dict:
    """Everything :func:`run` hands the compiled loop, without running it (the batch integrator,
    :mod:`trikedyn.simulate.batch`, runs several of these in lockstep).

    Parameters
    ----------
    vehicle, manoeuvre, driver, integrator, speed_control, **options
        As for :func:`run`.
    speed_kmh : float, optional
        Target speed [km/h], for a manoeuvre given by name.
    dt : float, optional
        Time step [s]; automatic by default.
    duration_s : float, optional
        Simulated time [s]; the manoeuvre's own by default.
    end_at_exit : bool
        End the run once its CG is past the exit gate (as for :func:`run`).

    Returns
    -------
    dict
        The keyword arguments of :func:`~trikedyn.simulate.run.run_model` but ``output_rate_hz`` and
        ``raise_on_failure``: ``model``, ``x0``, ``inputs``, ``duration_s`` [s], ``dt`` [s], ``path``,
        ``speed_profile``, ``driver``, ``meta``, ``extra``, ``manoeuvre``, ``integrator``.
    """
    model = vehicle if isinstance(vehicle, VehicleModel) else build_model(vehicle)
    params = model.params
    if speed_control not in SPEED_CONTROLS:
        raise InputError(f"unknown speed control {speed_control!r}; expected one of {', '.join(SPEED_CONTROLS)}",
                         where="speed_control")
    if speed_control == "ideal":
        model = model.with_ideal_drive()
    if not isinstance(manoeuvre, Manoeuvre):
        from ..manoeuvres.registry import build

        if speed_kmh is None:
            raise InputError("a manoeuvre given by name needs speed_kmh", where="run")
        manoeuvre = build(manoeuvre, params, speed_kmh, **options)
    elif options:
        raise InputError(f"options {sorted(options)} apply only to a manoeuvre given by name", where="run")
    if duration_s is not None:
        manoeuvre = manoeuvre.lasting(duration_s)
    duration = manoeuvre.duration_s
    settings = driver or DriverSettings()
    v0 = float(manoeuvre.speed.speed_mps[0])
    eq = static_equilibrium(model.on_flat_road())
    path = manoeuvre.path
    heading = float(path.heading_rad[0]) if path is not None else 0.0
    x0 = rolling_state(model, eq, v0, heading_rad=heading)
    dt = time_step(model, x0, dt, integrator)
    if path is not None:
        x0[0], x0[1] = float(path.x_m[0]), float(path.y_m[0])
    drv = with_steering(driver_array(settings, params, dt), open_loop=not manoeuvre.closed_loop,
                        hold_after_s=manoeuvre.steer_hold_s)
    gate = exit_gate(manoeuvre) if end_at_exit else None
    if gate is not None:
        drv = with_end_gate(drv, gate, (params.mass.cg_x_m, params.mass.cg_y_m))
    path_rows = path.as_array() if path is not None else np.zeros((2, 5))
    inputs = np.zeros((1, 4))
    if manoeuvre.steer is not None:
        inputs = _steer_inputs(manoeuvre.steer, duration, dt)
    meta = {"manoeuvre": manoeuvre.title, "manoeuvre_name": manoeuvre.name, "driver": settings.__dict__,
            "target_speed_kmh": float(manoeuvre.speed.speed_mps.max() * 3.6), "speed_control": speed_control,
            "window": manoeuvre.window.to_dict(), "footprint_m": list(footprint(params))}
    return {"model": model, "x0": x0, "inputs": inputs, "duration_s": duration, "dt": dt, "path": path_rows,
            "speed_profile": manoeuvre.speed.as_array(), "driver": drv, "meta": meta,
            "extra": _judging_channels(params, manoeuvre), "manoeuvre": manoeuvre, "integrator": integrator}


def _steer_inputs(steer: np.ndarray, duration_s: float, dt: float) -> np.ndarray:
    """The steer table on the loop's uniform grid (drive and brake columns unused: the driver sets them)."""
    grid = np.arange(0.0, duration_s + dt, dt)
    table = np.zeros((grid.size, 4))
    table[:, 0] = grid
    table[:, 1] = np.interp(grid, steer[:, 0], steer[:, 1]) if steer.shape[0] > 1 else steer[0, 1]
    return table


def drive(vehicle: ParameterSet | VehicleModel, path, speed, *, driver: DriverSettings | None = None,
          duration_s: float | None = None, dt: float | None = None, output_rate_hz: float = 100.0,
          raise_on_failure: bool = False) -> Result:
    """Drive a bare ``path`` at ``speed`` (km/h, or a :class:`~trikedyn.manoeuvres.speed.SpeedProfile`).

    The path is judged over its whole length and continued beyond its end (run-out); prefer
    :func:`run` with a registered manoeuvre, which knows its own gates.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleModel
        The vehicle with its payload.
    path : Path
        The reference line (:class:`~trikedyn.manoeuvres.geometry.Path`).
    speed : float or SpeedProfile
        Constant target speed [km/h], or a speed profile.
    driver : DriverSettings, optional
        The driver's parameters; defaults otherwise.
    duration_s : float, optional
        Simulated time [s]; the path's length at the speed, with run-out, by default.
    dt : float, optional
        Time step [s]; automatic by default.
    output_rate_hz : float
        Output rate [Hz].
    raise_on_failure : bool
        Raise :class:`~trikedyn.errors.SimulationError` (with the partial ``.result``) when the run stops
        early; by default the result says so (``success``, ``message``), as with :func:`run`.

    Returns
    -------
    Result
        The recorded run.
    """
    from ..manoeuvres import speed as speeds
    from ..manoeuvres.base import whole_path

    if hasattr(speed, "speed_mps"):
        profile = speed
    else:
        value = float(speed)
        if not np.isfinite(value) or value <= 0:
            raise InputError(f"speed must be > 0 km/h, got {speed!r}", where="speed")
        profile = speeds.constant(value, 1.0)
    return run(vehicle, whole_path(path, profile), driver=driver, dt=dt, output_rate_hz=output_rate_hz,
               raise_on_failure=raise_on_failure, duration_s=duration_s)
