"""Headless Chromium for the report's tests: a screenshot, the DOM after load, the console, and a probe of the
laid-out page (overflow of the page width, every image decoded)."""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import pytest

BROWSER_TIMEOUT_S = 90
WIDTHS = (1280, 800)
"""The viewport widths the report must fit: a typical desktop window and a narrow one [px]."""

# Runs after every image has loaded (the load event), with every <details> opened: the page's width against
# the viewport's, each element that sticks out of the page (an element inside a box that scrolls or clips is
# that box's business: the box itself is checked), and each image's decoded size. The result goes into a
# hidden <pre> for --dump-dom.
PROBE = """<script>
window.addEventListener("load", () => {
  document.querySelectorAll("details").forEach((d) => { d.open = true; });  // folded tables must fit too
  const root = document.documentElement, width = root.clientWidth;
  const inBox = (el) => {
    for (let p = el.parentElement; p && p !== document.body; p = p.parentElement) {
      if (["auto", "scroll", "hidden", "clip"].includes(getComputedStyle(p).overflowX)) return true;
    }
    return false;
  };
  const wide = [];
  for (const el of document.body.querySelectorAll("*")) {
    const r = el.getBoundingClientRect();
    if ((r.right > width + 0.5 || r.left < -0.5) && !inBox(el)) {
      wide.push(`${el.tagName.toLowerCase()}.${el.className} [${Math.round(r.left)}, ${Math.round(r.right)}]`);
    }
  }
  const images = Array.from(document.images, (img) => ({
    src: img.getAttribute("src").slice(0, 60), complete: img.complete, width: img.naturalWidth,
    height: img.naturalHeight, shown: img.getBoundingClientRect().width,
  }));
  const out = document.createElement("pre");
  out.id = "probe";
  out.hidden = true;
  out.textContent = JSON.stringify({scrollWidth: root.scrollWidth, clientWidth: width, wide, images});
  document.body.appendChild(out);
});
</script>"""


def chromium() -> str:
    exe = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")
    if not exe:
        pytest.skip("no Chromium installed: none of chromium, chromium-browser, google-chrome is on PATH "
                    "(.ci/run installs Debian's chromium)")
    return exe


def render(page: Path, tmp_path: Path, size=(1200, 2000)) -> tuple[Path, str, str]:
    """Load ``page`` in headless Chromium: (screenshot, the DOM after load, stderr with the console log)."""
    shot = tmp_path / f"{page.stem}-{size[0]}x{size[1]}.png"
    command = [
        chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--disable-quic",
        "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--hide-scrollbars", f"--user-data-dir={tmp_path / f'{page.stem}-profile'}", "--enable-logging=stderr",
        "--v=0", "--virtual-time-budget=10000", "--dump-dom", f"--screenshot={shot}",
        f"--window-size={size[0]},{size[1]}", page.resolve().as_uri(),
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


def console_messages(stderr: str) -> list[str]:
    """Console lines of Chromium's log: this Chromium logs every console message, errors too, as INFO:CONSOLE."""
    return [line for line in stderr.splitlines() if ":CONSOLE" in line or "Uncaught" in line]


class Images(HTMLParser):
    """The ``src`` of every ``<img>`` of a document."""

    def __init__(self):
        super().__init__()
        self.sources: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.sources.append(dict(attrs).get("src") or "")


def probe(report: Path, tmp_path: Path, width: int, height: int = 2000) -> tuple[dict, Path, str]:
    """Lay ``report`` out at ``width`` px: (the probe's findings, the screenshot, the console messages).

    The probe runs in a copy of the report beside it (so that its images resolve as the report's do), its
    Content-Security-Policy let through inline scripts and nothing else.
    """
    doc = report.read_text(encoding="utf-8")
    policy = "default-src 'none';"
    assert doc.count(policy) == 1, "expected the report's Content-Security-Policy"
    doc = doc.replace(policy, policy + " script-src 'unsafe-inline';").replace("</body>", PROBE + "</body>")
    page = report.with_name(f"{report.stem}-probe-{width}.html")
    page.write_text(doc, encoding="utf-8")
    try:
        shot, dom, err = render(page, tmp_path, size=(width, height))
    finally:
        page.unlink()
    found = re.search(r'<pre id="probe" hidden="">(.*?)</pre>', dom, re.DOTALL)
    assert found, f"the probe did not run:\n{err[-3000:]}"
    text = found.group(1).replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", '"').replace("&amp;", "&")
    return json.loads(text), shot, "\n".join(console_messages(err))


def assert_fits_and_loads(result: dict, width: int) -> None:
    """No horizontal overflow of the page, and every image decoded with a size."""
    assert result["clientWidth"] <= width
    assert result["scrollWidth"] <= result["clientWidth"], (
        f"the page is {result['scrollWidth']} px wide in a {result['clientWidth']} px viewport; "
        f"sticking out: {result['wide']}")
    assert result["wide"] == [], f"elements wider than the {width} px page: {result['wide']}"
    assert result["images"], "expected images"
    for image in result["images"]:
        assert image["complete"] and image["width"] > 0 and image["height"] > 0, f"image not loaded: {image}"
        assert 0 < image["shown"] <= result["clientWidth"], f"image not shown within the page: {image}"
