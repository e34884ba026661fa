"""`trikedyn reproduce` (:mod:`trikedyn.paper`): the paper's workflow end to end, and its report in a browser."""

import json
import re

import pytest
from PIL import Image

from trikedyn.cli import main

from .browser import WIDTHS, Images, assert_fits_and_loads, console_messages, probe, render


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
    assert {"animation_slc.gif", "animation_dlc.gif"} <= names
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


def test_lane_change_animations_are_small_gifs(run):
    for name in ("animation_slc.gif", "animation_dlc.gif"):
        with Image.open(run / name) as gif:
            assert gif.format == "GIF" and gif.n_frames >= 5 and gif.size[0] <= 600
        assert (run / name).stat().st_size < 400_000


def test_report_shows_each_statement_once_with_equations_and_human_headers(run):
    doc = (run / "report.html").read_text(encoding="utf-8")
    summary = json.loads((run / "summary.json").read_text())
    titles = re.findall(r"<h2>\d+\. ([^<]+)</h2>", doc)
    assert len(titles) == len(set(titles)) and sum("Table 1" in t for t in titles) == 1, titles
    assert doc.count("<details>") == 0  # the study's table is folded, and --no-study leaves it out
    for s in summary["statements"]:
        assert f">{s['verdict']}</span>" in doc
    captions = re.findall(r'<figure class="table">.*?<figcaption>([^<]+)</figcaption>', doc, re.DOTALL)
    assert len(captions) == len(set(captions)) and len(captions) >= 5, captions
    assert doc.count('<math display="block">') == 5 and "sqrt(" not in doc
    assert "threshold_speed_kmh" not in doc and "_N_per_m" not in doc
    headers = re.findall(r'<th scope="col"[^>]*>([^<]*(?:<sub>[^<]*</sub>[^<]*)*)</th>', doc)
    assert headers and not [h for h in headers if re.search(r"[a-z]_[a-z]", h)], headers
    assert 'src="animation_slc.gif"' in doc and 'src="animation_dlc.gif"' in doc


def test_reproduce_report_renders_in_headless_chromium(run, tmp_path):
    """The real report of `reproduce` in headless Chromium: no console message, every figure and animation
    drawn."""
    import numpy as np
    from matplotlib import image as mpimg

    shot, dom, err = render(run / "report.html", tmp_path)
    assert console_messages(err) == [], "\n".join(console_messages(err))
    images = Images()
    images.feed(dom)
    assert len(images.sources) >= 8 and all((run / s).is_file() for s in images.sources), images.sources
    rgb = mpimg.imread(shot)[..., :3]
    assert len(np.unique((rgb * 255).round().astype(np.uint8).reshape(-1, 3), axis=0)) >= 256
    assert rgb.std() >= 0.05


@pytest.mark.parametrize("width", WIDTHS)
def test_reproduce_report_fits_the_page_and_its_images_load(run, tmp_path, width):
    """No element wider than a 1280 px or an 800 px page, every figure and both animations decoded, no console
    message."""
    result, _, console = probe(run / "report.html", tmp_path, width)
    assert console == ""
    assert_fits_and_loads(result, width)
    assert sum(image["src"].endswith(".gif") for image in result["images"]) == 2
