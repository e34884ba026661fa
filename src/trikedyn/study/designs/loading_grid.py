"""The grid of a loading chart (:mod:`trikedyn.study.designs.loading`) and its cells: freight masses [kg] x
fore-aft positions x [m] x heights z [m] of the freight site (:func:`default_grid`, :func:`grid_cells`), one cell
evaluated (:func:`evaluate_cell`, in a worker) and its safe speed (:func:`safe_speed`), and the CSV the cells are
appended to as they finish (:class:`CellLog`: what a resumed chart reads back).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ...errors import InputError, ParameterError
from ...params.io import ParameterSet
from .csv_log import AppendedCsv
from .search import Search

__all__ = ["DEFAULT_MARGIN_KMH", "DEFAULT_MASSES_KG", "DEFAULT_X_OFFSETS_M", "DEFAULT_Z_OFFSETS_M", "MAX_CELLS",
           "CellLog", "default_grid", "evaluate_cell", "grid_cells", "safe_speed"]

DEFAULT_MASSES_KG = (0.0, 50.0, 100.0, 150.0, 200.0)
DEFAULT_X_OFFSETS_M = (-0.2, 0.0, 0.2)
"""Fore-aft positions of the default grid, from the vehicle's freight site [m]."""
DEFAULT_Z_OFFSETS_M = (0.0, 0.2, 0.4)
"""Heights of the default grid, above the vehicle's freight site (a trunk) [m]."""
MAX_CELLS = 5000


def default_grid(pset: ParameterSet) -> tuple[list[float], list[float], list[float]]:
    """Masses [kg], x [m] and z [m] of the default grid (45 cells) around the vehicle's freight site.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.

    Returns
    -------
    masses : list of float
        [kg].
    x : list of float
        [m].
    z : list of float
        [m].
    """
    site = pset.params.freight
    return (list(DEFAULT_MASSES_KG), [round(site.x_m + d, 9) for d in DEFAULT_X_OFFSETS_M],
            [round(site.z_m + d, 9) for d in DEFAULT_Z_OFFSETS_M])


def grid_cells(pset: ParameterSet, masses_kg: Sequence[float] | None = None, x_m: Sequence[float] | None = None,
               z_m: Sequence[float] | None = None) -> tuple[list[float], list[float], list[float]]:
    """The chart's grid: masses [kg], x [m] and z [m], each as given (None: :func:`default_grid`'s) with
    repeats dropped; the cells run in the order ``z``, mass, ``x`` (:meth:`LoadingChart.keys`).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    masses_kg : sequence of float, optional
        Freight masses [kg].
    x_m : sequence of float, optional
        Fore-aft positions [m].
    z_m : sequence of float, optional
        Heights [m].

    Returns
    -------
    masses : list of float
        [kg].
    x : list of float
        [m].
    z : list of float
        [m].

    Raises
    ------
    InputError
        A value that is not finite, a negative mass, or more than :data:`MAX_CELLS` cells.
    """
    masses, xs, zs = default_grid(pset)
    masses = list(dict.fromkeys(float(v) for v in (masses if masses_kg is None else masses_kg)))
    xs = list(dict.fromkeys(float(v) for v in (xs if x_m is None else x_m)))
    zs = list(dict.fromkeys(float(v) for v in (zs if z_m is None else z_m)))
    for name, values in (("masses", masses), ("x", xs), ("z", zs)):
        if not values or not all(math.isfinite(v) for v in values):
            raise InputError("needs finite numbers", where=f"--{name}")
    if any(m < 0 for m in masses):
        raise InputError("freight masses must be >= 0 kg", where="--masses")
    if len(masses) * len(xs) * len(zs) > MAX_CELLS:
        raise InputError(f"{len(masses) * len(xs) * len(zs)} cells; at most {MAX_CELLS}", where="grid")
    return masses, xs, zs


class CellLog(AppendedCsv):
    """The cells of a chart as a CSV file, one row appended (and flushed) as each cell finishes.

    Columns: ``cell`` (its index in :meth:`LoadingChart.keys` order), ``freight_kg`` [kg], ``status`` (``ok``
    or ``failed``), ``threshold_speed_kmh`` [km/h], ``x_m`` and ``z_m`` [m] (the freight's position) and
    ``error`` (with another ``metric``, its value's column is named by it:
    :func:`~trikedyn.study.designs.named.column`).
    """

    COLUMNS = ["cell", "freight_kg", "status", "threshold_speed_kmh", "x_m", "z_m", "error"]

    def __init__(self, path, metric: str = "threshold"):
        from .named import column

        super().__init__(path, [column(c, metric) if c == "threshold_speed_kmh" else c for c in self.COLUMNS],
                         self.COLUMNS)

    def read(self, keys: list[tuple[float, float, float]]) -> dict:
        """The cells logged already: ``(mass, x, z)`` -> ``(threshold [km/h] or None, error or None)``.

        A row cut short by a kill is skipped (run again).

        Parameters
        ----------
        keys : list of tuple of float
            The chart's cells (mass [kg], x [m], z [m]).

        Returns
        -------
        dict
            ``(mass [kg], x [m], z [m])`` -> ``(threshold [km/h] or None, error or None)``.

        Raises
        ------
        InputError
            The file's columns, or a row's cell, are not this chart's.
        """
        known = {}
        for row in self.logged_rows("use another --out or --force (another grid?)"):
            try:
                i, key = int(row[0]), (float(row[1]), float(row[4]), float(row[5]))
                value = float(row[3]) if row[2] == "ok" else None
            except ValueError:
                continue
            if not 0 <= i < len(keys) or keys[i] != key:
                raise InputError(f"cell {i} is not this chart's (another grid?); use another --out or --force",
                                 where=str(self.path))
            known[key] = (value, row[6] or None)
        return known

    def append(self, index: int, key: tuple[float, float, float], threshold: float | None,
               error: str | None) -> None:
        """Log one finished cell (flushed at once).

        Parameters
        ----------
        index : int
            The cell's place.
        key : tuple of float
            (mass [kg], x [m], z [m]).
        threshold : float or None
            Threshold [km/h].
        error : str or None
            Why it has none.
        """
        mass, x, z = key
        self.write([index, repr(mass), "ok" if threshold is not None else "failed",
                    "" if threshold is None else repr(float(threshold)), repr(x), repr(z), error or ""])


DEFAULT_MARGIN_KMH = 5.0


def safe_speed(threshold_kmh: float | None, margin_kmh: float | None = DEFAULT_MARGIN_KMH,
               margin_fraction: float | None = None) -> float | None:
    """The threshold [km/h] less the margin (``margin_kmh`` or a fraction of it), floored at 0.

    Parameters
    ----------
    threshold_kmh : float or None
        Threshold [km/h].
    margin_kmh : float, optional
        Margin [km/h].
    margin_fraction : float, optional
        Margin as a fraction, dimensionless.

    Returns
    -------
    float or None
        Speed [km/h].
    """
    if threshold_kmh is None:
        return None
    if margin_fraction is not None:
        return round(max(threshold_kmh * (1.0 - margin_fraction), 0.0), 6)
    return round(max(threshold_kmh - (margin_kmh or 0.0), 0.0), 6)


def evaluate_cell(pset: ParameterSet, mass_kg: float, x_m: float, z_m: float,
                  search: Search) -> tuple[float | None, str | None]:
    """The threshold velocity [km/h] with ``mass_kg`` of freight at ``(x_m, z_m)``, or None and why not.

    Runs in a worker process; an invalid vehicle or a failed search is a null cell, not an error.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    mass_kg : float
        Freight mass [kg].
    x_m, z_m : float
        Freight position [m].
    search : Search
        The threshold search (manoeuvre, options, speed range [km/h], criterion).

    Returns
    -------
    threshold : float or None
        [km/h].
    error : str or None
        Why there is none.
    """
    from ...params.knobs import apply_knobs
    from ...params.ops import with_freight
    try:
        vehicle = with_freight(apply_knobs(pset, {"freight.x_m": x_m, "freight.z_m": z_m}), mass_kg)
    except ParameterError as exc:
        return None, f"invalid vehicle: {' '.join(str(exc).split())}"
    return search.threshold(vehicle)
