"""The IMU layout registry (trikedyn.measure.formats): a layout defined here is read by `log info`."""

import json

import numpy as np
import pytest

from trikedyn.cli import main
from trikedyn.errors import LogFormatError
from trikedyn.measure import formats
from trikedyn.measure.logs import FORMATS, detect_format, read_log, write_log


class PotholeLogger(formats.TableFormat):
    """A made-up logger: ``#POTHOLE-T[ms];Gz[g];Temp`` with time in ms and vertical acceleration in g."""

    name = "pothole-logger"
    description = "made-up test logger (#POTHOLE-T[ms];Gz[g])"
    sep = ";"
    columns = {"#POTHOLE-T[ms]": ("time_s", 1e-3), "Gz[g]": ("az_mps2", 9.80665)}


def write_pothole(path, n=50):
    rows = [f"{10 * i};{1.0 + 0.01 * np.sin(i):.6f};21.5" for i in range(n)]
    path.write_text("#POTHOLE-T[ms];Gz[g];Temp\n" + "\n".join(rows) + "\n")
    return path


def test_builtins_are_registered_in_their_order():
    assert formats.available() == ("witmotion-sdk", "witmotion-pc", "witmotion-2025", "wt901sd-binary",
                                   "bwt901cl-csv", "phyphox", "csv")
    assert tuple(FORMATS) == formats.available()
    assert FORMATS["csv"].startswith("generic CSV") and all(formats.get(n).writable for n in FORMATS)


def test_a_layout_registered_in_a_test_is_read_by_log_info(tmp_path, capsys):
    log = write_pothole(tmp_path / "ride.txt")
    assert detect_format(log) == "csv"  # unknown layout: the generic fallback
    with formats.registered(PotholeLogger):
        assert "pothole-logger" in FORMATS and detect_format(log) == "pothole-logger"
        assert main(["log", "info", str(log), "--json"]) == 0
        info = json.loads(capsys.readouterr().out)
        assert info["format"] == "pothole-logger" and info["samples"] == 50
        assert info["sample_rate_hz"] == pytest.approx(100.0)
        assert info["channels"]["az_mps2"]["original"] == "Gz[g]"
        assert info["channels"]["az_mps2"]["mean"] == pytest.approx(9.80665, rel=0.01)
        assert info["channels"]["Temp"]["mean"] == pytest.approx(21.5)
        assert main(["log", "info", str(log), "--format", "pothole-logger"]) == 0
        assert "pothole-logger, 50 samples" in capsys.readouterr().out
        with pytest.raises(LogFormatError, match="can be read but not written; writable formats: .*csv"):
            write_log(read_log(log).data, tmp_path / "out.txt", "pothole-logger")
        with pytest.raises(LogFormatError, match="apply to format 'phyphox' or 'csv' only, not 'pothole-logger'"):
            read_log(log, columns={"az_mps2": "Gz[g]"})
    assert "pothole-logger" not in FORMATS and detect_format(log) == "csv"
    with pytest.raises(LogFormatError, match="unknown format 'pothole-logger'"):
        read_log(log, "pothole-logger")


def test_register_refuses_duplicates_and_unregister_removes():
    with pytest.raises(ValueError, match="already registered"):
        formats.register(formats.get("csv"))
    fmt = formats.register(PotholeLogger())
    try:
        assert formats.get("pothole-logger") is fmt
    finally:
        assert formats.unregister("pothole-logger") is fmt
    with pytest.raises(LogFormatError, match="unknown format 'pothole-logger'"):
        formats.get("pothole-logger")


def test_detect_takes_bytes_or_text():
    assert formats.detect("time_s,az_mps2\n0,9.8\n") == "csv"
    assert formats.detect(b"Chiptime\tax(g)\n") == "witmotion-sdk"
    with pytest.raises(LogFormatError, match="cannot detect the format") as e:
        formats.detect("hello\n", "x.txt")
    assert e.value.where == "x.txt"
