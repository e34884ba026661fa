"""A parameter file's raw table: the file and the chain of files and presets it ``extends``, merged.

A set may start from another with ``extends = "PRESET"`` or ``extends = "FILE.toml"`` and give only what
differs; tables merge key by key, ``[[wheels]]`` by wheel name (:func:`read_raw`; the rules are those of
:func:`~trikedyn.params.io.parse_vehicle`). Each file's ``wheels[*].tyre_file`` is made absolute relative to
the folder of the file that names it, before the merge.
"""

from __future__ import annotations

from pathlib import Path

from .._reading import file_problem, named_file
from ..errors import ParameterError, did_you_mean
from .notes import is_annotated_value as _is_annotated_value
from .paths import shown as _shown
from .shipped import list_presets, preset_dir, preset_text
from .tomlfile import MAX_FILE_BYTES, parse_toml, read_text

__all__ = ["MAX_EXTENDS", "read_raw"]

MAX_EXTENDS = 8
"""Most ``extends`` links in a chain (a file that extends one that extends ...)."""


def read_raw(toml_text: str, origin: str, folder: Path | None, chain: tuple, named_in: dict) -> dict:
    """The merged raw table of ``toml_text`` and the chain of files it extends.

    Parameters
    ----------
    toml_text : str
        The TOML text.
    origin : str
        Where it came from (errors).
    folder : Path or None
        The real folder of the file read (None for a preset: it may extend presets only).
    chain : tuple
        The files and presets read so far, to stop a cycle.
    named_in : dict
        Tyre file -> the file that names it (filled in).

    Returns
    -------
    dict
        The raw table, notes still in place, ``extends`` merged away, tyre files made absolute.

    Raises
    ------
    ParameterError
        A file too long or not TOML, a refused or cyclic ``extends``, a chain longer than :data:`MAX_EXTENDS`, a
        layout changed by a file that extends another, a refused tyre file path.
    """
    where = _shown(origin)
    if len(toml_text) > MAX_FILE_BYTES:
        raise ParameterError(f"longer than {MAX_FILE_BYTES // 1024} KiB; expected a parameter file", where=where)
    raw = parse_toml(toml_text, where, error=ParameterError)
    _resolve_tyre_files(raw, origin, folder, named_in)
    base_name = raw.pop("extends", None)
    if base_name is None:
        return raw
    base_text, base_origin, base_folder, key = _extended(base_name, where, folder)
    if key in chain:
        loop = " -> ".join(_shown(Path(k[1]).name if k[0] == "file" else k[1], 60)
                           for k in (*chain, key)[chain.index(key):])
        raise ParameterError(f"extends: a cycle ({loop})", where=where)
    if len(chain) > MAX_EXTENDS:
        raise ParameterError(f"extends: more than {MAX_EXTENDS} in a chain", where=where)
    base = read_raw(base_text, base_origin, base_folder, (*chain, key), named_in)
    _check_same_layout(base, raw, base_name, where)
    return _deep_merge(base, raw)


def _resolve_tyre_files(raw: dict, origin: str, folder: Path | None, named_in: dict) -> None:
    """Make each ``wheels[*].tyre_file`` of one file's raw table absolute, relative to that file's folder
    (the presets' folder for a preset), after the rule for a file a file names; ``named_in`` records which
    file named each.

    Raises
    ------
    ParameterError
        ``where="wheels[NAME].tyre_file"``: a path the rule refuses (absolute, with ``..``, a link out of the
        folder), naming the vehicle file; nothing is opened.
    """
    wheels = raw.get("wheels")
    if not isinstance(wheels, list):
        return
    base = Path(str(preset_dir())) if folder is None else folder
    place = "the folder of the shipped presets" if folder is None else "the vehicle file's folder"
    for i, wheel in enumerate(wheels):
        if not isinstance(wheel, dict) or "tyre_file" not in wheel:
            continue
        node = wheel["tyre_file"]
        value = node.get("value") if _is_annotated_value(node) else node
        if not isinstance(value, str) or not value.strip() or not value.isprintable():
            continue  # the schema says what is wrong with it
        label = wheel.get("name") if isinstance(wheel.get("name"), str) else str(i)
        named = named_file(value, base, expected="a .tir file", where=f"wheels[{_shown(label, 40)}].tyre_file",
                           place=place, error=ParameterError, note=f"(tyre file named in {_shown(origin, 120)})")
        resolved = str(named.path)
        if _is_annotated_value(node):
            wheel["tyre_file"] = {**node, "value": resolved}
        else:
            wheel["tyre_file"] = resolved
        named_in.setdefault(resolved, _shown(origin, 120))


def _check_same_layout(base: dict, raw: dict, base_name: str, where: str) -> None:
    """A file that extends another keeps its layout and its wheels (they merge by name): a layout changed, or
    wheels added to a base that has its three, is refused in words (not as a tuple of too many wheels)."""
    names = [_item_name(w) for w in base.get("wheels", []) if isinstance(w, dict)]
    added = [_item_name(w) for w in raw.get("wheels", []) if isinstance(w, dict) and _item_name(w) is not None
             and _item_name(w) not in names]
    layout, base_layout = raw.get("layout"), base.get("layout", "delta")
    if (layout is None or layout == base_layout) and not (added and len(names) >= 3):
        return
    what = (f"changes the layout from {base_layout} to {layout}" if layout not in (None, base_layout)
            else f"adds the wheels {', '.join(map(str, added))}")
    tip = "reference-tadpole" if (layout or "") == "tadpole" else "reference-etrike" if layout == "delta" else None
    start = f"extend '{tip}' (or a file of that layout)" if tip else "extend a file of the layout you want"
    raise ParameterError(
        f"extends '{_shown(base_name, 60)}' (a {base_layout} with the wheels {', '.join(map(str, names))}) but "
        f"{what}: a file that extends another keeps its layout, and its wheels merge with the base's by name; "
        f"to build another layout, {start}, or write the whole vehicle without extends", where=where)


def _extended(name, where: str, folder: Path | None) -> tuple[str, str, Path | None, tuple]:
    """Text, origin, folder and identity of what ``extends = name`` names, or a ParameterError.

    Every refusal is decided from the name and the resolved path alone (the rule of
    :func:`trikedyn._reading.named_file`), before the target is opened; none shows where a link points.
    """
    usage = "expected a preset name or a .toml file in this file's folder or below it"
    if not isinstance(name, str) or not name.strip():
        raise ParameterError(f"extends: {usage}", where=where)
    shown = _shown(name, 60)
    presets = list_presets()
    if name in presets:
        return preset_text(name), name, None, ("preset", name)
    if folder is None:
        tip = did_you_mean(name, presets)
        raise ParameterError(f"extends: no preset '{shown}'{tip} (a preset extends presets only)", where=where)
    named = named_file(name, folder, expected="a preset name or a .toml file", where=where, key="extends",
                       error=ParameterError)
    if not name.endswith(".toml"):
        tip = did_you_mean(name, presets)
        raise ParameterError(f"extends: no preset '{shown}'{tip} ({usage})", where=where)
    problem = file_problem(named.real)
    if problem == "no such file":
        raise ParameterError(f"extends: no preset or file '{shown}' (looked in {_shown(str(folder), 60)})",
                             where=where)
    if problem is not None:
        raise ParameterError(f"extends: no preset or file '{shown}' (it {problem})", where=where)
    origin = str(named.path)
    text = read_text(named.real, _shown(origin), error=ParameterError)
    return text, origin, named.real.parent, ("file", str(named.real))


def _deep_merge(base, over):
    if isinstance(base, dict) and isinstance(over, dict):
        if _is_annotated_value(base) or _is_annotated_value(over):
            return over
        merged = dict(base)
        for key, value in over.items():
            merged[key] = _deep_merge(base[key], value) if key in base else value
        return merged
    if isinstance(base, list) and isinstance(over, list) and all(isinstance(i, dict) for i in base + over):
        by_name = {_item_name(item): item for item in base if _item_name(item) is not None}
        merged = [_deep_merge(by_name[_item_name(i)], i) if _item_name(i) in by_name else i for i in over]
        named = {_item_name(i) for i in over} - {None}
        return [b for b in base if _item_name(b) not in named] + merged
    return over


def _item_name(item: dict) -> str | None:
    """The name of a ``[[wheels]]`` (or other named) entry, if it has a text one."""
    name = item.get("name")
    return name if isinstance(name, str) else None
