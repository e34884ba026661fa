"""A self-contained HTML report of a reproduction: one file that renders offline.

The report is a single ``report.html``: figures are embedded as base64 PNG data URIs, tables are rendered
from CSV files or pandas DataFrames, the style is inline CSS and there is no JavaScript and no external
URL of any kind (no fonts, no CDNs). A Content-Security-Policy ``<meta>`` makes the browser refuse any
resource that is not inline, so the file cannot silently depend on the network.

A *section* is a plain dict, one per statement of the paper::

    {
        "title": "Damping coefficients (Eq. 4)",           # str, required
        "paper": "Eq. 4, C = 2 xi sqrt(K M_s), gives ...",  # str, required: the paper's statement
        "verdict": "contradicts",                           # str, required: shown as a coloured badge
        "evidence": "Eq. 4 gives 3183.2 N s/m, 1.59x ...",  # str, required: one paragraph with numbers
        "figures": [("fig1.png", "Caption"), ...],          # optional: PNG paths and captions
        "tables": [("table1.csv", "Caption"), ...],         # optional: CSV paths or DataFrames, captions
        "notes": ["a remark", ...],                         # optional
    }

The badge is green for ``"reproduces"``, amber for a qualified agreement (``"reproduces, with a
finding"``, ``"reproduces, with a caveat"``, ...), red for ``"contradicts"`` and grey for anything else.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import math
import numbers
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from ..errors import InputError

__all__ = ["REQUIRED_KEYS", "OPTIONAL_KEYS", "write_report", "render_report", "render_section",
           "render_figure", "render_table", "format_value", "verdict_class", "validate_section"]

REQUIRED_KEYS = ("title", "paper", "verdict", "evidence")
"""Keys every section must have, each a non-empty string."""

OPTIONAL_KEYS = ("figures", "tables", "notes")
"""Keys a section may have; each defaults to an empty list."""

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

_CSS = """
:root { color-scheme: light; }
* { box-sizing: border-box; }
body { margin: 0; background: #f4f5f7; color: #1f2328;
  font: 16px/1.55 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, "Noto Sans",
  "Liberation Sans", sans-serif; }
main { max-width: 1000px; margin: 0 auto; padding: 24px 28px 48px; background: #fff;
  box-shadow: 0 0 0 1px #e1e4e8; min-height: 100vh; }
header { border-bottom: 3px solid #1f4e79; padding-bottom: 12px; margin-bottom: 24px; }
h1 { font-size: 1.75rem; line-height: 1.25; margin: 0 0 8px; color: #1f4e79; }
h2 { font-size: 1.3rem; line-height: 1.3; margin: 0 0 10px; color: #1f4e79; }
h3 { font-size: 1.05rem; margin: 18px 0 6px; }
.meta { margin: 0; color: #57606a; font-size: 0.92rem; }
.meta span + span::before { content: " \\00b7  "; }
.intro { margin: 0 0 16px; }
section.finding { border-top: 1px solid #d0d7de; padding-top: 20px; margin-top: 28px; }
.paper { margin: 8px 0 12px; padding: 8px 14px; border-left: 4px solid #8c959f; background: #f6f8fa;
  font-style: italic; }
.paper-label { font-style: normal; font-weight: 600; color: #57606a; }
.badge { display: inline-block; padding: 2px 10px; border-radius: 12px; font-size: 0.85rem;
  font-weight: 600; white-space: nowrap; color: #fff; background: #6e7781; vertical-align: middle; }
.badge.ok { background: #1a7f37; }
.badge.qualified { background: #9a6700; }
.badge.bad { background: #cf222e; }
figure { margin: 18px 0; text-align: center; }
figure img { max-width: 100%; height: auto; border: 1px solid #e1e4e8; }
figcaption, caption { font-size: 0.9rem; color: #57606a; margin-top: 6px; }
caption { caption-side: bottom; text-align: left; padding-top: 6px; }
.table-wrap { overflow-x: auto; margin: 18px 0; }
table { border-collapse: collapse; font-size: 0.88rem; min-width: 50%; }
th, td { padding: 4px 10px; border-bottom: 1px solid #e1e4e8; text-align: left; vertical-align: top; }
thead th { background: #1f4e79; color: #fff; font-weight: 600; }
tbody tr:nth-child(even) { background: #f3f6f9; }
th.num, td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.summary { width: 100%; }
table.summary td:last-child { white-space: nowrap; }
a { color: #0b5cad; }
ul.notes { margin: 10px 0; padding-left: 22px; color: #3d444d; }
footer { margin-top: 36px; font-size: 0.85rem; color: #57606a; }
"""

_CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'; base-uri 'none'; form-action 'none'"


def _esc(text: Any) -> str:
    """Escape any value for HTML text or a quoted attribute value."""
    return html.escape(str(text), quote=True)


def format_value(value: Any) -> str:
    """Format one table cell for display.

    Parameters
    ----------
    value : object
        A cell: a number, a string, None or a missing value.

    Returns
    -------
    str
        Integers as they are; whole floats without decimals; floats of magnitude 1e-3 to 1e6 with
        four significant digits (one decimal from 1000 on); others in scientific notation; NaN and None
        as an empty cell; infinities as ``inf``/``-inf``. Anything else is ``str(value)``. Not escaped.
    """
    if value is None or value is pd.NA or value is pd.NaT:
        return ""
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        x = float(value)
        if math.isnan(x):
            return ""
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        if x == 0:
            return "0"
        mag = abs(x)
        if x.is_integer() and mag < 1e12:
            return str(int(x))
        if mag >= 1e6 or mag < 1e-3:
            return f"{x:.3e}"
        if mag >= 1000:
            return f"{x:.1f}"
        return f"{x:.4g}"
    return str(value)


def _is_number(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def verdict_class(verdict: str) -> str:
    """The CSS class of a verdict's badge.

    Parameters
    ----------
    verdict : str
        A section's verdict.

    Returns
    -------
    str
        ``"ok"`` for exactly "reproduces"; ``"qualified"`` for "reproduces, ..." or "partly ...";
        ``"bad"`` for a verdict starting with "contradicts"; ``"other"`` otherwise.
    """
    v = " ".join(verdict.lower().split())
    if v == "reproduces":
        return "ok"
    if v.startswith("contradicts"):
        return "bad"
    if v.startswith(("reproduces", "partly", "partially")):
        return "qualified"
    return "other"


def _badge(verdict: str) -> str:
    return f'<span class="badge {verdict_class(verdict)}">{_esc(verdict)}</span>'


def _load_table(source: Any, where: str) -> pd.DataFrame:
    """A DataFrame from a DataFrame or the path of a CSV file."""
    if isinstance(source, pd.DataFrame):
        return source
    if isinstance(source, str | Path):
        path = Path(source)
        if not path.is_file():
            raise InputError(f"table file not found: {path}", where)
        try:
            return pd.read_csv(path)
        except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
            raise InputError(f"cannot read table {path}: {exc}", where) from exc
    raise InputError(f"a table is a CSV path or a pandas DataFrame, not {type(source).__name__}", where)


def render_table(table: pd.DataFrame, caption: str = "") -> str:
    """Render a DataFrame as an HTML table with formatted, escaped cells.

    Parameters
    ----------
    table : pandas.DataFrame
        The data; its columns are the header. A non-default index is shown as the first column(s).
    caption : str, optional
        Shown under the table.

    Returns
    -------
    str
        A ``<div class="table-wrap"><table>...</table></div>`` fragment; numeric cells are right-aligned.
    """
    frame = table if isinstance(table.index, pd.RangeIndex) else table.reset_index()
    numeric = [pd.api.types.is_numeric_dtype(frame[c]) and not pd.api.types.is_bool_dtype(frame[c])
               for c in frame.columns]
    head = "".join(f'<th scope="col" class="num">{_esc(c)}</th>' if num else f'<th scope="col">{_esc(c)}</th>'
                   for c, num in zip(frame.columns, numeric, strict=True))
    rows = []
    for record in frame.itertuples(index=False, name=None):
        cells = "".join(
            f'<td class="num">{_esc(format_value(v))}</td>' if _is_number(v) else f"<td>{_esc(format_value(v))}</td>"
            for v in record
        )
        rows.append(f"<tr>{cells}</tr>")
    cap = f"<caption>{_esc(caption)}</caption>" if caption else ""
    return (f'<div class="table-wrap"><table>{cap}<thead><tr>{head}</tr></thead>'
            f"<tbody>{''.join(rows)}</tbody></table></div>")


def _png_data_uri(path: Path, where: str) -> str:
    """The base64 data URI of a PNG file; InputError naming the file if it is missing or not a PNG."""
    if not path.is_file():
        raise InputError(f"figure file not found: {path}", where)
    data = path.read_bytes()
    if not data.startswith(_PNG_SIGNATURE):
        raise InputError(f"figure file is not a PNG image: {path}", where)
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def render_figure(png_path: str | Path, caption: str = "", *, where: str = "figure") -> str:
    """Render a PNG file as an embedded ``<figure>``.

    Parameters
    ----------
    png_path : str or Path
        The PNG file; its bytes are embedded as a base64 data URI.
    caption : str, optional
        The figure's caption, also its alt text.
    where : str, optional
        Prefix of an error's message (which section and figure).

    Returns
    -------
    str
        A ``<figure>`` fragment.

    Raises
    ------
    InputError
        The file is missing or is not a PNG; the message names it.
    """
    uri = _png_data_uri(Path(png_path), where)
    alt = caption or Path(png_path).name
    cap = f"<figcaption>{_esc(caption)}</figcaption>" if caption else ""
    return f'<figure><img src="{uri}" alt="{_esc(alt)}">{cap}</figure>'


def _pairs(value: Any, key: str, where: str) -> list[tuple[Any, str]]:
    """Validate a list of (item, caption) pairs."""
    if isinstance(value, str | bytes) or not isinstance(value, Sequence):
        raise InputError(f"'{key}' must be a list of (item, caption) pairs", where)
    pairs = []
    for k, pair in enumerate(value):
        if isinstance(pair, str | bytes) or not isinstance(pair, Sequence) or len(pair) != 2:
            raise InputError(f"'{key}'[{k}] must be an (item, caption) pair", where)
        item, caption = pair
        if not isinstance(caption, str):
            raise InputError(f"'{key}'[{k}]: the caption must be a string", where)
        pairs.append((item, caption))
    return pairs


def validate_section(section: Any, index: int = 0) -> dict:
    """Check a section's keys and types and fill in the optional keys.

    Parameters
    ----------
    section : dict
        A section (see the module's docstring).
    index : int, optional
        Its position, for error messages (counted from 1).

    Returns
    -------
    dict
        A new dict with every key of REQUIRED_KEYS and OPTIONAL_KEYS; figures and tables as lists of pairs.

    Raises
    ------
    InputError
        Not a dict, a missing or unknown key, a wrong type, or a figure file that is missing or not a PNG.
    """
    where = f"section {index}"
    if not isinstance(section, Mapping):
        raise InputError(f"a section must be a dict, not {type(section).__name__}", where)
    if isinstance(section.get("title"), str) and section["title"].strip():
        where = f"section {index} ({section['title']!r})"
    unknown = sorted(set(section) - set(REQUIRED_KEYS) - set(OPTIONAL_KEYS), key=str)
    if unknown:
        raise InputError(f"unknown key(s) {unknown}; expected {list(REQUIRED_KEYS + OPTIONAL_KEYS)}", where)
    for key in REQUIRED_KEYS:
        if key not in section:
            raise InputError(f"missing key '{key}'", where)
        if not isinstance(section[key], str) or not section[key].strip():
            raise InputError(f"'{key}' must be a non-empty string", where)
    out = {key: section[key] for key in REQUIRED_KEYS}
    out["figures"] = _pairs(section.get("figures") or [], "figures", where)
    out["tables"] = _pairs(section.get("tables") or [], "tables", where)
    for k, (png, _) in enumerate(out["figures"]):
        if not isinstance(png, str | Path):
            raise InputError(f"'figures'[{k}]: the figure must be a PNG path", where)
        path = Path(png)
        if not path.is_file():
            raise InputError(f"figure file not found: {path}", where)
    notes = section.get("notes") or []
    if isinstance(notes, str) or not isinstance(notes, Sequence) or not all(isinstance(n, str) for n in notes):
        raise InputError("'notes' must be a list of strings", where)
    out["notes"] = list(notes)
    return out


def _anchor(index: int) -> str:
    return f"section-{index}"


def render_section(section: Mapping, index: int = 1) -> str:
    """Render one section: title, the paper's statement, the verdict badge, evidence, figures, tables, notes.

    Parameters
    ----------
    section : dict
        A section (see the module's docstring); validated here.
    index : int, optional
        Its number, counted from 1; the anchor is ``section-<index>``.

    Returns
    -------
    str
        A ``<section>`` fragment.

    Raises
    ------
    InputError
        See :func:`validate_section`; also an unreadable table.
    """
    s = validate_section(section, index)
    where = f"section {index} ({s['title']!r})"
    parts = [
        f'<section class="finding" id="{_anchor(index)}">',
        f"<h2>{index}. {_esc(s['title'])} {_badge(s['verdict'])}</h2>",
        f'<p class="paper"><span class="paper-label">Paper:</span> {_esc(s["paper"])}</p>',
        f'<p class="evidence">{_esc(s["evidence"])}</p>',
    ]
    parts += [render_figure(png, cap, where=where) for png, cap in s["figures"]]
    parts += [render_table(_load_table(src, where), cap) for src, cap in s["tables"]]
    if s["notes"]:
        parts.append('<ul class="notes">' + "".join(f"<li>{_esc(n)}</li>" for n in s["notes"]) + "</ul>")
    parts.append("</section>")
    return "\n".join(parts)


def _summary_table(sections: Sequence[Mapping]) -> str:
    """The table at the top: each section's title, paper statement and verdict, linked to the section."""
    rows = "".join(
        f'<tr><td><a href="#{_anchor(i)}">{i}. {_esc(s["title"])}</a></td><td>{_esc(s["paper"])}</td>'
        f"<td>{_badge(s['verdict'])}</td></tr>"
        for i, s in enumerate(sections, start=1)
    )
    return ('<div class="table-wrap"><table class="summary"><thead><tr><th scope="col">Section</th>'
            '<th scope="col">The paper says</th><th scope="col">Verdict</th></tr></thead>'
            f"<tbody>{rows}</tbody></table></div>")


def render_report(title: str, sections: Sequence[Mapping], *, summary: bool | str | None = None,
                  vehicle: str | None = None, date: _dt.date | str | None = None) -> str:
    """Render the whole report as one HTML document.

    Parameters
    ----------
    title : str
        The report's title.
    sections : list of dict
        The sections (see the module's docstring).
    summary : bool or str, optional
        True or a string: open with a summary table of every section's statement and verdict, linked to
        the sections; a string is also shown as an introductory paragraph above it. None or False: none.
    vehicle : str, optional
        The vehicle the report is about, shown in the header.
    date : datetime.date or str, optional
        The date shown in the header; today by default.

    Returns
    -------
    str
        The HTML document.

    Raises
    ------
    InputError
        A malformed section, a missing figure file (named) or an unreadable table.
    """
    from .. import __version__

    if not isinstance(title, str):
        raise InputError(f"the title must be a string, not {type(title).__name__}", "report")
    if isinstance(sections, Mapping) or not isinstance(sections, Sequence):
        raise InputError("sections must be a list of dicts", "report")
    checked = [validate_section(s, i) for i, s in enumerate(sections, start=1)]
    when = date if date is not None else _dt.date.today()
    when = when.isoformat() if isinstance(when, _dt.date) else str(when)
    meta = [f"<span>Vehicle: <strong>{_esc(vehicle)}</strong></span>"] if vehicle else []
    meta += [f"<span>Date: {_esc(when)}</span>", f"<span>trikedyn {_esc(__version__)}</span>"]
    body = [f"<header><h1>{_esc(title)}</h1><p class=\"meta\">{''.join(meta)}</p></header>"]
    if summary:
        body.append('<h2 id="summary">Summary</h2>')
        if isinstance(summary, str):
            body.append(f'<p class="intro">{_esc(summary)}</p>')
        body.append(_summary_table(checked))
    body += [render_section(s, i) for i, s in enumerate(checked, start=1)]
    body.append(f"<footer>Generated by trikedyn {_esc(__version__)} on {_esc(when)}.</footer>")
    return "\n".join([
        "<!DOCTYPE html>",
        '<html lang="en">',
        "<head>",
        '<meta charset="utf-8">',
        f'<meta http-equiv="Content-Security-Policy" content="{_CSP}">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{_esc(title)}</title>",
        f"<style>{_CSS}</style>",
        "</head>",
        "<body><main>",
        *body,
        "</main></body>",
        "</html>",
        "",
    ])


def write_report(out_dir: str | Path, title: str, sections: Sequence[Mapping], *,
                 summary: bool | str | None = None, vehicle: str | None = None,
                 date: _dt.date | str | None = None) -> Path:
    """Write ``out_dir/report.html``: one self-contained file that renders offline.

    Parameters
    ----------
    out_dir : str or Path
        The folder; created if missing.
    title : str
        The report's title.
    sections : list of dict
        The sections, each a dict with ``title``, ``paper``, ``verdict``, ``evidence`` (strings) and
        optionally ``figures`` (list of (PNG path, caption)), ``tables`` (list of (CSV path or
        DataFrame, caption)) and ``notes`` (list of strings); see the module's docstring.
    summary : bool or str, optional
        True or a string: open with a summary table linking to the sections (a string is shown as an
        introductory paragraph above it). None or False: no summary table.
    vehicle : str, optional
        The vehicle, shown in the header.
    date : datetime.date or str, optional
        The date shown in the header; today by default.

    Returns
    -------
    Path
        The path of ``report.html``.

    Raises
    ------
    InputError
        A malformed section, a missing figure file (named in the message) or an unreadable table.
        Nothing is written then.
    """
    document = render_report(title, sections, summary=summary, vehicle=vehicle, date=date)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    from .._files import atomic_write

    return atomic_write(out / "report.html", lambda fh: fh.write(document), binary=False)

