"""``trikedyn tyre show | forces | plot`` through a small Typer app holding the sub-app (as cli.py will)."""

import json
import math

import pytest
import typer
from typer.testing import CliRunner

from trikedyn.commands.tyre import tyre_app
from trikedyn.errors import InputError
from trikedyn.tyre import mf_figures, pac2002, pac2002_pack
from trikedyn.tyre.tir import read_tir

root = typer.Typer()
root.add_typer(tyre_app, name="tyre")


@root.callback()
def _root():
    """The test's stand-in for trikedyn's root app."""


def run(*args):
    result = CliRunner().invoke(root, ["tyre", *map(str, args)])
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result.exit_code, result.output


def test_show_json(write_tir):
    path = write_tir()
    code, out = run("show", path, "--json")
    data = json.loads(out)
    tir = read_tir(path)
    assert code == 0 and data["family"] == "PAC2002" and data["nominal_load_N"] == 2000.0
    assert data["cornering_stiffness_N_per_rad"] == pytest.approx(mf_figures.cornering_stiffness(tir, 2000.0))
    assert data["longitudinal_slip_stiffness_N"] == pytest.approx(mf_figures.longitudinal_slip_stiffness(tir, 2000.0))
    peaks = mf_figures.peak_forces(tir, 2000.0)
    assert data["peak_lateral_force_N"] == pytest.approx(peaks.peak_lateral_N)
    assert data["peak_longitudinal_force_N"] == pytest.approx(peaks.peak_longitudinal_N)
    assert data["unloaded_radius_m"] == 0.3 and data["clamped"] == [] and "warnings" not in data
    code, out = run("show", path, "--load", 9000, "--json")
    assert json.loads(out)["clamped"] == ["fz"]
    code, out = run("show", path)
    assert code == 0 and "cornering stiffness" in out and "N/rad" in out and "peak Fy" in out


def test_forces_json_and_clamping(write_tir):
    path = write_tir()
    code, out = run("forces", path, "--load", 2500, "--slip-angle-deg", 4, "--slip-ratio", 0.05, "--camber-deg", 1,
                    "--json")
    data = json.loads(out)
    expected = pac2002.mf_forces(2500.0, 0.05, math.radians(4), math.radians(1), 15.0, pac2002_pack.pack(read_tir(path)))
    assert code == 0 and [data[k] for k in ("fx_N", "fy_N", "mz_Nm", "mx_Nm", "my_Nm")] == pytest.approx(expected[:5])
    assert data["clamped"] == [] and data["fy_N"] < 0 < data["fx_N"]
    code, out = run("forces", path, "--load", 2500, "--slip-angle-deg", 80, "--json")
    assert json.loads(out)["clamped"] == ["alpha"]
    code, out = run("forces", path, "--load", 2500, "--side", "right", "--json")
    mirrored = json.loads(out)
    code, out = run("forces", path, "--load", 2500, "--json")
    assert mirrored["fy_N"] == pytest.approx(-json.loads(out)["fy_N"])
    code, out = run("forces", path, "--load", 2500, "--slip-angle-deg", 80)
    assert "clamped to the file's validity range: alpha" in out


def test_plot_writes_once_unless_forced(write_tir, tmp_path):
    path = write_tir()
    out = tmp_path / "tyre.png"
    code, text = run("plot", path, "--out", out)
    assert code == 0 and out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and f"wrote {out}" in text
    with pytest.raises(InputError, match="exists; not overwriting it"):
        run("plot", path, "--out", out)
    code, text = run("plot", path, "--out", out, "--force", "--json")
    assert code == 0 and json.loads(text) == {"wrote": str(out)}
    with pytest.raises(InputError, match="is also an input"):
        run("plot", path, "--out", path, "--force")


def test_errors_are_input_errors(write_tir, make_tir_text, tmp_path):
    bad = write_tir("bad.tir", text=make_tir_text().replace("PCX1                     = 1.65", "PCX1 = oops"))
    with pytest.raises(InputError) as info:
        run("show", bad)
    assert info.value.where == f"{bad}:79"
    with pytest.raises(InputError, match="no such file"):
        run("forces", tmp_path / "absent.tir", "--load", 100)
    with pytest.raises(InputError, match="must be >= 0 and <= 1e"):
        run("forces", write_tir(), "--load", -5)
    with pytest.raises(InputError, match="must be 'left' or 'right'"):
        run("forces", write_tir(), "--load", 5, "--side", "middle")
    code, out = run("forces", write_tir())  # a missing required option: click's usage error, exit 2
    assert code == 2


def test_real_file_through_the_commands(real_tir, tmp_path):
    code, out = run("show", real_tir.path, "--json")
    data = json.loads(out)
    expected = real_tir["PKY1"] * 3800.0 * math.sin(2.0 * math.atan(1.0 / real_tir["PKY2"]))
    assert data["cornering_stiffness_N_per_rad"] == pytest.approx(expected, rel=1e-12)
    assert 0.8 < data["peak_friction_lateral"] < 1.3 and data["defaulted"] == []
    code, out = run("plot", real_tir.path, "--out", tmp_path / "real.svg")
    assert code == 0 and (tmp_path / "real.svg").stat().st_size > 10_000
