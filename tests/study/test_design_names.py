"""A design's figures say what they are (issue 23): with ``--metric tilt_angle`` no ``_kmh`` key or column of
``sensitivity``, ``uncertainty``, ``loading-chart`` or ``optimise`` holds the angle, the JSON names the metric
and its unit beside neutral keys (``reference_value``, ``median``, ``value`` ...), the CSV headers name the
metric, and the text output gives the unit ``deg`` and no threshold-only line; with the threshold every name
is as before (:mod:`trikedyn.study.designs.named`)."""

from __future__ import annotations

import csv
import json
import subprocess
import sys

import pytest

SEARCH_SETTINGS = {"resolution_kmh", "high_kmh"}  # speeds of the (unused) search, as given
NULL_WITHOUT_THRESHOLD = {"margin_kmh", "safe_speed_kmh"}  # no safe speed for another metric


def _trikedyn(cwd, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "trikedyn", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=600)


def _kmh_keys(data, path=""):
    """Every ``(path, value)`` whose key ends in ``_kmh``, at any depth."""
    if isinstance(data, dict):
        for key, value in data.items():
            if str(key).endswith("_kmh"):
                yield f"{path}.{key}", value
            yield from _kmh_keys(value, f"{path}.{key}")
    elif isinstance(data, list):
        for i, value in enumerate(data):
            yield from _kmh_keys(value, f"{path}[{i}]")


DESIGNS = {
    "sensitivity": (["sensitivity", "reference-etrike", "--samples", "2", "-p", "track_m,cg_height_m"],
                    "sensitivity.json", ["sensitivity-samples.csv"], ["reference_value"]),
    "uncertainty": (["uncertainty", "reference-etrike", "--samples", "3", "-p", "track_m,cg_height_m"],
                    "uncertainty.json", ["uncertainty-samples.csv"],
                    ["reference_value", "median", "p05", "p95", "mean", "std"]),
    "loading-chart": (["loading-chart", "reference-etrike", "--masses", "0,150", "--x", "0.3", "--z", "0.4"],
                      "loading-chart.json", ["loading-chart.csv", "loading-chart-cells.csv"], []),
    "optimise": (["optimise", "reference-etrike", "--spec", "battery-layout", "--maxiter", "1", "--popsize", "1"],
                 "optimise.json", ["optimise-evaluations.csv"], ["reference_value", "best_value", "gain"]),
}


@pytest.mark.parametrize("design", list(DESIGNS))
def test_a_tilt_angle_is_named_as_one(tmp_path, design):
    args, json_file, csv_files, neutral = DESIGNS[design]
    done = _trikedyn(tmp_path, *args, "--metric", "tilt_angle", "--workers", "0", "--out", "out")
    assert done.returncode == 0, done.stderr[-2000:]
    data = json.loads((tmp_path / "out" / json_file).read_text())
    assert (data["metric"], data["unit"]) == ("tilt_angle", "deg")
    for key in neutral:
        assert isinstance(data[key], float), (key, data.get(key))
    assert 15.0 < data.get("reference_value", 35.0) < 60.0  # degrees
    kmh = dict(_kmh_keys(data))
    assert {path.rsplit(".", 1)[1] for path in kmh} <= SEARCH_SETTINGS | NULL_WITHOUT_THRESHOLD, sorted(kmh)
    assert all(v is None for p, v in kmh.items() if p.rsplit(".", 1)[1] in NULL_WITHOUT_THRESHOLD)
    values = ([row["value"] for row in data["samples"]] if design == "uncertainty" else
              [cell["value"] for cell in data["cells"]] if design == "loading-chart" else
              list(data["values"]["dlc"].values()) if design == "optimise" else [])
    assert all(15.0 < v < 60.0 for v in values)
    for name in csv_files:
        with (tmp_path / "out" / name).open() as fh:
            header = next(csv.reader(fh))
        assert [c for c in header if c.endswith("_kmh")] == (["safe_speed_kmh"] if name == "loading-chart.csv"
                                                              else [])
        assert any(c == "tilt_angle" or c.startswith("worst_tilt_angle") for c in header), header
    text = done.stdout
    assert " deg" in text and "km/h" not in text, text
    assert "criterion" not in text and "speed control" not in text and "course:" not in text, text
    if design == "optimise":
        assert "check:" not in text and data["check"] == []  # `trikedyn threshold` would not give the angle


def test_with_the_threshold_the_names_are_as_before():
    from trikedyn.study.designs.csv_log import SampleLog
    from trikedyn.study.designs.loading_grid import CellLog
    from trikedyn.study.designs.named import JSON_NAMES, by_metric, column
    from trikedyn.study.designs.optimise_log import EvaluationLog

    data = {"reference_threshold_speed_kmh": 40.0, "samples": [{"threshold_speed_kmh": 39.0, "track_m": 1.1}]}
    assert by_metric(data, "threshold") is data
    assert by_metric(data, "peak_ri") == {"reference_value": 40.0, "samples": [{"value": 39.0, "track_m": 1.1}]}
    assert not [k for k in JSON_NAMES.values() if k.endswith("_kmh")]
    assert SampleLog("x.csv", [], 1).columns == ["sample", "group", "status", "threshold_speed_kmh", "limit", "error"]
    assert SampleLog("x.csv", [], 1, "peak_ri").columns[3] == "peak_ri"
    assert CellLog("x.csv").columns == ["cell", "freight_kg", "status", "threshold_speed_kmh", "x_m", "z_m", "error"]
    assert EvaluationLog("x.csv", ["k"], ["dlc", "slc"]).columns == [
        "evaluation", "generation", "status", "worst_threshold_speed_kmh", "threshold_dlc_kmh", "threshold_slc_kmh",
        "error", "k"]
    assert EvaluationLog("x.csv", ["k"], ["dlc", "slc"], "peak_ri").columns == [
        "evaluation", "generation", "status", "worst_peak_ri", "peak_ri_dlc", "peak_ri_slc", "error", "k"]
    assert column("threshold_speed_kmh", "threshold") == "threshold_speed_kmh"


@pytest.mark.slow
def test_a_log_of_the_earlier_names_is_not_resumed_as_this_metrics(tmp_path):
    """A run of another metric written before these names (its log says ``threshold_speed_kmh``) is refused in
    one line naming the file and the way out, not read as this run's."""
    args = ["uncertainty", "reference-etrike", "--samples", "2", "-p", "track_m", "--metric", "tilt_angle",
            "--workers", "0", "--out", "out"]
    assert _trikedyn(tmp_path, *args).returncode == 0
    log = tmp_path / "out" / "uncertainty-samples.csv"
    head, rest = log.read_text().split("\n", 1)
    assert head.split(",")[3] == "tilt_angle"
    log.write_text(head.replace("tilt_angle", "threshold_speed_kmh") + "\n" + rest)
    again = _trikedyn(tmp_path, *args, "--resume")
    assert again.returncode == 2 and again.stderr.strip().splitlines() == [
        f"trikedyn: error: {log.relative_to(tmp_path)}: was written by an earlier trikedyn, which named a metric's "
        "value as a threshold speed (threshold_speed_kmh); it cannot be resumed: use --force (start again) or "
        "another --out"]
    resumed = _trikedyn(tmp_path, *args[:-2], "--out", "fresh")
    assert resumed.returncode == 0 and _trikedyn(tmp_path, *args[:-2], "--out", "fresh", "--resume").returncode == 0
