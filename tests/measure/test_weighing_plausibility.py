"""Weighings that no vehicle gives: refused through the command line with one line naming the file and the
entry (exit 2, no traceback), a reading off the others warned about; valid weighings pass silently."""

import numpy as np
import pytest
from tests.conftest import WEIGHING, strict_json

from trikedyn.cli import main
from trikedyn.errors import InputError
from trikedyn.measure.cg import tilted_wheel_loads, wheel_loads_from_cg
from trikedyn.measure.weighing import MAX_CG_HEIGHT_M, MAX_MASS_KG, reduce_weighing
from trikedyn.plausibility import PlausibilityWarning
from trikedyn.units import STANDARD_GRAVITY as G

TILTED = '[[tilted]]\nraised = "front"\nheight_m = {h}\nraised_axle_kg = {kg}\n'


def weigh(capsys, tmp_path, text, *extra):
    file = tmp_path / "weighing.toml"
    file.write_text(text, encoding="utf-8")
    code = main(["cg", "weigh", str(file), *extra])
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err
    return code, captured.out, captured.err, str(file)


def refused(capsys, tmp_path, text, where, *needles):
    """Exit 2, one line ``trikedyn: error: FILE: WHERE: ...`` holding every needle; the same under --json."""
    code, out, err, file = weigh(capsys, tmp_path, text)
    assert code == 2, err
    assert err.count("\n") == 1 and err.startswith(f"trikedyn: error: {file}: {where}: "), err
    for needle in needles:
        assert needle in err, err
    code, out, err, _ = weigh(capsys, tmp_path, text, "--json")
    assert code == 2 and err.count("\n") == 1 and strict_json(out)["error"]
    return err


def test_the_valid_weighing_passes_silently(capsys, tmp_path):
    code, out, err, _ = weigh(capsys, tmp_path, WEIGHING)
    assert code == 0 and err == ""
    assert "mass 583.00" in out and "cg z 682.0" in out


def test_raised_axle_readings_that_rise_are_refused(capsys, tmp_path):
    """The issue's case: the front reading rises from 249.1 kg (level) to 262 kg raised: CG below the ground."""
    err = refused(capsys, tmp_path, WEIGHING.replace("236.4", "262.0"), "tilted",
                  "rises as it is raised", "249.1 kg level; 262 kg at 0.2 m", "-148.5 mm", "below the ground")
    assert "Is raised_axle_kg read under the raised axle" in err
    # a rise that leaves the CG above the ground still puts it below the wheel centres: refused too
    refused(capsys, tmp_path, WEIGHING.replace("236.4", "252.0"), "tilted", "rises",
            "below the wheel centres (wheel_radius_m 0.27 m)")
    # the rear raised: its reading must fall as well
    rear = WEIGHING.replace('raised = "front"', 'raised = "rear"')
    refused(capsys, tmp_path, rear.replace("236.4", "340.0"), "tilted", "rises", "333.9 kg level")
    code, out, err, _ = weigh(capsys, tmp_path, rear.replace("236.4", "330.0"))
    assert code == 0 and err == "" and "cg z 396.5" in out


def test_a_rise_within_the_noise_passes(capsys, tmp_path):
    """A CG at the wheel centres' height, read with 0.5 kg noise: a reading 0.3 kg above the level one is
    within twice the result's sigma (16 mm)."""
    code, out, err, _ = weigh(capsys, tmp_path, WEIGHING.replace("236.4", "249.4"))
    assert code == 0 and err == "", err


def test_readings_typed_in_newtons_suggest_dividing(capsys, tmp_path):
    """A 375 kg trike weighed in newtons: 3678.8 'kg'."""
    text = (WEIGHING.replace("249.1", "1350.0").replace("175.6", "1200.0").replace("158.3", "1128.8")
            .replace("236.4", "1300.0"))
    refused(capsys, tmp_path, text, "level", "3678.8 kg", "heavier than any three-wheeler",
            "did you type newtons? divide by 9.81 (375.1 kg)")


def test_masses_out_of_any_trikes_range(capsys, tmp_path):
    tonnes = WEIGHING.replace("249.1", "0.2491").replace("175.6", "0.1756").replace("158.3", "0.1583")
    refused(capsys, tmp_path, tonnes.split("[[tilted]]")[0], "level", "lighter than any three-wheeler",
            "did you type tonnes? multiply by 1000 (583.0 kg)")
    heavy = WEIGHING.replace("249.1", "2000").replace("175.6", "1500").replace("158.3", "1500")
    refused(capsys, tmp_path, heavy.split("[[tilted]]")[0], "level", "5000.0 kg", f"10 to {MAX_MASS_KG:g} kg",
            "did you type newtons? divide by 9.81 (509.9 kg)")
    feather = WEIGHING.replace("249.1", "3").replace("175.6", "2").replace("158.3", "2")
    err = refused(capsys, tmp_path, feather.split("[[tilted]]")[0], "level", "7.0 kg")
    assert "did you type" not in err


def test_heavy_readings_in_newtons_hint_only_when_they_make_a_trike(capsys, tmp_path):
    huge = WEIGHING.replace("249.1", "9000").replace("175.6", "9000").replace("158.3", "9000")
    err = refused(capsys, tmp_path, huge.split("[[tilted]]")[0], "level", "27000.0 kg")
    assert "did you type" not in err  # 2753 kg in newtons: still no trike


def test_a_wheel_reading_zero_would_tip(capsys, tmp_path):
    refused(capsys, tmp_path, WEIGHING.replace("158.3", "0"), "level.rear_right", "reads 0 kg", "tipping over")


def test_contacts_on_one_line_are_refused(capsys, tmp_path):
    line = WEIGHING.replace("front = [1.95, 0.0]", "front = [1.95, 0.55]").replace("[0.0, -0.55]", "[0.9, 0.55]")
    refused(capsys, tmp_path, line, "contacts", "within 0 mm of one line")
    twice = WEIGHING.replace("[0.0, -0.55]", "[0.0, 0.55]")  # two wheels on one spot
    refused(capsys, tmp_path, twice, "contacts", "of one line")
    narrow = WEIGHING.replace("[0.0, 0.55]", "[0.0, 0.02]").replace("[0.0, -0.55]", "[0.0, -0.02]")
    refused(capsys, tmp_path, narrow, "contacts", "within 40 mm of one line")


def test_an_axle_heavier_than_the_vehicle(capsys, tmp_path):
    refused(capsys, tmp_path, WEIGHING.replace("236.4", "600"), "tilted[0].raised_axle_kg",
            "600 kg is more than the whole vehicle weighs (583.0 kg in [level])")


def test_a_cg_above_any_trike(capsys, tmp_path):
    """A raise height typed 10 times too small (0.02 m for 0.2 m) puts the CG 10 times too high."""
    err = refused(capsys, tmp_path, WEIGHING.replace("height_m = 0.20", "height_m = 0.02"), "tilted",
                  f"above any three-wheeler's (at most {MAX_CG_HEIGHT_M:g} m)", "check height_m (in m)")
    assert "mm high" in err


def test_a_cg_that_would_have_tipped_the_vehicle_at_the_largest_raise(capsys, tmp_path):
    """Readings of 0 kg at 0.2 m and 1.5 m: each alone balances the vehicle on its lower axle, their fit puts
    the CG higher than the 1.5 m raise allows."""
    text = WEIGHING.replace("236.4", "0") + TILTED.format(h=1.5, kg=0)
    refused(capsys, tmp_path, text, "tilted", "would have tipped the vehicle onto its lower axle at the raise of 1.5 m",
            "do not fit the geometry")


@pytest.mark.parametrize(("edit", "where", "needle"), [
    (("[1.95, 0.0]", "[1950, 0.0]"), "contacts.front[0]", "did you type millimetres or centimetres? 1950 mm is 1.95 m"),
    (("249.1", "249100"), "level.front", "did you type grams? 249100 g is 249.1 kg"),
    (("wheel_radius_m = 0.27", "wheel_radius_m = 270"), "wheel_radius_m", "270 mm is 0.27 m"),
    (("height_m = 0.20", "height_m = 20"), "tilted[0].height_m", "20 mm is 0.02 m, 20 cm is 0.2 m"),
    (("height_m = 0.20", "height_m = 2.5"), "tilted[0].height_m", "must be below the wheelbase"),
    (("158.3", "-158.3"), "level.rear_right", "scale reading must be >= 0 kg"),
])
def test_values_out_of_range_say_the_unit_they_fit(capsys, tmp_path, edit, where, needle):
    assert edit[0] in WEIGHING
    refused(capsys, tmp_path, WEIGHING.replace(*edit, 1), where, needle)


def test_a_reading_off_the_others_warns_and_the_result_stands(capsys, tmp_path):
    text = WEIGHING + TILTED.format(h=0.30, kg=236.0) + TILTED.format(h=0.40, kg=223.6)
    code, out, err, file = weigh(capsys, tmp_path, text)
    assert code == 0 and "cg z" in out
    assert err.count("\n") == 1 and err.startswith(f"trikedyn: warning: PlausibilityWarning: {file}: tilted[1]"), err
    assert "236 kg at 0.3 m is +4.1 kg off the fit through all 3 heights" in err
    # without a reading uncertainty there is no scale to judge by: silent
    code, _, err, _ = weigh(capsys, tmp_path, text.replace("reading_std_kg = 0.5", "reading_std_kg = 0.0"))
    assert code == 0 and err == ""


def _record(mass, cg, heights, raised="front", radius=0.27, wheelbase=1.95, track=1.1, noise=0.0, seed=0):
    contacts = {"front": [wheelbase, 0.0], "rear_left": [0.0, track / 2], "rear_right": [0.0, -track / 2]}
    rng = np.random.default_rng(seed)
    level = wheel_loads_from_cg(mass, cg[:2], list(contacts.values())) / G + rng.normal(0.0, noise, 3)
    axle = tilted_wheel_loads(mass, cg, wheelbase, heights, wheel_radius_m=radius, raised=raised) / G
    axle = axle + rng.normal(0.0, noise, len(heights))
    return {"reading_std_kg": noise, "wheel_radius_m": radius, "contacts": contacts,
            "level": dict(zip(contacts, level.tolist(), strict=True)),
            "tilted": [{"raised": raised, "height_m": h, "raised_axle_kg": f}
                       for h, f in zip(heights, axle.tolist(), strict=True)]}


@pytest.mark.parametrize(("mass", "cg", "heights", "raised", "radius"), [
    (583.0, (0.8321, 0.016, 0.3804), [0.15, 0.25, 0.35], "front", 0.27),   # the paper's trike (x read as mass split)
    (25.0, (0.35, 0.0, 0.28), [0.1, 0.2], "front", 0.25),                   # a recumbent trike without rider
    (120.0, (0.5, 0.0, 0.36), [0.1], "rear", 0.25),                        # a low recumbent with its rider
    (1900.0, (1.2, 0.05, 0.9), [0.2, 0.4, 0.6], "front", 0.35),            # a laden three-wheeled truck
    (400.0, (0.6, -0.03, 1.4), [0.05, 0.1], "rear", 0.3),                  # a tall box on a cargo trike
    (300.0, (0.9, 0.0, 0.5), [0.2, 0.5, 0.8, 1.1], "front", 0.27),          # large raises
])
def test_plausible_trikes_reduce_silently(recwarn, mass, cg, heights, raised, radius):
    """Weighings of vehicles across the range, with 0.5 kg noise (0.05 kg on the light ones), reduce without
    a refusal or a warning and give their CG back."""
    noise = 0.05 if mass < 200 else 0.5
    result = reduce_weighing(_record(mass, cg, heights, raised, radius, noise=noise, seed=7), where="w.toml")
    assert result.level.mass_kg == pytest.approx(mass, abs=5 * noise)
    assert result.height.cg_z_m == pytest.approx(cg[2], abs=max(4 * result.height.cg_z_std_m, 1e-6))
    assert not [w for w in recwarn if issubclass(w.category, PlausibilityWarning)]


def test_the_python_api_refuses_the_same(tmp_path):
    rec = _record(583.0, (0.8321, 0.016, 0.3804), [0.2])
    rec["tilted"][0]["raised_axle_kg"] = rec["level"]["front"] + 13.0
    with pytest.raises(InputError, match="rises as it is raised") as info:
        reduce_weighing(rec, where="w.toml")
    assert info.value.where == "w.toml: tilted"
    with pytest.warns(PlausibilityWarning, match=r"tilted\[0\]"):
        rec = _record(583.0, (0.8321, 0.016, 0.3804), [0.2, 0.3])
        rec["reading_std_kg"] = 0.1
        rec["tilted"][0]["raised_axle_kg"] += 3.0
        reduce_weighing(rec, where="w.toml")
