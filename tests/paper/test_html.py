"""Tests of trikedyn.paper.html: the report from its templates, escaped text, bad input, and a real browser."""

from __future__ import annotations

import base64
import datetime as dt
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.image as mpimg
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest

import trikedyn
from trikedyn.errors import InputError
from trikedyn.paper.cells import column_header, format_value, verdict_class
from trikedyn.paper.html import render_report, write_report

from .browser import WIDTHS, Images, assert_fits_and_loads, console_messages, probe, render

MAGENTA = "#ff00ff"  # a colour that only the first figure has: seeing it in a screenshot proves it rendered


# --------------------------------------------------------------------------------------------- fixtures


def _figure(path: Path, *, fill: str | None = None) -> Path:
    fig, ax = plt.subplots(figsize=(6, 3.5), dpi=100)
    t = np.linspace(0.0, 5.0, 400)
    ax.plot(t, np.exp(-t / 2) * np.sin(2 * np.pi * 1.5 * t), label="body")
    if fill:
        ax.axvspan(1.0, 3.0, color=fill)
    ax.set_xlabel("t [s]")
    ax.set_title("Free decay")
    fig.savefig(path)
    plt.close(fig)
    return path


def _animation(path: Path) -> Path:
    """A small animated GIF (three frames)."""
    from PIL import Image

    frames = [Image.new("RGB", (120, 80), colour) for colour in ((200, 30, 30), (30, 200, 30), (30, 30, 200))]
    frames[0].save(path, save_all=True, append_images=frames[1:], duration=200, loop=0)
    return path


@pytest.fixture
def report_inputs(tmp_path):
    """Sections with two figures, an animation, equations, a CSV table, a wide DataFrame, a folded table, and
    every kind of verdict."""
    fig1 = _figure(tmp_path / "decay.png", fill=MAGENTA)
    fig2 = _figure(tmp_path / "second.png")
    gif = _animation(tmp_path / "lane-change.gif")
    csv = tmp_path / "table1.csv"
    pd.DataFrame(
        {"suspension": ["front", "rear"], "stiffness_N_per_m": [38000.0, 52000.5], "damping_ratio": [0.2345678, 0.31]}
    ).to_csv(csv, index=False)
    frame = pd.DataFrame({"freight_kg": [0, 100, 200], "cg_x_mm": [912.25, 1001.5, 1075.125]})
    wide = pd.DataFrame({f"quantity_number_{k}_mps2": [1234.5678 * k, 0.5] for k in range(16)})
    wide["warnings"] = ["a long warning that would hide off-screen in a table as wide as this one is", ""]
    study = pd.DataFrame({"manoeuvre": ["slc", "dlc"] * 25, "freight_kg": np.repeat(np.arange(25) * 10.0, 2),
                          "stiffness_scale": 1.2, "threshold_speed_kmh": np.linspace(40, 30, 50)})
    sections = [
        {
            "title": "Damping coefficients (Eq. 4)",
            "statements": [
                {"paper": "Eq. 4 gives Table 1's damping coefficients", "verdict": "contradicts",
                 "evidence": "Eq. 4 gives 3183.2 and 4120.7 N s/m, 1.59x and 1.37x Table 1's values."},
                {"paper": "Eq. 3 gives the stiffness", "verdict": "reproduces, with a finding",
                 "evidence": "M_s = 239.18 kg, more than the vehicle."},
            ],
            "equations": ["eq1", "eq2", "eq3", "eq4"],
            "figures": [(fig1, "Free decay of the front suspension")],
            "tables": [(csv, "Table 1, recomputed")],
            "notes": ["Both presets ship: reference-etrike and reference-etrike-eq4."],
        },
        {
            "title": "CG against freight (Table 3)",
            "paper": "Table 3: CG against freight mass (0-200 kg in the back trunk)",
            "verdict": "reproduces",
            "evidence": "every coordinate within 0.049 mm with a 583 kg base mass.",
            "tables": [(frame, "CG against freight"), (wide, "A table too wide for the page")],
        },
        {
            "title": "Sampling at 10 Hz and the lane changes",
            "paper": "10 Hz sampling satisfies Shannon's theorem for 2.9 Hz",
            "verdict": "reproduces, with a caveat",
            "evidence": "K within 1.2 % and C within 4.8 %, but only 3.4 samples per cycle.",
            "equations": ["eq5"],
            "figures": [(str(fig2), "Resampled record")],
            "animations": [(gif, "The lane change from above")],
            "folded": [(study, "Every scenario")],
        },
    ]
    return tmp_path, sections, [fig1, fig2, gif]


def _write(tmp_path, sections, **kwargs):
    kwargs.setdefault("summary", "Three statements of the paper, checked.")
    kwargs.setdefault("vehicle", "reference-etrike")
    return write_report(tmp_path / "out", "Electric delta trike: reproduction", sections, **kwargs)


def _statements(sections):
    return [st for s in sections for st in s.get("statements", [s])]


# ---------------------------------------------------------------------------------------- the document

_ATTR = re.compile(r"""\b(src|href)\s*=\s*(?:"([^"]*)"|'([^']*)'|([^\s>]+))""", re.IGNORECASE)


def _resources(doc: str) -> list[tuple[str, str]]:
    return [(m.group(1).lower(), m.group(2) or m.group(3) or m.group(4) or "") for m in _ATTR.finditer(doc)]


def _no_external_resource(doc: str) -> list[tuple[str, str]]:
    assert "http://" not in doc and "https://" not in doc
    assert "<script" not in doc.lower() and "<link" not in doc.lower() and "@import" not in doc and "url(" not in doc
    resources = _resources(doc)
    assert resources, "expected images and anchors"
    for attr, value in resources:
        assert not value.startswith(("http:", "https:", "//", "file:", "/")), (attr, value[:60])
        if attr == "href":
            assert value.startswith("#")
    return [value for attr, value in resources if attr == "src"]


def test_report_links_its_images_written_beside_it(report_inputs):
    tmp_path, sections, images = report_inputs
    path = _write(tmp_path, sections)
    assert path == tmp_path / "out" / "report.html"
    assert sorted(p.name for p in path.parent.iterdir()) == sorted(["report.html", *(p.name for p in images)])
    sources = _no_external_resource(path.read_text(encoding="utf-8"))
    assert sorted(sources) == sorted(p.name for p in images)
    for image in images:
        assert (path.parent / image.name).read_bytes() == image.read_bytes()


def test_images_already_beside_the_report_are_linked_not_copied(report_inputs):
    tmp_path, sections, _ = report_inputs
    out = tmp_path / "out"
    out.mkdir()
    inside = _figure(out / "sub-figure.png")
    sections[1]["figures"] = [(inside, "Already there")]
    doc = _write(tmp_path, sections).read_text(encoding="utf-8")
    assert 'src="sub-figure.png"' in doc
    assert not list(out.glob("sub-figure-*.png"))


def test_embedded_report_is_one_self_contained_file(report_inputs):
    tmp_path, sections, images = report_inputs
    path = _write(tmp_path, sections, embed=True)
    assert sorted(p.name for p in path.parent.iterdir()) == ["report.html"]
    doc = path.read_text(encoding="utf-8")
    sources = _no_external_resource(doc)
    assert len(sources) == len(images)
    for image in images:
        kind = "gif" if image.suffix == ".gif" else "png"
        assert f"data:image/{kind};base64," + base64.b64encode(image.read_bytes()).decode("ascii") in doc
    assert "Free decay of the front suspension" in doc and "Resampled record" in doc


def test_text_is_escaped(report_inputs):
    tmp_path, sections, _ = report_inputs
    sections[0]["statements"][0]["evidence"] = 'C < 2 xi & "K" > 0 <img src=x onerror=alert(1)>'
    sections[1]["notes"] = ["</section><h1>injected</h1>"]
    sections[1]["tables"] = [(pd.DataFrame({"<b>col</b>": ["<i>cell</i>"]}), "<u>caption</u>")]
    path = write_report(tmp_path / "out", "<script>alert('x')</script> report", sections, summary=True,
                        vehicle="<b>trike</b>")
    doc = path.read_text(encoding="utf-8")
    assert "<script" not in doc.lower()
    assert "&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt;" in doc
    assert "C &lt; 2 xi &amp; &#34;K&#34; &gt; 0 &lt;img src=x onerror=alert(1)&gt;" in doc
    assert "&lt;/section&gt;&lt;h1&gt;injected&lt;/h1&gt;" in doc and "<h1>injected" not in doc
    assert "&lt;b&gt;trike&lt;/b&gt;" in doc
    assert "&lt;b&gt;col&lt;/b&gt;" in doc and "&lt;i&gt;cell&lt;/i&gt;" in doc and "&lt;u&gt;caption&lt;/u&gt;" in doc
    assert "<b>" not in doc and "<i>" not in doc and "<u>" not in doc
    assert "onerror=" not in doc.replace("&lt;img src=x onerror=", "")


def test_verdicts_headers_and_table_values_are_shown(report_inputs):
    tmp_path, sections, _ = report_inputs
    doc = _write(tmp_path, sections).read_text(encoding="utf-8")
    for statement in _statements(sections):
        assert f">{statement['verdict']}</span>" in doc
        assert statement["evidence"].replace("'", "&#39;") in doc
    assert 'class="badge bad">contradicts<' in doc
    assert 'class="badge ok">reproduces<' in doc
    assert 'class="badge qualified">reproduces, with a caveat<' in doc
    # human headers with units, numbers formatted
    for text in ("Suspension", "Stiffness [N/m]", "Damping ratio ξ [–]", "38000", "52000.5", "0.2346", "0.31", "front"):
        assert f">{text}</t" in doc, text
    for text in ("Freight [kg]", "Cg x [mm]", "912.2", "1001.5", "1075.1", "200", "Quantity number 3 [m/s²]"):
        assert f">{text}</t" in doc, text
    assert "stiffness_N_per_m" not in doc and "freight_kg" not in doc
    assert "Table 1, recomputed" in doc and "Both presets ship" in doc


@pytest.mark.parametrize(
    ("name", "header"),
    [("threshold_speed_kmh", "Threshold speed [km/h]"), ("max_roll_deg", "Max roll [deg]"),
     ("stiffness_N_per_m", "Stiffness [N/m]"), ("damping_Ns_per_m", "Damping [N s/m]"), ("speed_mps", "Speed [m/s]"),
     ("ay_mps2", "Ay [m/s²]"), ("limit", "Limit"), ("error_pct", "Error [%]"), ("a<b", "A&lt;b")],
)
def test_column_header(name, header):
    assert column_header(name) == header


def test_equations_are_mathml(report_inputs):
    tmp_path, sections, _ = report_inputs
    doc = _write(tmp_path, sections).read_text(encoding="utf-8")
    assert doc.count('<math display="block">') == 5
    for label in ("Eq. 1", "Eq. 2", "Eq. 3", "Eq. 4", "Eq. 5"):
        assert f"{label}: " in doc
    assert "<msqrt>" in doc and "<mfrac>" in doc and "sqrt(" not in doc


def test_folded_table_and_animation(report_inputs):
    tmp_path, sections, _ = report_inputs
    doc = _write(tmp_path, sections).read_text(encoding="utf-8")
    folded = doc[doc.index("<details>"):doc.index("</details>")]
    assert "<summary>Every scenario (50 rows)</summary>" in folded and folded.count("<tr>") == 51
    assert "Stiffness [% of Table 1]" in folded and ">120</td>" in folded  # scale factors as percent
    assert '<figure class="animation"><img src="lane-change.gif"' in doc


def test_header_and_summary_link_to_the_sections(report_inputs):
    tmp_path, sections, _ = report_inputs
    doc = _write(tmp_path, sections, date=dt.date(2026, 11, 21)).read_text(encoding="utf-8")
    assert "reference-etrike" in doc and "2026-11-21" in doc and f"trikedyn {trikedyn.__version__}" in doc
    assert "Three statements of the paper, checked." in doc
    for i in range(1, len(sections) + 1):
        assert f'href="#section-{i}"' in doc and f'id="section-{i}"' in doc
        assert doc.count(f"<h2>{i}. ") == 1
    for statement in _statements(sections):
        assert doc.count(statement["paper"].replace("'", "&#39;")) == 2  # summary table and section
    no_summary = render_report("t", sections)
    assert 'class="summary"' not in no_summary and 'href="#section-1"' not in no_summary


def test_missing_figure_raises_input_error_naming_it(report_inputs):
    tmp_path, sections, _ = report_inputs
    missing = tmp_path / "no-such-figure.png"
    sections[2]["figures"].append((missing, "gone"))
    with pytest.raises(InputError, match="no-such-figure.png") as info:
        _write(tmp_path, sections)
    assert "Sampling at 10 Hz" in str(info.value)
    assert not (tmp_path / "out" / "report.html").exists()


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda s: s.pop("verdict"), "missing key 'verdict'"),
        (lambda s: s.update(verdit="reproduces"), "unknown key"),
        (lambda s: s.update(evidence=""), "'evidence' must be a non-empty string"),
        (lambda s: s.update(statements=[]), "give 'statements' or"),
        (lambda s: s.update(figures=["decay.png"]), r"'figures'\[0\]"),
        (lambda s: s.update(animations=[("nope.gif", "gone")]), "figure file not found: nope.gif"),
        (lambda s: s.update(tables=[(42, "caption")]), "CSV path or a pandas DataFrame"),
        (lambda s: s.update(tables=[("nope.csv", "caption")]), "table file not found: nope.csv"),
        (lambda s: s.update(folded=[("nope.csv", "caption")]), "table file not found: nope.csv"),
        (lambda s: s.update(notes="one note"), "'notes' must be a list of strings"),
        (lambda s: s.update(equations=["eq9"]), "unknown equation 'eq9'"),
    ],
)
def test_malformed_section_raises_input_error(report_inputs, change, message):
    tmp_path, sections, _ = report_inputs
    change(sections[1])
    with pytest.raises(InputError, match=message):
        _write(tmp_path, sections)


def test_not_an_image_raises_input_error(report_inputs):
    tmp_path, sections, _ = report_inputs
    fake = tmp_path / "fake.png"
    fake.write_text("not an image")
    sections[0]["figures"] = [(fake, "fake")]
    with pytest.raises(InputError, match="not a PNG or GIF image: .*fake.png"):
        _write(tmp_path, sections)


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (3, "3"), (np.int64(-12), "-12"), (583.0, "583"), (0.0, "0"), (0.2345678, "0.2346"), (12.3456, "12.35"),
        (1234.5678, "1234.6"), (25312345.6, "2.531e+07"), (200000.0, "200000"), (1.2e-5, "1.200e-05"), (float("nan"), ""), (None, ""),
        (float("inf"), "inf"), (True, "True"), ("front", "front"),
    ],
)
def test_format_value(value, text):
    assert format_value(value) == text


def test_verdict_class():
    assert verdict_class("reproduces") == "ok"
    assert verdict_class("reproduces, with a finding") == "qualified"
    assert verdict_class("contradicts") == "bad"
    assert verdict_class("not tested") == "other"


# ------------------------------------------------------------------------------------ headless Chromium


def test_console_capture_sees_errors(tmp_path):
    """The check below is only as good as its view of the console: a page with errors must show them."""
    page = tmp_path / "broken.html"
    page.write_text('<!DOCTYPE html><html><body><p>broken</p><script>console.error("boom"); noSuchFunction();'
                    "</script></body></html>", encoding="utf-8")
    _, _, err = render(page, tmp_path, size=(400, 300))
    messages = "\n".join(console_messages(err))
    assert "boom" in messages and "Uncaught ReferenceError" in messages, err[-3000:]


def test_probe_sees_overflow_and_a_broken_image(tmp_path):
    """The layout probe is only as good as what it sees: a too-wide element and a missing image must show."""
    page = tmp_path / "report.html"
    page.write_text('<!DOCTYPE html><html><head><meta http-equiv="Content-Security-Policy" content="default-src '
                    "'none'; img-src 'self'; style-src 'unsafe-inline'\"></head><body><div style=\"width: 1500px\">"
                    'wide</div><div style="overflow-x: auto"><table style="width: 3000px"><tr><td>boxed</td></tr>'
                    '</table></div><img src="missing.png" alt="gone"></body></html>', encoding="utf-8")
    result, _, _ = probe(page, tmp_path, 800, 600)
    assert result["scrollWidth"] > result["clientWidth"]
    assert any(w.startswith("div.") for w in result["wide"]) and not any(w.startswith("table") for w in result["wide"])
    assert [(image["src"], image["width"]) for image in result["images"]] == [("missing.png", 0)]
    with pytest.raises(AssertionError):
        assert_fits_and_loads(result, 800)


def test_report_renders_in_headless_chromium(report_inputs):
    tmp_path, sections, images = report_inputs
    report = _write(tmp_path, sections)
    shot, dom, err = render(report, tmp_path)

    assert console_messages(err) == [], "\n".join(console_messages(err))
    parser = Images()
    parser.feed(dom)
    assert sorted(parser.sources) == sorted(p.name for p in images)
    assert "Damping coefficients (Eq. 4)" in dom and "reproduces, with a caveat" in dom

    rgb = mpimg.imread(shot)[..., :3]
    assert rgb.shape[:2] == (2000, 1200)
    colours = np.unique((rgb * 255).round().astype(np.uint8).reshape(-1, 3), axis=0)
    assert len(colours) >= 256, f"screenshot looks blank: {len(colours)} distinct colours"
    assert rgb.std() >= 0.05, f"screenshot looks blank: pixel standard deviation {rgb.std():.4f}"
    # the first figure's magenta band is on screen: the linked PNG was decoded and drawn
    magenta = (rgb[..., 0] > 0.9) & (rgb[..., 1] < 0.1) & (rgb[..., 2] > 0.9)
    assert magenta.sum() > 5_000, f"the figure is not on screen ({magenta.sum()} magenta pixels)"


@pytest.mark.parametrize("width", WIDTHS)
@pytest.mark.parametrize("embed", [False, True], ids=["linked", "embedded"])
def test_report_fits_the_page_and_its_images_load(report_inputs, width, embed):
    """At a desktop and a narrow width: nothing wider than the page (the wide table scrolls in its box), every
    image and the animation decoded, no console message."""
    tmp_path, sections, images = report_inputs
    report = _write(tmp_path, sections, embed=embed)
    result, _, console = probe(report, tmp_path, width)
    assert console == ""
    assert_fits_and_loads(result, width)
    assert len(result["images"]) == len(images)
