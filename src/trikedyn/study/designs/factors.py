"""Which of a vehicle's values a sensitivity study varies, and over what range (the factors).

See :mod:`trikedyn.study.designs.sensitivity`, step 1. A factor's range is the one its vehicle file declares next to
the value (``[ranges.mass] cg_x_m = [0.70, 0.95]``, or ``{ rel = 0.1 }``; see
:mod:`trikedyn.params.schema` and :func:`declared_ranges`), else ``value * (1 -/+ fraction)`` with the stated
default :data:`DEFAULT_FRACTION` (``--fraction``); each factor says which (``range_from``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace

from ...errors import InputError, did_you_mean
from ...params.io import ParameterSet
from .vehicle_values import (  # noqa: F401  (numeric_parameters, declared_ranges: re-exported)
    PAIR_SEPARATOR,
    _declared_range,
    _knob_value,
    _knobs,
    _leaves,
    _note,
    _pairs,
    declared_ranges,
    numeric_parameters,
)

__all__ = ["DEFAULT_FRACTION", "EXCLUDED_GROUPS", "Factor", "apply_factors", "candidate_factors", "declared_ranges",
           "numeric_parameters", "problem", "select_factors"]

DEFAULT_FRACTION = 0.2
"""Each factor varies over ``value * (1 -/+ fraction)`` unless its vehicle file declares a range (its
``[ranges]`` tables: :func:`declared_ranges`); ``--fraction`` changes it."""


EXCLUDED_GROUPS = {
    "sensor": "where the IMU sits: a measurement, not the vehicle's dynamics",
    "freight": "the site of the paper's freight: no effect without freight aboard",
    "components": ("a part of the body mass: the vehicle's mass, CG and inertia are [mass]'s, so its declared "
                   "place and mass do not act (moving it is a design change: --parameter component.NAME.z_m ...)"),
    "payload": "a load item, not an assumption of the vehicle",
}
"""Top-level groups whose values never enter the default factor list, with the reason."""


@dataclass(frozen=True)
class Factor:
    """One input of the sensitivity analysis.

    Attributes
    ----------
    name : str
        The dotted parameter path (``mass.roll_inertia_kgm2``), a design knob (``track_m``, ``wheelbase_m``,
        ``component.battery.z_m``: :mod:`trikedyn.params.knobs`), or ``wheels.LEFT+RIGHT.ATTR`` for a value
        both wheels of a pair share (set on both at once).
    value : float
        Reference value, in the parameter's unit (the suffix of its name: ``_m``, ``_kg``, ...).
    low, high : float
        The range sampled, same unit.
    paths : tuple of str
        The dotted paths or knob the factor sets (:func:`~trikedyn.params.ops.override` reads both).
    kind : {"value", "track"}
        ``"value"``: every path takes the factor's value. ``"track"`` (only without the knobs module): ``paths``
        are the left and right wheels' ``y_m`` [m], set to ``centre +/- value / 2``.
    centre : float
        The pair's centre line [m] (``"track"`` only).
    note : str
        Why the value is what it is (the vehicle file's ``assumed`` or ``source`` note).
    range_from : str
        ``"fraction"`` (no range declared: ``value * (1 -/+ fraction)``), ``"declared"`` (the vehicle file's
        ``[ranges]``, :func:`declared_ranges`) or ``"narrowed"``
        (a fraction narrowed so that every combination is a valid vehicle: the principal inertias).
    covers : tuple of str
        The vehicle file's values it varies (for a knob: those it moves, e.g. both wheels' ``y_m``).
    """

    name: str
    value: float
    low: float
    high: float
    paths: tuple[str, ...]
    kind: str = "value"
    centre: float = 0.0
    note: str = ""
    range_from: str = "fraction"
    covers: tuple[str, ...] = ()

    def overrides(self, x: float) -> dict[str, float]:
        """The dotted paths and values [parameter units] that put this factor at ``x``.

        Parameters
        ----------
        x : float
            The factor's value [parameter unit].

        Returns
        -------
        dict of str to float
            Dotted path -> value.
        """
        x = float(x)
        if self.kind == "track":
            left, right = self.paths
            return {left: self.centre + 0.5 * x, right: self.centre - 0.5 * x}
        return dict.fromkeys(self.paths, x)

    def to_dict(self) -> dict:
        """The factor as JSON-ready values.

        Returns
        -------
        dict
            Parameter, value, bounds (parameter units), paths set, covers, where the range came from, note.
        """
        return {"parameter": self.name, "value": self.value, "low": self.low, "high": self.high,
                "sets": list(self.paths), "covers": list(self.covers), "range_from": self.range_from,
                "note": self.note}


def _check_fraction(fraction: float) -> float:
    if not (isinstance(fraction, int | float) and math.isfinite(fraction) and 0.0 < fraction < 1.0):
        raise InputError(f"expected a fraction between 0 and 1 (0.2 = +/-20 %), got {fraction!r}", where="--fraction")
    return float(fraction)


def _make(pset, name, value, paths, fraction, kind="value", centre=0.0, note_path=None, covers=None,
          ranges=None) -> Factor:
    declared = _declared_range(pset, name, value, (*paths, *([note_path] if note_path else [])), ranges)
    if declared is not None:
        low, high, origin = *declared, "declared"
    else:
        low, high = sorted((value * (1.0 - fraction), value * (1.0 + fraction)))
        origin = "fraction"
    covers = tuple(covers) if covers is not None else (note_path,) if note_path else tuple(paths)
    return Factor(name, float(value), float(low), float(high), tuple(paths), kind, float(centre),
                  _note(pset, note_path or paths[0]), origin, covers)


def _all_factors(pset: ParameterSet, fraction: float) -> tuple[dict[str, Factor], dict[str, str], dict[str, str]]:
    """Every factor a name may ask for; the names refused with the reason (zero values, a wheel of a pair
    moved alone, a component's declared place changed without its knob); and each paired wheel's path with
    the pair factor that varies it."""
    knobs = _knobs()
    values = numeric_parameters(pset)
    factors: dict[str, Factor] = {}
    refused: dict[str, str] = {}
    paired: dict[str, str] = {}  # a paired wheel's path -> the pair factor that varies it

    declared = declared_ranges(pset)

    def add(name, value, paths, note_path=None, **kw):
        """Add the factor ``name`` (value ``value``, varying ``paths``), or refuse it when it is 0 and no range is
        declared."""
        keys = (*paths, *([note_path] if note_path else []))
        if value == 0.0 and _declared_range(pset, name, value, keys, declared) is None:
            refused[name] = (f"'{name}' is 0: a relative range is empty (declare one in the vehicle file: "
                             f"[ranges] \"{name}\" = [low, high])")
        else:
            factors[name] = _make(pset, name, value, paths, fraction, note_path=note_path, ranges=declared, **kw)

    for left, right in _pairs(pset):
        pair = f"wheels.{left}{PAIR_SEPARATOR}{right}"
        ys = (f"wheels.{left}.y_m", f"wheels.{right}.y_m")
        yl, yr = values[ys[0]], values[ys[1]]
        if knobs is not None:  # the design knob: both wheels symmetrically (and the body width with a wider track)
            add("track_m", yl - yr, ("track_m",), note_path=ys[0], covers=ys)
        else:
            add("track_m", yl - yr, ys, kind="track", centre=0.5 * (yl + yr))
        for path in ys:
            paired[path] = "track_m"
            refused[path] = (knobs.inconsistent_override(pset, path) if knobs is not None else None) or (
                f"'{path}' moves one wheel of the pair {left}/{right} alone (a lopsided vehicle); vary 'track_m' "
                "(both wheels, symmetrically)")
        prefix = f"wheels.{left}."
        for path, value in values.items():
            if not path.startswith(prefix) or path.endswith((".x_m", ".y_m")):
                continue
            attr = path[len(prefix):]
            other = f"wheels.{right}.{attr}"
            if values.get(other) == value:
                name = f"{pair}.{attr}"
                add(name, value, (path, other))
                paired[path] = paired[other] = name
    if knobs is not None:
        for name in knobs.knob_names(pset):
            known = _knob_value(pset, name)
            if name in factors or name in refused or name in values or known is None:
                continue
            add(name, known[0], (name,), note_path=known[1])
    for path, value in values.items():
        if path in refused or path in factors:
            continue
        why = knobs.inconsistent_override(pset, path) if knobs is not None else None
        if why:
            refused[path] = why
            continue
        add(path, value, (path,))
    return factors, refused, paired


INERTIAS = ("mass.roll_inertia_kgm2", "mass.pitch_inertia_kgm2", "mass.yaw_inertia_kgm2")


def _narrow_inertias(pset: ParameterSet, factors: list[Factor], fraction: float) -> list[Factor]:
    """The factors, the principal inertias' ranges narrowed (all by the same fraction) so that every
    combination in the box is a rigid body: each inertia at most the sum of the other two (the schema refuses
    the rest). Varied alone by +/-20 %, the reference trike's inertias (118, 373, 421 kg m^2) break it in a
    quarter of the Morris samples; together they may vary by +/-7.6 %."""
    m = pset.params.mass
    v = [m.roll_inertia_kgm2, m.pitch_inertia_kgm2, m.yaw_inertia_kgm2]
    varied = {f.name: f for f in factors if f.name in INERTIAS and f.range_from == "fraction"}
    d = [1.0 if name in varied else 0.0 for name in INERTIAS]
    limit = fraction
    for c in range(3):
        a, b = (i for i in range(3) if i != c)
        weight = v[a] * d[a] + v[b] * d[b] + v[c] * d[c]
        if weight > 0:
            limit = min(limit, 0.999 * (v[a] + v[b] - v[c]) / weight)
    if limit >= fraction or limit <= 0:
        return factors
    out = []
    for f in factors:
        if f.name in varied:
            low, high = sorted((f.value * (1 - limit), f.value * (1 + limit)))
            note = (f"{f.note}; range narrowed to +/-{limit:.1%} so that every combination of the principal "
                    "inertias is a rigid body (each at most the sum of the other two)")
            f = replace(f, low=low, high=high, note=note, range_from="narrowed")
        out.append(f)
    return out


def candidate_factors(pset: ParameterSet, fraction: float = DEFAULT_FRACTION) -> tuple[list[Factor], dict[str, str]]:
    """The default factors: the vehicle's assumed numbers that can vary on their own and act on its dynamics.

    Left out, with the reason: values that are not numbers (names, flags); measured values (a ``source``
    note; name them with :func:`select_factors` to include them); zero values (a relative range is empty:
    ``roll_yaw_product_kgm2 = 0``, the rear wheels' ``x_m = 0`` that fixes the origin); one wheel of a
    mirrored pair moved alone (its ``y_m``: the knob ``track_m`` moves both); the groups of
    :data:`EXCLUDED_GROUPS` (sensor and freight sites, the components, which are part of ``[mass]`` and
    act only when a design knob moves them); ``steering.ackermann_fraction`` on a vehicle with fewer than
    two steered wheels (it acts on a steered pair only). The principal inertias' ranges are narrowed so that
    every combination is a rigid body (:func:`_narrow_inertias`).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle, with its notes.
    fraction : float
        Each factor varies over ``value * (1 -/+ fraction)`` [-] unless a range is declared.

    Returns
    -------
    factors : list of Factor
        In the vehicle file's order, a pair's factors where its first value would be.
    excluded : dict
        Assumed value's dotted path -> why it is not a factor.
    """
    fraction = _check_fraction(fraction)
    every, refused, paired = _all_factors(pset, fraction)
    assumed = [path for path, note in pset.notes.items() if "assumed" in note]
    values = numeric_parameters(pset)
    steered = sum(bool(w.steered) for w in pset.params.wheels)
    factors: list[Factor] = []
    excluded: dict[str, str] = {}
    for path in assumed:
        group = path.split(".", 1)[0]
        if path not in values:
            excluded[path] = "not a number"
        elif group in EXCLUDED_GROUPS:
            excluded[path] = EXCLUDED_GROUPS[group]
        elif path == "steering.ackermann_fraction" and steered < 2:
            excluded[path] = "acts on a pair of steered wheels only; this vehicle has none"
        elif path in refused and path not in paired:
            excluded[path] = refused[path]
        else:
            name = paired.get(path, path)
            if all(f.name != name for f in factors):
                factors.append(every[name])
    return _narrow_inertias(pset, factors, fraction), excluded


def select_factors(pset: ParameterSet, names: Iterable[str], fraction: float = DEFAULT_FRACTION) -> list[Factor]:
    """The factors named (measured values too), in the order given, each once.

    Names may be separated by commas. A name is a dotted path of a numeric parameter (``mass.cg_z_m``,
    ``wheels.front.x_m``, ``steering.trail_m``), a design knob (``track_m``, ``wheelbase_m``,
    ``cg_height_m``, ``cg_x_fraction``, ``component.NAME.x_m|y_m|z_m|mass_kg``) or a value shared by a pair
    of wheels (``wheels.rear_left+rear_right.radius_m``).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    names : iterable of str
        The factor names.
    fraction : float
        Default relative range, dimensionless.

    Returns
    -------
    list of Factor
        The factors.

    Raises
    ------
    InputError
        ``where="--parameter"``: an unknown name (with the closest known one), a value that is not a number,
        a zero value, one wheel of a pair moved alone, a component's declared place without its knob.
    """
    fraction = _check_fraction(fraction)
    every, refused, _ = _all_factors(pset, fraction)
    all_paths = {path for path, _ in _leaves(pset.params.model_dump(exclude={"ranges"}))}
    chosen: list[Factor] = []
    for raw in names:
        for name in (n.strip() for n in str(raw).split(",")):
            if not name:
                continue
            if name in refused:
                raise InputError(refused[name], where="--parameter")
            if name not in every:
                if name in all_paths:
                    raise InputError(f"'{name}' is not a number; it cannot be varied", where="--parameter")
                tip = did_you_mean(name, [*every, *refused]) or " (see `trikedyn vehicle show`)"
                raise InputError(f"unknown parameter '{name}'{tip}", where="--parameter")
            if all(f.name != name for f in chosen):
                chosen.append(every[name])
    if not chosen:
        raise InputError("no parameter named", where="--parameter")
    return _narrow_inertias(pset, chosen, fraction)


def apply_factors(pset: ParameterSet, factors: Iterable[Factor], x) -> ParameterSet:
    """The vehicle with each factor at its value in ``x`` (a new, validated set).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    factors : iterable of Factor
        The factors.
    x : sequence of float
        Their values [parameter units].

    Returns
    -------
    ParameterSet
        The new set.

    Raises
    ------
    ParameterError
        The values give an invalid vehicle.
    """
    from ...params.ops import override

    values: dict[str, float] = {}
    for factor, value in zip(factors, x, strict=True):
        values.update(factor.overrides(value))
    return override(pset, values)


# ------------------------------------------------------------------------------------------------
# sampling and analysis (SALib)
# ------------------------------------------------------------------------------------------------
def problem(factors: Iterable[Factor]) -> dict:
    """The SALib problem: the factors' names and ``[low, high]`` bounds.

    Parameters
    ----------
    factors : iterable of Factor
        The factors.

    Returns
    -------
    dict
        ``num_vars``, ``names``, ``bounds``.
    """
    factors = list(factors)
    return {"num_vars": len(factors), "names": [f.name for f in factors], "bounds": [[f.low, f.high] for f in factors]}
