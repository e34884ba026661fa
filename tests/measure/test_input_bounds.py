"""Bounded measurement inputs: weighing files (a schema), suspension identification, IMU log readers."""

import time

import numpy as np
import pandas as pd
import pytest

from trikedyn.cli import main
from trikedyn.errors import InputError, LogFormatError
from trikedyn.measure import limits
from trikedyn.measure.logs import read_log, write_log
from trikedyn.measure.quarter_car import quarter_car_free_decay
from trikedyn.measure.signals import upsample
from trikedyn.measure.suspension import identify_suspension
from trikedyn.measure.weighing import load_weighing, reduce_weighing

WEIGHING = """reading_std_kg = 0.5
wheel_radius_m = 0.27
description = "workshop, 2026-11-03"

[contacts]
front = [1.95, 0.0]
rear_left = [0.0, 0.55]
rear_right = [0.0, -0.55]

[level]
front = 249.1
rear_left = 175.6
rear_right = 158.3

[[tilted]]
raised = "front"
height_m = 0.20
raised_axle_kg = 236.4
"""


def _weigh(tmp_path, text):
    file = tmp_path / "w.toml"
    file.write_text(text, encoding="utf-8")
    return reduce_weighing(load_weighing(file), where=str(file))


def test_the_documented_weighing_format_stays_valid(tmp_path):
    res = _weigh(tmp_path, WEIGHING)
    assert res.level.mass_kg == pytest.approx(583.0) and res.height is not None
    integers = WEIGHING.replace("249.1", "249").replace("[1.95, 0.0]", "[2, 0]")
    assert _weigh(tmp_path, integers).level.mass_kg == pytest.approx(582.9)
    level_only = WEIGHING.split("[[tilted]]")[0].replace("wheel_radius_m = 0.27\n", "")
    assert _weigh(tmp_path, level_only).height is None


@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        # each of these once escaped as a traceback
        (('raised = "front"', "raised = {}"), "tilted[0].raised: input should be 'front' or 'rear'"),  # TypeError
        (("249.1", "99999999999999999999999999"), "level.front: integer beyond 64 bits"),  # TypeError
        (("249.1", "9" * 5000), "invalid TOML: a number too long to read"),  # ValueError
        (("249.1", "[" * 3000 + "]" * 3000), "nested more than"),  # RecursionError
        # types and ranges checked
        (("249.1", '"249.1"'), "level.front: input should be a valid number (got '249.1')"),
        (("249.1", "true"), "level.front: input should be a valid number (got True)"),
        (("249.1", "nan"), "level.front: input should be a finite number"),
        (("249.1", "-3"), "level.front: scale reading must be >= 0 kg"),
        (("249.1", "1e9"), "level.front: input should be less than or equal to 10000"),
        (("front = [1.95, 0.0]", "front = [1.95]"), "contacts.front: expected [x, y] in m"),
        (("front = [1.95, 0.0]", "front = [1e300, 0.0]"), "contacts.front[0]: input should be less than or equal to 20"),
        (("reading_std_kg = 0.5", "reading_std_kg = -0.5"), "reading_std_kg: input should be greater than or equal to 0"),
        (("reading_std_kg", "reading_sd_kg"), "unknown key 'reading_sd_kg' in the top level; did you mean 'reading_std_kg'?"),
        (("height_m = 0.20", "heigth_m = 0.20"), "did you mean 'height_m'?"),
        (("height_m = 0.20", "height_m = 2.5"), "tilted[0].height_m: must be below the wheelbase of the contacts (1.95 m)"),
        (("wheel_radius_m = 0.27\n", ""), "wheel_radius_m: missing: [[tilted]] weighings need the axle height"),
    ],
)
def test_weighing_file_mistakes_give_one_line(tmp_path, edit, needle):
    assert edit[0] in WEIGHING
    with pytest.raises(InputError) as info:
        _weigh(tmp_path, WEIGHING.replace(edit[0], edit[1], 1))
    message = str(info.value)
    assert message.startswith(str(tmp_path / "w.toml")) and "\n" not in message
    assert needle in message, message


def test_tilted_must_be_a_list_of_tables(tmp_path):
    level_only = WEIGHING.split("[[tilted]]")[0]
    for text, needle in (("tilted = [1.0]\n", "tilted[0]: input should be a valid dictionary"),  # AttributeError
                         ("tilted = {}\n", "tilted: input should be a valid list")):
        with pytest.raises(InputError, match=needle.replace("[", r"\[").replace("]", r"\]")):
            _weigh(tmp_path, text + level_only)


def test_weighing_files_are_read_bounded(tmp_path):
    big = tmp_path / "big.toml"
    big.write_bytes(b"#" * (2 << 20))
    with pytest.raises(InputError, match="big.toml: larger than 1024 KiB"):
        load_weighing(big)
    latin = tmp_path / "latin.toml"
    latin.write_bytes(b'description = "pes\xe9e"\n')
    with pytest.raises(InputError, match=r"latin.toml: not UTF-8 text"):
        load_weighing(latin)


def test_cg_weigh_command_with_a_hostile_file(tmp_path, capsys):
    file = tmp_path / "w.toml"
    file.write_text(WEIGHING.replace('raised = "front"', "raised = {}"), encoding="utf-8")
    assert main(["cg", "weigh", str(file)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"trikedyn: error: {file}: tilted[0].raised")


# ----------------------------------------------------------------------------------------------------------
# suspension identification
# ----------------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def record():
    return quarter_car_free_decay(160.0, 20.0, 46000.0, 1100.0, 200e3, duration_s=8.0, sample_rate_hz=100.0,
                                  bump=(0.05, 0.5, 5 / 3.6), event_time_s=1.0, noise_std_mps2=0.05, seed=3,
                                  include_gravity=True)


@pytest.mark.parametrize(
    ("kwargs", "where", "needle"),
    [
        ({"sprung_mass_kg": 1e300}, "sprung_mass_kg", "expected 1 to 5000 kg"),
        ({"sprung_mass_kg": 0.5}, "sprung_mass_kg", "expected 1 to 5000 kg"),
        ({"sprung_mass_kg": float("nan")}, "sprung_mass_kg", "expected 1 to 5000 kg"),
        ({"tyre_stiffness_N_per_m": 1e-3}, "tyre_stiffness_N_per_m", "expected 1000 to 1e+07 N/m"),
        ({"tyre_stiffness_N_per_m": 1e300}, "tyre_stiffness_N_per_m", "expected 1000 to 1e+07 N/m"),
        ({"tyre_stiffness_N_per_m": 2e5, "tyre_damping_Ns_per_m": -1.0}, "tyre_damping_Ns_per_m", "0 to 10000"),
        ({"unsprung_mass_kg": 1e9}, "unsprung_mass_kg", "expected 0 to 500 kg"),
        ({"resample_hz": 1e9}, "resample_hz", "expected 1 to 10000 Hz"),
        ({"resample_hz": -5.0}, "resample_hz", "expected 1 to 10000 Hz"),
        ({"n_cycles": 0}, "n_cycles", "1 to 1000"),
        ({"n_cycles": 2.5}, "n_cycles", "1 to 1000"),
    ],
)
def test_identification_parameters_are_bounded(record, kwargs, where, needle):
    t, a = record
    args = {"sprung_mass_kg": 160.0} | kwargs
    start = time.perf_counter()
    with pytest.raises(InputError) as info:
        identify_suspension(t, a, **args)
    assert info.value.where == where and needle in str(info.value)
    assert time.perf_counter() - start < 1.0  # refused before any work


def test_identification_record_bounds(record):
    t, a = record
    with pytest.raises(InputError, match="sample rate 1e-300 Hz") as info:  # a --sample-rate 1e-300 record
        identify_suspension(np.arange(t.size) * 1e300, a, 160.0)
    assert info.value.where == "time_s"
    with pytest.raises(InputError, match="at most 3600 s"):
        identify_suspension(np.arange(400_000) * 0.01, np.resize(a, 400_000), 160.0)
    with pytest.raises(InputError, match="expected 1 to 10000 Hz"):  # time stamps in microseconds, read as s
        identify_suspension(t * 1e-6, a, 160.0)
    # 600 samples 0.1 ms apart, then 400 over 200 s: a median rate of 10 kHz over 200 s, 2e6 grid points
    burst = np.r_[np.arange(600) * 1e-4, 0.06 + np.linspace(0.5, 200.0, 400)]
    with pytest.raises(InputError, match=r"make 2e\+06 samples, at most 1000000") as info:
        identify_suspension(burst, np.resize(a, burst.size), 160.0)
    assert info.value.where == "time_s"
    long = np.zeros(limits.MAX_RECORD_SAMPLES + 1)
    with pytest.raises(InputError, match="record too long"):
        identify_suspension(np.arange(long.size) * 1e-3, long, 160.0)


def test_resampling_is_bounded(record):
    t, a = record
    ok = identify_suspension(t, a, 160.0, resample_hz=1e4)  # 7 s at 10 kHz: within the budget
    assert ok.processed_rate_hz == pytest.approx(1e4)
    with pytest.raises(InputError, match="rate_hz"):
        upsample(np.arange(0.0, 1000.0, 0.01), np.zeros(100_000), 1e4)  # 1e7 samples


def test_identify_command_refuses_absurd_rates(tmp_path, record, capsys):
    t, a = record
    file = tmp_path / "notime.csv"
    pd.DataFrame({"ax_mps2": 0.0 * a, "az_mps2": a}).to_csv(file, index=False)
    cases = [  # the command line may check an option itself; the library refuses it either way
        (["--sprung-mass", "1e300", "--sample-rate", "1e-300"], ("sprung", "sample")),
        (["--sprung-mass", "160", "--sample-rate", "1e-300"], ("sample",)),
        (["--sprung-mass", "1e300", "--sample-rate", "100"], ("sprung",)),
        (["--sprung-mass", "160", "--sample-rate", "100", "--resample-hz", "1e9"], ("resample",)),
    ]
    for args, needles in cases:
        assert main(["identify", str(file), *args]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and any(n in err.lower() for n in needles), err
    assert main(["identify", str(file), "--sprung-mass", "160", "--sample-rate", "100", "--json"]) == 0


# ----------------------------------------------------------------------------------------------------------
# log readers
# ----------------------------------------------------------------------------------------------------------
def test_values_that_overflow_in_si_units_are_refused(tmp_path):
    file = tmp_path / "g.csv"
    file.write_text("time_s,az\n0.0,1.0\n0.1,1e308\n0.2,1.0\n")
    with pytest.raises(LogFormatError, match=r"g.csv:3: column 'az' holds '1e\+?308', which overflows in SI units"):
        read_log(file, columns={"az_mps2": "az"}, units={"az_mps2": "g"})
    file.write_text("time_s,az_mps2\n-1e308,1.0\n1e308,1.0\n")
    with pytest.raises(LogFormatError, match=r"g.csv:3: time column 'time_s' holds '1e\+?308'"):
        read_log(file)


@pytest.mark.parametrize("rate", [0.0, -5.0, float("nan"), float("inf"), 1e-300, 1e9])
def test_absurd_sample_rates_are_refused(tmp_path, rate):
    file = tmp_path / "notime.csv"
    file.write_text("az_mps2\n9.8\n9.81\n9.79\n")
    with pytest.raises(LogFormatError, match="must lie within 0.01 .. 10000 Hz"):
        read_log(file, "csv", sample_rate_hz=rate)


def test_sample_rates_within_the_bounds_build_time(tmp_path):
    file = tmp_path / "notime.csv"
    file.write_text("az_mps2\n9.8\n9.81\n9.79\n")
    for rate in (0.01, 10.0, 10_000.0):
        assert read_log(file, "csv", sample_rate_hz=rate).sample_rate_hz == pytest.approx(rate)


def test_a_log_too_large_is_refused_before_reading(tmp_path, monkeypatch):
    frame = pd.DataFrame({"time_s": np.arange(50) * 0.01, "az_mps2": 9.81})
    file = write_log(frame, tmp_path / "log.txt", "witmotion-sdk")
    monkeypatch.setattr("trikedyn.measure.logs.MAX_LOG_BYTES", 100)
    with pytest.raises(LogFormatError, match="log.txt: .* MiB, more than the 0 MiB read"):
        read_log(file)
