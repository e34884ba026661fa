"""Provenance notes of a parameter file: a value written with its ``assumed``, ``source`` or ``note`` next to it.

A value may be written plainly (``wheelbase_m = 1.95``) or with its provenance next to it::

    driver_kg = { value = 75.0, assumed = "EU 1230/2012 standard driver; fits Table 3" }
    stiffness_N_per_m = { value = 80289.0, source = "paper Table 2, 100 %" }

:func:`split_notes` takes the notes out of a raw table, keyed by dotted path (``mass.driver_kg``,
``wheels.front.radius_m``), as :attr:`~trikedyn.params.parameter_set.ParameterSet.notes` keeps them;
:func:`merge_notes` puts them back next to their values for writing.
"""

from __future__ import annotations

__all__ = ["NOTE_KEYS", "is_annotated_value", "merge_notes", "split_notes"]

NOTE_KEYS = ("assumed", "source", "note")
"""The keys a value's provenance may be written under."""


def is_annotated_value(node) -> bool:
    """Whether a raw TOML node is a value written with its notes (``{value = x, assumed = "..."}``).

    Parameters
    ----------
    node : object
        A node of a raw TOML table.

    Returns
    -------
    bool
        True for a table with ``value`` and nothing but :data:`NOTE_KEYS` besides.
    """
    return isinstance(node, dict) and "value" in node and set(node) <= {"value", *NOTE_KEYS}


def split_notes(node, path):
    """Replace ``{value = x, assumed = "..."}`` by ``x``, collecting the notes by dotted path.

    Parameters
    ----------
    node : object
        A raw TOML table, list or value.
    path : tuple of str
        Its dotted path (``()`` for the whole file); list items are named by their ``name``, else their index.

    Returns
    -------
    plain : object
        ``node`` without the notes.
    notes : dict
        Dotted path -> ``{key: note}``.
    """
    notes: dict[str, dict] = {}
    if is_annotated_value(node):
        notes[".".join(path)] = {k: str(v) for k, v in node.items() if k != "value"}
        return node["value"], notes
    if isinstance(node, dict):
        out = {}
        for key, value in node.items():
            out[key], sub = split_notes(value, (*path, key))
            notes.update(sub)
        return out, notes
    if isinstance(node, list):
        out = []
        for i, item in enumerate(node):
            label = item.get("name", str(i)) if isinstance(item, dict) else str(i)
            value, sub = split_notes(item, (*path, str(label)))
            out.append(value)
            notes.update(sub)
        return out, notes
    return node, notes


def merge_notes(data: dict, notes: dict) -> None:
    """Put the notes back next to their values in a plain table, in place (for writing).

    Parameters
    ----------
    data : dict
        A plain table (``model_dump``); written.
    notes : dict
        Dotted path -> ``{key: note}``, as :func:`split_notes` gives them; a path no longer in ``data`` is left
        out.
    """
    for dotted, note in notes.items():
        keys = dotted.split(".")
        node = data
        for key in keys[:-1]:
            if isinstance(node, list):
                node = next((item for item in node if item.get("name") == key), None)
            else:
                node = node.get(key)
            if node is None:
                break
        if isinstance(node, dict) and keys[-1] in node:
            node[keys[-1]] = {"value": node[keys[-1]], **note}
