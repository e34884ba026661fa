"""Load parameter sets: a preset by name, a TOML file by path, or TOML text, validated against the schema.

The file and what it ``extends`` are read and merged by :mod:`trikedyn.params.extends`; a value's provenance
notes (``assumed``, ``source``, ``note``: :mod:`trikedyn.params.notes`) are kept by dotted path in
:attr:`ParameterSet.notes` and written back by :func:`~trikedyn.params.save.save_vehicle`; the presets are
:mod:`trikedyn.params.shipped`'s.

A wheel's ``tyre_file`` (an Adams/MF-Tyre ``.tir`` file) is a file a file names, so the one rule holds
(:mod:`trikedyn._reading`): relative to the folder of the file that names it, in that folder or below it once
symbolic links are resolved (no absolute path, no ``..``; a preset names shipped files only). Loading stores
it as an absolute path (that folder joined with the name, links not resolved), so
``pathlib.Path(wheel.tyre_file)`` finds it wherever the program runs, and reads it with
:func:`trikedyn.tyre.tir.read_tir`: a refused, missing or invalid tyre file fails the load, naming the wheel
and the vehicle file. :func:`~trikedyn.params.save.save_vehicle` writes it relative to the new file's folder,
and copies a tyre file that lies outside that folder beside the new file (never over another file), so that
what it writes loads.

A value the schema refuses that it would accept in another unit says so (``steering.max_angle_deg: ... (got
0.7); did you type radians? 0.7 rad is 40.1 deg``: :func:`trikedyn.plausibility.unit_slip_hint`), and a
loaded set is looked at for values that look like slips (radians in a degree field, a tyre file of another
size, ...): each is a :class:`~trikedyn.plausibility.PlausibilityWarning` (:mod:`trikedyn.params.plausibility`).
"""

from __future__ import annotations

from pathlib import Path

from pydantic import ValidationError

from ..errors import ParameterError, did_you_mean
from ..plausibility import unit_slip_hint
from .extends import read_raw
from .notes import split_notes
from .parameter_set import ParameterSet
from .parameter_set import describe_error as _describe
from .paths import real_path as _real
from .paths import shown as _shown
from .plausibility import warn_implausible
from .schema import VehicleParameters
from .shipped import list_presets, preset_text
from .tomlfile import is_file, read_text

__all__ = ["ParameterSet", "load_vehicle", "parse_vehicle"]


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
    return _parse(preset_text(text), text, None, (("preset", text),))


def parse_vehicle(toml_text: str, origin: str = "<string>") -> ParameterSet:
    """Validate a parameter set given as TOML text.

    A set may start from another with ``extends = "PRESET"`` or ``extends = "FILE.toml"`` and give only
    what differs; tables merge key by key, ``[[wheels]]`` by wheel name. A file named by ``extends`` is
    relative to the folder of the file that names it (for text, the folder of ``origin``; a preset may
    extend presets only) and must lie in that folder or below it once symbolic links are resolved: no
    absolute path, no ``..`` (the rule for every file a file names, :mod:`trikedyn._reading`). It is read
    like the first file (UTF-8, at most 1 MiB). A chain of ``extends`` may be at most :data:`~trikedyn.params.extends.MAX_EXTENDS` long
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
    raw = read_raw(toml_text, origin, folder, chain, named_in)
    plain, notes = split_notes(raw, ())
    try:
        params = VehicleParameters.model_validate(plain)
    except ValidationError as exc:
        hint = unit_slip_hint(exc, plain, VehicleParameters)
        raise ParameterError(_describe(exc, plain) + hint, where=_shown(origin)) from None
    tyres = _check_tyre_files(params, named_in, origin)
    warn_implausible(params, _shown(origin), tyres)
    return ParameterSet(params, notes, origin)


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


# ------------------------------------------------------------------------------------------------
