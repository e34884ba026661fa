"""trikedyn.model.packing.record: compiled records are filled by field name, never by position (issue 22,
"records filled by field name"); build_model sets every WHEEL and VEHICLE field so."""

import numpy as np
import pytest

import trikedyn.model.vehicle as vehicle_module
from trikedyn.model.packing import ROAD, VEHICLE, WHEEL, record, road_record
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle


def _values(dtype, start=1.0):
    return {name: start + i for i, name in enumerate(dtype.names)}


def test_every_field_by_name():
    values = _values(WHEEL)
    row = record(WHEEL, values)
    assert row.shape == (1,) and row.dtype == WHEEL
    assert {n: float(row[0][n]) for n in WHEEL.names} == values


def test_a_missing_or_unknown_field_is_refused():
    values = _values(WHEEL)
    del values["relaxation_x"]
    with pytest.raises(ValueError, match=r"not set: relaxation_x$"):
        record(WHEEL, values)
    with pytest.raises(ValueError, match="not a field: radius_m"):
        record(WHEEL, _values(WHEEL) | {"radius_m": 0.3})
    with pytest.raises(ValueError, match="not set: g.*not a field: gravity"):
        record(VEHICLE, {k: v for k, v in _values(VEHICLE).items() if k != "g"} | {"gravity": 9.8})


def test_a_reordered_record_cannot_mix_fields():
    values = _values(WHEEL)
    reordered = np.dtype(list(reversed([(n, WHEEL.fields[n][0]) for n in WHEEL.names])), align=True)
    a, b = record(WHEEL, values)[0], record(reordered, values)[0]
    assert all(a[n] == b[n] for n in WHEEL.names)
    assert a.tolist() != b.tolist()  # by position they differ: a positional fill would have mixed them


def test_road_record_by_name():
    road = road_record(True, 10.0, 0.9, 0.06, 0.2, 1.5)[0]
    assert road.dtype == ROAD
    assert (int(road["bump"]), road["start"], road["length"], road["height"], road["y_min"], road["y_max"]) == (
        1, 10.0, 0.9, 0.06, 0.2, 1.5)


@pytest.mark.parametrize("preset", ["reference-etrike", "reference-tadpole"])
def test_build_model_fills_every_field_by_name(preset, monkeypatch):
    filled = []
    real = vehicle_module.record

    def spy(dtype, values):
        filled.append((dtype, dict(values)))
        return real(dtype, values)

    monkeypatch.setattr(vehicle_module, "record", spy)
    model = build_model(load_vehicle(preset))
    wheels = [v for d, v in filled if d == WHEEL]
    vehicles = [v for d, v in filled if d == VEHICLE]
    assert len(wheels) == 3 and len(vehicles) == 1
    for k, values in enumerate(wheels):
        assert set(values) == set(WHEEL.names)
        for name in WHEEL.names:
            assert model.plant.wheels[k][name] == values[name], name
    assert model.plant.vehicle[0]["wheelbase"] == vehicles[0]["wheelbase"] > 0
    # named values that say which is which: the steered wheels carry the servo, the rear one none
    for k, station in enumerate(model.tree.wheels):
        steered = station.steer_body >= 0
        assert (model.plant.wheels[k]["steer_kp"] > 0) == steered
        assert model.plant.wheels[k]["radius"] == pytest.approx(load_vehicle(preset).params.wheel(station.name).radius_m)
