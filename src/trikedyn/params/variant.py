"""A vehicle variant as one value that travels: suspension scale factors, overrides and the paper's freight.

:class:`Variant` is what a study scenario, a command (``trikedyn threshold --stiffness-scale --payload``) and
a design vary on a base vehicle: the spring and damper rates scaled (paper Table 2), values set by dotted
path or design knob (:func:`~trikedyn.params.ops.override`), and freight in the trunk (Table 3). Its
settings are :class:`~trikedyn.options.Option` (:data:`VARIANT_OPTIONS`: default, unit, bounds), so the
command line and the study spec refuse the same values. :meth:`Variant.apply` makes the variant of a
vehicle in one fixed order: scale, override, freight.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ..errors import InputError
from ..options import Option, checked, find_option

__all__ = ["VARIANT_OPTIONS", "Variant", "variant_option"]

VARIANT_OPTIONS: tuple[Option, ...] = (
    Option("stiffness_scale", 1.0, "", "factor on the suspension's spring rates (paper Table 2)", minimum=0.01,
           maximum=100.0),
    Option("damping_scale", 1.0, "", "factor on the suspension's damper rates (paper Table 2)", minimum=0.01,
           maximum=100.0),
    Option("freight_kg", 0.0, "kg", "the paper's freight in the trunk (Table 3)", minimum=0.0, maximum=2000.0),
)
"""The numbers of a variant, with their defaults, units and bounds (inclusive)."""


def variant_option(name: str) -> Option:
    """One number of :data:`VARIANT_OPTIONS` by name (an :class:`InputError` with a close match if none).

    Parameters
    ----------
    name : str
        ``stiffness_scale``, ``damping_scale`` or ``freight_kg``.

    Returns
    -------
    Option
        Default, unit and bounds.
    """
    return find_option(VARIANT_OPTIONS, name, "a vehicle variant", "variant")


@dataclass(frozen=True)
class Variant:
    """A variation of a base vehicle.

    Parameters
    ----------
    stiffness_scale : float
        Factor on the spring rates [-], within [0.01, 100].
    damping_scale : float
        Factor on the damper rates [-], within [0.01, 100].
    overrides : mapping of str to value
        Dotted parameter path or design knob -> value [its unit] (:func:`~trikedyn.params.ops.override`).
    freight_kg : float
        The paper's freight in the trunk [kg], within [0, 2000].

    Raises
    ------
    InputError
        A number out of its bounds (the message names it), an override key that is not text.
    """

    stiffness_scale: float = VARIANT_OPTIONS[0].default  # type: ignore[assignment]
    damping_scale: float = VARIANT_OPTIONS[1].default  # type: ignore[assignment]
    overrides: Mapping[str, Any] = field(default_factory=dict)
    freight_kg: float = VARIANT_OPTIONS[2].default  # type: ignore[assignment]

    def __post_init__(self):
        for opt in VARIANT_OPTIONS:
            object.__setattr__(self, opt.name, checked(opt, getattr(self, opt.name)))
        overrides = dict(self.overrides)
        for key in overrides:
            if not isinstance(key, str) or not key:
                raise InputError(f"an override is named by a dotted path or a knob, got {key!r}", where="overrides")
        object.__setattr__(self, "overrides", overrides)

    def __hash__(self) -> int:
        return hash((self.stiffness_scale, self.damping_scale, tuple(sorted(self.overrides.items())),
                     self.freight_kg))

    def apply(self, pset):
        """The variant of ``pset``: suspension scaled, overrides set, freight added (in that order).

        Parameters
        ----------
        pset : ParameterSet
            The base vehicle.

        Returns
        -------
        ParameterSet
            The variant.
        """
        from .ops import override, scale_suspension, with_freight

        out = scale_suspension(pset, stiffness=self.stiffness_scale, damping=self.damping_scale)
        if self.overrides:
            out = override(out, dict(self.overrides))
        return with_freight(out, self.freight_kg)

    def to_dict(self) -> dict:
        """The variant as JSON-safe data.

        Returns
        -------
        dict
            ``stiffness_scale``, ``damping_scale`` [-], ``overrides`` (dict) and ``freight_kg`` [kg].
        """
        return {"stiffness_scale": self.stiffness_scale, "damping_scale": self.damping_scale,
                "overrides": dict(self.overrides), "freight_kg": self.freight_kg}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Variant:
        """The variant from :meth:`to_dict`'s data (a scenario: other keys are left out).

        Parameters
        ----------
        data : mapping
            The variant's keys; those not given take their defaults.

        Returns
        -------
        Variant
            The variant.
        """
        keys = ("stiffness_scale", "damping_scale", "overrides", "freight_kg")
        return cls(**{k: data[k] for k in keys if data.get(k) is not None})
