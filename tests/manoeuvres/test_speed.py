"""Target speed profiles: values, interpolation, resampling of records, errors."""

import numpy as np
import pytest

from trikedyn.errors import InputError
from trikedyn.manoeuvres import SpeedProfile, constant, from_record, linear
from trikedyn.manoeuvres.speed import DT_S


def _uniform(profile: SpeedProfile):
    step = np.diff(profile.time_s)
    assert profile.time_s[0] == 0.0
    assert step.max() <= DT_S + 1e-12
    assert np.allclose(step, step[0], rtol=0, atol=1e-12)
    for arr in (profile.time_s, profile.speed_mps):
        assert arr.dtype == np.float64 and arr.flags.c_contiguous


def test_constant():
    p = constant(36.0, 5.0)
    _uniform(p)
    assert p.kind == "constant"
    assert p.duration_s == pytest.approx(5.0)
    assert np.all(p.speed_mps == pytest.approx(10.0))
    assert p.at([-1.0, 2.345, 99.0]) == pytest.approx([10.0, 10.0, 10.0])
    assert p.as_array().shape == (p.time_s.size, 2)


def test_constant_duration_not_a_multiple_of_the_step():
    p = constant(18.0, 1.234)
    _uniform(p)
    assert p.duration_s == pytest.approx(1.234)


def test_linear_ramp_and_interpolation():
    # the paper's double lane change: throttle held, speed rising about linearly
    p = linear(10.0, 20.0, 10.0)
    _uniform(p)
    assert p.kind == "linear"
    assert p.speed_mps[0] == pytest.approx(10 / 3.6) and p.speed_mps[-1] == pytest.approx(20 / 3.6)
    assert p.at(5.0) == pytest.approx(15 / 3.6)
    assert p.at(2.505) == pytest.approx((10 + 2.505) / 3.6)
    assert p.at([-3.0, 42.0]) == pytest.approx([10 / 3.6, 20 / 3.6])  # ends hold
    assert linear(30.0, 0.0, 3.0).at(1.5) == pytest.approx(15 / 3.6)
    d = p.to_dict()
    assert d["kind"] == "linear" and d["speed_max_mps"] == pytest.approx(20 / 3.6)


def test_from_record_resamples_to_a_uniform_grid():
    t = np.array([100.0, 100.3, 101.0, 102.5])  # logger time, uneven steps
    v = np.array([4.0, 4.3, 5.0, 5.0])
    p = from_record(t, v)
    _uniform(p)
    assert p.kind == "record"
    assert p.duration_s == pytest.approx(2.5)  # time 0 is the first sample
    assert p.at([0.0, 0.15, 0.65, 2.0]) == pytest.approx([4.0, 4.15, 4.65, 5.0])
    longer = from_record(t, v, duration_s=4.0)
    assert longer.duration_s == pytest.approx(4.0) and longer.speed_mps[-1] == 5.0
    shorter = from_record(t, v, duration_s=1.0)
    assert shorter.speed_mps[-1] == pytest.approx(5.0)


@pytest.mark.parametrize(
    ("call", "where"),
    [
        (lambda: constant(-5.0, 1.0), "speed_kmh"),
        (lambda: constant(float("nan"), 1.0), "speed_kmh"),
        (lambda: constant("fast", 1.0), "speed_kmh"),
        (lambda: constant(20.0, 0.0), "duration_s"),
        (lambda: linear(10.0, -1.0, 5.0), "end_kmh"),
        (lambda: linear(10.0, 20.0, float("inf")), "duration_s"),
        (lambda: from_record([0.0, 1.0, 1.0, 2.0], [1.0, 1.0, 1.0, 1.0]), "time_s[2]"),
        (lambda: from_record([0.0, 2.0, 1.0], [1.0, 1.0, 1.0]), "time_s[2]"),
        (lambda: from_record([0.0, np.nan, 1.0], [1.0, 1.0, 1.0]), "time_s[1]"),
        (lambda: from_record([0.0, 1.0, 2.0], [1.0, np.nan, 1.0]), "speed_mps[1]"),
        (lambda: from_record([0.0, 1.0, 2.0], [1.0, 1.0, -0.5]), "speed_mps[2]"),
        (lambda: from_record([0.0, 1.0, 2.0], [1.0, 1.0]), "speed_mps"),
        (lambda: from_record([0.0], [1.0]), "time_s"),
        (lambda: from_record([0.0, 1.0], [1.0, 1.0], duration_s=-1.0), "duration_s"),
        (lambda: SpeedProfile("ramp", np.array([0.0, 0.01]), np.array([1.0, 1.0])), "kind"),
        (lambda: SpeedProfile("constant", np.array([0.0, 0.5]), np.array([1.0, 1.0])), "time_s"),
    ],
)
def test_errors_name_the_field(call, where):
    with pytest.raises(InputError) as err:
        call()
    assert err.value.where == where
    assert "\n" not in str(err.value)
