"""``trikedyn sensitivity --metric NAME``: the sensitivity of any registered study metric, not only the threshold."""

from __future__ import annotations

import json
import subprocess
import sys


def _trikedyn(cwd, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "trikedyn", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=600)


def test_the_sensitivity_of_the_tilt_angle_ranks_track_and_cg_height(tmp_path):
    done = _trikedyn(tmp_path, "sensitivity", "reference-etrike", "--metric", "tilt_angle", "--samples", "2",
                     "-p", "track_m,cg_height_m", "--workers", "0", "--out", "out", "--json")
    assert done.returncode == 0, done.stderr[-2000:]
    data = json.loads(done.stdout)
    assert (data["metric"], data["unit"], data["n_runs"], data["failed"]) == ("tilt_angle", "deg", 6, 0)
    assert 10.0 < data["reference_value"] < 60.0  # the vehicle as given, in degrees
    mu = {row["parameter"]: row["mu_star"] for row in data["indices"]}
    assert set(mu) == {"track_m", "cg_height_m"} and min(mu.values()) > 1.0  # both move the tilt angle
    rows = (tmp_path / "out" / "sensitivity-samples.csv").read_text().splitlines()[1:]
    by_inputs = {tuple(map(float, row.split(",")[6:])): float(row.split(",")[3]) for row in rows}
    for (track, cg), angle in by_inputs.items():  # a wider track tilts further, a higher CG less far
        wider = [a for (t, c), a in by_inputs.items() if c == cg and t > track]
        higher = [a for (t, c), a in by_inputs.items() if t == track and c > cg]
        assert all(a > angle for a in wider) and all(a < angle for a in higher)
    plan = json.loads((tmp_path / "out" / "sensitivity-plan.json").read_text())
    assert plan["metric"] == "tilt_angle"  # a resumed run must measure the same


def test_an_unknown_metric_or_a_missing_option_is_one_line(tmp_path):
    for args, says in ((["--metric", "tilt_angel"], "unknown metric"),
                       (["--metric", "peak_ri"], "needs the option 'speed_kmh'"),
                       (["--metric", "peak_ri", "--metric-option", "speed"], "expected KEY=VALUE")):
        done = _trikedyn(tmp_path, "sensitivity", "reference-etrike", *args, "--workers", "0")
        lines = done.stderr.strip().splitlines()
        assert done.returncode == 2 and len(lines) == 1 and says in lines[0], (args, done.stderr)


def test_the_sensitivity_of_the_understeer_gradient_ranks_the_cg_fore_aft_first(tmp_path):
    """The understeer gradient is first the axle loads over the axles' cornering stiffnesses (K = W_f/C_f -
    W_r/C_r): the CG's fore-aft place sets the front/rear split of the load and moves K at first order. The CG's
    height and the track act only through the lateral load transfer on the rear pair, which lowers that pair's
    cornering stiffness through the tyres' load sensitivity: a second-order effect, towards oversteer for a
    higher CG or a narrower track."""
    done = _trikedyn(tmp_path, "sensitivity", "reference-etrike", "--metric", "understeer_gradient", "--samples", "2",
                     "-p", "mass.cg_x_m,cg_height_m,track_m", "--workers", "0", "--out", "out", "--json")
    assert done.returncode == 0, done.stderr[-2000:]
    data = json.loads(done.stdout)
    assert (data["metric"], data["unit"], data["n_runs"], data["failed"]) == ("understeer_gradient", "deg/g", 8, 0)
    assert 0.0 < data["reference_value"] < 3.0  # the vehicle as given understeers, in deg/g
    mu = {row["parameter"]: row["mu_star"] for row in data["indices"]}
    assert max(mu, key=mu.get) == "mass.cg_x_m" and mu["mass.cg_x_m"] > 3 * max(mu["cg_height_m"], mu["track_m"]), mu
    header, *rows = (tmp_path / "out" / "sensitivity-samples.csv").read_text().splitlines()
    names = header.split(",")[6:]
    rows.sort(key=lambda row: int(row.split(",", 1)[0]))  # in sample order: a trajectory's steps in turn
    steps = [(tuple(map(float, row.split(",")[6:])), float(row.split(",")[3]), row.split(",")[1]) for row in rows]
    rising = {"mass.cg_x_m": +1, "cg_height_m": -1, "track_m": +1}  # the sign of dK/dfactor (see above)
    seen = set()
    for (a, ka, ga), (b, kb, gb) in zip(steps, steps[1:], strict=False):  # a Morris trajectory moves one factor
        moved = [i for i in range(len(names)) if a[i] != b[i]]
        if ga != gb or len(moved) != 1:
            continue
        name = names[moved[0]]
        seen.add(name)
        assert (kb - ka) * (b[moved[0]] - a[moved[0]]) * rising[name] > 0, (name, a, ka, b, kb)
    assert seen == set(names)  # each factor's step judged
