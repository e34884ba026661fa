"""Design knobs: named changes of a vehicle that keep it consistent.

A parameter path (``wheels.rear_left.y_m``) sets one value of the file; a *knob* changes the vehicle as a
designer would, moving whatever has to move with it. :func:`apply_knobs` applies knobs to a
:class:`~trikedyn.params.parameter_set.ParameterSet` and returns a new, validated one;
:func:`~trikedyn.params.ops.override` and a study's ``overrides`` accept knob names next to parameter paths.

========================  ======  ===================================================================
knob                      unit    what moves
========================  ======  ===================================================================
``wheelbase_m``           m       the steered (front) wheel(s) along x, so that the wheelbase is the value
``track_m``               m       both wheels of the pair, symmetrically about their mid-point
``cg_x_fraction``         1       the vehicle's CG along x, to this fraction of the wheelbase from the rear
``cg_height_m``           m       the vehicle's CG height
``component.NAME.x_m``    m       a component of ``[[components]]`` (also ``y_m``, ``z_m``)
``component.NAME.mass_kg``  kg    a component's mass (the vehicle's mass changes with it)
``freight.x_m``           m       the freight site (also ``y_m``, ``z_m``)
========================  ======  ===================================================================

What each keeps (choices, stated):

* ``wheelbase_m`` keeps the CG, the components, the sensor and the freight site where they are on the body
  (their absolute x); give ``cg_x_fraction`` as well to put the CG at a fraction of the new wheelbase. The
  rear axle stays the origin. The body's ``overall_length_m`` grows with a longer wheelbase (the front
  overhang is kept) and stays as it is with a shorter one.
* ``track_m`` moves both wheels of the pair by the same amount in opposite directions, about the pair's
  mid-point (the centre line of a symmetric trike): mass, CG and inertia are unchanged. The body's
  ``overall_width_m`` (which sets the ISO 3888 lane widths) grows with a wider track (the wheels' overhang
  beyond the track is kept) and stays as it is with a narrower one.
* ``cg_x_fraction`` and ``cg_height_m`` move the CG of vehicle + driver; its mass and its inertia about the
  CG are unchanged; components stay where they are (the rest of the body takes the change).
* ``component.NAME.*`` moves or re-weighs a component of the body: its mass properties (a uniform box of
  its size, or a point) are taken off at the old place and put on at the new one (parallel-axis
  theorem), so the vehicle's CG moves by ``m dx / M`` and its inertia changes by the parallel-axis terms.
  A new mass changes ``curb_kg`` (and ``body_kg`` if given) by the difference.
* ``freight.*`` moves the site where :func:`~trikedyn.params.ops.with_freight` puts the freight (the
  loading chart's knobs); the vehicle without freight is unchanged.

Knobs are applied in the order of :data:`KNOBS` (geometry, then CG, then components, then freight),
whatever the order they are given in: ``{"wheelbase_m": 2.1, "cg_x_fraction": 0.45}`` puts the CG at
45 % of the new wheelbase. Each changed value gets a ``note`` in :attr:`ParameterSet.notes` naming the
knobs, so a vehicle file written afterwards says where its values came from.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace

import numpy as np

from ..errors import ParameterError, close_match, did_you_mean
from ..mechanics import Box, MassProperties
from .parameter_set import ParameterSet, revalidated
from .schema import VehicleParameters

__all__ = ["KNOBS", "Knob", "apply_knobs", "inconsistent_override", "is_knob", "knob_names", "knob_problem"]


@dataclass(frozen=True)
class Knob:
    """One design knob of :data:`KNOBS`.

    Attributes
    ----------
    function : callable
        ``function(data, value, target)``: changes ``data`` (a vehicle's ``model_dump()``) in place;
        ``target`` is the component's name for a ``component.NAME.*`` knob, else None.
    unit : str
        Unit of the value (``"m"``, ``"kg"``, ``"1"``).
    description : str
        What it moves, in a line.
    bounds : (float, float)
        Least and largest value accepted, inclusive (the schema's ranges may refuse more).
    """

    function: Callable[[dict, float, str | None], None]
    unit: str
    description: str
    bounds: tuple[float, float]


# ------------------------------------------------------------------------------------------------
# the knobs (each changes a model_dump() of VehicleParameters in place)
# ------------------------------------------------------------------------------------------------
def _axle_x(data: dict) -> tuple[list[dict], float, float]:
    """The steered wheels, the mean x of the steered wheels and that of the others [m]."""
    steered = [w for w in data["wheels"] if w["steered"]]
    fixed = [w for w in data["wheels"] if not w["steered"]]
    return steered, sum(w["x_m"] for w in steered) / len(steered), sum(w["x_m"] for w in fixed) / len(fixed)


def _wheelbase(data: dict, value: float, _target) -> None:
    steered, front, rear = _axle_x(data)
    for w in steered:  # each keeps its offset from the axle's mean (zero on a square axle)
        w["x_m"] = rear + value + (w["x_m"] - front)
    body = data["body"]
    body["overall_length_m"] = max(body["overall_length_m"], body["overall_length_m"] + value - (front - rear))


def _track(data: dict, value: float, _target) -> None:
    pair = [w for w in data["wheels"] if w["steered"] == (data["layout"] == "tadpole")]
    old = abs(pair[0]["y_m"] - pair[1]["y_m"])
    mid = (pair[0]["y_m"] + pair[1]["y_m"]) / 2
    for w in pair:
        w["y_m"] = mid + (value / 2 if w["y_m"] > mid else -value / 2)
    body = data["body"]
    body["overall_width_m"] = max(body["overall_width_m"], body["overall_width_m"] + value - old)


def _cg_x_fraction(data: dict, value: float, _target) -> None:
    _, front, rear = _axle_x(data)
    data["mass"]["cg_x_m"] = rear + value * (front - rear)


def _cg_height(data: dict, value: float, _target) -> None:
    data["mass"]["cg_z_m"] = value


def _whole(mass: dict) -> MassProperties:
    """Vehicle + driver (``[mass]``) as MassProperties."""
    ixy, ixz, iyz = mass["roll_pitch_product_kgm2"], mass["roll_yaw_product_kgm2"], mass["pitch_yaw_product_kgm2"]
    inertia = [[mass["roll_inertia_kgm2"], -ixy, -ixz],
               [-ixy, mass["pitch_inertia_kgm2"], -iyz],
               [-ixz, -iyz, mass["yaw_inertia_kgm2"]]]
    return MassProperties(mass["curb_kg"] + mass["driver_kg"], (mass["cg_x_m"], mass["cg_y_m"], mass["cg_z_m"]),
                          np.array(inertia, dtype=float))


def _part(component: dict) -> MassProperties:
    """A component as a uniform box (a point if it has no size)."""
    c = component
    return Box(c["mass_kg"], (c["x_m"], c["y_m"], c["z_m"]), (c["length_m"], c["width_m"], c["height_m"]),
               c["name"]).mass_properties()


def _component(field: str) -> Callable[[dict, float, str | None], None]:
    def move(data: dict, value: float, target: str | None) -> None:
        """Set component ``target``'s ``field`` to ``value``; the vehicle's mass [kg], CG [m] and inertia [kg m^2]
        follow."""
        component = next(c for c in data["components"] if c["name"] == target)
        old = _part(component)
        component[field] = value
        new = _part(component)
        mass = data["mass"]
        whole = _whole(mass)
        rest = whole - old if old.mass_kg > 0 else whole
        moved = rest + new if new.mass_kg > 0 else rest
        dm = new.mass_kg - old.mass_kg
        if dm:
            mass["curb_kg"] += dm
            if mass["body_kg"] is not None:
                mass["body_kg"] += dm
        inertia = (moved.inertia_kgm2 + moved.inertia_kgm2.T) / 2
        mass.update(
            cg_x_m=float(moved.cg_m[0]), cg_y_m=float(moved.cg_m[1]), cg_z_m=float(moved.cg_m[2]),
            roll_inertia_kgm2=float(inertia[0, 0]), pitch_inertia_kgm2=float(inertia[1, 1]),
            yaw_inertia_kgm2=float(inertia[2, 2]), roll_pitch_product_kgm2=float(-inertia[0, 1]) + 0.0,  # + 0.0: no -0.0 in a file
            roll_yaw_product_kgm2=float(-inertia[0, 2]) + 0.0, pitch_yaw_product_kgm2=float(-inertia[1, 2]) + 0.0,
        )

    return move


def _freight(axis: str) -> Callable[[dict, float, str | None], None]:
    def move(data: dict, value: float, _target) -> None:
        """Set the freight site's ``axis`` coordinate to ``value`` [m]."""
        data["freight"][axis] = value

    return move


_COMPONENT_FIELDS = ("x_m", "y_m", "z_m", "mass_kg")
_PLACEHOLDER = "NAME"

KNOBS: dict[str, Knob] = {
    "wheelbase_m": Knob(_wheelbase, "m", "moves the steered (front) wheel(s) along x to this wheelbase; the CG, "
                        "components and freight site keep their place on the body", (0.5, 5.0)),
    "track_m": Knob(_track, "m", "moves both wheels of the pair symmetrically to this track; mass and CG "
                    "unchanged", (0.3, 3.0)),
    "cg_x_fraction": Knob(_cg_x_fraction, "1", "puts the CG of vehicle + driver at this fraction of the "
                          "wheelbase ahead of the rear axle; inertia about the CG unchanged", (0.0, 1.0)),
    "cg_height_m": Knob(_cg_height, "m", "puts the CG of vehicle + driver at this height; inertia about the CG "
                        "unchanged", (0.05, 3.0)),
    "component.NAME.x_m": Knob(_component("x_m"), "m", "moves a component along x (CG and inertia follow)",
                               (-5.0, 10.0)),
    "component.NAME.y_m": Knob(_component("y_m"), "m", "moves a component along y (CG and inertia follow)",
                               (-2.0, 2.0)),
    "component.NAME.z_m": Knob(_component("z_m"), "m", "moves a component along z (CG and inertia follow)",
                               (-1.0, 5.0)),
    "component.NAME.mass_kg": Knob(_component("mass_kg"), "kg", "re-weighs a component (the vehicle's mass, "
                                   "CG and inertia follow)", (0.0, 2000.0)),
    "freight.x_m": Knob(_freight("x_m"), "m", "moves the freight site along x", (-5.0, 10.0)),
    "freight.y_m": Knob(_freight("y_m"), "m", "moves the freight site along y", (-2.0, 2.0)),
    "freight.z_m": Knob(_freight("z_m"), "m", "moves the freight site along z", (-1.0, 5.0)),
}
"""Knob name -> :class:`Knob`, in the order they are applied. ``NAME`` stands for a component's name."""

_COMPONENT_KNOB = re.compile(r"^component\.([^.]*)\.([^.]*)$")


# ------------------------------------------------------------------------------------------------
# names
# ------------------------------------------------------------------------------------------------
def _params(vehicle) -> VehicleParameters:
    return vehicle.params if isinstance(vehicle, ParameterSet) else vehicle


def is_knob(name: str) -> bool:
    """Whether ``name`` is written as a knob (a registered name, or ``component.NAME.FIELD``), known or not
    to a given vehicle.

    Parameters
    ----------
    name : str
        A name.

    Returns
    -------
    bool
        Whether it is written as a knob.
    """
    return name in KNOBS and _PLACEHOLDER not in name or name.startswith("component.")


def knob_names(vehicle) -> list[str]:
    """Every knob of ``vehicle`` (a ParameterSet or VehicleParameters), its components' knobs spelled out.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleParameters
        The vehicle.

    Returns
    -------
    list of str
        The knob names.
    """
    params = _params(vehicle)
    names = [n for n in KNOBS if _PLACEHOLDER not in n]
    for c in params.components:
        names += [f"component.{c.name}.{f}" for f in _COMPONENT_FIELDS]
    return names


def _resolve(params: VehicleParameters, name: str) -> tuple[str, str | None] | str:
    """(registry key, component name) of a knob, or why there is no such knob (one line)."""
    if name in KNOBS and _PLACEHOLDER not in name:
        return name, None
    match = _COMPONENT_KNOB.match(name)
    if match:
        component, field = match.groups()
        names = [c.name for c in params.components]
        if field not in _COMPONENT_FIELDS:
            hint = close_match(field, _COMPONENT_FIELDS)
            tip = f"; did you mean 'component.{component}.{hint}'?" if hint is not None else ""
            return f"no design knob '{name}'{tip} (a component has {', '.join(_COMPONENT_FIELDS)})"
        if component not in names:
            if not names:
                return (f"no design knob '{name}': this vehicle lists no components "
                        "(add [[components]] to its file)")
            hint = close_match(component, names)
            tip = f"; did you mean 'component.{hint}.{field}'?" if hint is not None else ""
            return f"no component '{component}'{tip} (components: {', '.join(names)})"
        return f"component.{_PLACEHOLDER}.{field}", component
    return _unknown(params, name)


def _unknown(params: VehicleParameters, name: str) -> str:
    """An unknown knob (or, from :func:`~trikedyn.params.ops.override`, an unknown top-level parameter)."""
    tip = did_you_mean(name, knob_names(params) + list(VehicleParameters.model_fields))
    fixed = ", ".join(n for n in KNOBS if _PLACEHOLDER not in n and not n.startswith("freight."))
    return (f"no design knob or parameter '{name}'{tip} "
            f"(knobs: {fixed}, component.NAME.x_m|y_m|z_m|mass_kg, freight.x_m|y_m|z_m)")


def _value_problem(key: str, value) -> str | None:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return f"expected a number, got {value!r}"
    low, high = KNOBS[key].bounds
    unit = KNOBS[key].unit
    shown = "" if unit == "1" else f" {unit}"
    if not math.isfinite(value) or not low <= value <= high:
        return f"expected a value from {low:g} to {high:g}{shown}, got {value!r}"
    return None


def knob_problem(vehicle, name: str, values=()) -> str | None:
    """Why ``name`` with ``values`` is not a knob setting for ``vehicle`` (None if it is): an unknown knob
    (with a close match) or a value that is not a number within the knob's bounds. One line.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleParameters
        The vehicle.
    name : str
        The knob.
    values : iterable
        Its values [the knob's unit].

    Returns
    -------
    str or None
        The problem, one line.
    """
    params = _params(vehicle)
    resolved = _resolve(params, name)
    if isinstance(resolved, str):
        return resolved
    for value in values:
        problem = _value_problem(resolved[0], value)
        if problem:
            return f"{name}: {problem}"
    return None


def inconsistent_override(vehicle, dotted: str, together: Mapping | None = None) -> str | None:
    """Why a parameter path should not be varied on its own in a study (None if it may).

    A wheel of the pair moved alone builds a lopsided trike (``track_m`` moves both) or a skewed axle
    (``wheelbase_m``); a component's declared place or mass changed alone leaves the CG where it was
    (``component.NAME.FIELD`` moves the CG with it). :func:`~trikedyn.params.ops.override` itself sets
    such paths as written (an asymmetric vehicle is still a vehicle); a study spec refuses them.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleParameters
    dotted : str
        The parameter path.
    together : mapping, optional
        The other overrides of the same grid (path -> list of values). A wheel's ``x_m`` or ``y_m`` is
        allowed when the other wheel of the pair gets the same field and each has a single value: one
        deliberate layout, not an axis that crosses the two wheels' values into lopsided combinations.

    Returns
    -------
    str or None
        The reason, one line.
    """
    params = _params(vehicle)
    keys = dotted.split(".")
    if len(keys) == 3 and keys[0] == "wheels" and keys[2] in ("x_m", "y_m"):
        pair = [w.name for w in params.wheels if w.steered == (params.layout == "tadpole")]
        if keys[1] in pair:
            other = f"wheels.{next(n for n in pair if n != keys[1])}.{keys[2]}"
            if together is not None and other in together and all(
                len(set(together.get(k, ()))) == 1 for k in (dotted, other)
            ):
                return None
            knob = "track_m" if keys[2] == "y_m" else "wheelbase_m"
            moves = "both wheels of the pair symmetrically" if knob == "track_m" else "the front axle"
            return (f"'{dotted}' moves one wheel of the pair ({' and '.join(pair)}) only, a lopsided trike; "
                    f"use the knob {knob}, which moves {moves}")
    if len(keys) == 3 and keys[0] == "components" and keys[2] in _COMPONENT_FIELDS:
        return (f"'{dotted}' changes a component's declared {keys[2]} but leaves the vehicle's CG and inertia; "
                f"use the knob component.{keys[1]}.{keys[2]}, which moves them with it")
    return None


# ------------------------------------------------------------------------------------------------
# applying
# ------------------------------------------------------------------------------------------------
def _leaves(node, prefix: str = "") -> dict:
    """Dotted path (list items by name, as the notes are) -> value of every leaf."""
    out = {}
    if isinstance(node, dict):
        for key, value in node.items():
            out.update(_leaves(value, f"{prefix}{key}."))
    elif isinstance(node, list | tuple) and all(isinstance(i, dict) for i in node) and node:
        for i, item in enumerate(node):
            out.update(_leaves(item, f"{prefix}{item.get('name', i)}."))
    else:
        out[prefix[:-1]] = node
    return out


def apply_knobs(vehicle, knobs: Mapping[str, float]) -> ParameterSet:
    """The vehicle with design knobs set, e.g. ``{"track_m": 1.2, "component.battery.z_m": 0.25}``.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleParameters
        The vehicle; not changed.
    knobs : mapping of str to float
        Knob name (see :data:`KNOBS`; ``component.NAME.FIELD`` for a component) -> value in the knob's unit
        (lengths [m], masses [kg], ``cg_x_fraction`` [1]).

    Returns
    -------
    ParameterSet
        A new, validated parameter set; its notes say which values the knobs set.

    Raises
    ------
    ParameterError
        An unknown knob (``where="knobs"``, with a close match), a value that is not a number within the
        knob's bounds (``where=`` the knob), or a vehicle the schema refuses (``where="knobs"``).
    """
    pset = vehicle if isinstance(vehicle, ParameterSet) else ParameterSet(vehicle)
    params = pset.params
    order = list(KNOBS)
    steps = []
    for name, value in knobs.items():
        resolved = _resolve(params, name)
        if isinstance(resolved, str):
            raise ParameterError(resolved, where="knobs")
        problem = _value_problem(resolved[0], value)
        if problem:
            raise ParameterError(problem, where=name)
        steps.append((order.index(resolved[0]), resolved, name, float(value)))
    if not steps:
        return pset
    data = params.model_dump()
    for _, (key, target), _, value in sorted(steps, key=lambda s: s[0]):
        KNOBS[key].function(data, value, target)
    text = ", ".join(f"{name} = {value:.10g}" for _, _, name, value in steps)
    new = revalidated(pset, data, f"knobs ({text})")
    before, after = _leaves(params.model_dump()), _leaves(new.params.model_dump())
    notes = dict(new.notes)
    for path, value in after.items():
        if before.get(path, value) != value:
            notes[path] = moved_note(notes.get(path, {}), before[path], text)
    return replace(new, notes=notes)


def moved_note(old: Mapping[str, str], was, text: str) -> dict:
    """The provenance of a value a design knob moved: ``note`` says which knobs set it; a ``source`` (a
    measurement, a weighing) no longer describes the new value, so it becomes ``was <old value> from <source>``
    inside the note and is dropped; ``assumed`` (the reason for an assumed value it was derived from) stays."""
    note = f"set by design knobs: {text}"
    if old.get("source"):
        shown = f"{was:.6g}" if isinstance(was, int | float) and not isinstance(was, bool) else str(was)
        note += f"; was {shown} from {old['source']}"
    return {**{k: v for k, v in old.items() if k not in ("source", "note")}, "note": note}
