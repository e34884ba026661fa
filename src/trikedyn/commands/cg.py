"""``trikedyn cg``: centre of gravity from wheel weighings, and with payload."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from ._common import (
    FreightAliasOpt,
    JsonOpt,
    PayloadOpt,
    VehicleArg,
    emit,
    payload_kg,
)

cg_app = typer.Typer(help="Centre of gravity: from wheel weighings, and with payload.", no_args_is_help=True)


@cg_app.command("weigh")
def cg_weigh(file: Annotated[Path, typer.Argument(help="Weighing record (TOML); see the docs.")], as_json: JsonOpt = False):
    """Mass and CG from wheel weighings: x, y level; z from raised-axle weighings (least squares)."""
    from ..measure.weighing import load_weighing, reduce_weighing

    result = reduce_weighing(load_weighing(file), where=str(file)).to_dict()
    text = (
        f"mass {result['mass_kg']:.2f} ± {result['mass_std_kg']:.2f} kg\n"
        f"cg x {result['cg_x_m'] * 1000:.1f} ± {result['cg_x_std_m'] * 1000:.1f} mm\n"
        f"cg y {result['cg_y_m'] * 1000:.1f} ± {result['cg_y_std_m'] * 1000:.1f} mm"
    )
    if "cg_z_m" in result:
        text += f"\ncg z {result['cg_z_m'] * 1000:.1f} ± {result['cg_z_std_m'] * 1000:.1f} mm"
    emit(result, as_json, text)


def _floats(text: str, n: int, option: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != n:
        raise InputError(f"expected {n} comma-separated numbers, got '{text}'", where=option)
    return values


@cg_app.command("payload")
def cg_payload(
    vehicle: VehicleArg,
    payload: PayloadOpt = 0.0,
    freight: FreightAliasOpt = None,
    point: Annotated[list[str], typer.Option(help="Point mass 'KG,X,Y,Z' [kg, m]; repeatable.")] = [],  # noqa: B006
    box: Annotated[list[str], typer.Option(help="Box 'KG,X,Y,Z,LX,LY,LZ' [kg, m]; repeatable.")] = [],  # noqa: B006
    remove: Annotated[bool, typer.Option(help="Take the payload off instead of adding it.")] = False,
    as_json: JsonOpt = False,
):
    """Mass, CG and inertia of a vehicle with a payload added (or removed)."""
    payload = payload_kg(payload, freight)
    from ..measure.cg import Box, Payload, PointMass
    from ..params import freight as paper_freight
    from ..params import load_vehicle, mass_properties, with_payload

    pset = load_vehicle(vehicle)
    items = list(paper_freight(pset.params, payload).items) if payload else []
    for i, spec in enumerate(point):
        m, x, y, z = _floats(spec, 4, f"--point #{i + 1}")
        items.append(PointMass(m, (x, y, z), name=f"--point #{i + 1}"))
    for i, spec in enumerate(box):
        m, x, y, z, lx, ly, lz = _floats(spec, 7, f"--box #{i + 1}")
        items.append(Box(m, (x, y, z), (lx, ly, lz), name=f"--box #{i + 1}"))
    mp = mass_properties(with_payload(pset, Payload("cli", tuple(items)), remove=remove).params)
    base = pset.params.mass.total_kg
    data = {"total_kg": mp.mass_kg, "payload_kg": mp.mass_kg - base, "cg_m": mp.cg_m, "inertia_kgm2": mp.inertia_kgm2}
    i = mp.inertia_kgm2
    text = (
        f"total {mp.mass_kg:.2f} kg (payload {mp.mass_kg - base:+.2f} kg)\n"
        f"cg ({mp.cg_m[0] * 1000:.1f}, {mp.cg_m[1] * 1000:.1f}, {mp.cg_m[2] * 1000:.1f}) mm\n"
        f"Ixx {i[0, 0]:.1f}  Iyy {i[1, 1]:.1f}  Izz {i[2, 2]:.1f} kg m^2"
    )
    emit(data, as_json, text)


@cg_app.command("freight-table")
def cg_freight_table(
    vehicle: Annotated[str, typer.Argument(help="Preset name or .toml file.")] = "reference-etrike",
    masses: Annotated[str, typer.Option(help="Freight masses [kg], comma-separated.")] = "0,50,100,150,200",
    as_json: JsonOpt = False,
):
    """CG against freight mass, like the paper's Table 3."""
    from ..params import load_vehicle, mass_properties, with_freight

    pset = load_vehicle(vehicle)
    rows = []
    for text in masses.split(","):
        m = _floats(text, 1, "--masses")[0]
        cg = mass_properties(with_freight(pset, m).params).cg_m
        rows.append({"freight_kg": m, "cg_x_m": cg[0], "cg_y_m": cg[1], "cg_z_m": cg[2]})
    text = "freight_kg   x_mm    y_mm    z_mm\n" + "\n".join(
        f"{r['freight_kg']:>10.1f} {r['cg_x_m'] * 1e3:7.1f} {r['cg_y_m'] * 1e3:7.1f} {r['cg_z_m'] * 1e3:7.1f}" for r in rows
    )
    emit(rows, as_json, text)
