"""Tests of trikedyn.measure.logs: the three real WitMotion files, round trips, detection, bad input."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from trikedyn.errors import LogFormatError
from trikedyn.measure.logs import CHANNELS, FORMATS, ImuLog, detect_format, read_log, write_log
from trikedyn.units import STANDARD_GRAVITY as G

DATA = Path(__file__).resolve().parents[3] / "shared" / "data" / "witmotion"
SDK = DATA / "witmotion_official_sdk_jy901_20220705190138.txt"
BIN = DATA / "witmotion_wt901sd_raw_example_data.TXT"
BWT = DATA / "bwt901cl_two_sensors_231213_181935_sensor_data.csv"
real = pytest.mark.skipif(not DATA.is_dir(), reason=f"real WitMotion data folder {DATA} is absent")
DEG = np.pi / 180


def accel_norm(log: ImuLog) -> np.ndarray:
    return np.sqrt(sum(log.channel(c) ** 2 for c in CHANNELS[:3]))


def check_common(log: ImuLog, fmt: str, path: Path) -> None:
    t = log.channel("time_s")
    assert log.format == fmt and log.source == str(path)
    assert list(log.data.columns[:1]) == ["time_s"] and t[0] == 0.0
    assert np.all(np.diff(t) > 0)
    assert np.median(accel_norm(log)) == pytest.approx(9.81, rel=0.05)
    assert detect_format(path) == fmt


# ------------------------------------------------------------------------------------- real files
@real
def test_sdk_file():
    text = SDK.read_bytes().decode("gbk")
    rows = [line.split("\t") for line in text.split("\n")[1:] if line.strip()]
    times = [r[0] for r in rows]
    distinct = list(dict.fromkeys(times))
    assert (len(rows), len(distinct)) == (712, 178)

    log = read_log(SDK)
    check_common(log, "witmotion-sdk", SDK)
    assert len(log.data) == len(distinct)
    assert any(f"dropped {len(rows) - len(distinct)} of {len(rows)} rows" in n for n in log.notes)
    first = rows[0]  # ' 2022-7-5 11:58:22.115', ax(g) 0.1577, ..., AngleX -29.125, T 35.99
    assert log.channel("az_mps2")[0] == pytest.approx(float(first[3]) * G)
    assert log.channel("roll_rad")[0] == pytest.approx(float(first[7]) * DEG)
    assert log.channel("temperature_degC")[0] == pytest.approx(float(first[10]))
    assert log.original_columns["temperature_degC"] == "T(°)"
    # the millisecond field is not padded: '11:58:23.30' is 30 ms after 11:58:23, i.e. 0.915 s after 22.115
    i = distinct.index(" 2022-7-5 11:58:23.30")
    assert log.channel("time_s")[i] == pytest.approx(0.915)
    assert log.sample_rate_hz == pytest.approx(1 / 0.115, rel=1e-3)


@real
def test_wt901sd_binary_file():
    raw = BIN.read_bytes()
    assert len(raw) % 11 == 0
    types = np.frombuffer(raw, np.uint8)[1::11]
    counts = {t: int((types == t).sum()) for t in (0x51, 0x52, 0x53, 0x54)}
    assert counts == dict.fromkeys((0x51, 0x52, 0x53, 0x54), 2017)

    log = read_log(BIN)
    check_common(log, "wt901sd-binary", BIN)
    assert len(log.data) == counts[0x51]
    assert log.sample_rate_hz == pytest.approx(10.0)
    assert any("assumed" in n for n in log.notes)
    az_raw = int.from_bytes(raw[6:8], "little", signed=True)
    assert log.channel("az_mps2")[0] == pytest.approx(az_raw / 32768 * 16 * G)
    assert log.channel("temperature_degC")[0] == pytest.approx(int.from_bytes(raw[8:10], "little") / 100)
    wz_raw = int.from_bytes(raw[17:19], "little", signed=True)
    assert log.channel("wz_radps")[0] == pytest.approx(wz_raw / 32768 * 2000 * DEG)
    assert read_log(BIN, sample_rate_hz=50).sample_rate_hz == pytest.approx(50.0)


@real
@pytest.mark.parametrize("sensor", [1, 2])
def test_bwt901cl_file(sensor):
    with BWT.open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(BWT.read_text().strip().split("\n")) - 1 == 61
    groups = [[f"{p}{c}{sensor}" for c in "XYZ"] for p in ("Acc", "Ang")]
    unreported = 0
    while any(all(float(rows[unreported][h]) == 0 for h in g) for g in groups):
        unreported += 1
    assert unreported == 1  # both sensors: the first row still holds the logger's zeros

    log = read_log(BWT, sensor=sensor)
    check_common(log, "bwt901cl-csv", BWT)
    assert len(log.data) == len(rows) - unreported
    assert log.sample_rate_hz == pytest.approx(9.6, rel=0.05)
    row = rows[unreported]
    assert log.channel("az_mps2")[0] == float(row[f"AccZ{sensor}"])  # m/s^2 as written
    assert log.channel("yaw_rad")[0] == pytest.approx(float(row[f"AngZ{sensor}"]) * DEG)
    assert log.channel("wy_radps")[0] == pytest.approx(float(row[f"AngVelY{sensor}"]) * DEG)
    assert any("had not reported" in n for n in log.notes)
    with pytest.raises(LogFormatError, match="sensor=3"):
        read_log(BWT, sensor=3)


# ------------------------------------------------------------------------------------ round trips
def synthetic(n: int = 200, rate: float = 100.0) -> pd.DataFrame:
    rng = np.random.default_rng(1)
    t = np.arange(n) / rate
    data = {"time_s": t}
    for k, c in enumerate(CHANNELS):
        scale = (2 * G, 3.0, 1.5)[k // 3]
        data[c] = scale * np.sin(2 * np.pi * (0.5 + k) * t + k) + (G if c == "az_mps2" else 0)
    data["temperature_degC"] = 25 + rng.normal(0, 0.3, n).round(2)
    return pd.DataFrame(data)


LSB = {"mps2": 16 / 32768 * G, "radps": 2000 / 32768 * DEG, "rad": 180 / 32768 * DEG, "degC": 0.01}


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_round_trip(fmt, tmp_path):
    src = synthetic()
    path = write_log(src, tmp_path / f"log.{fmt}", fmt)
    assert detect_format(path) == fmt
    log = read_log(path)
    assert log.format == fmt
    assert list(log.data.columns) == list(src.columns)
    for c in src.columns:
        got, want = log.channel(c), src[c].to_numpy()
        if fmt == "wt901sd-binary" and c != "time_s":
            tol = LSB[c.rsplit("_", 1)[-1]]
            assert np.max(np.abs(got - want)) <= tol / 2 + 1e-12, c
        elif c == "time_s" and fmt != "csv":
            assert np.max(np.abs(got - want)) <= 0.5e-3  # clock to 1 ms
        else:
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12, err_msg=c)
    assert read_log(path, fmt).data.equals(log.data)


def test_round_trip_of_imu_log_keeps_extras(tmp_path):
    log = read_log(write_log(synthetic(), tmp_path / "a.csv", "csv"))
    data = log.to_pandas().assign(q0=np.linspace(0, 1, len(log.data)))
    for fmt in ("witmotion-sdk", "witmotion-pc", "witmotion-2025", "bwt901cl-csv", "csv"):
        back = read_log(write_log(data, tmp_path / f"b.{fmt}", fmt))
        np.testing.assert_allclose(back.channel("q0"), data["q0"], rtol=1e-12, atol=0)


def test_sdk_writer_mimics_the_quirks(tmp_path):
    src = synthetic(n=3).assign(time_s=[0.0, 0.007, 0.03])
    raw = write_log(src, tmp_path / "sdk.txt").read_bytes()
    assert raw.count(b"\r\r\n") == 4 and "T(°)".encode("gbk") in raw
    assert b" 2000-1-1 0:0:0.7\t" in raw and b" 2000-1-1 0:0:0.30\t" in raw
    np.testing.assert_allclose(read_log(tmp_path / "sdk.txt").channel("time_s"), [0, 0.007, 0.03])


@real
def test_real_sdk_file_round_trips(tmp_path):
    log = read_log(SDK)
    back = read_log(write_log(log, tmp_path / "copy.txt"))
    pd.testing.assert_frame_equal(back.data, log.data, check_exact=False, rtol=1e-12)


def test_pc_export_with_two_devices(tmp_path):
    p = tmp_path / "pc.txt"
    head = "time\tDeviceName\tChipTime\tAccX(g)\tAccY(g)\tAccZ(g)\tAsX(°/s)\tAsY(°/s)\tAsZ(°/s)\tAngleX(°)\n"
    rows = [f"10:00:0{i // 2}.000\t{'AB'[i % 2]}\t2023-1-2 10:00:0{i // 2}.{i % 2}\t0\t0\t{1 + i % 2}"
            "\t0\t0\t0\t5" for i in range(6)]
    p.write_text(head + "\n".join(rows) + "\n", encoding="gbk")
    assert detect_format(p) == "witmotion-pc"
    log = read_log(p, sensor=2)
    np.testing.assert_allclose(log.channel("az_mps2"), 2 * G)
    np.testing.assert_allclose(log.channel("time_s"), [0, 1, 2])
    assert log.channel("roll_rad")[0] == pytest.approx(5 * DEG)
    assert any("2 devices" in n for n in log.notes)
    with pytest.raises(LogFormatError, match="2 device"):
        read_log(p, sensor=3)


def test_pc_export_without_chip_time_uses_pc_clock(tmp_path):
    p = tmp_path / "pc.txt"
    p.write_text("time\tDeviceName\tChipTime\tAccZ(g)\n23:59:59.500\tA\t\t1\n00:00:00.250\tA\t\t1\n")
    log = read_log(p)
    np.testing.assert_allclose(log.channel("time_s"), [0, 0.75])
    assert any("PC clock" in n for n in log.notes) and any("midnight" in n for n in log.notes)


def test_write_errors(tmp_path):
    with pytest.raises(LogFormatError, match="unknown format 'sdk'"):
        write_log(synthetic(), tmp_path / "x", "sdk")
    with pytest.raises(LogFormatError, match="needs the 0x51 acceleration"):
        write_log(synthetic().drop(columns="ax_mps2"), tmp_path / "x", "wt901sd-binary")
    with pytest.raises(LogFormatError, match="strictly increasing"):
        write_log(synthetic().iloc[::-1], tmp_path / "x", "csv")
    with pytest.raises(LogFormatError, match="less than 1 ms apart"):
        write_log(synthetic(rate=5000.0), tmp_path / "x", "witmotion-pc")


def test_csv_mapping_units_and_midnight(tmp_path):
    p = tmp_path / "m.csv"
    p.write_text("clock,AccZ,gyro,temp\n23:59:59.9,1.0,90,20\n00:00:00.0,1.5,180,21\n00:00:00.25,2,0,22\n")
    log = read_log(p, columns={"time_s": "clock", "az_mps2": "AccZ", "wz_radps": "gyro"},
                   units={"az_mps2": "g", "wz_radps": "°/s"})
    np.testing.assert_allclose(log.channel("time_s"), [0, 0.1, 0.35])
    np.testing.assert_allclose(log.channel("az_mps2"), np.array([1, 1.5, 2]) * G)
    np.testing.assert_allclose(log.channel("wz_radps"), [np.pi / 2, np.pi, 0])
    assert list(log.channel("temp")) == [20, 21, 22]
    assert log.original_columns["az_mps2"] == "AccZ"
    assert any("midnight" in n for n in log.notes)
    q = tmp_path / "ms.csv"
    q.write_text("t;ax_mps2\n0;1\n5;2\n10;3\n")
    log = read_log(q, columns={"time_s": "t"}, units={"time_s": "ms"})
    np.testing.assert_allclose(log.channel("time_s"), [0, 0.005, 0.01])
    assert log.sample_rate_hz == pytest.approx(200)


def test_csv_without_time_uses_given_rate(tmp_path):
    p = tmp_path / "r.csv"
    p.write_text("ax_mps2,ay_mps2\n1,2\n3,4\n")
    log = read_log(p, sample_rate_hz=50)
    np.testing.assert_allclose(log.channel("time_s"), [0, 0.02])


def test_binary_damage_is_counted(tmp_path):
    src = synthetic(n=50)
    raw = bytearray(write_log(src, tmp_path / "b.bin", "wt901sd-binary").read_bytes())
    assert raw[1::11][:5] == bytes([0x50, 0x51, 0x52, 0x53, 0x50])  # 4 frames a sample
    raw[10 * 44 + 11 + 4] ^= 0xFF  # corrupt the 0x51 frame of sample 10: samples 9 and 10 lose their boundary
    (tmp_path / "c.bin").write_bytes(bytes(raw) + b"\x55\x51\x00")  # plus a partial frame
    log = read_log(tmp_path / "c.bin")
    assert len(log.data) == 48
    assert any("1 bad frame" in n for n in log.notes) and any("partial frame" in n for n in log.notes)
    assert any("dropped 1 incomplete" in n for n in log.notes)
    kept = src.set_index(np.round(src["time_s"], 3)).loc[np.round(log.channel("time_s"), 3)]
    np.testing.assert_allclose(log.channel("wz_radps"), kept["wz_radps"], atol=LSB["radps"])  # no mixing
    (tmp_path / "d.bin").write_bytes(bytes(b ^ 0x01 if i % 3 else b for i, b in enumerate(raw)))
    with pytest.raises(LogFormatError, match=r"d\.bin: byte \d+: .*more than 10 %"):
        read_log(tmp_path / "d.bin", "wt901sd-binary")
    (tmp_path / "e.bin").write_bytes(raw[:11 * 1 + 5])  # a 0x50 frame and half a 0x51
    with pytest.raises(LogFormatError, match="no complete sample"):
        read_log(tmp_path / "e.bin", "wt901sd-binary")


# -------------------------------------------------------------------------------------- bad input
def assert_error(excinfo, path: Path, line: int | None = None) -> str:
    text = str(excinfo.value)
    assert path.name in text and "\n" not in text
    if line is not None:
        assert f"{path.name}:{line}:" in text
    return text


def test_missing_and_empty_file(tmp_path):
    with pytest.raises(LogFormatError, match="not found") as e:
        read_log(tmp_path / "none.csv")
    assert_error(e, tmp_path / "none.csv")
    (tmp_path / "empty.csv").write_bytes(b"")
    with pytest.raises(LogFormatError, match="empty") as e:
        read_log(tmp_path / "empty.csv")


def test_truncated_file(tmp_path):
    p = write_log(synthetic(n=10), tmp_path / "cut.txt", "witmotion-sdk")
    p.write_bytes(p.read_bytes()[:-40])
    with pytest.raises(LogFormatError, match="truncated") as e:
        read_log(p)
    assert_error(e, p, 11)


def test_mis_encoded_file(tmp_path):
    p = write_log(synthetic(n=5), tmp_path / "bad.csv", "witmotion-2025")
    lines = p.read_bytes().split(b"\n")
    lines[3] = lines[3].replace(b",", b",\xff\xfe", 1)
    p.write_bytes(b"\n".join(lines))
    with pytest.raises(LogFormatError, match="invalid byte 0xFF") as e:
        read_log(p)
    assert_error(e, p, 4)
    with pytest.raises(LogFormatError, match=r"b\.TXT: byte \d+: binary data") as e:
        read_log(write_log(synthetic(n=5), tmp_path / "b.TXT", "wt901sd-binary"), format="csv")
    assert_error(e, tmp_path / "b.TXT")
    if SDK.is_file():  # GBK degree sign is not UTF-8: format 'csv' reads UTF-8 only
        with pytest.raises(LogFormatError, match="invalid byte 0xA1") as e:
            read_log(SDK, format="csv")
        assert_error(e, SDK, 1)


def test_missing_time_column(tmp_path):
    p = tmp_path / "notime.csv"
    p.write_text("ax_mps2,az_mps2\n1,2\n")
    with pytest.raises(LogFormatError, match="no time column; columns present: ax_mps2, az_mps2") as e:
        read_log(p)
    assert_error(e, p, 1)
    q = tmp_path / "notime.txt"
    q.write_text("ax(g)\tay(g)\taz(g)\n0\t0\t1\n")
    with pytest.raises(LogFormatError, match="columns present: ax.g., ay.g., az.g.") as e:
        read_log(q, "witmotion-sdk")
    assert_error(e, q, 1)


def test_non_monotonic_time(tmp_path):
    p = tmp_path / "back.csv"
    p.write_text("time_s,az_mps2\n0,9.8\n0.1,9.8\n0.1,9.8\n0.05,9.8\n")
    with pytest.raises(LogFormatError, match="time goes backwards") as e:
        read_log(p)
    assert_error(e, p, 5)
    q = tmp_path / "dup.csv"
    q.write_text("time_s,az_mps2\n0,9.8\n0.1,9.8\n0.1,9.7\n0.2,9.8\n")
    log = read_log(q)
    assert list(log.channel("az_mps2")) == [9.8, 9.8, 9.8] and "az_mps2" in log.notes[0]


@pytest.mark.parametrize("value", ["nan", "", "abc", "inf"])
def test_nan_or_text_value(tmp_path, value):
    p = tmp_path / "nan.csv"
    p.write_text(f"time_s,ax_mps2,az_mps2\n0,0,9.8\n0.1,0,{value}\n")
    with pytest.raises(LogFormatError, match="column 'az_mps2' holds") as e:
        read_log(p)
    assert_error(e, p, 3)


def test_unknown_format(tmp_path):
    p = tmp_path / "x.csv"
    p.write_text("time_s,az_mps2\n0,9.8\n")
    with pytest.raises(LogFormatError, match="unknown format 'witmotion'.*witmotion-sdk") as e:
        read_log(p, format="witmotion")
    assert_error(e, p)
    q = tmp_path / "words.txt"
    q.write_text("hello\nworld\n")
    with pytest.raises(LogFormatError, match="known formats: .*wt901sd-binary") as e:
        detect_format(q)
    assert_error(e, q)
    r = tmp_path / "noise.bin"
    r.write_bytes(bytes(range(256)))
    with pytest.raises(LogFormatError, match="not 0x55 WIT frames"):
        read_log(r)


def test_unknown_channel_and_column(tmp_path):
    p = tmp_path / "c.csv"
    p.write_text("t,AccZ\n0,1\n1,1\n")
    log = read_log(p, columns={"time_s": "t", "az_mps2": "AccZ"})
    with pytest.raises(LogFormatError, match=r"no channel 'az_mps'.*az_mps2.*did you mean 'az_mps2'") as e:
        log.channel("az_mps")
    assert_error(e, p)
    with pytest.raises(LogFormatError, match=r"'Acc_Z'.*did you mean 'AccZ'") as e:
        read_log(p, columns={"time_s": "t", "az_mps2": "Acc_Z"})
    assert_error(e, p, 1)
    with pytest.raises(LogFormatError, match="did you mean 'az_mps2'"):
        read_log(p, columns={"time_s": "t", "az_mps": "AccZ"})
    with pytest.raises(LogFormatError, match=r"units= \(--unit\) gives 'km' for 'az_mps2'.*one of m/s2, g"):
        read_log(p, columns={"time_s": "t", "az_mps2": "AccZ"}, units={"az_mps2": "km"})
