"""Closed-loop runs: the driver follows a manoeuvre's path at a speed profile.

``drive(vehicle, path, speed)`` starts the vehicle at the start of the path, rolling straight at the
profile's first speed from static equilibrium, lets the driver (:mod:`trikedyn.driver.preview`) steer
and hold the speed inside the compiled loop, and judges the run: lateral path error of the CG, cone
strikes of the vehicle's footprint, the rollover index (Eq. 5), wheel loads and accelerations.
"""

from __future__ import annotations

import numpy as np

from ..driver.preview import DriverSettings, driver_array
from ..errors import InputError
from ..model.statics import rolling_state, static_equilibrium
from ..model.vehicle import VehicleModel, build_model
from ..params.io import ParameterSet
from .result import Result
from .run import input_table, run_model

__all__ = ["drive", "footprint", "summary"]


def footprint(params) -> tuple[float, float, float]:
    """The vehicle's plan-view rectangle about the rear-axle centre: (x_rear, x_front, half width) [m].

    The overhangs split the overall length beyond the wheelbase evenly (the parameter set gives only the
    overall length).
    """
    overhang = max(params.body.overall_length_m - params.wheelbase_m, 0.0) / 2
    return -overhang, params.wheelbase_m + overhang, params.body.overall_width_m / 2


def _speed_rows(speed) -> np.ndarray:
    if hasattr(speed, "time_s") and hasattr(speed, "speed_mps"):
        rows = np.column_stack([speed.time_s, speed.speed_mps])
    else:
        value = float(speed)
        if not np.isfinite(value) or value <= 0:
            raise InputError(f"speed must be > 0 km/h, got {speed!r}", where="speed")
        rows = np.array([[0.0, value / 3.6]])
    return np.ascontiguousarray(rows, dtype=float)


def drive(vehicle: ParameterSet | VehicleModel, path, speed, *, driver: DriverSettings | None = None,
          duration_s: float | None = None, dt: float = 5e-3, output_rate_hz: float = 100.0,
          raise_on_failure: bool = True) -> Result:
    """Drive ``path`` at ``speed`` (km/h, or a :class:`~trikedyn.manoeuvres.speed.SpeedProfile`).

    Parameters
    ----------
    vehicle : ParameterSet or VehicleModel
    path : Path
        From :mod:`trikedyn.manoeuvres.paths` (reference line, cones, corridors).
    speed : float or SpeedProfile
        Constant target speed [km/h], or a target speed profile (the driver's PI controller follows it).
    driver : DriverSettings, optional
        The driver's parameters; defaults otherwise.
    duration_s : float, optional
        Simulated time [s]; by default until the rear axle has covered the path at the mean target speed.
    dt, output_rate_hz : float
        Time step [s] and output rate [Hz].

    Returns
    -------
    Result
        With the channels of :func:`~trikedyn.simulate.run.simulate` plus ``path_error_m``, and in
        ``meta`` the cone strikes and the :func:`summary`.
    """
    model = vehicle if isinstance(vehicle, VehicleModel) else build_model(vehicle)
    params = model.params
    settings = driver or DriverSettings()
    rows = _speed_rows(speed)
    v0 = float(rows[0, 1])
    if duration_s is None:
        duration_s = float(path.s_m[-1]) / max(float(rows[:, 1].mean()), 0.5)
    eq = static_equilibrium(model.on_flat_road())
    x0 = rolling_state(model, eq, v0, heading_rad=float(path.heading_rad[0]))
    x0[0], x0[1] = float(path.x_m[0]), float(path.y_m[0])
    arrays = np.column_stack([path.x_m, path.y_m, path.s_m, path.heading_rad, path.curvature_per_m])
    drv = driver_array(settings, params, dt)
    meta = {"manoeuvre": path.name, "driver": settings.__dict__}
    try:
        result = run_model(model, x0, input_table(duration_s, dt), duration_s=duration_s, dt=dt,
                           output_rate_hz=output_rate_hz, raise_on_failure=raise_on_failure, path=arrays,
                           speed_profile=rows, driver=drv, meta=meta)
    except Exception as err:  # judge what was driven before the failure too
        partial = getattr(err, "result", None)
        if partial is not None:
            _judge(partial, path, params)
        raise
    _judge(result, path, params)
    return result


def _judge(result: Result, path, params) -> None:
    """Add the path error, cone strikes and the summary to a result (in place: channels and meta)."""
    x, y, yaw = result["x_m"], result["y_m"], result["yaw_rad"]
    cg = np.asarray([params.mass.cg_x_m, params.mass.cg_y_m])
    cx = x + cg[0] * np.cos(yaw) - cg[1] * np.sin(yaw)
    cy = y + cg[0] * np.sin(yaw) + cg[1] * np.cos(yaw)
    _, offset = path.project(cx, cy)
    result.channels["path_error_m"] = np.asarray(offset, dtype=float)
    strikes = []
    if len(path.cones):
        from ..manoeuvres.paths import cone_strikes

        strikes = cone_strikes(path, result.time_s, x, y, yaw, footprint(params))
    result.meta["cone_strikes"] = strikes
    result.meta["summary"] = summary(result)


def summary(result: Result) -> dict:
    """The figures a run is judged by (``trikedyn simulate --json``)."""
    fz = np.column_stack([result[f"{w}_fz_N"] for w in result.meta["wheels"]])
    all_down = (fz > 0).all(axis=1)
    ri = np.abs(result["ri"])
    return {
        "manoeuvre": result.meta.get("manoeuvre", "open loop"),
        "status": result.status,
        "duration_s": float(result.time_s[-1]),
        "cone_strikes": len(result.meta.get("cone_strikes", [])),
        "max_abs_ri": float(np.nanmax(ri)) if ri.size else float("nan"),
        "max_abs_ri_all_wheels_down": float(np.nanmax(ri[all_down])) if all_down.any() else float("nan"),
        "min_wheel_load_N": float(fz.min()),
        "wheel_lifted": bool((fz <= 0).any()),
        "max_lateral_acceleration_mps2": float(np.abs(result["ay_mps2"]).max()),
        "max_yaw_rate_radps": float(np.abs(result["yaw_rate_radps"]).max()),
        "max_path_error_m": float(np.abs(result.channels.get("path_error_m", np.zeros(1))).max()),
        "max_speed_kmh": float(result["speed_mps"].max() * 3.6),
        "min_speed_kmh": float(result["speed_mps"].min() * 3.6),
    }
