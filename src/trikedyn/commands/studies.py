"""``trikedyn study`` and ``trikedyn reproduce``: parametric studies and the paper's whole workflow."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from ._common import (
    DaskLocalOpt,
    JsonOpt,
    SchedulerOpt,
    WorkersOpt,
    emit,
    within,
)


def study_cmd(
    spec: Annotated[str, typer.Argument(help="Study spec (TOML file), or 'paper' for the built-in Fig. 10 study.")],
    workers: WorkersOpt = None,
    dask_local: DaskLocalOpt = None,
    scheduler: SchedulerOpt = None,
    out: Annotated[Path, typer.Option("--out", help="Output folder (its store makes a re-run resume).")] = Path("study-output"),
    dry_run: Annotated[bool, typer.Option("--dry-run", help="Check the spec and count its scenarios; run nothing.")] = False,
    max_scenarios: Annotated[int, typer.Option("--max-scenarios", callback=within(1, 1e9), help="Refuse a spec with more scenarios than this.")] = 10_000,
    force: Annotated[bool, typer.Option("--force", help="Write into an existing --out folder that holds other files but no study (its results.csv, results.parquet and fig_*.png are replaced). A study's folder needs none: the run resumes it.")] = False,
    as_json: JsonOpt = False,
):
    """Parametric study: vehicle variations x manoeuvres x metrics (threshold by default); parallel, resumable, CSV, Parquet and figures."""
    if dry_run:
        from ..study import count_scenarios, load_spec
        from ..study.metrics import label

        loaded = load_spec(spec)
        count, exact = count_scenarios(loaded)
        if count > max_scenarios:
            raise InputError(f"the spec expands to {'up to ' if not exact else ''}{count:,} scenarios, more than the "
                             f"limit {max_scenarios:,}; pass --max-scenarios {count} to run it", where=str(spec))
        metrics = [label(name, options) for name, options in loaded.metrics]
        data = {"study": loaded.name, "vehicle": loaded.vehicle, "manoeuvres": list(loaded.manoeuvres),
                "metrics": metrics, "scenarios": count, "exact": exact, "groups": [g.name for g in loaded.groups]}
        emit(data, as_json, lambda: (f"study '{loaded.name}': {count} scenarios on {loaded.vehicle} "
                                      f"({', '.join(loaded.manoeuvres)}; {', '.join(metrics)}); nothing run"))
        return
    run_study_cmd(spec, out, workers=workers, dask_local=dask_local, scheduler=scheduler, max_scenarios=max_scenarios,
                  as_json=as_json, force=force)


def study_summary_text(s: dict) -> str:
    """The text summary of a study run (:attr:`trikedyn.study.designs.runner.StudyRun.summary`).

    Parameters
    ----------
    s : dict
        The summary.

    Returns
    -------
    str
        The text.
    """
    n = s["scenarios"]
    lines = [
        f"study '{s['study']}': {n['done']} of {n['total']} scenarios stored ({n['failed']} failed); "
        f"{n['computed']} computed in this run, {n['skipped']} already stored",
        f"wall time {s['wall_time_s']:.1f} s"
        + (f"; {s['executor']}" if s["executor"].startswith("no executor") else f" on {s['executor']}"),
    ]
    if "threshold" in (s.get("metrics") or ["threshold"]) and s.get("criterion"):
        lines.insert(1, f"threshold: the {s['criterion']} criterion, {s['speed_control']} speed control")
    if s["table"]:
        lines.append(f"table: {s['table']} (and {Path(s['parquet']).name})")
    if s.get("figures"):
        lines.append(f"figures: {', '.join(Path(p).name for p in s['figures'])}")
    return "\n".join(lines)


def _said_interrupted(exc, as_json: bool = False) -> None:
    """Say a :class:`~trikedyn.study.designs.runner.StudyInterrupted` in one line on stderr (``interrupted by SIGTERM``
    after a SIGTERM), with ``as_json`` also as a JSON object on stdout, and exit with 128 + the signal's number
    (130, 143).

    The study's own signal handler took the signal, not the command line's, so the study says it here."""
    import signal

    name = getattr(exc, "signal", None) or "SIGINT"
    said = str(exc) if name == "SIGINT" else str(exc).replace("interrupted", f"interrupted by {name}", 1)
    typer.echo(f"trikedyn: {said}", err=True)
    if as_json:
        typer.echo(json.dumps({"error": said, "where": name, "interrupted": True}))
    raise SystemExit(128 + int(signal.Signals[name])) from None


def run_study_cmd(spec, out, *, workers=None, dask_local=None, scheduler=None, max_scenarios=10_000,
                  as_json=False, force=False) -> dict:
    """Run or resume a study, print its summary (text or JSON) and progress (a bar on a terminal, a line every
    few seconds otherwise); SIGINT -> exit 130, SIGTERM -> 143, lost workers or scheduler -> exit 1 (each with
    one line on stderr).

    Parameters
    ----------
    spec : str
        The study spec (a TOML file, or ``paper``).
    out : Path
        The output folder.
    workers : int, optional
        Processes on this machine.
    dask_local : int, optional
        Workers of a local Dask cluster.
    scheduler : str, optional
        Dask scheduler address.
    max_scenarios : int
        Largest number of scenarios accepted.
    as_json : bool
        Print the summary as JSON.
    force : bool
        Write into a folder that holds other files.

    Returns
    -------
    dict
        The run's summary.
    """
    from ..study.engine.executors import check_executor, start_pool_server

    check_executor(workers, dask_local, scheduler)
    start_pool_server(workers, dask_local, scheduler)  # first: its imports overlap this process's of the study
    from ..study.designs.runner import StudyIncomplete, StudyInterrupted, execute_study
    from ._common import on_interrupt

    on_interrupt(f"the scenarios finished are stored in {out}: the same command resumes")
    run = execute_study(spec, out, workers=workers, dask_local=dask_local, scheduler=scheduler, progress=True,
                        max_scenarios=max_scenarios, force=force)
    if as_json:
        typer.echo(json.dumps(run.summary, indent=2))
    else:
        typer.echo(study_summary_text(run.summary))
    try:
        run.raise_unfinished()
    except StudyInterrupted as exc:
        _said_interrupted(exc)
    except StudyIncomplete as exc:
        typer.echo(f"trikedyn: {exc}", err=True)
        raise SystemExit(1) from None
    return run.summary


def reproduce_cmd(
    out: Annotated[Path, typer.Option("--out", help="Output folder (created; a non-empty one needs --force).")] = Path(
        "trikedyn-output"
    ),
    no_figures: Annotated[bool, typer.Option("--no-figures", help="Skip the PNG figures, the animations and the report.")] = False,
    no_study: Annotated[bool, typer.Option("--no-study", help="Skip the parametric study (Fig. 10).")] = False,
    workers: Annotated[int | None, typer.Option("--workers", help="Processes for the study (default 2).")] = 2,
    force: Annotated[bool, typer.Option("--force", help="Write into a folder that holds files (they are replaced).")] = False,
    as_json: JsonOpt = False,
):
    """The reference paper's workflow on the built-in reference vehicle: tables, figures, verdicts, report.html."""
    from .._files import check_output_folder
    from ..paper.reproduce import reproduce
    from ..study.designs.runner import StudyInterrupted

    if workers is not None and not 1 <= workers <= 256:
        raise InputError(f"expected 1 to 256 processes, got {workers}", where="--workers")
    check_output_folder(out, force=force)
    try:
        summary = reproduce(out, figures=not no_figures, study=not no_study, workers=workers)
    except StudyInterrupted as exc:  # its study's handler took the signal: said here, not lost to a bare 130
        _said_interrupted(exc, as_json)
    text = "\n".join(
        [f"wrote {len(summary['files'])} files to {out}"]
        + [f"- {s['verdict'].upper()}: {s['paper']}" for s in summary["statements"]]
        + [f"see {out / 'summary.md'}"]
    )
    emit({k: summary[k] for k in ("out_dir", "statements", "files")}, as_json, text)
