"""Delta against tadpole: mirror_layout, the layout comparison and ``trikedyn compare-layouts``."""

import json
import math

import pytest

from tests.conftest import strict_json
from trikedyn.analysis.layouts import compare_layouts, static_tip_over_g
from trikedyn.analysis.tilt import tilt_table
from trikedyn.cli import main
from trikedyn.params import load_vehicle, override
from trikedyn.params.layouts import WHEEL_NAMES, mirror_layout
from trikedyn.params.ops import mass_properties, static_wheel_loads, unsprung_mass
from trikedyn.units import STANDARD_GRAVITY


def _frequencies(params):
    """Static natural frequency per wheel [Hz] from its spring and its CG-implied sprung mass."""
    loads = static_wheel_loads(params)
    out = {}
    for w in params.wheels:
        m_s = loads[w.name] / STANDARD_GRAVITY - unsprung_mass(params, w.name)
        out[w.name] = math.sqrt(params.suspension[w.suspension].stiffness_N_per_m / m_s) / (2 * math.pi)
    return out


@pytest.mark.parametrize("name", ["reference-etrike", "reference-tadpole"])
def test_mirror_keeps_mass_cg_wheelbase_and_track(name):
    p = load_vehicle(name).params
    m = mirror_layout(p)
    assert {p.layout, m.layout} == {"delta", "tadpole"}
    assert [w.name for w in m.wheels] == list(WHEEL_NAMES[m.layout])
    assert m.mass == p.mass and m.payload == p.payload
    a, b = mass_properties(p), mass_properties(m)
    assert b.mass_kg == a.mass_kg and b.cg_m[2] == a.cg_m[2]
    assert b.cg_m[0] / m.wheelbase_m == a.cg_m[0] / p.wheelbase_m  # the same fraction from the rear axle
    assert (m.wheelbase_m, m.track_m) == (p.wheelbase_m, p.track_m)
    # the steered parts weigh as before; each end keeps its static natural frequency (mean over a pair)
    heads = lambda v: v.steering.head_mass_kg * sum(w.steered for w in v.wheels)  # noqa: E731
    assert heads(m) == pytest.approx(heads(p))
    fp, fm = _frequencies(p), _frequencies(m)
    for end in (True, False):
        before = [f for n, f in fp.items() if p.wheel(n).steered == end]
        after = [f for n, f in fm.items() if m.wheel(n).steered == end]
        assert sum(after) / len(after) == pytest.approx(sum(before) / len(before), rel=0.03)


def test_mirror_of_the_delta_is_the_tadpole_preset_and_back():
    delta = load_vehicle("reference-etrike").params
    preset = load_vehicle("reference-tadpole").params
    mirror = mirror_layout(delta)
    assert mirror.wheels == preset.wheels and mirror.steering == preset.steering and mirror.mass == preset.mass
    for name, s in preset.suspension.items():
        got = mirror.suspension[name]
        for key in ("stiffness_N_per_m", "damping_Ns_per_m", "bump_stop_stiffness_N_per_m"):
            assert getattr(got, key) == pytest.approx(getattr(s, key), rel=1e-3), (name, key)
        assert got.model_copy(update={k: getattr(s, k) for k in ("stiffness_N_per_m", "damping_Ns_per_m",
                                                                 "bump_stop_stiffness_N_per_m")}) == s
    back = mirror_layout(mirror)
    assert back.wheels == delta.wheels and back.steering == delta.steering
    for name, s in delta.suspension.items():
        assert back.suspension[name].stiffness_N_per_m == pytest.approx(s.stiffness_N_per_m, rel=1e-12)
        assert back.suspension[name].damping_Ns_per_m == pytest.approx(s.damping_Ns_per_m, rel=1e-12)


def test_static_tip_over_of_the_mirror_is_the_closed_form():
    """Centred CG at d from the single wheel's axle: delta d = L - x, tadpole d = x; a_y / g = d T / (2 h L)."""
    delta = override(load_vehicle("reference-etrike"), {"mass.cg_y_m": 0.0}).params
    tadpole = mirror_layout(delta)
    h, L, T, x = delta.mass.cg_z_m, delta.wheelbase_m, delta.track_m, delta.mass.cg_x_m
    assert static_tip_over_g(delta)[0] == pytest.approx((L - x) * T / (2 * h * L), rel=1e-12)
    assert static_tip_over_g(tadpole)[0] == pytest.approx(x * T / (2 * h * L), rel=1e-12)


def test_tilt_table_of_a_near_rigid_tadpole_meets_the_closed_form():
    """The compliant model on the tilting table, springs and tyres near rigid: within 3 % of
    atan(d T / (2 h L)) (the issue's acceptance for the quasi-static tip-over of a tadpole)."""
    stiff = {"mass.cg_y_m": 0.0, "suspension.front.stiffness_N_per_m": 1e7, "suspension.rear.stiffness_N_per_m": 1e7,
             "tyre.vertical_stiffness_N_per_m": 1e7}
    pset = override(load_vehicle("reference-tadpole"), stiff)
    p = pset.params
    closed = math.degrees(math.atan(p.mass.cg_x_m * p.track_m / (2 * p.mass.cg_z_m * p.wheelbase_m)))
    result = tilt_table(pset)
    assert result.rigid_tilt_angle_deg == pytest.approx(closed, rel=1e-9)
    assert result.tilt_angle_deg == pytest.approx(closed, rel=0.03)


def test_compare_layouts_without_runs():
    result = compare_layouts(load_vehicle("reference-etrike"), manoeuvres=(), tilt=False)
    assert [r.layout for r in result.rows] == ["delta", "tadpole"]
    assert result.rows[0].static_tip_over_g > result.rows[1].static_tip_over_g  # CG nearer the rear pair
    assert result.rows[0].tilt_angle_deg is None and result.rows[0].threshold_speed_kmh == {}
    assert "static tip-over" in result.table() and result.wheelbase_m == 1.95


def test_compare_layouts_command_json(capsys, tmp_path):
    out = tmp_path / "cmp"
    code = main(["compare-layouts", "reference-etrike", "--manoeuvre", "slc", "--resolution", "5", "--low", "40",
                 "--json", "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    data = strict_json(captured.out)
    layouts = data["layouts"]
    assert [r["layout"] for r in layouts] == ["delta", "tadpole"]
    assert layouts[0]["name"] == "reference-etrike"
    for row in layouts:
        assert set(row) >= {"layout", "name", "static_tip_over_g", "tilt_angle_deg", "threshold_speed_kmh"}
        assert 0.3 < row["static_tip_over_g"] < 1.0 and 10.0 < row["tilt_angle_deg"] < 45.0
        assert list(row["threshold_speed_kmh"]) == ["slc"]
        assert row["threshold_speed_kmh"]["slc"] is None or 40.0 <= row["threshold_speed_kmh"]["slc"] <= 90.0
    assert {p.name for p in out.iterdir()} == {"comparison.json", "tadpole-mirror.toml", "layouts.png"}
    assert json.loads((out / "comparison.json").read_text())["layouts"] == layouts
    assert load_vehicle(out / "tadpole-mirror.toml").params.layout == "tadpole"
    # a second run does not overwrite without --force; an unknown manoeuvre fails before any run
    assert main(["compare-layouts", "reference-etrike", "--manoeuvre", "slc", "--out", str(out)]) == 2
    assert "--force" in capsys.readouterr().err
    assert main(["compare-layouts", "reference-etrike", "--manoeuvre", "nope", "--json"]) == 2
    assert strict_json(capsys.readouterr().out)["where"] == "--manoeuvre"


def test_compare_layouts_command_text(capsys):
    code = main(["compare-layouts", "reference-tadpole", "--manoeuvre", "slc", "--no-tilt", "--resolution", "10",
                 "--low", "50", "--high", "80"])
    out = capsys.readouterr().out
    assert code == 0
    assert "tadpole (reference-tadpole)" in out and "delta (reference-tadpole (delta mirror))" in out
    assert "threshold slc [km/h]" in out
