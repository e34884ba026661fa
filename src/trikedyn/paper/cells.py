"""How a report's tables read: a column's name as a human header with its unit (:func:`column_header`), a
cell's value as text (:func:`format_value`), a verdict's badge (:func:`verdict_class`), and a table (a CSV
file or a DataFrame) as the rows of (text, numeric) cells the templates of :mod:`trikedyn.paper.html` show.
"""

from __future__ import annotations

import math
import numbers
import re
from pathlib import Path
from typing import Any

import pandas as pd

from ..errors import InputError

__all__ = ["column_header", "format_value", "verdict_class"]


_LABELS = {
    "suspension": "Suspension",
    "vehicle": "Vehicle",
    "manoeuvre": "Manoeuvre",
    "natural_frequency_hz": "Natural frequency f<sub>n</sub> [Hz]",
    "damping_ratio": "Damping ratio ξ [–]",
    "damping_table1_Ns_per_m": "C, Table 1 [N s/m]",
    "sprung_mass_eq3_kg": "M<sub>s</sub> by Eq. 3 [kg]",
    "damping_eq4_Ns_per_m": "C by Eq. 4 [N s/m]",
    "ratio_eq4_to_table1": "Eq. 4 / Table 1 [–]",
    "sprung_mass_kg": "Sprung mass [kg]",
    "body_mode_frequency_hz": "Body mode [Hz]",
    "body_mode_damping_ratio": "Body mode ξ [–]",
    "identified_frequency_hz": "Identified f<sub>n</sub> [Hz]",
    "identified_damping_ratio": "Identified ξ [–]",
    "model_stiffness_N_per_m": "Model K [N/m]",
    "identified_stiffness_N_per_m": "Identified K [N/m]",
    "stiffness_error_pct": "K error [%]",
    "model_damping_Ns_per_m": "Model C [N s/m]",
    "identified_damping_Ns_per_m": "Identified C [N s/m]",
    "damping_error_pct": "C error [%]",
    "cycles_used": "Cycles used",
    "freight_kg": "Freight [kg]",
    "paper_x_mm": "x, paper [mm]",
    "paper_y_mm": "y, paper [mm]",
    "paper_z_mm": "z, paper [mm]",
    "x_mm": "x, ours [mm]",
    "y_mm": "y, ours [mm]",
    "z_mm": "z, ours [mm]",
    "max_abs_error_mm": "Largest error [mm]",
    "stiffness_scale": "Stiffness [% of Table 1]",
    "damping_scale": "Damping [% of Table 1]",
    "threshold_speed_kmh": "Threshold speed [km/h]",
    "limit": "Limit",
    "limiting_wheel": "Limiting wheel",
    "min_speed_kmh": "Lowest speed [km/h]",
    "max_speed_kmh": "Highest speed [km/h]",
    "max_lateral_acceleration_mps2": "Peak lateral acceleration [m/s²]",
    "max_path_error_m": "Largest path error [m]",
    "max_abs_ri": "Peak |RI| [–]",
    "cone_strikes": "Cones struck",
    "wheel_lifted": "Wheel lifted",
}
_UNITS = (  # name endings and their units, the longest first
    ("_Ns_per_m", "N s/m"), ("_N_per_m", "N/m"), ("_mps2", "m/s²"), ("_radps", "rad/s"), ("_degps", "deg/s"),
    ("_kmh", "km/h"), ("_mps", "m/s"), ("_pct", "%"), ("_deg", "deg"), ("_rad", "rad"), ("_kg", "kg"),
    ("_mm", "mm"), ("_hz", "Hz"), ("_Nm", "N m"), ("_m", "m"), ("_s", "s"), ("_N", "N"),
)
_PERCENT_COLUMNS = {"stiffness_scale", "damping_scale"}


def column_header(name: str) -> str:
    """A table column's header: a human label with its unit in brackets.

    Parameters
    ----------
    name : str
        A column name such as ``threshold_speed_kmh``.

    Returns
    -------
    str
        A known column's label (``"Threshold speed [km/h]"``), else the name in words with the unit its
        ending names (``max_roll_deg`` -> ``"Max roll [deg]"``). May hold ``<sub>`` markup (for ``f_n``
        and ``M_s``); nothing else of it is markup (the templates mark it safe).
    """
    name = str(name)
    if name in _LABELS:
        return _LABELS[name]
    words, unit = name, ""
    for ending, symbol in _UNITS:
        if name.endswith(ending) and len(name) > len(ending):
            words, unit = name[: -len(ending)], symbol
            break
    text = re.sub(r"[_\s]+", " ", words).strip()
    text = (text[:1].upper() + text[1:]) if text else name
    text = text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return f"{text} [{unit}]" if unit else text


def format_value(value: Any) -> str:
    """Format one table cell for display.

    Parameters
    ----------
    value : object
        A cell: a number, a string, None or a missing value.

    Returns
    -------
    str
        Integers as they are; whole floats without decimals; floats of magnitude 1e-3 to 1e6 with
        four significant digits (one decimal from 1000 on); others in scientific notation; NaN and None
        as an empty cell; infinities as ``inf``/``-inf``. Anything else is ``str(value)``. Not escaped.
    """
    if value is None or value is pd.NA or value is pd.NaT:
        return ""
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        x = float(value)
        if math.isnan(x):
            return ""
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        if x == 0:
            return "0"
        mag = abs(x)
        if x.is_integer() and mag < 1e12:
            return str(int(x))
        if mag >= 1e6 or mag < 1e-3:
            return f"{x:.3e}"
        if mag >= 1000:
            return f"{x:.1f}"
        return f"{x:.4g}"
    return str(value)


def _is_number(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def verdict_class(verdict: str) -> str:
    """The CSS class of a verdict's badge.

    Parameters
    ----------
    verdict : str
        A statement's verdict.

    Returns
    -------
    str
        ``"ok"`` for exactly "reproduces"; ``"qualified"`` for "reproduces, ..." or "partly ...";
        ``"bad"`` for a verdict starting with "contradicts"; ``"other"`` otherwise.
    """
    v = " ".join(verdict.lower().split())
    if v == "reproduces":
        return "ok"
    if v.startswith("contradicts"):
        return "bad"
    if v.startswith(("reproduces", "partly", "partially")):
        return "qualified"
    return "other"


def _load_table(source: Any, where: str) -> pd.DataFrame:
    """A DataFrame from a DataFrame or the path of a CSV file."""
    if isinstance(source, pd.DataFrame):
        return source
    if isinstance(source, str | Path):
        path = Path(source)
        if not path.is_file():
            raise InputError(f"table file not found: {path}", where)
        try:
            return pd.read_csv(path)
        except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
            raise InputError(f"cannot read table {path}: {exc}", where) from exc
    raise InputError(f"a table is a CSV path or a pandas DataFrame, not {type(source).__name__}", where)


def _table(source: Any, caption: str, where: str) -> dict:
    """What the table template needs: headers, rows of (text, numeric) cells, caption."""
    table = _load_table(source, where)
    frame = table if isinstance(table.index, pd.RangeIndex) else table.reset_index()
    numeric = [pd.api.types.is_numeric_dtype(frame[c]) and not pd.api.types.is_bool_dtype(frame[c])
               for c in frame.columns]
    percent = [str(c) in _PERCENT_COLUMNS and num for c, num in zip(frame.columns, numeric, strict=True)]
    rows = []
    for record in frame.itertuples(index=False, name=None):
        rows.append([(format_value(100 * v if pct and _is_number(v) else v), _is_number(v))
                     for v, pct in zip(record, percent, strict=True)])
    return {"headers": [(column_header(c), num) for c, num in zip(frame.columns, numeric, strict=True)],
            "rows": rows, "caption": caption}
