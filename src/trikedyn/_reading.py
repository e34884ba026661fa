"""One bounded reader for every file a user names, and one rule for every file a file names.

Reading (:func:`open_binary`, :func:`read_bytes`, :func:`read_text`)
    Every input file that trikedyn reads for a user -- a vehicle file and what it ``extends``, a wheel's
    ``.tir``, a study or optimise spec and the vehicle or path CSV it names, a weighing record, an
    identification JSON, an IMU log, a path CSV given with ``--manoeuvre`` -- is read here, at most a stated
    number of bytes:

    1. ``os.stat`` (symbolic links followed): a missing file, a folder, a named pipe (FIFO), a device or a
       socket is refused before it is opened (opening a FIFO waits for a writer; opening a device may act
       on it), and a regular file larger than the bound is refused unread (a sparse file of terabytes
       costs nothing);
    2. ``os.open`` with ``O_NONBLOCK`` and ``O_NOCTTY``: a name swapped for a FIFO after the stat opens at
       once instead of waiting for a writer;
    3. ``os.fstat`` of the open file: it must still be a regular file, the one the stat saw;
    4. at most ``max_bytes + 1`` bytes are read: a file that grew beyond the bound (or a ``/proc`` file that
       reports a size of 0) is refused, never read to its end.

    Each refusal is one :class:`~trikedyn.errors.InputError` (of the subclass the caller chooses) naming the
    file; none shows the file's content.

Files named in files (:func:`named_file`)
    A path written *inside* a file -- ``extends``, a wheel's ``tyre_file``, a study spec's ``vehicle`` and its
    ``tyre_file`` overrides, an optimise spec's path CSV -- is relative to the folder of the file that names
    it and must lie in that folder or below it once symbolic links are resolved: no absolute path, no ``~``,
    no ``..``, no link that leads out. A preset or a built-in spec names shipped files only (its own folder
    in the package). A folder of files is so complete in itself, and a file from someone else reads nothing
    beside it. Paths typed on the command line are the user's own and may lie anywhere; every file, named
    either way, is read by the bounded reader.

Echoes (:func:`excerpt`)
    Where a message must quote a file's text (a cell that is not a number, a line that is not
    ``KEY = value``), it quotes at most a short excerpt, with anything unprintable escaped.
"""

from __future__ import annotations

import errno
import io
import os
import stat
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import BinaryIO

from .errors import InputError

__all__ = ["MAX_NAME_CHARS", "NamedFile", "excerpt", "file_problem", "named_file", "open_binary", "read_bytes",
           "read_text"]

MAX_NAME_CHARS = 1024
"""Longest path a file may name [characters] (each part of it at most 255 bytes, as file systems allow)."""

_FLAGS = (os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
          | getattr(os, "O_BINARY", 0))


def _kind(mode: int) -> str | None:
    """What a non-regular file is, in words (None for a regular file)."""
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a named pipe (FIFO)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "a special file"


def _amount(n: int) -> str:
    """A size in words: bytes, KiB, or MiB from 2 MiB up (1 MiB is ``1024 KiB``)."""
    if n >= 2 * 2**20:
        return f"{n / 2**20:g} MiB"
    if n >= 1024:
        return f"{n / 1024:g} KiB"
    return f"{n} bytes"


def _reason(exc: OSError) -> str:
    """The reason of a file-system error without the file name (which ``where`` gives)."""
    reason = exc.strerror or type(exc).__name__
    return reason[0].lower() + reason[1:]


def file_problem(path: str | os.PathLike) -> str | None:
    """Why ``path`` cannot be read as a file, in words (``"no such file"``, ``"is a named pipe (FIFO), not a
    regular file"``, ...), or None for an existing regular file. Nothing is opened."""
    try:
        mode = os.stat(path).st_mode
    except (FileNotFoundError, NotADirectoryError):
        return "no such file"
    except OSError as exc:
        return f"cannot open it: {_reason(exc)}"
    except ValueError:
        return "cannot open it: a name with a NUL byte"
    kind = _kind(mode)
    return None if kind is None else f"is {kind}, not a regular file"


class _Capped(io.RawIOBase):
    """An open file descriptor read at most ``limit`` bytes; one byte more raises ``exceeded()``."""

    def __init__(self, fd: int, limit: int, exceeded: Callable[[], Exception]):
        super().__init__()
        self._fd, self._limit, self._count, self._exceeded = fd, limit, 0, exceeded

    def readable(self) -> bool:
        """True: the file is open for reading."""
        return True

    def fileno(self) -> int:
        """The file descriptor."""
        return self._fd

    def readinto(self, buffer) -> int:
        """Read into ``buffer`` (at most one byte past the limit, which raises); the count read."""
        room = self._limit + 1 - self._count
        data = os.read(self._fd, max(0, min(len(buffer), room)))
        buffer[: len(data)] = data
        self._count += len(data)
        if self._count > self._limit:
            raise self._exceeded()
        return len(data)

    def close(self) -> None:
        """Close the file descriptor (once)."""
        if not self.closed:
            try:
                os.close(self._fd)
            finally:
                super().close()


def open_binary(path: str | os.PathLike, where: str | None = None, *, max_bytes: int,
                error: type[InputError] = InputError, expected: str = "", missing: str = "no such file",
                too_large: Callable[[int | None], str] | None = None) -> BinaryIO:
    """The regular file ``path`` opened for reading without blocking, read at most ``max_bytes`` (the steps
    of the module docstring); use it in a ``with`` block.

    Parameters
    ----------
    path : str or os.PathLike
    where : str, optional
        What errors name (default: ``path``).
    max_bytes : int
        Largest size read [bytes].
    error : type
        The :class:`~trikedyn.errors.InputError` subclass raised.
    expected : str
        What the file should be, for the refusals (``"a .tir tyre property file"``).
    missing : str
        The message for a file that does not exist (``"no such parameter file"``).
    too_large : callable, optional
        ``too_large(size)`` -> the message for a file over ``max_bytes`` (size in bytes, None when it grew
        while read); by default ``larger than N KiB``.

    Raises
    ------
    InputError
        ``error(..., where)``: missing, not a regular file, too large, cannot be opened or changed while
        being opened.
    """
    where = str(path) if where is None else where
    tail = f"; expected {expected}" if expected else ""

    def _refuse(message: str) -> InputError:
        """The error to raise, naming the file."""
        return error(message, where=where)

    def _over(size: int | None) -> InputError:
        """The error for a file over the bound (``size`` None: it grew while read)."""
        return _refuse(too_large(size) if too_large else f"larger than {_amount(max_bytes)}{tail}")

    try:
        before = os.stat(path)
    except (FileNotFoundError, NotADirectoryError):
        raise _refuse(missing) from None
    except OSError as exc:
        text = f"{missing} (a name too long)" if exc.errno == errno.ENAMETOOLONG else f"cannot open it: {_reason(exc)}"
        raise _refuse(text) from None
    except ValueError:
        raise _refuse(f"{missing} (a name with a NUL byte)") from None
    kind = _kind(before.st_mode)
    if kind is not None:
        raise _refuse(f"is {kind}, not a regular file{tail}")
    if before.st_size > max_bytes:
        raise _over(before.st_size)
    try:
        fd = os.open(path, _FLAGS)
    except OSError as exc:
        raise _refuse(f"cannot open it: {_reason(exc)}") from None
    try:
        after = os.fstat(fd)
        if _kind(after.st_mode) is not None or (after.st_dev, after.st_ino) != (before.st_dev, before.st_ino):
            raise _refuse(f"changed while being opened (now {_kind(after.st_mode) or 'another file'}); try again")
        if after.st_size > max_bytes:
            raise _over(after.st_size)
    except BaseException:
        os.close(fd)
        raise
    return io.BufferedReader(_Capped(fd, max_bytes, lambda: _over(None)))


def read_bytes(path: str | os.PathLike, where: str | None = None, *, max_bytes: int,
               error: type[InputError] = InputError, expected: str = "", missing: str = "no such file",
               too_large: Callable[[int | None], str] | None = None) -> bytes:
    """The bytes of the regular file ``path``, at most ``max_bytes`` (see :func:`open_binary` for the
    parameters and the refusals)."""
    where = str(path) if where is None else where
    with open_binary(path, where, max_bytes=max_bytes, error=error, expected=expected, missing=missing,
                     too_large=too_large) as fh:
        try:
            return fh.read()
        except OSError as exc:
            raise error(f"cannot read it: {_reason(exc)}", where=where) from None


def read_text(path: str | os.PathLike, where: str | None = None, *, max_bytes: int,
              error: type[InputError] = InputError, expected: str = "", missing: str = "no such file",
              too_large: Callable[[int | None], str] | None = None) -> str:
    """The UTF-8 text of the regular file ``path`` (a byte-order mark dropped), at most ``max_bytes``.

    Raises
    ------
    InputError
        As :func:`read_bytes`, and ``not UTF-8 text (REASON at byte N)``.
    """
    where = str(path) if where is None else where
    raw = read_bytes(path, where, max_bytes=max_bytes, error=error, expected=expected, missing=missing,
                     too_large=too_large)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(f"not UTF-8 text ({exc.reason} at byte {exc.start})", where=where) from None
    return text.removeprefix("\ufeff")


def excerpt(text: str, limit: int = 40) -> str:
    """``text`` quoted for a one-line message: at most ``limit`` characters, anything unprintable escaped,
    ``...`` where it was cut."""
    return repr(text[:limit]) + ("..." if len(text) > limit else "")


# ------------------------------------------------------------------------------------------------
# the rule for a file a file names
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class NamedFile:
    """A file named in a file, once the rule has allowed it.

    Attributes
    ----------
    path : Path
        The naming file's folder joined with the name as written: what messages show and what is read.
    real : Path
        The same with symbolic links resolved: the file's identity, whose folder is where a file it names
        in turn may reach.
    """

    path: Path
    real: Path


def _shown(name: str, limit: int = 60) -> str:
    """A name as written, for a message: unprintable characters escaped, cut at ``limit`` characters."""
    text = name if name.isprintable() else repr(name)[1:-1]
    return text if len(text) <= limit else text[: limit - 3] + "..."


def named_file(name, folder: str | os.PathLike, *, expected: str, where: str, key: str = "",
               place: str = "this file's folder", error: type[InputError] = InputError,
               suffixes: tuple[str, ...] = (), note: str = "") -> NamedFile:
    """Apply the rule (module docstring) to a path written in a file; nothing is opened.

    Parameters
    ----------
    name : object
        The value as written (a non-empty text is expected).
    folder : path
        The real folder of the file that names it (for a preset or a built-in spec, its folder in the package).
    expected : str
        What may be named, for the messages (``"a .tir file"``).
    where : str
        The error's ``where`` (the naming file, or ``wheels[front].tyre_file``).
    key : str
        The key it was written under, prefixed to the message (``"extends"``); none when ``where`` says it.
    place : str
        The folder in words (``"this file's folder"``, ``"the folder of the shipped presets"``).
    error : type
        The :class:`~trikedyn.errors.InputError` subclass raised.
    suffixes : tuple of str
        The suffixes allowed (lower case, with the dot); any when empty.
    note : str
        Appended to every message (``"(tyre file named in v.toml)"``).

    Returns
    -------
    NamedFile

    Raises
    ------
    InputError
        An absolute path (or ``~``), a path with ``..``, a backslash or a control character, a name too long,
        another suffix, a path that cannot be resolved (a loop of links) or leads out of ``folder``; the
        message shows the name as written (cut short, escaped), never where a link points.
    """
    usage = f"expected {expected} in {place} or below it"
    prefix = f"{key}: " if key else ""
    end = f" {note}" if note else ""
    if not isinstance(name, str) or not name.strip():
        raise error(f"{prefix}{usage}{end}", where=where)
    shown = _shown(name)
    rel = PurePosixPath(name)
    refused = (
        "an absolute path" if rel.is_absolute() or name.startswith("~") or name[1:2] == ":" else
        "a path with '..'" if ".." in rel.parts else
        "a name with a backslash or a control character" if "\\" in name or not name.isprintable() else
        "a name too long" if len(name) > MAX_NAME_CHARS or any(len(p.encode()) > 255 for p in rel.parts) else
        f"not a {' or '.join(suffixes)} file" if suffixes and rel.suffix.lower() not in suffixes else None
    )
    if refused:
        raise error(f"{prefix}'{shown}' is {refused}; {usage}{end}", where=where)
    base = Path(folder)
    try:
        real_base = base.resolve()
        real = (real_base / rel).resolve()
    except (OSError, RuntimeError, ValueError):  # a loop of symbolic links
        raise error(f"{prefix}'{shown}' cannot be resolved (a loop of symbolic links?); {usage}{end}",
                    where=where) from None
    if not real.is_relative_to(real_base):
        raise error(f"{prefix}'{shown}' leads out of {place} (a symbolic link); {usage}{end}", where=where)
    return NamedFile(base / rel, real)
