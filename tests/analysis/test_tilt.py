"""Tilt-table test: the closed form on a near-rigid vehicle, compliance, sides, requirement, JSON, CLI."""

import json
import math

import pytest

from trikedyn.analysis.tilt import TiltResult, tilt_table
from trikedyn.cli import main
from trikedyn.errors import InputError
from trikedyn.model.vehicle import build_model
from trikedyn.params import load_vehicle, override, scale_suspension


@pytest.fixture(scope="module")
def reference_tilt():
    return tilt_table(load_vehicle("reference-etrike"))


def near_rigid(cg_y_m=0.0):
    """reference-etrike with springs and tyres at the schema's limit, 1e7 N/m (springs 125x and 218x,
    tyres 50x), CG on the centre line by default."""
    return override(
        load_vehicle("reference-etrike"),
        {
            "mass.cg_y_m": cg_y_m,
            "suspension.front.stiffness_N_per_m": 1e7,
            "suspension.rear.stiffness_N_per_m": 1e7,
            "tyre.vertical_stiffness_N_per_m": 1e7,
        },
    )


def test_near_rigid_vehicle_tilts_at_the_closed_form():
    """tan(theta) = a T / (2 h L): a the CG's distance behind the front contact, T the rear track,
    h the CG height, L the wheelbase (all from the parameters, no payload)."""
    pset = near_rigid()
    p = pset.params
    front = next(w for w in p.wheels if w.steered)
    rear = [w for w in p.wheels if not w.steered]
    wheelbase = front.x_m - rear[0].x_m
    track = abs(rear[0].y_m - rear[1].y_m)
    a = front.x_m - p.mass.cg_x_m
    closed = math.degrees(math.atan(a * track / (2 * p.mass.cg_z_m * wheelbase)))
    result = tilt_table(pset)
    for side, lifting in (("left", "rear_right"), ("right", "rear_left")):
        s = result.sides[side]
        assert s.tilt_angle_deg == pytest.approx(closed, abs=0.5)
        assert s.tilt_angle_deg < closed  # what compliance is left can only lower it
        assert s.rigid_tilt_angle_deg == pytest.approx(closed, abs=1e-9)
        assert s.first_lifting_wheel == lifting
        assert s.body_roll_deg < 0.2  # it hardly rolls
    # a symmetric vehicle tilts alike both ways
    assert result.sides["left"].tilt_angle_deg == pytest.approx(result.sides["right"].tilt_angle_deg, abs=0.02)


def test_compliance_lowers_the_tilt_angle(reference_tilt):
    for s in reference_tilt.sides.values():
        assert s.tilt_angle_deg < s.rigid_tilt_angle_deg - 1.0  # the body rolls and the CG moves downhill
        assert s.body_roll_deg > 1.0 and s.cg_shift_m > 0.01
        assert s.wheel_loads_N[s.first_lifting_wheel][-1] == pytest.approx(0.0, abs=1e-6)
        assert min(min(v[:-1]) for v in s.wheel_loads_N.values()) > 0.0
        assert s.angles_deg[0] == 0.0 and s.angles_deg[-1] == s.tilt_angle_deg


def test_softer_springs_tilt_less():
    base = load_vehicle("reference-etrike")
    angles = [tilt_table(scale_suspension(base, stiffness=k), side="left").tilt_angle_deg for k in (2.0, 1.0, 0.5)]
    assert angles[0] > angles[1] + 0.2 and angles[1] > angles[2] + 0.2


def test_the_cg_offset_decides_the_side(reference_tilt):
    """The CG 16 mm left of centre: tipping to the left (right wheel lifting) comes first."""
    left, right = reference_tilt.sides["left"], reference_tilt.sides["right"]
    assert left.tilt_angle_deg < right.tilt_angle_deg - 1.0
    assert (left.first_lifting_wheel, right.first_lifting_wheel) == ("rear_right", "rear_left")
    assert (reference_tilt.side, reference_tilt.first_lifting_wheel) == ("left", "rear_right")
    assert reference_tilt.tilt_angle_deg == left.tilt_angle_deg
    assert reference_tilt.rigid_tilt_angle_deg == left.rigid_tilt_angle_deg < right.rigid_tilt_angle_deg
    # the mirrored vehicle (CG 16 mm to the right) is its mirror image
    mirrored = tilt_table(override(load_vehicle("reference-etrike"), {"mass.cg_y_m": -0.016}), side="right")
    assert mirrored.side == "right" and mirrored.first_lifting_wheel == "rear_left"
    assert mirrored.tilt_angle_deg == pytest.approx(left.tilt_angle_deg, abs=0.01)


def test_requirement_and_json():
    model = build_model(load_vehicle("reference-etrike"))  # a VehicleModel is accepted too
    low = tilt_table(model, side="left", require_deg=30.0)
    high = tilt_table(model, side="left", require_deg=low.tilt_angle_deg + 0.5)
    assert low.passes is True and high.passes is False
    assert tilt_table(model, side="left").passes is None
    data = json.loads(json.dumps(low.to_dict(), allow_nan=False))
    assert data["passes"] is True and data["require_deg"] == 30.0 and list(data["sides"]) == ["left"]
    assert data["tilt_angle_deg"] == pytest.approx(low.tilt_angle_deg)
    broken = TiltResult(float("nan"), "left", "rear_right", float("inf"))
    assert json.loads(json.dumps(broken.to_dict(), allow_nan=False))["tilt_angle_deg"] is None
    with pytest.raises(InputError, match="side"):
        tilt_table(model, side="up")
    with pytest.raises(InputError, match="require_deg"):
        tilt_table(model, require_deg=95.0)
    fig = low.plot()
    assert len(fig.axes) == 1 and fig.axes[0].get_xlabel() == "table angle [deg]"


def test_tilt_command_json(capsys):
    code = main(["tilt", "reference-etrike", "--json", "--require-deg", "35"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0
    for key in ("tilt_angle_deg", "side", "first_lifting_wheel", "rigid_tilt_angle_deg", "passes"):
        assert key in data
    assert data["side"] == "left" and data["passes"] is True and data["payload_kg"] == 0.0


def test_tilt_command_text_plot_and_mistakes(capsys, tmp_path):
    png = tmp_path / "tilt.png"
    assert main(["tilt", "reference-etrike", "--side", "right", "--payload", "50", "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("tilt angle ") and "(right; rear_left lifts first); rigid " in out
    assert png.stat().st_size > 0
    assert main(["tilt", "reference-etrike", "--plot", str(png)]) == 2
    assert "exists; not overwriting it (pass --force" in capsys.readouterr().err
    assert main(["tilt", "reference-etrike", "--side", "up"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("trikedyn: error: --side: ") and err.count("\n") == 1
