"""Manoeuvre geometry: ISO 3888 tracks, ISO 14791 single lane change, circles, CSV paths, cone strikes."""

import math
import time

import numpy as np
import pytest

from trikedyn.errors import InputError
from trikedyn.manoeuvres import (
    CONE_RADIUS_M,
    DS_MAX_M,
    Corridor,
    Path,
    circle,
    cone_strikes,
    corridor_violations,
    double_lane_change,
    path_from_csv,
    single_lane_change,
    straight,
)
from trikedyn.manoeuvres import csv_path as paths_module

TRIKE_WIDTH_M = 1.25  # the paper's e-trike


def _check_line(path: Path, *, heading_tol=5e-5, curvature_tol=1e-4):
    """Uniform arc length, points ds apart, heading and curvature consistent with finite differences."""
    for arr in (path.x_m, path.y_m, path.s_m, path.heading_rad, path.curvature_per_m):
        assert arr.dtype == np.float64 and arr.flags.c_contiguous
    ds = np.diff(path.s_m)
    assert ds.max() <= DS_MAX_M + 1e-12
    assert np.allclose(ds, ds[0], rtol=0, atol=1e-9)
    chord = np.hypot(np.diff(path.x_m), np.diff(path.y_m))
    assert np.allclose(chord, ds, rtol=0, atol=1e-6)
    # the chord direction is the mean tangent direction to O(ds^2 dkappa/ds)
    mid_heading = np.arctan2(np.diff(path.y_m), np.diff(path.x_m))
    error = mid_heading - 0.5 * (path.heading_rad[1:] + path.heading_rad[:-1])
    assert np.max(np.abs(np.angle(np.exp(1j * error)))) < heading_tol
    fd_curvature = np.diff(path.heading_rad) / ds
    assert np.max(np.abs(fd_curvature - 0.5 * (path.curvature_per_m[1:] + path.curvature_per_m[:-1]))) < curvature_tol
    assert path.x_m[0] == 0.0 and path.y_m[0] == 0.0 and path.heading_rad[0] == 0.0
    arr = path.as_array()
    assert arr.shape == (path.x_m.size, 5) and arr.flags.c_contiguous


def _by_name(path: Path) -> dict[str, Corridor]:
    return {c.name: c for c in path.corridors}


# ---------------------------------------------------------------------------------------------------------
# ISO 3888-1 double lane change
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("w", "widths"),
    [
        # 1.1 w + 0.25, 1.2 w + 0.25, 1.3 w + 0.25 (ISO 3888-1 Table 1)
        (1.25, {"section 1": 1.625, "section 3": 1.75, "section 5": 1.875, "section 6": 1.875}),
        (2.0, {"section 1": 2.45, "section 3": 2.65, "section 5": 2.85, "section 6": 2.85}),
    ],
)
def test_dlc_lane_widths(w, widths):
    lanes = _by_name(double_lane_change(w))
    assert set(lanes) == set(widths)
    for name, width in widths.items():
        assert lanes[name].width_m == pytest.approx(width, abs=1e-12)


def test_dlc_section_lengths_offsets_and_total():
    run_in = 30.0
    p = double_lane_change(TRIKE_WIDTH_M, run_in_m=run_in, run_out_m=20.0)
    s1, s3, s5, s6 = (_by_name(p)[f"section {k}"] for k in (1, 3, 5, 6))
    # 15 / 30 / 25 / 25 / 15 / 15 m, total 125 m, section 1 starting after the run-in
    assert s1.x_start_m == run_in
    assert [
        s1.length_m,
        s3.x_start_m - s1.x_end_m,
        s3.length_m,
        s5.x_start_m - s3.x_end_m,
        s5.length_m,
        s6.length_m,
    ] == (pytest.approx([15.0, 30.0, 25.0, 25.0, 15.0, 15.0]))
    assert s6.x_end_m - s1.x_start_m == pytest.approx(125.0)
    assert s6.x_start_m == s5.x_end_m
    # lane offset 3.5 m between the right-hand limits of sections 1 and 3; exit lane in line with section 1
    assert s1.y_min_m == pytest.approx(-0.8125)
    assert s3.y_min_m - s1.y_min_m == pytest.approx(3.5)
    assert s5.y_min_m == s1.y_min_m == s6.y_min_m
    assert p.x_m[-1] == pytest.approx(s6.x_end_m + 20.0)
    assert p.y_m[-1] == pytest.approx(s5.centre_y_m)
    assert p.to_dict()["cones"] == 18


def test_dlc_iso3888_2_variant():
    for w, widths in (
        # 1.1 w + 0.25, w + 1, 1.3 w + 0.25 but not less than 3 m
        (1.25, (1.625, 2.25, 3.0)),
        (2.2, (2.67, 3.2, 3.11)),
    ):
        p = double_lane_change(w, standard="ISO 3888-2", run_in_m=10.0)
        s1, s3, s5 = (_by_name(p)[f"section {k}"] for k in (1, 3, 5))
        assert [s1.width_m, s3.width_m, s5.width_m] == pytest.approx(widths)
        assert [s1.length_m, s3.x_start_m - s1.x_end_m, s3.length_m, s5.x_start_m - s3.x_end_m, s5.length_m] == (
            pytest.approx([12.0, 13.5, 11.0, 12.5, 12.0])
        )
        assert s5.x_end_m - s1.x_start_m == pytest.approx(61.0)
        assert s3.y_min_m - s1.y_max_m == pytest.approx(1.0)
        assert s5.y_min_m == s1.y_min_m
        # short blends: the curvature rate steps at their ends, which finite differences see at O(ds)
        _check_line(p, curvature_tol=1e-3)


def test_dlc_cones_on_the_corridor_edges():
    p = double_lane_change(TRIKE_WIDTH_M)
    assert p.cones.shape == (18, 2)
    for x, y in p.cones:
        # every cone sits on a lane limit of a section that spans its x, its base tangent to the limit
        on_edge = [
            math.isclose(y, c.y_max_m + CONE_RADIUS_M, abs_tol=1e-12)
            or math.isclose(y, c.y_min_m - CONE_RADIUS_M, abs_tol=1e-12)
            for c in p.corridors
            if c.x_start_m - 1e-9 <= x <= c.x_end_m + 1e-9
        ]
        assert any(on_edge), (x, y)
    # start, middle and end of each lane, both sides
    xs = sorted(set(np.round(p.cones[:, 0], 9)))
    assert xs == pytest.approx([30.0, 37.5, 45.0, 75.0, 87.5, 100.0, 125.0, 140.0, 155.0])


@pytest.mark.parametrize("w", [1.25, 2.0])
def test_dlc_reference_line_inside_every_corridor(w):
    p = double_lane_change(w)
    for c in p.corridors:
        inside = (p.x_m >= c.x_start_m) & (p.x_m <= c.x_end_m)
        assert inside.sum() > 100
        y = p.y_m[inside]
        assert np.all(y - 0.5 * w >= c.y_min_m - 1e-9)
        assert np.all(y + 0.5 * w <= c.y_max_m + 1e-9)
        assert np.allclose(y, c.centre_y_m, atol=1e-9)  # centred in every lane section


def test_dlc_heading_curvature_and_smoothness():
    p = double_lane_change(TRIKE_WIDTH_M)
    _check_line(p)
    # continuous curvature: steps between neighbouring points stay tiny (peak curvature ~0.025 1/m)
    assert np.max(np.abs(np.diff(p.curvature_per_m))) < 1e-3
    # peak of the sharper blend (3.4375 m across the 25 m of section 4), 2 pi D / L^2 less the slope factor
    assert np.max(np.abs(p.curvature_per_m)) == pytest.approx(2 * math.pi * 3.4375 / 25.0**2, rel=0.03)
    # straight run-in and run-out
    assert np.all(p.curvature_per_m[p.x_m <= 45.0] == 0.0)
    assert np.allclose(p.curvature_per_m[p.x_m >= 155.0], 0.0, atol=1e-12)


def test_dlc_right_is_the_mirror_of_left():
    left = double_lane_change(TRIKE_WIDTH_M)
    right = double_lane_change(TRIKE_WIDTH_M, direction="right")
    assert np.allclose(right.y_m, -left.y_m)
    assert np.allclose(right.cones[:, 1], -left.cones[:, 1])
    assert [(c.y_min_m, c.y_max_m) for c in right.corridors] == [(-c.y_max_m, -c.y_min_m) for c in left.corridors]


@pytest.mark.parametrize(
    ("kwargs", "where"),
    [
        ({"vehicle_width_m": 0.0}, "vehicle_width_m"),
        ({"vehicle_width_m": float("nan")}, "vehicle_width_m"),
        ({"vehicle_width_m": "wide"}, "vehicle_width_m"),
        ({"vehicle_width_m": 1250.0}, "vehicle_width_m"),
        ({"vehicle_width_m": 1.25, "run_in_m": -1.0}, "run_in_m"),
        ({"vehicle_width_m": 1.25, "standard": "ISO 3888-3"}, "standard"),
        ({"vehicle_width_m": 1.25, "direction": "up"}, "direction"),
    ],
)
def test_dlc_errors(kwargs, where):
    with pytest.raises(InputError) as err:
        double_lane_change(**kwargs)
    assert err.value.where == where
    assert "\n" not in str(err.value)


# ---------------------------------------------------------------------------------------------------------
# ISO 14791 single lane change
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("offset", [3.5, -3.5])
def test_slc_lateral_acceleration_is_one_sine_period(offset):
    length, run_in, v = 50.0, 20.0, 12.0
    p = single_lane_change(lateral_offset_m=offset, length_m=length, run_in_m=run_in, run_out_m=25.0)
    _check_line(p)
    ay = p.curvature_per_m * v**2  # at constant speed along the path
    xp = p.x_m - run_in
    during = (xp > 0.0) & (xp < length)
    assert np.all(ay[~during] == pytest.approx(0.0, abs=1e-12))
    # one interior zero crossing, at the middle
    a = ay[during]
    crossings = np.flatnonzero(np.sign(a[1:]) != np.sign(a[:-1]))
    assert crossings.size == 1
    assert xp[during][crossings[0]] == pytest.approx(length / 2, abs=2 * DS_MAX_M)
    # first half toward the offset, then back
    assert np.sign(a[: crossings[0]]).mean() == np.sign(offset)
    # peak against the closed form 2 pi A v^2 / L^2, and the whole period against the sine
    peak = 2 * math.pi * abs(offset) * v**2 / length**2
    assert np.max(np.abs(a)) == pytest.approx(peak, rel=0.02)
    assert np.max(np.abs(a - np.sign(offset) * peak * np.sin(2 * math.pi * xp[during] / length))) < 0.02 * peak
    # final lateral offset
    assert p.y_m[-1] == pytest.approx(offset, abs=1e-12)
    assert p.heading_rad[-1] == pytest.approx(0.0, abs=1e-12)


def test_slc_lanes_and_cones():
    p = single_lane_change(lateral_offset_m=3.5, length_m=40.0, run_in_m=20.0, run_out_m=30.0, lane_width_m=3.0)
    start, target = p.corridors
    assert (start.name, start.x_start_m, start.x_end_m, start.y_min_m, start.y_max_m) == (
        "start lane",
        0.0,
        20.0,
        -1.5,
        1.5,
    )
    assert (target.name, target.x_start_m, target.x_end_m) == ("target lane", 60.0, 90.0)
    assert (target.y_min_m, target.y_max_m) == pytest.approx((2.0, 5.0))
    assert p.cones.shape == (8, 2)
    assert set(np.round(p.cones[:, 1], 9)) == {1.65, -1.65, 5.15, 1.85}
    assert p.x_m[-1] == pytest.approx(90.0)
    assert single_lane_change(run_in_m=0.0, run_out_m=0.0).corridors == ()


@pytest.mark.parametrize(
    ("kwargs", "where"),
    [
        ({"lateral_offset_m": 0.0}, "lateral_offset_m"),
        ({"length_m": -5.0}, "length_m"),
        ({"lane_width_m": 0.0}, "lane_width_m"),
        ({"run_out_m": float("inf")}, "run_out_m"),
    ],
)
def test_slc_errors(kwargs, where):
    with pytest.raises(InputError) as err:
        single_lane_change(**kwargs)
    assert err.value.where == where


# ---------------------------------------------------------------------------------------------------------
# circle, straight, projection
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("direction", ["left", "right"])
def test_circle_curvature_and_geometry(direction):
    r, run_in = 20.0, 10.0
    p = circle(r, laps=1.0, run_in_m=run_in, direction=direction)
    _check_line(p, heading_tol=DS_MAX_M / r, curvature_tol=1.0 / r)  # the curvature steps at the entry
    sign = 1.0 if direction == "left" else -1.0
    on = p.s_m > run_in
    assert np.allclose(p.curvature_per_m[on], sign / r, rtol=1e-3, atol=0)
    assert np.all(p.curvature_per_m[~on] == 0.0)
    assert p.length_m == pytest.approx(run_in + 2 * math.pi * r)
    assert np.allclose(np.hypot(p.x_m[on] - run_in, p.y_m[on] - sign * r), r, atol=1e-9)
    assert p.heading_rad[-1] == pytest.approx(sign * 2 * math.pi)
    assert p.cones.shape == (0, 2) and p.corridors == ()


def test_project_round_trip_on_a_circle():
    r = 20.0
    p = circle(r, laps=1.0, run_in_m=10.0)
    rng = np.random.default_rng(1)
    # on the circle, away from where it closes near the run-in
    i = rng.integers(np.searchsorted(p.s_m, 15.0), np.searchsorted(p.s_m, p.length_m - 15.0), size=200)
    s, off = p.project(p.x_m[i], p.y_m[i])
    assert np.allclose(off, 0.0, atol=1e-9)
    assert np.allclose(s, p.s_m[i], atol=1e-9)
    # points moved along the normal (left positive) come back with their offset
    d = rng.uniform(-3.0, 3.0, size=i.size)
    nx, ny = -np.sin(p.heading_rad[i]), np.cos(p.heading_rad[i])
    s, off = p.project(p.x_m[i] + d * nx, p.y_m[i] + d * ny)
    assert np.allclose(off, d, atol=1e-4)
    assert np.allclose(s, p.s_m[i], atol=3.0 * DS_MAX_M / (2 * r))  # chord projection: |d| ds / (2 R)
    # shapes follow the input
    s, off = p.project(np.zeros((2, 3)) + 10.0, np.ones((2, 3)))
    assert s.shape == off.shape == (2, 3)
    assert np.allclose(off, 1.0, atol=1e-6)


def test_project_on_the_double_lane_change_and_beyond_the_ends():
    p = double_lane_change(TRIKE_WIDTH_M)
    rng = np.random.default_rng(2)
    i = rng.integers(1, p.x_m.size - 1, size=300)
    d = rng.uniform(-0.5, 0.5, size=i.size)
    s, off = p.project(p.x_m[i] - d * np.sin(p.heading_rad[i]), p.y_m[i] + d * np.cos(p.heading_rad[i]))
    assert np.allclose(off, d, atol=1e-5)
    assert np.allclose(s, p.s_m[i], atol=1e-5)
    # beyond the ends: clamped arc length, offset normal to the end segment
    s, off = p.project([-5.0, p.x_m[-1] + 3.0], [-1.0, p.y_m[-1] + 0.2])
    assert s == pytest.approx([0.0, p.length_m])
    assert off == pytest.approx([-1.0, 0.2])


def test_straight_and_to_dict():
    p = straight(12.3)
    _check_line(p)
    assert p.length_m == pytest.approx(12.3) and np.all(p.y_m == 0.0)
    d = p.to_dict()
    assert d["name"] == "straight" and d["cones"] == 0 and d["corridors"] == []
    import json

    json.dumps(double_lane_change(TRIKE_WIDTH_M).to_dict())
    with pytest.raises(InputError):
        straight(0.0)


def test_path_and_corridor_validation():
    with pytest.raises(InputError, match="at least 2"):
        Path("p", [0.0], [0.0], [0.0], [0.0], [0.0])
    with pytest.raises(InputError) as err:
        Path("p", [0.0, 1.0], [0.0, np.nan], [0.0, 1.0], [0.0, 0.0], [0.0, 0.0])
    assert err.value.where == "path.y_m"
    with pytest.raises(InputError):
        Corridor(5.0, 1.0, -1.0, 1.0, "backwards")


# ---------------------------------------------------------------------------------------------------------
# CSV paths
# ---------------------------------------------------------------------------------------------------------
def _sine(x):
    k = 2 * math.pi / 25.0
    y = 2.0 * np.sin(k * x)
    dy = 2.0 * k * np.cos(k * x)
    ddy = -2.0 * k * k * np.sin(k * x)
    return y, dy, ddy


def _write(tmp_path, text, name="line.csv"):
    file = tmp_path / name
    file.write_text(text, encoding="utf-8")
    return file


def test_path_from_csv_round_trip(tmp_path):
    x = np.arange(0.0, 50.0 + 1e-9, 0.5)
    y, _, _ = _sine(x)
    rows = "\n".join(f"{a:.9f},{b:.9f},{i}" for i, (a, b) in enumerate(zip(x, y, strict=True)))
    file = _write(tmp_path, "# a sampled sine\nx_m,y_m,index\n" + rows + "\n")
    p = path_from_csv(file, smoothing_m=0.0, align=False)
    assert p.name == "line"
    assert p.ds_m <= DS_MAX_M
    yt, dyt, ddyt = _sine(p.x_m)
    inner = (p.x_m > 2.0) & (p.x_m < 48.0)
    assert np.max(np.abs(p.y_m - yt)) < 1e-3
    assert np.max(np.abs(p.heading_rad - np.arctan(dyt))[inner]) < 1e-3
    assert np.max(np.abs(p.curvature_per_m - ddyt / (1 + dyt**2) ** 1.5)[inner]) < 3e-3
    # length of the sine, integrated finely
    xf = np.linspace(0.0, 50.0, 200_001)
    assert p.length_m == pytest.approx(np.trapezoid(np.hypot(1.0, _sine(xf)[1]), xf), rel=1e-4)
    # default: smoothed a little, moved to start at the origin heading +x
    q = path_from_csv(file)
    _check_line(q, heading_tol=1e-5, curvature_tol=1e-3)
    assert q.length_m == pytest.approx(p.length_m, rel=1e-3)
    assert np.max(np.abs(q.curvature_per_m - p.curvature_per_m)[inner]) < 0.02


def test_path_from_csv_short_column_names(tmp_path):
    file = _write(tmp_path, "t,y,x\n0,0,0\n1,0.1,1\n2,0.4,2\n3,0.9,3\n")
    p = path_from_csv(file, align=False, smoothing_m=0.0, name="quad")
    assert p.name == "quad"
    assert p.x_m[-1] == pytest.approx(3.0) and p.y_m[-1] == pytest.approx(0.9)


@pytest.mark.parametrize(
    ("text", "line", "match"),
    [
        ("a,b\n0,0\n1,1\n2,2\n", 1, "missing column 'x_m'"),
        ("x_m,z\n0,0\n1,1\n2,2\n", 1, "missing column 'y_m'"),
        ("x_m,y_m\n0,0\n1,1\n", None, "at least 3"),
        ("x_m,y_m\n0,0\n1,nan\n2,2\n", 3, "finite"),
        ("x_m,y_m\n0,0\n1,abc\n2,2\n", 3, "expected a number"),
        ("x_m,y_m\n0,0\n\n1,1\n1,1\n2,2\n", 5, "repeats the point of line 4"),
        ("x_m,y_m\n0,0\n1\n2,2\n", 3, "missing the y value"),
        ("", None, "empty file"),
    ],
)
def test_path_from_csv_errors(tmp_path, text, line, match):
    file = _write(tmp_path, text)
    with pytest.raises(InputError, match=match) as err:
        path_from_csv(file)
    assert err.value.where == (f"{file}:{line}" if line else str(file))
    assert "\n" not in str(err.value)


def test_path_from_csv_missing_file(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        path_from_csv(tmp_path / "nope.csv")


# ---------------------------------------------------------------------------------------------------------
# bounds: each case once ran out of memory, ran for minutes or escaped as a traceback
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("text", "line", "match"),
    [
        ("x_m,y_m\n0,0\n1e9,0\n2e9,0\n", 3, r"x: 1e\+09 m is beyond \+-1e\+07 m"),  # MemoryError
        ("x_m,y_m\n0,0\n5000,0\n10000,0\n", 3, "5000 m from the point of line 2; consecutive points must be 1 mm to 1000 m apart"),
        ("x_m,y_m\n0,0\n1e-12,0\n2e-12,0\n", 3, "1e-12 m from the point of line 2"),  # IndexError
        ("x_m,y_m\n0,0\n1,0\n1.0005,0\n3,0\n", 4, "0.0005 m from the point of line 3"),
        ("x_m,y_m\n" + "\n".join(f"{500 * i},0" for i in range(201)) + "\n", 43, "longer than 20000 m by here"),
        ("x_m,y_m\n0,0\n1,1\n" + "9" * 200_000 + ",1\n", 4, "not a CSV line: field larger than field limit"),
    ],
)
def test_path_from_csv_bounds(tmp_path, text, line, match):
    file = _write(tmp_path, text)
    start = time.perf_counter()
    with pytest.raises(InputError, match=match) as err:
        path_from_csv(file)
    assert err.value.where == f"{file}:{line}" and "\n" not in str(err.value)
    assert time.perf_counter() - start < 2.0


def test_path_from_csv_point_count_is_bounded(tmp_path, monkeypatch):
    monkeypatch.setattr(paths_module, "MAX_CSV_POINTS", 5)
    file = _write(tmp_path, "x_m,y_m\n" + "\n".join(f"{i},0" for i in range(6)) + "\n")
    with pytest.raises(InputError, match="more than 5 points") as err:
        path_from_csv(file)
    assert err.value.where == f"{file}:7"
    monkeypatch.setattr(paths_module, "MAX_CSV_BYTES", 10)
    with pytest.raises(InputError, match="a path CSV is read up to 0 MiB") as err:
        path_from_csv(file)
    assert err.value.where == str(file)


def test_path_from_csv_near_the_bounds_is_fine(tmp_path):
    """Points 1.5 mm and 999 m apart, in UTM-sized coordinates, a line of almost 20 km."""
    x = np.r_[0.0, 0.0015, 0.003, 999.0 * np.arange(1, 21)] + 5e5
    file = _write(tmp_path, "x_m,y_m\n" + "\n".join(f"{v:.4f},4000000" for v in x) + "\n")
    p = path_from_csv(file, smoothing_m=0.0)
    assert p.length_m == pytest.approx(19_980.0, rel=1e-6) and p.x_m[0] == 0.0


@pytest.mark.parametrize(
    ("build", "where", "match"),
    [
        (lambda: circle(1e9), "circle", "make 6.283e\\+09 m; at most 20000 m"),  # MemoryError
        (lambda: circle(20.0, laps=1e9), "circle", "at most 20000 m"),
        (lambda: circle(20.0, run_in_m=1e12), "circle", "at most 20000 m"),
        (lambda: circle(1e-300), "radius_m", "must be >= 1"),
        (lambda: straight(1e12), "length_m", "at most 20000 m"),
        (lambda: single_lane_change(length_m=1e12), "ISO 14791 single lane change", "at most 20000 m"),
        (lambda: double_lane_change(TRIKE_WIDTH_M, run_out_m=1e12), "ISO 3888-1 double lane change", "at most 20000 m"),
    ],
)
def test_built_lines_are_bounded(build, where, match):
    start = time.perf_counter()
    with pytest.raises(InputError, match=match) as err:
        build()
    assert err.value.where == where and time.perf_counter() - start < 1.0
    assert circle(3000.0).length_m == pytest.approx(10.0 + 2 * math.pi * 3000.0)  # 18.9 km is fine


# ---------------------------------------------------------------------------------------------------------
# cone strikes and corridor violations
# ---------------------------------------------------------------------------------------------------------
def test_no_strikes_down_the_middle_with_a_narrow_footprint():
    p = double_lane_change(TRIKE_WIDTH_M)
    t = p.s_m / 10.0
    footprint = (-0.3, 0.3, 0.3)
    assert cone_strikes(p, t, p.x_m, p.y_m, p.heading_rad, footprint) == []
    assert corridor_violations(p, t, p.x_m, p.y_m, p.heading_rad, footprint) == []


def test_straight_run_through_section_3_strikes_its_right_hand_cones():
    p = double_lane_change(TRIKE_WIDTH_M)
    s3 = _by_name(p)["section 3"]
    v, dt = 10.0, 1e-3
    t = np.arange(0.0, 18.0, dt)
    x = v * t
    y = np.full_like(t, s3.y_min_m)  # along the right-hand limit of section 3
    yaw = np.zeros_like(t)
    x_front, half_width = 1.5, 0.6
    footprint = (-0.5, x_front, half_width)
    strikes = cone_strikes(p, t, x, y, yaw, footprint)
    assert [s["x_m"] for s in strikes] == pytest.approx([75.0, 87.5, 100.0])
    assert all(s["y_m"] == pytest.approx(s3.y_min_m - CONE_RADIUS_M) for s in strikes)
    assert len({s["cone"] for s in strikes}) == 3
    # first contact when the front reaches the cone's base circle
    assert strikes[0]["time_s"] == pytest.approx((75.0 - x_front - CONE_RADIUS_M) / v, abs=2 * dt)
    assert [s["time_s"] for s in strikes] == sorted(s["time_s"] for s in strikes)

    violations = corridor_violations(p, t, x, y, yaw, footprint)
    by_name = {v_["name"]: v_ for v_ in violations}
    assert set(by_name) == {"section 1", "section 3", "section 5", "section 6"}
    assert by_name["section 3"]["side"] == "right"
    assert by_name["section 3"]["worst_excursion_m"] == pytest.approx(half_width)
    assert by_name["section 1"]["side"] == "left"
    assert by_name["section 1"]["worst_excursion_m"] == pytest.approx(s3.y_min_m + half_width - 0.8125)
    # the front corners enter section 3 first
    assert by_name["section 3"]["time_start_s"] == pytest.approx((75.0 - x_front) / v, abs=2 * dt)
    assert by_name["section 3"]["time_end_s"] == pytest.approx((100.0 + 0.5) / v, abs=2 * dt)


def test_yawed_footprint_strikes_a_cone_beside_it():
    p = double_lane_change(TRIKE_WIDTH_M)
    cx, cy = p.cones[0]  # left-hand cone at the start of section 1
    # vehicle beside the cone, parallel: the footprint misses it; turned 90 deg, its front reaches it
    footprint = (0.0, 1.0, 0.3)
    parallel = cone_strikes(p, [0.0], [cx - 1.0], [cy - 0.5], [0.0], footprint)
    turned = cone_strikes(p, [0.0], [cx], [cy - 1.0], [math.pi / 2], footprint)
    assert parallel == [] and [s["cone"] for s in turned] == [0]


@pytest.mark.parametrize(
    ("footprint", "where"),
    [((1.0, 0.0, 0.5), "footprint"), ((0.0, 1.0), "footprint"), ((0.0, 1.0, -0.5), "footprint")],
)
def test_judging_errors(footprint, where):
    p = double_lane_change(TRIKE_WIDTH_M)
    with pytest.raises(InputError) as err:
        cone_strikes(p, [0.0], [0.0], [0.0], [0.0], footprint)
    assert err.value.where == where
    with pytest.raises(InputError) as err:
        corridor_violations(p, [0.0, 1.0], [0.0], [0.0, 0.0], [0.0, 0.0], (-0.5, 1.0, 0.5))
    assert err.value.where == "x_m"
