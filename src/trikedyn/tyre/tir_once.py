"""A ``.tir`` file parsed once per version: the load's validation, the audit and the tyre setup of a vehicle
share one :class:`~trikedyn.tyre.tir_properties.TyreProperties` for the file a wheel names.

A version is the file's real path, device, inode, size and modification and change times, with the name
given (``TyreProperties.path`` stays that name); a file changed since it was read is read again. Anything but
a regular file is never kept: :func:`~trikedyn.tyre.tir.read_tir` says what is wrong with it.
"""

from __future__ import annotations

import os
import stat
import threading
from collections import OrderedDict
from pathlib import Path

from .tir import read_tir
from .tir_properties import TyreProperties

__all__ = ["KEPT_VERSIONS", "forget_tir_files", "read_tir_once"]

KEPT_VERSIONS = 64
"""File versions kept (the least recently used goes first)."""

_KEPT: OrderedDict[tuple, TyreProperties] = OrderedDict()
_LOCK = threading.Lock()


def _version(path: Path) -> tuple | None:
    """Real path, device, inode, size, modification and change times [ns] of a regular file; None otherwise."""
    try:
        st = os.stat(path)
        real = os.path.realpath(path)
    except (OSError, ValueError):
        return None
    if not stat.S_ISREG(st.st_mode):
        return None
    return real, st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns


def read_tir_once(path: str | Path) -> TyreProperties:
    """:func:`~trikedyn.tyre.tir.read_tir`, parsed once per version of the file.

    Parameters
    ----------
    path : str or Path
        The ``.tir`` file.

    Returns
    -------
    TyreProperties
        The parsed file: the same (immutable) object for the same name and version.

    Raises
    ------
    InputError
        As :func:`~trikedyn.tyre.tir.read_tir`.
    """
    path = Path(path)
    version = _version(path)
    if version is None:
        return read_tir(path)
    key = (str(path), *version)
    with _LOCK:
        kept = _KEPT.get(key)
        if kept is not None:
            _KEPT.move_to_end(key)
            return kept
    read = read_tir(path)
    if _version(path) == version:  # unchanged while it was read: this version's content
        with _LOCK:
            _KEPT[key] = read
            while len(_KEPT) > KEPT_VERSIONS:
                _KEPT.popitem(last=False)
    return read


def forget_tir_files() -> None:
    """Drop every kept version (the next :func:`read_tir_once` of each file parses it again)."""
    with _LOCK:
        _KEPT.clear()
