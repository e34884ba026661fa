"""An HTML report of a reproduction, rendered from Jinja2 templates (``paper/templates/*.html.j2``).

The templates are autoescaped: every string from a section (titles, statements, evidence, table cells,
captions) reaches the page as text, never as markup. The only markup that is not escaped is the
templates' own, the MathML of the paper's equations among them (``templates/equations.html.j2``).

The page has no JavaScript and no external URL (no fonts, no CDNs); a Content-Security-Policy ``<meta>``
makes the browser refuse anything else. Images (PNG figures, GIF animations) are either files beside
the report (:func:`write_report`: relative links; a file from elsewhere is copied in) or embedded as
base64 data URIs (:func:`render_report` without ``image_dir``).

A *section* is a plain dict::

    {
        "title": "Suspension stiffness and damping (Table 1)",  # str, required
        "statements": [                                          # required (or the three keys below)
            {"paper": "Eq. 4 gives Table 1's damping", "verdict": "contradicts", "evidence": "..."},
        ],
        "intro": "a paragraph above the statements",             # optional
        "equations": ["eq3", "eq4"],                             # optional: names of EQUATIONS
        "figures": [("fig1.png", "Caption"), ...],               # optional: PNG or GIF paths, captions
        "animations": [("run.gif", "Caption"), ...],             # optional: GIF paths, captions
        "tables": [("table1.csv", "Caption"), ...],              # optional: CSV paths or DataFrames
        "folded": [("study.csv", "Caption"), ...],               # optional: tables folded in <details>
        "notes": ["a remark", ...],                              # optional
    }

A section of one statement may give ``paper``, ``verdict`` and ``evidence`` at its top level instead of
``statements``. Column names become human headers with units
(:func:`~trikedyn.paper.cells.column_header`).

The badge is green for ``"reproduces"``, amber for a qualified agreement (``"reproduces, with a
finding"``, ...), red for ``"contradicts"`` and grey for anything else.
"""

from __future__ import annotations

import base64
import datetime as _dt
import shutil
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..errors import InputError
from .cells import _table, verdict_class

__all__ = ["EQUATIONS", "REQUIRED_KEYS", "OPTIONAL_KEYS", "STATEMENT_KEYS", "render_report", "validate_section",
           "write_report"]

STATEMENT_KEYS = ("paper", "verdict", "evidence")
"""Keys of a statement, each a non-empty string."""

REQUIRED_KEYS = ("title",)
"""Keys every section must have (and ``statements``, or the keys of one statement)."""

OPTIONAL_KEYS = ("statements", *STATEMENT_KEYS, "intro", "equations", "figures", "animations", "tables",
                 "folded", "notes")
"""Keys a section may have."""

EQUATIONS = {
    "eq1": "Eq. 1: logarithmic decrement over n cycles",
    "eq2": "Eq. 2: damping ratio from the logarithmic decrement",
    "eq3": "Eq. 3: suspension stiffness from the natural frequency",
    "eq4": "Eq. 4: damping coefficient from the damping ratio",
    "eq5": "Eq. 5: rollover index of the rear axle",
}
"""The paper's equations a section can show (MathML in ``templates/equations.html.j2``)."""

_SIGNATURES = {b"\x89PNG\r\n\x1a\n": "image/png", b"GIF87a": "image/gif", b"GIF89a": "image/gif"}


def _image_type(path: Path, where: str) -> str:
    """The MIME type of a PNG or GIF file; InputError naming the file if it is missing or neither."""
    if not path.is_file():
        raise InputError(f"figure file not found: {path}", where)
    with path.open("rb") as fh:
        head = fh.read(8)
    for signature, kind in _SIGNATURES.items():
        if head.startswith(signature):
            return kind
    raise InputError(f"figure file is not a PNG or GIF image: {path}", where)


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


def _strings(value: Any, key: str, where: str) -> list[str]:
    if isinstance(value, str) or not isinstance(value, Sequence) or not all(isinstance(n, str) for n in value):
        raise InputError(f"'{key}' must be a list of strings", where)
    return list(value)


def _statement(value: Any, where: str) -> dict:
    if not isinstance(value, Mapping):
        raise InputError(f"a statement must be a dict, not {type(value).__name__}", where)
    for key in STATEMENT_KEYS:
        if key not in value:
            raise InputError(f"missing key '{key}'", where)
        if not isinstance(value[key], str) or not value[key].strip():
            raise InputError(f"'{key}' must be a non-empty string", where)
    return {key: value[key] for key in STATEMENT_KEYS}


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
        A new dict with ``title``, ``statements`` (a list of dicts), ``intro`` and every list key.

    Raises
    ------
    InputError
        Not a dict, a missing or unknown key, a wrong type, an unknown equation, or an image file that is
        missing or not a PNG or GIF.
    """
    where = f"section {index}"
    if not isinstance(section, Mapping):
        raise InputError(f"a section must be a dict, not {type(section).__name__}", where)
    if isinstance(section.get("title"), str) and section["title"].strip():
        where = f"section {index} ({section['title']!r})"
    unknown = sorted(set(section) - set(REQUIRED_KEYS) - set(OPTIONAL_KEYS), key=str)
    if unknown:
        raise InputError(f"unknown key(s) {unknown}; expected {list(REQUIRED_KEYS + OPTIONAL_KEYS)}", where)
    if "title" not in section:
        raise InputError("missing key 'title'", where)
    if not isinstance(section["title"], str) or not section["title"].strip():
        raise InputError("'title' must be a non-empty string", where)
    out = {"title": section["title"]}
    if "statements" in section:
        if any(k in section for k in STATEMENT_KEYS):
            raise InputError("give 'statements' or 'paper', 'verdict' and 'evidence', not both", where)
        items = section["statements"]
        if isinstance(items, str | Mapping) or not isinstance(items, Sequence) or not items:
            raise InputError("'statements' must be a non-empty list of dicts", where)
        out["statements"] = [_statement(s, f"{where}, statement {k}") for k, s in enumerate(items, start=1)]
    else:
        out["statements"] = [_statement(section, where)]
    intro = section.get("intro") or ""
    if not isinstance(intro, str):
        raise InputError("'intro' must be a string", where)
    out["intro"] = intro
    out["equations"] = _strings(section.get("equations") or [], "equations", where)
    for name in out["equations"]:
        if name not in EQUATIONS:
            raise InputError(f"unknown equation {name!r}; expected one of {list(EQUATIONS)}", where)
    for key in ("figures", "animations"):
        out[key] = _pairs(section.get(key) or [], key, where)
        for k, (image, _) in enumerate(out[key]):
            if not isinstance(image, str | Path):
                raise InputError(f"'{key}'[{k}]: the image must be a file path", where)
            _image_type(Path(image), where)
    for key in ("tables", "folded"):
        out[key] = _pairs(section.get(key) or [], key, where)
    out["notes"] = _strings(section.get("notes") or [], "notes", where)
    return out


def _environment():
    import jinja2

    return jinja2.Environment(loader=jinja2.PackageLoader("trikedyn.paper", "templates"), autoescape=True,
                              undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True,
                              keep_trailing_newline=True)


def _image_source(path: Path, image_dir: Path | None, taken: dict, where: str) -> str:
    """The ``src`` of an image: a data URI, or its name relative to ``image_dir`` (copied in if elsewhere)."""
    kind = _image_type(path, where)
    if image_dir is None:
        return f"data:{kind};base64," + base64.b64encode(path.read_bytes()).decode("ascii")
    image_dir = Path(image_dir)
    try:
        return path.resolve().relative_to(image_dir.resolve()).as_posix()
    except ValueError:
        pass
    key = path.resolve()
    if key not in taken:
        name, k = path.name, 1
        while name in taken.values() or (image_dir / name).exists():
            name, k = f"{path.stem}-{k}{path.suffix}", k + 1
        taken[key] = name
        shutil.copyfile(path, image_dir / name)
    return taken[key]


def _context(title: str, sections: Sequence[Mapping], *, summary, vehicle, date, image_dir) -> dict:
    from .._version import __version__

    if not isinstance(title, str):
        raise InputError(f"the title must be a string, not {type(title).__name__}", "report")
    if isinstance(sections, Mapping) or not isinstance(sections, Sequence):
        raise InputError("sections must be a list of dicts", "report")
    checked = [validate_section(s, i) for i, s in enumerate(sections, start=1)]
    prepared, taken = [], {}
    for i, s in enumerate(checked, start=1):
        where = f"section {i} ({s['title']!r})"
        prepared.append({
            **s,
            "anchor": f"section-{i}",
            "statements": [{**st, "badge": verdict_class(st["verdict"])} for st in s["statements"]],
            "equations": [(name, EQUATIONS[name]) for name in s["equations"]],
            "figures": [(_image_source(Path(p), image_dir, taken, where), cap, Path(p).name) for p, cap in s["figures"]],
            "animations": [(_image_source(Path(p), image_dir, taken, where), cap, Path(p).name)
                           for p, cap in s["animations"]],
            "tables": [_table(src, cap, where) for src, cap in s["tables"]],
            "folded": [_table(src, cap, where) for src, cap in s["folded"]],
        })
    when = date if date is not None else _dt.date.today()
    when = when.isoformat() if isinstance(when, _dt.date) else str(when)
    return {"title": title, "sections": prepared, "summary": bool(summary),
            "intro": summary if isinstance(summary, str) else "", "vehicle": vehicle, "date": when,
            "version": __version__, "self_contained": image_dir is None}


def render_report(title: str, sections: Sequence[Mapping], *, summary: bool | str | None = None,
                  vehicle: str | None = None, date: _dt.date | str | None = None,
                  image_dir: str | Path | None = None) -> str:
    """Render the whole report as one HTML document.

    Parameters
    ----------
    title : str
        The report's title.
    sections : list of dict
        The sections (see the module's docstring).
    summary : bool or str, optional
        True or a string: open with a summary table of every statement and its verdict, linked to the
        sections; a string is also shown as an introductory paragraph above it. None or False: none.
    vehicle : str, optional
        The vehicle the report is about, shown in the header.
    date : datetime.date or str, optional
        The date shown in the header; today by default.
    image_dir : str or Path, optional
        The folder the report will be in: images are linked relative to it (an image from elsewhere is
        copied in). None: images are embedded as data URIs (one self-contained file).

    Returns
    -------
    str
        The HTML document.

    Raises
    ------
    InputError
        A malformed section, a missing image file (named) or an unreadable table.
    """
    context = _context(title, sections, summary=summary, vehicle=vehicle, date=date, image_dir=image_dir)
    return _environment().get_template("report.html.j2").render(context)


def write_report(out_dir: str | Path, title: str, sections: Sequence[Mapping], *,
                 summary: bool | str | None = None, vehicle: str | None = None,
                 date: _dt.date | str | None = None, embed: bool = False) -> Path:
    """Write ``out_dir/report.html``, its images beside it (or embedded with ``embed=True``).

    Parameters
    ----------
    out_dir : str or Path
        The folder; created if missing.
    title : str
        The report's title.
    sections : list of dict
        The sections; see the module's docstring.
    summary : bool or str, optional
        True or a string: open with a summary table linking to the sections (a string is shown as an
        introductory paragraph above it). None or False: no summary table.
    vehicle : str, optional
        The vehicle, shown in the header.
    date : datetime.date or str, optional
        The date shown in the header; today by default.
    embed : bool, optional
        Embed the images as data URIs (one self-contained file) instead of linking them.

    Returns
    -------
    Path
        The path of ``report.html``.

    Raises
    ------
    InputError
        A malformed section, a missing image file (named in the message) or an unreadable table. The
        report is not written then.
    """
    from .._files import atomic_write

    out = Path(out_dir)
    if isinstance(sections, Mapping) or not isinstance(sections, Sequence):
        raise InputError("sections must be a list of dicts", "report")
    for i, s in enumerate(sections, start=1):  # every section checked before anything is written or copied
        validate_section(s, i)
    out.mkdir(parents=True, exist_ok=True)
    document = render_report(title, sections, summary=summary, vehicle=vehicle, date=date,
                             image_dir=None if embed else out)
    return atomic_write(out / "report.html", lambda fh: fh.write(document), binary=False)
