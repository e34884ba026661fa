"""The documentation (docs/, mkdocs.yml): a strict build, the generated references, and every example run.

How the examples of a page are run (in page order, in an empty folder of their own):

- a fenced block with a title (```` ```toml title="my-trike.toml" ````) is written to that file;
- a ```` ```python ```` block is executed, every block of a page in one namespace (like one session);
- each line of a ```` ```bash ```` block that starts with ``trikedyn`` is run (in this process) and must
  exit 0;
- ```` ```shell ```` blocks are shown, not run; ```` ```text ```` blocks are outputs. An output block marked
  ```` ```text output ```` is checked: each of its lines must be a line that a command of the last bash block
  before it printed, so that the figures a page quotes are the ones a run gives (show the lines that matter;
  leave out the ones that change from run to run, such as wall times).

Every ``trikedyn ...`` command in a bash or shell block, and every ```trikedyn X``` in the text, must name
an existing command whose ``--help`` works, with options that command has.
"""

from __future__ import annotations

import contextlib
import importlib.util
import io
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
DOCS = REPO / "docs"
PAGES = sorted(DOCS.rglob("*.md"))

FENCE = re.compile(r"^```([\w-]*)([^\n]*)\n(.*?)^```[ \t]*$", re.MULTILINE | re.DOTALL)
TITLE = re.compile(r'title="([^"]+)"')
INLINE = re.compile(r"`trikedyn((?: [a-z][a-z0-9-]*)*)[^`]*`")


def page_id(page: Path) -> str:
    return str(page.relative_to(DOCS))


def blocks(page: Path, info: bool = False):
    """``(language, title or None, body, line)`` of each fenced block of a page, in order (and, with ``info``,
    the rest of the fence's info string, e.g. ``output``)."""
    text = page.read_text(encoding="utf-8")
    for match in FENCE.finditer(text):
        title = TITLE.search(match.group(2))
        found = (match.group(1), title.group(1) if title else None, match.group(3),
                 text.count("\n", 0, match.start()) + 1)
        yield (*found, match.group(2)) if info else found


def command_lines(body: str):
    """The ``trikedyn`` command lines of a shell block, as argument lists (comments removed)."""
    for line in body.splitlines():
        line = line.strip().removeprefix("$ ")
        if line.startswith("trikedyn ") or line == "trikedyn":
            yield line, shlex.split(line, comments=True)[1:]


def run_cli(args: list[str]) -> tuple[int, str]:
    """``trikedyn ARGS`` in this process: exit code and what it printed."""
    from trikedyn.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = main(list(args))
    return code, out.getvalue()


def load_hooks():
    spec = importlib.util.spec_from_file_location("trikedyn_docs_hooks", DOCS / "hooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# ------------------------------------------------------------------------------------------------------------
# the build
# ------------------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site, built strictly (a broken link, anchor or cross-reference, or any warning, fails)."""
    for name in ("mkdocs", "material", "mkdocstrings", "mkdocstrings_handlers.python"):
        try:
            importlib.import_module(name)
        except ImportError:
            pytest.skip(f"{name} is not installed (pip install -e '.[docs]'): the docs cannot be built")
    out = tmp_path_factory.mktemp("site")
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet", "-f", str(REPO / "mkdocs.yml"),
         "-d", str(out)], cwd=REPO, env=env, capture_output=True, text=True, timeout=600,
    )
    assert done.returncode == 0, f"mkdocs build --strict failed:\n{done.stdout[-4000:]}\n{done.stderr[-4000:]}"
    return out


def test_docs_build_strictly(site):
    for page in PAGES:
        if page.name == "index.md":
            built = site / page.relative_to(DOCS).parent / "index.html"
        else:
            built = site / page.relative_to(DOCS).with_suffix("") / "index.html"
        assert built.is_file(), f"{page_id(page)} was not built (is it in the nav of mkdocs.yml?)"
        assert "<!-- generated:" not in built.read_text(encoding="utf-8"), page_id(page)


def test_vehicle_file_page_documents_every_key(site):
    from trikedyn.params.schema import VehicleParameters

    hooks = load_hooks()
    html = (site / "reference" / "vehicle-file" / "index.html").read_text(encoding="utf-8")

    def keys(model):
        for name, field in model.model_fields.items():
            yield name
            kind, sub = hooks._nested(field)
            if kind is not None:
                yield from keys(sub)

    forms = ("<code>{}</code>", "<code>[{}]</code>", "<code>[[{}]]</code>", "<code>[{}.NAME]</code>")
    missing = [k for k in keys(VehicleParameters) if not any(form.format(k) in html for form in forms)]
    assert not missing, f"keys of the schema not on the vehicle-file page: {missing}"
    assert "<code>[[wheels]]</code>" in html and "<code>[suspension.NAME]</code>" in html


def command_paths():
    """Every command of the program as its words (``["trikedyn", "cg", "weigh"]``), groups included.

    Duck-typed: recent Typer releases carry their own copy of click, whose classes are not ``click``'s."""
    import typer

    from trikedyn.cli import app

    def walk(command, path):
        yield path, command
        if hasattr(command, "list_commands"):
            ctx = command.context_class(command)
            for name in command.list_commands(ctx):
                yield from walk(command.get_command(ctx, name), [*path, name])

    return list(walk(typer.main.get_command(app), ["trikedyn"]))


def test_cli_page_has_every_command(site):
    html = (site / "reference" / "cli" / "index.html").read_text(encoding="utf-8")
    paths = command_paths()
    assert len(paths) > 20
    for path, _ in paths:
        assert f"Usage: {' '.join(path)} " in html, path


def test_api_page_has_every_flat_name(site):
    import trikedyn

    html = (site / "api" / "index.html").read_text(encoding="utf-8")
    missing = [name for name in trikedyn._LAZY if f"td.{name}" not in html]
    assert not missing, missing


def test_design_outputs_page_names_every_column_and_key():
    """The design-study file formats page names each log's columns and each result's JSON keys as the code writes
    them (a column or key added without the page fails here)."""
    import numpy as np

    from trikedyn.study.designs.optimise_log import EvaluationLog
    from trikedyn.study.designs.sample_runs import SampleLog
    from trikedyn.study.designs.sensitivity import SensitivityResult
    from trikedyn.study.designs.uncertainty import UncertaintyResult

    text = (DOCS / "reference" / "design-outputs.md").read_text(encoding="utf-8")
    named = set(re.findall(r"`([\w+.-]+)`", text))
    columns = SampleLog("x.csv", [], 1).columns + EvaluationLog("x.csv", [], []).columns
    columns += ["freight_kg", "x_m", "z_m", "threshold_speed_kmh", "safe_speed_kmh", "error"]
    assert not [c for c in columns if c not in named]
    empty = (np.zeros((0, 1)), np.zeros(0), [])
    keys = set(SensitivityResult("v", "dlc", "morris", 0.2, 1, 1, [], {}, *empty, [], 0, 0, None).to_dict())
    keys |= set(UncertaintyResult("v", "dlc", 0.2, 1, 1, [], {}, *empty, None).to_dict())
    assert not sorted(keys - named)


# ------------------------------------------------------------------------------------------------------------
# generated from the code
# ------------------------------------------------------------------------------------------------------------
def test_vehicle_reference_follows_the_schema():
    """A field added to the schema shows up in the reference, with its unit, bounds, default and text."""
    from pydantic import Field, create_model

    from trikedyn.params.schema import MassSpec, VehicleParameters

    hooks = load_hooks()

    class MassWithFuel(MassSpec):
        fuel_kg: float = Field(default=0.0, ge=0, le=50, description="fuel aboard [kg]")

    extended = create_model(
        "Extended",
        __base__=VehicleParameters,
        mass=(MassWithFuel, ...),
        hitch_height_m=(float, Field(default=0.3, gt=0, le=1.5, description="tow hitch above the ground [m]")),
    )
    text = hooks.vehicle_file(extended)
    assert "| `fuel_kg` | number | kg | ≥ 0, ≤ 50 | `0` | fuel aboard [kg] |" in text
    assert "| `hitch_height_m` | number | m | > 0, ≤ 1.5 | `0.3` | tow hitch above the ground [m] |" in text
    assert "fuel_kg" not in hooks.vehicle_file()
    # the physical least value of a quantity that must be > 0 is the bound shown
    assert "| `curb_kg` | number | kg | ≥ 10, ≤ 5000 | required |" in text


def test_unknown_generated_part_is_an_error():
    hooks = load_hooks()
    with pytest.raises(ValueError, match="unknown generated part 'nothing'"):
        hooks.expand("text\n<!-- generated: nothing -->\n", "page.md")


# ------------------------------------------------------------------------------------------------------------
# the examples
# ------------------------------------------------------------------------------------------------------------
def resolve(words: list[str]):
    """The command that ``trikedyn WORDS...`` names, and the words that name it; AssertionError if none."""
    import typer

    from trikedyn.cli import app

    command = typer.main.get_command(app)
    path: list[str] = []
    for word in words:
        if not hasattr(command, "list_commands") or word.startswith("-"):
            break
        sub = command.get_command(command.context_class(command), word)
        assert sub is not None, f"`trikedyn {' '.join([*path, word])}`: no such command"
        command, path = sub, [*path, word]
    return command, path


def test_commands_in_the_docs_exist():
    """Every ``trikedyn ...`` in a shell block or in the text names a command (its --help works) and its
    options exist."""
    seen = {}
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for lang, title, body, line in blocks(page):
            if lang in ("bash", "shell") and title is None:
                for shown, args in command_lines(body):
                    seen.setdefault(shown, (f"{page_id(page)}:{line}", args))
        for match in INLINE.finditer(text):
            seen.setdefault(match.group(0), (page_id(page), match.group(1).split()))
    assert len(seen) > 20
    helped = set()
    for shown, (where, args) in seen.items():
        command, path = resolve(args)
        if tuple(path) not in helped:
            code, out = run_cli([*path, "--help"])
            assert code == 0 and "Usage:" in out, f"{where}: {shown}: --help fails\n{out}"
            helped.add(tuple(path))
        options = {opt for param in command.params for opt in (*param.opts, *param.secondary_opts)}
        for token in args[len(path):]:
            if re.match(r"^--?[a-zA-Z]", token):
                name = token.split("=", 1)[0]
                assert name in options, f"{where}: {shown}: `trikedyn {' '.join(path)}` has no option {name}"


EXAMPLE_PAGES = [p for p in PAGES if any(lang in ("python", "bash") or title for lang, title, _, _ in blocks(p))]


@pytest.mark.parametrize("page", EXAMPLE_PAGES, ids=page_id)
def test_examples_run(page, tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__docs__"}
    printed = None  # what the commands of the last bash block printed
    for lang, title, body, line, info in blocks(page, info=True):
        where = f"{page_id(page)}:{line}"
        if lang == "text" and "output" in info.split():
            assert printed is not None, f"{where}: an output block without a bash block before it"
            lines_printed = [row.rstrip() for row in printed.splitlines()]
            for row in body.splitlines():
                if row.strip():
                    assert row.rstrip() in lines_printed, f"{where}: not printed by the command: {row!r}\n{printed[-2000:]}"
        elif title is not None:
            (tmp_path / title).write_text(body, encoding="utf-8")
        elif lang == "python":
            exec(compile(body, where, "exec"), namespace)  # noqa: S102 - the docs' own examples
            plt.close("all")
        elif lang == "bash":
            printed = ""
            for shown, args in command_lines(body):
                code, out = run_cli(args)
                assert code == 0, f"{where}: `{shown}` exited {code}:\n{out[-3000:]}"
                printed += out
