"""Write a parameter set as TOML: its provenance notes next to the values, its tyre files where it can name them.

:func:`save_vehicle` writes what :func:`~trikedyn.params.io.load_vehicle` reads back: a wheel's ``tyre_file``
relative to the new file's folder, and a tyre file that lies outside that folder copied beside the new file
(never over another file), so that what it writes loads (the rule of :mod:`trikedyn._reading`).
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import tomli_w

from .._reading import file_problem
from ..errors import ParameterError
from .notes import is_annotated_value as _is_annotated_value
from .notes import merge_notes as _merge_notes
from .parameter_set import ParameterSet
from .paths import real_path as _real
from .paths import shown as _shown
from .schema import VehicleParameters

__all__ = ["save_vehicle"]


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
