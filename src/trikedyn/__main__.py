"""``python -m trikedyn``: the command line."""

from .cli import _console

_console()
