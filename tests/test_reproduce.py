"""`trikedyn reproduce`: the measurement side of the paper, end to end."""

import json

import pytest

from trikedyn.cli import main


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("repro")
    assert main(["reproduce", "--out", str(out), "--no-study"]) == 0  # the study has its own tests
    return out


def test_writes_tables_figures_and_summary(run):
    names = {p.name for p in run.iterdir()}
    assert {"table1_equations.csv", "table1_identified.csv", "table1_model_bump.csv", "table3.csv", "audit.json",
            "manoeuvres.csv", "summary.md", "summary.json", "report.html"} <= names
    assert {"fig7_slc.png", "fig8_dlc.png", "fig9_rollover_index.png", "fig2_model_bump_front.png"} <= names
    for png in run.glob("*.png"):
        assert png.stat().st_size > 10_000


def test_summary_states_each_finding_with_numbers(run):
    summary = json.loads((run / "summary.json").read_text())
    verdicts = {s["paper"][:20]: s["verdict"] for s in summary["statements"]}
    assert verdicts["Eq. 4, C = 2 xi sqrt"] == "contradicts"
    assert verdicts["Table 3: CG against "] == "reproduces"
    assert all(row["max_abs_error_mm"] < 0.5 for row in summary["table3"])
    ratios = [row["ratio_eq4_to_table1"] for row in summary["table1_equations"]]
    assert ratios == pytest.approx([9.535, 9.669], abs=0.01)


def test_identification_recovers_the_models_suspension(run):
    """Closing the loop on the quarter car: emulated 10 Hz bump records give back K and C."""
    summary = json.loads((run / "summary.json").read_text())
    for row in summary["table1_identified"]:
        assert abs(row["stiffness_error_pct"]) < 3.0, row
        assert abs(row["damping_error_pct"]) < 10.0, row
        assert row["identified_frequency_hz"] == pytest.approx(row["body_mode_frequency_hz"], rel=0.02)


def test_model_bump_test_comes_close_to_the_models_suspension(run):
    """Closing the loop on the multibody model: its seat sensor at 10 Hz gives back K within 10 %."""
    summary = json.loads((run / "summary.json").read_text())
    for row in summary["table1_model_bump"]:
        assert abs(row["stiffness_error_pct"]) < 10.0, row


def test_manoeuvres_completed_and_ri_static(run):
    summary = json.loads((run / "summary.json").read_text())
    assert all(row["cone_strikes"] == 0 and not row["wheel_lifted"] for row in summary["manoeuvres"])
    assert summary["static_rollover_index"] == pytest.approx(-0.0518, abs=2e-3)
    assert "data:image/png;base64," in (run / "report.html").read_text()


def test_reproduce_report_renders_in_headless_chromium(run, tmp_path):
    """The real report of `reproduce` in headless Chromium: no console message, every figure drawn."""
    import numpy as np
    from matplotlib import image as mpimg

    from .report.test_html import _console_messages, _Images, _render

    shot, dom, err = _render(run / "report.html", tmp_path)
    assert _console_messages(err) == [], "\n".join(_console_messages(err))
    images = _Images()
    images.feed(dom)
    assert len(images.sources) >= 6 and all(s.startswith("data:image/png;base64,") for s in images.sources)
    rgb = mpimg.imread(shot)[..., :3]
    assert len(np.unique((rgb * 255).round().astype(np.uint8).reshape(-1, 3), axis=0)) >= 256
    assert rgb.std() >= 0.05
