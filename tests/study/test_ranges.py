"""Issue 12: the ranges of the assumed values declared next to them in the vehicle file (``[ranges.SECTION]``),
used by the sensitivity and uncertainty factors; the measured sigmas of a weighing file and an identification
reaching ``trikedyn uncertainty`` (``--weighing``, ``--identification``)."""

from __future__ import annotations

import json
import math
import textwrap

import numpy as np
import pytest

from trikedyn.cli import main
from trikedyn.errors import InputError, ParameterError
from trikedyn.params import load_vehicle, save_vehicle
from trikedyn.params.schema import RelativeRange, VehicleParameters
from trikedyn.study.designs import factors as fm
from trikedyn.study.designs import uncertainty as ua

from ..conftest import SHARED, WEIGHING, strict_json
from . import warm_numba_cache

RUN = ["--manoeuvre", "dlc", "--samples", "4", "--resolution", "1.0", "--workers", "0"]


def run(capsys, *args):
    code = main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def vehicle_file(tmp_path, body: str, name: str = "mine.toml"):
    path = tmp_path / name
    path.write_text('extends = "reference-etrike"\nname = "mine"\n' + textwrap.dedent(body), encoding="utf-8")
    return path


# ------------------------------------------------------------------------------------------------------------
# the TOML form
# ------------------------------------------------------------------------------------------------------------
def test_nested_and_dotted_forms_are_the_same_and_round_trip(tmp_path, reference):
    nested = vehicle_file(tmp_path, """
        [tyre]
        mu_y = { value = 0.85, assumed = "dry asphalt" }

        [ranges.tyre]
        mu_y = [0.6, 1.0]  # damp to dry

        [ranges.wheels.front]
        radius_m = { rel = 0.05 }
    """, "nested.toml")
    dotted = vehicle_file(tmp_path, """
        [ranges]
        "tyre.mu_y" = [0.6, 1.0]
        wheels.front.radius_m = { rel = 0.05 }
    """, "dotted.toml")
    a, b = load_vehicle(nested).params.ranges, load_vehicle(dotted).params.ranges
    assert a == b and a["tyre.mu_y"] == (0.6, 1.0) and a["wheels.front.radius_m"] == RelativeRange(rel=0.05)
    saved = save_vehicle(load_vehicle(nested), tmp_path / "saved.toml")
    assert load_vehicle(saved).params.ranges == a


def test_a_vehicle_without_ranges_dumps_as_before():
    """No ``ranges`` key in the dump of a vehicle that declares none (study digests stay what they were)."""
    tadpole = load_vehicle("reference-tadpole")
    assert tadpole.params.ranges == {} and "ranges" not in tadpole.params.model_dump()


def test_the_reference_preset_declares_ranges_with_reasons(reference):
    from importlib import resources

    declared = fm.declared_ranges(reference)  # every range holds its value (else ParameterError)
    assert {"mass.cg_x_m", "tyre.mu_y", "tyre.cornering_stiffness_factor", "steering.trail_m",
            "wheels.front.x_m", "body.overall_width_m"} <= set(declared)
    assert all(low < fm.numeric_parameters(reference)[k] < high for k, (low, high) in declared.items())
    # each range is an assumed value's and carries its reason (a comment) on its line
    assumed = reference.assumed()
    assert set(declared) <= set(assumed)
    text = (resources.files("trikedyn.params") / "presets" / "reference-etrike.toml").read_text(encoding="utf-8")
    section = None
    for line in text.splitlines():
        if line.startswith("["):
            section = line
        elif section and section.startswith("[ranges") and "=" in line:
            assert "#" in line and len(line.split("#", 1)[1].strip()) > 10, line
    # the variant that extends it inherits them
    assert fm.declared_ranges(load_vehicle("reference-etrike-eq4")) == declared


# ------------------------------------------------------------------------------------------------------------
# the factors use them
# ------------------------------------------------------------------------------------------------------------
def test_a_declared_range_is_the_factors_range(tmp_path):
    pset = load_vehicle(vehicle_file(tmp_path, """
        [ranges]
        track_m = [1.0, 1.2]
        "mass.roll_yaw_product_kgm2" = [-5.0, 5.0]

        [ranges.tyre]
        mu_y = [0.6, 1.0]

        [ranges.steering]
        head_mass_kg = { rel = 0.5 }

        [ranges.wheels.rear_left]
        radius_m = [0.26, 0.30]
    """))
    factors, excluded = fm.candidate_factors(pset)
    by = {f.name: f for f in factors}
    assert (by["tyre.mu_y"].low, by["tyre.mu_y"].high, by["tyre.mu_y"].range_from) == (0.6, 1.0, "declared")
    assert (by["steering.head_mass_kg"].low, by["steering.head_mass_kg"].high) == pytest.approx((4.0, 12.0))
    assert (by["track_m"].low, by["track_m"].high) == (1.0, 1.2)  # a knob, declared under its own name
    assert (by["wheels.rear_left+rear_right.radius_m"].low, by["wheels.rear_left+rear_right.radius_m"].high) == (
        0.26, 0.30)  # a pair, declared next to one of its wheels
    # a zero value is a factor once it has a range (a relative range of it would be empty)
    assert by["mass.roll_yaw_product_kgm2"].range_from == "declared"
    assert "mass.roll_yaw_product_kgm2" not in excluded
    # undeclared ones keep the stated default fraction, and say so
    assert by["tyre.shape_x"].range_from == "fraction"
    assert by["tyre.shape_x"].high == pytest.approx(1.65 * (1 + fm.DEFAULT_FRACTION))
    # named factors (sensitivity --parameter, uncertainty -p) too; --fraction changes the others only
    (mu, shape) = fm.select_factors(pset, ["tyre.mu_y", "tyre.shape_x"], fraction=0.1)
    assert (mu.low, mu.high) == (0.6, 1.0) and shape.high == pytest.approx(1.65 * 1.1)
    # the uncertainty inputs are uniform over the same range
    inputs, _ = ua.build_inputs(pset, ["tyre.mu_y"])
    assert inputs[0].to_dict()["range_from"] == "declared" and (inputs[0].factor.low, inputs[0].factor.high) == (
        0.6, 1.0)


def test_sensitivity_json_lists_the_declared_range(capsys, tmp_path):
    warm_numba_cache()
    path = vehicle_file(tmp_path, """
        [ranges.steering]
        trail_m = [0.06, 0.08]
    """)
    code, out, err = run(capsys, "sensitivity", path, "--manoeuvre", "dlc", "--parameter",
                         "steering.trail_m,tyre.shape_x", "--samples", "2", "--resolution", "1.0", "--workers", "0",
                         "--json")
    assert code == 0, err
    data = strict_json(out)
    factors = {f["parameter"]: f for f in data["factors"]}
    assert (factors["steering.trail_m"]["low"], factors["steering.trail_m"]["high"]) == (0.06, 0.08)
    assert factors["steering.trail_m"]["range_from"] == "declared"
    assert factors["tyre.shape_x"]["range_from"] == "fraction"


BAD = [
    ("[ranges.tyre]\nmu_y = [0.9, 1.0]\n", "ranges.tyre.mu_y", "does not hold the value 0.85"),
    ("[ranges.tyre]\nmu_y = [1.0, 0.6]\n", "ranges.tyre.mu_y", "low < high"),
    ("[ranges.tyre]\nmu_yy = [0.6, 1.0]\n", "ranges.tyre.mu_yy", "did you mean 'tyre.mu_y'?"),
    ("[ranges.tyre]\nmu_y = { rel = 1.5 }\n", "ranges.tyre.mu_y", "between 0 and 1"),
    ("[ranges.tyre]\nmu_y = \"wide\"\n", "ranges.tyre.mu_y", "expected [low, high]"),
    ("[ranges.tyre]\nmu_y = [0.6, nan]\n", "ranges.tyre.mu_y", "finite"),
    ("[ranges.mass]\nroll_yaw_product_kgm2 = { rel = 0.1 }\n", "ranges.mass.roll_yaw_product_kgm2", "is empty"),
]


@pytest.mark.parametrize(("body", "key", "needle"), BAD, ids=[b[2] for b in BAD])
@pytest.mark.parametrize("command", ["sensitivity", "uncertainty"])
def test_a_bad_range_is_exit_2_and_one_line(capsys, tmp_path, body, key, needle, command):
    path = vehicle_file(tmp_path, body)
    code, out, err = run(capsys, command, path, "--manoeuvre", "dlc", "--samples", "2", "--workers", "0")
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert str(path) in lines[0] and key in lines[0] and needle in lines[0], lines[0]


def test_declared_ranges_raise_a_parameter_error(tmp_path):
    pset = load_vehicle(vehicle_file(tmp_path, "[ranges.tyre]\nmu_y = [0.9, 1.0]\n"))
    with pytest.raises(ParameterError, match=r"mine\.toml: ranges\.tyre\.mu_y"):
        fm.candidate_factors(pset)


def test_the_schema_checks_the_form():
    data = load_vehicle("reference-tadpole").params.model_dump()
    ok = VehicleParameters.model_validate({**data, "ranges": {"tyre": {"mu_y": [0.6, 1]}, "track_m": {"rel": 0.1}}})
    assert ok.ranges == {"tyre.mu_y": (0.6, 1.0), "track_m": RelativeRange(rel=0.1)}
    for bad in ({"tyre": {"mu_y": [1, 0.6]}}, {"tyre": {"mu_y": [0.6, 1, 2]}}, {"tyre": {"mu_y": [True, 1]}},
                {"tyre": {"mu_y": {"rel": 0.1, "abs": 2}}}, {"tyre": {"mu_y": {"rel": 0}}}, [1, 2]):
        with pytest.raises(ValueError):
            VehicleParameters.model_validate({**data, "ranges": bad})


# ------------------------------------------------------------------------------------------------------------
# measured sigmas: --weighing
# ------------------------------------------------------------------------------------------------------------
@pytest.fixture
def weighing_file(tmp_path):
    path = tmp_path / "weighing.toml"
    path.write_text(WEIGHING, encoding="utf-8")
    return path


def test_weighing_sigmas_are_those_of_the_reduction(weighing_file, reference):
    from trikedyn.measure.weighing import load_weighing, reduce_weighing

    expected = reduce_weighing(load_weighing(weighing_file))
    found = {m.path: m for m in ua.weighing_stds(weighing_file)}
    assert set(found) == {"mass.cg_x_m", "mass.cg_y_m", "mass.cg_z_m"}
    assert found["mass.cg_x_m"].std == expected.level.cg_x_std_m
    assert found["mass.cg_y_m"].std == expected.level.cg_y_std_m
    assert found["mass.cg_z_m"].std == expected.height.cg_z_std_m
    assert found["mass.cg_z_m"].measured == expected.height.cg_z_m
    # by hand: 0.5 kg per reading on 583 kg puts x within about 1.4 mm
    assert 0.001 < found["mass.cg_x_m"].std < 0.002 and 0.01 < found["mass.cg_z_m"].std < 0.03
    assert "level weighing" in found["mass.cg_x_m"].source and str(weighing_file) in found["mass.cg_x_m"].source
    # a level weighing alone gives x and y, no z
    level_only = weighing_file.with_name("level.toml")
    level_only.write_text(WEIGHING.split("[[tilted]]")[0], encoding="utf-8")
    assert {m.path for m in ua.weighing_stds(level_only)} == {"mass.cg_x_m", "mass.cg_y_m"}


def test_a_weighing_without_uncertainty_is_refused(tmp_path):
    path = tmp_path / "exact.toml"
    path.write_text(WEIGHING.replace("reading_std_kg = 0.5", "reading_std_kg = 0.0").split("[[tilted]]")[0],
                    encoding="utf-8")
    with pytest.raises(InputError, match="without an uncertainty"):
        ua.weighing_stds(path)


def test_uncertainty_with_weighing_sets_the_cg_sigmas(capsys, weighing_file):
    from trikedyn.measure.weighing import load_weighing, reduce_weighing

    warm_numba_cache()
    expected = reduce_weighing(load_weighing(weighing_file))
    code, out, err = run(capsys, "uncertainty", "reference-etrike", *RUN, "--parameter", "steering.trail_m",
                         "--weighing", weighing_file, "--std", "mass.cg_y_m=0.002", "--json")
    assert code == 0, err
    data = strict_json(out)
    normal = {i["parameter"]: i for i in data["inputs"] if i["distribution"] == "normal"}
    assert normal["mass.cg_x_m"]["std"] == pytest.approx(expected.level.cg_x_std_m, rel=1e-12)
    assert normal["mass.cg_z_m"]["std"] == pytest.approx(expected.height.cg_z_std_m, rel=1e-12)
    assert normal["mass.cg_x_m"]["mean"] == 0.8321  # about the vehicle's value
    assert normal["mass.cg_z_m"]["truncated"] == pytest.approx(
        [0.3804 - 3 * expected.height.cg_z_std_m, 0.3804 + 3 * expected.height.cg_z_std_m])
    assert "level weighing" in normal["mass.cg_x_m"]["source"] and "tilted" in normal["mass.cg_z_m"]["source"]
    assert normal["mass.cg_y_m"]["std"] == 0.002 and normal["mass.cg_y_m"]["source"] == "--std"  # --std wins
    used = {m["parameter"]: m["used"] for m in data["measured"]}
    assert used == {"mass.cg_x_m": True, "mass.cg_y_m": False, "mass.cg_z_m": True}
    # the synthetic weighing's CG is 0.68 m high, the vehicle's 0.38 m: said, not hidden
    assert any(n.startswith("mass.cg_z_m") for n in data["notes"])
    x = np.array([[s["mass.cg_x_m"], s["mass.cg_z_m"]] for s in data["samples"]])
    assert np.all(np.abs(x[:, 0] - 0.8321) <= 3 * expected.level.cg_x_std_m + 1e-12)
    assert np.all(np.abs(x[:, 1] - 0.3804) <= 3 * expected.height.cg_z_std_m + 1e-12)
    # the text lists where each sigma came from
    code, out, err = run(capsys, "uncertainty", "reference-etrike", *RUN, "--parameter", "steering.trail_m",
                         "--weighing", weighing_file)
    assert code == 0, err
    assert f"[{weighing_file}: level weighing]" in out and f"[{weighing_file}: tilted weighings]" in out
    assert "over the range declared in the vehicle file" in out


# ------------------------------------------------------------------------------------------------------------
# measured sigmas: --identification
# ------------------------------------------------------------------------------------------------------------
def synthetic_identification(tmp_path, tyre_stiffness=None):
    """A free decay at 2.9 Hz, xi 0.2, with noise, identified as ``trikedyn identify --json`` would."""
    from trikedyn.measure.suspension import identify_suspension

    fs, fn, xi = 100.0, 2.9, 0.2
    t = np.arange(0.0, 20.0, 1.0 / fs)
    wn = 2 * np.pi * fn
    decay = 8.0 * np.exp(-xi * wn * (t - 5.0)) * np.cos(wn * np.sqrt(1 - xi**2) * (t - 5.0))
    a = np.where(t >= 5.0, decay, 0.0) + np.random.default_rng(1).normal(0.0, 0.05, t.size)
    result = identify_suspension(t, a, 239.2, tyre_stiffness_N_per_m=tyre_stiffness)
    path = tmp_path / ("id-tyre.json" if tyre_stiffness else "id.json")
    path.write_text(json.dumps(result.to_dict() | {"file": "synthetic", "axis": "z"}), encoding="utf-8")
    return path, result


def test_identification_sigmas_follow_from_those_of_fn_and_xi(tmp_path):
    path, r = synthetic_identification(tmp_path)
    k, c = ua.identification_stds(path, "front")
    assert k.path == "suspension.front.stiffness_N_per_m" and c.path == "suspension.front.damping_Ns_per_m"
    assert k.measured == pytest.approx(r.stiffness_N_per_m) and c.measured == pytest.approx(r.damping_Ns_per_m)
    f, sf, xi, sxi = r.natural_frequency_hz, r.natural_frequency_std_hz, r.damping_ratio, r.damping_ratio_std
    assert k.std == pytest.approx(r.stiffness_N_per_m * 2 * sf / f, rel=1e-4)  # K = 4 pi^2 f^2 M
    assert c.std == pytest.approx(r.damping_Ns_per_m * math.hypot(sf / f, sxi / xi), rel=1e-4)  # C = 4 pi xi f M
    # with the tyre in series the propagation goes through the quarter car; a folder holding the file works too
    folder = tmp_path / "folder"
    folder.mkdir()
    tyre_path, rt = synthetic_identification(folder, tyre_stiffness=200000.0)
    kt, ct = ua.identification_stds(tyre_path.parent, "rear")
    assert kt.measured == pytest.approx(rt.stiffness_N_per_m) and kt.std > k.std and ct.std > 0


def test_uncertainty_with_identification(capsys, tmp_path):
    warm_numba_cache()
    path, r = synthetic_identification(tmp_path)
    code, out, err = run(capsys, "uncertainty", "reference-etrike", *RUN, "--parameter", "steering.trail_m",
                         "--identification", f"front={path}", "--json")
    assert code == 0, err
    data = strict_json(out)
    normal = {i["parameter"]: i for i in data["inputs"] if i["distribution"] == "normal"}
    assert set(normal) == {"suspension.front.stiffness_N_per_m", "suspension.front.damping_Ns_per_m"}
    k = normal["suspension.front.stiffness_N_per_m"]
    assert k["std"] == pytest.approx(r.stiffness_N_per_m * 2 * r.natural_frequency_std_hz / r.natural_frequency_hz,
                                     rel=1e-4)
    assert k["mean"] == 80289.0 and str(path) in k["source"]


@pytest.mark.parametrize(("item", "needle"), [
    ("{path}", "name the suspension"),
    ("frnt={path}", "did you mean 'front'?"),
    ("front={missing}", "no such identification file"),
    ("front={bad}", "natural_frequency_hz"),
])
def test_identification_mistakes_are_one_line(capsys, tmp_path, item, needle):
    path, _ = synthetic_identification(tmp_path)
    bad = tmp_path / "bad.json"
    bad.write_text('{"natural_frequency_hz": "fast"}', encoding="utf-8")
    arg = item.format(path=path, missing=tmp_path / "none.json", bad=bad)
    code, out, err = run(capsys, "uncertainty", "reference-etrike", *RUN, "--identification", arg)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and needle in err, err


def test_identification_of_the_real_recordings(capsys, tmp_path):
    """The real WitMotion recordings, when present: an identification of one of them reaches the inputs."""
    folder = SHARED / "data" / "witmotion"
    logs = sorted(p for p in folder.glob("*") if p.suffix.lower() in (".txt", ".csv")) if folder.is_dir() else []
    if not logs:
        pytest.skip(f"no real recordings in {folder}")
    reasons = []
    for log in logs:
        out_json = tmp_path / f"{log.stem}.json"
        code, out, err = run(capsys, "identify", log, "--sprung-mass", "239.2", "--json")
        if code == 0:
            out_json.write_text(out, encoding="utf-8")
            found = {m.path: m for m in ua.identification_stds(out_json, "front")}
            assert all(m.std > 0 for m in found.values())
            return
        reasons.append(f"{log.name}: {err.strip().splitlines()[-1] if err.strip() else code}")
    pytest.skip("no real recording is a speed-bump decay that `trikedyn identify` can reduce ("
                + "; ".join(reasons) + ")")

