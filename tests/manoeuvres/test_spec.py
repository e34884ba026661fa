"""trikedyn.manoeuvres.spec: a manoeuvre with its options, checked against the registry's option table."""

import pytest

from trikedyn.errors import InputError
from trikedyn.manoeuvres.registry import build
from trikedyn.manoeuvres.spec import ManoeuvreSpec, manoeuvre_label
from trikedyn.params import load_vehicle


def test_options_are_checked_converted_and_kept_as_given():
    spec = ManoeuvreSpec("dlc", {"run_in_m": "40", "direction": "right"})
    assert spec.options == {"direction": "right", "run_in_m": 40.0}
    assert spec == ManoeuvreSpec("dlc", {"direction": "right", "run_in_m": 40})
    assert hash(spec) == hash(ManoeuvreSpec("dlc", {"run_in_m": 40.0, "direction": "right"}))
    assert ManoeuvreSpec("dlc") == ManoeuvreSpec("dlc", {}) and ManoeuvreSpec().name == "dlc"
    assert spec.label == "dlc(direction=right, run_in_m=40)" and ManoeuvreSpec("slc").label == "slc"
    assert manoeuvre_label("slc", {"lateral_offset_m": 2.5}) == "slc(lateral_offset_m=2.5)"
    complete = spec.complete_options()
    assert complete["run_in_m"] == 40.0 and complete["standard"] == "ISO 3888-1"


def test_round_trip_and_with_options():
    spec = ManoeuvreSpec("slc", {"lateral_offset_m": 2.5})
    assert ManoeuvreSpec.from_dict(spec.to_dict()) == spec
    assert spec.to_dict() == {"name": "slc", "options": {"lateral_offset_m": 2.5}}
    assert spec.with_options(length_m=60).options == {"lateral_offset_m": 2.5, "length_m": 60.0}


def test_build_is_the_registry_build_with_the_options():
    params = load_vehicle("reference-etrike").params
    spec = ManoeuvreSpec("slc", {"lateral_offset_m": 2.5})
    built = spec.build(params, 40.0)
    direct = build("slc", params, 40.0, lateral_offset_m=2.5)
    assert built.parameters == direct.parameters and built.parameters["lateral_offset_m"] == 2.5


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ({"name": "dlc", "run_in": 40}, "manoeuvres[1]: manoeuvre 'dlc' has no option 'run_in'; did you mean 'run_in_m'?"),
        ({"name": "dlc", "run_in_m": "40"}, "manoeuvres[1]: dlc.run_in_m: expected a number, got '40'"),
        ({"name": "dlc", "direction": "up"}, "manoeuvres[1]: dlc.direction: expected one of left, right"),
        ({"name": "dcl"}, "unknown manoeuvre 'dcl'; did you mean 'dlc'?"),
        ({"run_in_m": 40}, "manoeuvres[1]: a manoeuvre table needs a name"),
        (3, "manoeuvres[1]: expected a manoeuvre name or a table"),
    ],
)
def test_a_file_entry_is_refused_in_one_line_naming_the_option(entry, message):
    with pytest.raises(InputError) as info:
        ManoeuvreSpec.from_entry(entry, where="manoeuvres[1]")
    assert message in str(info.value) and "\n" not in str(info.value)


def test_a_file_entry_takes_a_name_or_a_table():
    assert ManoeuvreSpec.from_entry("slc") == ManoeuvreSpec("slc")
    assert ManoeuvreSpec.from_entry({"name": "dlc", "run_in_m": 40}) == ManoeuvreSpec("dlc", {"run_in_m": 40.0})


def test_a_path_csv_takes_the_path_options_but_not_file():
    assert ManoeuvreSpec("lap.csv", {"smoothing_m": 0.05}).options == {"smoothing_m": 0.05}
    with pytest.raises(InputError, match="the path file is the manoeuvre's name"):
        ManoeuvreSpec("lap.csv", {"file": "other.csv"})
