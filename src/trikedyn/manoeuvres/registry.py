"""The registry of manoeuvres: one module per test registers itself here; everything else looks it up.

A manoeuvre module defines a builder ``build(params, speed_kmh, **options) -> Manoeuvre`` and registers
it::

    from trikedyn.manoeuvres.registry import Option, register

    @register("dlc", "ISO 3888-1 double lane change", options=(Option("run_in_m", 30.0, "m", "..."),))
    def build(params, speed_kmh, run_in_m=30.0):
        ...

``params`` is the vehicle's :class:`~trikedyn.params.schema.VehicleParameters` (some tests depend on the
vehicle: lane widths, the steer that gives 0.3 g). The command line (``simulate``, ``threshold``,
``handling``), the study spec and the report find manoeuvres by name with :func:`get` / :func:`build`,
and ``trikedyn manoeuvres`` lists them with their options. A name ending in ``.csv`` is a path file
(:mod:`trikedyn.manoeuvres.csv_path`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from difflib import get_close_matches

from ..errors import InputError, did_you_mean

__all__ = ["ManoeuvreType", "Option", "available", "build", "get", "register", "parse_options"]


@dataclass(frozen=True)
class Option:
    """One option of a manoeuvre: its name (with the unit in it), default, unit and meaning."""

    name: str
    default: float | str
    unit: str = ""
    help: str = ""
    choices: tuple[str, ...] = ()

    def parse(self, value, where: str):
        """``value`` (a number, or text from the command line) checked and converted."""
        if isinstance(self.default, str):
            text = str(value)
            if self.choices and text not in self.choices:
                raise InputError(f"expected one of {', '.join(self.choices)}, got {text!r}", where=where)
            return text
        if isinstance(value, bool):
            raise InputError(f"expected a number, got {value!r}", where=where)
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise InputError(f"expected a number, got {value!r}", where=where) from None
        if not math.isfinite(number):
            raise InputError(f"expected a finite number, got {value!r}", where=where)
        return number

    def to_dict(self) -> dict:
        out = {"name": self.name, "default": self.default, "unit": self.unit, "help": self.help}
        if self.choices:
            out["choices"] = list(self.choices)
        return out


@dataclass(frozen=True)
class ManoeuvreType:
    """A registered manoeuvre: its builder and what it accepts."""

    name: str
    title: str
    builder: Callable
    options: tuple[Option, ...] = ()
    closed_loop: bool = True
    summary: str = ""

    def option(self, name: str) -> Option:
        for opt in self.options:
            if opt.name == name:
                return opt
        names = [o.name for o in self.options]
        hint = get_close_matches(name, names, n=1)
        known = f"; it takes {', '.join(names)}" if names else "; it takes no options"
        raise InputError(f"manoeuvre '{self.name}' has no option '{name}'"
                         + (f"; did you mean '{hint[0]}'?" if hint else known), where="manoeuvre options")

    def build(self, params, speed_kmh: float, **options):
        """The manoeuvre for a vehicle at a target speed [km/h], options checked against the declared ones."""
        speed = float(speed_kmh)
        if not math.isfinite(speed) or speed <= 0 or speed > 400:
            raise InputError(f"speed must be > 0 and <= 400 km/h, got {speed_kmh!r}", where="speed")
        values = {o.name: o.default for o in self.options}
        for key, value in options.items():
            values[key] = self.option(key).parse(value, where=f"{self.name}.{key}")
        return self.builder(params, speed, **values)

    def to_dict(self) -> dict:
        return {"name": self.name, "title": self.title, "closed_loop": self.closed_loop, "summary": self.summary,
                "options": [o.to_dict() for o in self.options]}


_REGISTRY: dict[str, ManoeuvreType] = {}


def register(name: str, title: str, *, options: tuple[Option, ...] = (), closed_loop: bool = True,
             summary: str = "", replace: bool = False):
    """Decorator: register ``build(params, speed_kmh, **options)`` under ``name``.

    Raises
    ------
    ValueError
        When ``name`` is taken (pass ``replace=True`` to redefine it on purpose).
    """

    def decorate(builder):
        if name in _REGISTRY and not replace and _REGISTRY[name].builder is not builder:
            raise ValueError(f"manoeuvre '{name}' is registered already")
        doc = (builder.__doc__ or "").strip().splitlines()
        _REGISTRY[name] = ManoeuvreType(name, title, builder, tuple(options), closed_loop,
                                        summary or (doc[0] if doc else title))
        return builder

    return decorate


def _load_builtins() -> None:
    from . import builtin  # noqa: F401  (its modules register themselves)


def available() -> list[ManoeuvreType]:
    """Every registered manoeuvre, in registration order."""
    _load_builtins()
    return list(_REGISTRY.values())


def get(name: str) -> ManoeuvreType:
    """The registered manoeuvre ``name``; an :class:`InputError` with a close match when unknown."""
    _load_builtins()
    if name in _REGISTRY:
        return _REGISTRY[name]
    raise InputError(f"unknown manoeuvre '{name}'" + did_you_mean(name, list(_REGISTRY))
                     + f" (known: {', '.join(_REGISTRY)}, or a path .csv)", where="manoeuvre")


def build(name: str, params, speed_kmh: float, **options):
    """Build manoeuvre ``name`` (or the path in a ``.csv`` file) for a vehicle at ``speed_kmh`` [km/h]."""
    if str(name).lower().endswith(".csv"):
        return get("path").build(params, speed_kmh, file=str(name), **options)
    return get(name).build(params, speed_kmh, **options)


def parse_options(pairs: list[str] | tuple[str, ...], where: str = "--option") -> dict[str, str]:
    """``["radius_m=15", "laps=2"]`` as a dict of text values (checked later by the manoeuvre's options)."""
    out = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key.strip() or not value.strip():
            raise InputError(f"expected KEY=VALUE, got '{pair}'", where=where)
        out[key.strip()] = value.strip()
    return out
