"""The import graph of ``trikedyn``, read from the code with :mod:`ast` (issue 22).

What counts as an arrow ``A -> B`` (A imports B):

* every ``import`` and ``from ... import`` statement in A, at module level *and* inside functions, classes and
  ``try`` blocks (a function-level import still runs, only later); relative imports are resolved against A's
  package;
* statements under ``if TYPE_CHECKING:`` (or ``typing.TYPE_CHECKING``) are left out: they never run;
* the target is the module the statement names: ``import trikedyn.x.y`` and ``from trikedyn.x import y`` (``y`` a
  submodule) point at ``trikedyn.x.y``; ``from trikedyn.x import name`` (``name`` not a submodule) points at
  ``trikedyn.x`` itself, that is at ``trikedyn/x/__init__.py``;
* the parent packages that Python runs on the way (``trikedyn/x/__init__.py`` before ``trikedyn/x/y.py``) are
  *not* arrows: a package's ``__init__`` is a facade that may load its own submodules, and a submodule loaded
  through it sees its siblings already bound or loads them itself;
* imports done with :func:`importlib.import_module` (the lazy tables of ``trikedyn/__init__.py`` and
  ``trikedyn/study/__init__.py``, the plug-in discovery of ``measure/formats``) are not seen.

The rule for facades that follows: a module inside a package never imports *names* from its own package's
``__init__`` or from an ancestor's (the facade re-exports it, directly or lazily, so that is a circle whether the
graph sees the re-export or not); it imports from the module that defines the name. Test (c) checks that, and
test (b) finds the remaining circles (strongly connected components of more than one module, ``__init__`` files
included).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = "trikedyn"
ROOT = Path(__file__).resolve().parents[1] / "src" / PACKAGE


def _modules(root: Path = ROOT) -> dict[str, Path]:
    """Dotted module name -> file, for every ``.py`` file under ``root`` (``pkg/__init__.py`` named ``pkg``)."""
    found = {}
    for path in sorted(root.rglob("*.py")):
        parts = list(path.relative_to(root.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        found[".".join(parts)] = path
    return found


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _import_nodes(tree: ast.AST):
    """Every import statement that can run: all of them but those under ``if TYPE_CHECKING:``."""
    todo = [tree]
    while todo:
        node = todo.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
            continue
        if isinstance(node, ast.If) and _is_type_checking(node.test):
            todo.extend(node.orelse)
            continue
        todo.extend(ast.iter_child_nodes(node))


def _targets(module: str, is_package: bool, node: ast.Import | ast.ImportFrom, modules: dict) -> set[str]:
    """The package modules an import statement points at (see the module docstring for the rule)."""
    if isinstance(node, ast.Import):
        names = [alias.name for alias in node.names]
    else:
        if node.level:
            base = module.split(".") if is_package else module.split(".")[:-1]
            base = base[: len(base) - (node.level - 1)]
            stem = ".".join(base + ([node.module] if node.module else []))
        else:
            stem = node.module or ""
        names = []
        for alias in node.names:
            names.append(f"{stem}.{alias.name}" if f"{stem}.{alias.name}" in modules else stem)
    out = set()
    for name in names:
        while name and name not in modules:
            name = name.rpartition(".")[0]
        if name and name != module:
            out.add(name)
    return out


def import_graph(root: Path = ROOT) -> dict[str, set[str]]:
    """Module -> the package modules it imports (module- and function-level, ``TYPE_CHECKING`` left out)."""
    modules = _modules(root)
    graph = {}
    for name, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        graph[name] = set()
        for node in _import_nodes(tree):
            graph[name] |= _targets(name, path.name == "__init__.py", node, modules)
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan, iterative), each sorted."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []
    counter = 0
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, successors = work[-1]
            for successor in successors:
                if successor not in index:
                    index[successor] = low[successor] = counter
                    counter += 1
                    stack.append(successor)
                    on_stack.add(successor)
                    work.append((successor, iter(sorted(graph[successor]))))
                    break
                if successor in on_stack:
                    low[node] = min(low[node], index[successor])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
    return found


def _arrows_within(component: list[str], graph: dict[str, set[str]]) -> list[str]:
    members = set(component)
    return [f"{a} -> {b}" for a in component for b in sorted(graph[a] & members)]


@pytest.fixture(scope="module")
def graph():
    return import_graph()


def test_the_graph_reader_sees_what_it_should(tmp_path):
    """The reader itself: function-level and relative imports seen, TYPE_CHECKING skipped, a circle found."""
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("from .b import thing\n")
    (pkg / "a.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .sub import c\n"
                              "def f():\n    from .sub import b\n")
    (pkg / "sub" / "b.py").write_text("thing = 1\ndef g():\n    from ..a import f\n")
    (pkg / "sub" / "c.py").write_text("from . import thing\n")
    seen = import_graph(pkg)
    assert seen["pkg.a"] == {"pkg.sub.b"}
    assert seen["pkg.sub"] == {"pkg.sub.b"}
    assert seen["pkg.sub.c"] == {"pkg.sub"}
    assert circles(seen) == [["pkg.a", "pkg.sub.b"]]


def test_a_no_import_runs_back_up_into_the_command_line(graph):
    """(a) Only ``trikedyn.cli``, ``trikedyn.__main__`` and ``trikedyn.commands.*`` import the CLI's modules."""
    def is_cli(name):
        return name in (f"{PACKAGE}.cli", f"{PACKAGE}.__main__") or name == f"{PACKAGE}.commands" or \
            name.startswith(f"{PACKAGE}.commands.")

    arrows = [f"{a} -> {b}" for a, targets in sorted(graph.items()) if not is_cli(a)
              for b in sorted(targets) if is_cli(b) and b != f"{PACKAGE}.__main__"]
    assert arrows == [], "imports that run back up into the CLI:\n" + "\n".join(arrows)


def test_b_no_import_circle(graph):
    """(b) No strongly connected component of more than one module; the message names the arrows inside."""
    found = circles(graph)
    message = "\n\n".join(" <-> ".join(c) + ":\n  " + "\n  ".join(_arrows_within(c, graph)) for c in found)
    assert found == [], "import circles:\n" + message


def test_c_no_module_imports_names_from_its_own_facade(graph):
    """(c) A module never imports from its own package's ``__init__`` or an ancestor's (the facade's rule)."""
    modules = _modules()
    arrows = []
    for name, targets in sorted(graph.items()):
        own = name if modules[name].name == "__init__.py" else name.rpartition(".")[0]
        ancestors = {".".join(own.split(".")[:i]) for i in range(1, own.count(".") + 2)}
        arrows += [f"{name} -> {t}" for t in sorted(targets & ancestors)
                   if modules[t].name == "__init__.py" and t != name]
    assert arrows == [], "imports from an own package's facade:\n" + "\n".join(arrows)
