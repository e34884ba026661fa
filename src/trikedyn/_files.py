"""Safe outputs on disk: never onto an input, never over a file without ``force``, never half-written,
never through a planted symbolic link.

Every file trikedyn writes for a user goes through here:

- :func:`check_output` / :func:`check_output_folder` check an output before any work is done (so a long
  run does not end in a refusal): not one of the command's inputs, not an existing file unless ``force``,
  in a folder that exists and can be written;
- an input is every file the command reads (:func:`inputs_of`): each one named in ``reads`` and, for a
  vehicle file, the files it reads in turn (the chain of files it ``extends``, every wheel's ``.tir``:
  :func:`trikedyn.params.files.vehicle_files`). An output folder is checked against the names the command
  writes in it (:func:`check_not_inputs`: ``sensitivity-samples.csv``, ``fig_*.png``, ...), so that a path CSV
  or an identification JSON that sits in ``--out`` under such a name is never replaced, not even with
  ``force`` (which only allows replacing earlier outputs). Two names are one file when they are the same
  file on disk (:func:`os.path.samefile`: symbolic and hard links) or resolve to the same path;

- :func:`ensure_folder` creates the folder; a path that cannot be a writable folder (its parent is a
  file, no permission, a read-only file system) is an :class:`~trikedyn.errors.InputError` naming it;
- :func:`refuse_symlink` refuses a symbolic link planted where the study keeps its lock, store or result
  tables (``out/results.csv -> ~/.bashrc``): the study never writes through one. The output folder itself
  may be a link; only the files in it are checked;
- :func:`atomic_write` writes a file to a fresh temporary name in the same folder (created exclusively,
  never through a link), flushes it to disk and renames it into place (``os.replace``): an interrupted
  write leaves the old file (or none) and no temporary file, never half a file.

The SQLite store (``study.sqlite``) has its own crash safety (:mod:`trikedyn.study.engine.store`).
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import IO

from .errors import InputError

__all__ = ["atomic_write", "check_not_inputs", "check_output", "check_output_folder", "describe_os_error",
           "ensure_folder", "inputs_of", "open_nofollow", "refuse_symlink"]


def describe_os_error(exc: OSError) -> str:
    """One line for a file-system error: its reason without the errno noise (``permission denied``)."""
    reason = exc.strerror or type(exc).__name__
    return reason[0].lower() + reason[1:]


def refuse_symlink(path: str | os.PathLike) -> Path:
    """``path``, after checking that it is not a symbolic link (a missing file is fine).

    Raises
    ------
    InputError
        ``path`` is a symbolic link (dangling or not).
    """
    path = Path(path)
    if path.is_symlink():
        raise InputError("is a symbolic link; not following it (remove it, or use another --out folder)",
                         where=str(path))
    return path


def _blocking_ancestor(folder: Path) -> Path | None:
    """The nearest existing ancestor of ``folder`` (or itself) that is not a folder, if any."""
    try:
        for candidate in (folder, *folder.parents):
            if candidate.exists() or candidate.is_symlink():
                return None if candidate.is_dir() else candidate
    except OSError:  # a parent we may not look into: mkdir says why
        return None
    return None


def ensure_folder(folder: str | os.PathLike) -> Path:
    """Create ``folder`` (and its parents) if missing.

    Raises
    ------
    InputError
        Naming the folder: it, or one of its parents, is a file; it cannot be created (no permission, a
        read-only file system, ...); it exists but this user may not write into it.
    """
    folder = Path(folder)
    where = str(folder)
    blocker = _blocking_ancestor(folder)
    if blocker is not None:
        what = "exists and is not a folder" if blocker == folder else f"cannot be created: '{blocker}' is not a folder"
        raise InputError(what, where=where)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:  # PermissionError, read-only file system, a race with another process, ...
        raise InputError(f"cannot create this folder ({describe_os_error(exc)})", where=where) from None
    if not folder.is_dir():  # a dangling symbolic link, or a file made meanwhile
        raise InputError("exists and is not a folder", where=where)
    if not os.access(folder, os.W_OK | os.X_OK):  # root passes, unless the file system is read-only
        raise InputError(f"cannot write into this folder ({_why_not_writable(folder)})", where=where)
    return folder


def _why_not_writable(folder: Path) -> str:
    with contextlib.suppress(OSError, AttributeError):
        if os.statvfs(folder).f_flag & os.ST_RDONLY:
            return "read-only file system"
    return "permission denied"


def open_nofollow(path: str | os.PathLike) -> int:
    """Open (create if missing) ``path`` for reading and writing without following a symbolic link.

    Returns
    -------
    int
        The file descriptor (the caller closes it).

    Raises
    ------
    InputError
        ``path`` is a symbolic link, or cannot be opened (naming it, with the reason).
    """
    path = refuse_symlink(path)
    flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        return os.open(path, flags, 0o666)
    except OSError as exc:
        if path.is_symlink():  # planted between the check and the open: O_NOFOLLOW refused it
            refuse_symlink(path)
        raise InputError(f"cannot open ({describe_os_error(exc)})", where=str(path)) from None


def _fsync_folder(folder: Path) -> None:
    with contextlib.suppress(OSError):  # not every file system lets a folder be opened or synced
        fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _create_temporary(path: Path) -> tuple[int, Path]:
    """A new file ``.<name>.<random>.tmp`` next to ``path``: created exclusively (never an existing file or a
    link), with the permissions a plain ``open`` would give (0o666 less the umask; ``mkstemp`` gives 0o600)."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
    for _ in range(100):
        tmp = path.with_name(f".{path.name}.{secrets.token_hex(6)}.tmp")
        try:
            return os.open(tmp, flags, 0o666), tmp
        except FileExistsError:
            continue
    raise FileExistsError(errno.EEXIST, "no free temporary file name", str(path))


def atomic_write(path: str | os.PathLike, write: Callable[[IO], object], *, binary: bool = True) -> Path:
    """Write ``path`` atomically: ``write(fh)`` fills a temporary file in the same folder, then it is renamed.

    Parameters
    ----------
    path : path
        The file to (re)place. A symbolic link there is refused, not followed.
    write : callable
        Called with the open temporary file (binary, or UTF-8 text with ``newline=""`` if ``binary`` is
        False); it writes the whole content.
    binary : bool
        Binary or text file.

    Raises
    ------
    InputError
        ``path`` is a symbolic link, or the file system refuses the write (naming ``path``, with the
        reason). Whatever ``write`` raises otherwise propagates. In every case the old file is left as it
        was and the temporary file is removed.
    """
    path = refuse_symlink(path)
    folder = path.parent
    try:
        fd, tmp = _create_temporary(path)
    except OSError as exc:
        raise InputError(f"cannot write ({describe_os_error(exc)})", where=str(path)) from None
    try:
        with os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        refuse_symlink(path)  # planted while we wrote: os.replace would not follow it, but say so
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, OSError):
            raise InputError(f"cannot write ({describe_os_error(exc)})", where=str(path)) from None
        raise
    _fsync_folder(folder)
    return path


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def _resolved(path: Path) -> Path:
    try:
        return path.resolve()
    except (OSError, RuntimeError, ValueError):  # a loop of symbolic links, a name the system refuses
        return path.absolute()


def _is_one(a: Path, b: Path) -> bool:
    """Whether the names ``a`` and ``b`` are one file: the same file on disk, or the same resolved path."""
    return _same_file(a, b) or _resolved(a) == _resolved(b)


def inputs_of(reads: Iterable) -> list[tuple[Path, str | None]]:
    """Every file behind the inputs ``reads`` of a command, each with what it is (None: as named).

    ``reads`` holds paths (None entries are skipped). A ``.toml`` file among them is taken as a vehicle file:
    the files it reads are added (:func:`trikedyn.params.files.vehicle_files`: its ``extends`` chain and
    its wheels' tyre files). A file that is no vehicle file adds nothing.
    """
    found: list[tuple[Path, str | None]] = []
    for source in reads:
        if source is None:
            continue
        path = Path(os.fspath(source))
        found.append((path, None))
        if path.suffix.lower() == ".toml":
            from .params.files import vehicle_files

            found += [(file, why) for file, why in vehicle_files(path)[1:]]
    return found


def _refuse_input(path: Path, inputs: list[tuple[Path, str | None]], option: str | None) -> None:
    for source, why in inputs:
        if _is_one(path, source):
            what = f" ({why})" if why else ""
            other = f"; use another {option}" if option else ""
            raise InputError(f"is also an input of this command{what}; not writing onto it, not even with "
                             f"--force{other}", where=str(path))


def check_not_inputs(folder: str | os.PathLike, writes: Iterable[str], reads: Iterable = (),
                     option: str | None = "--out") -> None:
    """Refuse an output folder in which a file the command would write is one of the files it reads.

    Parameters
    ----------
    folder : path
        The output folder (it need not exist).
    writes : iterable of str
        The names the command writes in ``folder``; a name may be a pattern (``fig_*.png``,
        :mod:`fnmatch`).
    reads : iterable of path
        The command's inputs, expanded by :func:`inputs_of`.
    option : str, optional
        The option that names the folder, for the message.

    Raises
    ------
    InputError
        Naming the output file that is an input, and what it is (``is an input of this command (extended by
        child.toml)``); regardless of ``force``.
    """
    import fnmatch
    import glob

    folder = Path(folder)
    inputs = inputs_of(reads)
    if not inputs:
        return
    here = _resolved(folder)
    for name in writes:
        if not glob.has_magic(name):
            _refuse_input(folder / name, inputs, option)
            continue
        for source, _ in inputs:  # an input named by this pattern, in this folder
            if fnmatch.fnmatchcase(source.name, name) and _resolved(source).parent == here:
                _refuse_input(folder / source.name, inputs, option)
        with contextlib.suppress(OSError):  # an existing output that is an input by another name (a link)
            for existing in (folder.glob(name) if folder.is_dir() else ()):
                _refuse_input(existing, inputs, option)


def check_output(path: str | os.PathLike, *, force: bool = False, reads: Iterable = (),
                 option: str | None = None) -> Path:
    """``path`` checked as an output file.

    Raises
    ------
    InputError
        When it is one of the files the command reads (``reads``, expanded by :func:`inputs_of`: a vehicle
        file's ``extends`` chain and tyre files count; even with ``force``), exists and ``force`` is not
        given, is a folder, or its folder does not exist.
    """
    path = Path(path)
    where = str(path)
    _refuse_input(path, inputs_of(reads), option)
    if path.is_dir():
        raise InputError("is a folder; expected a file name", where=where)
    refuse_symlink(path)
    if path.exists() and not force:
        raise InputError("exists; not overwriting it (pass --force to replace it)", where=where)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InputError("its folder does not exist" if not parent.exists() else "its parent is not a folder",
                         where=where)
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError("its folder is not writable", where=where)
    return path


def check_output_folder(path: str | os.PathLike, *, force: bool = False, option: str | None = None,
                        reads: Iterable = (), writes: Iterable[str] = ()) -> Path:
    """``path`` checked as an output folder: created if missing; an existing non-empty one only with
    ``force`` (its files may be replaced); never one in which a name of ``writes`` is a file of ``reads``
    (:func:`check_not_inputs`, whatever ``force``)."""
    path = Path(path)
    check_not_inputs(path, writes, reads, option)
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

