"""Load and save parameter sets as TOML; find the presets shipped with the package.

A value may be written plainly (``wheelbase_m = 1.95``) or with its provenance next to it::

    driver_kg = { value = 75.0, assumed = "EU 1230/2012 standard driver; fits Table 3" }
    stiffness_N_per_m = { value = 80289.0, source = "paper Table 2, 100 %" }

The notes (``assumed``, ``source``, ``note``) are kept by dotted path (``mass.driver_kg``,
``wheels.front.radius_m``) in :attr:`ParameterSet.notes` and written back by :func:`save_vehicle`.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field, replace
from difflib import get_close_matches
from importlib import resources
from pathlib import Path

import tomli_w
from pydantic import ValidationError

from .._validation import describe_validation_error
from ..errors import ParameterError
from .schema import VehicleParameters

__all__ = ["NOTE_KEYS", "ParameterSet", "list_presets", "load_vehicle", "parse_vehicle", "save_vehicle"]

NOTE_KEYS = ("assumed", "source", "note")


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
        return self.params.name

    def assumed(self) -> dict[str, str]:
        """Every assumed value's path and reason."""
        return {k: v["assumed"] for k, v in self.notes.items() if "assumed" in v}

    def with_params(self, params: VehicleParameters, origin: str | None = None) -> ParameterSet:
        """The same provenance with other values (after a scaling or an override)."""
        return replace(self, params=params, origin=self.origin if origin is None else origin)


# ------------------------------------------------------------------------------------------------
def _preset_dir():
    return resources.files("trikedyn.params") / "presets"


def list_presets() -> list[str]:
    """Names of the parameter sets shipped with trikedyn."""
    return sorted(p.name[:-5] for p in _preset_dir().iterdir() if p.name.endswith(".toml"))


def load_vehicle(name_or_path: str | Path) -> ParameterSet:
    """Load a preset by name, or a parameter file by path.

    Raises
    ------
    ParameterError
        Unknown preset (with a close match), unreadable TOML, unknown key, missing or out-of-range value.
    """
    text = str(name_or_path)
    path = Path(text)
    if path.suffix == ".toml" or path.exists() or "/" in text:
        if not path.is_file():
            raise ParameterError("no such parameter file", where=text)
        try:
            raw = path.read_text(encoding="utf-8")
        except UnicodeDecodeError as exc:
            raise ParameterError(f"not UTF-8 text ({exc.reason} at byte {exc.start})", where=text) from None
        return parse_vehicle(raw, origin=text)
    presets = list_presets()
    if text not in presets:
        hint = get_close_matches(text, presets, n=1)
        tip = f"; did you mean '{hint[0]}'?" if hint else ""
        raise ParameterError(
            f"unknown vehicle '{text}'{tip} (presets: {', '.join(presets)}; or give a .toml file)", where="vehicle"
        )
    return parse_vehicle((_preset_dir() / f"{text}.toml").read_text(encoding="utf-8"), origin=text)


def parse_vehicle(toml_text: str, origin: str = "<string>") -> ParameterSet:
    """Validate a parameter set given as TOML text.

    A set may start from another with ``extends = "PRESET"`` (or a path relative to its own file) and
    give only what differs; tables merge key by key, ``[[wheels]]`` by wheel name.
    """
    raw = _read_raw(toml_text, origin, depth=0)
    plain, notes = _split_notes(raw, ())
    try:
        params = VehicleParameters.model_validate(plain)
    except ValidationError as exc:
        raise ParameterError(_describe(exc, plain), where=origin) from None
    return ParameterSet(params, notes, origin)


def save_vehicle(pset: ParameterSet | VehicleParameters, path: str | Path) -> Path:
    """Write a parameter set as TOML, with its provenance notes next to the values."""
    if isinstance(pset, VehicleParameters):
        pset = ParameterSet(pset)
    data = pset.params.model_dump(mode="json", exclude_none=True)
    _merge_notes(data, pset.notes)
    path = Path(path)
    path.write_text(_to_toml(data), encoding="utf-8")
    return path


def _toml_value(value) -> str:
    if _is_annotated_value(value):
        return "{ " + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items()) + " }"
    return tomli_w.dumps({"v": value}).strip()[len("v = ") :]


def _to_toml(data: dict, header: tuple = ()) -> str:
    """TOML with provenance notes as inline tables next to their values (tomli_w alone would not)."""

    def is_table(v):
        return isinstance(v, dict) and not _is_annotated_value(v)

    def is_table_array(v):
        return isinstance(v, list) and v and all(isinstance(i, dict) for i in v)

    lines = [f"{k} = {_toml_value(v)}" for k, v in data.items() if not is_table(v) and not is_table_array(v)]
    out = ([f"[{'.'.join(header)}]"] if header and lines else []) + lines
    chunks = ["\n".join(out)] if out else []
    for key, value in data.items():
        if is_table(value):
            chunks.append(_to_toml(value, (*header, key)))
        elif is_table_array(value):
            for item in value:
                body = _to_toml(item).strip()
                chunks.append(f"[[{'.'.join((*header, key))}]]\n{body}")
    return "\n\n".join(c for c in chunks if c) + ("\n" if not header else "")


# ------------------------------------------------------------------------------------------------
def _read_raw(toml_text: str, origin: str, depth: int) -> dict:
    try:
        raw = tomllib.loads(toml_text)
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"invalid TOML: {exc}", where=origin) from None
    base_name = raw.pop("extends", None)
    if base_name is None:
        return raw
    if depth > 8:
        raise ParameterError("'extends' chain deeper than 8 (a cycle?)", where=origin)
    if not isinstance(base_name, str):
        raise ParameterError("extends: must be a preset name or a file path", where=origin)
    candidate = Path(origin).parent / base_name
    if base_name in list_presets():
        base_text, base_origin = (_preset_dir() / f"{base_name}.toml").read_text(encoding="utf-8"), base_name
    elif candidate.is_file():
        base_text, base_origin = candidate.read_text(encoding="utf-8"), str(candidate)
    else:
        hint = get_close_matches(base_name, list_presets(), n=1)
        tip = f"; did you mean '{hint[0]}'?" if hint else ""
        raise ParameterError(f"extends: no preset or file '{base_name}'{tip}", where=origin)
    return _deep_merge(_read_raw(base_text, base_origin, depth + 1), raw)


def _deep_merge(base, over):
    if isinstance(base, dict) and isinstance(over, dict):
        if _is_annotated_value(base) or _is_annotated_value(over):
            return over
        merged = dict(base)
        for key, value in over.items():
            merged[key] = _deep_merge(base[key], value) if key in base else value
        return merged
    if isinstance(base, list) and isinstance(over, list) and all(isinstance(i, dict) for i in base + over):
        by_name = {item.get("name"): item for item in base}
        merged = [_deep_merge(by_name[i["name"]], i) if i.get("name") in by_name else i for i in over]
        named = {i.get("name") for i in over}
        return [b for b in base if b.get("name") not in named] + merged
    return over


def _is_annotated_value(node) -> bool:
    return isinstance(node, dict) and "value" in node and set(node) <= {"value", *NOTE_KEYS}


def _split_notes(node, path):
    """Replace ``{value = x, assumed = "..."}`` by ``x``, collecting the notes by dotted path."""
    notes: dict[str, dict] = {}
    if _is_annotated_value(node):
        notes[".".join(path)] = {k: str(v) for k, v in node.items() if k != "value"}
        return node["value"], notes
    if isinstance(node, dict):
        out = {}
        for key, value in node.items():
            out[key], sub = _split_notes(value, (*path, key))
            notes.update(sub)
        return out, notes
    if isinstance(node, list):
        out = []
        for i, item in enumerate(node):
            label = item.get("name", str(i)) if isinstance(item, dict) else str(i)
            value, sub = _split_notes(item, (*path, str(label)))
            out.append(value)
            notes.update(sub)
        return out, notes
    return node, notes


def _merge_notes(data: dict, notes: dict) -> None:
    for dotted, note in notes.items():
        keys = dotted.split(".")
        node = data
        for key in keys[:-1]:
            if isinstance(node, list):
                node = next((item for item in node if item.get("name") == key), None)
            else:
                node = node.get(key)
            if node is None:
                break
        if isinstance(node, dict) and keys[-1] in node:
            node[keys[-1]] = {"value": node[keys[-1]], **note}


def _describe(exc: ValidationError, plain: dict) -> str:
    """One line for the first validation error of a parameter set."""
    return describe_validation_error(exc, plain, VehicleParameters)
