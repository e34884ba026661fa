"""The parameter sets shipped with trikedyn (the presets): their folder, their names and their text."""

from __future__ import annotations

from importlib import resources

from .tomlfile import builtin_names

__all__ = ["list_presets", "preset_dir", "preset_text"]


def preset_dir():
    """The folder of the shipped presets (a :mod:`importlib.resources` traversable).

    Returns
    -------
    importlib.resources.abc.Traversable
        ``trikedyn/params/presets``.
    """
    return resources.files("trikedyn.params") / "presets"


def list_presets() -> list[str]:
    """Names of the parameter sets shipped with trikedyn.

    Returns
    -------
    list of str
        The names, sorted.
    """
    return builtin_names(preset_dir())


def preset_text(name: str) -> str:
    """The TOML text of a shipped preset.

    Parameters
    ----------
    name : str
        One of :func:`list_presets`.

    Returns
    -------
    str
        The file's text.
    """
    return (preset_dir() / f"{name}.toml").read_text(encoding="utf-8")
