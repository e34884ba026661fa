"""Variants of a parameter set: payload aboard, suspension scaled, single values overridden.

Each function returns a new, validated :class:`~trikedyn.params.parameter_set.ParameterSet`; nothing is changed in
place. These are the operations a parametric study applies (Tables 2-3 of the paper).
"""

from __future__ import annotations

import numpy as np
from pydantic import ValidationError

from ..errors import ParameterError, did_you_mean
from ..mechanics import Payload, PointMass, wheel_loads_from_cg
from ..units import STANDARD_GRAVITY
from .parameter_set import ParameterSet, mass_properties, revalidated
from .schema import PayloadItemSpec, VehicleParameters

__all__ = ["freight", "mass_properties", "override", "scale_suspension", "static_wheel_loads", "unsprung_mass",
           "with_freight", "with_payload"]


def freight(params: VehicleParameters, mass_kg: float) -> Payload:
    """The paper's freight (Table 3): ``mass_kg`` as a point mass at the vehicle's freight site.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    mass_kg : float
        Freight mass [kg].

    Returns
    -------
    Payload
        The freight as one point mass.
    """
    site = params.freight
    return Payload("paper-freight", (PointMass(mass_kg, (site.x_m, site.y_m, site.z_m), name="freight"),))


def with_payload(pset: ParameterSet, payload: Payload, *, remove: bool = False) -> ParameterSet:
    """The vehicle with ``payload`` aboard (or, ``remove=True``, with those masses taken off it).

    Items are point masses (:class:`~trikedyn.measure.cg.PointMass`) or boxes
    (:class:`~trikedyn.measure.cg.Box`); they are appended to ``params.payload``.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    payload : Payload
        Point masses and boxes (masses [kg], positions and sizes [m]).
    remove : bool
        Take the masses off instead.

    Returns
    -------
    ParameterSet
        The new set.
    """
    rows = []
    for item in payload.items:
        size = getattr(item, "size_m", (0.0, 0.0, 0.0))
        pos = getattr(item, "centre_m", getattr(item, "position_m", None))
        item.mass_properties()  # validates the mass
        rows.append(
            dict(
                name=item.name, mass_kg=float(item.mass_kg), x_m=float(pos[0]), y_m=float(pos[1]), z_m=float(pos[2]),
                length_m=float(size[0]), width_m=float(size[1]), height_m=float(size[2]), removed=remove,
            )
        )
    return _with_items(pset, rows, f"payload '{payload.name}'")


def _with_items(pset: ParameterSet, rows: list[dict], what: str) -> ParameterSet:
    """``pset`` with payload items appended, each built as a :class:`PayloadItemSpec` from its fields; the
    set is validated again from its own (already validated) sections, not from a dump of them. Its mass
    properties are composed here, once (:func:`mass_properties` keeps them): removing more than there is
    fails here, with a clear message. A refusal is worded as for the whole set (``what`` names the
    operation)."""
    params = pset.params
    try:
        items = tuple(PayloadItemSpec(**row) for row in rows)
        new = VehicleParameters.model_validate({**dict(params), "payload": params.payload + items})
    except ValidationError:
        data = params.model_dump()
        data["payload"] = list(data["payload"]) + rows
        revalidated(pset, data, what)  # raises, naming the dotted path and the value as given
        raise
    laden = pset.with_params(new)
    mass_properties(new)
    return laden


def with_freight(pset: ParameterSet, mass_kg: float) -> ParameterSet:
    """The vehicle with the paper's freight of ``mass_kg`` [kg] in its trunk (Table 3).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    mass_kg : float
        Freight mass [kg], >= 0.

    Returns
    -------
    ParameterSet
        The new set (``pset`` itself for no freight).

    Raises
    ------
    ParameterError
        On a negative or non-finite mass.
    """
    if not np.isfinite(mass_kg) or mass_kg < 0:
        raise ParameterError(f"freight mass must be >= 0 kg, got {mass_kg!r}", where="payload")
    if mass_kg == 0:
        return pset
    site = pset.params.freight  # the point mass of freight(), as the one schema item it becomes
    row = dict(name="freight", mass_kg=float(mass_kg), x_m=site.x_m, y_m=site.y_m, z_m=site.z_m)
    return _with_items(pset, [row], "payload 'paper-freight'")


def scale_suspension(
    pset: ParameterSet, *, stiffness: float = 1.0, damping: float = 1.0, suspensions=None
) -> ParameterSet:
    """Spring and damper rates multiplied by ``stiffness`` and ``damping`` (Table 2: 0.8, 1.0, 1.2).

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    stiffness : float
        Factor on the spring rates, dimensionless (> 0).
    damping : float
        Factor on the damper rates, dimensionless (> 0).
    suspensions : iterable of str, optional
        Names of the suspensions to scale; all by default.

    Returns
    -------
    ParameterSet
        The new set.
    """
    for name, factor in (("stiffness", stiffness), ("damping", damping)):
        if not np.isfinite(factor) or factor <= 0:
            raise ParameterError(f"scale factor must be > 0, got {factor!r}", where=name)
    data = pset.params.model_dump()
    names = list(data["suspension"]) if suspensions is None else list(suspensions)
    for name in names:
        if name not in data["suspension"]:
            raise ParameterError(f"no suspension '{name}' (have {', '.join(data['suspension'])})", where="suspensions")
        data["suspension"][name]["stiffness_N_per_m"] *= stiffness
        data["suspension"][name]["damping_Ns_per_m"] *= damping
    return revalidated(pset, data, "scale_suspension")


def override(pset: ParameterSet, values: dict) -> ParameterSet:
    """Set values by dotted path or by design knob.

    ``{"mass.driver_kg": 80, "wheels.front.radius_m": 0.3, "track_m": 1.2}``: a dotted path sets that one
    value as written (wheels and components by name); a design knob (:mod:`trikedyn.params.knobs`:
    ``wheelbase_m``, ``track_m``, ``cg_x_fraction``, ``cg_height_m``, ``component.NAME.x_m|y_m|z_m|mass_kg``,
    ``freight.x_m|y_m|z_m``) changes the vehicle consistently. The paths are set first, then the knobs are
    applied (in the order of :data:`~trikedyn.params.knobs.KNOBS`). A path of one wheel of the pair is set
    as written here (an asymmetric vehicle is allowed); a study spec refuses it and points to ``track_m``.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    values : dict
        Dotted path or knob -> value [its unit].

    Returns
    -------
    ParameterSet
        The new, validated set.

    Raises
    ------
    ParameterError
        An unknown path or knob (with a close match), a value out of range, a vehicle the schema refuses.
    """
    from .knobs import _unknown, apply_knobs, is_knob

    knobs = {k: v for k, v in values.items() if is_knob(k)}
    paths = {k: v for k, v in values.items() if k not in knobs}
    data = pset.params.model_dump()
    for dotted, value in paths.items():
        if "." not in dotted and dotted not in data:
            raise ParameterError(_unknown(pset.params, dotted), where="override")
        node = data
        keys = dotted.split(".")
        for key in keys[:-1]:
            if isinstance(node, list | tuple):
                node = next((w for w in node if w.get("name") == key), None)
            else:
                node = node.get(key) if isinstance(node, dict) else None
            if node is None:
                raise ParameterError(f"no parameter '{dotted}' (no '{key}')", where="override")
        if not isinstance(node, dict) or keys[-1] not in node:
            tip = did_you_mean(keys[-1], list(node) if isinstance(node, dict) else [])
            raise ParameterError(f"no parameter '{dotted}'{tip}", where="override")
        node[keys[-1]] = value
    new = revalidated(pset, data, "override") if paths or not knobs else pset
    return apply_knobs(new, knobs) if knobs else new


def unsprung_mass(params: VehicleParameters, wheel_name: str) -> float:
    """Mass moving with the wheel vertically [kg]: wheel plus fork slider, or plus half the swing arm.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    wheel_name : str
        The wheel.

    Returns
    -------
    float
        Mass [kg].
    """
    wheel = params.wheel(wheel_name)
    susp = params.suspension[wheel.suspension]
    share = 1.0 if susp.kind == "telescopic" else 0.5  # arm's CG taken midway between pivot and axle
    return wheel.mass_kg + share * susp.moving_mass_kg


def static_wheel_loads(params: VehicleParameters, g: float = STANDARD_GRAVITY) -> dict[str, float]:
    """Static vertical load on each wheel [N] of the vehicle as a rigid body on level ground.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    g : float
        Gravity [m/s^2].

    Returns
    -------
    dict of str to float
        Wheel -> load [N].
    """
    contacts = [(w.x_m, w.y_m) for w in params.wheels]
    mp = mass_properties(params)
    loads = wheel_loads_from_cg(mp.mass_kg, mp.cg_m[:2], contacts, g)
    return {w.name: float(f) for w, f in zip(params.wheels, loads, strict=True)}
