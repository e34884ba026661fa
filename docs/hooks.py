"""MkDocs hooks: the parts of the documentation generated from the code at build time, so they cannot drift.

A page asks for a generated part with a marker on a line of its own, ``<!-- generated: NAME -->``; NAME is
a key of :data:`GENERATORS` (an unknown name fails the build). What is generated:

- ``vehicle-file``: every key of a vehicle TOML file with its type, unit, bounds, default and description,
  from the pydantic schema (:class:`trikedyn.params.schema.VehicleParameters`);
- ``weighing-file``, ``study-spec``: the same for the weighing record and the study spec models;
- ``log-formats``, ``channels``, ``manoeuvres``, ``presets``: tables from the registries and constants;
- ``cli``: the ``--help`` of every command, walked from the Typer app;
- ``api-flat``: a mkdocstrings entry for each name of the flat API (``trikedyn._LAZY``).

The functions are plain (``tests/test_docs.py`` imports this file and calls them on a schema with an
added field). After a page is rendered, Sphinx-style roles left in docstrings (``:func:`name```) become
optional cross-references: links where the name is documented, code where it is not.
"""

from __future__ import annotations

import re
import types
import typing
from collections import defaultdict

MARKER = re.compile(r"^<!--\s*generated:\s*([a-z-]+)\s*-->\s*$", re.MULTILINE)

# ------------------------------------------------------------------------------------------------------------
# units and numbers
# ------------------------------------------------------------------------------------------------------------
UNIT_SUFFIXES = (  # longest first: the unit a key's name ends with
    ("_deg_per_s", "deg/s"),
    ("_kg_per_m3", "kg/m³"),
    ("_mps2_per_s", "m/s³"),
    ("_N_per_m", "N/m"),
    ("_Ns_per_m", "N s/m"),
    ("_kgm2", "kg m²"),
    ("_radps", "rad/s"),
    ("_mps2", "m/s²"),
    ("_degC", "°C"),
    ("_kmh", "km/h"),
    ("_mps", "m/s"),
    ("_deg", "deg"),
    ("_rad", "rad"),
    ("_Nm", "N m"),
    ("_m2", "m²"),
    ("_hz", "Hz"),
    ("_kg", "kg"),
    ("_N", "N"),
    ("_W", "W"),
    ("_s", "s"),
    ("_m", "m"),
    ("_g", "g"),
)


def unit_of(name: str) -> str:
    """The unit a name carries in its suffix (``stiffness_N_per_m`` -> ``N/m``), or ``""``."""
    for suffix, unit in UNIT_SUFFIXES:
        if name.endswith(suffix):
            return unit
    return ""


def number(value) -> str:
    """A bound or default as written in a TOML file (``1e7``, not ``1e+07``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        text = f"{value:g}"
        return re.sub(r"e\+?(-?)0*(\d)", r"e\1\2", text)
    return str(value)


def humanise(name: str) -> str:
    """A name without its unit suffix, in words (``vertical_stiffness_N_per_m`` -> ``vertical stiffness``)."""
    for suffix, _ in UNIT_SUFFIXES:
        if name.endswith(suffix):
            name = name[: -len(suffix)]
            break
    return name.replace("_", " ")


def cell(text: str) -> str:
    """Text safe inside a Markdown table cell."""
    return str(text).replace("|", "\\|").replace("\n", " ")


# ------------------------------------------------------------------------------------------------------------
# pydantic models -> tables of keys
# ------------------------------------------------------------------------------------------------------------
def _is_model(tp) -> bool:
    from pydantic import BaseModel

    return isinstance(tp, type) and issubclass(tp, BaseModel)


def _strip(tp):
    """The annotation without ``Annotated`` and ``None`` alternatives, and the metadata found on the way."""
    meta = []
    while True:
        origin = typing.get_origin(tp)
        if origin is typing.Annotated:
            tp, *extra = typing.get_args(tp)
            meta.extend(extra)
        elif origin in (typing.Union, types.UnionType):
            args = [a for a in typing.get_args(tp) if a is not type(None)]
            if len(args) != 1:
                return tp, meta
            tp = args[0]
        else:
            return tp, meta


def type_text(tp) -> str:
    """A TOML reader's name for a type."""
    tp, _ = _strip(tp)
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if tp is float:
        return "number"
    if tp is int:
        return "integer"
    if tp is bool:
        return "true / false"
    if tp is str:
        return "text"
    if origin is typing.Literal:
        return " or ".join(f'`"{a}"`' if isinstance(a, str) else f"`{number(a)}`" for a in args)
    if origin in (typing.Union, types.UnionType):
        return " or ".join(type_text(a) for a in args if a is not type(None))
    if _is_model(tp):
        return "table"
    if origin in (list, tuple):
        if origin is tuple and args and args[-1] is not Ellipsis:
            return "[" + ", ".join(type_text(a) for a in args) + "]"
        inner = args[0] if args else typing.Any
        return "array of tables" if _is_model(_strip(inner)[0]) else f"array of {type_text(inner)}"
    if origin is dict:
        value = args[1] if len(args) == 2 else typing.Any
        if _is_model(_strip(value)[0]):
            return "tables by name"
        return f"table: name = {type_text(value)}"
    return getattr(tp, "__name__", str(tp))


def bounds_text(field) -> str:
    """The bounds of a field: numeric range (with the physical least value of ``_at_least``), lengths, pattern."""
    _, inner = _strip(field.annotation)
    lower = upper = None
    parts = []
    least = None
    lengths = [None, None]
    for item in [*field.metadata, *inner]:
        for attr, kind in (("gt", ">"), ("ge", "≥")):
            if getattr(item, attr, None) is not None and type(item).__name__ in ("Gt", "Ge"):
                lower = (kind, getattr(item, attr))
        for attr, kind in (("lt", "<"), ("le", "≤")):
            if getattr(item, attr, None) is not None and type(item).__name__ in ("Lt", "Le"):
                upper = (kind, getattr(item, attr))
        if type(item).__name__ == "MinLen":
            lengths[0] = item.min_length
        if type(item).__name__ == "MaxLen":
            lengths[1] = item.max_length
        pattern = getattr(item, "pattern", None)
        if isinstance(pattern, str):
            parts.append(f"matches `{pattern}`")
        func = getattr(item, "func", None)
        if getattr(func, "minimum", None) is not None:
            least = func.minimum
    if least is not None and (lower is None or least >= lower[1]):
        lower = ("≥", least)
    numeric = [f"{b[0]} {number(b[1])}" for b in (lower, upper) if b is not None]
    tp, _ = _strip(field.annotation)
    noun = "characters" if tp is str else "entries"
    if lengths[0] is not None and lengths[1] is not None:
        parts.insert(0, f"{lengths[0]}–{lengths[1]} {noun}" if lengths[0] != lengths[1] else f"{lengths[0]} {noun}")
    elif lengths[0] is not None:
        parts.insert(0, f"at least {lengths[0]} {noun}")
    elif lengths[1] is not None:
        parts.insert(0, f"at most {lengths[1]} {noun}")
    return ", ".join(numeric + parts)


def default_text(field) -> str:
    """A field's default as TOML, ``required``, or ``(none)`` for an optional value."""
    from pydantic_core import PydanticUndefined

    if field.is_required():
        return "required"
    value = field.get_default(call_default_factory=True)
    if value is None:
        return "(none)"
    if isinstance(value, str):
        return f'`"{value}"`'
    if isinstance(value, list | tuple):
        if not value:
            return "`[]`"
        return "`[" + ", ".join(number(v) if not isinstance(v, str) else f'"{v}"' for v in value) + "]`"
    if isinstance(value, dict):
        return "`{}`" if not value else "(see below)"
    if value is PydanticUndefined:
        return "required"
    if _is_model(type(value)):
        return "(see below)"
    return f"`{number(value)}`"


def first_paragraph(doc: str | None) -> str:
    """The first paragraph of a docstring, on one line."""
    if not doc:
        return ""
    return " ".join(doc.strip().split("\n\n")[0].split())


def _nested(field):
    """``(kind, model)`` of a field holding tables: ``"table"``, ``"named"`` (dict of) or ``"array"``."""
    tp, _ = _strip(field.annotation)
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if _is_model(tp):
        return "table", tp
    if origin is dict and len(args) == 2 and _is_model(_strip(args[1])[0]):
        return "named", _strip(args[1])[0]
    if origin in (list, tuple) and args and _is_model(_strip(args[0])[0]):
        return "array", _strip(args[0])[0]
    return None, None


FALLBACK_TEXT = {
    # Descriptions for fields whose schema gives none (the schema's own ``description`` wins when it has one).
    ("VehicleParameters", "name"): "short name of the parameter set (shown in results and reports)",
    ("VehicleParameters", "description"): "what vehicle this is, in a sentence",
    ("VehicleParameters", "source"): "where the values come from (paper, measurements, date)",
    ("VehicleParameters", "layout"): "delta: one steered front wheel, two rear; tadpole: two steered front, one rear",
    ("BodySpec", "overall_width_m"): "overall width of the vehicle (sets the ISO 3888 lane widths)",
    ("BodySpec", "overall_length_m"): "overall length of the vehicle",
    ("SuspensionSpec", "kind"): "telescopic fork (along the steering axis) or trailing swing arm",
    ("WheelSpec", "steered"): "turned by the steering",
    ("WheelSpec", "driven"): "driven through the open differential",
    ("WheelSpec", "braked"): "has a brake",
    ("TyreSpec", "vertical_stiffness_N_per_m"): "tyre vertical stiffness kz (paper: 200 kN/m)",
    ("TyreSpec", "vertical_damping_Ns_per_m"): "tyre vertical damping cz (paper: 75 N s/m)",
    ("DriveSpec", "differential"): "differential between the driven wheels",
    ("AeroSpec", "drag_coefficient"): "drag coefficient Cd",
    ("AeroSpec", "frontal_area_m2"): "frontal area A",
    ("AeroSpec", "air_density_kg_per_m3"): "air density rho",
    ("PointSpec", "x_m"): "ahead of the rear axle",
    ("PointSpec", "y_m"): "left of the centre line",
    ("PointSpec", "z_m"): "above the ground",
    ("PayloadItemSpec", "name"): "what the item is",
    ("PayloadItemSpec", "mass_kg"): "its mass",
    ("PayloadItemSpec", "x_m"): "its centre, ahead of the rear axle",
    ("PayloadItemSpec", "y_m"): "its centre, left of the centre line",
    ("PayloadItemSpec", "z_m"): "its centre, above the ground",
    ("WeighingRecord", "description"): "what was weighed, when",
    ("WeighingRecord", "reading_std_kg"): "standard uncertainty of one scale reading (carried into the CG)",
    ("WeighingRecord", "wheel_radius_m"): "loaded wheel radius: the axle height (needed with [[tilted]])",
    ("WeighingRecord", "contacts"): "contact point of each wheel: [x ahead of the rear axle, y left] in m",
    ("WeighingRecord", "level"): "scale reading under each wheel, vehicle level [kg]; same wheel names as contacts",
    ("TiltedWeighing", "raised"): "the axle lifted (the same in every entry)",
    ("TiltedWeighing", "raised_axle_kg"): "scale reading under the raised axle, the sum of its wheels; ≥ 0",
    ("_Spec", "name"): "name of the study (shown in its summary)",
    ("_Spec", "description"): "what the study asks",
    ("_Spec", "vehicle"): "preset name, or a .toml vehicle file relative to the spec file",
    ("_Spec", "manoeuvres"): "registered manoeuvres (see the manoeuvre reference), each with its default options",
    ("_Spec", "freight_kg"): "the paper's freight in the trunk, one scenario per value; each ≥ 0",
    ("_Spec", "resolution_kmh"): "threshold search: bisection resolution",
    ("_Spec", "low_kmh"): "threshold search: lowest speed (should pass)",
    ("_Spec", "high_kmh"): "threshold search: highest speed",
    ("_Spec", "step_kmh"): "threshold search: bracketing step",
    ("_Group", "name"): "name of the group (a scenario carries the names of the groups that hold it)",
    ("_Group", "stiffness_scale"): "factors on every suspension stiffness (Table 2: 0.8, 1.0, 1.2); each > 0",
    ("_Group", "damping_scale"): "factors on every suspension damping; each > 0",
    ("_Group", "overrides"): "dotted parameter path = list of values, each list one more grid axis",
}


def key_table(model, fields=None) -> str:
    """A Markdown table of a model's scalar keys."""
    rows = ["| key | type | unit | bounds | default | description |", "| --- | --- | --- | --- | --- | --- |"]
    for name, field in model.model_fields.items():
        if fields is not None and name not in fields:
            continue
        kind, sub = _nested(field)
        description = field.description or FALLBACK_TEXT.get((model.__name__, name)) or humanise(name)
        if kind is not None:
            description = f"{description} (see {table_header(name, kind, sub)})"
        unit = unit_of(name)
        if not unit and field.description and _strip(field.annotation)[0] in (float, int):
            # a number's unit in brackets at the end of the schema's description
            found = re.search(r"\[([^\]]+)\]\s*$", field.description)
            unit = found.group(1) if found and found.group(1) != "1" else ""
        rows.append(
            f"| `{name}` | {cell(type_text(field.annotation))} | {cell(unit) or '–'} | "
            f"{cell(bounds_text(field)) or '–'} | {cell(default_text(field))} | {cell(description)} |"
        )
    return "\n".join(rows)


def table_header(path: str, kind: str, model=None) -> str:
    """How the table of a nested field is written in TOML."""
    if kind == "named":
        return f"`[{path}.NAME]`"
    if kind == "array":
        return f"`[[{path}]]`"
    return f"`[{path}]`"


def model_reference(model, level: int = 3, path: str = "", top_title: str = "Top-level keys") -> str:
    """Every key of a pydantic model and of the tables nested in it, as Markdown tables under headings
    that say how each table is written in TOML (``[mass]``, ``[suspension.NAME]``, ``[[wheels]]``)."""
    out = []
    scalars = [n for n, f in model.model_fields.items() if _nested(f)[0] is None]
    if scalars:
        if not path:
            out.append(f"{'#' * level} {top_title}\n")
        out.append(key_table(model, scalars) + "\n")
    for name, field in model.model_fields.items():
        kind, sub = _nested(field)
        if kind is None:
            continue
        dotted = f"{path}.{name}" if path else name
        out.append(f"{'#' * level} {table_header(dotted, kind, sub)}\n")
        described = field.description and field.description[0].upper() + field.description[1:] + "."
        intro = " ".join(x for x in (described, first_paragraph(sub.__doc__)) if x)
        if kind == "named":
            intro += " One table per name; the name is how other keys refer to it."
        if kind == "array":
            intro += " One `[[...]]` table per entry."
        if intro.strip():
            out.append(intro.strip() + "\n")
        out.append(model_reference(sub, level, f"{dotted}.NAME" if kind == "named" else dotted))
    return "\n".join(out)


# ------------------------------------------------------------------------------------------------------------
# the generators
# ------------------------------------------------------------------------------------------------------------
def vehicle_file(model=None) -> str:
    """Every key of a vehicle file, from :class:`~trikedyn.params.schema.VehicleParameters` (or ``model``)."""
    if model is None:
        from trikedyn.params.schema import VehicleParameters as model
    return model_reference(model)


def weighing_file() -> str:
    from trikedyn.measure.weighing import WeighingRecord

    return model_reference(WeighingRecord)


def study_spec() -> str:
    from trikedyn.study.spec_model import _Spec

    return model_reference(_Spec)


def search_settings() -> str:
    """The threshold search's settings with their defaults and bounds (one set for the command line, the study
    spec and the optimise spec: trikedyn.analysis.search_settings), and the variant's numbers."""
    from trikedyn.analysis.search_settings import search_options
    from trikedyn.params.variant import VARIANT_OPTIONS

    rows = ["| key | default | unit | allowed | what |", "| --- | --- | --- | --- | --- |"]
    for o in (*search_options(), *VARIANT_OPTIONS):
        allowed = (", ".join(f"`{c}`" for c in o.choices) if o.choices
                   else f"{o.minimum:g} to {o.maximum:g}" if o.minimum is not None else "")
        rows.append(f"| `{o.name}` | `{o.default}` | {o.unit} | {allowed} | {cell(o.help)} |")
    return "\n".join(rows)


def presets() -> str:
    from trikedyn.params import list_presets, load_vehicle

    rows = ["| preset | description |", "| --- | --- |"]
    for name in list_presets():
        rows.append(f"| `{name}` | {cell(load_vehicle(name).params.description)} |")
    return "\n".join(rows)


def log_formats() -> str:
    from trikedyn.measure import logs

    rows = ["| `--format` | what it is |", "| --- | --- |"]
    rows += [f"| `{key}` | {cell(text)} |" for key, text in logs.FORMATS.items()]
    channels = ", ".join(f"`{c}` [{unit_of(c)}]" for c in logs.CHANNELS)
    return "\n".join(rows) + f"\n\nEvery reader gives `time_s` [s] and any of {channels}, in SI units.\n"


CHANNEL_TEXT = {
    "x_m": "chassis reference point, road axes (forward along the start heading)",
    "y_m": "chassis reference point, road axes (left)",
    "z_m": "chassis reference point, road axes (up)",
    "roll_rad": "chassis roll angle (about x, right-handed: positive leans right)",
    "pitch_rad": "chassis pitch angle (about y, positive nose down)",
    "yaw_rad": "chassis heading (about z, positive to the left)",
    "roll_rate_radps": "chassis angular velocity about its x axis",
    "pitch_rate_radps": "chassis angular velocity about its y axis",
    "yaw_rate_radps": "chassis angular velocity about its z axis",
    "vx_mps": "velocity of the CG, chassis x (forward)",
    "vy_mps": "velocity of the CG, chassis y (left)",
    "vz_mps": "velocity of the CG, chassis z (up)",
    "ax_mps2": "acceleration of the CG, chassis x, without gravity",
    "ay_mps2": "acceleration of the CG, chassis y (lateral), without gravity",
    "az_mps2": "acceleration of the CG, chassis z, without gravity",
    "speed_mps": "horizontal speed of the CG",
    "steer_rad": "steer angle about the steering axis (positive left)",
    "fx_N": "longitudinal tyre force (positive forward)",
    "fy_N": "lateral tyre force (positive left)",
    "fz_N": "vertical tyre force (wheel load; 0 when the wheel is off the ground)",
    "kappa": "longitudinal slip ratio (positive driving)",
    "alpha_rad": "slip angle",
    "deflection_m": "tyre deflection",
    "travel_m": "suspension travel from static (positive in bump)",
    "spin_radps": "wheel spin rate",
    "vx_mps_wheel": "forward speed of the wheel centre",
    "mz_Nm": "aligning moment of the tyre (about the vertical)",
    "camber_rad": "camber (inclination) angle of the wheel to the road",
}


IMU_TEXT = {
    "ax_mps2": "specific force along chassis x (forward), gravity included",
    "ay_mps2": "specific force along chassis y (left), gravity included",
    "az_mps2": "specific force along chassis z (up), gravity included: about +9.81 at rest",
    "wx_radps": "angular rate about chassis x (roll rate)",
    "wy_radps": "angular rate about chassis y (pitch rate)",
    "wz_radps": "angular rate about chassis z (yaw rate)",
    "roll_rad": "roll angle of the chassis",
    "pitch_rad": "pitch angle of the chassis",
    "yaw_rad": "heading of the chassis",
}


def channels() -> str:
    from trikedyn.simulate.channels import BASE_CHANNELS, IMU_CHANNELS, WHEEL_CHANNELS

    def row(name, text, unit=None):
        unit = unit_of(name) if unit is None else unit
        return f"| `{name}` | {unit or '–'} | {cell(text)} |"

    head = ["| channel | unit | what it is |", "| --- | --- | --- |"]
    out = ["### Vehicle channels\n", *head]
    out += [row(n, CHANNEL_TEXT.get(n, humanise(n))) for n in BASE_CHANNELS]
    out += ["", "### Per wheel: `<wheel>_<quantity>`\n",
            "One column per wheel and quantity, e.g. `rear_left_fz_N`; wheels are named as in the vehicle file "
            "(`front`, `rear_left`, `rear_right` for a delta trike).\n", *head]
    out += [row(n, CHANNEL_TEXT.get(n + "_wheel" if n == "vx_mps" else n, humanise(n))) for n in WHEEL_CHANNELS]
    out += ["", "### The emulated IMU: `imu_<channel>`\n",
            "What an IMU fixed to the chassis at the vehicle file's `[sensor]` point reads: specific force "
            "(gravity included: `imu_az_mps2` is about +9.81 at rest), angular rate in chassis axes, and "
            "its Euler angles. The names after `imu_` are those of an IMU log.\n", *head]
    out += [row(f"imu_{n}", IMU_TEXT.get(n, humanise(n)), unit_of(n)) for n in IMU_CHANNELS]
    return "\n".join(out) + "\n"


def manoeuvres() -> str:
    from trikedyn.manoeuvres.registry import available

    out = []
    for kind in available():
        k = kind.to_dict()
        loop = "closed loop: the driver follows a path at a target speed" if k["closed_loop"] else \
            "open-loop steer; the driver holds the speed"
        out.append(f"### `{k['name']}`\n\n{k['title']} ({loop}). {cell(k['summary'])}\n")
        if k["options"]:
            out += ["| option (`-o KEY=VALUE`) | default | unit | what it is |", "| --- | --- | --- | --- |"]
            for o in k["options"]:
                choices = f" (one of {', '.join(map(str, o['choices']))})" if o.get("choices") else ""
                default = f"`{o['default']}`" if o["default"] != "" else "–"
                out.append(f"| `{o['name']}` | {default} | {o['unit'] or '–'} | {cell(o['help'] + choices)} |")
            out.append("")
    return "\n".join(out)


def cli() -> str:
    """The ``--help`` of every command, walked from the Typer app (a group first, then its commands).

    Duck-typed on the command objects (``list_commands``, ``context_class``): recent Typer releases carry
    their own copy of click, whose classes are not ``click``'s.
    """
    import typer

    from trikedyn.cli import app

    out = []

    def walk(command, path, parent, level):
        ctx = command.context_class(command, info_name=path[-1], parent=parent, terminal_width=88,
                                    max_content_width=88)
        anchor = "-".join(path[1:]) or "trikedyn"
        title = " ".join(path)
        out.append(f"{'#' * level} `{title}` {{#{anchor}}}\n\n```text\n{command.get_help(ctx).rstrip()}\n```\n")
        if hasattr(command, "list_commands"):
            for name in command.list_commands(ctx):
                sub = command.get_command(ctx, name)
                if sub is not None and not sub.hidden:
                    walk(sub, [*path, name], ctx, 2 if len(path) == 1 else 3)

    walk(typer.main.get_command(app), ["trikedyn"], None, 2)
    return "\n".join(out)


def flat_api() -> dict[str, list[tuple[str, str]]]:
    """The flat API (``trikedyn._LAZY``) by defining module: ``{module: [(flat name, name there), ...]}``."""
    import importlib

    import trikedyn

    groups = defaultdict(list)
    for name, (module, attribute) in trikedyn._LAZY.items():
        obj = getattr(importlib.import_module(f"trikedyn.{module}"), attribute)
        home = getattr(obj, "__module__", None) or f"trikedyn.{module}"
        groups[home].append((name, getattr(obj, "__qualname__", attribute)))
    return dict(groups)


def api_flat() -> str:
    """One mkdocstrings entry per name of ``import trikedyn as td``, grouped by the module that defines it."""
    flow = ("trikedyn.params", "trikedyn.measure", "trikedyn.mechanics", "trikedyn.model", "trikedyn.manoeuvres",
            "trikedyn.simulate", "trikedyn.analysis", "trikedyn.study")  # the order data flows in

    def place(module):
        return next((i for i, p in enumerate(flow) if module.startswith(p)), len(flow)), module

    out = []
    for module, names in sorted(flat_api().items(), key=lambda item: place(item[0])):
        listed = ", ".join(f"`td.{n}`" for n, _ in names)
        out.append(f"## `{module}`\n\n{listed}\n")
        for name, attribute in names:
            out.append(f"::: {module}.{attribute}\n    options:\n      heading_level: 3\n"
                       f'      heading: "td.{name}"\n      toc_label: "td.{name}"\n')
    return "\n".join(out)


API_MODULES = (
    ("Parameter sets", ("trikedyn.params.parameter_set", "trikedyn.params.io", "trikedyn.params.save",
                        "trikedyn.params.shipped", "trikedyn.params.extends", "trikedyn.params.ops",
                        "trikedyn.params.variant",
                        "trikedyn.params.audit", "trikedyn.params.springs", "trikedyn.params.plausibility", "trikedyn.params.schema")),
    ("Measurements", ("trikedyn.measure.imu_log", "trikedyn.measure.logs", "trikedyn.measure.suspension",
                      "trikedyn.measure.signals", "trikedyn.measure.decay", "trikedyn.measure.weighing", "trikedyn.measure.cg",
                      "trikedyn.mechanics.mass")),
    ("The model", ("trikedyn.model.vehicle", "trikedyn.model.statics", "trikedyn.model.linear")),
    ("Manoeuvres", ("trikedyn.manoeuvres.registry", "trikedyn.manoeuvres.spec", "trikedyn.manoeuvres.base",
                    "trikedyn.manoeuvres.csv_path")),
    ("Simulation", ("trikedyn.simulate.run", "trikedyn.simulate.closed_loop", "trikedyn.simulate.result",
                    "trikedyn.simulate.channels", "trikedyn.simulate.exponential", "trikedyn.simulate.runfile")),
    ("Judging", ("trikedyn.analysis.window", "trikedyn.analysis.metrics", "trikedyn.analysis.verdict",
                 "trikedyn.analysis.threshold", "trikedyn.analysis.search_settings", "trikedyn.analysis.criteria",
                 "trikedyn.analysis.search",
                 "trikedyn.analysis.margins",
                 "trikedyn.analysis.compare",
                 "trikedyn.analysis.alignment", "trikedyn.analysis.scoring", "trikedyn.analysis.tilt",
                 "trikedyn.analysis.handling_tests", "trikedyn.analysis.steady_state", "trikedyn.analysis.steer_shape",
                 "trikedyn.analysis.performance", "trikedyn.analysis.performance_results",
                 "trikedyn.analysis.straight_line", "trikedyn.analysis.wheel_balance",
                 "trikedyn.analysis.straight_balance")),
    ("Studies", ("trikedyn.study.spec", "trikedyn.study.scenarios", "trikedyn.study.designs.runner",
                 "trikedyn.study.engine.executors", "trikedyn.study.engine.dask", "trikedyn.study.engine.loop",
                 "trikedyn.study.engine.pool", "trikedyn.study.engine.store", "trikedyn.study.engine.database",
                 "trikedyn.study.engine.table",
                 "trikedyn.study.metrics",
                 "trikedyn.study.optimise_spec", "trikedyn.study.designs.figures",
                 "trikedyn.study.designs.sensitivity", "trikedyn.study.designs.uncertainty",
                 "trikedyn.study.designs.loading", "trikedyn.study.designs.optimise",
                 "trikedyn.study.designs.search", "trikedyn.study.designs.sensitivity_methods",
                 "trikedyn.study.designs.uncertain_inputs", "trikedyn.study.designs.loading_grid")),
    ("The reference paper", ("trikedyn.paper", "trikedyn.paper.data", "trikedyn.paper.reproduce",
                             "trikedyn.paper.report", "trikedyn.paper.html",
                             "trikedyn.paper.cells")),
    ("Tyres", ("trikedyn.tyre.magic_formula", "trikedyn.tyre.tir", "trikedyn.tyre.tir_properties", "trikedyn.tyre.pac2002",
               "trikedyn.tyre.pac2002_pack", "trikedyn.tyre.pac2002_arrays", "trikedyn.tyre.models")),
    ("Registries and plug-ins", ("trikedyn.registry", "trikedyn.options")),
    ("Errors and units", ("trikedyn.errors", "trikedyn.units")),
)
"""The main modules of the API reference, by theme (each object of the flat API is documented once, there)."""


def api_modules() -> str:
    """A mkdocstrings entry per main module; names of the flat API are left to its page."""
    flat = flat_api()
    out = []
    for title, modules in API_MODULES:
        out.append(f"## {title}\n")
        for module in modules:
            skip = "".join(f', "!^{re.escape(attr)}$"' for _, attr in flat.get(module, ()))
            out.append(f"::: {module}\n    options:\n      heading_level: 3\n      show_root_full_path: true\n"
                       f'      filters: ["!^_"{skip}]\n')
    return "\n".join(out)


def tyre_in_the_model() -> str:
    """How the vehicle model takes tyre data: the ``[tyre]`` section, and per wheel a ``.tir`` file where the
    schema has a ``tyre_file`` key."""
    from trikedyn.params.schema import WheelSpec

    text = ("The vehicle model's tyres are set by the vehicle file's `[tyre]` section: a Magic Formula with "
            "load dependence, similarity combined slip and relaxation lengths (see "
            "[the vehicle file](vehicle-file.md#tyre) and `trikedyn.tyre.magic_formula`).")
    field = WheelSpec.model_fields.get("tyre_file")
    if field is not None:
        text += (f" A wheel's `tyre_file` key names a `.tir` file instead: {field.description}. It is read "
                 "when the vehicle file is loaded, and a missing or invalid file fails the load.")
    return text + "\n"


GENERATORS = {
    "tyre-in-the-model": tyre_in_the_model,
    "vehicle-file": vehicle_file,
    "weighing-file": weighing_file,
    "study-spec": study_spec,
    "search-settings": search_settings,
    "presets": presets,
    "log-formats": log_formats,
    "channels": channels,
    "manoeuvres": manoeuvres,
    "cli": cli,
    "api-flat": api_flat,
    "api-modules": api_modules,
}


def expand(markdown: str, where: str = "page") -> str:
    """The page with every ``<!-- generated: NAME -->`` marker replaced by what NAME generates."""

    def replace(match):
        name = match.group(1)
        if name not in GENERATORS:
            raise ValueError(f"{where}: unknown generated part '{name}' (known: {', '.join(GENERATORS)})")
        return "\n" + GENERATORS[name]().strip("\n") + "\n\n"

    return MARKER.sub(replace, markdown)


# ------------------------------------------------------------------------------------------------------------
# MkDocs events
# ------------------------------------------------------------------------------------------------------------
def on_page_markdown(markdown, page, config, files):
    from mkdocs.exceptions import PluginError

    try:
        return expand(markdown, page.file.src_uri)
    except ValueError as exc:
        raise PluginError(str(exc)) from None


ROLE = re.compile(r":(?:py:)?(?:func|class|mod|meth|attr|data|exc|obj|const):<code>(~?)([\w.]+)</code>")


def on_page_content(html, page, config, files):
    """``:func:`name``` left in docstrings -> an optional cross-reference (a link if ``name`` is documented)."""

    def link(match):
        short, identifier = match.groups()
        shown = identifier.rsplit(".", 1)[-1] if short else identifier
        return f'<autoref optional identifier="{identifier}"><code>{shown}</code></autoref>'

    return ROLE.sub(link, html)
