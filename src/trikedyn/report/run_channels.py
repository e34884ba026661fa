"""A run read for its figures: its channels and metadata from a Result, a run file's table or a mapping (checked
as a run file is), each channel's axis label and unit, the judged window, the spans a wheel is lifted, the title.

Pure functions, no drawing: :mod:`trikedyn.report.run_figures` draws what these read.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from ..errors import InputError
from ._drawing import plain

__all__ = ["LABELS", "SUFFIXES", "judged_window", "label_of", "lift_spans", "need_channel", "run_source",
           "title_of", "wheel_names"]


# channel -> (label with unit, scale from the stored SI value)
LABELS = {
    "speed_mps": ("speed [km/h]", 3.6),
    "vx_mps": ("longitudinal velocity [km/h]", 3.6),
    "vy_mps": ("lateral velocity [m/s]", 1.0),
    "ax_mps2": ("longitudinal acceleration [m/s²]", 1.0),
    "ay_mps2": ("lateral acceleration [m/s²]", 1.0),
    "az_mps2": ("vertical acceleration [m/s²]", 1.0),
    "imu_ay_mps2": ("lateral acceleration, seat sensor [m/s²]", 1.0),
    "imu_ax_mps2": ("longitudinal acceleration, seat sensor [m/s²]", 1.0),
    "yaw_rate_radps": ("yaw rate [deg/s]", math.degrees(1.0)),
    "roll_rate_radps": ("roll rate [deg/s]", math.degrees(1.0)),
    "pitch_rate_radps": ("pitch rate [deg/s]", math.degrees(1.0)),
    "imu_wz_radps": ("yaw rate, seat sensor [deg/s]", math.degrees(1.0)),
    "roll_rad": ("roll [deg]", math.degrees(1.0)),
    "pitch_rad": ("pitch [deg]", math.degrees(1.0)),
    "yaw_rad": ("yaw [deg]", math.degrees(1.0)),
    "steer_rad": ("steer angle [deg]", math.degrees(1.0)),
    "steer_cmd_rad": ("steer command [deg]", math.degrees(1.0)),
    "ri": ("rollover index RI (Eq. 5) [-]", 1.0),
    "ltr": ("load transfer ratio [-]", 1.0),
    "min_wheel_load_N": ("least wheel load [N]", 1.0),
    "path_error_m": ("path error [m]", 1.0),
    "x_m": ("x [m]", 1.0),
    "y_m": ("y [m]", 1.0),
}
# unit suffix of a channel name -> (unit shown, scale)
SUFFIXES = (("_radps", "deg/s", math.degrees(1.0)), ("_rad", "deg", math.degrees(1.0)), ("_mps2", "m/s²", 1.0),
            ("_mps", "m/s", 1.0), ("_Nm", "N·m", 1.0), ("_N", "N", 1.0), ("_m", "m", 1.0), ("_s", "s", 1.0),
            ("_kmh", "km/h", 1.0))
def label_of(name: str) -> tuple[str, float]:
    """A channel's axis label with its unit, and the factor from its stored (SI) value to the value shown.

    Parameters
    ----------
    name : str
        Channel name (its unit in its suffix, ``roll_rad``).

    Returns
    -------
    label : str
        Axis label with the unit shown (``roll [deg]``).
    scale : float
        Factor from the stored SI value to the value shown.
    """
    if name in LABELS:
        return LABELS[name]
    for suffix, unit, scale in SUFFIXES:
        if name.endswith(suffix):
            words = name[: -len(suffix)].replace("_", " ")
            words = words.replace(" fz", " vertical load").replace(" fy", " lateral force").replace(" fx", " longitudinal force")
            return f"{words} [{unit}]", scale
    return f"{name.replace('_', ' ')} [-]", 1.0


def run_source(source, meta) -> tuple[dict, dict]:
    """``(channels, meta)`` of a Result, a DataFrame or a mapping; channels hold ``time_s``. A table or a mapping
    is checked as a run file is (:func:`trikedyn.simulate.runcheck.check_run_table`: numbers, finite increasing
    time, ...), and so is metadata that does not come with a Result (:func:`~trikedyn.simulate.runmeta.check_meta`).

    Parameters
    ----------
    source : Result, pandas.DataFrame or mapping of str to array_like
        The run (channels in SI units, ``time_s`` [s]).
    meta : mapping or None
        The run's metadata; None: the Result's own, or the table's ``attrs``.

    Returns
    -------
    channels : dict of str to numpy.ndarray
    meta : dict

    Raises
    ------
    InputError
        Not a run, or a table or metadata a run file could not hold.
    """
    from ..simulate.runcheck import check_run_table
    from ..simulate.runmeta import check_meta

    if hasattr(source, "time_s") and hasattr(source, "channels") and not isinstance(source, Mapping):
        channels = {"time_s": np.asarray(source.time_s, dtype=float), **dict(source.channels)}
        return channels, dict(source.meta or {}) if meta is None else check_meta(meta, "meta")
    if isinstance(source, Mapping):
        import pandas as pd

        try:
            source = pd.DataFrame({str(k): np.asarray(v).reshape(-1) for k, v in source.items()})
        except (TypeError, ValueError) as exc:
            raise InputError(f"the channels are not one table ({' '.join(str(exc).split())[:120]})",
                             where="run") from None
    if not (hasattr(source, "columns") and hasattr(source, "attrs")):
        raise InputError(f"expected a run (Result, table or channels), got {type(source).__name__}", where="run")
    table = check_run_table(source, "run")
    meta = check_meta(table.attrs if meta is None else meta, "meta")
    return {c: table[c].to_numpy() for c in table.columns}, meta


def need_channel(channels: dict, name: str) -> np.ndarray:
    """The channel ``name`` as floats.

    Parameters
    ----------
    channels : dict of str to array_like
        The run's channels.
    name : str
        The channel wanted.

    Returns
    -------
    numpy.ndarray
        Its values (stored SI units).

    Raises
    ------
    InputError
        The run does not have it.
    """
    if name not in channels:
        raise InputError(f"not a run of trikedyn: no channel '{name}'", where="run")
    return np.asarray(channels[name], dtype=float)


def wheel_names(channels: dict, meta: dict) -> list[str]:
    """The run's wheels: ``meta["wheels"]`` when each has its load channel, else every ``<wheel>_fz_N`` channel.

    Parameters
    ----------
    channels : dict of str to array_like
        The run's channels.
    meta : dict
        The run's metadata.

    Returns
    -------
    list of str
        Wheel names.
    """
    names = meta.get("wheels")
    if isinstance(names, list | tuple) and names and all(f"{n}_fz_N" in channels for n in names):
        return [str(n) for n in names]
    return [c[: -len("_fz_N")] for c in channels if str(c).endswith("_fz_N")]


def title_of(meta: Mapping) -> str:
    """``vehicle - manoeuvre at N km/h (payload P kg)`` from a run's metadata (what it holds of these).

    Parameters
    ----------
    meta : mapping
        A run's metadata.

    Returns
    -------
    str
        The title.
    """
    summary = meta.get("summary") if isinstance(meta.get("summary"), Mapping) else {}
    vehicle = meta.get("vehicle") or summary.get("vehicle")
    manoeuvre = meta.get("manoeuvre") or summary.get("manoeuvre") or meta.get("manoeuvre_name")
    speed = meta.get("target_speed_kmh") or summary.get("speed_kmh")
    payload = summary.get("payload_kg") or meta.get("payload_kg")
    text = " - ".join(str(v) for v in (vehicle, manoeuvre) if v) or "run"
    if speed:
        text += f" at {float(speed):g} km/h"
    if payload:
        text += f" (payload {float(payload):g} kg)"
    return plain(text)


def judged_window(channels: dict) -> tuple[float, float] | None:
    """The judged window (entry to exit gate), from the ``judged`` channel.

    Parameters
    ----------
    channels : dict of str to array_like
        The run's channels (``time_s`` [s]).

    Returns
    -------
    tuple of float or None
        ``(t_start, t_end)`` [s]; None when the run has no judged samples.
    """
    if "judged" not in channels:
        return None
    inside = np.nonzero(np.asarray(channels["judged"], dtype=float) > 0.5)[0]
    if not inside.size:
        return None
    t = np.asarray(channels["time_s"], dtype=float)
    return float(t[inside[0]]), float(t[inside[-1]])

def lift_spans(time_s, fz_N) -> list[tuple[float, float]]:
    """The spans of time ``(t_start, t_end)`` [s] in which a wheel's vertical load is zero or less (lifted).

    Parameters
    ----------
    time_s : array_like
        Times [s].
    fz_N : array_like
        Vertical load of one wheel [N].

    Returns
    -------
    list of tuple of float
        ``(t_start, t_end)`` [s] per span.
    """
    t = np.asarray(time_s, dtype=float)
    off = np.asarray(fz_N, dtype=float) <= 0.0
    if not off.any():
        return []
    edges = np.diff(np.concatenate(([0], off.astype(int), [0])))
    starts, ends = np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0] - 1
    return [(float(t[a]), float(t[b])) for a, b in zip(starts, ends, strict=True)]
