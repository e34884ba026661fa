"""The flat public API."""

import trikedyn as td


def test_every_public_name_exists():
    missing = [name for name in td.__all__ if not hasattr(td, name)]
    assert missing == []


def test_tour_of_the_readme_runs(tmp_path):
    trike = td.load_vehicle("reference-etrike")
    assert any(f.level == "inconsistent" for f in td.audit(trike))
    laden = td.with_freight(trike, 100.0)
    run = td.run_open_loop(laden, duration_s=2.0, speed_kmh=25.0, steer_rad=0.02, drive_torque_Nm=50.0)
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


def test_the_flat_api_offers_what_the_readme_uses():
    """Issue 13: drive, compare, run_study, override and the manoeuvres at ``td.``, each the module's own."""
    from trikedyn.analysis.compare import compare
    from trikedyn.manoeuvres.registry import build
    from trikedyn.params import override
    from trikedyn.simulate.closed_loop import drive
    from trikedyn.study.designs.runner import run_study

    expected = {"drive": drive, "compare": compare, "run_study": run_study, "override": override,
                "build_manoeuvre": build, "threshold_velocity": td.threshold_velocity, "run": td.run}
    for name, value in expected.items():
        assert name in td.__all__ and getattr(td, name) is value, name
    trike = td.override(td.load_vehicle("reference-etrike"), {"mass.driver_kg": 80.0})
    assert trike.params.mass.driver_kg == 80.0
    assert td.build_manoeuvre("slc", trike.params, 30.0) is not None


def test_a_vehicle_has_its_mass_and_cg_at_hand():
    import numpy as np

    trike = td.load_vehicle("reference-etrike")
    assert trike.mass_kg == trike.params.mass.total_kg
    assert isinstance(trike.cg_m, np.ndarray) and trike.cg_m.shape == (3,)
    np.testing.assert_allclose(trike.cg_m, trike.params.mass.cg_m)
    laden = td.with_freight(trike, 100.0)
    site = trike.params.freight
    assert laden.mass_kg == trike.mass_kg + 100.0
    expected = (trike.mass_kg * trike.cg_m + 100.0 * np.array([site.x_m, site.y_m, site.z_m])) / laden.mass_kg
    np.testing.assert_allclose(laden.cg_m, expected, atol=1e-12)
    laden.cg_m[0] = 99.0  # a copy: the vehicle is not changed
    assert laden.cg_m[0] != 99.0


def test_import_trikedyn_loads_no_heavy_library():
    import subprocess
    import sys

    code = ("import sys, trikedyn\n"
            "print(sorted(m for m in ('scipy', 'pandas', 'numba', 'matplotlib') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
