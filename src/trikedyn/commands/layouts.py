"""``trikedyn compare-layouts``: a vehicle and its mirror layout (delta and tadpole) side by side; ``--keep``
chooses what the mirror keeps of the CG's place (:mod:`trikedyn.analysis.layouts`)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ._bounds import SEARCH_DEFAULTS, search_bound
from ._common import (
    CriterionOpt,
    ForceOpt,
    FreightAliasOpt,
    JsonOpt,
    PayloadOpt,
    SpeedControlOpt,
    VehicleArg,
    absolute_csv,
    choice,
    emit,
    finite,
    manoeuvre_options,
    payload_kg,
    save_figure,
)

DEFAULT_MANOEUVRES = ("dlc", "slc")


def compare_layouts_cmd(
    vehicle: VehicleArg,
    manoeuvre: Annotated[
        list[str], typer.Option("--manoeuvre", callback=absolute_csv, help="A manoeuvre for the threshold velocity (see `trikedyn "
                                "manoeuvres`); repeatable. Default: dlc and slc.")
    ] = [],  # noqa: B006
    keep: Annotated[str, typer.Option(
        "--keep", callback=choice("pair-distance", "cg", "both"),
        help="What the mirror keeps of the CG's place. pair-distance (the default): the CG at the same distance "
             "from the two-wheel axle, the body mirrored end for end, so the load split and the rigid tip-over "
             "a T / (2 h L) are the same and what differs is the layout's own (the fair comparison of layouts); "
             "cg: the CG where it is on the vehicle, only the wheels moved, so a CG near one layout's pair is "
             "near the other's single wheel (compares two CG places as much as two layouts); both: the two "
             "mirrors.")] = "pair-distance",
    payload: PayloadOpt = 0.0,
    freight: FreightAliasOpt = None,
    no_tilt: Annotated[bool, typer.Option("--no-tilt", help="Skip the tilt-table test.")] = False,
    low: Annotated[float, typer.Option("--low", callback=search_bound("low_kmh"), help="Lowest speed searched [km/h].")] = SEARCH_DEFAULTS["low_kmh"],
    high: Annotated[float, typer.Option("--high", callback=search_bound("high_kmh"), help="Highest speed searched [km/h].")] = SEARCH_DEFAULTS["high_kmh"],
    resolution: Annotated[float, typer.Option("--resolution", callback=search_bound("resolution_kmh"), help="Threshold resolution [km/h].")] = SEARCH_DEFAULTS["resolution_kmh"],
    criterion: CriterionOpt = SEARCH_DEFAULTS["criterion"],
    speed_control: SpeedControlOpt = SEARCH_DEFAULTS["speed_control"],
    out: Annotated[Path | None, typer.Option("--out", help="Folder to write comparison.json, each mirror vehicle "
                                             "(LAYOUT-mirror-KEEP.toml) and a figure into (created; a non-empty one "
                                             "needs --force).")] = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Delta against tadpole: the vehicle and its mirror layout on the same mass, CG height, wheelbase and track.

    The mirror has the wheel pair at the other end. By default (--keep pair-distance) its CG is at the same
    distance from its two-wheel axle, so the static load split and rigid tip-over are the same and the
    comparison is of the layouts; --keep cg leaves the CG where it is on the vehicle. For each: the CG's
    distance a from the single wheel's axle [m], the weight on the single wheel [%], the static rigid
    tip-over [g], the tilt-table angle [deg] and the threshold velocity [km/h] in each manoeuvre.
    """
    payload = payload_kg(payload, freight)
    from ..analysis.layouts import compare_layouts
    from ..errors import InputError
    from ..params import load_vehicle, with_freight

    manoeuvres = tuple(manoeuvre) or DEFAULT_MANOEUVRES
    for m in manoeuvres:
        manoeuvre_options(m, [])  # an unknown manoeuvre fails here, before any run
    if not low < high:
        raise InputError(f"must be above --low ({low:g} km/h), got {high:g}", where="--high")
    if out is not None:
        from .._files import check_output_folder

        check_output_folder(out, force=force, option="--out", reads=[vehicle, *manoeuvres],
                            writes=["comparison.json", "*-mirror-*.toml", "layouts.png"])
    pset = with_freight(load_vehicle(vehicle), payload)
    result = compare_layouts(pset, manoeuvres, keep=keep, tilt=not no_tilt, low_kmh=low, high_kmh=high,
                             resolution_kmh=resolution, criterion=criterion, speed_control=speed_control)
    data = {"vehicle": pset.name, "payload_kg": payload, "criterion": criterion, "speed_control": speed_control,
            **result.to_dict()}
    if out is not None:
        data["wrote"] = _write(out, result, data)
    text = lambda: result.table() + (f"\nwrote {', '.join(data['wrote'])}" if out is not None else "")  # noqa: E731
    emit(data, as_json, text)


def _write(out: Path, result, data: dict) -> list[str]:
    import json

    import matplotlib

    from .._files import atomic_write
    from ..params import save_vehicle

    table = out / "comparison.json"
    atomic_write(table, lambda fh: fh.write(json.dumps(finite(data)[0], indent=2, allow_nan=False)), binary=False)
    mirrors = []
    for keep, params in result.mirrors.items():
        mirrors.append(out / f"{params.layout}-mirror-{keep}.toml")
        save_vehicle(params, mirrors[-1])
    matplotlib.use("Agg")
    figure = out / "layouts.png"
    save_figure(result.plot(), figure)
    return [str(table), *map(str, mirrors), str(figure)]
