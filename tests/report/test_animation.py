"""``trikedyn animate`` and :mod:`trikedyn.report.animation`: a run file becomes a GIF of the trike through the
cones, in plan or 3d (issue 13: "writes a GIF of at least 20 frames showing the cones"), outputs are never overwritten
without --force, and bad input is one line with exit code 2."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from PIL import Image

from trikedyn.cli import main
from trikedyn.report.animation import animate, ffmpeg_available
from trikedyn.report.scene import frame_indices

from ..conftest import strict_json


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    """A 30 km/h double lane change of the reference e-trike, written by ``trikedyn simulate --out``."""
    folder = tmp_path_factory.mktemp("animate")
    path = folder / "run.parquet"
    assert main(["simulate", "reference-etrike", "--manoeuvre", "dlc", "--speed", "30", "--out", str(path)]) == 0
    return path


def _call(capsys, *args):
    code = main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _one_line_error(code, err, needle):
    assert code == 2, err
    assert err.startswith("trikedyn: error: ") and err.count("\n") == 1 and needle in err, err


def test_animate_writes_a_gif_of_the_cones_and_keeps_it(capsys, run_file, tmp_path):
    gif = tmp_path / "a.gif"
    code, out, err = _call(capsys, "animate", run_file, "--out", gif, "--every-s", 0.5, "--json")
    assert code == 0, err
    data = strict_json(out)
    assert data["cones"] == 18 and data["cones_struck"] == 0  # ISO 3888-1: 3 lanes x 3 gates x 2 sides
    assert data["vehicle"] == "the vehicle recorded with the run ('reference-etrike')"
    assert data["course"].startswith("'dlc' rebuilt at 30 km/h")
    with Image.open(gif) as image:
        assert image.format == "GIF" and image.size == (600, 400)
        assert image.n_frames == data["frames"] >= 20
        image.seek(image.n_frames // 3)
        pixels = np.asarray(image.convert("RGB"), dtype=int)
    orange = (np.abs(pixels - (255, 127, 14)).sum(axis=2) < 40).sum()  # the cones' colour
    assert orange > 20

    before = gif.read_bytes()
    code, out, err = _call(capsys, "animate", run_file, "--out", gif, "--every-s", 0.5)
    _one_line_error(code, err, "exists; not overwriting it (pass --force to replace it)")
    assert gif.read_bytes() == before
    code, out, err = _call(capsys, "animate", run_file, "--out", gif, "--every-s", 2, "--force")
    assert code == 0 and out.startswith(f"wrote {gif}: 11 frames (plan view") and "18 cones" in out, err


def test_rear_view_as_an_html_page(capsys, run_file, tmp_path):
    page = tmp_path / "rear.html"
    code, out, err = _call(capsys, "animate", run_file, "--out", page, "--view", "rear", "--every-s", 4, "--json")
    assert code == 0, err
    assert strict_json(out)["frames"] == 6  # 0, 4, ..., 16 s and the last sample (19.68 s)
    text = page.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and text.count("data:image/png;base64") == 6


def test_3d_view_writes_a_gif_of_the_cones(capsys, run_file, tmp_path):
    """The 3d view: a GIF of at least 20 frames; cones (orange) in the frames where the vehicle is among them,
    the body and the wheels drawn."""
    gif = tmp_path / "3d.gif"
    code, out, err = _call(capsys, "animate", run_file, "--out", gif, "--view", "3d", "--every-s", 0.9, "--json")
    assert code == 0, err
    data = strict_json(out)
    assert data["view"] == "3d" and data["cones"] == 18
    with Image.open(gif) as image:
        assert image.format == "GIF" and image.size == (600, 400)
        assert image.n_frames == data["frames"] >= 20
        orange = []
        for k in range(image.n_frames):
            image.seek(k)
            pixels = np.asarray(image.convert("RGB"), dtype=int)
            orange.append(int((np.abs(pixels - (255, 127, 14)).sum(axis=2) < 40).sum()))
    assert sum(n > 20 for n in orange) >= 5, orange  # the cones of the three lanes pass by


def test_a_run_of_an_unknown_vehicle_is_drawn_from_its_footprint(capsys, run_file, tmp_path):
    """A run file from before the vehicle was recorded: the cones are rebuilt for a stand-in vehicle made from the
    recorded footprint (the DLC's lanes depend on the vehicle's width only)."""
    frame = pd.read_parquet(run_file)
    frame.attrs["vehicle"] = "my-own-trike"
    mine = tmp_path / "mine.parquet"
    frame.to_parquet(mine, index=False)
    side = json.loads(run_file.with_suffix(".json").read_text(encoding="utf-8"))
    side.pop("vehicle_params")
    mine.with_suffix(".json").write_text(json.dumps({**side, "vehicle": "my-own-trike"}), encoding="utf-8")
    code, out, err = _call(capsys, "animate", mine, "--every-s", 5, "--json")
    assert code == 0, err
    data = strict_json(out)
    assert data["cones"] == 18 and "stand-in" in data["vehicle"] and (tmp_path / "mine.gif").is_file()


def test_a_run_of_an_own_vehicle_file_is_drawn_with_that_vehicle(capsys, tmp_path):
    """The run file records the vehicle as driven: an open-loop fishhook of a user's own vehicle file (not a
    preset) animates in 3d with its own vehicle, without a warning (it was a stand-in, which could not rebuild
    the fishhook)."""
    own = tmp_path / "own.toml"
    own.write_text('extends = "reference-etrike"\nname = "own-trike"\n[mass]\ncg_z_m = 0.45\n', encoding="utf-8")
    run = tmp_path / "fish.parquet"
    code, _, err = _call(capsys, "simulate", own, "--manoeuvre", "fishhook", "--speed", "25", "--out", run)
    assert code == 0, err
    side = json.loads(run.with_suffix(".json").read_text(encoding="utf-8"))
    assert side["vehicle_params"]["name"] == "own-trike" and side["vehicle_params"]["mass"]["cg_z_m"] == 0.45
    code, out, err = _call(capsys, "animate", run, "--view", "3d", "--every-s", 1, "--json")
    assert code == 0 and "warning" not in err, err
    data = strict_json(out)
    assert data["vehicle"] == "the vehicle recorded with the run ('own-trike')"
    assert data["course"].startswith("'fishhook' rebuilt")


def test_bad_input_is_one_line_and_exit_2(capsys, run_file, tmp_path):
    code, _, err = _call(capsys, "animate", tmp_path / "missing.parquet", "--out", tmp_path / "x.gif")
    _one_line_error(code, err, "missing.parquet: file not found")
    table = tmp_path / "other.csv"
    table.write_text("time_s,a\n0.0,1\n0.1,2\n0.2,3\n", encoding="utf-8")
    code, _, err = _call(capsys, "animate", table, "--out", tmp_path / "x.gif")
    _one_line_error(code, err, "not a run of trikedyn: no channel")
    code, _, err = _call(capsys, "animate", run_file, "--out", tmp_path / "x.png")
    _one_line_error(code, err, "expected a .gif, .html, .mp4 file name")
    code, _, err = _call(capsys, "animate", run_file, "--out", tmp_path / "x.gif", "--view", "top")
    _one_line_error(code, err, "--view: expected one of plan, rear")
    code, _, err = _call(capsys, "animate", run_file, "--out", tmp_path / "x.gif", "--fps", 0)
    _one_line_error(code, err, "--fps")
    if not ffmpeg_available():
        code, _, err = _call(capsys, "animate", run_file, "--out", tmp_path / "x.mp4")
        _one_line_error(code, err, "writing .mp4 needs ffmpeg")
    assert not list(tmp_path.glob("x.*"))


def test_python_api_returns_the_frames_written(tmp_path):
    import trikedyn

    result = trikedyn.run(trikedyn.load_vehicle("reference-etrike"), "dlc", speed_kmh=30, duration_s=3.0)
    frames = animate(result, tmp_path / "api.gif", view="plan", fps=5, every_s=0.25)
    with Image.open(tmp_path / "api.gif") as image:
        assert frames == image.n_frames == 13  # 0, 0.25, ..., 3 s
    with pytest.raises(trikedyn.InputError, match="view"):
        animate(result, tmp_path / "b.gif", view="side")


def test_frame_indices_take_the_nearest_samples_and_the_last():
    t = np.arange(0.0, 1.005, 0.01)
    assert frame_indices(t, 0.25).tolist() == [0, 25, 50, 75, 100]
    assert frame_indices(t, 0.3).tolist() == [0, 30, 60, 90, 100]
