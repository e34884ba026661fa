"""The judged window's cone strikes (trikedyn.analysis.window), computed once per run and kept with it."""

import numpy as np
import pytest

from trikedyn.analysis import window
from trikedyn.manoeuvres.judging import cone_strikes
from trikedyn.simulate.closed_loop import run


@pytest.fixture(scope="module")
def struck(reference):
    return run(reference, "dlc", speed_kmh=45.0)  # the reference trike strikes cones at 45 km/h


def test_the_strikes_are_those_of_the_window_samples_and_computed_once(struck, monkeypatch):
    mask = window.judged_mask(struck)
    direct = cone_strikes(struck.manoeuvre.path, struck.time_s[mask], struck["x_m"][mask], struck["y_m"][mask],
                          struck["yaw_rad"][mask], tuple(struck.meta["footprint_m"]))
    assert direct and window.cone_strikes(struck) == direct
    calls = []
    monkeypatch.setattr(window, "_cone_strikes", lambda result: calls.append(result) or [])
    assert window.cone_strikes(struck) == direct and not calls  # kept with the run: not computed again
    mine = window.cone_strikes(struck)
    mine[0]["time_s"] = -1.0
    mine.clear()
    assert window.cone_strikes(struck) == direct  # each call has its own copies


def test_a_kept_figure_is_computed_once_per_result(struck):
    calls = []
    first = struck.derived("test figure", lambda: calls.append(1) or np.arange(3))
    again = struck.derived("test figure", lambda: calls.append(1) or None)
    assert again is first and calls == [1]
