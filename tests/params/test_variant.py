"""trikedyn.params.variant: a vehicle variant (scale factors, overrides, freight) with one set of bounds."""

import pytest

from trikedyn.errors import InputError
from trikedyn.params import load_vehicle, override, scale_suspension, with_freight
from trikedyn.params.variant import VARIANT_OPTIONS, Variant, variant_option


def test_defaults_and_round_trip():
    v = Variant()
    assert v.to_dict() == {"stiffness_scale": 1.0, "damping_scale": 1.0, "overrides": {}, "freight_kg": 0.0}
    assert {o.name: o.default for o in VARIANT_OPTIONS} == {k: x for k, x in v.to_dict().items() if k != "overrides"}
    w = Variant(stiffness_scale=1.2, damping_scale=0.8, overrides={"mass.driver_kg": 90}, freight_kg=50)
    assert Variant.from_dict(w.to_dict()) == w and hash(Variant.from_dict(w.to_dict())) == hash(w)
    assert Variant.from_dict({"stiffness_scale": 1.2, "manoeuvre": "dlc"}) == Variant(stiffness_scale=1.2)


def test_apply_is_scale_then_override_then_freight():
    base = load_vehicle("reference-etrike")
    w = Variant(stiffness_scale=1.2, damping_scale=0.8, overrides={"mass.driver_kg": 90.0}, freight_kg=50.0)
    expected = with_freight(override(scale_suspension(base, stiffness=1.2, damping=0.8), {"mass.driver_kg": 90.0}), 50.0)
    assert w.apply(base).params == expected.params
    assert w.apply(base).params != base.params


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"stiffness_scale": 0.0}, "stiffness_scale: must be within [0.01, 100], got 0"),
        ({"damping_scale": 200.0}, "damping_scale: must be within [0.01, 100], got 200"),
        ({"freight_kg": -5.0}, "freight_kg: must be within [0, 2000] kg, got -5"),
        ({"freight_kg": float("inf")}, "freight_kg: expected a finite number"),
        ({"overrides": {3: 1.0}}, "overrides: an override is named by a dotted path"),
    ],
)
def test_bad_values_are_refused_naming_them(changes, message):
    with pytest.raises(InputError) as info:
        Variant(**changes)
    assert message in str(info.value)


def test_the_cli_and_the_study_spec_refuse_the_same_scale(capsys):
    import inspect

    from trikedyn.cli import main
    from trikedyn.commands.stability import threshold_cmd
    from trikedyn.study.spec import parse_spec

    given = inspect.signature(threshold_cmd).parameters  # the command's defaults are the variant's
    assert (given["stiffness"].default, given["damping"].default) == (Variant().stiffness_scale, Variant().damping_scale)

    assert variant_option("stiffness_scale").minimum == 0.01
    assert main(["threshold", "reference-etrike", "--stiffness-scale", "0"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--stiffness-scale: must be within [0.01, 100], got 0" in err
    with pytest.raises(InputError, match=r"groups\[g\]\.stiffness_scale: must be within \[0.01, 100\], got 0"):
        parse_spec('name = "s"\n[[groups]]\nname = "g"\nstiffness_scale = [0]\n')
