"""The shared pieces of error messages and of reading built-in TOML files."""

import pytest

from trikedyn.errors import InputError, did_you_mean
from trikedyn.params.tomlfile import MAX_KEY_CHARS, builtin_names


def test_did_you_mean_names_the_closest_choice_or_nothing():
    assert did_you_mean("dlk", ["dlc", "slc", "circle"]) == "; did you mean 'dlc'?"
    assert did_you_mean("zzz", ["dlc", "slc"]) == ""
    assert did_you_mean("mass.cg_z", ["mass.cg_z_m"]) == "; did you mean 'mass.cg_z_m'?"
    assert did_you_mean("mass.cg_z", ["mass.cg_z_m"], 0.95) == ""  # a match of 0.9, below the cutoff


def test_every_builtin_listing_is_the_folder_of_toml_files():
    from importlib import resources

    from trikedyn.params import list_presets
    from trikedyn.study.optimise_spec import list_optimise_specs
    from trikedyn.study.spec import list_specs

    assert list_specs() == builtin_names(resources.files("trikedyn.study") / "specs") == ["paper"]
    assert list_optimise_specs() == ["battery-layout"]
    assert "reference-etrike" in list_presets() and list_presets() == sorted(list_presets())


@pytest.mark.parametrize("kind", ["study", "optimise"])
def test_spec_files_are_read_within_the_same_bounds_as_vehicle_files(kind):
    """A study or optimise spec goes through the one bounded TOML reader (a huge key is refused, one line)."""
    from trikedyn.study.optimise_spec import parse_optimise_spec
    from trikedyn.study.spec import parse_spec

    text = f'{"k" * (MAX_KEY_CHARS + 1)} = 1\n'
    with pytest.raises(InputError, match="keys have at most") as info:
        (parse_spec if kind == "study" else parse_optimise_spec)(text, origin="x.toml")
    assert info.value.where == "x.toml" and "\n" not in str(info.value)
    with pytest.raises(InputError, match="invalid TOML"):
        (parse_spec if kind == "study" else parse_optimise_spec)("[broken\n", origin="x.toml")
