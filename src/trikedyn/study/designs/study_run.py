"""What a grid study's run (:mod:`trikedyn.study.designs.runner`) gives and how it ends: :class:`StudyRun`,
and :class:`StudyInterrupted` (a signal: what finished is stored) or :class:`StudyIncomplete` (scenarios lost
to dead workers or a lost scheduler); and the checks made before anything is written: the spec's size
(counted without expanding it) and the study's folder (:func:`check_study_folder`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ...errors import InputError, RunIncomplete
from ..scenarios import count_scenarios
from ..spec import StudySpec

__all__ = ["STUDY_FILES", "StudyIncomplete", "StudyInterrupted", "StudyRun", "check_study_folder"]


class StudyInterrupted(KeyboardInterrupt):
    """A study run stopped by SIGINT/SIGTERM; what finished is stored and a re-run resumes.

    Attributes
    ----------
    summary : dict
        As :attr:`StudyRun.summary` (``out``, ``scenarios`` counts, ``wall_time_s``, ...).
    signal : str or None
        The signal that stopped it (``"SIGINT"``, ``"SIGTERM"``).
    """

    def __init__(self, message: str, summary: dict, signal: str | None = None):
        super().__init__(message)
        self.summary = summary
        self.signal = signal


class StudyIncomplete(RunIncomplete):
    """Some scenarios were lost to dead workers or a lost scheduler (not to their own errors); a re-run retries
    them (the study's :class:`~trikedyn.errors.RunIncomplete`, with its summary)."""

    def __init__(self, message: str, summary: dict):
        super().__init__(message)
        self.summary = summary


@dataclass
class StudyRun:
    """What a run of a study gives (:func:`execute_study`).

    Attributes
    ----------
    summary : dict
        ``study``, ``out``, ``database``, ``executor``, ``outcome`` (``completed``, ``interrupted``,
        ``incomplete``), ``scenarios`` {``total``, ``done``, ``failed``, ``computed``, ``skipped``, ``lost``},
        ``wall_time_s`` [s], ``table`` and ``parquet`` (paths once every scenario is stored, else None),
        ``figures`` (PNG paths), ``run_token``.
    table : pandas.DataFrame
        The stored scenarios in spec order (see :meth:`StudyStore.to_pandas`).
    lost : list of (scenario_id, why)
        Scenarios lost to dead workers in this run.
    signal : str or None
        The signal that interrupted the run (``"SIGINT"``, ``"SIGTERM"``), or None.
    """

    summary: dict
    table: object = None
    lost: list = field(default_factory=list)
    signal: str | None = None

    def raise_unfinished(self) -> None:
        """Raise :class:`StudyInterrupted` or :class:`StudyIncomplete` if the run did not complete."""
        s = self.summary
        n = s["scenarios"]
        if s["outcome"] == "interrupted":
            raise StudyInterrupted(
                f"interrupted: {n['done']} of {n['total']} scenarios stored in {s['database']}; run the same "
                f"command again to resume (stored scenarios are not recomputed)", s, self.signal)
        if s["outcome"] == "incomplete":
            first = self.lost[0][1] if self.lost else "unknown"
            raise StudyIncomplete(
                f"{n['lost']} scenario(s) not finished ({first}); {n['done']} of {n['total']} stored in "
                f"{s['database']}; run the same command again to resume (stored scenarios are not recomputed)", s)


def _check_limit(max_scenarios) -> None:
    if max_scenarios is None:
        return
    if isinstance(max_scenarios, bool) or not isinstance(max_scenarios, int | float) or max_scenarios < 1 \
            or int(max_scenarios) != max_scenarios:
        raise InputError(f"expected a whole number of scenarios >= 1, got {max_scenarios!r}", where="max_scenarios")


def _check_size(spec: StudySpec, max_scenarios) -> None:
    """Refuse a spec with more than ``max_scenarios`` scenarios, counted without expanding it."""
    if max_scenarios is None:
        return
    n, exact = count_scenarios(spec)
    if n > max_scenarios:
        size = f"{n:,} scenarios" if exact else f"up to {n:,} scenarios"
        raise InputError(f"the spec expands to {size}, more than the limit {int(max_scenarios):,}; "
                         f"pass --max-scenarios {n} to run it", where=spec.origin)


STUDY_FILES = ("study.sqlite", "study.sqlite-wal", "study.sqlite-shm", "study.sqlite-journal", "study.lock",
               "results.csv", "results.parquet", "fig_*.png")
"""What a study writes in its folder (``fig_*.png``: a pattern); none may be a file the study reads."""


def check_study_folder(out_dir: str | Path, spec: StudySpec, force: bool = False) -> None:
    """``out_dir`` checked as a study's folder before anything is written in it.

    A missing or empty folder, or a study's (one with its ``study.sqlite``: a re-run resumes it), is fine.
    An existing folder that holds other files is not a study: its ``results.csv``, ``results.parquet`` and
    ``fig_*.png`` would be replaced, so it is refused unless ``force``. Whatever ``force``, no file the study
    writes there may be one it reads (the spec, its vehicle with the files that one reads, a path CSV, a
    ``tyre_file`` override: :func:`trikedyn._files.check_not_inputs`).

    Parameters
    ----------
    out_dir : str or Path
        The folder.
    spec : StudySpec
        The study.
    force : bool
        Accept a folder holding other files.

    Raises
    ------
    InputError
        Naming the folder, or the output file that is an input.
    """
    from ..._files import check_not_inputs

    folder = Path(out_dir)
    tyres = [value for group in spec.groups for key, values in group.overrides if key.endswith(".tyre_file")
             for value in values if isinstance(value, str)]
    check_not_inputs(folder, STUDY_FILES, [spec.origin, spec.vehicle_source, *spec.manoeuvres, *tyres])
    if force or not folder.is_dir() or (folder / "study.sqlite").exists():
        return
    try:
        others = sorted(p.name for p in folder.iterdir() if p.name not in STUDY_FILES)
    except OSError:  # not readable: the store says why
        return
    if others:
        shown = ", ".join(others[:3]) + (f" and {len(others) - 3} more" if len(others) > 3 else "")
        raise InputError(f"holds files ({shown}) but no study (no study.sqlite): its results.csv, results.parquet "
                         "and fig_*.png would be replaced; use another --out, or pass --force to write into it",
                         where=str(folder))
