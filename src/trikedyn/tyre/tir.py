"""Adams / MF-Tyre tyre property files (``.tir``): a bounded reader into an immutable, typed object.

A ``.tir`` file is a TeimOrbit text file: ``[SECTION]`` headers, ``KEY = value`` lines, comments that start
with ``!`` or ``$`` (a ``$`` may also follow a value on the same line), strings in single quotes, and
bare tables under a ``{column column}`` header (``[SHAPE]``). Sections and keys are read case-insensitively
and kept upper case.

What :func:`read_tir` gives (:class:`~trikedyn.tyre.tir_properties.TyreProperties`):

- the model family from ``FITTYP`` (6 PAC2002, 21 MF 5.2, 61 MF 6.1, 62 MF 6.2) or, without it, from
  ``PROPERTY_FILE_FORMAT`` (``'PAC2002'``, ``'MF_05'``/``'MF 5.2'``, ``'MF_61'``/``'MF 6.1'``, ``'MF_62'``);
  any other format (PAC89, PAC94, Fiala, ...) is refused;
- ``TYRESIDE`` (``LEFT``, ``RIGHT`` or ``SYMMETRIC``; ``LEFT`` when absent, with a note), ``USE_MODE``,
  ``FILE_VERSION``;
- ``coefficients``: every value the Magic Formula evaluator (:mod:`trikedyn.tyre.pac2002`) reads for the
  file's family, in SI units, with the format's defaults for those the file lacks (0; scaling factors 1;
  ``PKY4`` 2, the value that makes MF 6.1's cornering stiffness the PAC2002 one; ``LONGVL`` 16.7 m/s;
  ``VXLOW`` 1 m/s; the validity ranges unbounded: ``Fz`` in [0, inf), ``kappa`` in (-inf, inf), ``alpha``
  and ``gamma`` in [-pi/2, pi/2]); ``defaulted`` names them;
- ``sections``: everything as read (dimensional values converted to SI), ``tables``; ``ignored_keys`` (kept,
  not used by the evaluator), ``unknown_sections``.

Units: the ``[UNITS]`` section names the units of the file's *dimensional* entries (radius, loads,
stiffness, damping, speeds, range angles, pressures, masses, inertias); they are converted to SI. The Magic
Formula coefficients themselves are dimensionless by construction and are never converted.

Mistakes (not a text file, over 1 MiB, a line that is neither a comment, a section, a ``KEY = value`` nor a
table row, a number that is not finite, a duplicate key, an unknown unit, a missing ``FNOMIN`` or
``UNLOADED_RADIUS``, an ``UNLOADED_RADIUS`` outside 0.01 .. 2.5 m once converted (lengths in another unit
than ``[UNITS]`` says), an unsupported format) raise :class:`~trikedyn.errors.InputError` naming ``file:line``.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from types import MappingProxyType

from .._reading import excerpt, read_bytes
from ..errors import InputError
from .tir_properties import MF52, MF61, MF62, PAC2002, RANGE_PAIRS, TirTable, TyreProperties

__all__ = ["MAX_BYTES", "MAX_RADIUS_M", "MIN_RADIUS_M", "parse_tir", "read_tir"]

MAX_BYTES = 1 << 20  #: largest file read [bytes]
MAX_LINE_CHARS = 4096  #: longest line read [characters]
MIN_RADIUS_M, MAX_RADIUS_M = 0.01, 2.5  #: range of UNLOADED_RADIUS [m]: from a toy's tyre to the largest earthmover's

_FITTYP = {6: PAC2002, 21: MF52, 61: MF61, 62: MF62}
_FORMATS = {"PAC2002": PAC2002, "MF05": MF52, "MF52": MF52, "MF5.2": MF52, "MF61": MF61, "MF6.1": MF61,
            "MF62": MF62, "MF6.2": MF62}

_UNITS = {
    "LENGTH": {"meter": 1.0, "metre": 1.0, "m": 1.0, "millimeter": 1e-3, "millimetre": 1e-3, "mm": 1e-3,
               "centimeter": 1e-2, "centimetre": 1e-2, "cm": 1e-2, "kilometer": 1e3, "km": 1e3,
               "inch": 0.0254, "in": 0.0254, "foot": 0.3048, "feet": 0.3048, "ft": 0.3048},
    "FORCE": {"newton": 1.0, "n": 1.0, "kilonewton": 1e3, "kn": 1e3, "pound_force": 4.4482216152605,
              "lbf": 4.4482216152605, "kilogram_force": 9.80665, "kgf": 9.80665},
    "ANGLE": {"radian": 1.0, "rad": 1.0, "degree": math.pi / 180.0, "deg": math.pi / 180.0},
    "MASS": {"kg": 1.0, "kilogram": 1.0, "gram": 1e-3, "g": 1e-3, "tonne": 1e3, "pound_mass": 0.45359237,
             "lbm": 0.45359237, "slug": 14.593902937206364},
    "TIME": {"second": 1.0, "sec": 1.0, "s": 1.0, "millisecond": 1e-3, "ms": 1e-3, "minute": 60.0, "min": 60.0,
             "hour": 3600.0, "h": 3600.0},
    "PRESSURE": {"pascal": 1.0, "pa": 1.0, "kilopascal": 1e3, "kpa": 1e3, "megapascal": 1e6, "mpa": 1e6,
                 "bar": 1e5, "psi": 6894.757293168361},
}
_LETTER = {"L": "LENGTH", "F": "FORCE", "A": "ANGLE", "M": "MASS", "T": "TIME", "P": "PRESSURE"}
_DIMENSIONS = {  # key -> dimension, as products (*) and quotients (/) of L F A M T P
    **dict.fromkeys(("UNLOADED_RADIUS", "WIDTH", "RIM_RADIUS", "RIM_WIDTH", "BOTTOM_OFFST"), "L"),
    **dict.fromkeys(("FNOMIN", "FZMIN", "FZMAX"), "F"),
    **dict.fromkeys(("VERTICAL_STIFFNESS", "LONGITUDINAL_STIFFNESS", "LATERAL_STIFFNESS", "BOTTOM_STIFF"), "F/L"),
    "VERTICAL_DAMPING": "F*T/L", "LONGVL": "L/T", "VXLOW": "L/T", "GRAVITY": "L/T/T",
    **dict.fromkeys(("ALPMIN", "ALPMAX", "CAMMIN", "CAMMAX"), "A"),
    **dict.fromkeys(("NOMPRES", "INFLPRES", "PRESMIN", "PRESMAX"), "P"),
    **dict.fromkeys(("MASS", "MBELT", "BELT_MASS"), "M"),
    **dict.fromkeys(("IXX", "IYY", "BELT_IXX", "BELT_IYY"), "M*L*L"),
}

# ---- what the evaluator reads: key -> default, by family ("*" both, "5" PAC2002/MF 5.2, "6" MF 6.x) ------
_ONE = "LFZO LCX LMUX LEX LKX LHX LVX LCY LMUY LEY LKY LHY LVY LTR LRES LXAL LYKA LVYKA LS LMX LVMX LMY"
_BOTH = (
    "PCX1 PDX1 PDX2 PDX3 PEX1 PEX2 PEX3 PEX4 PKX1 PKX2 PKX3 PHX1 PHX2 PVX1 PVX2 RBX1 RBX2 RCX1 REX1 REX2 RHX1 "
    "QSX1 QSX2 QSX3 PCY1 PDY1 PDY2 PDY3 PEY1 PEY2 PEY3 PEY4 PKY1 PKY2 PKY3 PHY1 PHY2 PVY1 PVY2 PVY3 PVY4 "
    "RBY1 RBY2 RBY3 RCY1 REY1 REY2 RHY1 RHY2 RVY1 RVY2 RVY3 RVY4 RVY5 RVY6 QSY1 QSY2 QSY3 QSY4 "
    "QBZ1 QBZ2 QBZ3 QBZ4 QBZ5 QBZ9 QBZ10 QCZ1 QDZ1 QDZ2 QDZ3 QDZ4 QDZ6 QDZ7 QDZ8 QDZ9 QEZ1 QEZ2 QEZ3 QEZ4 QEZ5 "
    "QHZ1 QHZ2 QHZ3 QHZ4 SSZ1 SSZ2 SSZ3 SSZ4 VERTICAL_STIFFNESS VERTICAL_DAMPING"
)
_ONLY5 = "PHY3 PTX1 PTX2 PTX3 PTY1 PTY2"
_ONE5 = "LGAX LGAY LGAZ LSGKP LSGAL"
_ONLY6 = (
    "PEY5 PKY5 PKY6 PKY7 RBX3 RBY4 QDZ10 QDZ11 QSX4 QSX5 QSX6 QSX7 QSX8 QSX9 QSX10 QSX11 QSX12 QSX13 QSX14 "
    "QSY5 QSY6 QSY7 LONGITUDINAL_STIFFNESS LATERAL_STIFFNESS PCFX1 PCFX2 PCFY1 PCFY2"
)
_ONE6 = "LKYC LKZC"
_HALF_PI = 0.5 * math.pi
_SPECIAL = {"PKY4": 2.0, "LONGVL": 16.7, "VXLOW": 1.0, "FZMIN": 0.0, "FZMAX": math.inf,
            "KPUMIN": -math.inf, "KPUMAX": math.inf, "ALPMIN": -_HALF_PI, "ALPMAX": _HALF_PI,
            "CAMMIN": -_HALF_PI, "CAMMAX": _HALF_PI}
_REQUIRED = ("FNOMIN", "UNLOADED_RADIUS")
_RECORDED = {"PROPERTY_FILE_FORMAT", "FITTYP", "TYRESIDE", "USE_MODE", "FILE_TYPE", "FILE_VERSION", "FILE_FORMAT",
             "WIDTH", "ASPECT_RATIO", "RIM_RADIUS", "RIM_WIDTH", "NOMPRES", "INFLPRES"}
_STRINGS = {"PROPERTY_FILE_FORMAT", "TYRESIDE", "FILE_TYPE", "FILE_FORMAT", "FUNCTION_NAME", "CONTACT_MODEL"}
_KNOWN_SECTIONS = {
    "MDI_HEADER", "UNITS", "MODEL", "DIMENSION", "OPERATING_CONDITIONS", "INERTIA", "VERTICAL", "STRUCTURAL",
    "CONTACT_PATCH", "INFLATION_PRESSURE_RANGE", "VERTICAL_FORCE_RANGE", "LONG_SLIP_RANGE", "SLIP_ANGLE_RANGE",
    "INCLINATION_ANGLE_RANGE", "SCALING_COEFFICIENTS", "LONGITUDINAL_COEFFICIENTS", "OVERTURNING_COEFFICIENTS",
    "LATERAL_COEFFICIENTS", "ROLLING_COEFFICIENTS", "ALIGNING_COEFFICIENTS", "TURNSLIP_COEFFICIENTS", "SHAPE",
    "LOADED_RADIUS_COEFFICIENTS", "BOTTOMING_CURVE", "DEFLECTION_LOAD_CURVE", "TIRE_CONDITIONS",
}


def _evaluator_keys(family: str) -> dict[str, float]:
    """Every key the evaluator reads for ``family``, with its default."""
    mf6 = family in (MF61, MF62)
    keys = dict.fromkeys(_ONE.split() + (_ONE6 if mf6 else _ONE5).split(), 1.0)
    keys |= dict.fromkeys(_BOTH.split() + (_ONLY6 if mf6 else _ONLY5).split(), 0.0)
    keys |= {k: v for k, v in _SPECIAL.items() if mf6 or k != "PKY4"}
    return keys


# ---- reading ---------------------------------------------------------------------------------------------
def read_tir(path: str | Path) -> TyreProperties:
    """Read a tyre property file.

    Parameters
    ----------
    path : str or Path
        The ``.tir`` file: UTF-8 (a byte-order mark is skipped) or else latin-1, at most ``MAX_BYTES``.

    Returns
    -------
    TyreProperties

    Raises
    ------
    InputError
        The file is missing, not a regular file (a folder, a pipe, a device: refused before it is opened),
        unreadable, too large, binary, or not a valid property file (naming ``file:line`` and what is wrong;
        a line is quoted at most 40 characters, escaped). Read by the one bounded reader
        (:mod:`trikedyn._reading`).
    """
    path = Path(path)
    where = str(path)
    data = read_bytes(path, where, max_bytes=MAX_BYTES, expected="a .tir tyre property file",
                      too_large=lambda _: f"larger than {MAX_BYTES // 1024} KiB; not a tyre property file")
    if b"\x00" in data:
        raise InputError("contains NUL bytes: a binary file, not a text .tir property file", where=where)
    encoding = "utf-8"
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        text, encoding = data.decode("latin-1"), "latin-1"
    return parse_tir(text, where, encoding=encoding)


_SECTION = re.compile(r"\[\s*([A-Za-z0-9_ \-]+?)\s*\]")
_ASSIGN = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\s*=\s*(.*)")
_FORTRAN_D = re.compile(r"(?<=[0-9.])[dD](?=[+-]?[0-9])")


def _strip_comment(line: str) -> str:
    """``line`` up to the first ``$`` or ``!`` outside quotes."""
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch in "$!":
            return line[:i]
    return line


def _number(text: str) -> float | None:
    try:
        value = float(_FORTRAN_D.sub("e", text))
    except ValueError:
        return None
    return value


def _value(raw: str, key: str, where: str) -> float | str:
    raw = raw.strip()
    if not raw:
        raise InputError(f"{key} has no value", where=where)
    if raw[0] in "'\"":
        if len(raw) < 2 or raw[-1] != raw[0]:
            raise InputError(f"{key}: unterminated string {excerpt(raw)}", where=where)
        return raw[1:-1].strip()
    value = _number(raw)
    if value is None:
        if key in _STRINGS and re.fullmatch(r"[A-Za-z0-9_.\- ]+", raw):
            return raw  # an unquoted word
        raise InputError(f"{key}: expected a number or a quoted string, got {excerpt(raw)}", where=where)
    if not math.isfinite(value):
        raise InputError(f"{key}: {raw[:40]} is not a finite number", where=where)  # float() read it: printable
    return value


def parse_tir(text: str, name: str = "<tir>", *, encoding: str = "utf-8") -> TyreProperties:
    """Parse the text of a tyre property file (see :func:`read_tir`); ``name`` prefixes error locations.

    Parameters
    ----------
    text : str
        The file's text.
    name : str
        Where it came from, for error locations (``name:line``).
    encoding : str
        The encoding it was decoded with (recorded).

    Returns
    -------
    TyreProperties
        The parsed file.

    Raises
    ------
    InputError
        On a line that is not a valid property file line (naming ``name:line``).
    """
    sections: dict[str, dict[str, float | str]] = {}
    lines: dict[tuple[str, str], int] = {}
    tables: dict[str, list] = {}
    section = None
    for number, line in enumerate(text.splitlines(), start=1):
        where = f"{name}:{number}"
        if len(line) > MAX_LINE_CHARS:
            raise InputError(f"line longer than {MAX_LINE_CHARS} characters", where=where)
        body = _strip_comment(line).strip()
        if not body:
            continue
        if body.startswith("["):
            match = _SECTION.fullmatch(body)
            if not match:
                raise InputError(f"malformed section header {excerpt(body)}", where=where)
            section = match.group(1).upper().replace(" ", "_").replace("-", "_")
            sections.setdefault(section, {})
            continue
        if section is None:
            raise InputError(f"{excerpt(body)} before any [SECTION] header", where=where)
        if body.startswith("{"):
            if not body.endswith("}"):
                raise InputError(f"malformed table header {excerpt(body)}", where=where)
            tables[section] = [tuple(body[1:-1].split()), [], number]
            continue
        match = _ASSIGN.fullmatch(body)
        if match:
            key = match.group(1).upper()
            if key in sections[section]:
                first = lines[(section, key)]
                raise InputError(f"{key} given twice in [{section}] (first at line {first})", where=where)
            sections[section][key] = _value(match.group(2), key, where)
            lines[(section, key)] = number
            continue
        values = [_number(v) for v in body.replace(",", " ").split()]
        if section in tables and values and None not in values:
            columns = tables[section][0]
            if columns and len(values) != len(columns):
                raise InputError(f"table row has {len(values)} numbers, its header {len(columns)}", where=where)
            if not all(math.isfinite(v) for v in values):
                raise InputError("table row has a number that is not finite", where=where)
            tables[section][1].append(tuple(values))
            continue
        raise InputError(f"cannot read {excerpt(body)}: expected KEY = value, [SECTION], a table row or a "
                         "comment (! or $)", where=where)
    return _build(name, sections, lines, tables, encoding)


def _build(name, sections, lines, tables, encoding) -> TyreProperties:
    def at(section, key):
        """``file:line`` of a key of a section."""
        return f"{name}:{lines[(section, key)]}"

    notes: list[str] = []
    units = {k: str(v).strip().lower() for k, v in sections.get("UNITS", {}).items()}
    factors = {}
    for quantity, table in _UNITS.items():
        unit = units.get(quantity)
        if unit is None:
            factors[quantity] = 1.0
            continue
        factor = table.get(unit, table.get(unit[:-1]) if unit.endswith("s") else None)
        if factor is None:
            raise InputError(f"unknown {quantity.lower()} unit {excerpt(unit)} (known: {', '.join(sorted(table))})",
                             where=at("UNITS", quantity))
        factors[quantity] = factor
    if "UNITS" not in sections:
        notes.append("no [UNITS] section: SI units assumed")

    flat: dict[str, tuple[float | str, str]] = {}  # key -> (value, section), every section but UNITS/MDI_HEADER
    for sec, entries in sections.items():
        if sec == "UNITS":
            continue
        for key, value in entries.items():
            if isinstance(value, float) and key in _DIMENSIONS and sec != "MDI_HEADER":
                value = entries[key] = value * _si_factor(_DIMENSIONS[key], factors)
            if sec == "MDI_HEADER":
                continue
            if key in flat:
                raise InputError(f"{key} given twice: in [{flat[key][1]}] and [{sec}]", where=at(sec, key))
            flat[key] = (value, sec)

    family, file_format = _family(name, flat, sections, at)
    expected = _evaluator_keys(family)
    coefficients, defaulted = {}, []
    for key in _REQUIRED:
        if key not in flat:
            raise InputError(f"missing {key} (needed by every Magic Formula model)", where=name)
    for key, default in (dict.fromkeys(_REQUIRED, 0.0) | expected).items():
        if key in flat:
            value, sec = flat[key]
            if not isinstance(value, float):
                raise InputError(f"{key} must be a number, got {excerpt(str(value))}", where=at(sec, key))
            coefficients[key] = value
        else:
            coefficients[key] = default
            if key not in _SPECIAL or key in ("LONGVL", "PKY4"):
                defaulted.append(key)
    _check(coefficients, flat, at, units.get("LENGTH", "meter"))

    side_entry = flat.get("TYRESIDE")
    side = str(side_entry[0]).strip().upper() if side_entry else "LEFT"
    if side not in ("LEFT", "RIGHT", "SYMMETRIC"):
        raise InputError(f"TYRESIDE must be 'LEFT', 'RIGHT' or 'SYMMETRIC', got {excerpt(str(side_entry[0]))}",
                         where=at(side_entry[1], "TYRESIDE"))
    if side_entry is None:
        notes.append("no TYRESIDE: the tyre is taken as measured on the LEFT")
    unbounded = [f"{lo}/{hi}" for lo, hi in RANGE_PAIRS if lo not in flat or hi not in flat]
    if unbounded:
        notes.append(f"no validity range {', '.join(unbounded)}: the missing bounds are open")
    use_mode = flat.get("USE_MODE", (None,))[0]
    version = sections.get("MDI_HEADER", {}).get("FILE_VERSION")
    if family in (MF61, MF62):
        notes.append(f"{family}: evaluated at the nominal inflation pressure (pressure terms PPX*, PPY*, PPZ*, "
                     "QPZ*, PPMX1, QSY8 have no effect); turn slip and speed-dependent friction (LMUV) not modelled")
    if encoding != "utf-8":
        notes.append(f"not UTF-8: read as {encoding}")
    used = set(expected) | set(_REQUIRED) | _RECORDED
    ignored = tuple(f"{sec}.{key}" for key, (_, sec) in flat.items() if key not in used)
    unknown = tuple(s for s in sections if s not in _KNOWN_SECTIONS)
    return TyreProperties(
        path=name, family=family, file_format=file_format,
        file_version=version if isinstance(version, float) else None,
        tyre_side=side, use_mode=int(use_mode) if isinstance(use_mode, float) else None,
        units=MappingProxyType(units), coefficients=MappingProxyType(coefficients),
        sections=MappingProxyType({s: MappingProxyType(dict(e)) for s, e in sections.items()}),
        tables=MappingProxyType({s: TirTable(t[0], tuple(t[1])) for s, t in tables.items()}),
        defaulted=tuple(defaulted), ignored_keys=ignored, unknown_sections=unknown, encoding=encoding,
        notes=tuple(notes),
    )


def _si_factor(dimension: str, factors: dict[str, float]) -> float:
    """Factor from the file's units to SI of a dimension such as ``'F*T/L'``."""
    tokens = re.split(r"([*/])", dimension)
    value = factors[_LETTER[tokens[0]]]
    for op, letter in zip(tokens[1::2], tokens[2::2], strict=True):
        value = value * factors[_LETTER[letter]] if op == "*" else value / factors[_LETTER[letter]]
    return value


def _family(name, flat, sections, at) -> tuple[str, str]:
    """The model family, from FITTYP or PROPERTY_FILE_FORMAT."""
    accepted = "PAC2002, MF_05 (MF 5.2), MF_61 (MF 6.1) or MF_62 (MF 6.2)"
    if "FITTYP" in flat:
        value, sec = flat["FITTYP"]
        if not isinstance(value, float) or int(value) != value or int(value) not in _FITTYP:
            shown = repr(value) if isinstance(value, float) else excerpt(str(value))
            raise InputError(f"FITTYP {shown} is not a Magic Formula 5.2/6.x model (6, 21, 61 or 62)",
                             where=at(sec, "FITTYP"))
        return _FITTYP[int(value)], f"FITTYP={int(value)}"
    if "PROPERTY_FILE_FORMAT" not in flat:
        raise InputError(f"missing PROPERTY_FILE_FORMAT (or FITTYP) in [MODEL]; expected {accepted}", where=name)
    value, sec = flat["PROPERTY_FILE_FORMAT"]
    family = _FORMATS.get(re.sub(r"[\s_\-]", "", str(value).upper()))
    if family is None:
        raise InputError(f"PROPERTY_FILE_FORMAT {excerpt(str(value))} is not supported; expected {accepted}",
                         where=at(sec, "PROPERTY_FILE_FORMAT"))
    return family, str(value)


def _check(c: dict[str, float], flat, at, length_unit: str) -> None:
    """Values the equations cannot work with, and a radius no tyre has (lengths in another unit)."""

    def where(key):
        """``file:line`` of a key, or the key when the file lacks it."""
        return at(flat[key][1], key) if key in flat else key

    for key in ("FNOMIN", "UNLOADED_RADIUS", "LFZO"):
        if not c[key] > 0.0:
            raise InputError(f"{key} must be > 0, got {c[key]:g}", where=where(key))
    if not MIN_RADIUS_M <= c["UNLOADED_RADIUS"] <= MAX_RADIUS_M:
        raise InputError(f"UNLOADED_RADIUS {c['UNLOADED_RADIUS']:g} m is no tyre's ({MIN_RADIUS_M:g} to "
                         f"{MAX_RADIUS_M:g} m); are the file's lengths in {excerpt(length_unit)}, its [UNITS] LENGTH?",
                         where=where("UNLOADED_RADIUS"))
    if c["LMUY"] == 0.0:
        raise InputError("LMUY must not be 0 (the aligning-torque stiffness divides by it)", where=where("LMUY"))
    if c["LONGVL"] <= 0.0:
        raise InputError(f"LONGVL must be > 0 m/s, got {c['LONGVL']:g}", where=where("LONGVL"))
    for lo, hi in RANGE_PAIRS:
        if not c[lo] < c[hi]:
            raise InputError(f"{lo} ({c[lo]:g}) must be below {hi} ({c[hi]:g})", where=where(hi))
    if c["FZMIN"] < 0.0:
        raise InputError(f"FZMIN must be >= 0 N, got {c['FZMIN']:g}", where=where("FZMIN"))
