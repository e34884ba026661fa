"""``trikedyn vehicle``: list, show, check and export parameter sets."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ._common import (
    ForceOpt,
    JsonOpt,
    VehicleArg,
    emit,
)

vehicle_app = typer.Typer(help="Vehicle parameter sets: list, show, check, export.", no_args_is_help=True)


@vehicle_app.command("list")
def vehicle_list(as_json: JsonOpt = False):
    """List the parameter sets shipped with trikedyn."""
    from ..params import list_presets, load_vehicle

    rows = [{"name": n, "description": load_vehicle(n).params.description} for n in list_presets()]
    emit(rows, as_json, "\n".join(f"{r['name']:<24} {r['description']}" for r in rows))


@vehicle_app.command("show")
def vehicle_show(vehicle: VehicleArg, as_json: JsonOpt = False):
    """Show every value of a parameter set, marking assumed values (*) and their reasons."""
    from ..params import load_vehicle

    pset = load_vehicle(vehicle)
    data = pset.params.model_dump(mode="json", exclude_none=True)
    if as_json:
        emit({"origin": pset.origin, "parameters": data, "notes": pset.notes}, True)
        return
    lines = [f"{pset.name}: {pset.params.description}", f"source: {pset.params.source}", ""]
    for path, value in _flatten(data):
        note = pset.notes.get(path, {})
        mark = "*" if "assumed" in note else " "
        lines.append(f"{mark} {path:<48} {value}")
    assumed = pset.assumed()
    lines += ["", f"* assumed ({len(assumed)} values):"]
    lines += [f"  {k}: {v}" for k, v in assumed.items()]
    emit(None, False, "\n".join(lines))


def _flatten(node, prefix=""):
    if isinstance(node, dict):
        for key, value in node.items():
            yield from _flatten(value, f"{prefix}.{key}" if prefix else key)
    elif isinstance(node, list) and node and all(isinstance(i, dict) for i in node):
        for i, item in enumerate(node):
            label = item.get("name", str(i))
            yield from _flatten({k: v for k, v in item.items() if k != "name"}, f"{prefix}.{label}")
    else:
        yield prefix, node


@vehicle_app.command("check")
def vehicle_check(vehicle: VehicleArg, as_json: JsonOpt = False):
    """Audit a parameter set for consistency (Eqs. 3-4, CG against loads, support triangle, ...).

    Exit code 0 when no finding is INCONSISTENT, 1 when one is (the findings are printed either way, as
    JSON with --json); 2 for a file that cannot be read or is invalid.
    """
    from ..params import audit, load_vehicle

    pset = load_vehicle(vehicle)
    findings = audit(pset)
    bad = sum(f.level == "inconsistent" for f in findings)
    if as_json:
        emit({"vehicle": pset.name, "findings": [f.to_dict() for f in findings]}, True)
    else:
        width = max((len(f.level) for f in findings), default=0)
        lines = [f"{pset.name} ({pset.origin})"]
        lines += [f"{f.level.upper():<{width}}  {f.topic}: {f.message}" for f in findings]
        lines.append(f"{len(findings)} findings, {bad} inconsistent")
        emit(None, False, "\n".join(lines))
    if bad:
        raise typer.Exit(1)


@vehicle_app.command("export")
def vehicle_export(
    vehicle: VehicleArg, file: Annotated[Path, typer.Argument(help="TOML file to write.")], force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Write a parameter set to a TOML file (with its notes) to start your own vehicle from."""
    from .._files import check_output
    from ..params import load_vehicle, save_vehicle

    check_output(file, force=force, reads=[vehicle])
    save_vehicle(load_vehicle(vehicle), file)
    emit({"wrote": str(file)}, as_json, f"wrote {file}")
