"""Fuzzing tyre property files (issue 21): a ``.tir`` (the real one from ``shared/data`` when it is at hand, and
a synthetic PAC2002 file with every coefficient set), its bytes mutated, read by ``tyre show`` and as a wheel's
``tyre_file`` of a vehicle file by ``vehicle check``. Each case exits 0 or 2 (``vehicle check`` also 1:
inconsistent findings); an error is the one line on stderr; ``--json`` output is valid JSON; nothing hangs
(:mod:`tests.fuzz.contract`)."""

from __future__ import annotations

import re

import pytest
from hypothesis import event, given
from hypothesis import strategies as st

from ..tyre.conftest import REAL_TIR, tir_text
from .contract import check_contract, mutated


def _seeds() -> list[bytes]:
    seeds = [tir_text().encode("utf-8")]
    if REAL_TIR.is_file():
        seeds.append(REAL_TIR.read_bytes())
    return seeds


def _radius(seed: bytes) -> float:
    """The seed's UNLOADED_RADIUS [m]: the wheel of the vehicle file is given it (no plausibility warning)."""
    return float(re.search(rb"UNLOADED_RADIUS\s*=\s*([0-9.eE+-]+)", seed).group(1))


def _vehicle(radius_m: float) -> str:
    return (f'extends = "reference-etrike"\nname = "tir-fuzz"\ndescription = "a .tir on the front wheel"\n'
            f'[[wheels]]\nname = "front"\ntyre_file = "x.tir"\nradius_m = {radius_m}\n')


@pytest.mark.parametrize("seed", range(len(_seeds())), ids=["synthetic", "real"][: len(_seeds())])
@given(data=st.data())
def test_tir_files(tmp_path, seed, data):
    raw = _seeds()[seed]
    (tmp_path / "x.tir").write_bytes(data.draw(mutated(raw)))
    if data.draw(st.booleans()):
        args = ["tyre", "show", str(tmp_path / "x.tir"), "--json"]
    else:
        (tmp_path / "vehicle.toml").write_text(_vehicle(_radius(raw)), encoding="utf-8")
        args = ["vehicle", "check", str(tmp_path / "vehicle.toml"), "--json"]
    code = check_contract(args, one_line=True)
    event(f"{args[0]} {args[1]}: exit {code}")
