"""Variants of a parameter set: payload aboard, suspension scaled, single values overridden.

Each function returns a new, validated :class:`~trikedyn.params.io.ParameterSet`; nothing is changed in
place. These are the operations a parametric study applies (Tables 2-3 of the paper).
"""

from __future__ import annotations

import numpy as np
from pydantic import ValidationError

from ..errors import ParameterError
from ..measure.cg import MassProperties, Payload, PointMass
from .io import ParameterSet, _describe
from .schema import VehicleParameters

__all__ = ["mass_properties", "freight", "with_payload", "with_freight", "scale_suspension", "override"]


def mass_properties(params: VehicleParameters) -> MassProperties:
    """The whole vehicle's mass [kg], CG [m] and inertia about the CG [kg m^2]."""
    m = params.mass
    return MassProperties(m.total_kg, m.cg_m, np.array(m.inertia_tensor_kgm2))


def freight(params: VehicleParameters, mass_kg: float) -> Payload:
    """The paper's freight (Table 3): ``mass_kg`` as a point mass at the vehicle's freight site."""
    site = params.freight
    return Payload("paper-freight", (PointMass(mass_kg, (site.x_m, site.y_m, site.z_m), name="freight"),))


def _revalidate(pset: ParameterSet, data: dict, what: str) -> ParameterSet:
    try:
        params = VehicleParameters.model_validate(data)
    except ValidationError as exc:
        raise ParameterError(_describe(exc, data), where=what) from None
    return pset.with_params(params)


def with_payload(pset: ParameterSet, payload: Payload, *, remove: bool = False) -> ParameterSet:
    """The vehicle with ``payload`` aboard (or taken off, ``remove=True``): mass, CG and inertia updated."""
    base = mass_properties(pset.params)
    new = payload.removed_from(base) if remove else payload.added_to(base)
    sign = -1.0 if remove else 1.0
    inertia = new.inertia_kgm2
    data = pset.params.model_dump()
    data["mass"].update(
        payload_kg=pset.params.mass.payload_kg + sign * payload.mass_kg,
        cg_x_m=float(new.cg_m[0]),
        cg_y_m=float(new.cg_m[1]),
        cg_z_m=float(new.cg_m[2]),
        roll_inertia_kgm2=float(inertia[0, 0]),
        pitch_inertia_kgm2=float(inertia[1, 1]),
        yaw_inertia_kgm2=float(inertia[2, 2]),
        roll_pitch_product_kgm2=float(-inertia[0, 1]),
        roll_yaw_product_kgm2=float(-inertia[0, 2]),
        pitch_yaw_product_kgm2=float(-inertia[1, 2]),
    )
    return _revalidate(pset, data, f"payload '{payload.name}'")


def with_freight(pset: ParameterSet, mass_kg: float) -> ParameterSet:
    """The vehicle with the paper's freight of ``mass_kg`` [kg] in its trunk (Table 3)."""
    if not np.isfinite(mass_kg) or mass_kg < 0:
        raise ParameterError(f"freight mass must be >= 0 kg, got {mass_kg!r}", where="payload")
    return with_payload(pset, freight(pset.params, mass_kg)) if mass_kg > 0 else pset


def scale_suspension(
    pset: ParameterSet, *, stiffness: float = 1.0, damping: float = 1.0, suspensions=None
) -> ParameterSet:
    """Spring and damper rates multiplied by ``stiffness`` and ``damping`` (Table 2: 0.8, 1.0, 1.2).

    Parameters
    ----------
    suspensions : iterable of str, optional
        Names of the suspensions to scale; all by default.
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
    return _revalidate(pset, data, "scale_suspension")


def override(pset: ParameterSet, values: dict) -> ParameterSet:
    """Set values by dotted path, e.g. ``{"mass.driver_kg": 80, "wheels.front.radius_m": 0.3}``."""
    data = pset.params.model_dump()
    for dotted, value in values.items():
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
            from difflib import get_close_matches

            hint = get_close_matches(keys[-1], list(node) if isinstance(node, dict) else [], n=1)
            tip = f"; did you mean '{hint[0]}'?" if hint else ""
            raise ParameterError(f"no parameter '{dotted}'{tip}", where="override")
        node[keys[-1]] = value
    return _revalidate(pset, data, "override")
