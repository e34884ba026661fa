"""The registry of manoeuvres: one module per test registers itself here; everything else looks it up.

A manoeuvre module defines a builder ``build(params, speed_kmh, **options) -> Manoeuvre`` and registers
it::

    from trikedyn.manoeuvres.registry import Option, register

    @register("dlc", "ISO 3888-1 double lane change", options=(Option("run_in_m", 30.0, "m", "..."),))
    def build(params, speed_kmh, *, run_in_m):
        ...

Each option is stated once, in ``options`` (:class:`~trikedyn.options.Option`: default, unit, bounds,
help): the builder takes it as a keyword without a default (it is always given, the default filled in),
and the built manoeuvre records every option's value in its ``parameters`` (a value the builder records
itself, such as a width resolved from the vehicle, takes the place of the option's). Plug-ins from other
distributions register through the entry-point group ``trikedyn.manoeuvres`` (:mod:`trikedyn.registry`).

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
from dataclasses import replace as _with

from ..errors import InputError
from ..options import Option, find_option
from ..registry import Registry, did_you_mean, first_line

__all__ = ["MANOEUVRES", "ManoeuvreType", "Option", "available", "build", "get", "register", "parse_options"]


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
        """The option ``name``; an :class:`InputError` with a close match when it has none.

        Parameters
        ----------
        name : str
            The option's name.

        Returns
        -------
        Option
            The option (name, default, unit, bounds).
        """
        return find_option(self.options, name, f"manoeuvre '{self.name}'", "manoeuvre options")

    def build(self, params, speed_kmh: float, **options):
        """The manoeuvre for a vehicle at a target speed [km/h], options checked against the declared ones.

        Parameters
        ----------
        params : VehicleParameters
            The vehicle (its width lays out the lanes).
        speed_kmh : float
            Target speed [km/h], > 0 and <= 400.
        **options
            Option values (numbers, or text parsed by the options).

        Returns
        -------
        Manoeuvre
            The manoeuvre, its ``parameters`` holding every option's value.
        """
        speed = float(speed_kmh)
        if not math.isfinite(speed) or speed <= 0 or speed > 400:
            raise InputError(f"speed must be > 0 and <= 400 km/h, got {speed_kmh!r}", where="speed")
        values = {o.name: o.default for o in self.options}
        for key, value in options.items():
            values[key] = self.option(key).parse(value, where=f"{self.name}.{key}")
        man = self.builder(params, speed, **values)
        # the options are recorded as built; what the builder records itself (a resolved value) wins
        return _with(man, parameters={**values, **man.parameters})

    def to_dict(self) -> dict:
        """The manoeuvre type as JSON-safe data (``trikedyn manoeuvres --json``).

        Returns
        -------
        dict
            ``name``, ``title``, ``closed_loop``, ``summary`` and ``options`` (each with its unit and bounds).
        """
        return {"name": self.name, "title": self.title, "closed_loop": self.closed_loop, "summary": self.summary,
                "options": [o.to_dict() for o in self.options]}


def _load_builtins() -> None:
    from . import builtin  # noqa: F401  (its modules register themselves)


MANOEUVRES: Registry[ManoeuvreType] = Registry("manoeuvre", group="trikedyn.manoeuvres", builtins=_load_builtins,
                                               where="manoeuvre")
"""The registered manoeuvres (plug-ins: entry-point group ``trikedyn.manoeuvres``)."""


def register(name: str, title: str, *, options: tuple[Option, ...] = (), closed_loop: bool = True,
             summary: str = "", replace: bool = False):
    """Decorator: register ``build(params, speed_kmh, **options)`` under ``name``.

    The builder is called with every option's value (the defaults of :class:`Option` filled in), and the
    manoeuvre records them in its ``parameters``: an option is stated once, in ``options``.

    Parameters
    ----------
    name : str
        The manoeuvre's name.
    title : str
        Human title.
    options : tuple of Option
        The options the builder takes, with units and bounds.
    closed_loop : bool
        A path-following manoeuvre (True) or open-loop steer.
    summary : str
        One line; the builder's first docstring line by default.
    replace : bool
        Replace a manoeuvre of the same name.

    Returns
    -------
    callable
        The decorator (returns the builder unchanged).

    Raises
    ------
    ValueError
        When ``name`` is taken (pass ``replace=True`` to redefine it on purpose).
    """

    def decorate(builder):
        """Register ``builder`` as the manoeuvre ``name`` and return it unchanged."""
        MANOEUVRES.register(name, ManoeuvreType(name, title, builder, tuple(options), closed_loop,
                                                summary or first_line(builder, title)), replace=replace)
        return builder

    return decorate


def available() -> list[ManoeuvreType]:
    """Every registered manoeuvre, in registration order.

    Returns
    -------
    list of ManoeuvreType
        The manoeuvres.
    """
    return MANOEUVRES.values()


def get(name: str) -> ManoeuvreType:
    """The registered manoeuvre ``name``; an :class:`InputError` with a close match when unknown.

    Parameters
    ----------
    name : str
        A registered name.

    Returns
    -------
    ManoeuvreType
        The manoeuvre type.

    Raises
    ------
    InputError
        For an unknown name (with a close match and the known names).
    """
    try:
        return MANOEUVRES.get(name)
    except InputError:
        names = MANOEUVRES.names()
        raise InputError(f"unknown manoeuvre '{name}'" + did_you_mean(name, names)
                         + f" (known: {', '.join(names)}, or a path .csv)", where="manoeuvre") from None


def build(name: str, params, speed_kmh: float, **options):
    """Build manoeuvre ``name`` (or the path in a ``.csv`` file) for a vehicle at ``speed_kmh`` [km/h].

    Parameters
    ----------
    name : str
        A registered name, or a path ``.csv`` file.
    params : VehicleParameters
        The vehicle.
    speed_kmh : float
        Target speed [km/h].
    **options
        The manoeuvre's options.

    Returns
    -------
    Manoeuvre
        The manoeuvre.
    """
    if str(name).lower().endswith(".csv"):
        return get("path").build(params, speed_kmh, file=str(name), **options)
    return get(name).build(params, speed_kmh, **options)


def parse_options(pairs: list[str] | tuple[str, ...], where: str = "--option") -> dict[str, str]:
    """``["radius_m=15", "laps=2"]`` as a dict of text values (checked later by the manoeuvre's options).

    Parameters
    ----------
    pairs : list of str
        ``KEY=VALUE`` items.
    where : str
        The option named in errors.

    Returns
    -------
    dict of str to str
        Key -> text value.

    Raises
    ------
    InputError
        On an item that is not ``KEY=VALUE``.
    """
    out = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key.strip() or not value.strip():
            raise InputError(f"expected KEY=VALUE, got '{pair}'", where=where)
        out[key.strip()] = value.strip()
    return out
