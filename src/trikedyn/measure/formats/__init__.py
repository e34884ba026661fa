"""IMU log layouts: a registry, one module per layout; importing this package registers the built-ins.

A layout is a :class:`LogFormat` (its ``name``, a one-line ``description``, ``sniff`` that scores a file's
first bytes, ``read`` and, optionally, ``write``) handed to :func:`register`.
:func:`trikedyn.measure.logs.read_log`, :func:`~trikedyn.measure.logs.write_log`,
:func:`~trikedyn.measure.logs.detect_format` and :data:`~trikedyn.measure.logs.FORMATS` go through this
registry, so a new layout is one new module in this folder (every public module here is imported, in name
order), or a :func:`register` call anywhere before the log is read. A text table with fixed headers can
subclass :class:`TableFormat` and give its headers only.
"""

from ...registry import import_submodules
from .base import (
    FORMATS,
    Head,
    LogFormat,
    ReadOptions,
    TableFormat,
    available,
    detect,
    get,
    register,
    registered,
    unregister,
)

__all__ = ["FORMATS", "Head", "LogFormat", "ReadOptions", "TableFormat", "available", "detect", "get", "register",
           "registered", "unregister"]

import_submodules(__name__, __path__)  # the built-in layouts, each registering itself in base.FORMATS
