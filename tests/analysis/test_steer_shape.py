"""The steer curve's shape (trikedyn.analysis.steer_shape) on synthetic curves of known shape (no model).

Each curve is a constant-radius run as the model's driver produces it: a_y rising evenly in time from
0.87 m/s^2 (15 km/h on 20 m), the steer a known function of a_y, noise on both (0.005 deg, 0.02 m/s^2:
about what the model's runs show about a smooth curve).
"""

from __future__ import annotations

import json
import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

from trikedyn.analysis.steady_state import handling_diagram
from trikedyn.analysis.steer_shape import (
    band_gradients,
    behaviour,
    first_peak,
    line_fit,
    steer_curve,
    steer_shape,
)
from trikedyn.errors import InputError

G = 9.80665
DELTA_A = 5.6  # Ackermann steer [deg]


def run(steer_of_a, a_end=6.0, n=6000, seed=1, noise=True):
    """a_y [m/s^2] rising evenly from 0.87 to ``a_end``; steer [deg] = ``steer_of_a(a)`` (+ noise)."""
    rng = np.random.default_rng(seed)
    a = np.linspace(0.87, a_end, n)
    steer = steer_of_a(a)
    if noise:
        return a + rng.normal(0, 0.02, n), steer + rng.normal(0, 0.005, n)
    return a, steer


def quadratic(k1=2.0, peak=3.0):
    """Steer rising at ``k1`` deg/g at a_y = 0 and peaking at ``peak`` m/s^2; its gradient at a_y is
    ``k1 (1 - a / peak)`` [deg/g]."""
    return lambda a: DELTA_A + k1 * a / G - k1 / (2 * peak) * a * a / G


def piecewise(a, kinks=(2.0, 4.0), slopes=(2.0, 0.5, -3.0)):
    """Straight pieces of ``slopes`` [deg/g] joined at ``kinks`` [m/s^2]."""
    out = np.full_like(a, DELTA_A)
    edges = (0.0, *kinks, np.inf)
    for lo, hi, k in zip(edges[:-1], edges[1:], slopes, strict=True):
        out += k / G * np.clip(a - lo, 0.0, hi - lo)
    return out


def test_band_gradients_of_a_quadratic_are_its_slope_at_the_band_middle():
    """The least-squares slope of a quadratic over evenly spread points is its slope at their middle."""
    shape = steer_shape(*run(quadratic()))
    edges = [(b.low_mps2, b.high_mps2) for b in shape.bands]
    assert np.ravel(edges) == pytest.approx(np.ravel([(0.87, 2), (2, 3), (3, 4), (4, 5), (5, 6)]), abs=0.06)
    for band in shape.bands:
        middle = 0.5 * (band.low_mps2 + band.high_mps2)
        assert band.gradient_deg_per_g == pytest.approx(2.0 * (1 - middle / 3.0), abs=0.05)
    assert [b.behaviour for b in shape.bands] == ["understeer", "understeer", "oversteer", "oversteer", "oversteer"]
    # the neutral-steer point is the peak; the limit is the slope over the last 0.5 m/s^2 (middle 5.75)
    assert shape.neutral_steer == "peak"
    assert shape.neutral_steer_lateral_acceleration_mps2 == pytest.approx(3.0, abs=0.05)
    assert shape.neutral_steer_deg == pytest.approx(quadratic()(3.0), abs=0.003)
    assert shape.limit_behaviour == "oversteer"
    assert shape.limit_gradient_deg_per_g == pytest.approx(2.0 * (1 - 5.75 / 3.0), abs=0.15)
    assert shape.limit_high_mps2 == pytest.approx(6.0, abs=0.1)
    assert shape.limit_high_mps2 - shape.limit_low_mps2 == pytest.approx(0.5, abs=0.05)


@pytest.mark.parametrize("peak", [1.5, 2.2, 4.5])
def test_neutral_steer_follows_the_peak(peak):
    shape = steer_shape(*run(quadratic(k1=1.0, peak=peak), seed=int(10 * peak)))
    assert shape.neutral_steer == "peak"
    assert shape.neutral_steer_lateral_acceleration_mps2 == pytest.approx(peak, abs=0.1)
    assert shape.limit_behaviour == "oversteer"


def test_piecewise_linear_bands_are_the_pieces():
    """Kinks on band edges: each band's gradient is its piece's slope (to 0.05 deg/g: the noise, and the
    bin across each kink); the peak is the kink at 4 m/s^2, read 0.13 m/s^2 toward the flatter side (the
    local quadratics round a kink off; a measured curve has none)."""
    shape = steer_shape(*run(piecewise))
    assert [b.gradient_deg_per_g for b in shape.bands] == pytest.approx([2.0, 0.5, 0.5, -3.0, -3.0], abs=0.05)
    assert [b.behaviour for b in shape.bands] == ["understeer"] * 3 + ["oversteer"] * 2
    assert shape.neutral_steer_lateral_acceleration_mps2 == pytest.approx(4.0, abs=0.15)
    assert shape.limit_gradient_deg_per_g == pytest.approx(-3.0, abs=0.1)
    # without noise, only the bins across the kinks
    exact = steer_shape(*run(piecewise, noise=False))
    assert [b.gradient_deg_per_g for b in exact.bands] == pytest.approx([2.0, 0.5, 0.5, -3.0, -3.0], abs=0.02)
    assert exact.bands[0].intercept_deg == pytest.approx(DELTA_A, abs=1e-3)


def test_limit_understeer_after_early_oversteer_has_no_neutral_steer_point():
    """The tadpole's shape: the steer falls first, then rises ever faster to the limit."""
    shape = steer_shape(*run(lambda a: DELTA_A - 1.2 * a / G + 0.12 * np.clip(a - 2.0, 0, None) ** 3 / G))
    assert shape.bands[0].behaviour == "oversteer" and shape.bands[-1].behaviour == "understeer"
    assert shape.neutral_steer == "not reached"
    assert math.isnan(shape.neutral_steer_lateral_acceleration_mps2)
    assert shape.limit_behaviour == "understeer" and shape.limit_gradient_deg_per_g > 2


def test_oversteer_from_the_start():
    shape = steer_shape(*run(lambda a: DELTA_A - 0.5 * a / G - 0.05 * a * a / G))
    assert shape.neutral_steer == "falls from the start"
    assert math.isnan(shape.neutral_steer_lateral_acceleration_mps2)
    assert shape.limit_behaviour == "oversteer"
    assert all(b.behaviour == "oversteer" for b in shape.bands)


def test_understeer_throughout_and_neutral():
    rising = steer_shape(*run(lambda a: DELTA_A + 1.5 * a / G))
    assert rising.neutral_steer == "not reached" and rising.limit_behaviour == "understeer"
    assert rising.limit_gradient_deg_per_g == pytest.approx(1.5, abs=0.15)
    flat = steer_shape(*run(lambda a: DELTA_A + 0.1 * a / G))
    assert flat.limit_behaviour == "neutral" and all(b.behaviour == "neutral" for b in flat.bands)
    assert flat.neutral_steer == "not reached"


def test_a_long_dwell_at_the_top_does_not_weigh_on_the_fits():
    """A run that ends at its top speed dwells at one a_y (reference-etrike: 30 s): bins weigh alike."""
    a, s = run(quadratic())
    top = a > 5.9
    dwell_a = np.r_[a, np.repeat(a[top], 40)]
    dwell_s = np.r_[s, np.repeat(s[top], 40)]
    plain, dwelt = steer_shape(a, s), steer_shape(dwell_a, dwell_s)
    assert [b.gradient_deg_per_g for b in dwelt.bands] == pytest.approx(
        [b.gradient_deg_per_g for b in plain.bands], abs=0.05)
    assert dwelt.limit_gradient_deg_per_g == pytest.approx(plain.limit_gradient_deg_per_g, abs=0.2)


def test_a_right_turn_is_folded():
    a, s = run(quadratic())
    left, right = steer_shape(a, s), steer_shape(-a, -s)
    assert right.neutral_steer_lateral_acceleration_mps2 == pytest.approx(left.neutral_steer_lateral_acceleration_mps2)
    assert right.limit_behaviour == left.limit_behaviour
    assert [b.gradient_deg_per_g for b in right.bands] == pytest.approx([b.gradient_deg_per_g for b in left.bands])


def test_short_end_bands_merge_and_short_records():
    """A record ending at 4.3 m/s^2: the last 0.3 m/s^2 joins the 3-4 band. A record within one band."""
    shape = steer_shape(*run(lambda a: DELTA_A + 1.0 * a / G, a_end=4.3))
    assert np.ravel([(b.low_mps2, b.high_mps2) for b in shape.bands]) == pytest.approx(
        np.ravel([(0.87, 2.0), (2.0, 3.0), (3.0, 4.3)]), abs=0.06)
    short = steer_shape(*run(lambda a: DELTA_A + 1.0 * a / G, a_end=1.6))
    assert len(short.bands) == 1 and short.bands[0].gradient_deg_per_g == pytest.approx(1.0, abs=0.1)
    assert short.limit_high_mps2 - short.limit_low_mps2 == pytest.approx(0.25 * (1.6 - 0.87), abs=0.05)


def test_pure_pieces():
    a = np.linspace(0.0, 3.0, 31)
    assert line_fit(a, 2.0 + 0.5 * a) == pytest.approx((0.5 * G, 2.0))
    assert all(math.isnan(v) for v in line_fit([1.0], [2.0]))
    assert [behaviour(k) for k in (0.3, 0.25, 0.0, -0.25, -0.3, math.nan)] == [
        "understeer", "neutral", "neutral", "neutral", "oversteer", "neutral"]
    assert behaviour(0.3, tolerance_deg_per_g=0.5) == "neutral"
    bands = band_gradients(a, 2.0 + 0.5 * a, band_width_mps2=1.0)
    assert np.ravel([(lo, hi) for lo, hi, _, _ in bands]) == pytest.approx([0, 1, 1, 2, 2, 3])
    assert [k for _, _, k, _ in bands] == pytest.approx([0.5 * G] * 3)
    spread = np.linspace(0.0, 2.95, 60)
    curve_a, curve_s, counts = steer_curve(np.r_[spread, 4.0], np.r_[spread, 9.0], bin_mps2=0.5)
    assert list(counts) == [10] * 6 and curve_a[-1] < 3.0  # the lone sample's bin is left out
    assert curve_s == pytest.approx(curve_a)
    s = np.array([0.0, 0.02, 0.04, 0.03, 0.0])
    assert first_peak(np.arange(5.0), s) == (2, "peak")
    assert first_peak(np.arange(5.0) * 0.05, s) == (None, "falls from the start")  # peak within 0.2 of start
    assert first_peak(np.arange(5.0), np.array([0.04, 0.03, 0.02, 0.0, -0.01])) == (None, "falls from the start")
    assert first_peak(np.arange(5.0), np.array([0.0, -0.02, -0.03, -0.01, 0.05])) == (None, "not reached")


def test_bad_input():
    a, s = run(quadratic())
    with pytest.raises(InputError, match="road_steer_deg"):
        steer_shape(a, s[:-1])
    with pytest.raises(InputError, match="band_width_mps2"):
        steer_shape(a, s, band_width_mps2=0.0)
    with pytest.raises(InputError, match="neutral_tolerance"):
        steer_shape(a, s, neutral_tolerance_deg_per_g=-1.0)
    with pytest.raises(InputError, match="mixes left and right"):
        steer_shape(np.r_[a, -a], np.r_[s, -s])
    with pytest.raises(InputError, match="needs 5"):
        steer_shape(a[:12], s[:12])


def test_the_diagram_carries_the_shape_to_json_and_the_figure():
    """handling_diagram: the shape of the steer it is given (radians), JSON-safe; the figure marks the
    linear range, the bands, the neutral-steer point and the limit."""
    a, s = run(quadratic())
    zeros = np.zeros_like(a)
    d = handling_diagram(a, np.radians(s), zeros, zeros, radius_m=20.0, wheelbase_m=1.95)
    assert d.shape.neutral_steer_lateral_acceleration_mps2 == pytest.approx(3.0, abs=0.05)
    assert d.fit_start_mps2 == pytest.approx(a.min()) and d.fit_limit_mps2 == pytest.approx(0.2 * G)
    out = json.loads(json.dumps(d.to_dict(), allow_nan=False))
    assert out["shape"]["limit_behaviour"] == "oversteer"
    assert [b["behaviour"] for b in out["shape"]["bands"]][0] == "understeer"
    no_peak = steer_shape(*run(lambda x: DELTA_A + x / G))
    assert json.loads(json.dumps(no_peak.to_dict(), allow_nan=False))["neutral_steer_lateral_acceleration_mps2"] is None
    fig = d.plot()
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any(t.startswith("linear range 0.8") for t in labels)
    assert any(t.startswith("neutral steer: 3.0") for t in labels)
    assert any(t.startswith("limit: oversteer") for t in labels)
    assert any(t == "band gradient: understeer" for t in labels) and any(t == "band gradient: oversteer" for t in labels)
    plt.close(fig)
