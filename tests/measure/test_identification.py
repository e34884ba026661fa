"""Fig. 2c-d identification figure (issue 13): zoom on the decay, spectrum to Nyquist, axis-aware labels."""

import json
import math

import matplotlib
import numpy as np
import pandas as pd
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from trikedyn.measure.quarter_car import quarter_car_free_decay  # noqa: E402
from trikedyn.measure.suspension import identify_suspension  # noqa: E402

MS, MU, KS, KT = 160.0, 25.0, 46e3, 200e3


def bump_record(rate=10.0, duration=30.0, event=10.0, damping=1500.0):
    """A typical 30 s speed-bump record at 10 Hz: 5 cm x 0.5 m bump at 5 km/h, noise, bias and gravity."""
    return quarter_car_free_decay(MS, MU, KS, damping, KT, duration_s=duration, sample_rate_hz=rate,
                                  bump=(0.05, 0.5, 5 / 3.6), event_time_s=event, noise_std_mps2=0.05,
                                  bias_mps2=0.3, seed=5, include_gravity=True)


@pytest.fixture(scope="module")
def result():
    t, a = bump_record()
    return identify_suspension(t, a, MS)


def test_time_panel_zooms_on_the_bump_response(result):
    fig = result.plot()
    try:
        lo, hi = fig.axes[0].get_xlim()
        assert hi - lo < 5.0  # not the 30 s record
        assert lo < 10.0 + 0.1 and lo > 10.0 - 2.0  # shortly before the bump at 10 s
        crests = np.concatenate([result.compression_crest_time_s, result.extension_crest_time_s])
        assert lo <= result.decay_start_s and hi >= crests.max()
        assert hi >= result.decay_start_s + 3.0 / result.damped_frequency_hz  # a few periods
    finally:
        plt.close(fig)


@pytest.mark.parametrize("event", [3.0, 20.0])
def test_zoom_follows_the_event(event):
    t, a = bump_record(event=event)
    r = identify_suspension(t, a, MS)
    lo, hi = r.decay_window()
    assert event - 2.0 < lo <= event + 0.1 and hi - lo < 5.0


def test_spectrum_stops_at_nyquist_and_marks_f_n(result):
    fig = result.plot()
    try:
        spec = fig.axes[1]
        nyquist = result.sample_rate_hz / 2
        assert math.isclose(nyquist, 5.0, rel_tol=1e-6)
        assert spec.get_xlim()[1] <= nyquist + 1e-9
        assert max(float(np.max(line.get_xdata())) for line in spec.lines) <= nyquist + 1e-9
        marked = [line.get_xdata()[0] for line in spec.lines if "f_n" in line.get_label()]
        assert marked and math.isclose(marked[0], result.natural_frequency_hz)
    finally:
        plt.close(fig)


@pytest.mark.parametrize("axis, word", [("x", "longitudinal"), ("y", "lateral"), ("z", "vertical")])
def test_labels_follow_the_axis(result, axis, word):
    fig = result.plot(axis=axis)
    try:
        assert fig.axes[0].get_ylabel().startswith(f"{word} acceleration")
        assert word in fig.axes[1].get_ylabel()
        others = {"longitudinal", "lateral", "vertical"} - {word}
        assert not any(o in fig.axes[0].get_ylabel() for o in others)
    finally:
        plt.close(fig)


def test_plot_rejects_an_unknown_axis(result):
    with pytest.raises(ValueError):
        result.plot(axis="q")


def test_cli_identify_axis_x_plot_says_longitudinal(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    from trikedyn.cli import app
    from trikedyn.measure import identification

    t, a = bump_record()
    log = tmp_path / "bump.csv"
    pd.DataFrame({"time_s": t, "ax_mps2": a, "ay_mps2": 0 * a, "az_mps2": 0 * a + 9.81}).to_csv(log, index=False)
    seen = {}
    original = identification.SuspensionIdentification.plot

    def spy(self, ax=None, axis="z"):
        fig = original(self, ax, axis=axis)
        seen["ylabel"] = fig.axes[0].get_ylabel()
        return fig

    monkeypatch.setattr(identification.SuspensionIdentification, "plot", spy)
    png = tmp_path / "fig.png"
    res = CliRunner().invoke(app, ["identify", str(log), "--sprung-mass", str(MS), "--axis", "x",
                                   "--plot", str(png), "--json"])
    assert res.exit_code == 0, res.output
    assert png.exists() and json.loads(res.stdout)["axis"] == "x"
    assert seen["ylabel"].startswith("longitudinal acceleration")
