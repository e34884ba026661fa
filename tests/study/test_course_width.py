"""Designs lay a width-dependent course out for the reference vehicle (issue 20): a wider variant meets the same
ISO 3888 lanes, not easier ones, unless asked (``course_width_m = 0``: each variant's own)."""

import numpy as np
import pytest

from trikedyn.manoeuvres.registry import build
from trikedyn.params.knobs import apply_knobs
from trikedyn.study.designs.sample_runs import Search
from trikedyn.study.scenarios import expand
from trikedyn.study.spec import parse_spec


def test_the_double_lane_change_takes_the_width_it_is_laid_out_for(reference):
    wide = apply_knobs(reference, {"track_m": 1.3})
    assert wide.params.body.overall_width_m > reference.params.body.overall_width_m
    own = build("dlc", wide.params, 40.0)
    same = build("dlc", wide.params, 40.0, course_width_m=reference.params.body.overall_width_m)
    base = build("dlc", reference.params, 40.0)
    assert np.array_equal(same.path.cones, base.path.cones) and not np.array_equal(own.path.cones, base.path.cones)
    assert same.parameters["course_width_m"] == reference.params.body.overall_width_m
    with pytest.raises(Exception, match="course_width_m"):
        build("dlc", reference.params, 40.0, course_width_m=-1.0)


def test_a_design_search_meets_the_reference_course(reference):
    width = reference.params.body.overall_width_m
    dlc = Search("dlc").on_course_of(reference)
    assert dlc.options == {"course_width_m": width} and f"{width:.3f} m wide vehicle" in dlc.course_note()
    assert Search("slc").on_course_of(reference).options == {} and Search("slc").course_note() is None
    asked = Search("dlc", {"course_width_m": "0"}).on_course_of(reference)
    assert asked.options == {"course_width_m": "0"} and "each variant's own" in asked.course_note()


def test_study_scenarios_carry_the_base_width_for_the_lane_changes_only(reference):
    spec = parse_spec({"name": "w", "manoeuvres": ["dlc", "slc"], "metrics": ["threshold", "tilt_angle"],
                       "groups": [{"name": "track", "overrides": {"track_m": [1.1, 1.3]}}]})
    rows = expand(spec)
    dlc = [s for s in rows if s["manoeuvre"] == "dlc"]
    assert dlc and all(s["course_width_m"] == reference.params.body.overall_width_m for s in dlc)
    assert all(s["course_width_m"] is None for s in rows if s["manoeuvre"] != "dlc")
