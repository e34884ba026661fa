"""Bounded reading of the TOML files a user gives trikedyn: vehicle parameter files, weighing records.

A file is read only if it is a regular file (not a folder, a device or a pipe) of at most
:data:`MAX_FILE_BYTES`, in UTF-8, by the one bounded reader (:mod:`trikedyn._reading`). Its TOML may nest tables and arrays at most :data:`MAX_NESTING` deep and
hold integers of at most 64 bits, keys of at most :data:`MAX_KEY_CHARS` characters and texts of at most
:data:`MAX_TEXT_CHARS`. Each breach is an :class:`~trikedyn.errors.InputError` (of the subclass the caller
chooses) naming the file and, where it applies, the key; none shows the file's content.
"""

from __future__ import annotations

import os
import tomllib
from pathlib import Path

from .._reading import read_text as _bounded_text
from ..errors import InputError, did_you_mean

__all__ = ["MAX_FILE_BYTES", "MAX_KEY_CHARS", "MAX_NESTING", "MAX_TEXT_CHARS", "builtin_names", "builtin_or_file",
           "is_file", "parse_toml", "read_text"]

MAX_FILE_BYTES = 1 << 20
"""Largest TOML file read [bytes] (1 MiB: the reference vehicle, with every note, is 14 KiB)."""

MAX_NESTING = 10
"""Deepest nesting of tables and arrays (a vehicle file nests 4 deep: ``suspension.front.K.value``)."""

MAX_KEY_CHARS = 100
"""Longest key [characters]."""

MAX_TEXT_CHARS = 10_000
"""Longest text value [characters] (the longest note of the reference vehicle has about 600)."""

_INT_LIMIT = 2**63


def is_file(path: Path) -> bool:
    """Whether ``path`` is an existing regular file; False for a name the system cannot even look up.

    Parameters
    ----------
    path : Path
        The path.

    Returns
    -------
    bool
        Whether it is a regular file.
    """
    try:
        return path.is_file()
    except (OSError, ValueError):  # a name too long, a NUL byte, a permission denied on the way
        return False


def builtin_names(folder) -> list[str]:
    """Names of the built-in ``.toml`` files in the package resource ``folder`` (without the suffix), sorted.

    Parameters
    ----------
    folder : importlib.resources.abc.Traversable
        The resource folder.

    Returns
    -------
    list of str
        The names.
    """
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def builtin_or_file(name_or_path: str | Path, folder, kind: str, where: str) -> tuple[str, Path | None]:
    """The TOML text of a built-in file (a name of a ``.toml`` in the package resource ``folder``) or of a
    file (a ``.toml`` name, a path with a folder, or an existing file), and that file's path (None for a
    built-in). ``kind`` names what is asked for in errors (``"study spec"``), ``where`` the option.

    Parameters
    ----------
    name_or_path : str or Path
        A built-in name or a file.
    folder : importlib.resources.abc.Traversable
        The resource folder.
    kind : str
        What is asked for, in errors.
    where : str
        The option, in errors.

    Returns
    -------
    text : str
        The TOML text.
    path : Path or None
        The file, None for a built-in.

    Raises
    ------
    InputError
        No such file, or an unknown name (with the closest built-in one and the list).
    """
    text = str(name_or_path)
    path = Path(text)
    if path.suffix == ".toml" or "/" in text or os.sep in text or is_file(path):
        return read_text(path, text, missing=f"no such {kind} file"), path
    names = builtin_names(folder)
    if text not in names:
        tip = did_you_mean(text, names)
        raise InputError(f"unknown {kind} '{text}'{tip} (built in: {', '.join(names)}; or give a .toml file)",
                         where=where)
    return (folder / f"{text}.toml").read_text(encoding="utf-8"), None


def read_text(path: Path, where: str, *, error: type[InputError] = InputError,
              max_bytes: int = MAX_FILE_BYTES, missing: str = "no such file") -> str:
    """The UTF-8 text of the regular file ``path`` of at most ``max_bytes``; ``error(..., where)`` else.

    Read by the one bounded reader (:func:`trikedyn._reading.read_text`): a pipe, a device or a folder named
    in place of a file is refused before it is opened, never waited on or read without end. ``missing`` is
    the message for a file that does not exist.

    Parameters
    ----------
    path : Path
        The file.
    where : str
        Error location.
    error : type
        The error class raised.
    max_bytes : int
        Size limit [bytes].
    missing : str
        Message for a missing file.

    Returns
    -------
    str
        The text.
    """
    return _bounded_text(path, where, max_bytes=max_bytes, error=error, missing=missing,
                   too_large=lambda _: f"larger than {max_bytes / 1024:g} KiB; expected a small TOML file")


def parse_toml(text: str, where: str, *, error: type[InputError] = InputError) -> dict:
    """The TOML document ``text``, checked against the bounds of the module docstring.

    Parameters
    ----------
    text : str
        The document.
    where : str
        Error location.
    error : type
        The error class raised.

    Returns
    -------
    dict
        The document.

    Raises
    ------
    InputError
        Invalid TOML or beyond the bounds (of class ``error``).
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"invalid TOML: {exc}", where=where) from None
    except ValueError:  # an integer of more than 4300 digits
        raise error("invalid TOML: a number too long to read", where=where) from None
    except RecursionError:
        raise error(f"invalid TOML: arrays or inline tables nested more than {MAX_NESTING} deep",
                    where=where) from None
    _check_bounds(data, where, error)
    return data


def _check_bounds(data: dict, where: str, error: type[InputError]) -> None:
    stack = [(data, "", 0)]
    while stack:
        node, path, depth = stack.pop()
        if depth > MAX_NESTING:
            raise error(f"{path}: tables and arrays nested more than {MAX_NESTING} deep", where=where)
        if isinstance(node, dict):
            for key, value in node.items():
                if len(key) > MAX_KEY_CHARS:
                    raise error(f"a key of {len(key)} characters in {path or 'the top level'}; keys have at "
                                f"most {MAX_KEY_CHARS}", where=where)
                stack.append((value, f"{path}.{key}" if path else key, depth + 1))
        elif isinstance(node, list):
            stack.extend((value, f"{path}[{i}]", depth + 1) for i, value in enumerate(node))
        elif isinstance(node, int) and not isinstance(node, bool) and abs(node) >= _INT_LIMIT:
            raise error(f"{path}: integer beyond 64 bits; expected a number in physical units", where=where)
        elif isinstance(node, str) and len(node) > MAX_TEXT_CHARS:
            raise error(f"{path}: a text of {len(node)} characters; at most {MAX_TEXT_CHARS}", where=where)
