"""The one generic registry: every extension point of trikedyn is a :class:`Registry` of named entries.

Manoeuvres (:mod:`trikedyn.manoeuvres.registry`), IMU log layouts (:mod:`trikedyn.measure.formats`), run
metrics (:mod:`trikedyn.analysis.metrics`), handling reducers (:mod:`trikedyn.analysis.handling_tests`),
study metrics (:mod:`trikedyn.study.metrics`) and tyre models (:mod:`trikedyn.tyre.models`) are each one
:class:`Registry`. They share one set of rules:

- **one name, one entry**: registering a name that is taken raises :class:`ValueError`, unless
  ``replace=True`` says it is meant;
- **one error for an unknown name**: :meth:`Registry.get` raises :class:`~trikedyn.errors.InputError`
  ``unknown manoeuvre 'dcl'; did you mean 'dlc'?`` (one close match, :func:`did_you_mean`);
- **options with units and bounds**: an entry's options are :class:`~trikedyn.options.Option` (name, default, unit, bounds,
  choices, help), parsed and checked by :meth:`~trikedyn.options.Option.parse`;
- **plug-ins by entry point**: an installed distribution that declares an entry point in the group
  ``trikedyn.<kind>`` (``trikedyn.manoeuvres``, ``trikedyn.log_formats``, ``trikedyn.metrics``,
  ``trikedyn.handling_reducers``, ``trikedyn.study_metrics``, ``trikedyn.tyre_models``) is loaded on the
  registry's first lookup or listing (and again for a name not found); loading imports the module, which
  registers itself, or, if it did not, the loaded object is handed to the registry's ``adopt``. A plug-in
  that fails to load is a :class:`PluginWarning` naming it, never a crash.

Example::

    from trikedyn.registry import Registry

    shapes = Registry("shape", group="trikedyn.shapes")

    @shapes.register("square")
    def square(side_m):
        return side_m**2
"""

from __future__ import annotations

import contextlib
import warnings
from collections.abc import Callable, Iterator
from typing import Any, Generic, TypeVar

from .errors import InputError, did_you_mean

__all__ = ["PluginWarning", "Registry", "did_you_mean", "first_line",
           "import_submodules"]

T = TypeVar("T")


class PluginWarning(UserWarning):
    """An entry-point plug-in of trikedyn failed to load (its name and the reason are in the message)."""


def first_line(obj, fallback: str = "") -> str:
    """The first line of ``obj``'s docstring (an entry's one-line help), or ``fallback`` when it has none.

    Parameters
    ----------
    obj : object
        A function or class.
    fallback : str
        What to return for an object without a docstring.

    Returns
    -------
    str
    """
    lines = (getattr(obj, "__doc__", None) or "").strip().splitlines()
    return lines[0] if lines else fallback


def import_submodules(package: str, path) -> None:
    """Import every public module of a package folder, in name order (built-ins that register themselves).

    Parameters
    ----------
    package : str
        The package's dotted name (its ``__name__``).
    path : list of str
        Its ``__path__``.
    """
    import importlib
    import pkgutil

    for info in sorted(pkgutil.iter_modules(path), key=lambda m: m.name):
        if not info.name.startswith("_"):
            importlib.import_module(f"{package}.{info.name}")


class Registry(Generic[T]):
    """Name -> entry, with one duplicate policy, one unknown-name error and entry-point plug-ins.

    Parameters
    ----------
    noun : str
        What an entry is, for messages (``"manoeuvre"``).
    group : str, optional
        The entry-point group of plug-ins (``"trikedyn.manoeuvres"``); None: no plug-ins.
    builtins : callable, optional
        Called once before the first lookup or listing (imports the built-in entries' modules).
    where : str, optional
        The ``where`` of the unknown-name error.
    adopt : callable, optional
        ``adopt(registry, name, obj)``: registers an object an entry point loaded when its module did not
        register ``name`` itself; by default the object is registered as it is.
    error : type, optional
        The :class:`~trikedyn.errors.InputError` subclass of the unknown-name error.
    """

    def __init__(self, noun: str, *, group: str | None = None, builtins: Callable[[], None] | None = None,
                 where: str | None = None, adopt: Callable[[Registry, str, Any], None] | None = None,
                 error: type[InputError] = InputError):
        self.noun = noun
        self.group = group
        self.where = where
        self.error = error
        self._builtins = builtins
        self._adopt = adopt
        self._entries: dict[str, T] = {}
        self._ready = False
        self._tried: set[tuple[str, str]] = set()

    # -- registering ---------------------------------------------------------------------------------------
    def register(self, name: str, entry: T | None = None, *, replace: bool = False):
        """Register ``entry`` under ``name``; without ``entry``, a decorator registering what it decorates.

        Parameters
        ----------
        name : str
            The registered name.
        entry : object, optional
            The entry; a decorator is returned without it.
        replace : bool
            Replace an entry of the same name.

        Returns
        -------
        The entry (or the decorator).

        Raises
        ------
        ValueError
            ``name`` is empty, or taken and ``replace`` is False.
        """
        if entry is None:
            def decorate(obj):
                """Register ``obj`` under the name given; returns it unchanged."""
                self.register(name, obj, replace=replace)
                return obj

            return decorate
        if not isinstance(name, str) or not name:
            raise ValueError(f"a {self.noun} needs a name, got {name!r}")
        if name in self._entries and not replace:
            raise ValueError(f"{self.noun} {name!r} is already registered (replace=True redefines it)")
        self._entries[name] = entry
        return entry

    def unregister(self, name: str) -> T:
        """Remove ``name`` and return its entry (:class:`KeyError` if it is not registered).

        Parameters
        ----------
        name : str
            The registered name.

        Returns
        -------
        object
            The entry removed.
        """
        return self._entries.pop(name)

    @contextlib.contextmanager
    def registered(self, name: str, entry: T) -> Iterator[T]:
        """Register ``entry`` for the ``with`` block only (tests); yields it.

        Parameters
        ----------
        name : str
            The registered name.
        entry : object
            The entry.

        Yields
        ------
        object
            ``entry``, registered until the block ends.
        """
        self.register(name, entry)
        try:
            yield entry
        finally:
            if self._entries.get(name) is entry:
                del self._entries[name]

    # -- looking up ----------------------------------------------------------------------------------------
    def get(self, name: str) -> T:
        """The entry ``name``.

        Parameters
        ----------
        name : str
            The registered name.

        Returns
        -------
        object
            The entry.

        Raises
        ------
        InputError
            ``unknown <noun> '<name>'; did you mean '<close>'?`` when it is not registered (after a search of
            the plug-ins installed since the last one); of the class given as ``error``.
        """
        self._load()
        if name not in self._entries:
            self._discover()
        if name in self._entries:
            return self._entries[name]
        raise self.error(self.unknown(name), where=self.where)

    def unknown(self, name: str) -> str:
        """The message for an unknown ``name``: ``unknown <noun> 'x'`` and one close match, or the known names.

        Parameters
        ----------
        name : str
            The unknown name.

        Returns
        -------
        str
            The message.
        """
        names = self.names()
        return f"unknown {self.noun} '{name}'" + (did_you_mean(str(name), names)
                                                   or (f"; known: {', '.join(names)}" if names else ""))

    def names(self) -> tuple[str, ...]:
        """The registered names, in registration order.

        Returns
        -------
        tuple of str
            The names.
        """
        self._load()
        return tuple(self._entries)

    def values(self) -> list[T]:
        """The registered entries, in registration order.

        Returns
        -------
        list
            The entries.
        """
        self._load()
        return list(self._entries.values())

    def items(self) -> list[tuple[str, T]]:
        """``(name, entry)`` pairs, in registration order.

        Returns
        -------
        list of tuple
            ``(name, entry)`` pairs.
        """
        self._load()
        return list(self._entries.items())

    def __contains__(self, name: object) -> bool:
        self._load()
        return name in self._entries

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())

    def __len__(self) -> int:
        return len(self.names())

    def __repr__(self) -> str:
        return f"<registry of {self.noun}s: {', '.join(self._entries)}>"

    # -- built-ins and plug-ins ----------------------------------------------------------------------------
    def _load(self) -> None:
        if self._ready:
            return
        self._ready = True  # before loading: a module that registers may look things up
        if self._builtins is not None:
            self._builtins()
        self._discover()

    def _discover(self) -> None:
        """Load the entry points of :attr:`group` not tried yet; one that fails is a warning."""
        if self.group is None:
            return
        from importlib.metadata import entry_points

        for point in entry_points(group=self.group):
            key = (point.name, point.value)
            if key in self._tried:
                continue
            self._tried.add(key)
            try:
                obj = point.load()
                if point.name not in self._entries:
                    if self._adopt is not None:
                        self._adopt(self, point.name, obj)
                    else:
                        self.register(point.name, obj)
            except Exception as exc:  # noqa: BLE001 - a broken plug-in must not stop the program
                warnings.warn(f"trikedyn: {self.noun} plug-in '{point.name}' ({point.value}, entry point group "
                              f"{self.group}) failed to load: {type(exc).__name__}: {exc}", PluginWarning,
                              stacklevel=3)
