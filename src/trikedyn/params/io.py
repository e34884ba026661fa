"""Load and save parameter sets as TOML; find the presets shipped with the package.

A value may be written plainly (``wheelbase_m = 1.95``) or with its provenance next to it::

    driver_kg = { value = 75.0, assumed = "EU 1230/2012 standard driver; fits Table 3" }
    stiffness_N_per_m = { value = 80289.0, source = "paper Table 2, 100 %" }

The notes (``assumed``, ``source``, ``note``) are kept by dotted path (``mass.driver_kg``,
``wheels.front.radius_m``) in :attr:`ParameterSet.notes` and written back by :func:`save_vehicle`.

A wheel's ``tyre_file`` (an Adams/MF-Tyre ``.tir`` file) is a file a file names, so the one rule holds
(:mod:`trikedyn._reading`): relative to the folder of the file that names it, in that folder or below it once
symbolic links are resolved (no absolute path, no ``..``; a preset names shipped files only). Loading stores
it as an absolute path (that folder joined with the name, links not resolved), so
``pathlib.Path(wheel.tyre_file)`` finds it wherever the program runs, and reads it with
:func:`trikedyn.tyre.tir.read_tir`: a refused, missing or invalid tyre file fails the load, naming the wheel
and the vehicle file. :func:`save_vehicle` writes it relative to the new file's folder, and copies a tyre file
that lies outside that folder beside the new file (never over another file), so that what it writes loads.

A value the schema refuses that it would accept in another unit says so (``steering.max_angle_deg: ... (got
0.7); did you type radians? 0.7 rad is 40.1 deg``: :func:`trikedyn.plausibility.unit_slip_hint`), and a
loaded set is looked at for values that look like slips (radians in a degree field, a tyre file of another
size, ...): each is a :class:`~trikedyn.plausibility.PlausibilityWarning` (:mod:`trikedyn.params.plausibility`).
"""

from __future__ import annotations

import json
import os
import re
from importlib import resources
from pathlib import Path

import tomli_w
from pydantic import ValidationError

from .._reading import file_problem, named_file
from ..errors import ParameterError, did_you_mean
from ..plausibility import unit_slip_hint
from .parameter_set import ParameterSet
from .parameter_set import describe_error as _describe
from .plausibility import warn_implausible
from .schema import VehicleParameters
from .tomlfile import MAX_FILE_BYTES, builtin_names, is_file, parse_toml, read_text

__all__ = ["MAX_EXTENDS", "NOTE_KEYS", "ParameterSet", "list_presets", "load_vehicle", "parse_vehicle", "save_vehicle"]

NOTE_KEYS = ("assumed", "source", "note")

MAX_EXTENDS = 8
"""Most ``extends`` links in a chain (a file that extends one that extends ...)."""


def _preset_dir():
    return resources.files("trikedyn.params") / "presets"


def list_presets() -> list[str]:
    """Names of the parameter sets shipped with trikedyn.

    Returns
    -------
    list of str
        The names, sorted.
    """
    return builtin_names(_preset_dir())


def load_vehicle(name_or_path: str | Path) -> ParameterSet:
    """Load a preset by name, or a parameter file by path.

    A file is read if it is a regular UTF-8 file of at most 1 MiB (:mod:`trikedyn.params.tomlfile`).

    Parameters
    ----------
    name_or_path : str or Path
        A preset name, or a ``.toml`` file.

    Returns
    -------
    ParameterSet
        The parameters with their origin and provenance notes.

    Raises
    ------
    ParameterError
        Unknown preset (with a close match), unreadable TOML, unknown key, missing or out-of-range value,
        an ``extends`` that is refused (see :func:`parse_vehicle`), a wheel's ``tyre_file`` that is missing
        or not a valid ``.tir`` file (``where="wheels[NAME].tyre_file"``, naming the vehicle file).
    """
    text = str(name_or_path)
    path = Path(text)
    if path.suffix == ".toml" or "/" in text or is_file(path):
        body = read_text(path, _shown(text), error=ParameterError, missing="no such parameter file")
        real = _real(path)
        return _parse(body, text, real.parent, (("file", str(real)),))
    presets = list_presets()
    if text not in presets:
        tip = did_you_mean(text, presets)
        raise ParameterError(
            f"unknown vehicle '{_shown(text)}'{tip} (presets: {', '.join(presets)}; or give a .toml file)",
            where="vehicle",
        )
    return _parse(_preset_text(text), text, None, (("preset", text),))


def parse_vehicle(toml_text: str, origin: str = "<string>") -> ParameterSet:
    """Validate a parameter set given as TOML text.

    A set may start from another with ``extends = "PRESET"`` or ``extends = "FILE.toml"`` and give only
    what differs; tables merge key by key, ``[[wheels]]`` by wheel name. A file named by ``extends`` is
    relative to the folder of the file that names it (for text, the folder of ``origin``; a preset may
    extend presets only) and must lie in that folder or below it once symbolic links are resolved: no
    absolute path, no ``..`` (the rule for every file a file names, :mod:`trikedyn._reading`). It is read
    like the first file (UTF-8, at most 1 MiB). A chain of ``extends`` may be at most :data:`MAX_EXTENDS` long
    and must not come back to a file already in it. A refused ``extends`` names what was written and why,
    never the target's content nor where a link points. A wheel's ``tyre_file`` follows the same rule (see
    the module docstring).

    Parameters
    ----------
    toml_text : str
        The TOML text.
    origin : str
        Where it came from (errors; its folder resolves ``extends``).

    Returns
    -------
    ParameterSet
        The parameter set.

    Raises
    ------
    ParameterError
        As :func:`load_vehicle`.
    """
    return _parse(toml_text, origin, _real(Path(origin)).parent, (("text", origin),))


def _parse(toml_text: str, origin: str, folder: Path | None, chain: tuple) -> ParameterSet:
    named_in: dict[str, str] = {}
    raw = _read_raw(toml_text, origin, folder, chain, named_in)
    plain, notes = _split_notes(raw, ())
    try:
        params = VehicleParameters.model_validate(plain)
    except ValidationError as exc:
        hint = unit_slip_hint(exc, plain, VehicleParameters)
        raise ParameterError(_describe(exc, plain) + hint, where=_shown(origin)) from None
    tyres = _check_tyre_files(params, named_in, origin)
    warn_implausible(params, _shown(origin), tyres)
    return ParameterSet(params, notes, origin)


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
    base = Path(str(_preset_dir())) if folder is None else folder
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


def _check_tyre_files(params: VehicleParameters, named_in: dict, origin: str) -> dict:
    """Read every wheel's ``.tir`` file once (:func:`~trikedyn.tyre.tir_once.read_tir_once`: the audit and the
    tyre setup share what is read here); a missing or invalid one is a ParameterError naming the wheel
    and the vehicle file that names it. Returns ``tyre_file -> TyreProperties``."""
    files = {w.tyre_file for w in params.wheels if w.tyre_file is not None}
    read: dict = {}
    if not files:
        return read
    from ..errors import InputError
    from ..tyre.tir_once import read_tir_once

    for wheel in params.wheels:
        if wheel.tyre_file not in files:
            continue
        files.discard(wheel.tyre_file)
        try:
            read[wheel.tyre_file] = read_tir_once(Path(wheel.tyre_file))
        except InputError as exc:
            naming = named_in.get(wheel.tyre_file, _shown(origin, 120))
            raise ParameterError(f"{exc} (tyre file named in {naming})",
                                 where=f"wheels[{wheel.name}].tyre_file") from None
    return read


def save_vehicle(pset: ParameterSet | VehicleParameters, path: str | Path) -> Path:
    """Write a parameter set as TOML, with its provenance notes next to the values (atomically: a temporary
    file renamed into place).

    A wheel's ``tyre_file`` is written relative to the new file's folder. A tyre file that lies outside that
    folder (which the new file could not name: the rule of :mod:`trikedyn._reading`) is copied beside the
    new file under its own name first, byte for byte; an existing file of that name is used only if it is
    the same bytes, and never replaced.

    Parameters
    ----------
    pset : ParameterSet or VehicleParameters
        The vehicle.
    path : str or Path
        The TOML file to write.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ParameterError
        ``where="wheels[NAME].tyre_file"``: a tyre file to copy that cannot be read, or another file of its
        name beside the new file.
    """
    if isinstance(pset, VehicleParameters):
        pset = ParameterSet(pset)
    data = pset.params.model_dump(mode="json", exclude_none=True)
    folder = _real(Path(path)).parent
    for wheel in data.get("wheels", []):
        if "tyre_file" in wheel:
            wheel["tyre_file"] = _tyre_file_in(wheel["tyre_file"], folder, f"wheels[{wheel.get('name')}].tyre_file")
    _merge_notes(data, pset.notes)
    from .._files import atomic_write

    text = _to_toml(data)
    return atomic_write(Path(path), lambda fh: fh.write(text), binary=False)


def _tyre_file_in(file: str, folder: Path, where: str) -> str:
    """How a vehicle file written into the real ``folder`` names the tyre file ``file``: its path relative to
    ``folder`` (POSIX separators) when it lies there or below, else the name of its copy beside it."""
    real = _real(Path(file))
    if real.is_relative_to(folder):
        return Path(os.path.relpath(real, folder)).as_posix()
    from .._files import atomic_write
    from .._reading import read_bytes
    from ..tyre.tir import MAX_BYTES

    data = read_bytes(real, _shown(file), max_bytes=MAX_BYTES, error=ParameterError,
                      expected="a .tir tyre property file")
    copy = folder / Path(file).name
    if copy.is_symlink() or copy.exists():
        same = (file_problem(copy) is None and not copy.is_symlink()
                and read_bytes(copy, str(copy), max_bytes=MAX_BYTES, error=ParameterError) == data)
        if not same:
            raise ParameterError(f"{Path(file).name} lies outside {_shown(str(folder), 120)}, where the new file "
                                 f"could name it, and {copy.name} there is another file: a vehicle file names its "
                                 "tyre files in its own folder or below it; rename that file, or write the "
                                 "vehicle into a folder that holds the tyre file", where=where)
        return copy.name
    atomic_write(copy, lambda fh: fh.write(data))
    return copy.name


def _toml_value(value) -> str:
    if _is_annotated_value(value):
        return "{ " + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items()) + " }"
    return tomli_w.dumps({"v": value}).strip()[len("v = ") :]


def _toml_key(key) -> str:
    """A TOML key: bare when it can be (letters, digits, ``_``, ``-``), else quoted (a range key such as
    ``wheels.front_left+front_right.radius_m`` holds dots and a ``+``)."""
    text = str(key)
    return text if re.fullmatch(r"[A-Za-z0-9_-]+", text) else json.dumps(text)


def _to_toml(data: dict, header: tuple = ()) -> str:
    """TOML with provenance notes as inline tables next to their values (tomli_w alone would not)."""

    def is_table(v):
        """A TOML table (not a value with its notes)."""
        return isinstance(v, dict) and not _is_annotated_value(v)

    def is_table_array(v):
        """An array of tables (``[[wheels]]``)."""
        return isinstance(v, list) and v and all(isinstance(i, dict) for i in v)

    lines = [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in data.items()
             if not is_table(v) and not is_table_array(v)]
    out = ([f"[{'.'.join(_toml_key(h) for h in header)}]"] if header and lines else []) + lines
    chunks = ["\n".join(out)] if out else []
    for key, value in data.items():
        if is_table(value):
            chunks.append(_to_toml(value, (*header, key)))
        elif is_table_array(value):
            for item in value:
                body = _to_toml(item).strip()
                chunks.append(f"[[{'.'.join(_toml_key(h) for h in (*header, key))}]]\n{body}")
    return "\n\n".join(c for c in chunks if c) + ("\n" if not header else "")


# ------------------------------------------------------------------------------------------------
def _preset_text(name: str) -> str:
    return (_preset_dir() / f"{name}.toml").read_text(encoding="utf-8")


def _real(path: Path) -> Path:
    """The real path of a file (symbolic links resolved); its folder is where its ``extends`` may reach."""
    try:
        return path.resolve()
    except (OSError, RuntimeError, ValueError):  # a loop of symbolic links, a name the system refuses
        return path.absolute()


def _shown(text: str, limit: int = 300) -> str:
    """A name as the user wrote it, cut short for a one-line message."""
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _read_raw(toml_text: str, origin: str, folder: Path | None, chain: tuple, named_in: dict) -> dict:
    """The merged raw table of ``toml_text`` and the chain of files it extends.

    ``folder``: the real folder of the file read (None for a preset: it may extend presets only);
    ``chain``: the files and presets read so far, to stop a cycle; ``named_in``: tyre file -> the file that
    names it (filled in).
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
    base = _read_raw(base_text, base_origin, base_folder, (*chain, key), named_in)
    _check_same_layout(base, raw, base_name, where)
    return _deep_merge(base, raw)


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
        return _preset_text(name), name, None, ("preset", name)
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


def _is_annotated_value(node) -> bool:
    return isinstance(node, dict) and "value" in node and set(node) <= {"value", *NOTE_KEYS}


def _split_notes(node, path):
    """Replace ``{value = x, assumed = "..."}`` by ``x``, collecting the notes by dotted path."""
    notes: dict[str, dict] = {}
    if _is_annotated_value(node):
        notes[".".join(path)] = {k: str(v) for k, v in node.items() if k != "value"}
        return node["value"], notes
    if isinstance(node, dict):
        out = {}
        for key, value in node.items():
            out[key], sub = _split_notes(value, (*path, key))
            notes.update(sub)
        return out, notes
    if isinstance(node, list):
        out = []
        for i, item in enumerate(node):
            label = item.get("name", str(i)) if isinstance(item, dict) else str(i)
            value, sub = _split_notes(item, (*path, str(label)))
            out.append(value)
            notes.update(sub)
        return out, notes
    return node, notes


def _merge_notes(data: dict, notes: dict) -> None:
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
