"""Requirements files: parsing, judging (margins, tolerance, a metric as bound, a missing value), errors."""

from __future__ import annotations

import pytest

from trikedyn.assess.requirements import METRICS, judge, load_requirements, parse_requirements, preset_names
from trikedyn.errors import InputError

GOOD = """
title = "t"
[[requirement]]
id = "tilt"
metric = "tilt_angle_deg"
at_least = 35
[[requirement]]
id = "dlc"
metric = "dlc_threshold_kmh"
at_least = "top_speed_kmh"
tolerance = 0.1
[[requirement]]
id = "band"
metric = "understeer_gradient_deg_per_g"
at_least = 0
at_most = 2
laden = true
"""


def test_parse_and_judge_margins():
    reqs = parse_requirements(GOOD, "good.toml")
    values = {"tilt_angle_deg": 34.0, "dlc_threshold_kmh": 54.8, "top_speed_kmh": 54.86,
              "understeer_gradient_deg_per_g": 2.5}
    seen = []

    def value_of(item, metric):
        seen.append((item.id, item.laden))
        return values[metric]

    j = {x.id: x for x in judge(reqs, value_of)}
    assert not j["tilt"].passed and j["tilt"].margin == pytest.approx(-1.0) and j["tilt"].verdict == "FAIL"
    assert j["dlc"].passed and j["dlc"].margin == pytest.approx(-0.06)  # within the 0.1 km/h tolerance
    assert "top_speed_kmh (54.86)" in j["dlc"].bound
    assert not j["band"].passed and j["band"].margin == pytest.approx(-0.5)  # the smaller of the two margins
    assert ("band", True) in seen and j["band"].detail == "laden"


def test_missing_value_fails_and_says_so():
    reqs = parse_requirements(GOOD, "good.toml")
    j = judge(reqs, lambda item, metric: None if metric == "dlc_threshold_kmh" else 40.0)
    dlc = next(x for x in j if x.id == "dlc")
    assert not dlc.passed and dlc.margin is None and "dlc_threshold_kmh not found" in dlc.detail


def test_presets_parse_and_name_their_source():
    assert {"trikedyn-defaults", "tilt-35-single-deck"} <= set(preset_names())
    for name in preset_names():
        reqs = load_requirements(name)
        assert reqs.source.strip() and reqs.items
    assert "not a regulation" in load_requirements("trikedyn-defaults").title
    assert "Regulation 57" in load_requirements("tilt-35-single-deck").source


@pytest.mark.parametrize(("text", "needle"), [
    ("[[requirement]\nid=1", "not valid TOML"),
    ("", "no requirement"),
    ("[[requirement]]\nid = 'a'\nmetric = 'tilt_angel_deg'\nat_least = 3", "did you mean 'tilt_angle_deg'"),
    ("[[requirement]]\nid = 'a'\nmetric = 'tilt_angle_deg'", "give 'at_least', 'at_most' or both"),
    ("[[requirement]]\nid = 'a'\nmetric = 'tilt_angle_deg'\nat_least = 'fast'", "unknown metric 'fast'"),
    ("[[requirement]]\nid = 'a'\nmetric = 'tilt_angle_deg'\nat_lest = 3", "unknown key 'at_lest'"),
    ("[[requirement]]\nid = 'a'\nmetric = 'max_abs_ri'\nat_most = 1", "needs 'manoeuvre'"),
    ("[[requirement]]\nid = 'a'\nmetric = 'max_abs_ri'\nmanoeuvre = 'dlcc'\nspeed_kmh = 30\nat_most = 1",
     "unknown manoeuvre"),
    ("[[requirement]]\nid = 'a'\nmetric = 'tilt_angle_deg'\nat_least = nan", "must be finite"),
    ("[[requirement]]\nid = 'a'\nmetric = 'tilt_angle_deg'\nat_least = 1\n[[requirement]]\nid = 'a'\n"
     "metric = 'mass_kg'\nat_most = 1", "given twice"),
])
def test_malformed_files_name_the_file(text, needle):
    with pytest.raises(InputError, match=needle) as err:
        parse_requirements(text, "bad.toml")
    assert str(err.value).startswith("bad.toml")


def test_every_metric_is_documented():
    for name, metric in METRICS.items():
        assert metric.unit and metric.description, name
