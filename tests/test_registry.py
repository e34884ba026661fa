"""The one generic registry (trikedyn.registry): every extension point is one module that registers itself.

From this test: a manoeuvre, an IMU log layout, a run metric, a study metric and a tyre model, each one file
under ``tests/plugins/``, registered (imported), found by name where the program looks them up, unregistered
after; an entry-point plug-in installed into the test's environment; duplicates and close matches.
"""

from __future__ import annotations

import importlib
import json
import sys
import warnings

import numpy as np
import pytest

from trikedyn.cli import main
from trikedyn.errors import InputError, LogFormatError
from trikedyn.options import Option
from trikedyn.registry import PluginWarning, Registry, did_you_mean


def _plugin(module: str, registry, name: str):
    """Import ``tests.plugins.<module>`` afresh (it registers ``name`` in ``registry``); a fixture's body."""
    full = f"tests.plugins.{module}"
    sys.modules.pop(full, None)
    assert name not in registry
    mod = importlib.import_module(full)
    assert name in registry
    try:
        yield mod
    finally:
        if name in registry:
            registry.unregister(name)
        sys.modules.pop(full, None)
    assert name not in registry


def _fixture(module: str, registry: str, name: str):
    """A fixture that registers the plug-in ``module`` for one test; ``registry`` is ``"module:ATTRIBUTE"``."""

    @pytest.fixture
    def plugin():
        where, attribute = registry.split(":")
        yield from _plugin(module, getattr(importlib.import_module(where), attribute), name)

    return plugin


cruise = _fixture("cruise_manoeuvre", "trikedyn.manoeuvres.registry:MANOEUVRES", "test-cruise")
pothole = _fixture("pothole_layout", "trikedyn.measure.formats:FORMATS", "test-pothole")
span_metric = _fixture("span_metric", "trikedyn.analysis.metrics:METRICS", "test_window_span_s")
wheelbase_metric = _fixture("wheelbase_metric", "trikedyn.study.metrics:STUDY_METRICS", "test_wheelbase")
soft_tyre = _fixture("soft_tyre", "trikedyn.tyre.models:TYRE_MODELS", "test-soft")


# ------------------------------------------------------------------------------------------------
# one file each, found by name
# ------------------------------------------------------------------------------------------------
def test_a_manoeuvre_from_one_file_is_listed_built_and_recorded(cruise, reference, capsys):
    from trikedyn.manoeuvres.registry import build

    assert main(["manoeuvres", "--json"]) == 0
    listed = {k["name"]: k for k in json.loads(capsys.readouterr().out)}
    assert listed["test-cruise"]["options"] == [{"name": "length_m", "default": 80.0, "unit": "m",
                                                 "help": "length of the straight", "minimum": 20.0,
                                                 "maximum": 500.0}]
    man = build("test-cruise", reference.params, 30.0, length_m="120")
    assert man.parameters == {"length_m": 120.0}  # recorded from the option table, not restated
    assert (man.window.start, man.window.end) == (30.0, 90.0)
    assert build("test-cruise", reference.params, 30.0).parameters == {"length_m": 80.0}
    with pytest.raises(InputError, match=r"test-cruise.length_m: option 'length_m' must be within \[20, 500\] m"):
        build("test-cruise", reference.params, 30.0, length_m=5)


def test_a_run_metric_from_one_file_is_in_the_runs_summary(cruise, span_metric, capsys):
    from trikedyn.analysis.metrics import evaluate

    code = main(["simulate", "reference-etrike", "--manoeuvre", "test-cruise", "--speed", "36", "-o",
                 "length_m=60", "--json"])
    out = capsys.readouterr().out
    assert code == 0, out
    summary = json.loads(out)
    found = summary.get("test_window_span_s", summary.get("metrics", {}).get("test_window_span_s"))
    # 30 m judged at 10 m/s: about 3 s (the driver holds the speed within its band)
    assert found == pytest.approx(3.0, abs=0.3)

    class Judged:
        time_s = np.array([0.0, 1.0, 2.0, 3.5])
        channels: dict = {}
        manoeuvre = None

        def __getitem__(self, name):
            raise KeyError(name)

    assert evaluate(Judged(), "test_window_span_s") == pytest.approx(3.5)  # no manoeuvre: all of it is judged


def test_a_log_layout_from_one_file_is_detected_and_read(pothole, tmp_path, capsys):
    from trikedyn.measure.logs import FORMATS, detect_format, read_log

    log = tmp_path / "ride.txt"
    log.write_text("#POTHOLE-T[ms];Gz[g]\n" + "".join(f"{20 * i};{1 + 0.01 * i:.3f}\n" for i in range(30)))
    assert "test-pothole" in FORMATS and detect_format(log) == "test-pothole"
    data = read_log(log)
    assert data.format == "test-pothole" and data.sample_rate_hz == pytest.approx(50.0)
    assert data.channel("az_mps2")[-1] == pytest.approx(1.29 * 9.80665)
    assert main(["log", "info", str(log), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["format"] == "test-pothole"


def test_a_study_metric_from_one_file_is_parsed_and_evaluated(wheelbase_metric, reference):
    from trikedyn.study.metrics import get, label, parse_entry
    from trikedyn.study.spec import parse_spec

    spec = parse_spec('name = "x"\nmanoeuvres = ["slc"]\nmetrics = [{ name = "test_wheelbase", factor = 2 }]\n')
    assert [name for name, _ in spec.metrics] == ["test_wheelbase"]
    name, options = parse_entry({"name": "test_wheelbase", "factor": 2})
    assert label(name, options) == "test_wheelbase(factor=2)"
    assert get(name).fn(reference, {}, **options)["value"] == pytest.approx(2 * reference.params.wheelbase_m)
    with pytest.raises(InputError, match="option 'factor' must be within"):
        parse_entry({"name": "test_wheelbase", "factor": 9})


def test_a_tyre_model_from_one_file_takes_its_wheel(soft_tyre, reference):
    from trikedyn.model.linear import single_track
    from trikedyn.model.vehicle import build_model
    from trikedyn.params.springs import wheel_tyre
    from trikedyn.tyre.interface import SIMILARITY, linear_stiffnesses

    params = reference.params
    model = build_model(reference)
    names = [w.name for w in model.tree.wheels]
    k = names.index("front")
    assert model.tyres[k].name == "test-soft" and model.plant.wheels[k]["tyre_model"] == SIMILARITY
    assert model.plant.wheels[k]["relaxation_x"] == pytest.approx(soft_tyre.RELAXATION_M)
    assert model.plant.wheels[k]["vertical_stiffness"] == pytest.approx(0.5 * params.tyre.vertical_stiffness_N_per_m)
    assert all(t.name == "similarity" for i, t in enumerate(model.tyres) if i != k)
    soft = linear_stiffnesses("test-soft", model.tyres[k].coefficients, 2000.0)
    plain = linear_stiffnesses("similarity", model.tyres[k].coefficients, 2000.0)
    assert soft == pytest.approx((0.8 * plain[0], 0.8 * plain[1]))
    assert wheel_tyre(params, params.wheel("front")).label == "soft test tyre"
    assert wheel_tyre(params, params.wheel("rear_left")).label == "Magic Formula of [tyre]"
    track = single_track(model)  # the one front wheel's cornering stiffness is the soft tyre's
    expected = 0.8 * linear_stiffnesses("similarity", model.tyres[k].coefficients, track.front_load_N)[1]
    assert track.front_cornering_stiffness_N_per_rad == pytest.approx(expected, rel=1e-12)


def test_the_tyre_model_leaves_with_its_plugin(reference):
    from trikedyn.model.vehicle import build_model

    assert all(t.name == "similarity" for t in build_model(reference).tyres)


# ------------------------------------------------------------------------------------------------
# an entry-point plug-in installed into the test's environment
# ------------------------------------------------------------------------------------------------
EP_MODULE = '''
from trikedyn.manoeuvres import paths, speed
from trikedyn.manoeuvres.base import path_manoeuvre
from trikedyn.manoeuvres.registry import register
from trikedyn.measure.formats import TableFormat


@register("ep-straight", "straight line (entry-point plug-in)")
def build(params, speed_kmh):
    """A straight line from a plug-in distribution."""
    return path_manoeuvre("ep-straight", "straight", paths.straight(60.0), speed.constant(speed_kmh, 1.0),
                          entry_m=10.0, exit_m=50.0)


class EpLayout(TableFormat):
    """Registered by the registry (adopted), not by this module."""

    name = "ep-layout"
    description = "entry-point layout"
    columns = {"EP_T": ("time_s", 1.0), "EP_AZ": ("az_mps2", 1.0)}
'''


@pytest.fixture
def installed(tmp_path, monkeypatch):
    """A distribution ``trike-ep-plugin`` on ``sys.path``: its module and its entry points."""
    site = tmp_path / "site"
    dist = site / "trike_ep_plugin-0.1.dist-info"
    dist.mkdir(parents=True)
    (site / "trike_ep_plugin.py").write_text(EP_MODULE)
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: trike-ep-plugin\nVersion: 0.1\n")
    (dist / "entry_points.txt").write_text(
        "[trikedyn.manoeuvres]\nep-straight = trike_ep_plugin\nep-broken = trike_ep_no_such_module\n\n"
        "[trikedyn.log_formats]\nep-layout = trike_ep_plugin:EpLayout\n")
    monkeypatch.syspath_prepend(str(site))
    importlib.invalidate_caches()
    yield site
    from trikedyn.manoeuvres.registry import MANOEUVRES
    from trikedyn.measure.formats import FORMATS

    for registry, name in ((MANOEUVRES, "ep-straight"), (FORMATS, "ep-layout")):
        if name in registry:
            registry.unregister(name)
    sys.modules.pop("trike_ep_plugin", None)


def test_an_entry_point_plugin_is_found_by_name(installed, reference, tmp_path):
    from importlib.metadata import entry_points

    from trikedyn.manoeuvres.registry import MANOEUVRES, build, get
    from trikedyn.measure.logs import read_log

    assert {e.name for e in entry_points(group="trikedyn.manoeuvres")} >= {"ep-straight", "ep-broken"}
    with pytest.warns(PluginWarning, match="manoeuvre plug-in 'ep-broken'.*failed to load"):
        kind = get("ep-straight")  # not registered before: the lookup searches the entry points
    assert kind.title == "straight line (entry-point plug-in)" and "ep-straight" in MANOEUVRES.names()
    assert build("ep-straight", reference.params, 30.0).window.end == 50.0
    log = tmp_path / "ep.csv"
    log.write_text("EP_T,EP_AZ\n0,9.8\n0.1,9.9\n")
    assert read_log(log, "ep-layout").format == "ep-layout"  # adopted: the class registered under its name
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a broken plug-in warns once, not at every lookup
        get("dlc")


# ------------------------------------------------------------------------------------------------
# one duplicate policy, one close-match error, one option type
# ------------------------------------------------------------------------------------------------
def test_a_duplicate_name_raises_unless_replaced(reference):
    from trikedyn.analysis.metrics import metric
    from trikedyn.manoeuvres.registry import register
    from trikedyn.study.metrics import study_metric
    from trikedyn.tyre.models import TYRE_MODELS
    from trikedyn.tyre.models import register as register_tyre

    with pytest.raises(ValueError, match="manoeuvre 'dlc' is already registered"):
        register("dlc", "another DLC")(lambda params, speed_kmh: None)
    with pytest.raises(ValueError, match="metric 'max_abs_ri' is already registered"):
        metric("max_abs_ri")(lambda result: 0.0)
    with pytest.raises(ValueError, match="metric 'threshold' is already registered"):
        study_metric("threshold", per_manoeuvre=True)(lambda pset, scenario: {"value": 0.0})
    with pytest.raises(ValueError, match="tyre model 'similarity' is already registered"):
        register_tyre(TYRE_MODELS.get("similarity"))
    shapes = Registry("shape")
    shapes.register("square", 1)
    with pytest.raises(ValueError, match="shape 'square' is already registered"):
        shapes.register("square", 2)
    shapes.register("square", 2, replace=True)
    assert shapes.get("square") == 2 and shapes.names() == ("square",)


def test_an_unknown_name_is_one_error_with_a_close_match():
    from trikedyn.analysis.metrics import evaluate
    from trikedyn.manoeuvres.registry import get
    from trikedyn.measure.formats import get as get_format
    from trikedyn.study.metrics import get as get_study_metric
    from trikedyn.tyre.models import get as get_tyre

    with pytest.raises(InputError, match="unknown manoeuvre 'dcl'; did you mean 'dlc'?"):
        get("dcl")
    with pytest.raises(InputError, match="unknown metric 'max_abs_rii'; did you mean 'max_abs_ri'?"):
        evaluate(None, "max_abs_rii")
    with pytest.raises(LogFormatError, match="unknown format 'phyphoxx'; did you mean 'phyphox'?"):
        get_format("phyphoxx")
    with pytest.raises(InputError, match="unknown metric 'tilt_angel'; did you mean 'tilt_angle'?"):
        get_study_metric("tilt_angel")
    with pytest.raises(InputError, match="unknown tyre model 'similarty'; did you mean 'similarity'?"):
        get_tyre("similarty")
    with pytest.raises(InputError, match="unknown tyre model 'zzz'; known: similarity, magic-formula"):
        get_tyre("zzz")
    assert did_you_mean("dlk", ["dlc", "slc"]) == "; did you mean 'dlc'?" and did_you_mean("x", ["dlc"]) == ""


def test_an_option_states_its_unit_and_bounds_once():
    speed = Option("speed_kmh", None, "km/h", "speed of the run", minimum=1.0, maximum=300.0)
    assert speed.required and not speed.is_word
    assert speed.parse("40", "x") == 40.0
    with pytest.raises(InputError, match="expected a number, got '40'"):
        speed.parse("40", "x", text=False)  # a typed file gives numbers as numbers
    with pytest.raises(InputError, match=r"x: option 'speed_kmh' must be within \[1, 300\] km/h, got 400"):
        speed.parse(400, "x")
    with pytest.raises(InputError, match="expected a finite number"):
        speed.parse(float("nan"), "x")
    side = Option("direction", "left", choices=("left", "right"))
    assert side.is_word and side.parse("right", "x") == "right"
    with pytest.raises(InputError, match="expected one of left, right, got 'rihgt'; did you mean 'right'?"):
        side.parse("rihgt", "x")
    assert Option("rate", 0.0, minimum=0.0).to_dict() == {"name": "rate", "default": 0.0, "unit": "", "help": "",
                                                         "minimum": 0.0}
