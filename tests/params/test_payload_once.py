"""trikedyn.params.ops payload and trikedyn.params.parameter_set.mass_properties: ``--payload`` becomes one schema
item added to the set (no dump of the whole set), and the mass properties are composed once per parameter set
(issue 22, "parameters read once"). The numbers are those of the earlier path (model_dump -> pydantic), pinned."""

import numpy as np
import pytest

import trikedyn.params.parameter_set as parameter_set
from trikedyn.mechanics import Box, Payload, PointMass
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle, mass_properties, with_freight, with_payload
from trikedyn.params.audit import audit
from trikedyn.params.ops import static_wheel_loads
from trikedyn.params.parameter_set import revalidated
from trikedyn.params.schema import PayloadItemSpec

# mass [kg], CG [m], inertia about the CG [kg m^2], as the earlier path composed them
PINNED = {
    ("reference-etrike", "freight 100"): (
        683.0, [0.7316461200585651, 0.013657393850658858, 0.48488023426061494],
        [[161.48863831332358, -0.937033792093704, 41.791707127379226],
         [-0.937033792093704, 456.64796678038056, 0.9745916251830153],
         [41.791707127379226, 0.9745916251830153, 461.20303212737923]]),
    ("reference-tadpole", "freight 35.5"): (
        618.5, [0.7927199676637025, 0.01508164915117219, 0.4213584478577203],
        [[135.0484602888278, -0.3673369416329839, 16.383227596831034],
         [-0.3673369416329839, 405.79176114050927, 0.3820604016168141],
         [16.383227596831034, 0.3820604016168141, 436.76043360511727]]),
    ("reference-etrike", "mixed"): (
        615.0, [0.8089663414634145, 0.01646829268292683, 0.40028162601626016],
        [[122.93637363408133, -0.3286176936585381, 4.9283532503414165],
         [-0.3286176936585381, 384.3752024356423, -0.25431889170731825],
         [4.9283532503414165, -0.25431889170731825, 428.2237430649758]]),
    ("reference-etrike", "mixed, then 5 kg off"): (
        610.0, [0.8114988524590163, 0.01578360655737705, 0.3970052459016394],
        [[122.09577789927866, -0.4587178485245911, 4.305794176327851],
         [-0.4587178485245911, 383.08856709240973, -0.08600469245901676],
         [4.305794176327851, -0.08600469245901676, 427.7073560652624]]),
}
MIXED = Payload("mixed", (PointMass(20.0, (0.5, 0.1, 0.8), name="a"),
                          Box(12.0, (0.2, -0.1, 0.7), (0.4, 0.3, 0.2), name="b")))
OFF = Payload("off", (PointMass(5.0, (0.5, 0.1, 0.8), name="c"),))


def _laden(vehicle: str, case: str):
    base = load_vehicle(vehicle)
    if case.startswith("freight"):
        return with_freight(base, float(case.split()[1]))
    mixed = with_payload(base, MIXED)
    return mixed if case == "mixed" else with_payload(mixed, OFF, remove=True)


def _dump_path(pset, payload: Payload, remove: bool = False):
    """The earlier path: the whole set dumped, the items appended as dicts, validated again."""
    data = pset.params.model_dump()
    data["payload"] = list(data["payload"])
    for item in payload.items:
        pos = getattr(item, "centre_m", getattr(item, "position_m", None))
        size = getattr(item, "size_m", (0.0, 0.0, 0.0))
        data["payload"].append(dict(name=item.name, mass_kg=item.mass_kg, x_m=pos[0], y_m=pos[1], z_m=pos[2],
                                    length_m=size[0], width_m=size[1], height_m=size[2], removed=remove))
    return revalidated(pset, data, "payload")


@pytest.mark.parametrize(("vehicle", "case"), list(PINNED))
def test_mass_properties_are_the_earlier_paths(vehicle, case):
    mass, cg, inertia = PINNED[(vehicle, case)]
    pset = _laden(vehicle, case)
    mp = mass_properties(pset.params)
    assert mp.mass_kg == pytest.approx(mass, rel=1e-13) and pset.mass_kg == pytest.approx(mass, rel=1e-13)
    np.testing.assert_allclose(mp.cg_m, cg, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(pset.cg_m, cg, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(mp.inertia_kgm2, inertia, rtol=1e-12, atol=1e-12)


def test_the_laden_set_equals_the_dump_paths():
    base = load_vehicle("reference-etrike")
    freight = Payload("paper-freight", (PointMass(100.0, (base.params.freight.x_m, base.params.freight.y_m,
                                                         base.params.freight.z_m), name="freight"),))
    assert with_freight(base, 100.0).params == _dump_path(base, freight).params
    assert with_payload(base, MIXED).params == _dump_path(base, MIXED).params
    mixed = with_payload(base, MIXED)
    assert with_payload(mixed, OFF, remove=True).params == _dump_path(mixed, OFF, remove=True).params
    items = with_freight(base, 100.0).params.payload
    assert len(items) == 1 and isinstance(items[0], PayloadItemSpec)
    assert (items[0].name, items[0].mass_kg, items[0].removed) == ("freight", 100.0, False)
    assert with_freight(base, 0.0) is base
    # the sections other than the payload are the set's own objects, not rebuilt from a dump
    laden = with_freight(base, 100.0).params
    assert laden.mass is base.params.mass and laden.wheels[0] is base.params.wheels[0]


def test_composed_once_through_payload_model_and_audit(monkeypatch):
    laden_calls = []
    real = parameter_set._composed

    def counting(params):
        if params.payload:
            laden_calls.append(params)
        return real(params)

    monkeypatch.setattr(parameter_set, "_composed", counting)
    pset = with_freight(load_vehicle("reference-etrike"), 100.0)
    build_model(pset)
    audit(pset)
    static_wheel_loads(pset.params)
    assert pset.mass_kg == 683.0 and pset.cg_m[2] == pytest.approx(0.48488023426061494, rel=1e-13)
    assert len(laden_calls) == 1 and laden_calls[0] is pset.params


def test_the_kept_composition_is_read_only_and_per_set():
    pset = with_freight(load_vehicle("reference-etrike"), 100.0)
    mp = mass_properties(pset.params)
    assert mass_properties(pset.params) is mp
    with pytest.raises(ValueError, match="read-only"):
        mp.cg_m[0] = 0.0
    empty = pset.params.model_copy(update={"payload": ()})
    assert mass_properties(empty).mass_kg == pytest.approx(583.0)
    assert mass_properties(pset.params).mass_kg == 683.0
    pset.cg_m[0] = 99.0  # a copy
    assert mass_properties(pset.params).cg_m[0] == pytest.approx(0.7316461200585651)


def test_refusals_are_worded_as_before():
    base = load_vehicle("reference-etrike")
    with pytest.raises(Exception, match=r"payload\[freight\]\.mass_kg: input should be less than or equal to 5000"):
        with_freight(base, 6000.0)
    with pytest.raises(Exception, match="puts the CG .* above the ground"):
        with_payload(base, Payload("p", (PointMass(560.0, (0.5, 0.0, 0.5), name="x"),)), remove=True)
    with pytest.raises(Exception, match=r"payload\[b\]\.x_m: input should be less than or equal to 10 \(got 20.0\)"):
        with_payload(base, Payload("p", (Box(10.0, (20.0, 0.0, 0.5), (1.0, 1.0, 1.0), name="b"),)))
