"""Issue 20: logs that a spreadsheet or a phone wrote, read from the command line (--time-column, --time-unit,
--delimiter, --decimal, --column, --unit; phyphox's export detected)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from trikedyn.cli import main
from trikedyn.measure.logs import read_log, write_log
from trikedyn.measure.quarter_car import quarter_car_free_decay

G = 9.80665


def run(capsys, *args):
    code = main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def info(capsys, *args):
    code, out, err = run(capsys, "log", "info", *args, "--json")
    assert code == 0 and err == "", err
    return json.loads(out)


def bump(rate_hz=100.0):
    """A quarter car (M_s 160 kg, m 20 kg, K 46 kN/m, C 1100 N s/m, tyre 200 kN/m) over a 5 cm bump: t [s], a_z."""
    return quarter_car_free_decay(160.0, 20.0, 46000.0, 1100.0, 200e3, duration_s=12.0, sample_rate_hz=rate_hz,
                                  bump=(0.05, 0.5, 5 / 3.6), event_time_s=1.0, noise_std_mps2=0.02, seed=3,
                                  include_gravity=True)


def test_phyphox_exports_are_detected(capsys, tmp_path):
    comma = tmp_path / "Accelerometer.csv"
    comma.write_text('"Time (s)","Acceleration x (m/s^2)","Acceleration y (m/s^2)","Acceleration z (m/s^2)",'
                     '"Absolute acceleration (m/s^2)"\n'
                     "0.000000000E0,1.0E-1,2.0E-1,9.81E0,9.81E0\n1.000000000E-2,1.1E-1,2.0E-1,9.83E0,9.83E0\n")
    got = info(capsys, comma)
    assert got["format"] == "phyphox" and got["samples"] == 2 and got["sample_rate_hz"] == pytest.approx(100.0)
    assert got["channels"]["az_mps2"]["mean"] == pytest.approx(9.82)
    assert got["channels"]["az_mps2"]["original"] == "Acceleration z (m/s^2)"
    assert "Absolute acceleration (m/s^2)" in got["channels"]
    europe = tmp_path / "Linear Acceleration.csv"  # phyphox's "CSV (semicolon, decimal comma)", gravity removed
    europe.write_text('"Time (s)";"Linear Acceleration x (m/s^2)";"Linear Acceleration y (m/s^2)";'
                      '"Linear Acceleration z (m/s^2)"\n0,000000000E0;1,0E-1;0,0E0;2,5E-1\n2,0E-2;1,2E-1;0,0E0;-2,5E-1\n')
    got = info(capsys, europe)
    assert got["format"] == "phyphox" and got["duration_s"] == pytest.approx(0.02)
    assert got["channels"]["ax_mps2"]["mean"] == pytest.approx(0.11)
    assert any("decimal mark" in n for n in got["notes"]) and any("gravity removed" in n for n in got["notes"])


def test_a_time_ms_column(capsys, tmp_path):
    path = tmp_path / "logger.csv"
    path.write_text("time_ms,ax_mps2,az_mps2\n0,0.1,9.8\n10,0.2,9.7\n20,0.1,9.9\n")
    got = info(capsys, path)
    assert got["sample_rate_hz"] == pytest.approx(100.0) and any("read in ms" in n for n in got["notes"])
    other = tmp_path / "arduino.csv"
    other.write_text("millis,az\n1000,1.0\n1005,1.0\n1010,1.01\n")
    got = info(capsys, other, "--time-column", "millis", "--time-unit", "ms", "--column", "az_mps2=az", "--unit",
               "az_mps2=g")
    assert got["sample_rate_hz"] == pytest.approx(200.0) and got["duration_s"] == pytest.approx(0.01)
    assert got["channels"]["az_mps2"]["mean"] == pytest.approx(1.0033333 * G)
    code, _, err = run(capsys, "log", "info", tmp_path / "arduino.csv")
    assert code == 2 and "--time-column HEADER" in err and err.count("\n") == 1


def test_semicolon_and_decimal_comma_from_a_spreadsheet(capsys, tmp_path):
    t, az = bump()
    rows = "\n".join(f"{ti:.3f};{a:.5f}".replace(".", ",") for ti, a in zip(t, az, strict=True))
    path = tmp_path / "Fahrt.csv"
    path.write_text("Zeit [s];Beschleunigung Z [m/s²]\n" + rows + "\n", encoding="utf-8")
    options = ["--time-column", "Zeit [s]", "--column", "az_mps2=Beschleunigung Z [m/s²]"]
    got = info(capsys, path, *options)
    assert got["samples"] == len(t) and got["channels"]["az_mps2"]["mean"] == pytest.approx(az.mean(), abs=1e-4)
    explicit = info(capsys, path, *options, "--delimiter", ";", "--decimal", ",")
    assert explicit["channels"] == got["channels"]
    code, out, err = run(capsys, "identify", path, *options, "--sprung-mass", "160", "--tyre-stiffness", "200000",
                         "--unsprung-mass", "20", "--json")
    assert code == 0, err
    assert json.loads(out)["stiffness_N_per_m"] == pytest.approx(46000.0, rel=0.03)
    code, _, err = run(capsys, "log", "info", path, *options, "--decimal", ".")
    assert code == 2 and "--decimal ," in err and err.count("\n") == 1
    code, out, _ = run(capsys, "log", "convert", path, tmp_path / "si.csv", *options, "--json")
    assert code == 0
    np.testing.assert_allclose(read_log(tmp_path / "si.csv").channel("az_mps2"), np.round(az, 5), atol=1e-9)


def test_tab_separated_with_decimal_comma(capsys, tmp_path):
    path = tmp_path / "tab.txt"
    path.write_text("time_s\taz_mps2\n0,0\t9,81\n0,1\t9,79\n0,2\t9,83\n")
    got = info(capsys, path)
    assert got["channels"]["az_mps2"]["mean"] == pytest.approx(9.81) and got["sample_rate_hz"] == pytest.approx(10.0)
    assert info(capsys, path, "--delimiter", "tab")["samples"] == 3


@pytest.mark.parametrize(("args", "expect"), [
    (["--decimal", ";"], "--decimal"),
    (["--delimiter", "|"], "--delimiter"),
    (["--time-unit", "min"], "--time-unit"),
    (["--column", "az_mps2"], "--column"),
    (["--delimiter", ",", "--decimal", ","], "also the delimiter"),
    (["--time-column", "clock"], "'clock'"),
])
def test_bad_options_are_one_line(capsys, tmp_path, args, expect):
    path = tmp_path / "a.csv"
    path.write_text("time_s,az_mps2\n0,9.8\n0.1,9.8\n")
    code, out, err = run(capsys, "log", "info", path, *args)
    assert code == 2 and out == "" and err.count("\n") == 1 and expect in err, err


def test_the_options_belong_to_tables(capsys, tmp_path):
    t, az = bump(10.0)
    import pandas as pd

    log = write_log(pd.DataFrame({"time_s": t, "az_mps2": az}), tmp_path / "sdk.txt", "witmotion-sdk")
    code, _, err = run(capsys, "log", "info", log, "--time-column", "Chiptime")
    assert code == 2 and "time_column= (--time-column) apply to format 'phyphox' or 'csv' only" in err
