"""``--metric NAME`` on ``uncertainty``, ``loading-chart`` and ``optimise``: each design measures any registered study
metric, not only the threshold (the tilt angle here: a quasi-static metric, so the runs are small); an unknown metric
is one line and exit code 2 (``sensitivity``'s are in test_sensitivity_metric.py)."""

from __future__ import annotations

import csv
import json
import subprocess
import sys

import pytest


def _trikedyn(cwd, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "trikedyn", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=600)


@pytest.fixture(scope="module")
def tilt_as_given() -> float:
    """The reference vehicle's tilt angle [deg], from the metric itself (in this process)."""
    from trikedyn.params import load_vehicle
    from trikedyn.study.metrics import get

    return get("tilt_angle").fn(load_vehicle("reference-etrike"), {})["value"]


def test_uncertainty_of_the_tilt_angle(tmp_path, tilt_as_given):
    done = _trikedyn(tmp_path, "uncertainty", "reference-etrike", "--metric", "tilt_angle", "--samples", "4",
                     "-p", "track_m,cg_height_m", "--workers", "0", "--out", "out", "--json")
    assert done.returncode == 0, done.stderr[-2000:]
    data = json.loads(done.stdout)
    assert (data["metric"], data["unit"], data["n"], data["failed"]) == ("tilt_angle", "deg", 4, 0)
    assert data["reference_value"] == pytest.approx(tilt_as_given, abs=1e-9)
    angles = [row["value"] for row in data["samples"]]
    assert all(15.0 < a < 60.0 for a in angles) and len(set(angles)) == 4  # degrees, each sample its own
    assert min(angles) <= data["p05"] <= data["median"] <= data["p95"] <= max(angles)
    # the narrowest track with the highest CG tilts least: the sample lowest in track/CG height
    ratio = [row["track_m"] / row["cg_height_m"] for row in data["samples"]]
    assert angles.index(min(angles)) == ratio.index(min(ratio))
    assert json.loads((tmp_path / "out" / "uncertainty-plan.json").read_text())["metric"] == "tilt_angle"
    again = _trikedyn(tmp_path, "uncertainty", "reference-etrike", "--samples", "4", "-p", "track_m,cg_height_m",
                      "--workers", "0", "--out", "out", "--resume")  # the threshold: not the run in out/
    assert again.returncode == 2 and len(again.stderr.strip().splitlines()) == 1, again.stderr


def test_loading_chart_of_the_tilt_angle_has_no_safe_speed(tmp_path, tilt_as_given):
    done = _trikedyn(tmp_path, "loading-chart", "reference-etrike", "--metric", "tilt_angle", "--masses", "0,150",
                     "--x", "0.3", "--z", "0.4,1.2", "--workers", "0", "--out", "out", "--json")
    assert done.returncode == 0, done.stderr[-2000:]
    data = json.loads(done.stdout)
    assert (data["metric"], data["unit"], data["margin_kmh"], data["margin_fraction"]) == ("tilt_angle", "deg", None, None)
    cells = {(c["freight_kg"], c["freight_position_m"][1]): c for c in data["cells"]}
    assert all(c["safe_speed_kmh"] is None and c["error"] is None for c in cells.values())
    assert cells[(0.0, 0.4)]["value"] == pytest.approx(tilt_as_given, abs=1e-9)  # no freight
    assert cells[(0.0, 1.2)]["value"] == pytest.approx(tilt_as_given, abs=1e-9)
    assert cells[(150.0, 1.2)]["value"] < cells[(150.0, 0.4)]["value"]  # freight up high
    with (tmp_path / "out" / "loading-chart.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 4 and all(r["safe_speed_kmh"] == "" for r in rows)
    margin = _trikedyn(tmp_path, "loading-chart", "reference-etrike", "--metric", "tilt_angle", "--margin-kmh", "3",
                       "--workers", "0")
    assert margin.returncode == 2 and margin.stderr.strip().splitlines() == [
        "trikedyn: error: --margin-kmh: a margin applies to the threshold only: a chart of another metric has no "
        "safe speed"]


@pytest.mark.parametrize("minimise", [False, True])
def test_optimise_the_tilt_angle_either_way(tmp_path, tilt_as_given, minimise):
    done = _trikedyn(tmp_path, "optimise", "reference-etrike", "--spec", "battery-layout", "--metric", "tilt_angle",
                     *(["--minimise"] if minimise else []), "--maxiter", "1", "--popsize", "1", "--workers", "0",
                     "--out", "out", "--json")
    assert done.returncode == 0, done.stderr[-2000:]
    data = json.loads(done.stdout)
    assert (data["metric"], data["unit"], data["minimise"]) == ("tilt_angle", "deg", minimise)
    assert data["objective"] == f"tilt angle, {'minimised' if minimise else 'maximised'}"
    ref, best = data["reference_value"], data["best_value"]
    assert ref == pytest.approx(tilt_as_given, abs=1e-9)
    assert (best < ref - 0.1) if minimise else (best > ref + 0.1)  # the battery moved lowers / raises it
    assert data["vehicle_file_verified"] and data["vehicle_file_values"]["dlc"] == best
    with (tmp_path / "out" / "optimise-evaluations.csv").open() as fh:
        values = [float(r["worst_tilt_angle"]) for r in csv.DictReader(fh)]
    assert best == (min(values) if minimise else max(values))
    assert json.loads((tmp_path / "out" / "optimise-plan.json").read_text()).get("minimise", False) == minimise


@pytest.mark.parametrize("command", [["uncertainty"], ["loading-chart"], ["optimise", "--spec", "battery-layout"]])
def test_an_unknown_metric_is_one_line(tmp_path, command):
    done = _trikedyn(tmp_path, command[0], "reference-etrike", *command[1:], "--metric", "tilt_angel",
                     "--workers", "0", "--out", "out")
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().splitlines() == [
        "trikedyn: error: --metric: unknown metric 'tilt_angel'; did you mean 'tilt_angle'?"]
    assert not (tmp_path / "out").exists()  # refused before anything is written


def test_the_threshold_is_not_minimised(tmp_path):
    done = _trikedyn(tmp_path, "optimise", "reference-etrike", "--spec", "battery-layout", "--minimise",
                     "--workers", "0", "--out", "out")
    assert done.returncode == 2 and done.stderr.strip().splitlines() == [
        "trikedyn: error: --minimise: the threshold velocity is maximised; --minimise needs another --metric"]


def test_a_sampled_metric_runs_the_manoeuvre_with_its_options():
    """``-o`` reaches a metric that runs the manoeuvre (peak_ri), as a spec's manoeuvre options do in a study:
    a single lane change of 1 m rolls the trike less than one of 3.5 m (the default)."""
    from trikedyn.params import load_vehicle
    from trikedyn.study.designs.search import Search

    pset = load_vehicle("reference-etrike")
    default, _, _ = Search("slc", {}, metric="peak_ri", metric_options={"speed_kmh": 30}).outcome(pset)
    short, _, _ = Search("slc", {"lateral_offset_m": 1.0}, metric="peak_ri",
                         metric_options={"speed_kmh": 30}).outcome(pset)
    assert 0.0 < short < default - 0.02
