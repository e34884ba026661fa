"""trikedyn.analysis.search_settings: one set of defaults and bounds for the threshold search, the same on the
command line, in a study spec and in an optimise spec."""

import pytest

from trikedyn.analysis.search_settings import SEARCH_DEFAULTS, SearchSettings, search_option, search_options
from trikedyn.analysis.verdict import Judging
from trikedyn.cli import main
from trikedyn.errors import InputError
from trikedyn.study.optimise_spec import parse_optimise_spec
from trikedyn.study.spec import parse_spec


def test_defaults_are_the_options_defaults_and_the_search_functions():
    import inspect

    from trikedyn.analysis.threshold import threshold_velocity

    settings = SearchSettings()
    assert settings.to_dict() == {o.name: o.default for o in search_options()} == dict(SEARCH_DEFAULTS)
    assert (settings.low_kmh, settings.high_kmh, settings.step_kmh, settings.resolution_kmh) == (10.0, 90.0, 10.0, 0.1)
    assert (settings.criterion, settings.speed_control, settings.method) == ("course", "driver", "margin")
    signature = inspect.signature(threshold_velocity).parameters
    for name in ("low_kmh", "high_kmh", "step_kmh", "resolution_kmh", "method", "criterion", "speed_control"):
        assert signature[name].default == getattr(settings, name), name
    assert settings.judging() == Judging()


def test_round_trip_and_changes_are_checked_again():
    settings = SearchSettings(low_kmh=20, high_kmh=120.0, resolution_kmh=0.5, criterion="both", speed_control="ideal")
    assert isinstance(settings.low_kmh, float) and settings.low_kmh == 20.0
    assert SearchSettings.from_dict(settings.to_dict()) == settings
    assert SearchSettings.from_dict({"high_kmh": 120.0, "other": 1}) == SearchSettings(high_kmh=120.0)
    assert settings.with_(high_kmh=60.0).high_kmh == 60.0
    with pytest.raises(InputError, match="low_kmh"):
        settings.with_(high_kmh=15.0)
    kwargs = settings.threshold_kwargs()
    assert kwargs["judging"] == Judging() and kwargs["criterion"] == "both" and kwargs["high_kmh"] == 120.0


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"high_kmh": 500.0}, "high_kmh: must be within [1, 400] km/h, got 500"),
        ({"low_kmh": 0.0}, "low_kmh: must be within [0.1, 400] km/h, got 0"),
        ({"resolution_kmh": 20.0}, "resolution_kmh: must be within [0.001, 10] km/h, got 20"),
        ({"step_kmh": float("nan")}, "step_kmh: expected a finite number"),
        ({"low_kmh": 50.0, "high_kmh": 20.0}, "low_kmh (50) must be below high_kmh (20)"),
        ({"criterion": "curse"}, "did you mean 'course'?"),
        ({"speed_control": "drive"}, "expected one of driver, ideal"),
        ({"speed_band_percent": 0.0, "speed_band_kmh": 0.0}, "no speed can be held"),
        ({"speed_band_kmh": 101.0}, "speed_band_kmh: must be within [0, 100] km/h"),
        ({"high_kmh": "90"}, "high_kmh: expected a number"),
    ],
)
def test_bad_settings_are_refused_naming_the_setting(changes, message):
    with pytest.raises(InputError) as info:
        SearchSettings(**changes)
    assert message in str(info.value) and "\n" not in str(info.value)


def test_an_option_is_found_by_name_with_a_close_match():
    assert search_option("high_kmh").maximum == 400.0
    with pytest.raises(InputError, match="did you mean 'high_kmh'"):
        search_option("hgh_kmh")


def _one_line(capsys, code):
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("trikedyn: error: ") and err.count("\n") == 1, err
    return err


@pytest.mark.parametrize("high", ["500", "0.5"])
def test_the_cli_the_study_spec_and_the_optimise_spec_refuse_the_same_high_kmh(capsys, tmp_path, high):
    """One set of bounds: the same out-of-range highest speed is refused by each, in one line, with the same
    words (before, the study spec stopped at 300, the sampled designs at 11..400, threshold at 0..400)."""
    words = f"must be within [1, 400] km/h, got {float(high):g}"
    for argv in (["threshold", "reference-etrike", "--high", high],
                 ["compare-layouts", "reference-etrike", "--high", high],
                 ["sensitivity", "reference-etrike", "--high", high],
                 ["uncertainty", "reference-etrike", "--high", high],
                 ["loading-chart", "reference-etrike", "--high", high],
                 ["optimise", "battery-layout", "--high", high]):
        err = _one_line(capsys, main(argv))
        assert f"--high: {words}" in err, (argv, err)
    spec = tmp_path / "s.toml"
    spec.write_text(f'name = "s"\nmanoeuvres = ["slc"]\nhigh_kmh = {high}\n', encoding="utf-8")
    err = _one_line(capsys, main(["study", str(spec), "--dry-run"]))
    assert f"high_kmh: {words}" in err, err
    with pytest.raises(InputError) as info:
        parse_spec(spec.read_text(encoding="utf-8"), origin="s.toml")
    assert f"high_kmh: {words}" in str(info.value)
    with pytest.raises(InputError) as info:
        parse_optimise_spec(f'[optimise]\nknobs = {{ "track_m" = [1.0, 1.2] }}\nhigh_kmh = {high}\n', origin="o.toml")
    assert f"high_kmh: {words}" in str(info.value)


def test_a_high_kmh_within_the_bounds_is_taken_everywhere():
    """300 < 350 <= 400: the study spec took at most 300 before; now each takes it."""
    spec = parse_spec('name = "s"\nmanoeuvres = ["slc"]\nhigh_kmh = 350\n')
    assert spec.high_kmh == 350.0 and spec.search.high_kmh == 350.0
    opt = parse_optimise_spec('[optimise]\nknobs = { "track_m" = [1.0, 1.2] }\nhigh_kmh = 350\n')
    assert opt.high_kmh == 350.0
