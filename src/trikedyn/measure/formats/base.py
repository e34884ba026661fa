"""The IMU log layouts' registry: :class:`LogFormat` (and :class:`TableFormat` for fixed-header text tables),
the file head the sniffers score, the read options, and :data:`FORMATS` with :func:`register`, :func:`get`,
:func:`detect`.

The layouts (one module each in this folder) import it; :mod:`trikedyn.measure.formats` re-exports it and
imports the layouts, so no layout imports the package that loads it.
"""

from __future__ import annotations

import contextlib
from abc import ABC, abstractmethod
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar

from ...errors import LogFormatError
from ...registry import Registry
from .. import _log_tables as tables

if TYPE_CHECKING:
    import pandas as pd

    from ..imu_log import ImuLog

__all__ = ["FORMATS", "Head", "LogFormat", "ReadOptions", "TableFormat", "available", "detect", "get", "register",
           "registered", "unregister"]

HEAD_BYTES = 4096  # how much of a file detection looks at


@dataclass(frozen=True)
class Head:
    """The first bytes of a file, as the sniffers see them.

    Attributes
    ----------
    raw : bytes
        The first 4096 bytes.
    binary : bool
        Whether they hold a NUL byte (then ``text`` and ``first`` are empty and ``sep`` is None).
    text : str
        ``raw`` decoded as UTF-8 (bad bytes replaced, no BOM).
    first : str
        The first non-blank line.
    sep : str or None
        The first of tab, ``,`` or ``;`` found in ``first``.
    keys : frozenset of str
        The fields of ``first`` reduced for matching: lower case, no spaces, ``°`` spelled ``deg``.
    """

    raw: bytes
    binary: bool
    text: str
    first: str
    sep: str | None
    keys: frozenset[str]

    @classmethod
    def of(cls, data: bytes | str) -> Head:
        """The head of a file's bytes or text.

        Parameters
        ----------
        data : bytes or str
            The file's content (the first ``HEAD_BYTES`` are used).

        Returns
        -------
        Head
            Raw bytes, whether binary, text, first line, separator and header keys.
        """
        raw = (data.encode("utf-8") if isinstance(data, str) else bytes(data))[:HEAD_BYTES]
        if b"\x00" in raw:
            return cls(raw, True, "", "", None, frozenset())
        text = raw.decode("utf-8", errors="replace").lstrip("\ufeff")
        first = next((line for line in text.replace("\r", "\n").split("\n") if line.strip()), "")
        sep = next((s for s in "\t,;" if s in first), None)
        keys = frozenset(tables._norm(h) for h in first.split(sep)) if sep else frozenset()
        return cls(raw, False, text, first, sep, keys)


@dataclass(frozen=True)
class ReadOptions:
    """What the caller of :func:`~trikedyn.measure.logs.read_log` asked for (already checked for range).

    ``columns`` and ``units`` hold the time column and its unit (``time_column=``, ``time_unit=``) under
    ``time_s``; ``delimiter`` is one of ``,`` ``;`` tab, ``decimal`` ``.`` or ``,`` (None: detected).
    """

    columns: dict[str, str] | None = None
    units: dict[str, str] | None = None
    sensor: int = 1
    sample_rate_hz: float | None = None
    delimiter: str | None = None
    decimal: str | None = None


class LogFormat(ABC):
    """One log layout. Subclass, set ``name`` and ``description``, implement ``sniff`` and ``read``.

    ``sniff`` scores a file's :class:`Head`: 0 or False when the layout does not fit, True counts as 1.
    The highest score wins detection (ties: the layout listed first by :func:`available`); the built-ins
    score 1-2 for their header lines, 0.5 for any separated header (generic ``csv``) and 100 for valid
    binary frames. ``read`` returns an :class:`~trikedyn.measure.logs.ImuLog` whose ``format`` is ``name``;
    ``write`` (optional) writes SI columns. ``takes_columns`` says whether the table options apply
    (``columns=``, ``units=``, ``time_column=``, ``time_unit=``, ``delimiter=``, ``decimal=``).
    ``order`` places the layout in :func:`available` (then registration order).
    """

    name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    takes_columns: ClassVar[bool] = False
    order: ClassVar[float] = 100.0

    def sniff(self, head: Head) -> float | bool:
        """Score how well the layout fits a file (0 here: a layout that never claims a file unasked).

        Parameters
        ----------
        head : Head
            The file's first bytes.

        Returns
        -------
        float or bool
            The score: 0 or False when the layout does not fit.
        """
        return 0.0

    @abstractmethod
    def read(self, raw: bytes, path: Path, options: ReadOptions) -> ImuLog:
        """The log in ``raw`` (the file's bytes) as an :class:`~trikedyn.measure.logs.ImuLog`; every layout
        reads.

        Parameters
        ----------
        raw : bytes
            The file's bytes.
        path : Path
            The file, for errors.
        options : ReadOptions
            What the caller asked for (sensor, rate [Hz], columns, units, ...).

        Returns
        -------
        ImuLog
            The log, SI columns (time [s], accelerations [m/s^2], rates [rad/s], angles [rad]).
        """

    def write(self, data: pd.DataFrame, path: Path) -> None:
        """Write ``data`` in this layout (here: refused, the layout can only be read).

        Parameters
        ----------
        data : pandas.DataFrame
            SI columns (``time_s`` [s] increasing, ...).
        path : Path
            The file to write.

        Raises
        ------
        LogFormatError
            For a layout that is read-only.
        """
        raise LogFormatError(f"format {self.name!r} can be read but not written; writable formats: "
                             f"{', '.join(n for n in available() if get(n).writable)}", where=str(path))

    @property
    def writable(self) -> bool:
        """Whether the layout can be written (its class overrides :meth:`write`)."""
        return type(self).write is not LogFormat.write

    def __repr__(self) -> str:
        return f"<log format {self.name!r}: {self.description}>"


class TableFormat(LogFormat):
    """A one-sensor text table with fixed headers: ``columns`` maps header -> (SI name, factor to SI).

    The SI name ``time_s`` marks the time column (numbers times the factor, or clock times); other
    columns are kept as extras. ``sniff`` scores 5 when every header of ``columns`` is in the first line.
    """

    sep: ClassVar[str] = ","
    encodings: ClassVar[tuple[str, ...]] = ("utf-8-sig",)
    columns: ClassVar[dict[str, tuple[str, float]]] = {}

    def sniff(self, head: Head) -> float:
        """5 when every header of ``columns`` is in the first line, else 0.

        Parameters
        ----------
        head : Head
            The file's first bytes.

        Returns
        -------
        float
            The score.
        """
        fields = {h.strip() for h in head.first.split(self.sep)}
        return 5.0 if head.sep and set(self.columns) <= fields else 0.0

    def read(self, raw: bytes, path: Path, options: ReadOptions) -> ImuLog:
        """The table as an :class:`~trikedyn.measure.logs.ImuLog`: the ``columns`` converted to SI, the others kept.

        Parameters
        ----------
        raw : bytes
            The file's bytes.
        path : Path
            The file, for errors.
        options : ReadOptions
            What the caller asked for (sensor, rate [Hz], columns, units, ...).

        Returns
        -------
        ImuLog
            The log, SI columns (time [s], accelerations [m/s^2], rates [rad/s], angles [rad]).
        """
        tables._one_sensor(options.sensor, self.name, path)
        header, cells, lines, at_header = tables._split_table(tables._decode(raw, path, self.encodings), self.sep,
                                                            path)
        missing = [h for h in self.columns if h not in header]
        if missing:
            raise LogFormatError(f"no column {', '.join(missing)}; columns present: {', '.join(header)}",
                                 where=at_header)
        spec = {si: (header.index(h), f) for h, (si, f) in self.columns.items()}
        notes: list[str] = []
        j, factor = spec.get(tables.TIME, (None, 1.0))
        if j is None:
            raise LogFormatError(f"format {self.name!r} declares no time column", where=str(path))
        t = tables._times(cells[j], header[j], lines, path, notes, factor=factor)
        return tables._table_log(path, self.name, t, header, cells, lines, spec, set(), notes)


def _adopt(registry: Registry, name: str, obj) -> None:
    """An entry point's object (a :class:`LogFormat` or its class) registered under its own name."""
    register(obj)


FORMATS: Registry[LogFormat] = Registry("format", group="trikedyn.log_formats", adopt=_adopt, error=LogFormatError)
"""The registered layouts (plug-ins: entry-point group ``trikedyn.log_formats``)."""


def register(fmt: LogFormat | type[LogFormat], *, replace: bool = False):
    """Add a layout (an instance, or a class that is instantiated); returns what it was given.

    Usable as a class decorator. A name already registered is an error unless ``replace=True``.

    Parameters
    ----------
    fmt : LogFormat or type of LogFormat
        The layout, or its class.
    replace : bool
        Replace a layout of the same name.

    Returns
    -------
    LogFormat or type
        ``fmt``.

    Raises
    ------
    ValueError
        Not a named layout, or a name taken.
    """
    obj = fmt() if isinstance(fmt, type) else fmt
    if not isinstance(obj, LogFormat) or not obj.name or obj.name == "auto":
        raise ValueError(f"expected a LogFormat with a name (not 'auto'), got {fmt!r}")
    FORMATS.register(obj.name, obj, replace=replace)
    return fmt


def unregister(name: str) -> LogFormat:
    """Remove the layout ``name`` and return it (KeyError if it is not registered).

    Parameters
    ----------
    name : str
        The layout's name.

    Returns
    -------
    LogFormat
        The layout removed.
    """
    return FORMATS.unregister(name)


@contextlib.contextmanager
def registered(fmt: LogFormat | type[LogFormat]) -> Iterator[LogFormat]:
    """Register ``fmt`` for the ``with`` block only (for tests); yields the registered instance.

    Parameters
    ----------
    fmt : LogFormat or type of LogFormat
        The layout, or its class.

    Yields
    ------
    LogFormat
        The registered instance.
    """
    obj = fmt() if isinstance(fmt, type) else fmt
    register(obj)
    try:
        yield obj
    finally:
        if obj.name in FORMATS and FORMATS.get(obj.name) is obj:
            FORMATS.unregister(obj.name)


def available() -> tuple[str, ...]:
    """The names of the registered layouts, built-ins first in their usual order.

    Returns
    -------
    tuple of str
        The names.
    """
    entries = FORMATS.items()
    rank = {name: (fmt.order, i) for i, (name, fmt) in enumerate(entries)}
    return tuple(sorted(rank, key=rank.__getitem__))


def get(name: str) -> LogFormat:
    """The layout registered as ``name`` (:class:`LogFormatError` with a close match if none).

    Parameters
    ----------
    name : str
        The layout's name.

    Returns
    -------
    LogFormat
        The layout.
    """
    return FORMATS.get(name)


def detect(data: bytes | str, name: str = "<data>") -> str:
    """The name of the layout that fits ``data`` (a file's bytes or text) best.

    Parameters
    ----------
    data : bytes or str
        The file's content.
    name : str
        Its name, for errors.

    Returns
    -------
    str
        The format's name.

    Raises
    ------
    LogFormatError
        If no layout fits; ``where`` is ``name`` and the message lists the known layouts.
    """
    head = Head.of(data)
    best, best_score = None, 0.0
    for fmt_name in available():
        score = float(get(fmt_name).sniff(head) or 0.0)
        if score > best_score:
            best, best_score = fmt_name, score
    if best is not None:
        return best
    known = f"known formats: {', '.join(available())}"
    if head.binary:
        raise LogFormatError(f"binary data that are not 0x55 WIT frames; cannot detect the format ({known})",
                             where=name)
    raise LogFormatError(f"cannot detect the format from the first line {head.first[:60]!r}; {known}",
                         where=name)

