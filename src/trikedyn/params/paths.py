"""How the parameter files' readers and writers name files: real paths, and names cut short for a message."""

from __future__ import annotations

from pathlib import Path

__all__ = ["real_path", "shown"]


def real_path(path: Path) -> Path:
    """The real path of a file (symbolic links resolved); its folder is where its ``extends`` may reach.

    Parameters
    ----------
    path : Path
        The file.

    Returns
    -------
    Path
        Its resolved path, or its absolute path when it cannot be resolved (a loop of links, a name the
        system refuses).
    """
    try:
        return path.resolve()
    except (OSError, RuntimeError, ValueError):  # a loop of symbolic links, a name the system refuses
        return path.absolute()


def shown(text: str, limit: int = 300) -> str:
    """A name as the user wrote it, cut short for a one-line message.

    Parameters
    ----------
    text : str
        The name.
    limit : int
        Most characters shown.

    Returns
    -------
    str
        ``text``, or its first ``limit - 3`` characters and ``...``.
    """
    return text if len(text) <= limit else text[: limit - 3] + "..."
