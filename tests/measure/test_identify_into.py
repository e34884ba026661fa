"""Issue 20, the spring end to end: a quarter car with known suspension K, C and tyre, recorded at 10 and 100 Hz,
identified into a vehicle file through the command line; the audit then finds Eq. 3 consistent and the model's
quarter car bounces at the record's f_n. And every refusal of ``--into`` leaves the file as it was."""

from __future__ import annotations

import json
import os

import numpy as np
import pandas as pd
import pytest

from trikedyn.cli import main
from trikedyn.measure.logs import write_log
from trikedyn.measure.quarter_car import quarter_car_free_decay, quarter_car_modes
from trikedyn.params import load_vehicle
from trikedyn.params.springs import series_stiffness, suspension_quarter_car

K_OWN, C_OWN = 70_000.0, 1_500.0  # the suspension's own spring and damper at the wheel [N/m, N s/m]
VEHICLE = """extends = "reference-etrike-eq4"
name = "my-trike"
description = "a trike whose front spring is measured on a bump"
source = "test"

# weighed in the workshop
[mass]
cg_x_m = { value = 0.80, source = "weighing" }  # the CG moved forward
"""


def run(capsys, *args):
    code = main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def record(path, rate_hz, car, seed=3, damping=C_OWN):
    """The front quarter car of the vehicle file with K_OWN and ``damping`` over a 5 cm bump at 5 km/h, as a 10 or
    100 Hz accelerometer (noise 0.05 m/s^2, bias 0.2 m/s^2, gravity) reads it, written as a WitMotion SDK file."""
    t, az = quarter_car_free_decay(car.sprung_mass_kg, car.unsprung_mass_kg, K_OWN, damping, car.tyre_stiffness_N_per_m,
                                   car.tyre_damping_Ns_per_m, duration_s=12.0, sample_rate_hz=rate_hz,
                                   bump=(0.05, 0.5, 5 / 3.6), event_time_s=2.0, noise_std_mps2=0.05, bias_mps2=0.2,
                                   seed=seed, include_gravity=True)
    frame = pd.DataFrame({"time_s": t, "ax_mps2": 0.0 * t, "ay_mps2": 0.0 * t, "az_mps2": az})
    return write_log(frame, path, "witmotion-sdk")


@pytest.fixture()
def trike(tmp_path):
    path = tmp_path / "my-trike.toml"
    path.write_text(VEHICLE, encoding="utf-8")
    return path


@pytest.mark.parametrize("rate_hz", [10.0, 100.0])
@pytest.mark.parametrize("damping", [C_OWN, 2 * C_OWN])  # xi 0.12 and 0.24
def test_identify_into_then_check_finds_eq3_consistent(capsys, tmp_path, trike, rate_hz, damping):
    car = suspension_quarter_car(load_vehicle(trike).params, "front")
    true = quarter_car_modes(car.sprung_mass_kg, car.unsprung_mass_kg, K_OWN, damping, car.tyre_stiffness_N_per_m,
                             car.tyre_damping_Ns_per_m)
    log = record(tmp_path / "bump.txt", rate_hz, car, damping=damping)
    code, out, err = run(capsys, "identify", log, "--into", trike, "--suspension", "front", "--json")
    assert code == 0 and err == ""
    ident = json.loads(out)
    written = ident["vehicle_file"]["values"]
    assert written == ident["vehicle_values"]
    assert written["stiffness_N_per_m"] == pytest.approx(K_OWN, rel=0.03)
    assert written["damping_Ns_per_m"] == pytest.approx(damping, rel=0.10)
    assert written["natural_frequency_hz"] == pytest.approx(true.sprung_frequency_hz, rel=0.02)
    # the tyre-inclusive K of the paper's Eq. 3 is reported beside, well below the spring's own
    assert ident["equivalent_stiffness_N_per_m"] < 0.85 * written["stiffness_N_per_m"]

    text = trike.read_text(encoding="utf-8")
    assert text.startswith(VEHICLE)  # every other line, comment and note kept as written
    pset = load_vehicle(trike)
    front = pset.params.suspension["front"]
    assert front.stiffness_N_per_m == written["stiffness_N_per_m"] and front.damping_Ns_per_m == written["damping_Ns_per_m"]
    source = pset.notes["suspension.front.stiffness_N_per_m"]["source"]
    assert source.startswith(f"trikedyn identify {log} (") and "f_n" in source and "±" in source
    assert pset.notes["mass.cg_x_m"] == {"source": "weighing"}

    code, out, err = run(capsys, "vehicle", "check", trike, "--json")
    assert code == 0 and err == ""
    findings = json.loads(out)["findings"]
    eq3 = next(f for f in findings if f["topic"] == "sprung mass" and f["values"]["wheel"] == "front")
    assert eq3["level"] == "ok" and eq3["values"]["reading"] == "series"
    assert eq3["values"]["ratio_series_to_cg"] == pytest.approx(1.0, abs=0.02)
    assert eq3["values"]["ratio_eq3_to_cg"] > 1.15  # the rigid-tyre Eq. 3, beside: it would be inconsistent
    eq4 = next(f for f in findings if f["topic"] == "damping (Eq. 4)" and f["values"]["suspension"] == "front")
    assert eq4["level"] == "ok"
    # the model's quarter car of the file bounces at the record's f_n
    assert eq3["values"]["natural_frequency_model_hz"] == pytest.approx(true.sprung_frequency_hz, rel=0.02)
    assert ident["vehicle_file"]["model_frequency_hz"] == pytest.approx(ident["natural_frequency_hz"], rel=0.02)


def test_a_tyre_inclusive_k_is_a_warning_with_the_models_bounce(capsys, tmp_path, trike):
    """The old tutorial's mistake: Eq. 3's K (the tyre taken as rigid) written into the file."""
    car = suspension_quarter_car(load_vehicle(trike).params, "front")
    log = record(tmp_path / "bump.txt", 100.0, car)
    code, out, _ = run(capsys, "identify", log, "--sprung-mass", f"{car.sprung_mass_kg:.3f}", "--json")
    ident = json.loads(out)
    assert code == 0 and "vehicle_values" not in ident
    k_eq = ident["stiffness_N_per_m"]
    assert k_eq == pytest.approx(series_stiffness(K_OWN, car.tyre_stiffness_N_per_m), rel=0.05)
    with trike.open("a", encoding="utf-8") as fh:
        fh.write(f"\n[suspension.front]\nstiffness_N_per_m = {k_eq}\ndamping_Ns_per_m = {ident['damping_Ns_per_m']}\n"
                 f"natural_frequency_hz = {ident['natural_frequency_hz']}\ndamping_ratio = {ident['damping_ratio']}\n")
    code, out, _ = run(capsys, "vehicle", "check", trike, "--json")
    front = next(f for f in json.loads(out)["findings"] if f["topic"] == "sprung mass" and f["values"]["wheel"] == "front")
    assert front["level"] == "warning" and "tyre-inclusive" in front["message"]
    assert front["values"]["natural_frequency_model_hz"] < 0.95 * ident["natural_frequency_hz"]
    assert front["values"]["stiffness_own_for_frequency_N_per_m"] == pytest.approx(K_OWN, rel=0.05)


def test_force_rules_and_same_log(capsys, tmp_path, trike):
    car = suspension_quarter_car(load_vehicle(trike).params, "front")
    first, second = record(tmp_path / "a.txt", 100.0, car), record(tmp_path / "b.txt", 100.0, car, seed=4)
    assert run(capsys, "identify", first, "--into", trike, "--suspension", "front")[0] == 0
    assert run(capsys, "identify", first, "--into", trike, "--suspension", "front")[0] == 0  # the same log again
    before = trike.read_bytes()
    code, _, err = run(capsys, "identify", second, "--into", trike, "--suspension", "front")
    assert code == 2 and "suspension.front.stiffness_N_per_m is set in this file" in err and "--force" in err
    assert trike.read_bytes() == before
    code, out, _ = run(capsys, "identify", second, "--into", trike, "--suspension", "front", "--force")
    assert code == 0 and "replaced: suspension.front.stiffness_N_per_m" in out
    assert "trikedyn identify " + str(second) in load_vehicle(trike).notes["suspension.front.damping_Ns_per_m"]["source"]
    # a value of the paper in a whole exported file: replaced only with --force
    exported = tmp_path / "exported.toml"
    assert run(capsys, "vehicle", "export", "reference-etrike", exported)[0] == 0
    code, _, err = run(capsys, "identify", first, "--into", exported, "--suspension", "rear")
    assert code == 2 and "source 'paper Table 1" in err


@pytest.mark.parametrize("case", ["preset", "missing", "suspension", "read-only", "symlink", "log", "tyre", "alone"])
def test_refusals_are_one_line_exit_2_and_leave_the_file(capsys, tmp_path, trike, case):
    car = suspension_quarter_car(load_vehicle(trike).params, "front")
    log = record(tmp_path / "bump.txt", 100.0, car)
    into, extra, expect = trike, [], ""
    if case == "preset":
        into, expect = "reference-etrike", "is a preset, which is never changed"
    elif case == "missing":
        into, expect = tmp_path / "nothere.toml", "no such vehicle file"
    elif case == "suspension":
        extra, expect = ["--suspension", "frnt"], "did you mean 'front'?"
    elif case == "read-only":
        trike.chmod(0o444)
        expect = "is read-only"
    elif case == "symlink":
        into = tmp_path / "link.toml"
        os.symlink(trike, into)
        expect = "is a symbolic link"
    elif case == "log":
        into, expect = log, "is also an input of this command"
    elif case == "tyre":
        extra, expect = ["--tyre-stiffness", "150000"], "is not the vehicle file's 200000 N/m"
    before = trike.read_bytes(), trike.stat().st_mtime_ns
    args = ["identify", log, "--into", into, *(extra if case != "alone" else [])]
    if case == "alone":
        expect = "--into FILE and --suspension NAME go together"
    elif "--suspension" not in extra:
        args += ["--suspension", "front"]
    code, out, err = run(capsys, *args)
    assert code == 2 and out == "" and err.count("\n") == 1 and expect in err, err
    assert (trike.read_bytes(), trike.stat().st_mtime_ns) == before
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]
    trike.chmod(0o644)


def test_without_into_the_text_says_which_k_is_which(capsys, tmp_path, trike):
    car = suspension_quarter_car(load_vehicle(trike).params, "front")
    log = record(tmp_path / "bump.txt", 100.0, car)
    code, out, _ = run(capsys, "identify", log, "--sprung-mass", "227.5", "--tyre-stiffness", "200000",
                       "--unsprung-mass", f"{car.unsprung_mass_kg}")
    assert code == 0
    assert "the suspension's own spring and damper, at the wheel: what a vehicle file's [suspension.NAME] takes" in out
    assert "stiffness_N_per_m    = " in out and "tyre included, the paper's rigid-tyre Eqs. 3-4" in out
    own = float(out.split("stiffness_N_per_m    = ")[1].split()[0])
    assert own == pytest.approx(K_OWN, rel=0.03)
    code, out, _ = run(capsys, "identify", log, "--sprung-mass", "227.5")
    assert code == 0 and "give --tyre-stiffness" in out and "stiffness_N_per_m    =" not in out
    code, _, err = run(capsys, "identify", log, "--unsprung-mass", "12")
    assert code == 2 and "--unsprung-mass" in err


def test_a_table_written_another_way_is_refused_unchanged(capsys, tmp_path):
    """A file that writes the suspension as dotted keys: the edit cannot keep it faithfully, so it refuses."""
    path = tmp_path / "dotted.toml"
    path.write_text(VEHICLE + "\n[suspension]\nfront.damping_ratio = 0.2\n", encoding="utf-8")
    car = suspension_quarter_car(load_vehicle(path).params, "front")
    log = record(tmp_path / "bump.txt", 100.0, car)
    before = path.read_bytes()
    code, _, err = run(capsys, "identify", log, "--into", path, "--suspension", "front", "--force")
    assert code == 2 and "cannot update [suspension.front] in place" in err
    assert path.read_bytes() == before


def test_permissions_are_kept(capsys, tmp_path, trike):
    trike.chmod(0o640)
    car = suspension_quarter_car(load_vehicle(trike).params, "front")
    log = record(tmp_path / "bump.txt", 100.0, car)
    assert run(capsys, "identify", log, "--into", trike, "--suspension", "front")[0] == 0
    assert trike.stat().st_mode & 0o777 == 0o640
    assert np.isclose(load_vehicle(trike).params.suspension["front"].stiffness_N_per_m, K_OWN, rtol=0.03)
