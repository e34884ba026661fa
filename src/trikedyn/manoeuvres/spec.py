"""A manoeuvre with its options, as one value that travels (the command line, a study spec, a run file).

:class:`ManoeuvreSpec` names a registered manoeuvre (``trikedyn manoeuvres``) or a path ``.csv`` file, and
the options it is built with, each checked against the manoeuvre's option table
(:class:`~trikedyn.options.Option`: unit, bounds, choices) when the value is made: an unknown option is an
:class:`~trikedyn.errors.InputError` naming it, with a close match. Options left out take their defaults
when the manoeuvre is built; the spec keeps only those given, so ``ManoeuvreSpec("dlc")`` and
``ManoeuvreSpec("dlc", {})`` are the same value.

In a study spec a manoeuvre is a name or a table with its options beside the name (as a metric is)::

    manoeuvres = ["slc", { name = "dlc", run_in_m = 40, direction = "right" }]
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ..errors import InputError

__all__ = ["ManoeuvreSpec", "manoeuvre_label"]


def _is_csv(name: str) -> bool:
    return str(name).lower().endswith(".csv")


def manoeuvre_label(name: str, options: Mapping[str, Any] | None = None) -> str:
    """A manoeuvre as a table or a figure shows it: ``dlc``, or ``dlc(run_in_m=40)`` with options.

    Parameters
    ----------
    name : str
        The manoeuvre's name (or a path ``.csv``).
    options : mapping, optional
        The options given (values in their units).

    Returns
    -------
    str
        The label; the bare name when no option is given.
    """
    if not options:
        return str(name)
    shown = ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in sorted(options.items()))
    return f"{name}({shown})"


@dataclass(frozen=True)
class ManoeuvreSpec:
    """A manoeuvre and the options it is built with.

    Parameters
    ----------
    name : str
        A registered manoeuvre (``dlc``: ISO 3888-1, ``slc``: ISO 14791, ...) or a path ``.csv`` file.
    options : mapping of str to float or str
        Options given (each in the unit of the manoeuvre's option table, e.g. ``run_in_m`` [m]); values may be
        text (``"40"``, from ``-o run_in_m=40``). Checked and converted when the spec is made.

    Raises
    ------
    InputError
        An unknown manoeuvre or option (with a close match), or a value out of the option's bounds.
    """

    name: str = "dlc"
    options: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        from .registry import get

        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError(f"expected a manoeuvre's name, got {self.name!r}", where="manoeuvre")
        kind = get("path") if _is_csv(self.name) else get(self.name)
        parsed = {}
        for key, value in dict(self.options).items():
            if _is_csv(self.name) and key == "file":
                raise InputError("the path file is the manoeuvre's name, not an option", where=f"{self.name}.file")
            parsed[key] = kind.option(key).parse(value, where=f"{self.name}.{key}")
        object.__setattr__(self, "options", dict(sorted(parsed.items())))

    def __hash__(self) -> int:
        return hash((self.name, tuple(self.options.items())))

    @classmethod
    def from_entry(cls, entry: str | Mapping[str, Any], where: str = "manoeuvres") -> ManoeuvreSpec:
        """The spec of a file's entry: a name, or a table ``{ name = "dlc", run_in_m = 40 }`` (typed values:
        a number option takes a number, not text).

        Parameters
        ----------
        entry : str or mapping
            The entry as the TOML file gives it.
        where : str
            What an error names (``manoeuvres[1]``).

        Returns
        -------
        ManoeuvreSpec
            The spec.

        Raises
        ------
        InputError
            A table without a ``name``, an unknown manoeuvre or option, a value of the wrong kind or out of
            bounds; one line naming ``where`` and the option.
        """
        if isinstance(entry, str):
            given: dict[str, Any] = {}
            name = entry
        elif isinstance(entry, Mapping):
            given = dict(entry)
            name = given.pop("name", None)
            if not isinstance(name, str):
                raise InputError(f"a manoeuvre table needs a name, e.g. {{ name = \"dlc\", run_in_m = 40 }}, got "
                                 f"{dict(entry)!r}", where=where)
        else:
            raise InputError(f"expected a manoeuvre name or a table {{ name = ..., option = value }}, got {entry!r}",
                             where=where)
        try:
            from .registry import get

            kind = get("path") if _is_csv(name) else get(name)
            for key, value in given.items():  # typed values, as a metric's options are read
                kind.option(key).parse(value, where=f"{name}.{key}", text=False)
            return cls(name, given)
        except InputError as exc:
            named = f"{exc.where}: " if exc.where and "." in exc.where else ""  # dlc.run_in_m, not "manoeuvre"
            raise InputError(named + exc.reason, where=where) from None

    @property
    def label(self) -> str:
        """``dlc`` or ``dlc(run_in_m=40)``: the manoeuvre as a table shows it (:func:`manoeuvre_label`)."""
        return manoeuvre_label(self.name, self.options)

    def with_options(self, **options) -> ManoeuvreSpec:
        """This manoeuvre with more options (they replace the ones of the same name).

        Parameters
        ----------
        **options
            Option values.

        Returns
        -------
        ManoeuvreSpec
            The new spec.
        """
        return ManoeuvreSpec(self.name, {**self.options, **options})

    def complete_options(self) -> dict:
        """Every option's value: the given ones and the defaults of the others (a path's ``file`` left out).

        Returns
        -------
        dict
            Option name -> value [its unit].
        """
        from .registry import get

        kind = get("path") if _is_csv(self.name) else get(self.name)
        values = {o.name: o.default for o in kind.options if not (_is_csv(self.name) and o.name == "file")}
        return values | self.options

    def build(self, params, speed_kmh: float):
        """The manoeuvre for a vehicle at a target speed (:func:`trikedyn.manoeuvres.registry.build`).

        Parameters
        ----------
        params : VehicleParameters
            The vehicle (its width lays out the lanes).
        speed_kmh : float
            Target speed [km/h].

        Returns
        -------
        Manoeuvre
            The manoeuvre, its ``parameters`` holding every option's value.
        """
        from .registry import build

        return build(self.name, params, speed_kmh, **self.options)

    def to_dict(self) -> dict:
        """The spec as JSON-safe data: ``{"name": ..., "options": {...}}``.

        Returns
        -------
        dict
            Name and the options given.
        """
        return {"name": self.name, "options": dict(self.options)}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> ManoeuvreSpec:
        """The spec from :meth:`to_dict`'s data (a run file's metadata, a plan).

        Parameters
        ----------
        data : mapping
            ``name`` and, optionally, ``options``.

        Returns
        -------
        ManoeuvreSpec
            The spec.
        """
        return cls(str(data["name"]), dict(data.get("options") or {}))
