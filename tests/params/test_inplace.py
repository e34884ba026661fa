"""The in-place update of a vehicle file's table (trikedyn.params.inplace): only the lines of the keys set change."""

from __future__ import annotations

import pytest

from trikedyn.errors import InputError
from trikedyn.params import load_vehicle
from trikedyn.params.inplace import set_table_lines, update_vehicle_file

LINES = {"stiffness_N_per_m": "stiffness_N_per_m = 1.0", "damping_ratio": "damping_ratio = 0.2"}


def test_a_key_line_is_replaced_its_comment_kept_and_a_missing_key_added():
    text = ('# top\n[suspension.front]\nstiffness_N_per_m = { value = 5.0, source = "a # b" }  # old spring\n'
            "kind = 'telescopic'\n\n# the rear\n[suspension.rear]\nstiffness_N_per_m = 3.0\n")
    out = set_table_lines(text, ("suspension", "front"), LINES)
    assert out == ("# top\n[suspension.front]\nstiffness_N_per_m = 1.0  # old spring\nkind = 'telescopic'\n"
                   "damping_ratio = 0.2\n\n# the rear\n[suspension.rear]\nstiffness_N_per_m = 3.0\n")


def test_a_missing_table_is_added_at_the_end_with_the_files_line_ends():
    out = set_table_lines('name = "x"\r\n[mass]\r\ncurb_kg = 1\r\n', ("suspension", "front"), LINES)
    assert out == ('name = "x"\r\n[mass]\r\ncurb_kg = 1\r\n\r\n[suspension.front]\r\nstiffness_N_per_m = 1.0\r\n'
                   "damping_ratio = 0.2\r\n")
    assert set_table_lines('name = "x"', ("a",), {"k": "k = 1"}) == 'name = "x"\n\n[a]\nk = 1\n'


def test_a_quoted_header_and_an_array_of_tables_after():
    text = '[suspension."front"]\n"stiffness_N_per_m" = 2.0\n[[wheels]]\nname = "front"\n'
    out = set_table_lines(text, ("suspension", "front"), {"stiffness_N_per_m": "stiffness_N_per_m = 1.0"})
    assert out == '[suspension."front"]\nstiffness_N_per_m = 1.0\n[[wheels]]\nname = "front"\n'


def test_update_keeps_everything_else(tmp_path):
    path = tmp_path / "v.toml"
    body = 'extends = "reference-etrike"   # the paper\nname = "v"\n\n[suspension.rear]\nmoving_mass_kg = 6.0\n'
    path.write_text(body, encoding="utf-8")
    replaced = update_vehicle_file(path, ("suspension", "rear"), {"stiffness_N_per_m": (50000.0, "bench")})
    assert replaced == []
    assert path.read_text(encoding="utf-8") == body + 'stiffness_N_per_m = { value = 50000.0, source = "bench" }\n'
    pset = load_vehicle(path)
    assert pset.params.suspension["rear"].stiffness_N_per_m == 50000.0
    assert pset.notes["suspension.rear.stiffness_N_per_m"] == {"source": "bench"}
    with pytest.raises(InputError, match="suspension.rear.stiffness_N_per_m is set in this file .source 'bench'."):
        update_vehicle_file(path, ("suspension", "rear"), {"stiffness_N_per_m": (1.0e5, "other")})
    assert update_vehicle_file(path, ("suspension", "rear"), {"stiffness_N_per_m": (1.0e5, "other")},
                               replaceable=lambda source: source == "bench") == ["suspension.rear.stiffness_N_per_m"]
    with pytest.raises(InputError, match="input should be|cannot update"):  # a value the schema refuses: unchanged
        update_vehicle_file(path, ("suspension", "rear"), {"stiffness_N_per_m": (-1.0, "x")}, force=True)
    assert load_vehicle(path).params.suspension["rear"].stiffness_N_per_m == 1.0e5
