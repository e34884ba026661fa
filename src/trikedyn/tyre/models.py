"""The registry of tyre models, Python side: each model says which wheels it takes and how to set them up.

A tyre model is one module that registers a :class:`TyreModel` in :data:`TYRE_MODELS`: its name, the number
of its branch in the compiled :func:`~trikedyn.tyre.interface.tyre_forces` (``kernel``; a model may reuse an
existing branch with its own coefficients), which wheels it takes (``claims``: the highest ``priority`` of
the models that claim a wheel wins), the wheel's :class:`TyreSetup` for packing (``setup``), the linear
slip and cornering stiffnesses (``stiffnesses``), the vertical spring and the label the audit shows
(``vertical``) and the names of its clamp bits (``clamp_names``). The built-ins are the modules of
:mod:`trikedyn.tyre.builtin` (``similarity``: the ``[tyre]`` section; ``magic-formula``: a wheel's ``.tir``
file); plug-ins from other distributions register through the entry-point group ``trikedyn.tyre_models``.
The model build (:func:`trikedyn.model.vehicle.build_model`), the single-track model, the spring audit and
the run's clamp warning find a wheel's model with :func:`for_wheel` or by name with :func:`get`.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..registry import Registry
from .mf_coefficients import N_COEFFS
from .pac2002 import N_PACKED

__all__ = ["COEFFS_WIDTH", "MAGIC_FORMULA", "SIMILARITY", "TYRE_MODELS", "TyreModel", "TyreSetup", "for_wheel", "get",
           "register"]

SIMILARITY, MAGIC_FORMULA = 0, 1
"""Numbers of the compiled branches of :func:`~trikedyn.tyre.interface.tyre_forces` (the ``kernel`` ids)."""
COEFFS_WIDTH = max(N_COEFFS, N_PACKED)
"""Width of a wheel's coefficient row: the longest of the models' coefficient vectors."""


@dataclass(frozen=True)
class TyreSetup:
    """One wheel's tyre, ready for packing.

    Attributes
    ----------
    model : int
        The compiled branch (kernel id): ``SIMILARITY`` or ``MAGIC_FORMULA``.
    coefficients : numpy.ndarray
        The model's coefficient vector, padded to ``COEFFS_WIDTH``.
    vertical_stiffness_N_per_m, vertical_damping_Ns_per_m : float
        Vertical stiffness [N/m] and damping [N s/m].
    relaxation_x_m, relaxation_y_m : float
        Relaxation lengths [m].
    source : str
        ``"[tyre]"`` or the ``.tir`` file.
    name : str
        The registered tyre model (:data:`TYRE_MODELS`).
    """

    model: int
    coefficients: np.ndarray
    vertical_stiffness_N_per_m: float
    vertical_damping_Ns_per_m: float
    relaxation_x_m: float
    relaxation_y_m: float
    source: str
    name: str = ""


def _no_clamps(mask: int) -> list[str]:
    """No clamp bits: a model without validity ranges.

    Parameters
    ----------
    mask : int
        Bit mask of ``CLAMPED_*`` flags.

    Returns
    -------
    list of str
        Always empty.
    """
    return []


@dataclass(frozen=True)
class TyreModel:
    """A registered tyre model (Python side).

    Attributes
    ----------
    name : str
        Its name (``similarity``, ``magic-formula``).
    kernel : int
        Its branch of the compiled :func:`~trikedyn.tyre.interface.tyre_forces`.
    claims : callable
        ``claims(params, wheel) -> bool``: whether it is the tyre of a wheel station.
    setup : callable
        ``setup(params, wheel, static_load_N) -> TyreSetup`` (static load [N]); ``name`` is filled in.
    stiffnesses : callable
        ``stiffnesses(coefficients, fz_N) -> (slip stiffness [N], cornering stiffness [N/rad])`` at zero
        camber, both positive for a normal tyre (trikedyn's slip-angle sign).
    vertical : callable
        ``vertical(params, wheel) -> (stiffness [N/m], damping [N s/m], nominal load [N], label)``: the
        tyre's spring and damper as the audit shows them, with where they come from.
    clamp_names : callable
        ``clamp_names(mask) -> list of str``: the inputs a clamp mask of the run says left the data's range.
    priority : float
        Of the models that claim a wheel, the highest priority takes it.
    """

    name: str
    kernel: int
    claims: Callable
    setup: Callable
    stiffnesses: Callable
    vertical: Callable
    clamp_names: Callable = _no_clamps
    priority: float = 0.0


def _load_builtins() -> None:
    importlib.import_module("trikedyn.tyre.builtin")  # its modules register themselves


TYRE_MODELS: Registry[TyreModel] = Registry("tyre model", group="trikedyn.tyre_models", builtins=_load_builtins,
                                            where="tyre model")
"""The registered tyre models (plug-ins: entry-point group ``trikedyn.tyre_models``)."""


def register(model: TyreModel, *, replace: bool = False) -> TyreModel:
    """Register ``model`` under its name (a taken name raises ValueError unless ``replace=True``).

    Parameters
    ----------
    model : TyreModel
        The model.
    replace : bool
        Replace a model of the same name.

    Returns
    -------
    TyreModel
        ``model``.
    """
    if not isinstance(model, TyreModel):
        raise ValueError(f"expected a TyreModel, got {model!r}")
    return TYRE_MODELS.register(model.name, model, replace=replace)


def get(name: str) -> TyreModel:
    """The tyre model ``name``; an :class:`~trikedyn.errors.InputError` with a close match when unknown.

    Parameters
    ----------
    name : str
        The model's name.

    Returns
    -------
    TyreModel
        The model.
    """
    return TYRE_MODELS.get(name)


def for_wheel(params, wheel) -> TyreModel:
    """The tyre model of a wheel station: the highest priority of the models that claim it.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    wheel : WheelSpec
        One of its wheels.

    Returns
    -------
    TyreModel
        The model.

    Raises
    ------
    LookupError
        No registered model claims the wheel (the built-ins claim every wheel between them).
    """
    claiming = [m for m in TYRE_MODELS.values() if m.claims(params, wheel)]
    if not claiming:
        raise LookupError(f"no tyre model claims wheel '{wheel.name}' (models: {', '.join(TYRE_MODELS.names())})")
    return max(claiming, key=lambda m: m.priority)
