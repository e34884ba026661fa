"""The study spec's schema: a study file's TOML table validated into checked values (pydantic).

The keys a study file may hold, their types, defaults and bounds (:class:`_Spec`, its groups
:class:`_Group`), checked by :func:`validate_spec` with one line naming the first bad key. The search
settings' defaults are :data:`~trikedyn.analysis.search_settings.SEARCH_DEFAULTS` (their bounds are checked
by :class:`~trikedyn.analysis.search_settings.SearchSettings` when the spec is loaded), a grid axis of scale
factors or freight is checked by the variant's bounds (:data:`~trikedyn.params.variant.VARIANT_OPTIONS`).
What the keys mean, the files a spec names and the loaded spec are :mod:`trikedyn.study.spec`'s; the
reference page of the study file is generated from :class:`_Spec`.
"""

from __future__ import annotations

import math

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from .._validation import describe_validation_error
from ..analysis.search_settings import SEARCH_DEFAULTS
from ..errors import InputError

__all__ = ["Scalar", "validate_spec"]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


Scalar = float | int | bool | str
"""A value of an override axis or of an option in a manoeuvre or metric entry."""


class _Group(_Model):
    name: str = Field(min_length=1)
    stiffness_scale: list[float] = Field(default=[1.0], min_length=1)
    damping_scale: list[float] = Field(default=[1.0], min_length=1)
    overrides: dict[str, list[Scalar]] = Field(
        default_factory=dict,
        description="dotted parameter path or design knob (track_m, component.NAME.x_m ...) = list of values, "
        "each list one more grid axis",
    )

    @field_validator("stiffness_scale", "damping_scale")
    @classmethod
    def _scale(cls, values, info):
        return _variant_values(info.field_name, values)

    @field_validator("overrides")
    @classmethod
    def _non_empty(cls, values):
        for key, axis in values.items():
            if not axis:
                raise ValueError(f"override '{key}' needs at least one value")
            for v in axis:
                if isinstance(v, float) and not math.isfinite(v):  # a scenario id is JSON: no nan or inf
                    raise ValueError(f"override '{key}': values must be finite, got {v!r}")
        return values


class _Spec(_Model):
    name: str = Field(min_length=1)
    description: str = ""
    vehicle: str = "reference-etrike"
    manoeuvres: list[str | dict[str, Scalar]] = Field(
        default=["dlc", "slc"], min_length=1,
        description="registered manoeuvres, each a name or a table { name = ..., option = value } (its options)")
    metrics: list[str | dict[str, Scalar]] = Field(
        default=["threshold"], min_length=1,
        description="what each vehicle variation measures: registered study metrics (threshold, tilt_angle, "
        "understeer_gradient, peak_ri, min_wheel_load, ...), each a name or a table { name = ..., option = value }",
    )
    freight_kg: list[float] = Field(default=[0.0], min_length=1)
    # the search settings: defaults and bounds are SearchSettings' (checked when the spec is loaded, one line
    # naming the key: trikedyn.study.spec)
    resolution_kmh: float = Field(default=SEARCH_DEFAULTS["resolution_kmh"],
                                  description="threshold search resolution [km/h]")
    low_kmh: float = Field(default=SEARCH_DEFAULTS["low_kmh"], description="lowest speed searched [km/h]")
    high_kmh: float = Field(default=SEARCH_DEFAULTS["high_kmh"], description="highest speed searched [km/h] (the "
                            "driver's searches stop at the top speed when lower)")
    step_kmh: float = Field(default=SEARCH_DEFAULTS["step_kmh"], description="bracketing step [km/h]")
    criterion: str = Field(
        default=SEARCH_DEFAULTS["criterion"], description="what a run must do to pass: course (ISO 3888-1 "
        "validity), lift-off (the paper's) or both")
    speed_control: str = Field(
        default=SEARCH_DEFAULTS["speed_control"], description="the vehicle's own drive (stops at its top speed) or "
        "an unlimited one (ideal)")
    speed_band_percent: float = Field(default=SEARCH_DEFAULTS["speed_band_percent"], description="half-width of the "
                                      "band the speed is held to through the window [% of the target]")
    speed_band_kmh: float = Field(default=SEARCH_DEFAULTS["speed_band_kmh"], description="smallest half-width of the "
                                  "speed band [km/h] (the band is the larger of the two)")
    groups: list[_Group] = Field(default_factory=lambda: [_Group(name="base")], min_length=1)

    @field_validator("freight_kg")
    @classmethod
    def _freight(cls, values, info):
        return _variant_values(info.field_name, values)


def _variant_values(name: str, values: list) -> list:
    """A grid axis of a variant's number (a scale factor, the freight [kg]) checked by its bounds
    (:data:`~trikedyn.params.variant.VARIANT_OPTIONS`); a ValueError naming the value if one is out."""
    from ..options import checked
    from ..params.variant import variant_option

    opt = variant_option(name)
    try:
        return [checked(opt, v) for v in values]
    except InputError as exc:
        raise ValueError(exc.reason) from None


def validate_spec(raw: dict, origin: str) -> _Spec:
    """A study file's table checked against the schema.

    Parameters
    ----------
    raw : dict
        The table the TOML file parses to.
    origin : str
        Where it was read from, named in the error.

    Returns
    -------
    _Spec
        The checked values, defaults filled in.

    Raises
    ------
    InputError
        One line for the first bad key (an unknown one with a close match), naming ``origin``.
    """
    try:
        return _Spec.model_validate(raw)
    except ValidationError as exc:
        raise InputError(describe_validation_error(exc, raw, _Spec), where=origin) from None
