"""The flat public API."""

import trikedyn as td


def test_every_public_name_exists():
    missing = [name for name in td.__all__ if not hasattr(td, name)]
    assert missing == []


def test_tour_of_the_readme_runs(tmp_path):
    trike = td.load_vehicle("reference-etrike")
    assert any(f.level == "inconsistent" for f in td.audit(trike))
    laden = td.with_freight(trike, 100.0)
    run = td.simulate(laden, duration_s=2.0, speed_kmh=25.0, steer_rad=0.02, drive_torque_Nm=50.0)
    assert run.to_pandas().shape[0] == 201
    assert abs(run["ri"]).max() < 1.0
    found = td.modes(td.build_model(trike), td.static_equilibrium(td.build_model(trike)))
    assert found[0].frequency_hz > 0.5


def test_manoeuvre_level_api():
    trike = td.load_vehicle("reference-etrike")
    result = td.run(trike, "slc", speed_kmh=30.0)
    figures = td.summary(result)
    assert result.success and figures["cone_strikes"] == 0 and not figures["wheel_lifted"]
    assert "fishhook" in [m.name for m in td.list_manoeuvres()]


def test_the_command_line_starts_without_the_heavy_libraries():
    """`trikedyn --version` and `--help` load neither scipy, pandas, numba nor matplotlib (issue 11)."""
    import subprocess
    import sys

    code = ("import sys, contextlib, io\nfrom trikedyn.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n    main(['--version']); main(['--help'])\n"
            "print(sorted(m for m in ('scipy', 'pandas', 'numba', 'matplotlib') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
