"""In-place update of a few values of a vehicle file, everything else kept as written.

``trikedyn identify LOG --into FILE --suspension NAME`` is the one command that writes onto a file it reads:
it puts the identified K, C, f_n and xi, each with its provenance, into ``[suspension.NAME]`` of the user's
vehicle file. Why not :func:`~trikedyn.params.save.save_vehicle`: it writes the whole merged set, so a file that
``extends`` a preset would become a full copy of it, and the file's comments, its layout and its order would
be lost. Here only the lines of the keys set change: an existing ``key = ...`` line of the table is replaced
(a comment after it kept), a missing key is added at the end of the table, a missing table at the end of the
file. The result is then read back and must equal the old set with exactly those values and notes changed,
nothing else; a file written in a form this edit does not handle (the table as dotted keys or an inline
table, a key in a multi-line string) fails that check and is refused, unchanged.

The rules, checked before anything is written (:func:`check_vehicle_target`): a preset name is refused (write it
to a file first, ``trikedyn vehicle export``), as are a missing file, a symbolic link, a read-only file and a
folder that cannot be written. A value that the file itself sets with another source (another log, the paper,
a hand-written value) is replaced only with ``force``; values the file inherits through ``extends`` are
overridden without it (that is what the file is for). The file is written atomically (a temporary file
renamed into place, :func:`~trikedyn._files.atomic_write`) with its permissions kept, and not at all if it
changed on disk while the update ran.
"""

from __future__ import annotations

import os
import re
import stat
import tomllib
from collections.abc import Callable, Mapping
from pathlib import Path

import tomli_w

from .._files import atomic_write, describe_os_error
from ..errors import InputError, ParameterError
from .io import ParameterSet, parse_vehicle
from .shipped import list_presets
from .tomlfile import is_file, parse_toml, read_text

__all__ = ["check_vehicle_target", "read_vehicle_target", "set_table_lines", "update_vehicle_file"]

_HEADER = re.compile(r"^\s*\[(?!\[)\s*(?P<name>[^\]]+?)\s*\]\s*(#.*)?$")
_ANY_HEADER = re.compile(r"^\s*\[")


def check_vehicle_target(path: str | os.PathLike, *, reads=(), option: str = "--into") -> Path:
    """``path`` checked as a vehicle file to update in place: an existing regular ``.toml`` file (not a preset
    name, not a symbolic link), writable, in a writable folder, and none of ``reads`` (the command's other
    inputs).

    Parameters
    ----------
    path : str or os.PathLike
        The vehicle file.
    reads : iterable of path
        The command's other inputs.
    option : str
        The option named in errors.

    Returns
    -------
    Path
        The checked path.

    Raises
    ------
    InputError
        One line naming ``path`` (or ``option`` for a preset name) and what to do.
    """
    text = str(path)
    path = Path(path)
    if path.is_symlink():
        raise InputError("is a symbolic link; not updating through it (give the file it points to)", where=text)
    if not is_file(path):
        if text in list_presets():
            raise InputError(f"'{text}' is a preset, which is never changed: write it to a file first (trikedyn "
                             f"vehicle export {text} my-trike.toml) and give that file", where=option)
        raise InputError("no such vehicle file; expected an existing .toml file to update", where=text)
    for source in reads:
        try:
            same = source is not None and Path(source).exists() and os.path.samefile(path, source)
        except OSError:
            same = False
        if same:
            raise InputError(f"is also an input of this command; {option} names the vehicle file to update",
                             where=text)
    mode = path.stat().st_mode
    if not mode & (stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH) or not os.access(path, os.W_OK):
        raise InputError("is read-only; not updating it (make it writable first)", where=text)
    folder = path.parent if str(path.parent) else Path(".")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError("its folder is not writable (the update writes a temporary file beside it)", where=text)
    return path


def read_vehicle_target(path: Path) -> tuple[str, ParameterSet, os.stat_result]:
    """The text, the parameter set and the ``stat`` of a vehicle file about to be updated.

    Parameters
    ----------
    path : Path
        The vehicle file.

    Returns
    -------
    text : str
        Its text.
    pset : ParameterSet
        The parameter set parsed from it.
    stat : os.stat_result
        Its ``stat`` before the update.
    """
    where = str(path)
    before = path.stat()
    text = read_text(path, where, error=ParameterError)
    return text, parse_vehicle(text, where), before


def _key_of(line: str) -> str | None:
    """The bare key of a ``key = value`` line (quotes taken off), or None."""
    match = re.match(r"""^\s*(?P<q>["']?)(?P<key>[A-Za-z0-9_-]+)(?P=q)\s*=""", line)
    return match.group("key") if match else None


def _trailing_comment(line: str, key: str) -> str:
    """A comment after the value of ``key = value  # comment``, or ``""``."""
    body = line.rstrip("\r\n")
    for i, char in enumerate(body):
        if char == "#":
            try:
                if key in tomllib.loads(body[:i]):
                    return body[i:]
            except tomllib.TOMLDecodeError:
                continue
    return ""


def set_table_lines(text: str, table: tuple[str, ...], lines: Mapping[str, str]) -> str:
    """``text`` with the ``key = ...`` line of each key of ``lines`` in the table ``[a.b]`` (``table``) replaced
    by ``lines[key]`` (a comment after the old value kept), the missing keys added after the table's last
    key, and the table added at the end of the file if it has no ``[a.b]`` header.

    Text only: the caller reads the result back to check it (a table written as dotted keys or an inline
    table elsewhere makes a file that is not valid TOML, or not the same set).

    Parameters
    ----------
    text : str
        The TOML text.
    table : tuple of str
        The table's path (``("a", "b")`` for ``[a.b]``).
    lines : Mapping of str to str
        Key -> its new ``key = value`` line.

    Returns
    -------
    str
        The new text.
    """
    rows = text.splitlines(keepends=True)
    newline = "\r\n" if rows and rows[0].endswith("\r\n") else "\n"
    start = None
    for i, row in enumerate(rows):
        match = _HEADER.match(row)
        if match and tuple(p.strip().strip("\"'") for p in match.group("name").split(".")) == table:
            start = i
            break
    if start is None:
        body = "".join(f"{line}{newline}" for line in lines.values())
        gap = "" if not text or text.endswith("\n\n") else newline if text.endswith("\n") else newline * 2
        return f"{text}{gap}[{'.'.join(table)}]{newline}{body}"
    end = next((j for j in range(start + 1, len(rows)) if _ANY_HEADER.match(rows[j])), len(rows))
    todo = dict(lines)
    last = start
    for j in range(start + 1, end):
        key = _key_of(rows[j])
        if key is None:
            continue
        last = j
        if key in todo:
            comment = _trailing_comment(rows[j], key)
            indent = rows[j][: len(rows[j]) - len(rows[j].lstrip())]
            rows[j] = f"{indent}{todo.pop(key)}{'  ' + comment if comment else ''}{newline}"
    if todo:
        if not rows[last].endswith(("\n", "\r")):
            rows[last] += newline
        rows[last + 1:last + 1] = [f"{line}{newline}" for line in todo.values()]
    return "".join(rows)


def _toml_line(key: str, value: float, source: str) -> str:
    """``key = { value = ..., source = "..." }``, the number and the text as TOML writes them."""
    number = tomli_w.dumps({"v": float(value)})[4:].strip()
    return f"{key} = {{ value = {number}, source = {tomli_w.dumps({'s': source})[4:].strip()} }}"


def update_vehicle_file(path: str | os.PathLike, table: tuple[str, ...], values: Mapping[str, tuple[float, str]], *,
                        force: bool = False, replaceable: Callable[[str | None], bool] | None = None) -> list[str]:
    """Set ``values`` (key -> (value, source)) in the table ``table`` of the vehicle file ``path``, in place.

    Parameters
    ----------
    path : path
        The vehicle file (checked with :func:`check_vehicle_target` by the caller).
    table : tuple of str
        The table's path, e.g. ``("suspension", "front")``.
    values : mapping
        Key -> (number, its ``source`` note).
    force : bool
        Replace values the file itself sets with a source that ``replaceable`` refuses.
    replaceable : callable, optional
        ``replaceable(source)`` is True for a source (None: a value without one) that may be replaced
        without ``force``; by default none may.

    Returns
    -------
    list of str
        The dotted keys the file itself set before and that were replaced.

    Raises
    ------
    InputError
        A value set here with another source and no ``force`` (naming it), a file this edit cannot update
        faithfully, a file changed on disk meanwhile, a write that fails. The file is left as it was.
    """
    path = Path(path)
    where = str(path)
    text, old, before = read_vehicle_target(path)
    own = parse_toml(text, where, error=ParameterError)
    node = own
    for part in table:
        node = node.get(part, {}) if isinstance(node, dict) else {}
    dotted = ".".join(table)
    replaced = []
    for key in values:
        if not isinstance(node, dict) or key not in node:
            continue
        current = node[key]
        source = current.get("source") if isinstance(current, dict) else None
        replaced.append(f"{dotted}.{key}")
        if not force and not (replaceable or (lambda _: False))(source):
            said = f"source '{source[:60]}{'...' if len(source) > 60 else ''}'" if source else "no source"
            raise InputError(f"{dotted}.{key} is set in this file ({said}); not replacing it (pass --force to "
                             "replace it and its provenance)", where=where)
    new_text = set_table_lines(text, table, {k: _toml_line(k, v, s) for k, (v, s) in values.items()})
    try:
        new = parse_vehicle(new_text, where)
    except ParameterError as exc:
        raise InputError(f"cannot update [{dotted}] in place ({exc}); the file writes it in a form this update "
                         f"does not edit (dotted keys or an inline table): write it as a [{dotted}] table", where=where
                         ) from None
    expected = old.params.model_dump(mode="json")
    section = expected
    for part in table:
        section = section[part]
    section.update({k: v for k, (v, _) in values.items()})
    notes = {k: v for k, v in old.notes.items() if not any(k == f"{dotted}.{key}" for key in values)}
    notes |= {f"{dotted}.{k}": {"source": s} for k, (_, s) in values.items()}
    if new.params.model_dump(mode="json") != expected or new.notes != notes:
        raise InputError(f"cannot update [{dotted}] in place: the edited file would change more than "
                         f"{', '.join(values)} (the table is written in a form this update does not edit); edit "
                         "it by hand", where=where)
    now = path.stat()
    if (now.st_mtime_ns, now.st_size, now.st_ino) != (before.st_mtime_ns, before.st_size, before.st_ino):
        raise InputError("changed on disk while it was being updated; not writing (run the command again)",
                         where=where)
    atomic_write(path, lambda fh: fh.write(new_text), binary=False)
    try:
        os.chmod(path, stat.S_IMODE(before.st_mode))
    except OSError as exc:
        raise InputError(f"updated, but its permissions could not be restored ({describe_os_error(exc)})",
                         where=where) from None
    return replaced

