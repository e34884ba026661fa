"""Tests of trikedyn.report.html: a self-contained report, escaped text, bad input, and a real browser."""

from __future__ import annotations

import base64
import datetime as dt
import os
import re
import shutil
import signal
import subprocess
from html.parser import HTMLParser
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
from trikedyn.report import write_report
from trikedyn.report.html import format_value, render_report, verdict_class

MAGENTA = "#ff00ff"  # a colour that only the embedded figure has: seeing it in a screenshot proves it rendered
BROWSER_TIMEOUT_S = 60


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


@pytest.fixture
def report_inputs(tmp_path):
    """Sections with two figures, a CSV table and a DataFrame, and every kind of verdict."""
    fig1 = _figure(tmp_path / "decay.png", fill=MAGENTA)
    fig2 = _figure(tmp_path / "second.png")
    csv = tmp_path / "table1.csv"
    pd.DataFrame(
        {"suspension": ["front", "rear"], "stiffness_N_per_m": [38000.0, 52000.5], "damping_ratio": [0.2345678, 0.31]}
    ).to_csv(csv, index=False)
    frame = pd.DataFrame({"freight_kg": [0, 100, 200], "cg_x_mm": [912.25, 1001.5, 1075.125]})
    sections = [
        {
            "title": "Damping coefficients (Eq. 4)",
            "paper": "Eq. 4, C = 2 xi sqrt(K M_s), gives Table 1's damping coefficients",
            "verdict": "contradicts",
            "evidence": "Eq. 4 gives 3183.2 and 4120.7 N s/m, 1.59x and 1.37x Table 1's values.",
            "figures": [(fig1, "Free decay of the front suspension")],
            "tables": [(csv, "Table 1, recomputed")],
            "notes": ["Both presets ship: reference-etrike and reference-etrike-eq4."],
        },
        {
            "title": "CG against freight (Table 3)",
            "paper": "Table 3: CG against freight mass (0-200 kg in the back trunk)",
            "verdict": "reproduces",
            "evidence": "every coordinate within 0.049 mm with a 583 kg base mass.",
            "tables": [(frame, "CG against freight")],
        },
        {
            "title": "Sampling at 10 Hz",
            "paper": "10 Hz sampling satisfies Shannon's theorem for 2.9 Hz",
            "verdict": "reproduces, with a caveat",
            "evidence": "K within 1.2 % and C within 4.8 %, but only 3.4 samples per cycle.",
            "figures": [(str(fig2), "Resampled record")],
        },
    ]
    return tmp_path, sections, [fig1, fig2]


def _write(tmp_path, sections, **kwargs):
    kwargs.setdefault("summary", "Three statements of the paper, checked.")
    kwargs.setdefault("vehicle", "reference-etrike")
    return write_report(tmp_path / "out", "Electric delta trike: reproduction", sections, **kwargs)


# ---------------------------------------------------------------------------------------- the document

_ATTR = re.compile(r"""\b(src|href)\s*=\s*(?:"([^"]*)"|'([^']*)'|([^\s>]+))""", re.IGNORECASE)


def _resources(doc: str) -> list[tuple[str, str]]:
    return [(m.group(1).lower(), m.group(2) or m.group(3) or m.group(4) or "") for m in _ATTR.finditer(doc)]


def test_report_is_one_self_contained_file(report_inputs):
    tmp_path, sections, _ = report_inputs
    path = _write(tmp_path, sections)
    assert path == tmp_path / "out" / "report.html"
    assert sorted(p.name for p in path.parent.iterdir()) == ["report.html"]
    doc = path.read_text(encoding="utf-8")
    assert "http://" not in doc and "https://" not in doc
    assert "<script" not in doc.lower() and "<link" not in doc.lower() and "@import" not in doc and "url(" not in doc
    resources = _resources(doc)
    assert resources, "expected images and anchors"
    for attr, value in resources:
        assert not value.startswith(("http:", "https:", "//", "file:")), (attr, value[:60])
        if attr == "src":
            assert value.startswith("data:image/png;base64,")
        else:
            assert value.startswith("#")


def test_every_figure_is_embedded_as_a_png_data_uri(report_inputs):
    tmp_path, sections, figures = report_inputs
    doc = _write(tmp_path, sections).read_text(encoding="utf-8")
    assert doc.count("data:image/png;base64,") == len(figures)
    for png in figures:
        assert "data:image/png;base64," + base64.b64encode(png.read_bytes()).decode("ascii") in doc
    assert "Free decay of the front suspension" in doc and "Resampled record" in doc


def test_text_is_escaped(report_inputs):
    tmp_path, sections, _ = report_inputs
    sections[0]["evidence"] = 'C < 2 xi & "K" > 0 <img src=x onerror=alert(1)>'
    sections[1]["notes"] = ["</section><h1>injected</h1>"]
    path = write_report(tmp_path / "out", "<script>alert('x')</script> report", sections, summary=True,
                        vehicle="<b>trike</b>")
    doc = path.read_text(encoding="utf-8")
    assert "<script" not in doc.lower()
    assert "&lt;script&gt;alert(&#x27;x&#x27;)&lt;/script&gt;" in doc
    assert "C &lt; 2 xi &amp; &quot;K&quot; &gt; 0 &lt;img src=x onerror=alert(1)&gt;" in doc
    assert "&lt;/section&gt;&lt;h1&gt;injected&lt;/h1&gt;" in doc and "<h1>injected" not in doc
    assert "&lt;b&gt;trike&lt;/b&gt;" in doc
    assert "onerror=" not in doc.replace("&lt;img src=x onerror=", "")


def test_verdicts_and_table_values_are_shown(report_inputs):
    tmp_path, sections, _ = report_inputs
    doc = _write(tmp_path, sections).read_text(encoding="utf-8")
    for section in sections:
        assert f">{section['verdict']}</span>" in doc
        assert section["evidence"].replace("'", "&#x27;") in doc
    assert 'class="badge bad">contradicts<' in doc
    assert 'class="badge ok">reproduces<' in doc
    assert 'class="badge qualified">reproduces, with a caveat<' in doc
    # the CSV table and the DataFrame, numbers formatted
    for text in ("stiffness_N_per_m", "38000", "52000.5", "0.2346", "0.31", "front", "rear"):
        assert f">{text}</t" in doc, text
    for text in ("freight_kg", "cg_x_mm", "912.2", "1001.5", "1075.1", "200"):
        assert f">{text}</t" in doc, text
    assert "Table 1, recomputed" in doc and "Both presets ship" in doc


def test_header_and_summary_link_to_the_sections(report_inputs):
    tmp_path, sections, _ = report_inputs
    doc = _write(tmp_path, sections, date=dt.date(2026, 11, 21)).read_text(encoding="utf-8")
    assert "reference-etrike" in doc and "2026-11-21" in doc and f"trikedyn {trikedyn.__version__}" in doc
    assert "Three statements of the paper, checked." in doc
    for i, section in enumerate(sections, start=1):
        assert f'href="#section-{i}"' in doc and f'id="section-{i}"' in doc
        assert doc.count(section["paper"].replace("'", "&#x27;")) == 2  # summary table and section
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
        (lambda s: s.update(figures=["decay.png"]), r"'figures'\[0\]"),
        (lambda s: s.update(tables=[(42, "caption")]), "CSV path or a pandas DataFrame"),
        (lambda s: s.update(tables=[("nope.csv", "caption")]), "table file not found: nope.csv"),
        (lambda s: s.update(notes="one note"), "'notes' must be a list of strings"),
    ],
)
def test_malformed_section_raises_input_error(report_inputs, change, message):
    tmp_path, sections, _ = report_inputs
    change(sections[1])
    with pytest.raises(InputError, match=message):
        _write(tmp_path, sections)


def test_not_a_png_raises_input_error(report_inputs):
    tmp_path, sections, _ = report_inputs
    fake = tmp_path / "fake.png"
    fake.write_text("not an image")
    sections[0]["figures"] = [(fake, "fake")]
    with pytest.raises(InputError, match="not a PNG image: .*fake.png"):
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


def _chromium() -> str:
    exe = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")
    if not exe:
        pytest.skip("no Chromium installed: none of chromium, chromium-browser, google-chrome is on PATH "
                    "(.ci/run installs Debian's chromium)")
    return exe


def _render(page: Path, tmp_path: Path, size=(1200, 2000)) -> tuple[Path, str, str]:
    """Load ``page`` in headless Chromium: (screenshot, the DOM after load, stderr with the console log)."""
    shot = tmp_path / f"{page.stem}-screenshot.png"
    command = [
        _chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--disable-quic",
        "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync",
        f"--user-data-dir={tmp_path / f'{page.stem}-profile'}", "--enable-logging=stderr", "--v=0",
        "--dump-dom", f"--screenshot={shot}", f"--window-size={size[0]},{size[1]}", page.resolve().as_uri(),
    ]
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, cwd=tmp_path)
    try:
        out, err = proc.communicate(timeout=BROWSER_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)  # the browser and its children: its own process group
        proc.communicate()
        pytest.fail(f"Chromium did not finish within {BROWSER_TIMEOUT_S} s: {' '.join(command)}")
    assert proc.returncode == 0, f"Chromium exited with {proc.returncode}:\n{err[-3000:]}"
    assert shot.is_file(), f"no screenshot written:\n{err[-3000:]}"
    return shot, out, err


def _console_messages(stderr: str) -> list[str]:
    """Console lines of Chromium's log: this Chromium logs every console message, errors too, as INFO:CONSOLE."""
    return [line for line in stderr.splitlines() if ":CONSOLE" in line or "Uncaught" in line]


class _Images(HTMLParser):
    def __init__(self):
        super().__init__()
        self.sources: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.sources.append(dict(attrs).get("src") or "")


def test_console_capture_sees_errors(tmp_path):
    """The check below is only as good as its view of the console: a page with errors must show them."""
    page = tmp_path / "broken.html"
    page.write_text('<!DOCTYPE html><html><body><p>broken</p><script>console.error("boom"); noSuchFunction();'
                    "</script></body></html>", encoding="utf-8")
    _, _, err = _render(page, tmp_path, size=(400, 300))
    messages = "\n".join(_console_messages(err))
    assert "boom" in messages and "Uncaught ReferenceError" in messages, err[-3000:]


def test_report_renders_in_headless_chromium(report_inputs):
    tmp_path, sections, figures = report_inputs
    report = _write(tmp_path, sections)
    shot, dom, err = _render(report, tmp_path)

    assert _console_messages(err) == [], "\n".join(_console_messages(err))

    parser = _Images()
    parser.feed(dom)
    assert len(parser.sources) == len(figures)
    assert all(src.startswith("data:image/png;base64,") for src in parser.sources)
    assert "Damping coefficients (Eq. 4)" in dom and "reproduces, with a caveat" in dom

    rgb = mpimg.imread(shot)[..., :3]
    assert rgb.shape[:2] == (2000, 1200)
    colours = np.unique((rgb * 255).round().astype(np.uint8).reshape(-1, 3), axis=0)
    assert len(colours) >= 256, f"screenshot looks blank: {len(colours)} distinct colours"
    assert rgb.std() >= 0.05, f"screenshot looks blank: pixel standard deviation {rgb.std():.4f}"
    # the first figure's magenta band is on screen: the embedded PNG was decoded and drawn
    magenta = (rgb[..., 0] > 0.9) & (rgb[..., 1] < 0.1) & (rgb[..., 2] > 0.9)
    assert magenta.sum() > 5_000, f"the embedded figure is not on screen ({magenta.sum()} magenta pixels)"
