"""``trikedyn assess``: the stability dossier of a trike, judged against requirements.

The dossier's folder (``--out``) gets ``report.html`` (with its figures), ``assess.json`` and, as each piece
is done, ``assess-parts/``: ``--resume`` continues a dossier that was interrupted without computing the
pieces it has again."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ._common import ForceOpt, FreightAliasOpt, JsonOpt, PayloadOpt, VehicleArg, emit, on_interrupt, payload_kg


def _metrics_help() -> str:
    from ..assess.requirements import METRICS, preset_names

    return (f"Requirements to judge: a TOML file ([[requirement]] id, metric, at_least / at_most: a number or a "
            f"metric, laden, tolerance, note; see the documentation page assess.md) or a preset ({', '.join(preset_names())}). "
            f"Metrics: {', '.join(METRICS.names())}. Exit code 1 when an item fails.")


def assess_cmd(
    vehicle: VehicleArg,
    requirements: Annotated[str | None, typer.Option("--requirements", help=_metrics_help())] = None,
    payload: PayloadOpt = 0.0,
    freight: FreightAliasOpt = None,
    out: Annotated[Path | None, typer.Option("--out", help="Folder of the dossier (default: assess-NAME).")] = None,
    quick: Annotated[bool, typer.Option("--quick", help="Leave out the loading chart, the sensitivity, the "
                                        "animation and the speed limits beyond 0 kg and --payload (about a "
                                        "minute instead of several).")] = False,
    resume: Annotated[bool, typer.Option("--resume", help="Continue an interrupted dossier in --out: the pieces "
                                         "it holds are not computed again.")] = False,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """The stability dossier: vehicle sheet, static stability, handling, thresholds, guidelines and
    requirements in one HTML report (report.html) and its JSON (assess.json). Progress on stderr."""
    payload = payload_kg(payload, freight)
    from ..assess.dossier import FILES, assess
    from ..assess.report import write_dossier
    from ..assess.requirements import load_requirements, preset_names
    from ..params import load_vehicle
    from ._sampled import check_resume, start_output

    check_resume(out, resume, force)
    wanted = None if requirements is None else load_requirements(requirements)
    pset = load_vehicle(vehicle)
    folder = Path(out) if out is not None else Path(f"assess-{pset.name}")
    reads = [vehicle] + ([requirements] if requirements is not None and requirements not in preset_names() else [])
    start_output(folder, {"vehicle": pset.name, "payload_kg": float(payload), "quick": bool(quick)},
                 FILES["plan"], kind="an assess", resume=resume, force=force, reads=reads,
                 writes=[FILES["json"], FILES["report"]])
    on_interrupt(f"the pieces done are kept in {folder}: the same command with --resume continues")

    def say(text: str) -> None:
        """Print the progress line ``assess: text`` to stderr."""
        typer.echo(f"assess: {text}", err=True)

    data = assess(pset, payload_kg=payload, out=folder, quick=quick, resume=resume, requirements=wanted, say=say)
    import json

    from .._files import atomic_write
    from ._common import finite, json_default

    files = {"json": str(folder / FILES["json"]), "report": str(folder / FILES["report"])}
    data["files"] = files
    text = json.dumps(finite(data)[0], indent=1, default=json_default, allow_nan=False)
    atomic_write(folder / FILES["json"], lambda fh: fh.write(text), binary=False)
    write_dossier(folder, data)
    say(f"wrote {files['report']}")
    shown = {k: data[k] for k in ("payload_kg", "quick", "speed_limits", "guidelines", "requirements", "files")}
    shown = {"vehicle": pset.name, **shown,
             "metrics": {k: s["metrics"] for k, s in data["states"].items()}}
    emit(shown, as_json, lambda: _text(data))
    if data["requirements"] is not None and not data["requirements"]["passed"]:
        raise typer.Exit(1)


def _text(data: dict) -> str:
    from ._common import readable

    lines = [f"{data['vehicle']['name']}: stability dossier" + (" (quick)" if data["quick"] else "")]
    r = data["requirements"]
    if r is not None:
        failed = r["failed"]
        lines.append(f"requirements {r['name']}: " + ("PASS" if not failed else f"FAIL ({', '.join(failed)})"))
        for j in r["judgements"]:
            unit = "" if j["unit"] == "1" else f" {j['unit']}"  # a dimensionless metric
            value = "not found" if j["value"] is None else f"{readable(j['value'])}{unit}"
            margin = "" if j["margin"] is None else f", margin {j['margin']:+.3g}{unit}"
            lines.append(f"  {j['verdict']}  {j['id']}: {j['metric']} {value} {j['bound']}{margin} ({j['detail']})")
    for key, s in data["states"].items():
        if key == "laden" and data["payload_kg"] <= 0:
            continue
        m = s["metrics"]
        lines.append(f"{key.replace('_', ' ')} ({s['payload_kg']:g} kg):")
        for name in ("tilt_angle_deg", "rigid_tilt_angle_deg", "understeer_gradient_deg_per_g", "top_speed_kmh",
                     "dlc_threshold_kmh", "slc_threshold_kmh", "fishhook_threshold_kmh"):
            lines.append(f"  {name:<32}{'not found' if m[name] is None else readable(m[name])}")
    lines.append("speed limits:")
    lines += [f"  {t}" for t in data["guidelines"]["speed"]]
    lines.append(f"wrote {data['files']['report']}, {data['files']['json']}")
    return "\n".join(lines)
