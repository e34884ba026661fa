"""The manoeuvre registry: names, options, errors, and a manoeuvre added from outside the package."""

import math

import numpy as np
import pytest

from trikedyn.errors import InputError
from trikedyn.manoeuvres import registry
from trikedyn.manoeuvres.base import Manoeuvre, Window, with_run_out
from trikedyn.manoeuvres.paths import circle, straight


def test_builtins_are_registered_with_their_options(reference):
    names = [k.name for k in registry.available()]
    for name in ("dlc", "slc", "circle", "steady-state-circle", "step", "sweep", "braking-in-turn", "fishhook", "path"):
        assert name in names
    for kind in registry.available():
        assert kind.to_dict()["options"] == [o.to_dict() for o in kind.options]
    dlc = registry.build("dlc", reference.params, 30.0)
    assert dlc.closed_loop and dlc.window.kind == "distance"
    assert registry.build("step", reference.params, 30.0).closed_loop is False


def test_unknown_names_and_options_are_clear_errors(reference):
    with pytest.raises(InputError, match="unknown manoeuvre 'dcl'; did you mean 'dlc'"):
        registry.get("dcl")
    with pytest.raises(InputError, match="no option 'radius'; did you mean 'radius_m'"):
        registry.build("circle", reference.params, 20.0, radius="15")
    with pytest.raises(InputError, match="expected a number"):
        registry.build("circle", reference.params, 20.0, radius_m="fifteen")
    with pytest.raises(InputError, match="expected one of left, right"):
        registry.build("dlc", reference.params, 20.0, direction="up")
    with pytest.raises(InputError, match="speed must be > 0"):
        registry.build("dlc", reference.params, float("nan"))
    with pytest.raises(InputError, match="KEY=VALUE"):
        registry.parse_options(["radius_m"])


def test_the_path_goes_on_beyond_the_exit_gate(reference):
    """Run-out: the driver's preview never reaches the end of the line before the run ends."""
    for name in ("dlc", "slc", "circle"):
        m = registry.build(name, reference.params, 60.0)
        v = float(m.speed.speed_mps.max())
        covered = v * m.duration_s + reference.params.mass.cg_x_m
        preview = max(3.0, 0.3 * v)
        assert m.path.s_m[-1] > covered + preview, name
        assert m.window.end < covered


def test_run_out_continues_straight_or_round():
    line = with_run_out(straight(10.0), 5.0)
    assert line.s_m[-1] == pytest.approx(15.0, abs=0.06) and np.allclose(line.y_m, 0.0)
    ring = with_run_out(circle(10.0, laps=0.25, run_in_m=0.0), 2 * math.pi * 10.0 * 0.75)
    radius = np.hypot(ring.x_m, ring.y_m - 10.0)
    assert np.allclose(radius, 10.0, atol=1e-6)


def test_a_manoeuvre_needs_a_path_or_a_steer_table(reference):
    from trikedyn.manoeuvres.speed import constant

    with pytest.raises(InputError, match="needs a path"):
        Manoeuvre("x", "x", constant(20.0, 1.0), 5.0, Window("time", 0.0, 5.0))
    with pytest.raises(InputError, match="start < end"):
        Window("time", 2.0, 1.0)


def test_absurd_options_are_refused_before_any_run(reference):
    with pytest.raises(InputError, match="<= 3600 s"):
        registry.build("sweep", reference.params, 20.0, sweep_s=1e9)
    with pytest.raises(InputError, match="<= 3600 s"):
        registry.build("steady-state-circle", reference.params, 10.0, ay_rate_mps2_per_s=1e-9)
    with pytest.raises(InputError, match="must be > 0"):
        registry.build("circle", reference.params, 20.0, radius_m=-5)
