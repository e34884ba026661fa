"""Delta against tadpole: mirror_layout, the layout comparison and ``trikedyn compare-layouts``."""

import json
import math

import numpy as np
import pytest

from tests.conftest import strict_json
from trikedyn.analysis.layouts import compare_layouts, static_tip_over_g
from trikedyn.analysis.tilt import tilt_table
from trikedyn.cli import main
from trikedyn.errors import InputError
from trikedyn.params import load_vehicle, override, with_freight
from trikedyn.params.layouts import DEFAULT_KEEP, WHEEL_NAMES, mirror_layout
from trikedyn.params.ops import mass_properties, static_wheel_loads, unsprung_mass
from trikedyn.study.designs.factors import declared_ranges
from trikedyn.units import STANDARD_GRAVITY


def _frequencies(params):
    """Static natural frequency per wheel [Hz] from its spring and its CG-implied sprung mass."""
    loads = static_wheel_loads(params)
    out = {}
    for w in params.wheels:
        m_s = loads[w.name] / STANDARD_GRAVITY - unsprung_mass(params, w.name)
        out[w.name] = math.sqrt(params.suspension[w.suspension].stiffness_N_per_m / m_s) / (2 * math.pi)
    return out


@pytest.mark.parametrize("keep", ["cg", "pair-distance"])
@pytest.mark.parametrize("name", ["reference-etrike", "reference-tadpole"])
def test_mirror_keeps_mass_cg_wheelbase_and_track(name, keep):
    p = load_vehicle(name).params
    m = mirror_layout(p, keep)
    assert {p.layout, m.layout} == {"delta", "tadpole"}
    assert [w.name for w in m.wheels] == list(WHEEL_NAMES[m.layout])
    a, b = mass_properties(p), mass_properties(m)
    assert b.mass_kg == a.mass_kg and b.cg_m[2] == a.cg_m[2] and b.cg_m[1] == a.cg_m[1]
    if keep == "cg":
        assert m.mass == p.mass and m.payload == p.payload and m.components == p.components
        assert b.cg_m[0] / m.wheelbase_m == a.cg_m[0] / p.wheelbase_m  # the same fraction from the rear axle
    else:  # the body mirrored end for end: the same distance from the pair (x -> L - x)
        assert b.cg_m[0] == pytest.approx(p.wheelbase_m - a.cg_m[0], abs=1e-12)
        for before, after in zip(p.components, m.components, strict=True):
            assert after.x_m == pytest.approx(p.wheelbase_m - before.x_m) and after.z_m == before.z_m
        assert m.freight.x_m == pytest.approx(p.wheelbase_m - p.freight.x_m)
        assert m.sensor.x_m == pytest.approx(p.wheelbase_m - p.sensor.x_m)
        # the principal inertias are kept, the inertia tensor is mirrored (Ixy, Ixz change sign)
        mirror = np.diag([-1.0, 1.0, 1.0])
        assert np.allclose(b.inertia_kgm2, mirror @ a.inertia_kgm2 @ mirror)
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
    mirror = mirror_layout(delta, "cg")  # the preset is the delta with the wheels moved, the CG where it was
    assert mirror.wheels == preset.wheels and mirror.steering == preset.steering and mirror.mass == preset.mass
    for name, s in preset.suspension.items():
        got = mirror.suspension[name]
        for key in ("stiffness_N_per_m", "damping_Ns_per_m", "bump_stop_stiffness_N_per_m"):
            assert getattr(got, key) == pytest.approx(getattr(s, key), rel=1e-3), (name, key)
        assert got.model_copy(update={k: getattr(s, k) for k in ("stiffness_N_per_m", "damping_Ns_per_m",
                                                                 "bump_stop_stiffness_N_per_m")}) == s
    back = mirror_layout(mirror, "cg")
    assert back.wheels == delta.wheels and back.steering == delta.steering
    for name, s in delta.suspension.items():
        assert back.suspension[name].stiffness_N_per_m == pytest.approx(s.stiffness_N_per_m, rel=1e-12)
        assert back.suspension[name].damping_Ns_per_m == pytest.approx(s.damping_Ns_per_m, rel=1e-12)


def test_static_tip_over_of_the_mirror_is_the_closed_form():
    """Centred CG at d from the single wheel's axle: delta d = L - x, tadpole d = x; a_y / g = d T / (2 h L)."""
    delta = override(load_vehicle("reference-etrike"), {"mass.cg_y_m": 0.0}).params
    tadpole = mirror_layout(delta, "cg")
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
    result = compare_layouts(load_vehicle("reference-etrike"), manoeuvres=(), tilt=False, keep="cg")
    assert [r.layout for r in result.rows] == ["delta", "tadpole"] and result.keep == "cg"
    assert result.rows[0].static_tip_over_g > result.rows[1].static_tip_over_g  # CG nearer the rear pair
    assert result.rows[0].tilt_angle_deg is None and result.rows[0].threshold_speed_kmh == {}
    assert "static tip-over" in result.table() and result.wheelbase_m == 1.95


# ------------------------------------------------------------------------------------------------------------
# what stays: the CG where it is, or at the same distance from the two-wheel axle
# ------------------------------------------------------------------------------------------------------------
def _pair_of(pset, x_fraction: float, y_m: float = 0.0):
    """The vehicle with its CG at ``x_fraction`` of the wheelbase from its two-wheel axle."""
    length = pset.params.wheelbase_m
    x = x_fraction * length if pset.params.layout == "delta" else (1.0 - x_fraction) * length
    return override(pset, {"mass.cg_x_m": x, "mass.cg_y_m": y_m}).params


@pytest.mark.parametrize(("fraction", "y_m"), [(0.427, 0.016), (0.30, 0.0), (0.55, -0.03)])
def test_the_same_distance_from_the_pair_gives_the_same_rigid_tip_over(fraction, y_m):
    """The issue's acceptance: delta and tadpole of the same mass, wheelbase and track, the CG at the same
    distance from the two-wheel axle, have the same rigid tip-over (to 0.001 g), and it is a T / (2 h L)."""
    delta = _pair_of(load_vehicle("reference-etrike"), fraction, y_m)
    tadpole = _pair_of(load_vehicle("reference-tadpole"), fraction, y_m)  # built on its own, not mirrored
    mirrored = mirror_layout(delta, "pair-distance")
    got = {v.layout + tag: static_tip_over_g(v)[0] for v, tag in ((delta, ""), (tadpole, ""), (mirrored, " mirror"))}
    assert (delta.wheelbase_m, delta.track_m) == (tadpole.wheelbase_m, tadpole.track_m)
    assert mass_properties(delta).mass_kg == mass_properties(tadpole).mass_kg
    assert got["tadpole"] == pytest.approx(got["delta"], abs=0.001), got
    assert got["tadpole mirror"] == pytest.approx(got["delta"], abs=1e-9), got
    if y_m == 0.0:
        h, L, T = delta.mass.cg_z_m, delta.wheelbase_m, delta.track_m
        a = (1.0 - fraction) * L  # the CG's distance from the single wheel's axle
        assert got["delta"] == pytest.approx(a * T / (2 * h * L), rel=1e-12)
    # the CG kept where it is instead: the layout with the CG nearer its single wheel tips earlier
    kept = static_tip_over_g(mirror_layout(delta, "cg"))[0]
    assert (kept < got["delta"]) == (fraction < 0.5)


def test_compare_layouts_keep_both_with_freight():
    """Payload goes with the body: the pair-distance mirror keeps the rigid tip-over with freight aboard too."""
    laden = with_freight(load_vehicle("reference-etrike"), 100.0)
    result = compare_layouts(laden, manoeuvres=(), tilt=False, keep="both")
    given, pair, cg = result.rows
    assert [r.keep for r in result.rows] == [None, "pair-distance", "cg"] and set(result.mirrors) == {"pair-distance", "cg"}
    assert pair.static_tip_over_g == pytest.approx(given.static_tip_over_g, abs=1e-9)
    assert pair.cg_from_single_m == pytest.approx(given.cg_from_single_m)
    assert pair.single_wheel_load_fraction == pytest.approx(given.single_wheel_load_fraction)
    assert cg.cg_x_m == pytest.approx(given.cg_x_m) and cg.static_tip_over_g < given.static_tip_over_g
    assert cg.cg_from_single_m == pytest.approx(result.wheelbase_m - given.cg_from_single_m)
    text = result.table()
    assert "mirror (default): the CG at the same distance from the two-wheel axle" in text
    assert "mirror (--keep cg): the CG where it is on the vehicle" in text
    assert "tadpole mirror (pair distance kept)" in text and "tadpole mirror (CG kept)" in text
    data = result.to_dict()
    assert data["keep"] == "both" and set(data["keep_means"]) == {"pair-distance", "cg"}
    assert [r["label"] for r in data["layouts"]] == ["delta", "tadpole mirror (pair distance kept)",
                                                     "tadpole mirror (CG kept)"]


def test_the_default_keeps_the_distance_from_the_pair():
    assert DEFAULT_KEEP == "pair-distance"
    result = compare_layouts(load_vehicle("reference-etrike"), manoeuvres=(), tilt=False)
    assert result.keep == "pair-distance" and [r.keep for r in result.rows] == [None, "pair-distance"]
    assert result.rows[1].static_tip_over_g == pytest.approx(result.rows[0].static_tip_over_g, abs=1e-9)
    with pytest.raises(InputError, match="pair-distance"):
        compare_layouts(load_vehicle("reference-etrike"), manoeuvres=(), keep="body")
    with pytest.raises(InputError):
        mirror_layout(load_vehicle("reference-etrike"), "both")  # one mirror at a time


@pytest.mark.parametrize("keep", ["cg", "pair-distance"])
def test_the_mirrors_declared_ranges_name_its_own_values(keep):
    """A range follows its value: wheel ranges to the wheels that copy it, the front x to the wheelbase, a
    mirrored x mirrored; the mirror's ranges all hold their values (the uncertainty commands accept them)."""
    from trikedyn.params.io import ParameterSet

    delta = load_vehicle("reference-etrike")
    mirror = mirror_layout(delta, keep)
    ranges = mirror.ranges
    assert "wheels.front.radius_m" not in ranges and "wheels.front.x_m" not in ranges
    for name in ("front_left", "front_right"):
        assert ranges[f"wheels.{name}.radius_m"] == delta.params.ranges["wheels.front.radius_m"]
    assert ranges["wheels.rear.radius_m"] == delta.params.ranges["wheels.rear_left.radius_m"]
    assert ranges["wheelbase_m"] == delta.params.ranges["wheels.front.x_m"]
    low, high = delta.params.ranges["mass.cg_x_m"]
    L = delta.params.wheelbase_m
    assert ranges["mass.cg_x_m"] == (pytest.approx((low, high)) if keep == "cg"
                                     else pytest.approx((L - high, L - low)))
    declared = declared_ranges(ParameterSet(mirror, {}, "mirror"))
    assert set(declared) == set(ranges)


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
    assert data["keep"] == "pair-distance" and [r["keep"] for r in layouts] == [None, "pair-distance"]
    assert layouts[1]["static_tip_over_g"] == pytest.approx(layouts[0]["static_tip_over_g"], abs=1e-9)
    assert {p.name for p in out.iterdir()} == {"comparison.json", "tadpole-mirror-pair-distance.toml", "layouts.png"}
    assert json.loads((out / "comparison.json").read_text())["layouts"] == layouts
    assert load_vehicle(out / "tadpole-mirror-pair-distance.toml").params.layout == "tadpole"
    # a second run does not overwrite without --force; an unknown manoeuvre fails before any run
    assert main(["compare-layouts", "reference-etrike", "--manoeuvre", "slc", "--out", str(out)]) == 2
    assert "--force" in capsys.readouterr().err
    assert main(["compare-layouts", "reference-etrike", "--manoeuvre", "nope", "--json"]) == 2
    assert strict_json(capsys.readouterr().out)["where"] == "--manoeuvre"


def test_compare_layouts_command_text(capsys):
    code = main(["compare-layouts", "reference-tadpole", "--manoeuvre", "slc", "--no-tilt", "--resolution", "10",
                 "--low", "50", "--high", "80", "--keep", "both"])
    out = capsys.readouterr().out
    assert code == 0
    assert "tadpole (reference-tadpole)" in out and "delta mirror (pair distance kept)" in out
    assert "delta mirror (CG kept)" in out and "mirror (default): the CG at the same distance" in out
    assert "threshold slc [km/h]" in out and "CG from the single wheel's axle, a [m]" in out


def test_compare_layouts_command_keep_is_checked(capsys):
    code = main(["compare-layouts", "reference-etrike", "--keep", "pair", "--json"])
    assert code == 2 and strict_json(capsys.readouterr().out)["where"] == "--keep"
    code = main(["compare-layouts", "--help"])
    text = " ".join(capsys.readouterr().out.split()).replace("- ", "-")  # the help wraps at hyphens
    assert code == 0 and "pair-distance (the default)" in text
