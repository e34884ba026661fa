"""The files a vehicle file reads: itself, the chain of files it ``extends`` and every wheel's ``tyre_file``.

A command must never write onto a file it reads (:mod:`trikedyn._files`), and a vehicle file reads more than
itself: ``trikedyn vehicle export child.toml base.toml --force`` would otherwise replace the ``base.toml``
that ``child.toml`` extends, and an ``--out`` folder could hold the ``.tir`` file a wheel names.
:func:`vehicle_files` lists them by the rules of :func:`~trikedyn.params.io.parse_vehicle`: an ``extends``
or a ``tyre_file`` is relative to the real folder of the file that names it (symbolic links resolved); a
preset extends presets only, whose files are the package's own.

The walk reads with the bounded reader (:mod:`trikedyn.params.tomlfile`: regular files of at most 1 MiB,
never a pipe or a device) and never raises: a file it cannot read or parse ends the walk there (the load says
what is wrong with it). It lists more rather than less: a name the load would refuse (an absolute path, a
``..``) is still listed, since listing it only refuses an output.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import InputError
from .tomlfile import is_file, parse_toml, read_text

__all__ = ["vehicle_files"]

MAX_FILES = 64
"""Most files listed for one vehicle (the load allows 8 ``extends`` and a tyre file per wheel)."""


def _real(path: Path) -> Path:
    try:
        return path.resolve()
    except (OSError, RuntimeError, ValueError):  # a loop of symbolic links, a name the system refuses
        return path.absolute()


def _value(node):
    """A value written plainly or as ``{ value = ..., source = ... }``."""
    return node.get("value") if isinstance(node, dict) and "value" in node else node


def _tyre_files(raw: dict, folder: Path) -> list[Path]:
    wheels = raw.get("wheels")
    found = []
    for wheel in wheels if isinstance(wheels, list) else []:
        name = _value(wheel.get("tyre_file")) if isinstance(wheel, dict) else None
        if isinstance(name, str) and name.strip() and "\0" not in name:
            found.append(folder / name)
    return found


def vehicle_files(vehicle: str | os.PathLike) -> list[tuple[Path, str]]:
    """Every file the vehicle ``vehicle`` reads, with what it is to the vehicle.

    Parameters
    ----------
    vehicle : str or path
        A preset name (nothing listed: presets are package data) or a vehicle ``.toml`` file.

    Returns
    -------
    list of (Path, str)
        The file itself (``"the vehicle file"``), each file of its ``extends`` chain (``"extended by
        child.toml"``) and each wheel's tyre file (``"a tyre file named in child.toml"``), as named (not
        resolved: a caller compares them with :func:`os.path.samefile`), the vehicle file first.
    """
    path = Path(os.fspath(vehicle))
    if not is_file(path):
        return []
    found: list[tuple[Path, str]] = [(path, "the vehicle file")]
    seen = {_real(path)}
    while len(found) < MAX_FILES:
        real = _real(path)
        try:
            raw = parse_toml(read_text(path, str(path)), str(path))
        except InputError:
            break
        found += [(tyre, f"a tyre file named in {path.name}") for tyre in _tyre_files(raw, real.parent)]
        base = raw.get("extends")
        if not isinstance(base, str) or not base.endswith(".toml") or "\0" in base:
            break  # no extends, or a preset's name
        nxt = real.parent / base
        if _real(nxt) in seen or not is_file(nxt):
            break
        seen.add(_real(nxt))
        found.append((nxt, f"extended by {path.name}"))
        path = nxt
    return found[:MAX_FILES]
