"""Schema bounds (physical ranges, not just signs) and an audit that stays finite on whatever they accept."""

import json
import math
import typing

import numpy as np
import pytest
from annotated_types import Ge, Gt, Le, Lt
from pydantic import BaseModel

from trikedyn.cli import main
from trikedyn.errors import InputError, ParameterError
from trikedyn.measure.cg import Payload, PointMass
from trikedyn.params import audit, list_presets, load_vehicle, override, with_payload
from trikedyn.params.schema import VehicleParameters


def _all_finite(findings) -> bool:
    for f in findings:
        for value in f.values.values():
            if isinstance(value, float) and not math.isfinite(value):
                return False
    json.dumps([f.to_dict() for f in findings], allow_nan=False)
    return True


def _leaves(data, prefix=""):
    """Dotted override paths of every numeric leaf (wheels and payload items by name); the declared ranges of
    the assumed values (``[ranges]``) are not parameters (tests/study/test_ranges.py)."""
    if isinstance(data, dict):
        for key, value in data.items():
            if not prefix and key == "ranges":
                continue
            yield from _leaves(value, f"{prefix}{key}.")
    elif isinstance(data, list | tuple):
        for item in data:
            yield from _leaves(item, f"{prefix}{item['name']}.")
    elif isinstance(data, float | int) and not isinstance(data, bool):
        yield prefix[:-1]


def _field(path: str):
    """The pydantic field of a dotted path of VehicleParameters."""
    model, info = VehicleParameters, None
    parts = path.split(".")
    i = 0
    while i < len(parts):
        info = model.model_fields[parts[i]]
        inner = _model_in(info.annotation)
        if inner is not None and i < len(parts) - 1:
            model = inner
            i += 2 if parts[i] in ("suspension", "wheels", "payload", "components") else 1
        else:
            i += 1
    return info


def _model_in(annotation):
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in typing.get_args(annotation):
        found = _model_in(arg)
        if found is not None:
            return found
    return None


def _bounds(info) -> tuple[float, float]:
    """(least, largest) value the schema accepts for a field: its Ge/Gt/Le and its physical minimum."""
    low, high = -math.inf, math.inf
    stack = [*info.metadata, *typing.get_args(info.annotation)]
    while stack:
        item = stack.pop()
        if isinstance(item, Ge | Gt):
            low = max(low, item.ge if isinstance(item, Ge) else item.gt)
        elif isinstance(item, Le | Lt):
            high = item.le if isinstance(item, Le) else item.lt
        elif hasattr(getattr(item, "func", None), "minimum"):
            low = max(low, item.func.minimum)
        stack.extend(getattr(item, "__metadata__", ()))
        stack.extend(typing.get_args(item) if typing.get_origin(item) is not None else ())
    return low, high


@pytest.fixture(scope="module")
def laden():
    base = load_vehicle("reference-etrike")
    return with_payload(base, Payload("cargo", (PointMass(100.0, (0.2, 0.0, 1.0), name="cargo"),)))


def test_every_numeric_field_has_a_finite_range(laden):
    paths = list(_leaves(laden.params.model_dump()))
    assert len(paths) > 80
    for path in paths:
        low, high = _bounds(_field(path))
        assert -math.inf < low < high < math.inf, (path, low, high)
        if path.endswith(("_N_per_m", "_kgm2", "_hz", "radius_m", "length_m")) and "product" not in path:
            assert low > 0 or path.startswith(("payload", "components")) or "moving_inertia" in path, (path, low)


def test_stiffness_of_1e_300_is_refused_where_it_once_divided_by_zero(tmp_path, capsys):
    file = tmp_path / "soft.toml"
    file.write_text('extends = "reference-etrike"\n[suspension.rear]\nstiffness_N_per_m = 1e-300\n')
    assert main(["vehicle", "check", str(file)]) == 2
    err = capsys.readouterr().err
    assert err == f"trikedyn: error: {file}: suspension.rear.stiffness_N_per_m: input should be at least 100 N/m (got 1e-300)\n"


@pytest.mark.parametrize(
    ("values", "needle"),
    [
        ({"mass.curb_kg": -1.0}, "mass.curb_kg: input should be greater than 0"),  # the sign first, as before
        ({"mass.curb_kg": 1e-9}, "mass.curb_kg: input should be at least 10 kg"),
        ({"wheels.front.mass_kg": 1e-12}, "mass_kg: input should be at least 0.2 kg (got 1e-12)"),
        ({"tyre.vertical_stiffness_N_per_m": 10.0}, "input should be at least 1000 N/m"),
        ({"suspension.front.damping_Ns_per_m": 1e9}, "less than or equal to 100000"),
        ({"tyre.mu_y": float("nan")}, "tyre.mu_y: input should be a finite number"),
        ({"mass.cg_x_m": float("inf")}, "input should be a finite number"),
        ({"suspension.front.natural_frequency_hz": 1e-300}, "input should be at least 0.1 Hz"),
        ({"wheels.front.x_m": 0.01}, "wheel 'front' is 0.010 m from the line through the other two"),
        ({"wheels.rear_left.y_m": 0.01, "wheels.rear_right.y_m": -0.01}, "must span a triangle"),
        ({"name": "n" * 500}, "name: string should have at most 100 characters"),
    ],
)
def test_out_of_range_values_give_one_line(values, needle):
    with pytest.raises(ParameterError) as info:
        override(load_vehicle("reference-etrike"), values)
    assert needle in str(info.value) and "\n" not in str(info.value)


def test_payload_must_leave_a_vehicle_above_the_ground():
    base = load_vehicle("reference-etrike")
    with pytest.raises(InputError, match="payload: cannot remove 580 kg from 583 kg"):
        with_payload(base, Payload("x", (PointMass(580.0, (0.8, 0.0, 0.4)),)), remove=True)
    with pytest.raises(InputError, match="payload: puts the CG -0.8.. m above the ground"):
        with_payload(base, Payload("x", (PointMass(5000.0, (0.8, 0.0, -1.0)),)))


def test_presets_and_the_test_suites_vehicles_are_valid():
    """Values other tests set (rigid springs, stiff grippy tyres, light parts) stay inside the ranges."""
    for name in list_presets():
        load_vehicle(name)
    base = load_vehicle("reference-etrike")
    override(base, {"suspension.front.stiffness_N_per_m": 5e6, "suspension.rear.stiffness_N_per_m": 1e7,
                    "suspension.front.damping_Ns_per_m": 2e4, "tyre.vertical_stiffness_N_per_m": 2e6,
                    "tyre.vertical_damping_Ns_per_m": 2e3, "tyre.mu_x": 3.0, "tyre.mu_y": 3.0,
                    "drive.max_power_W": 5e4, "drive.max_drive_torque_Nm": 1000.0, "mass.cg_z_m": 1.1,
                    "steering.head_mass_kg": 0.5, "steering.head_inertia_kgm2": 0.05,
                    "suspension.front.moving_mass_kg": 0.5, "suspension.rear.moving_inertia_kgm2": 0.04,
                    "wheels.front.mass_kg": 1.0, "wheels.front.spin_inertia_kgm2": 0.03, "mass.cg_y_m": -1.0})


CANDIDATES = [-1e300, -1e6, -10.0, -1.0, -1e-300, 0.0, 1e-300, 1e-9, 1e-3, 5e-3, 0.01, 0.05, 0.1, 0.2, 0.3,
              0.5, 1.0, 2.0, 5.0, 10.0, 100.0, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e300]


def test_audit_is_finite_for_every_single_value_the_schema_accepts(laden):
    """Each numeric field in turn at each candidate magnitude and at its own bounds: what validates, the
    audit reports with finite numbers (or None), never an exception or NaN/inf."""
    accepted = 0
    for path in _leaves(laden.params.model_dump()):
        low, high = _bounds(_field(path))
        for value in {*CANDIDATES, low, high} - {-math.inf, math.inf}:
            try:
                variant = override(laden, {path: value})
            except InputError:
                continue
            accepted += 1
            assert _all_finite(audit(variant)), (path, value)
    assert accepted > 500


def test_audit_is_finite_for_random_sets_within_the_ranges(laden):
    """A quarter of the fields at once, each drawn log-uniformly (uniformly if signed) within its range."""
    rng = np.random.default_rng(7)
    # components are left out: the audit does not read them, and their masses share one budget (the body
    # mass; tests/params/test_knobs.py), which a quarter of them drawn at random would nearly always exceed
    ranges = {p: _bounds(_field(p)) for p in _leaves(laden.params.model_dump()) if not p.startswith("components.")}
    accepted = 0
    for _ in range(2000):
        values = {
            path: float(np.exp(rng.uniform(math.log(low), math.log(high)))) if low > 0 else float(rng.uniform(low, high))
            for path, (low, high) in ranges.items()
            if rng.random() < 0.25
        }
        try:
            variant = override(laden, values)
        except InputError:
            continue
        accepted += 1
        assert _all_finite(audit(variant)), values
    assert accepted >= 200


def test_audit_reports_what_it_cannot_compute():
    """CG outside the support with no measured f_n (once a square root of a negative mass), a zero damper
    against Eq. 4 (once inf): messages say so, the values are None."""
    base = load_vehicle("reference-etrike")
    outside = override(base, {"mass.cg_y_m": -1.0, "suspension.rear.natural_frequency_hz": None,
                              "suspension.rear.damping_ratio": None})
    findings = audit(outside)
    assert _all_finite(findings)
    left = next(f for f in findings if f.topic == "sprung mass" and f.values["wheel"] == "rear_left")
    assert left.level == "inconsistent" and "not positive" in left.message
    assert left.values["natural_frequency_from_cg_hz"] is None
    undamped = audit(override(base, {"suspension.front.damping_Ns_per_m": 0.0}))
    eq4 = next(f for f in undamped if f.topic == "damping (Eq. 4)" and f.values["suspension"] == "front")
    assert eq4.level == "inconsistent" and "no damper given" in eq4.message
    assert eq4.values["ratio_eq4_to_given"] is None
    assert _all_finite(undamped)
