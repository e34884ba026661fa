"""Study figures that cannot mislead: main effects only where the design is balanced for the factor, else the
means over the balanced part (said in the title), else one line per setting (trikedyn.study.designs.figures)."""

from __future__ import annotations

import itertools
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from trikedyn.study.designs.figures import AS_GIVEN, factors, main_effects, plan, study_figures

TUTORIAL = Path(__file__).resolve().parents[2] / "docs" / "tutorials" / "design-study.md"
Y_LEFT, Y_RIGHT = "wheels.rear_left.y_m", "wheels.rear_right.y_m"


def _row(manoeuvre="dlc", freight=0.0, k=1.0, c=1.0, left=math.nan, right=math.nan, value=40.0, groups="g"):
    return {"scenario_id": f"s{freight}{k}{c}{left}{manoeuvre}", "groups": groups, "vehicle": "v",
            "manoeuvre": manoeuvre, "freight_kg": freight, "stiffness_scale": k, "damping_scale": c,
            Y_LEFT: left, Y_RIGHT: right, "status": "ok", "threshold_speed_kmh": value, "limit": "lift-off"}


def _tutorial_shaped(value):
    """The tutorial's design (springs, dampers and a wide-track group over three freights), value(f, k, c, wide)."""
    rows = []
    for f in (0.0, 100.0, 200.0):
        for k, c in ((0.8, 1.0), (1.0, 1.0), (1.2, 1.0), (1.0, 0.8), (1.0, 1.2)):
            rows.append(_row(freight=f, k=k, c=c, value=value(f, k, c, False)))
        rows.append(_row(freight=f, left=0.6, right=-0.6, value=value(f, 1.0, 1.0, True), groups="wide-track"))
    return pd.DataFrame(rows)


def _effect(effects, factor, manoeuvre="dlc"):
    rows = effects[(effects["factor"] == factor) & (effects["manoeuvre"] == manoeuvre)]
    return dict(zip(rows["level"], rows["value"], strict=True)), rows


def _signs_agree(effect: dict, pivot: pd.DataFrame) -> None:
    """For every pair of levels, the main effect's difference never has the opposite sign of the pivot table's
    difference at any freight (row), and lies within their range."""
    for lo, hi in itertools.combinations(sorted(effect), 2):
        drawn = effect[hi] - effect[lo]
        per_freight = pivot[hi] - pivot[lo]
        for freight, diff in per_freight.items():
            assert np.sign(drawn) * np.sign(diff) >= 0, (lo, hi, freight, drawn, diff)
        assert per_freight.min() - 1e-9 <= drawn <= per_freight.max() + 1e-9


# ------------------------------------------------------------------------------------------------------------
# the acceptance: the tutorial's own design, run
# ------------------------------------------------------------------------------------------------------------
def _tutorial_files(folder: Path) -> None:
    text = TUTORIAL.read_text(encoding="utf-8")
    for name in ("cargo-trike.toml", "design.toml"):
        body = re.search(rf'```toml title="{re.escape(name)}"\n(.*?)^```', text, re.MULTILINE | re.DOTALL).group(1)
        (folder / name).write_text(body, encoding="utf-8")


def test_the_tutorials_stiffness_main_effect_agrees_with_its_pivot_table_at_every_freight(tmp_path):
    from trikedyn.study import run_study

    _tutorial_files(tmp_path)
    table = run_study(tmp_path / "design.toml", tmp_path / "out", workers=0, progress=False)
    assert len(table) == 18 and (table.status == "ok").all()
    effects = main_effects(table, "threshold")
    for factor, group, column in (("stiffness_scale", "springs", "stiffness_scale"),
                                  ("damping_scale", "dampers", "damping_scale")):
        effect, rows = _effect(effects, factor)
        # the design is not balanced for it (the middle level also meets the other groups): the balanced part
        assert set(rows["basis"]) == {"balanced part"} and (rows["n"] == 3).all()
        other = "damping scale = 1" if factor == "stiffness_scale" else "stiffness scale = 1"
        assert set(rows["over"]) == {f"{other}; {Y_LEFT} & {Y_RIGHT} {AS_GIVEN}"}
        part = table[table.groups.str.contains(group)]
        pivot = part.pivot_table(index="freight_kg", columns=column, values="threshold_speed_kmh")
        assert effect == pytest.approx(pivot.mean().to_dict(), abs=1e-12)
        _signs_agree(effect, pivot)
    freight, rows = _effect(effects, "freight_kg")  # every freight meets the same six configurations
    assert set(rows["basis"]) == {"balanced"} and (rows["n"] == 6).all()
    assert freight == pytest.approx(table.groupby("freight_kg")["threshold_speed_kmh"].mean().to_dict())
    assert (tmp_path / "out" / "fig_threshold.png").stat().st_size > 1000


# ------------------------------------------------------------------------------------------------------------
# the rule on made tables
# ------------------------------------------------------------------------------------------------------------
def test_the_issues_flaw_the_wide_track_no_longer_lifts_the_middle_spring():
    """A wide track far better than any spring: the mean over all rows puts 100 % above 120 %, though 120 % is
    better at every freight; the drawn effect is over the part every spring level meets."""
    table = _tutorial_shaped(lambda f, k, c, wide: 50.0 - f / 50 + 2.0 * k + (6.0 if wide else 0.0))
    naive = table.groupby("stiffness_scale")["threshold_speed_kmh"].mean()
    assert naive[1.0] > naive[1.2]  # the misleading figure
    effect, rows = _effect(main_effects(table), "stiffness_scale")
    assert effect[1.2] - effect[1.0] == pytest.approx(0.4) and effect[1.0] - effect[0.8] == pytest.approx(0.4)
    assert set(rows["over"]) == {f"damping scale = 1; {Y_LEFT} & {Y_RIGHT} {AS_GIVEN}"}
    springs = table[table[Y_LEFT].isna() & (table.damping_scale == 1.0)]
    _signs_agree(effect, springs.pivot_table(index="freight_kg", columns="stiffness_scale",
                                             values="threshold_speed_kmh"))


def test_an_override_left_empty_is_a_level_and_moving_columns_are_one_factor():
    table = _tutorial_shaped(lambda f, k, c, wide: 40.0 + wide)
    assert factors(table) == ["freight_kg", "stiffness_scale", "damping_scale", Y_LEFT, Y_RIGHT]
    assert plan(table) == [("threshold", "main effects", factors(table))]
    effects = main_effects(table)
    assert list(dict.fromkeys(effects["factor"])) == ["freight_kg", "stiffness_scale", "damping_scale",
                                                      f"{Y_LEFT} & {Y_RIGHT}"]
    track, rows = _effect(effects, f"{Y_LEFT} & {Y_RIGHT}")
    assert list(rows["level_label"]) == [AS_GIVEN, "0.6, -0.6"]
    assert track == {(None, None): 40.0, (0.6, -0.6): 41.0}
    assert set(rows["over"]) == {"stiffness scale = 1; damping scale = 1"}
    # the wide-track group alone: one factor (the two columns), a line against it
    wide_only = table[(table.stiffness_scale == 1.0) & (table.damping_scale == 1.0) & (table.freight_kg == 0.0)]
    assert plan(wide_only)[0][1] == "one factor"


def test_a_full_grid_is_balanced_and_its_main_effects_are_the_plain_means(tmp_path):
    rows = [_row(manoeuvre=m, freight=f, k=k, c=c, value=45.0 - f / 40 + 5 * k - c + (m == "slc"))
            for m in ("dlc", "slc") for f in (0.0, 100.0) for k in (0.8, 1.2) for c in (0.8, 1.0, 1.2)]
    table = pd.DataFrame(rows)
    effects = main_effects(table)
    assert set(effects["basis"]) == {"balanced"} and set(effects["over"]) == {""}
    for factor in ("freight_kg", "stiffness_scale", "damping_scale"):
        for man in ("dlc", "slc"):
            plain = table[table.manoeuvre == man].groupby(factor)["threshold_speed_kmh"].mean().to_dict()
            assert _effect(effects, factor, man)[0] == pytest.approx(plain)
    assert [p.name for p in study_figures(table, tmp_path)] == ["fig_threshold.png"]


def test_no_setting_met_by_every_level_gives_a_line_per_setting(tmp_path):
    """Springs 0.8 and 1.0 only with the standard dampers, 1.2 only with soft ones: no mean is honest."""
    rows = [_row(freight=f, k=k, c=1.0, value=40.0 + k) for f in (0.0, 100.0) for k in (0.8, 1.0)]
    rows += [_row(freight=f, k=1.2, c=0.8, value=30.0) for f in (0.0, 100.0)]
    rows += [_row(freight=f, k=1.0, c=0.8, value=35.0) for f in (0.0, 100.0)]
    table = pd.DataFrame(rows)
    effect, got = _effect(main_effects(table), "stiffness_scale")
    assert set(got["basis"]) == {"per setting"} and set(got["line"]) == {
        "freight = 0; damping scale = 1", "freight = 100; damping scale = 1",
        "freight = 0; damping scale = 0.8", "freight = 100; damping scale = 0.8"}
    assert len(got) == 8 and (got["n"] == 1).all()  # 0.8 and 1.2 meet two settings each, 1.0 four
    assert study_figures(table, tmp_path)[0].stat().st_size > 1000


def test_a_setting_run_twice_does_not_weigh_double():
    rows = [_row(freight=f, k=k, c=c, value=40.0) for f in (0.0, 100.0) for k in (0.8, 1.2) for c in (0.8, 1.2)]
    rows.append(_row(freight=0.0, k=0.8, c=0.8, value=10.0))  # a replicate of one setting
    effect, got = _effect(main_effects(pd.DataFrame(rows)), "stiffness_scale")
    assert set(got["basis"]) == {"balanced"}
    assert effect[0.8] == pytest.approx((25.0 + 40.0 * 3) / 4) and effect[1.2] == 40.0


def test_failed_scenarios_are_left_out_before_the_balance_is_judged():
    rows = [_row(freight=f, k=k, c=c, value=40.0 + k) for f in (0.0, 100.0) for k in (0.8, 1.2) for c in (0.8, 1.2)]
    rows[0]["threshold_speed_kmh"] = math.nan  # freight 0, k 0.8, c 0.8 failed
    effect, got = _effect(main_effects(pd.DataFrame(rows)), "stiffness_scale")
    assert set(got["basis"]) == {"balanced part"} and (got["n"] == 3).all()
    assert effect == pytest.approx({0.8: 40.8, 1.2: 41.2})
