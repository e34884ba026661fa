"""The .tir reader: the format's quirks, units to SI, defaults, and one-line errors naming file:line."""

import math

import pytest

from trikedyn.errors import InputError
from trikedyn.tyre.tir import MAX_BYTES, parse_tir, read_tir


def test_synthetic_file_reads_every_value(write_tir, synthetic_values):
    tir = read_tir(write_tir())
    assert (tir.family, tir.file_format, tir.file_version, tir.tyre_side, tir.use_mode) == (
        "PAC2002", "PAC2002", 3.0, "LEFT", 4)
    for entries in synthetic_values.values():
        for key, value in entries.items():
            assert tir[key] == value, key
    assert tir.unloaded_radius == 0.3 and tir.fnomin == 2000.0 and tir["LONGVL"] == 15.0
    assert tir.dimensions == {"UNLOADED_RADIUS": 0.3, "WIDTH": 0.205}
    assert tir.tables["SHAPE"].columns == ("radial", "width")
    assert tir.tables["SHAPE"].rows == ((1.0, 0.0), (1.0, 0.5), (0.95, 1.0))
    assert tir.ranges == {"fz": (100.0, 6000.0), "kappa": (-1.0, 1.0), "alpha": (-1.0, 1.0), "gamma": (-0.3, 0.3)}
    assert tir.defaulted == () and tir.ignored_keys == () and tir.unknown_sections == ()
    with pytest.raises(TypeError):  # immutable
        tir.coefficients["PKY1"] = 0.0
    with pytest.raises(AttributeError):
        tir.family = "MF6.1"


def test_quirks_comments_quotes_case_and_fortran_numbers():
    text = """[MDI_HEADER]
FILE_VERSION = 3.0 ! a comment after a value
[model]
property_file_format = 'PAC2002'   $ lower-case keys and section
TYRESIDE = RIGHT
FITTYP = 6
$ a whole-line comment
! another
[DIMENSION]
UNLOADED_RADIUS = 3.0D-01
[VERTICAL]
FNOMIN = 4.0E+003$no space before the comment
[SCALING_COEFFICIENTS]
LMUY = '1.0$not a comment'
[MY_OWN_SECTION]
ANYTHING = 1
"""
    with pytest.raises(InputError, match=r"x\.tir:14: LMUY must be a number"):
        parse_tir(text, "x.tir")
    tir = parse_tir(text.replace("'1.0$not a comment'", "0.9"), "x.tir")
    assert tir.tyre_side == "RIGHT" and tir.family == "PAC2002" and tir.file_format == "FITTYP=6"
    assert tir.unloaded_radius == 0.3 and tir.fnomin == 4000.0 and tir["LMUY"] == 0.9
    assert tir.unknown_sections == ("MY_OWN_SECTION",) and tir.ignored_keys == ("MY_OWN_SECTION.ANYTHING",)
    assert "PKY1" in tir.defaulted and tir["PKY1"] == 0.0 and tir["LKY"] == 1.0  # format defaults
    assert tir.ranges["fz"] == (0.0, math.inf) and any("no validity range" in n for n in tir.notes)
    assert any("no [UNITS]" in n for n in tir.notes)


def test_units_are_converted_to_si(make_tir_text):
    si = parse_tir(make_tir_text(), "si.tir")
    deg = math.pi / 180.0
    text = make_tir_text(
        units={"LENGTH": "millimeter", "FORCE": "kN", "ANGLE": "degrees", "MASS": "gram", "TIME": "second"},
        FNOMIN=2.0, UNLOADED_RADIUS=300.0, VERTICAL_STIFFNESS=0.15, VERTICAL_DAMPING=0.0002, LONGVL=15000.0,
        FZMIN=0.1, FZMAX=6.0, ALPMIN=-1.0 / deg, ALPMAX=1.0 / deg, CAMMIN=-0.3 / deg, CAMMAX=0.3 / deg)
    other = parse_tir(text, "mm.tir")
    for key, value in si.coefficients.items():
        assert other[key] == pytest.approx(value, rel=1e-12, abs=0.0), key
    assert other.units["FORCE"] == "kn" and other.dimensions["WIDTH"] == pytest.approx(0.205e-3)


@pytest.mark.parametrize(
    ("change", "where", "what"),
    [
        (("PCX1                     = 1.65", "PCX1 1.65"), ":79", "cannot read 'PCX1 1.65'"),
        (("PCX1                     = 1.65", "PCX1 = nan"), ":79", "PCX1: nan is not a finite number"),
        (("PCX1                     = 1.65", "PCX1 = 1e999"), ":79", "not a finite number"),
        (("PCX1                     = 1.65", "PCX1 = 'abc'"), ":79", "PCX1 must be a number"),
        (("PDX1                     = 1.2", "PCX1 = 1.2"), ":80", "PCX1 given twice in [LONGITUDINAL_COEFFICIENTS]"),
        (("[MDI_HEADER]", "FOO = 1\n[MDI_HEADER]"), ":1", "before any [SECTION] header"),
        (("'newton'", "'stone'"), ":8", "unknown force unit 'stone'"),
        (("='PAC2002'", "='PAC89'"), ":14", "PROPERTY_FILE_FORMAT 'PAC89' is not supported"),
        ((" 0.95   1.0", " 0.95 1.0 2.0"), ":26", "table row has 3 numbers, its header 2"),
        (("'LEFT'", "'MIDDLE'"), ":17", "TYRESIDE must be"),
        (("FZMAX                    = 6000.0", "FZMAX = 10.0"), ":35", "FZMIN (100) must be below FZMAX (10)"),
        (("[DIMENSION]", "[DIMENSION"), ":19", "malformed section header"),
        (("FILE_VERSION             =3.0", "FILE_VERSION ="), ":3", "FILE_VERSION has no value"),
        (("LFZO                     = 1.0", "LFZO = 0"), ":50", "LFZO must be > 0"),
    ],
)
def test_mistakes_name_file_and_line(write_tir, make_tir_text, change, where, what):
    text = make_tir_text()
    assert change[0] in text
    path = write_tir(text=text.replace(change[0], change[1], 1))
    with pytest.raises(InputError) as info:
        read_tir(path)
    assert info.value.where == f"{path}{where}" and what in str(info.value)
    assert "\n" not in str(info.value) and str(info.value).startswith(f"{path}{where}: ")


def test_missing_required_and_bounded_reading(write_tir, make_tir_text, tmp_path):
    text = make_tir_text().replace("FNOMIN                   = 2000.0", "")
    with pytest.raises(InputError, match=r"tyre\.tir: missing FNOMIN"):
        read_tir(write_tir(text=text))
    with pytest.raises(InputError, match="missing PROPERTY_FILE_FORMAT"):
        read_tir(write_tir(text=make_tir_text().replace("PROPERTY_FILE_FORMAT     ='PAC2002'", "")))
    big = tmp_path / "big.tir"
    big.write_bytes(b"$" * (MAX_BYTES + 1))
    with pytest.raises(InputError, match="larger than 1024 KiB"):
        read_tir(big)
    binary = tmp_path / "binary.tir"
    binary.write_bytes(b"[MODEL]\x00\x01")
    with pytest.raises(InputError, match="NUL bytes"):
        read_tir(binary)
    with pytest.raises(InputError, match="no such file"):
        read_tir(tmp_path / "absent.tir")
    with pytest.raises(InputError, match="is a folder"):
        read_tir(tmp_path)
    with pytest.raises(InputError, match="longer than"):
        parse_tir("[MODEL]\n" + "A" * 5000, "long.tir")


def test_latin1_file_is_read_with_a_note(tmp_path, make_tir_text):
    path = tmp_path / "latin.tir"
    path.write_bytes(make_tir_text().replace("made-up", "r\u00e9sum\u00e9").encode("latin-1"))
    tir = read_tir(path)
    assert tir.encoding == "latin-1" and any("latin-1" in n for n in tir.notes) and tir.fnomin == 2000.0
    bom = tmp_path / "bom.tir"
    bom.write_bytes(b"\xef\xbb\xbf" + make_tir_text().encode())
    assert read_tir(bom).encoding == "utf-8"


def test_mf61_family_and_its_defaults(make_tir_text):
    tir = parse_tir(make_tir_text(fmt="MF_61"), "mf61.tir")
    assert tir.family == "MF6.1" and tir.mf6 and tir["PKY4"] == 2.0 and tir["LKYC"] == 1.0
    assert "PKY6" in tir.defaulted and "PHY3" not in tir.coefficients
    assert any(k.endswith(".PHY3") for k in tir.ignored_keys)  # a PAC2002-only term, kept but not used
    assert any("nominal inflation pressure" in n for n in tir.notes)
    assert parse_tir(make_tir_text(fmt="USER", header_extra="FITTYP = 62"), "x").family == "MF6.2"
    with pytest.raises(InputError, match="FITTYP 5.0 is not a Magic Formula"):
        parse_tir(make_tir_text(header_extra="FITTYP = 5"), "x")


def test_real_file(real_tir):
    tir = real_tir
    assert (tir.family, tir.file_version, tir.tyre_side, tir.use_mode) == ("PAC2002", 3.0, "LEFT", 4)
    assert tir.fnomin == 3800.0 and tir.unloaded_radius == 0.376
    assert (tir.vertical_stiffness, tir.vertical_damping) == (1.75e5, 50.0)
    assert (tir["PKY1"], tir["PKY2"], tir["PKX1"], tir["PKX2"], tir["PKX3"]) == (-12.536, 1.3856, 19.733, 0.093405,
                                                                                 0.12433)
    assert tir["PDX3"] == 9.9376e-006 and tir["PVY1"] == 0.031255  # "$" comments straight after values
    assert tir.tables["SHAPE"].rows[-1] == (0.9, 1.0) and tir.ranges["fz"] == (190.0, 8550.0)
    assert tir.defaulted == () and "ALIGNING_COEFFICIENTS.QTZ1" in tir.ignored_keys
