"""Synthetic tyre property files for the .tir reader and Magic Formula tests (no shared data needed).

The coefficients are made up, of the size a passenger-car PAC2002 fit has, with every shift and asymmetry
non-zero; ``SYMMETRIC`` lists the coefficients that make the tyre odd-symmetric at zero camber when zeroed.
"""

from pathlib import Path

import pytest
from tests.conftest import SHARED

REAL_TIR = SHARED / "data" / "tyres" / "mf_185_80R14.tir"

SECTIONS = {
    "VERTICAL": {"FNOMIN": 2000.0, "VERTICAL_STIFFNESS": 150000.0, "VERTICAL_DAMPING": 200.0},
    "VERTICAL_FORCE_RANGE": {"FZMIN": 100.0, "FZMAX": 6000.0},
    "LONG_SLIP_RANGE": {"KPUMIN": -1.0, "KPUMAX": 1.0},
    "SLIP_ANGLE_RANGE": {"ALPMIN": -1.0, "ALPMAX": 1.0},
    "INCLINATION_ANGLE_RANGE": {"CAMMIN": -0.3, "CAMMAX": 0.3},
    "SCALING_COEFFICIENTS": {k: 1.0 for k in "LFZO LCX LMUX LEX LKX LHX LVX LGAX LCY LMUY LEY LKY LHY LVY LGAY "
                             "LTR LRES LGAZ LXAL LYKA LVYKA LS LSGKP LSGAL LMX LVMX LMY".split()},
    "LONGITUDINAL_COEFFICIENTS": {
        "PCX1": 1.65, "PDX1": 1.2, "PDX2": -0.1, "PDX3": 0.5, "PEX1": 0.3, "PEX2": 0.1, "PEX3": 0.05,
        "PEX4": 0.02, "PKX1": 21.0, "PKX2": 0.5, "PKX3": 0.2, "PHX1": 0.001, "PHX2": 0.0005, "PVX1": 0.0002,
        "PVX2": -0.0001, "RBX1": 12.0, "RBX2": -10.0, "RCX1": 1.1, "REX1": 0.4, "REX2": -0.1, "RHX1": 0.002,
        "PTX1": 2.0, "PTX2": 0.1, "PTX3": 0.3},
    "OVERTURNING_COEFFICIENTS": {"QSX1": 0.0002, "QSX2": 0.5, "QSX3": 0.05},
    "LATERAL_COEFFICIENTS": {
        "PCY1": 1.35, "PDY1": 1.0, "PDY2": -0.15, "PDY3": -1.0, "PEY1": -0.5, "PEY2": -0.2, "PEY3": 0.1,
        "PEY4": -5.0, "PKY1": -18.0, "PKY2": 1.8, "PKY3": 0.3, "PHY1": 0.002, "PHY2": 0.001, "PHY3": 0.03,
        "PVY1": 0.03, "PVY2": -0.01, "PVY3": -0.3, "PVY4": -0.5, "RBY1": 7.0, "RBY2": 9.0, "RBY3": -0.02,
        "RCY1": 1.05, "REY1": -0.2, "REY2": 0.3, "RHY1": 0.001, "RHY2": -0.001, "RVY1": -0.02, "RVY2": 0.05,
        "RVY3": -0.2, "RVY4": 12.0, "RVY5": 1.9, "RVY6": -10.0, "PTY1": 2.0, "PTY2": 1.9},
    "ROLLING_COEFFICIENTS": {"QSY1": 0.012, "QSY2": 0.0, "QSY3": 0.001, "QSY4": 0.0},
    "ALIGNING_COEFFICIENTS": {
        "QBZ1": 10.0, "QBZ2": -1.8, "QBZ3": -0.5, "QBZ4": 0.04, "QBZ5": 0.4, "QBZ9": 9.0, "QBZ10": 0.0,
        "QCZ1": 1.2, "QDZ1": 0.09, "QDZ2": -0.009, "QDZ3": -0.05, "QDZ4": 0.7, "QDZ6": -0.006, "QDZ7": 0.005,
        "QDZ8": -0.18, "QDZ9": 0.03, "QEZ1": -1.5, "QEZ2": 0.3, "QEZ3": 0.0, "QEZ4": 0.25, "QEZ5": -3.5,
        "QHZ1": 0.004, "QHZ2": 0.002, "QHZ3": 0.12, "QHZ4": 0.06, "SSZ1": 0.03, "SSZ2": 0.004, "SSZ3": 0.5,
        "SSZ4": -0.2},
}
SYMMETRIC = dict.fromkeys(
    "PHX1 PHX2 PVX1 PVX2 PEX4 RHX1 PHY1 PHY2 PHY3 PVY1 PVY2 PVY3 PVY4 PEY3 RHY1 RHY2 RBY3 RVY1 RVY2 RVY3 "
    "QHZ1 QHZ2 QHZ3 QHZ4 QDZ6 QDZ7 QDZ8 QDZ9 QEZ4 QSX1 SSZ1".split(), 0.0)


def tir_text(side="LEFT", fmt="PAC2002", units=None, header_extra="", drop=(), **values) -> str:
    """A PAC2002 property file in the format's own layout and quirks; ``values`` override coefficients."""
    lines = [
        "[MDI_HEADER]", "FILE_TYPE                ='tir'", "FILE_VERSION             =3.0",
        "! : COMMENT :  a synthetic tyre, made-up coefficients", "$----------------------------------units",
        "[UNITS]",
    ]
    units = units or {"LENGTH": "meter", "FORCE": "newton", "ANGLE": "radian", "MASS": "kg", "TIME": "second"}
    lines += [f"{k:<25}= '{v}'" for k, v in units.items()]
    lines += ["$----------------------------------model", "[MODEL]", f"PROPERTY_FILE_FORMAT     ='{fmt}'",
              "USE_MODE                 = 4                    $Tyre use switch (IUSED)",
              f"LONGVL                   = {values.pop('LONGVL', 15.0)!r}", f"TYRESIDE                 = '{side}'",
              header_extra, "[DIMENSION]", f"UNLOADED_RADIUS          = {values.pop('UNLOADED_RADIUS', 0.3)!r}",
              "WIDTH = 0.205   $ nominal width", "[SHAPE]", "{radial width}", " 1.0    0.0", " 1.0    0.5",
              " 0.95   1.0"]
    for section, entries in SECTIONS.items():
        lines += [f"$------------------------------{section.lower()}", f"[{section}]"]
        for key, value in entries.items():
            if key not in drop:
                lines.append(f"{key:<25}= {values.pop(key, value)!r:<20} $ {key.lower()}")
    assert not values, f"unknown keys {values}"
    return "\n".join(lines) + "\n"


@pytest.fixture
def write_tir(tmp_path):
    """``write_tir(name, **tir_text_args) -> Path``: a synthetic .tir file in a temporary folder."""

    def write(name="tyre.tir", text=None, **kwargs) -> Path:
        path = tmp_path / name
        path.write_text(tir_text(**kwargs) if text is None else text, encoding="utf-8")
        return path

    return write


@pytest.fixture(scope="session")
def real_tir():
    if not REAL_TIR.is_file():
        pytest.skip(f"shared tyre data absent ({REAL_TIR})")
    from trikedyn.tyre.tir import read_tir

    return read_tir(REAL_TIR)


@pytest.fixture
def symmetric():
    """Overrides that make the synthetic tyre odd-symmetric at zero camber (no shifts, no asymmetry)."""
    return dict(SYMMETRIC)


@pytest.fixture
def synthetic_values():
    """The synthetic file's coefficients by section (SI)."""
    return {s: dict(v) for s, v in SECTIONS.items()}


@pytest.fixture
def make_tir_text():
    """:func:`tir_text`: the synthetic file's text, with overrides."""
    return tir_text
