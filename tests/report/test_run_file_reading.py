"""Run files read back once, checked where they are read (issue 21, "Run files"): every reader -- ``plot`` (each
kind), ``animate`` (each view), ``compare``, the report's figures -- gets a table of numbers with a finite,
increasing time and metadata of the right types, or one line ``trikedyn: error: WHERE: WHAT`` with exit code 2,
no warning before it, within 60 s, the input files unchanged."""

from __future__ import annotations

import hashlib
import json
import math
import time

import numpy as np
import pandas as pd
import pytest

from trikedyn.analysis.compare import load_table
from trikedyn.cli import main
from trikedyn.errors import InputError
from trikedyn.report.run_figures import figure
from trikedyn.report.scene import MAX_FRAMES, check_frames
from trikedyn.simulate.runfile import (
    MAX_RUN_S,
    MAX_SIDECAR_BYTES,
    check_meta,
    check_run_table,
    read_run,
    run_course,
    run_vehicle,
)

from ..conftest import strict_json

LIMIT_S = 60.0


@pytest.fixture(scope="module")
def seed(tmp_path_factory):
    """A double lane change at 30 km/h (one row in 20 kept: 99 rows, 19.6 s) and its sidecar."""
    folder = tmp_path_factory.mktemp("run_reading")
    full = folder / "full.parquet"
    assert main(["simulate", "reference-etrike", "--manoeuvre", "dlc", "--speed", "30", "--out", str(full)]) == 0
    frame = pd.read_parquet(full).iloc[::20].reset_index(drop=True)
    frame.attrs = {}
    return frame, json.loads(full.with_suffix(".json").read_text(encoding="utf-8"))


def _write(folder, frame, sidecar, name="run.csv"):
    path = folder / name
    if path.suffix == ".csv":
        frame.to_csv(path, index=False)
    else:  # a column of numbers and text is stored as text
        frame.astype({c: str for c in frame.columns if frame[c].dtype == object}).to_parquet(path, index=False)
    if sidecar is not None:
        text = sidecar if isinstance(sidecar, str) else json.dumps(sidecar)
        path.with_suffix(".json").write_text(text, encoding="utf-8")
    return path


def _hashes(folder):
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir()) if p.is_file()}


def _cli(capsys, *args):
    start = time.perf_counter()
    code = main([str(a) for a in args])
    took = time.perf_counter() - start
    captured = capsys.readouterr()
    assert took < LIMIT_S, f"{args}: {took:.0f} s"
    return code, captured.out, captured.err


def _refused(capsys, folder, args, needle):
    """The command exits 2 with the one line holding ``needle``, writes nothing and changes no input byte."""
    before = _hashes(folder)
    code, out, err = _cli(capsys, *args, "--json")
    assert code == 2, err
    assert err.startswith("trikedyn: error: ") and err.count("\n") == 1, err
    assert needle in err, err
    assert strict_json(out)["error"]
    assert _hashes(folder) == before
    return err


# ------------------------------------------------------------------------------------------------------------
# the cases, through the command line
# ------------------------------------------------------------------------------------------------------------
def test_animate_a_run_with_a_channel_that_is_not_numbers(capsys, seed, tmp_path):
    frame, side = seed
    bad = frame.astype({"x_m": object})
    bad.loc[5, "x_m"] = "abc"
    run = _write(tmp_path, bad, side)
    _refused(capsys, tmp_path, ["animate", run, "--out", tmp_path / "a.gif"], "column 'x_m': row 5 is 'abc', not a number")


def test_plot_with_a_target_speed_that_is_a_list(capsys, seed, tmp_path):
    frame, side = seed
    run = _write(tmp_path, frame, side | {"target_speed_kmh": [30, 40]})
    for kind in ("time", "plan"):
        _refused(capsys, tmp_path, ["plot", run, "--kind", kind, "--out", tmp_path / "f.png"],
                 "run.json: target_speed_kmh: expected a number [km/h] or null, got a list")


@pytest.mark.parametrize("kind", ["roll", "time", "gg"])
def test_plot_when_the_lateral_acceleration_is_text(capsys, seed, tmp_path, kind):
    frame, side = seed
    bad = frame.astype({"ay_mps2": object})
    bad.loc[3, "ay_mps2"] = "hello"
    for name in ("run.csv", "run.parquet"):
        run = _write(tmp_path, bad, side, name)
        _refused(capsys, tmp_path, ["plot", run, "--kind", kind, "--out", tmp_path / "f.png"],
                 "column 'ay_mps2': row 3 is 'hello', not a number")


def test_animate_a_one_row_run_says_one_line(capsys, seed, tmp_path):
    frame, side = seed
    run = _write(tmp_path, frame.iloc[:1], side | {"manoeuvre_name": "no-such-manoeuvre"})  # would warn
    _refused(capsys, tmp_path, ["animate", run, "--out", tmp_path / "a.gif"], "1 row(s); a run has at least 2 samples")


def test_animate_a_run_stretched_a_million_fold_is_refused_at_once(capsys, seed, tmp_path):
    frame, side = seed
    run = _write(tmp_path, frame.assign(time_s=frame.time_s * 1e6), side)
    start = time.perf_counter()
    err = _refused(capsys, tmp_path, ["animate", run, "--out", tmp_path / "a.gif"],
                   f"more than the longest run ({MAX_RUN_S:g} s)")
    assert "1.96e+07 s" in err and time.perf_counter() - start < 10.0
    _refused(capsys, tmp_path, ["plot", run, "--kind", "plan", "--out", tmp_path / "f.png"], "longest run")


def test_too_many_frames_are_counted_and_refused_before_any_is_drawn(capsys, seed, tmp_path):
    frame, side = seed
    run = _write(tmp_path, frame.assign(time_s=frame.time_s * 100.0), side)  # 1960 s: a run of half an hour
    start = time.perf_counter()
    err = _refused(capsys, tmp_path, ["animate", run, "--out", tmp_path / "a.gif"],
                   f"is 19601 frames, more than the {MAX_FRAMES} drawn; take a time between frames of at least 0.981 s")
    assert "every_s" in err and time.perf_counter() - start < 10.0
    with pytest.raises(InputError, match="more than the 2000 drawn"):
        check_frames([0.0, 3600.0], 0.1)
    assert check_frames([0.0, 10.0], 0.1) == 101


def test_a_sidecar_that_cannot_be_read_is_one_line(capsys, seed, tmp_path):
    frame, side = seed
    run = _write(tmp_path, frame, "{not json")
    _refused(capsys, tmp_path, ["plot", run, "--out", tmp_path / "f.png"],
             "run.json: not JSON (Expecting property name enclosed in double quotes at line 1 column 2); move it away")
    run.with_suffix(".json").write_text("[1, 2]", encoding="utf-8")
    _refused(capsys, tmp_path, ["animate", run, "--out", tmp_path / "a.gif"], "holds a JSON list; expected the run's")
    run.with_suffix(".json").write_text('{"dt_s": NaN}', encoding="utf-8")
    _refused(capsys, tmp_path, ["plot", run, "--out", tmp_path / "f.png"], "NaN is not a JSON number")
    run.with_suffix(".json").write_text("[" * 100_000, encoding="utf-8")
    _refused(capsys, tmp_path, ["plot", run, "--out", tmp_path / "f.png"], "run.json: not")
    with open(run.with_suffix(".json"), "wb") as fh:
        fh.truncate(MAX_SIDECAR_BYTES + 1)  # sparse
    _refused(capsys, tmp_path, ["plot", run, "--out", tmp_path / "f.png"], "larger than 16 MiB")


@pytest.mark.parametrize(("change", "needle"), [
    ({"wheels": "front"}, "run.json: wheels: expected a list of 1 to 8 distinct wheel names, got a text"),
    ({"footprint_m": [2.0, 1.0, 0.5]}, "run.json: footprint_m: expected [x_rear, x_front, half_width]"),
    ({"vehicle": {"name": "x"}}, "run.json: vehicle: expected a text or null, got an object"),
    ({"vehicle": "v" * 300}, "run.json: vehicle: a text of 300 characters, more than 200"),
    ({"target_speed_kmh": 1e308}, "run.json: target_speed_kmh: got 1e+308, expected 0 to 400 km/h"),
    ({"target_speed_kmh": True}, "run.json: target_speed_kmh: expected a number [km/h] or null, got true"),
    ({"summary": {"payload_kg": "lots"}}, "run.json: summary.payload_kg: expected a number [kg] or null"),
    ({"manoeuvre_spec": {"parameters": [1]}}, "run.json: manoeuvre_spec.parameters: expected an object or null"),
    ({"vehicle_params": "reference-etrike"}, "run.json: vehicle_params: expected an object or null, got a text"),
])
def test_each_field_of_the_sidecar_is_checked(capsys, seed, tmp_path, change, needle):
    frame, side = seed
    run = _write(tmp_path, frame, side | change)
    _refused(capsys, tmp_path, ["plot", run, "--out", tmp_path / "f.png"], needle)


@pytest.mark.parametrize(("edit", "needle"), [
    (lambda f: f.assign(time_s=f.time_s.where(f.index != 4, np.nan)), "'time_s': time is not finite at row 4"),
    (lambda f: f.assign(time_s=f.time_s[::-1].to_numpy()), "'time_s': time does not increase at row 1"),
    (lambda f: f.assign(ri=f.ri.where(f.index != 7, np.inf)), "column 'ri': row 7 is inf, beyond +-1e+12"),
    (lambda f: f.assign(x_m=f.x_m.where(f.index != 2, 1e300)), "column 'x_m': row 2 is 1e+300"),
    (lambda f: f.drop(columns="time_s"), "no 'time_s' column"),
    (lambda f: f.assign(time_s=np.append(f.time_s.to_numpy()[:-1], 1e9)), "a gap of 1e+09 s at row 98"),
    (lambda f: f.assign(**{f"w{k}_fz_N": 1.0 for k in range(9)}), "12 wheel loads"),
])
def test_the_table_is_checked_for_every_reader(capsys, seed, tmp_path, edit, needle):
    frame, side = seed
    run = _write(tmp_path, edit(frame), side, "run.parquet")
    _refused(capsys, tmp_path, ["plot", run, "--out", tmp_path / "f.png"], needle)
    _refused(capsys, tmp_path, ["animate", run, "--out", tmp_path / "a.gif"], needle)
    _refused(capsys, tmp_path, ["compare", run, run], needle)


def test_parquet_metadata_of_the_wrong_type_names_the_file(capsys, seed, tmp_path):
    frame, side = seed
    frame = frame.copy()
    frame.attrs = {"target_speed_kmh": "fast"}
    run = _write(tmp_path, frame, side, "run.parquet")
    _refused(capsys, tmp_path, ["plot", run, "--out", tmp_path / "f.png"],
             "run.parquet (its own metadata): target_speed_kmh: expected a number [km/h] or null, got a text")


# ------------------------------------------------------------------------------------------------------------
# what reads well
# ------------------------------------------------------------------------------------------------------------
def test_nan_where_a_value_is_undefined_is_kept_and_the_run_draws(capsys, seed, tmp_path):
    frame, side = seed
    run = _write(tmp_path, frame.assign(ri=frame.ri.where(frame.index % 5 != 0, np.nan)), side)
    for args in (["plot", run, "--kind", "time"], ["plot", run, "--kind", "roll"],
                 ["animate", run, "--every-s", "5", "--out", tmp_path / "a.gif"]):
        code, out, err = _cli(capsys, *args, "--force", "--json")
        assert code == 0 and err == "", err
        strict_json(out)


def test_names_with_dollars_and_odd_wheel_names_draw(capsys, seed, tmp_path):
    frame, side = seed
    odd = frame.rename(columns={"front_fz_N": "a__b_fz_N"})
    run = _write(tmp_path, odd, {k: v for k, v in side.items() if k not in ("wheels", "vehicle_params")}
                 | {"vehicle": "trike $5 $\\frac"})
    for args in (["plot", run, "--kind", "wheel-loads"], ["plot", run, "--kind", "time"],
                 ["animate", run, "--every-s", "5", "--view", "rear", "--out", tmp_path / "a.gif"],
                 ["animate", run, "--every-s", "5", "--view", "3d", "--out", tmp_path / "b.gif"]):
        code, out, err = _cli(capsys, *args, "--force", "--json")
        assert code == 0, err
        assert all(line.startswith("trikedyn: warning: ") for line in err.splitlines()), err


def test_a_recorded_vehicle_without_the_runs_wheels_gives_way_to_a_stand_in(seed):
    frame, side = seed
    meta = check_meta(side)
    with pytest.warns(UserWarning, match="its wheels .* are not the run's"):
        params, note = run_vehicle(meta, ["front_left", "front_right", "rear"])
    assert params.name == "stand-in" and "stand-in" in note
    params, note = run_vehicle(meta, ["front", "rear_left", "rear_right"])
    assert note == "the vehicle recorded with the run ('reference-etrike')"


def test_read_run_gives_floats_and_checked_metadata(seed, tmp_path):
    frame, side = seed
    run = read_run(_write(tmp_path, frame.assign(judged=frame.judged > 0.5), side, "run.parquet"))
    assert run.kind == "run-parquet" and list(run.table.columns) == list(frame.columns)
    assert all(dtype == np.float64 for dtype in run.table.dtypes)
    assert run.meta["vehicle"] == "reference-etrike" and run.meta["read_from"] == str(run.path)
    with pytest.raises(InputError, match=r"expected a run file \(.parquet or .csv\)"):
        read_run(tmp_path / "run.json")
    with pytest.raises(InputError, match="run: column 'a' holds datetime64"):
        check_run_table(pd.DataFrame({"time_s": [0.0, 1.0], "a": pd.to_datetime(["2024-01-01", "2024-01-02"])}))
    with pytest.raises(InputError, match="column 'a' appears twice"):
        check_run_table(pd.DataFrame([[0.0, 1.0, 2.0], [1.0, 1.0, 2.0]], columns=["time_s", "a", "a"]))
    table = check_run_table(pd.DataFrame({"a": [1, 2]}, index=pd.Index([0.0, 0.5], name="time_s")), as_run=False)
    assert list(table.columns) == ["time_s", "a"] and table.a.dtype == np.float64


def test_the_report_figures_check_a_table_given_in_python(seed):
    frame, side = seed
    bad = frame.astype({"ay_mps2": object})
    bad.loc[0, "ay_mps2"] = "x"
    with pytest.raises(InputError, match="run: column 'ay_mps2': row 0 is 'x', not a number"):
        figure("gg", bad, side)
    with pytest.raises(InputError, match="meta: target_speed_kmh"):
        figure("time", frame, side | {"target_speed_kmh": "fast"})
    with pytest.raises(InputError, match="the channels are not one table"):
        figure("time", {"time_s": [0.0, 1.0], "ay_mps2": [1.0, 2.0, 3.0]})
    fig = figure("gg", {"time_s": [0.0, 1.0, 2.0], "ax_mps2": [0.0, 1.0, 0.5], "ay_mps2": [1.0, 2.0, 3.0]})
    assert "g-g" in fig.get_suptitle()
    with pytest.raises(InputError, match="no sample with both accelerations"):
        figure("gg", {"time_s": [0.0, 1.0], "ax_mps2": [math.nan, 1.0], "ay_mps2": [1.0, math.nan]})


def test_compare_reads_a_log_csv_with_clock_times_as_a_log(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("time_s,ay_mps2\n" + "".join(f"12:00:{i:02d}.0,{0.1 * i}\n" for i in range(30)),
                    encoding="utf-8")
    table, kind = load_table(path)
    assert kind == "csv" and table.time_s.iloc[-1] - table.time_s.iloc[0] == pytest.approx(29.0)


# ------------------------------------------------------------------------------------------------------------
# the course of a path CSV: a file named in a file
# ------------------------------------------------------------------------------------------------------------
def test_a_path_csv_is_recorded_beside_the_run_and_read_from_its_folder_only(capsys, tmp_path, monkeypatch):
    folder = tmp_path / "runs"
    folder.mkdir()
    line = folder / "line.csv"
    line.write_text("x_m,y_m\n" + "".join(f"{2.0 * i:.1f},{1.5 * min(i / 15, 1):.3f}\n" for i in range(31)),
                    encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    code, _, err = _cli(capsys, "simulate", "reference-etrike", "--manoeuvre", "runs/line.csv", "--speed", "15",
                        "--out", "runs/run.csv")
    assert code == 0, err
    side = json.loads((folder / "run.json").read_text(encoding="utf-8"))
    assert side["manoeuvre_spec"]["parameters"]["file"] == "line.csv"  # relative to the run's folder
    run = read_run(folder / "run.csv")
    params, _ = run_vehicle(run.meta, run.meta["wheels"])
    manoeuvre, note = run_course(run.meta, params)
    assert manoeuvre is not None and note.startswith("'path' rebuilt"), note
    for name, why in (("../line.csv", "a path with '..'"), (str(line), "an absolute path"),
                      ("/dev/zero", "an absolute path")):
        meta = run.meta | {"manoeuvre_spec": side["manoeuvre_spec"] | {"parameters": {"file": name}}}
        manoeuvre, note = run_course(meta, params)
        assert manoeuvre is None and why in note, note
    meta = run.meta | {"read_from": None}
    manoeuvre, note = run_course({k: v for k, v in meta.items() if v is not None}, params)
    assert manoeuvre is None and "not known here" in note
