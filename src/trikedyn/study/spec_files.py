"""What a study spec names, checked when it is loaded (:mod:`trikedyn.study.spec`): its vehicle (a preset or a
file the spec names), the ``.tir`` files of its overrides, and each override path or design knob.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..errors import InputError, did_you_mean

__all__ = ["check_path", "override_problem", "resolve_vehicle", "tyre_files"]


def resolve_vehicle(vehicle: str, base_dir: Path, place: str, origin: str) -> str:
    """A preset name stays a name; a path is a file the spec names (the rule of
    :func:`trikedyn._reading.named_file`), made absolute in the spec's folder.

    Parameters
    ----------
    vehicle : str
        The spec's ``vehicle``: a preset name or a ``.toml`` path relative to the spec's folder.
    base_dir : Path
        The spec's folder.
    place : str
        That folder in words, for errors.
    origin : str
        The spec, named in errors.

    Returns
    -------
    str
        The preset name, or the file's absolute path (an unknown name as it is: loading it explains).
    """
    from .._reading import named_file
    from ..params import list_presets

    if vehicle in list_presets() and not vehicle.endswith(".toml"):
        return vehicle
    if Path(vehicle).suffix == ".toml" or "/" in vehicle or "\\" in vehicle:
        named = named_file(vehicle, base_dir, expected="a preset name or a .toml vehicle file", where=origin,
                           key="vehicle", place=place)
        return str(named.path)
    return vehicle  # an unknown name: load_vehicle explains, with a close match


def tyre_files(group: str, overrides: dict, base_dir: Path, place: str, origin: str) -> dict:
    """A group's overrides with each ``wheels.NAME.tyre_file`` value made the absolute path of a ``.tir`` file
    the spec names (the rule of :func:`trikedyn._reading.named_file`), read and checked now.

    Parameters
    ----------
    group : str
        The group's name, for errors.
    overrides : dict
        Dotted path or knob -> list of values.
    base_dir : Path
        The spec's folder.
    place : str
        That folder in words, for errors.
    origin : str
        The spec, named in errors.

    Returns
    -------
    dict
        The overrides, tyre files as absolute paths.
    """
    from .._reading import named_file

    out = dict(overrides)
    for dotted, values in overrides.items():
        keys = dotted.split(".")
        if not (len(keys) == 3 and keys[0] == "wheels" and keys[2] == "tyre_file"):
            continue
        from ..tyre.tir import read_tir  # here: the tyre package loads numba, which a spec without .tir files skips

        key = f"groups[{group}].overrides.{dotted}"
        paths = []
        for value in values:
            named = named_file(value, base_dir, expected="a .tir file", where=origin, key=key, place=place,
                               suffixes=(".tir",))
            try:
                read_tir(named.path)
            except InputError as exc:
                raise InputError(f"{key}: {exc}", where=origin) from None
            paths.append(str(named.path))
        out[dotted] = paths
    return out


def override_problem(params, plain: dict, dotted: str, values, group: dict) -> str | None:
    """Why an override axis of a group cannot be varied (None if it can): an unknown knob or path (with a
    close match), a knob value that is not a number within the knob's bounds, or a path that moves one wheel
    of the pair or one component's declared place without the rest (a pointer to the knob that does it
    consistently; both wheels of the pair set in the group, one value each, are one deliberate layout).

    Parameters
    ----------
    params : VehicleParameters
        The base vehicle.
    plain : dict
        Its values as JSON data (``model_dump(mode="json")``).
    dotted : str
        The override's path or knob.
    values : list
        The axis' values [the parameter's unit].
    group : dict
        The group's overrides (path -> values).

    Returns
    -------
    str or None
        The problem in words, or None.
    """
    from ..params.knobs import _unknown, inconsistent_override, is_knob, knob_problem

    if is_knob(dotted):
        return knob_problem(params, dotted, values)
    if "." not in dotted and dotted not in plain:
        return _unknown(params, dotted)
    return check_path(plain, dotted) or inconsistent_override(params, dotted, group)


def check_path(plain: dict, dotted: str) -> str | None:
    """Why a dotted parameter path does not exist in a parameter set (None if it does).

    Parameters
    ----------
    plain : dict
        The parameter set's values as JSON data.
    dotted : str
        The path (wheels and components by name).

    Returns
    -------
    str or None
        The problem in words, with a close match; None for a path to a value.
    """
    node: Any = plain
    keys = dotted.split(".")
    for i, key in enumerate(keys):
        if isinstance(node, list):
            names = [w.get("name") for w in node if isinstance(w, dict)]
            nxt = next((w for w in node if isinstance(w, dict) and w.get("name") == key), None)
        elif isinstance(node, dict):
            names = list(node)
            nxt = node.get(key) if key in node else None
            if key in node and i == len(keys) - 1:
                return None
        else:
            return f"no parameter '{dotted}' ('{'.'.join(keys[:i])}' is a value)"
        if nxt is None:
            tip = did_you_mean(key, [str(n) for n in names])
            return f"no parameter '{dotted}' (no '{key}'){tip}"
        node = nxt
    if isinstance(node, dict | list):
        return f"'{dotted}' is a section, not a value"
    return None


