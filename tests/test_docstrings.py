"""Every public function and method of trikedyn has a numpydoc docstring, with units on physical parameters.

Modelled on python-control's ``control/tests/docstrings_test.py``. What is checked, for each public name:

1. it has a docstring (functions, methods and classes);
2. where a function or method takes parameters other than ``self``/``cls``, its docstring has a ``Parameters``
   section naming each of them (``*args``/``**kwargs`` may be grouped on one line, ``a, b : float`` names
   both); where it returns something (a return annotation other than ``None``, or a ``return <value>`` in its
   own body) it has a ``Returns`` section, or ``Yields`` for a generator. Properties need only a docstring;
3. a parameter whose name ends in a unit suffix (``_m``, ``_s``, ``_kg``, ``_N``, ``_mps``, ``_kmh``, ``_deg``,
   ``_rad``, ...) or that is listed as physical (``PHYSICAL``) has a unit in brackets (``[m]``, ``[km/h]``) or
   the word "dimensionless" (or ``[-]``) in its description; a parameter annotated ``bool`` is a switch and
   needs none.

Public: a name without a leading underscore, in a module whose dotted path has no ``_``-prefixed part; where
the module has ``__all__``, the names it lists. Names imported from another module are checked at home
(``obj.__module__``); numba dispatchers through their ``py_func``; a class's methods are those defined in its
own body. A method without a docstring of its own that overrides a documented one (a log layout's ``read``)
is checked with the docstring it shows, as :func:`inspect.getdoc` and the API pages show it.

The command functions of the CLI (the callbacks registered on the Typer apps of :mod:`trikedyn.cli`, all in
:mod:`trikedyn.commands`) are exempt from rule 2: their docstring is their ``--help`` text and their
parameters are described by the options' own help. So are the builders of the registered manoeuvres: an
option is stated once, in the manoeuvre's ``Option`` table (name, unit, bounds, help), so instead of a
Parameters section each keyword of the builder must be a declared option, with a unit where its name says it
carries one.

numpydoc is not a dependency; sections are found by their underlined headers (a line followed by a line of
dashes), as numpydoc itself does.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import pkgutil
import re
import textwrap

import pytest

import trikedyn

UNIT_SUFFIXES = (
    "_m", "_mm", "_km", "_s", "_ms", "_h", "_kg", "_g", "_N", "_kN", "_Nm", "_Npm", "_Nspm", "_mps", "_mps2",
    "_kmh", "_deg", "_rad", "_rads", "_rad_s", "_deg_s", "_dps", "_hz", "_Hz", "_W", "_kW", "_Wh", "_V", "_A",
    "_Pa", "_kgm2", "_m2", "_m3", "_per_m", "_per_s", "_N_per_m", "_Ns_per_m", "_Nm_per_rad", "_kg_m2",
)
"""Name endings that say a parameter carries a unit."""

PHYSICAL = frozenset({
    "dt", "mass", "speed", "velocity", "stiffness", "damping", "radius", "wheelbase", "track", "gravity",
    "duration", "frequency", "height", "rho",
})
"""Parameter names that are physical quantities without a unit suffix."""

UNIT_RE = re.compile(r"(^|[\s(,;:])\[[^\]\s][^\]]*\]|dimensionless", re.IGNORECASE)
SECTION_RE = re.compile(r"^\s*([A-Z][A-Za-z ]+)\n\s*-{3,}\s*$", re.MULTILINE)


# ---------------------------------------------------------------------------------------------------------
# what is public
# ---------------------------------------------------------------------------------------------------------
def _modules():
    names = [trikedyn.__name__]
    for info in pkgutil.walk_packages(trikedyn.__path__, prefix="trikedyn."):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        names.append(info.name)
    return sorted(names)


def _command_callbacks() -> set:
    """The functions registered as commands on the CLI's Typer apps (recursively)."""
    from trikedyn import cli

    found = set()

    def walk(app):
        for command in app.registered_commands:
            found.add(command.callback)
        for group in app.registered_groups:
            walk(group.typer_instance)

    walk(cli.app)
    return found


def _manoeuvre_builders() -> dict:
    """{builder function: its registered manoeuvre type} of every registered manoeuvre."""
    from trikedyn.manoeuvres.registry import available

    return {_unwrap(kind.builder): kind for kind in available()}


def builder_problems(qual: str, func, kind) -> list[str]:
    """What a manoeuvre builder's keywords lack: each a declared option, with a unit where it is physical."""
    options = {o.name: o for o in kind.options}
    out = []
    for p in inspect.signature(func).parameters.values():
        if p.kind is not inspect.Parameter.KEYWORD_ONLY:
            continue  # (params, speed_kmh): the same for every builder, described by the registry
        if p.name not in options:
            out.append(f"{qual}: keyword {p.name!r} is not a declared option of manoeuvre {kind.name!r}")
        elif _physical(p) and not options[p.name].unit:
            out.append(f"{qual}: option {p.name!r} has no unit")
    return out


def _unwrap(obj):
    py_func = getattr(obj, "py_func", None)  # a numba dispatcher
    return py_func if inspect.isfunction(py_func) else obj


def _inherited_doc(cls, attr):
    """The docstring a method without its own shows: that of the method it overrides (as ``inspect.getdoc``)."""
    for base in cls.__mro__[1:]:
        member = vars(base).get(attr)
        if member is None:
            continue
        member = getattr(member, "__func__", member)
        member = member.fget if isinstance(member, property) else member
        if getattr(member, "__doc__", None):
            return member.__doc__
    return None


def _public_objects():
    """Yield (qualified name, kind, function-or-class, docstring) for every public function, class and method.

    A method without a docstring of its own that overrides a documented one shows (and is checked with) the
    docstring it overrides, as :func:`inspect.getdoc` and the API pages show it.
    """
    for modname in _modules():
        module = importlib.import_module(modname)
        names = getattr(module, "__all__", None)
        if names is None:
            names = [n for n in vars(module) if not n.startswith("_")]
        for name in names:
            if name.startswith("_") or not hasattr(module, name):
                continue
            obj = _unwrap(getattr(module, name))
            if not (inspect.isfunction(obj) or inspect.isclass(obj)) or obj.__module__ != modname:
                continue
            qual = f"{modname}.{name}"
            if inspect.isfunction(obj):
                yield qual, "function", obj, obj.__doc__
                continue
            yield qual, "class", obj, inspect.getdoc(obj)
            for attr, member in vars(obj).items():
                if attr.startswith("_"):
                    continue
                if isinstance(member, property):
                    yield f"{qual}.{attr}", "property", member.fget, member.fget.__doc__ or _inherited_doc(obj, attr)
                    continue
                if hasattr(member, "func") and hasattr(member, "attrname"):  # functools.cached_property
                    yield f"{qual}.{attr}", "property", member.func, member.func.__doc__
                    continue
                kind = "method"
                if isinstance(member, staticmethod):
                    member, kind = member.__func__, "staticmethod"
                elif isinstance(member, classmethod):
                    member = member.__func__
                member = _unwrap(member)
                if inspect.isfunction(member) and member.__module__ == modname:
                    yield f"{qual}.{attr}", kind, member, member.__doc__ or _inherited_doc(obj, attr)


# ---------------------------------------------------------------------------------------------------------
# what a docstring must say
# ---------------------------------------------------------------------------------------------------------
def sections(doc: str) -> dict[str, str]:
    """Split a numpydoc docstring into its sections: {header: body (dedented)}."""
    doc = inspect.cleandoc(doc)
    found = {}
    matches = list(SECTION_RE.finditer(doc))
    for i, match in enumerate(matches):
        end = matches[i + 1].start() if i + 1 < len(matches) else len(doc)
        found[match.group(1).strip()] = textwrap.dedent(doc[match.end():end]).strip("\n")
    return found


def parameter_entries(body: str) -> dict[str, str]:
    """{parameter name: its type and description} of a Parameters section body."""
    entries, current = {}, None
    for line in body.splitlines():
        if line and not line[0].isspace():
            head = line.split(" : ", 1)[0].strip()
            current = [n.strip().lstrip("*") for n in head.split(",") if n.strip()]
            for name in current:
                entries[name] = line[len(head):]
        elif current:
            for name in current:
                entries[name] += "\n" + line
    return entries


def _returns_value(func) -> tuple[bool, bool]:
    """(returns a value, is a generator) from the annotation and the function's own body."""
    try:
        source = textwrap.dedent(inspect.getsource(func))
        tree = ast.parse(source)
    except (OSError, TypeError, SyntaxError):
        return False, False
    node = tree.body[0]
    if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
        return False, False
    returns = yields = False

    def visit(n):
        nonlocal returns, yields
        for child in ast.iter_child_nodes(n):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
                continue
            if isinstance(child, ast.Return) and child.value is not None and not (
                isinstance(child.value, ast.Constant) and child.value.value is None
            ):
                returns = True
            if isinstance(child, (ast.Yield, ast.YieldFrom)):
                yields = True
            visit(child)

    visit(node)
    annotation = node.returns
    if annotation is not None:
        text = ast.unparse(annotation).strip("'\"")
        if text not in ("None", "NoReturn", "typing.NoReturn", "Never"):
            if not yields:
                returns = True
    return returns, yields


def _physical(param: inspect.Parameter) -> bool:
    """A parameter that needs a unit: named with a unit suffix or in PHYSICAL, and not a ``bool`` switch."""
    if param.annotation in (bool, "bool", "bool | None"):
        return False
    return param.name.endswith(UNIT_SUFFIXES) or param.name in PHYSICAL


def problems(qual: str, kind: str, obj, exempt: bool, doc: str | None = None) -> list[str]:
    """What the docstring of ``obj`` (or ``doc``, the one it shows) lacks, as ``qualified.name: what`` lines."""
    if doc is None:
        doc = inspect.getdoc(obj) if kind == "class" else obj.__doc__
    if not doc or not doc.strip():
        return [f"{qual}: no docstring"]
    if kind in ("class", "property") or exempt:
        return []
    out = []
    found = sections(doc)
    try:
        params = list(inspect.signature(obj).parameters.values())
    except (TypeError, ValueError):
        params = []
    if kind == "method" and params and params[0].name in ("self", "cls"):
        params = params[1:]
    elif params and params[0].name in ("self", "cls") and kind != "staticmethod":
        params = params[1:]
    if params:
        if "Parameters" not in found:
            out.append(f"{qual}: no Parameters section")
        else:
            entries = parameter_entries(found["Parameters"])
            for p in params:
                if p.name not in entries:
                    out.append(f"{qual}: parameter {p.name!r} not described")
                elif _physical(p) and not UNIT_RE.search(entries[p.name]):
                    out.append(f"{qual}: parameter {p.name!r} has no unit ([m], [km/h], ... or dimensionless)")
    returns, yields = _returns_value(obj)
    if yields and "Yields" not in found and "Returns" not in found:
        out.append(f"{qual}: no Yields section")
    elif returns and "Returns" not in found:
        out.append(f"{qual}: no Returns section")
    return out


def all_problems() -> dict[str, list[str]]:
    """{qualified name: its problems} over the whole package (names with none are left out)."""
    exempt = _command_callbacks()
    builders = _manoeuvre_builders()
    seen, out = set(), {}
    for qual, kind, obj, doc in _public_objects():
        if qual in seen:
            continue
        seen.add(qual)
        found = problems(qual, kind, obj, obj in exempt or obj in builders, doc)
        if obj in builders:
            found += builder_problems(qual, obj, builders[obj])
        out[qual] = found
    return out


# ---------------------------------------------------------------------------------------------------------
# the tests
# ---------------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def checked():
    return all_problems()


def test_every_public_name_has_a_numpydoc_docstring(checked):
    offenders = [line for _, found in sorted(checked.items()) for line in found]
    assert not offenders, f"{len(offenders)} docstring problems:\n" + "\n".join(offenders)


def test_the_check_finds_what_it_should():
    """The checker itself: each rule catches a docstring that breaks it, and passes one that keeps it."""

    def good(speed_kmh, mu, *args, **kwargs):
        """Do a thing.

        Parameters
        ----------
        speed_kmh : float
            Target speed [km/h].
        mu : float
            Friction coefficient, dimensionless.
        *args, **kwargs
            Passed on.

        Returns
        -------
        float
            A value [m].
        """
        return 1.0

    def bad_unit(length_m):
        """Do a thing.

        Parameters
        ----------
        length_m : list[float]
            A length.
        """

    def missing(a, b) -> int:
        """Do a thing.

        Parameters
        ----------
        a : int
            One.
        """

    def generator(n):
        """Count.

        Parameters
        ----------
        n : int
            How many.
        """
        yield from range(n)

    def nothing():
        pass

    assert problems("m.good", "function", good, False) == []
    assert problems("m.bad_unit", "function", bad_unit, False) == [
        "m.bad_unit: parameter 'length_m' has no unit ([m], [km/h], ... or dimensionless)"]
    assert problems("m.missing", "function", missing, False) == [
        "m.missing: parameter 'b' not described", "m.missing: no Returns section"]
    assert problems("m.generator", "function", generator, False) == ["m.generator: no Yields section"]
    assert problems("m.nothing", "function", nothing, False) == ["m.nothing: no docstring"]
    assert problems("m.missing", "function", missing, True) == []  # a CLI command: the docstring is its help


def test_the_check_reads_inherited_docstrings_and_builders():
    """An undocumented override is checked with the docstring it shows; a manoeuvre builder's keywords are
    checked against its declared options."""
    from types import SimpleNamespace

    from trikedyn.options import Option

    class Base:
        def area(self, width_m):
            """Area.

            Parameters
            ----------
            width_m : float
                Width [m].

            Returns
            -------
            float
                Area [m^2].
            """
            return width_m

    class Child(Base):
        def area(self, width_m):
            return 2 * width_m

    assert _inherited_doc(Child, "area") == Base.area.__doc__
    assert problems("m.Child.area", "method", Child.area, False, _inherited_doc(Child, "area")) == []

    def build(params, speed_kmh, *, radius_m, laps):
        """Drive round."""

    kind = SimpleNamespace(name="round", options=(Option("radius_m", 10.0, ""),))
    assert builder_problems("m.build", build, kind) == [
        "m.build: option 'radius_m' has no unit",
        "m.build: keyword 'laps' is not a declared option of manoeuvre 'round'"]


def test_the_walk_sees_the_package():
    """The walk reaches functions, methods and numba-compiled functions of the package."""
    found = {qual: obj for qual, _, obj, _ in _public_objects()}
    assert "trikedyn.units.kmh_to_mps" in found
    assert "trikedyn.mechanics.mass.Payload.added_to" in found  # a method
    from trikedyn.tyre import contact

    assert found["trikedyn.tyre.contact.road_height"] is contact.road_height.py_func  # numba: its Python source
    assert "trikedyn.vehicle_list" not in found and not any(q.split(".")[1].startswith("_") for q in found)
    assert len(found) > 500
