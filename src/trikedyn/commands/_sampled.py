"""What the sampled studies (``sensitivity``, ``uncertainty``, ``loading-chart``, ``optimise``) share: the
executor's check (as ``study``'s), a progress line that works without a terminal, an output folder that a resumed run must match, and the
figure and JSON they end with."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from ..study.engine.executors import (
    check_executor,  # noqa: F401  (--workers, --dask-local, --scheduler: one)
    start_pool_server,  # noqa: F401  (its imports overlap the reference search)
)
from ..study.engine.progress import ProgressLine  # noqa: F401  (the sampled commands' progress line)

MetricOpt = Annotated[str, typer.Option("--metric", help="What each evaluation measures: a registered study metric (threshold, tilt_angle, understeer_gradient, peak_ri, min_wheel_load ...; see the study spec reference). Default: the threshold velocity. Another metric's value is named by it: value, reference_value, median ... in the JSON (with metric and unit), a column named by the metric in the CSV files.")]
MetricOptionOpt = Annotated[list[str], typer.Option("--metric-option", help="An option of the metric, KEY=VALUE (e.g. speed_kmh=40 for peak_ri); repeatable.")]


def metric_options(pairs: list[str]) -> dict:
    """``--metric-option KEY=VALUE`` pairs as a dict (numbers as numbers; checked by the metric).

    Parameters
    ----------
    pairs : list of str
        ``KEY=VALUE`` each.

    Returns
    -------
    dict
        Key -> value (a float when it reads as one, else the text).

    Raises
    ------
    InputError
        A pair without ``=`` or without a key (``where="--metric-option"``).
    """
    options = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key.strip():
            raise InputError(f"expected KEY=VALUE, got {pair!r}", where="--metric-option")
        try:
            options[key.strip()] = float(value)
        except ValueError:
            options[key.strip()] = value.strip()
    return options


MAX_PLAN_BYTES = 1 << 20
"""Largest plan file a resumed run reads [bytes] (a plan is a few KiB)."""


def check_resume(out: Path | None, resume: bool, force: bool) -> None:
    """``--resume`` needs ``--out`` and excludes ``--force`` (checked before any work)."""
    if resume and out is None:
        raise InputError("needs --out (the folder of the run to continue)", where="--resume")
    if resume and force:
        raise InputError("give --resume (continue) or --force (start again), not both", where="--resume")


def start_output(out: Path, plan: dict, plan_file: str, *, kind: str, resume: bool, force: bool,
                 reads=(), writes=()) -> None:
    """Prepare ``out`` for a run described by ``plan`` (written as ``plan_file``).

    With ``resume``, an existing plan must equal ``plan`` (else the folder holds another run); without it, a
    folder holding a ``kind`` run, or any other output, is replaced only with ``force``. In every case, none
    of the names the run writes in ``out`` (``writes``, and ``plan_file``) may be one of the files it reads
    (``reads``: :func:`trikedyn._files.check_not_inputs`), with ``--force`` or ``--resume`` too.
    """
    from .._files import atomic_write, check_not_inputs, check_output_folder, ensure_folder, refuse_symlink

    check_not_inputs(out, [plan_file, *writes], reads)
    plan_path = out / plan_file
    if resume and refuse_symlink(plan_path).exists():
        from .._reading import read_text

        try:
            earlier = json.loads(read_text(plan_path, max_bytes=MAX_PLAN_BYTES, expected="a run's plan (JSON)"))
        except InputError as exc:  # a FIFO, a device, a huge file, not UTF-8
            raise InputError(f"{exc.reason}; not resuming (pass --force to start again)", where=str(plan_path)) from None
        except ValueError:
            earlier = None
        if not isinstance(earlier, dict):
            raise InputError("cannot be read; not resuming (pass --force to start again)", where=str(plan_path))
        if earlier != plan:
            changed = sorted(k for k in plan if earlier.get(k) != plan[k])
            raise InputError(f"was another run (its {', '.join(changed)} differ); not resuming (pass --force "
                             "to start again)", where=str(plan_path))
    elif resume:
        ensure_folder(out)
    else:
        if not force and refuse_symlink(plan_path).exists():
            raise InputError(f"holds {kind} run; pass --resume to continue it or --force to start again",
                             where=str(out))
        check_output_folder(out, force=force)
    atomic_write(plan_path, lambda fh: fh.write(json.dumps(plan, indent=2)), binary=False)
    from ._common import on_interrupt

    on_interrupt(f"what is done is kept in {out}: the same command with --resume continues it")


def write_results(out: Path, data: dict, figure, figure_file: str, json_file: str, *, dpi: int = 110,
                  **more_files: str) -> dict:
    """End a run in ``out``: ``figure`` (a matplotlib figure) as ``figure_file``, then ``data`` with its
    ``files`` (``json``, ``figure`` and ``more_files``, name -> path) as ``json_file``, NaN as null.

    Returns ``data["files"]``."""
    import matplotlib

    from .._files import atomic_write
    from ._common import finite, json_default, save_figure

    matplotlib.use("Agg")
    files = {**more_files, "json": str(out / json_file), "figure": str(out / figure_file)}
    save_figure(figure, out / figure_file, dpi=dpi)
    data["files"] = files
    text = json.dumps(finite(data)[0], indent=2, default=json_default, allow_nan=False)
    atomic_write(out / json_file, lambda fh: fh.write(text), binary=False)
    return files
