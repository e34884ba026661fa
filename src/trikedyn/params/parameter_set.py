"""A validated vehicle parameter set with its provenance (:class:`ParameterSet`), its mass properties and its
re-validation after a change.

The bottom of :mod:`trikedyn.params`: :mod:`~trikedyn.params.io` reads and writes parameter sets,
:mod:`~trikedyn.params.ops` and :mod:`~trikedyn.params.knobs` make variants of them; all three import this
module and it imports none of them (so no import circle runs through ``params/``).
"""

from __future__ import annotations

import threading
import weakref
from dataclasses import dataclass, field, replace

import numpy as np
from pydantic import ValidationError

from .._validation import describe_validation_error
from ..errors import ParameterError
from ..mechanics import Box, MassProperties, Payload
from .schema import VehicleParameters

__all__ = ["ParameterSet", "describe_error", "mass_properties", "revalidated"]


@dataclass(frozen=True)
class ParameterSet:
    """A validated vehicle parameter set with the provenance of its values.

    Attributes
    ----------
    params : VehicleParameters
        The values.
    notes : dict
        Dotted parameter path -> {"assumed" | "source" | "note": text}.
    origin : str
        Preset name or file path it was read from.
    """

    params: VehicleParameters
    notes: dict = field(default_factory=dict)
    origin: str = ""

    @property
    def name(self) -> str:
        """The vehicle's name (``params.name``)."""
        return self.params.name

    @property
    def mass_kg(self) -> float:
        """Total mass [kg]: the vehicle (driver included) with its payload (:func:`mass_properties`)."""
        return float(mass_properties(self.params).mass_kg)

    @property
    def cg_m(self):
        """Centre of gravity ``[x, y, z]`` [m] in vehicle axes, payload included (a new numpy array)."""
        return mass_properties(self.params).cg_m.copy()

    def assumed(self) -> dict[str, str]:
        """Every assumed value's path and reason.

        Returns
        -------
        dict of str to str
            Dotted parameter path -> the ``assumed`` note (why the value is assumed).
        """
        return {k: v["assumed"] for k, v in self.notes.items() if "assumed" in v}

    def with_params(self, params: VehicleParameters, origin: str | None = None) -> ParameterSet:
        """The same provenance with other values (after a scaling or an override).

        Parameters
        ----------
        params : VehicleParameters
            The new values (validated).
        origin : str, optional
            A new origin; by default the set's own.

        Returns
        -------
        ParameterSet
            A new set; this one is not changed.
        """
        return replace(self, params=params, origin=self.origin if origin is None else origin)


def _base_mass_properties(params: VehicleParameters) -> MassProperties:
    m = params.mass
    return MassProperties(m.total_kg, m.cg_m, np.array(m.inertia_tensor_kgm2))


def _item(spec) -> Box:
    return Box(spec.mass_kg, (spec.x_m, spec.y_m, spec.z_m), (spec.length_m, spec.width_m, spec.height_m), spec.name)


_COMPOSED: dict[int, tuple] = {}  # id(params) -> (weak reference, its mass section, its payload, MassProperties)
_COMPOSED_MAX = 256
_COMPOSED_LOCK = threading.Lock()


def _composed(params: VehicleParameters) -> MassProperties:
    """The composition itself (parallel-axis theorem), read-only arrays."""
    added = Payload("added", tuple(_item(i) for i in params.payload if not i.removed))
    removed = Payload("removed", tuple(_item(i) for i in params.payload if i.removed))
    mp = removed.removed_from(added.added_to(_base_mass_properties(params)))
    mp = MassProperties(mp.mass_kg, mp.cg_m.copy(), mp.inertia_kgm2.copy())
    mp.cg_m.setflags(write=False)
    mp.inertia_kgm2.setflags(write=False)
    return mp


def _forget(key: int, ref: weakref.ref) -> None:
    with _COMPOSED_LOCK:
        if key in _COMPOSED and _COMPOSED[key][0] is ref:
            del _COMPOSED[key]


def mass_properties(params: VehicleParameters) -> MassProperties:
    """The whole vehicle's mass [kg], CG [m] and inertia about the CG [kg m^2], payload included.

    Composed once per parameter set (a :class:`VehicleParameters` is frozen): the same object is returned
    for the same ``params``, with read-only arrays.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle; its ``payload`` items (boxes) are added, or taken off where ``removed``.

    Returns
    -------
    MassProperties
        Mass [kg], CG ``[x, y, z]`` [m] in vehicle axes, inertia tensor about the CG [kg m^2].

    Raises
    ------
    InputError
        ``where="payload"``: the payload taken off weighs as much as the vehicle or more.
    """
    key = id(params)
    kept = _COMPOSED.get(key)
    if kept is not None and kept[0]() is params and kept[1] is params.mass and kept[2] is params.payload:
        return kept[3]
    mp = _composed(params)
    ref = weakref.ref(params, lambda r, k=key: _forget(k, r))
    with _COMPOSED_LOCK:
        _COMPOSED[key] = (ref, params.mass, params.payload, mp)
        while len(_COMPOSED) > _COMPOSED_MAX:
            del _COMPOSED[next(iter(_COMPOSED))]
    return mp


def describe_error(exc: ValidationError, plain: dict) -> str:
    """One line for the first validation error of a parameter set.

    Parameters
    ----------
    exc : pydantic.ValidationError
        The schema's refusal.
    plain : dict
        The values as given (to show the value refused).

    Returns
    -------
    str
        ``dotted.path: what is wrong (got VALUE)``.
    """
    return describe_validation_error(exc, plain, VehicleParameters)


def revalidated(pset: ParameterSet, data: dict, what: str) -> ParameterSet:
    """``pset`` with the changed values ``data`` (a ``model_dump`` edited), validated again.

    Parameters
    ----------
    pset : ParameterSet
        The set the values came from (its notes and origin are kept).
    data : dict
        The changed values, as :meth:`VehicleParameters.model_dump` gives them.
    what : str
        The operation that changed them, named in an error.

    Returns
    -------
    ParameterSet
        A new, validated set.

    Raises
    ------
    ParameterError
        The schema refuses ``data``; ``where=what`` (the operation that changed it).
    """
    try:
        params = VehicleParameters.model_validate(data)
    except ValidationError as exc:
        raise ParameterError(describe_error(exc, data), where=what) from None
    return pset.with_params(params)
