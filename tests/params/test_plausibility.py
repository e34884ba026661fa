"""A vehicle file that looks like a slip: a warning at load (radians in a degree field, a tyre file of another
size or load, a spring in N/mm, a damper in N s/mm), the command going on; a value refused by its range that
fits in another unit says which; the presets and the real data load silently."""

import shutil
import warnings

import pytest
from tests.conftest import SHARED

from trikedyn.cli import main
from trikedyn.errors import InputError, ParameterError
from trikedyn.params import list_presets, load_vehicle, parse_vehicle
from trikedyn.params.plausibility import RAKE_AS_RADIANS, implausible_values
from trikedyn.plausibility import PlausibilityWarning
from trikedyn.tyre.tir import parse_tir

TIR = SHARED / "data" / "tyres" / "mf_185_80R14.tir"
needs_tir = pytest.mark.skipif(not TIR.is_file(), reason=f"shared tyre data absent ({TIR})")


def run(capsys, *args):
    code = main(list(args))
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err
    return code, captured.out, captured.err


def vehicle(tmp_path, body: str, name="v.toml") -> str:
    path = tmp_path / name
    path.write_text('extends = "reference-etrike"\nname = "x"\n' + body, encoding="utf-8")
    return str(path)


def warned(capsys, file, *needles, count=1):
    """``vehicle check FILE`` goes on (exit 0 or 1: the audit's verdict) and prints ``count`` warning lines
    naming the file, holding every needle."""
    code, out, err = run(capsys, "vehicle", "check", file)
    assert code in (0, 1), err
    lines = err.splitlines()
    assert len(lines) == count and all(
        line.startswith(f"trikedyn: warning: PlausibilityWarning: {file}: ") for line in lines), err
    for needle in needles:
        assert needle in err, err
    assert out  # the findings still printed
    return err


def quiet(capsys, *args):
    code, _, err = run(capsys, *args)
    assert code in (0, 1) and err == "", err


@pytest.mark.parametrize("name", list_presets())
def test_every_preset_loads_silently(capsys, name):
    quiet(capsys, "vehicle", "check", name)
    assert implausible_values(load_vehicle(name).params) == []


def test_a_vertical_axis_and_a_rake_above_the_window_are_silent(capsys, tmp_path):
    quiet(capsys, "vehicle", "check", vehicle(tmp_path, "[steering]\naxis_angle_deg = 0.0\n"))  # a vertical axis
    quiet(capsys, "vehicle", "check", vehicle(tmp_path, "[steering]\naxis_angle_deg = 0.9\n"))  # no radian rake


@pytest.mark.parametrize("rake", [0.35, RAKE_AS_RADIANS[0], RAKE_AS_RADIANS[1]])
def test_a_rake_in_radians_warns(capsys, tmp_path, rake):
    """The issue's case, steering.axis_angle_deg = 0.35 (20.1 deg in radians), and the window's ends."""
    err = warned(capsys, vehicle(tmp_path, f"[steering]\naxis_angle_deg = {rake}\n"),
                 f"steering.axis_angle_deg = {rake:g} looks like radians", "write the angle in degrees")
    if rake == 0.35:
        assert "0.35 rad is 20.1 deg" in err


def test_the_warning_comes_through_the_api_and_the_set_loads(tmp_path):
    with pytest.warns(PlausibilityWarning, match=r"v.toml: steering.axis_angle_deg = 0.35 looks like radians"):
        pset = load_vehicle(vehicle(tmp_path, "[steering]\naxis_angle_deg = 0.35\n"))
    assert pset.params.steering.axis_angle_deg == 0.35
    with pytest.warns(PlausibilityWarning, match="<text>: steering"):
        parse_vehicle('extends = "reference-etrike"\nname = "x"\n[steering]\naxis_angle_deg = 0.4\n', "<text>")


@pytest.mark.parametrize(("body", "where", "needle"), [
    ("[steering]\nmax_angle_deg = 0.7\n", "steering.max_angle_deg", "did you type radians? 0.7 rad is 40.11 deg"),
    ("[steering]\nmax_rate_deg_per_s = 5\n", "steering.max_rate_deg_per_s", "did you type rad/s? 5 rad/s is 286.5 deg/s"),
    ("[mass]\ncg_z_m = 380.4\n", "mass.cg_z_m", "did you type millimetres? 380.4 mm is 0.3804 m"),
    ("[suspension.rear]\nstiffness_N_per_m = 45.8\n", "suspension.rear.stiffness_N_per_m",
     "did you type N/mm? 45.8 N/mm is 45800 N/m"),
    ('[[wheels]]\nname = "front"\nradius_m = 270\n', "wheels[front].radius_m", "270 mm is 0.27 m"),
])
def test_a_refused_value_says_the_unit_it_fits(capsys, tmp_path, body, where, needle):
    file = vehicle(tmp_path, body)
    code, _, err = run(capsys, "vehicle", "check", file)
    assert code == 2 and err.count("\n") == 1 and err.startswith(f"trikedyn: error: {file}: {where}: "), err
    assert needle in err, err


def test_a_refused_value_without_a_fitting_unit_has_no_hint(capsys, tmp_path):
    code, _, err = run(capsys, "vehicle", "check", vehicle(tmp_path, "[steering]\naxis_angle_deg = 60\n"))
    assert code == 2 and "did you type" not in err
    code, _, err = run(capsys, "vehicle", "check", vehicle(tmp_path, "[mass]\ncg_z_m = -1\n"))
    assert code == 2 and "did you type" not in err


def test_a_spring_in_n_per_mm_and_a_damper_in_n_s_per_mm_warn(capsys, tmp_path):
    file = vehicle(tmp_path, "[suspension.rear]\nstiffness_N_per_m = 120\n[suspension.front]\ndamping_Ns_per_m = 2.5\n")
    err = warned(capsys, file, "suspension.rear.stiffness_N_per_m = 120", "did you type N/mm? 120 N/mm is 120000 N/m",
                 "suspension.front.damping_Ns_per_m = 2.5", "did you type N s/mm? 2.5 N s/mm is 2500 N s/m", count=2)
    assert "no road vehicle's" in err
    # a soft but real spring (1.2 Hz) and an undamped suspension (C = 0) are no slips
    quiet(capsys, "vehicle", "check",
          vehicle(tmp_path, "[suspension.rear]\nstiffness_N_per_m = 9000\n[suspension.front]\ndamping_Ns_per_m = 0\n"))


@pytest.fixture
def tyres(tmp_path):
    (tmp_path / "tyres").mkdir()
    shutil.copy(TIR, tmp_path / "tyres" / TIR.name)
    return tmp_path


def _on_tir(wheels: dict[str, float | None]) -> str:
    """[[wheels]] entries naming the shared .tir, each with its radius (None: the preset's 0.27 m)."""
    return "".join(f'[[wheels]]\nname = "{w}"\ntyre_file = "tyres/{TIR.name}"\n'
                   + (f"radius_m = {r}\n" if r is not None else "") for w, r in wheels.items())


@needs_tir
def test_a_tyre_file_of_another_size_warns(capsys, tyres):
    """The issue's case: UNLOADED_RADIUS 0.376 m on a 0.21 m wheel; one line for the wheels sharing a file."""
    warned(capsys, vehicle(tyres, _on_tir({"front": 0.21})), "wheels[front].tyre_file: UNLOADED_RADIUS 0.376 m",
           "+79% off the wheel's radius_m 0.21 m (more than 10%)", "is it this wheel's tyre?")
    err = warned(capsys, vehicle(tyres, _on_tir({"front": None, "rear_left": None, "rear_right": None})),
                 "wheels[front, rear_left, rear_right].tyre_file", "+39%")
    assert "diameter" not in err
    warned(capsys, vehicle(tyres, _on_tir({"front": 0.75})), "radius_m looks like the diameter")


@needs_tir
def test_a_tyre_file_of_the_wheels_size_is_silent(capsys, tyres):
    """Within 10 %: 0.376 m against 0.35 and 0.40 m wheels."""
    quiet(capsys, "vehicle", "check", vehicle(tyres, _on_tir({"front": 0.376, "rear_left": 0.35, "rear_right": 0.40})))


@needs_tir
def test_a_tyre_file_in_kilonewtons_warns(capsys, tyres):
    (tyres / "tyres" / "kn.tir").write_text(
        TIR.read_text(encoding="utf-8").replace("FORCE                    ='newton'", "FORCE = 'kilonewton'"),
        encoding="utf-8")
    body = '[[wheels]]\nname = "front"\nradius_m = 0.376\ntyre_file = "tyres/kn.tir"\n'
    warned(capsys, vehicle(tyres, body), "wheels[front].tyre_file: FNOMIN 3.8e+06 N of kn.tir",
           "times the wheel's static load (2440 N)", "[UNITS] FORCE")


@needs_tir
def test_warnings_do_not_stop_a_simulation(capsys, tyres):
    file = vehicle(tyres, _on_tir({"front": 0.21}) + "[steering]\naxis_angle_deg = 0.42\n")
    code, out, err = run(capsys, "modes", file, "--json")
    assert code == 0, err
    assert err.count("trikedyn: warning: PlausibilityWarning") == 2 and "error" not in err


@needs_tir
def test_the_real_tyre_file_and_logs_still_load(capsys):
    code, out, err = run(capsys, "tyre", "show", str(TIR))
    assert code == 0 and err == "" and "0.376" in out
    logs = sorted(p for p in (SHARED / "data" / "witmotion").iterdir() if p.name != "SOURCES.md")
    assert logs
    for log in logs:
        code, _, err = run(capsys, "log", "info", str(log))
        assert code == 0 and "PlausibilityWarning" not in err, err


@pytest.mark.parametrize(("radius", "unit", "needle"), [("376", "meter", "376 m is no tyre's"),
                                                        ("0.376", "mm", "0.000376 m is no tyre's")])
def test_a_tyre_radius_in_another_unit_is_refused(radius, unit, needle):
    text = (f"[UNITS]\nLENGTH = '{unit}'\n[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC2002'\n[DIMENSION]\n"
            f"UNLOADED_RADIUS = {radius}\n[VERTICAL]\nFNOMIN = 3800\n")
    with pytest.raises(InputError, match=needle) as info:
        parse_tir(text, "t.tir")
    assert info.value.where == "t.tir:6" and f"'{unit}', its [UNITS] LENGTH" in str(info.value)
    assert parse_tir(text.replace(f"= {radius}\n", "= 0.3\n" if unit == "meter" else "= 300\n"), "t.tir")


def test_a_strict_run_turns_the_warning_into_an_error_naming_the_file(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        with pytest.raises(PlausibilityWarning, match=r"v.toml: steering.axis_angle_deg = 0.35 looks like radians"):
            load_vehicle(vehicle(tmp_path, "[steering]\naxis_angle_deg = 0.35\n"))
    with pytest.raises(ParameterError, match="axis_angle_deg"):  # a negative rake is refused, as before
        load_vehicle(vehicle(tmp_path, "[steering]\naxis_angle_deg = -0.35\n"))
