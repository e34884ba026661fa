"""What the command modules share: option types, range checks, output (text or valid JSON), figures."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError

__all__ = ["ForceOpt", "JsonOpt", "ManoeuvreOpt", "OptionOpt", "VehicleArg", "WARNINGS", "emit", "finite",
           "json_default", "manoeuvre_options", "save_figure", "within"]


def within(low: float, high: float, unit: str = "", *, above: bool = False):
    """Typer callback: the option's value must be finite and within ``[low, high]`` (``(low, high]`` with
    ``above``); None passes (an option left out)."""

    def check(ctx: typer.Context, param: typer.CallbackParam, value):
        if value is None or ctx.resilient_parsing:
            return value
        name = max(param.opts, key=len) if param.opts else param.name
        number = float(value)
        ok = math.isfinite(number) and (number > low if above else number >= low) and number <= high
        if not ok:
            bound = f"{'>' if above else '>='} {low:g} and <= {high:g}"
            raise InputError(f"must be {bound}{' ' + unit if unit else ''}, got {value!r}", where=name)
        return value

    return check


JsonOpt = Annotated[bool, typer.Option("--json", help="Print machine-readable JSON instead of text.")]
ForceOpt = Annotated[bool, typer.Option("--force", help="Replace output files that exist already.")]
VehicleArg = Annotated[str, typer.Argument(help="Preset name (see `trikedyn vehicle list`) or a .toml file.")]


WARNINGS: list[str] = []
"""Warnings raised while a command runs (printed as one line each, and listed under ``warnings`` in JSON)."""


def emit(data, as_json: bool, text=None) -> None:
    """Print a command's result: JSON (always valid: non-finite numbers become null, with a warning), or
    ``text`` (a string, or a function of nothing that makes it: text is only formatted when asked for)."""
    if as_json:
        clean, bad = finite(data)
        if isinstance(clean, dict) and (bad or WARNINGS):
            notes = [*WARNINGS, *(f"{p or 'value'}: non-finite number replaced by null" for p in bad)]
            clean = {**clean, "warnings": [*clean.get("warnings", []), *notes]}
        typer.echo(json.dumps(clean, indent=2, default=json_default, allow_nan=False))
    elif text is not None:
        typer.echo(text() if callable(text) else text)
    else:
        typer.echo(json.dumps(finite(data)[0], indent=2, default=json_default, allow_nan=False))


def json_default(obj):
    import numpy as np

    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def finite(node, path: str = ""):
    """``node`` with every non-finite float replaced by None, and the paths where that happened."""
    import math

    if isinstance(node, dict):
        out, bad = {}, []
        for key, value in node.items():
            out[key], sub = finite(value, f"{path}.{key}" if path else str(key))
            bad += sub
        return out, bad
    if isinstance(node, list | tuple):
        out, bad = [], []
        for i, value in enumerate(node):
            item, sub = finite(value, f"{path}[{i}]")
            out.append(item)
            bad += sub
        return out, bad
    if hasattr(node, "tolist") and not isinstance(node, str):  # numpy arrays and scalars
        return finite(node.tolist(), path)
    if isinstance(node, float) and not math.isfinite(node):
        return None, [path]
    return node, []


OptionOpt = Annotated[
    list[str], typer.Option("--option", "-o", help="A manoeuvre option KEY=VALUE (see `trikedyn manoeuvres`); repeatable.")
]
ManoeuvreOpt = Annotated[
    str, typer.Option("--manoeuvre", help="A registered manoeuvre (see `trikedyn manoeuvres`: dlc, slc, circle, step, "
                      "fishhook, ...) or a path .csv file.")
]


def manoeuvre_options(manoeuvre: str, pairs: list[str], **legacy) -> dict:
    """``-o KEY=VALUE`` pairs, plus the older shortcuts (``--radius``, ``--steer-deg``) where the manoeuvre
    takes that option."""
    from ..manoeuvres.registry import get, parse_options

    options = parse_options(pairs)
    if manoeuvre.lower().endswith(".csv"):
        return options
    try:
        kind = get(manoeuvre)
    except InputError as exc:
        raise InputError(exc.reason, where="--manoeuvre") from None
    for key, value in legacy.items():
        if value is not None and key not in options and any(o.name == key for o in kind.options):
            options[key] = value
    return options


def save_figure(fig, path: Path, dpi: int = 110) -> None:
    """Save a matplotlib figure atomically and close it (:func:`trikedyn.report.figures.save`)."""
    from ..report.figures import save

    save(fig, path, dpi=dpi)
