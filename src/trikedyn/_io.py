"""Safe outputs: never onto an input, never over an existing file without ``force``, never half-written.

Every file trikedyn writes for a user goes through :func:`check_output` (before any work is done, so a
long run does not end in a refusal) and :func:`atomic_write` (a temporary file in the same folder, renamed
into place: an interrupted write leaves the old file or none, never half a file). File-system failures
become an :class:`~trikedyn.errors.InputError` naming the path.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Callable, Iterable
from pathlib import Path

from .errors import InputError

__all__ = ["atomic_write", "check_output", "check_output_folder", "describe_os_error"]


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def describe_os_error(exc: OSError) -> str:
    """One line for a file-system error: its reason without the errno noise."""
    reason = exc.strerror or exc.__class__.__name__
    return reason[0].lower() + reason[1:] if reason else "cannot be accessed"


def check_output(path: str | os.PathLike, *, force: bool = False, reads: Iterable = (),
                 option: str | None = None) -> Path:
    """``path`` checked as an output file.

    Raises
    ------
    InputError
        When it is one of the files the command reads (``reads``), exists and ``force`` is not given, is a
        folder, or its folder does not exist.
    """
    path = Path(path)
    where = str(path)
    for source in reads:
        if source is not None and (_same_file(path, Path(source)) or path.resolve() == Path(source).resolve()):
            raise InputError(f"is also an input of this command; not writing onto it{_named(option)}", where=where)
    if path.is_dir():
        raise InputError("is a folder; expected a file name", where=where)
    if path.is_symlink() and not force:
        raise InputError("is a symbolic link; not writing through it (pass --force to replace the link)", where=where)
    if path.exists() and not force:
        raise InputError("exists; not overwriting it (pass --force to replace it)", where=where)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InputError("its folder does not exist" if not parent.exists() else "its parent is not a folder",
                         where=where)
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError("its folder is not writable", where=where)
    return path


def check_output_folder(path: str | os.PathLike, *, force: bool = False, option: str | None = None) -> Path:
    """``path`` checked as an output folder: created if missing; an existing non-empty one only with
    ``force`` (its files may be replaced)."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise InputError("exists and is not a folder", where=str(path))
    if path.is_dir() and any(path.iterdir()) and not force:
        raise InputError("is not empty; files in it would be replaced (pass --force to allow it)", where=str(path))
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create it: {describe_os_error(exc)}", where=str(path)) from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise InputError("is not writable", where=str(path))
    return path


def _named(option: str | None) -> str:
    return f" ({option})" if option else ""


def atomic_write(path: str | os.PathLike, write: Callable[[Path], object]) -> Path:
    """Write ``path`` through ``write(temporary_path)`` and rename it into place.

    The temporary file lies in the same folder (same file system: the rename is atomic) and keeps the
    suffix, so writers that look at it (pandas, matplotlib) choose the right format.
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=f".tmp{path.suffix}", dir=folder)
    except OSError as exc:
        raise InputError(f"cannot write here: {describe_os_error(exc)}", where=str(path)) from None
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        write(tmp_path)
        os.replace(tmp_path, path)
    except OSError as exc:
        raise InputError(f"cannot write it: {describe_os_error(exc)}", where=str(path)) from None
    finally:
        with contextlib.suppress(OSError):
            tmp_path.unlink()
    return path
