"""``trikedyn loading-chart``: the safe speed over freight mass and freight position (issue 12)."""

import csv
import json

import pytest

from trikedyn.cli import main
from trikedyn.params import load_vehicle
from trikedyn.study.designs.loading import run_loading_chart, safe_speed
from trikedyn.study.designs.sample_runs import Search

COARSE = ("--resolution", "1", "--high", "120")


def run(capsys, *args):
    code = main(list(args))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.fixture(scope="module")
def reference():
    return load_vehicle("reference-etrike")


def test_threshold_falls_with_freight_mass_and_height(reference):
    site = reference.params.freight
    masses, xs, zs = [0.0, 100.0, 200.0], [site.x_m], [site.z_m, site.z_m + 0.4]
    chart = run_loading_chart(reference, Search("dlc", {}, 1.0), masses, xs, zs, workers=0)
    assert chart.failed == 0
    t = chart.threshold
    for z in zs:  # more freight: lower or equal
        speeds = [t[(m, xs[0], z)] for m in masses]
        assert all(a >= b for a, b in zip(speeds, speeds[1:], strict=False)), speeds
    for m in masses:  # higher freight: lower or equal
        assert t[(m, xs[0], zs[0])] >= t[(m, xs[0], zs[1])]
    assert t[(200.0, xs[0], zs[1])] < t[(0.0, xs[0], zs[0])]  # and it does fall
    assert chart.safe((0.0, xs[0], zs[0])) == pytest.approx(t[(0.0, xs[0], zs[0])] - 5.0)


def test_margins_and_a_null_cell(reference):
    assert safe_speed(43.0) == 38.0 and safe_speed(3.0) == 0.0 and safe_speed(None) is None
    assert safe_speed(40.0, None, 0.25) == 30.0
    site = reference.params.freight
    chart = run_loading_chart(reference, Search("dlc", {}, 2.0), [50.0], [site.x_m], [site.z_m, 6.0],
                              margin_fraction=0.1, workers=0)
    cells = chart.to_dict()["cells"]
    bad = next(c for c in cells if c["freight_position_m"][1] == 6.0)
    assert bad["threshold_speed_kmh"] is None and bad["safe_speed_kmh"] is None
    assert "invalid vehicle" in bad["error"]
    good = next(c for c in cells if c["error"] is None)
    assert good["safe_speed_kmh"] == pytest.approx(0.9 * good["threshold_speed_kmh"])
    assert chart.to_dict()["margin_kmh"] is None and chart.to_dict()["margin_fraction"] == 0.1


def test_json_files_and_no_overwrite_without_force(capsys, reference, tmp_path):
    site = reference.params.freight
    x = f"{site.x_m - 0.2},{site.x_m + 0.2}"
    out = tmp_path / "chart"
    args = ("loading-chart", "reference-etrike", "--manoeuvre", "slc", *COARSE, "--masses", "0,200", "--x", x,
            "--z", str(site.z_m), "--workers", "2", "--out", str(out))
    code, stdout, err = run(capsys, *args, "--json")
    assert code == 0, err
    assert "loading-chart: 4/4 cells" in err  # the progress line
    data = json.loads(stdout)
    assert data["manoeuvre"] == "slc" and data["margin_kmh"] == 5.0 and len(data["cells"]) == 4
    for cell in data["cells"]:
        assert {"freight_kg", "freight_position_m", "threshold_speed_kmh", "safe_speed_kmh"} <= set(cell)
        assert len(cell["freight_position_m"]) == 2 and cell["error"] is None
        assert cell["safe_speed_kmh"] == pytest.approx(max(cell["threshold_speed_kmh"] - 5.0, 0.0))
    by = {(c["freight_kg"], c["freight_position_m"][0]): c["threshold_speed_kmh"] for c in data["cells"]}
    for xv in (site.x_m - 0.2, site.x_m + 0.2):
        assert by[(200.0, xv)] <= by[(0.0, xv)]
    assert json.loads((out / "loading-chart.json").read_text())["cells"] == data["cells"]
    rows = list(csv.reader((out / "loading-chart.csv").open()))
    assert rows[0][:5] == ["freight_kg", "x_m", "z_m", "threshold_speed_kmh", "safe_speed_kmh"] and len(rows) == 5
    assert (out / "loading-chart.png").read_bytes()[:4] == b"\x89PNG"
    code, stdout, err = run(capsys, *args)  # again: refused, nothing computed
    assert code == 2 and err.count("\n") == 1 and "--force" in err and stdout == ""
    code, stdout, err = run(capsys, *args, "--workers", "0", "--force", "--masses", "0")
    assert code == 0 and "freight height z" in stdout and "safe (threshold)" in stdout


@pytest.mark.parametrize("args, needle", [
    (("--masses", "0,heavy"), "--masses"),
    (("--masses", "-5"), "--masses"),
    (("--x", "nan"), "--x"),
    (("--margin-kmh", "5", "--margin-fraction", "0.1"), "not both"),
    (("--margin-kmh", "-1"), "--margin-kmh"),
    (("--manoeuvre", "no-such-manoeuvre"), "--manoeuvre"),
    (("--workers", "-1"), "--workers"),
])
def test_bad_input_is_one_line_and_exit_2(capsys, args, needle):
    code, stdout, err = run(capsys, "loading-chart", "reference-etrike", *args, "--json")
    assert code == 2 and err.startswith("trikedyn: error:") and err.count("\n") == 1 and needle in err
    assert "error" in json.loads(stdout)


def test_unknown_vehicle_exit_2(capsys):
    code, _, err = run(capsys, "loading-chart", "no-such-trike")
    assert code == 2 and "unknown vehicle" in err
