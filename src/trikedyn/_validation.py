"""One-line messages for pydantic validation errors, shared by every validated input (vehicles, studies).

The message names the field by its path in the user's file (``wheels[front].radius_m``), says what is
expected, and for an unknown key suggests the closest known one.
"""

from __future__ import annotations

from pydantic import BaseModel, ValidationError

from .errors import did_you_mean

__all__ = ["describe_validation_error"]


def _model_in(annotation):
    """The BaseModel class inside an annotation like ``X``, ``tuple[X, ...]``, ``dict[str, X]``."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in getattr(annotation, "__args__", ()):
        found = _model_in(arg)
        if found is not None:
            return found
    return None


def _fields_at(root: type[BaseModel], loc) -> list[str]:
    """Field names of the section of ``root`` at a validation-error location."""
    model: type[BaseModel] | None = root
    for part in loc[:-1]:
        if model is None:
            return []
        if isinstance(part, int):
            continue
        info = model.model_fields.get(part)
        if info is None:  # a dict-valued section (suspension.<name>): keep the value model
            continue
        model = _model_in(info.annotation)
    return list(model.model_fields) if model is not None else []


def _loc_text(loc, raw) -> str:
    parts = []
    node = raw
    for part in loc:
        if isinstance(part, int):
            name = None
            if isinstance(node, list) and part < len(node) and isinstance(node[part], dict):
                name = node[part].get("name")
            parts.append(f"[{name or part}]")
            node = node[part] if isinstance(node, list) and part < len(node) else None
        else:
            parts.append(("." if parts else "") + str(part))
            node = node.get(part) if isinstance(node, dict) else None
    return "".join(parts) or "(top level)"


def describe_validation_error(exc: ValidationError, raw: dict, root: type[BaseModel]) -> str:
    """One line for the first validation error of ``raw`` against ``root``: the field and what is expected."""
    errors = exc.errors()
    # a typo shows as an unknown key *and* a missing one: the unknown key, with its hint, says more
    err = next((e for e in errors if e["type"] == "extra_forbidden"), errors[0])
    loc = tuple(p for p in err["loc"] if p not in ("function-after", "function-before"))
    kind = err["type"]
    if kind == "extra_forbidden":
        section = _loc_text(loc[:-1], raw) if len(loc) > 1 else "the top level"
        tip = did_you_mean(str(loc[-1]), _fields_at(root, loc), 0.5)
        return f"unknown key '{loc[-1]}' in {section}{tip}"
    where = _loc_text(loc, raw)
    if kind == "missing":
        return f"{where}: missing (required)"
    msg = err["msg"].removeprefix("Value error, ")
    got = err.get("input")
    shown = "" if isinstance(got, dict | list) or kind.startswith("value_error") else f" (got {got!r})"
    return f"{where}: {msg[0].lower() + msg[1:]}{shown}"
