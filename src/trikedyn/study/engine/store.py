"""The result store of a study: one embedded SQLite database per output folder (``study.sqlite``).

Guarantees
----------
- **One row per finished scenario**, keyed by ``scenario_id`` (primary key). A row is written in its own
  transaction, at once, as soon as the scenario finishes; it is either fully present or absent. A second
  write of the same id is ignored, never duplicated or overwritten.
- **Crash safety**: the database runs in WAL mode with ``synchronous=FULL``. A kill of the writing process
  at any moment (SIGINT, SIGKILL; a power cut too, as far as the disk honours fsync) leaves the last
  committed state; an interrupted transaction is rolled back when the database is next opened.
- **Single writer**: only the main process of a run writes (the workers return rows to it). A run holds an
  exclusive lock on ``study.lock`` (``fcntl.flock``, released by the OS even on SIGKILL), so two runs cannot
  write into the same folder at once.
- **No run stays "running"**: a run that dies without recording how it ended (SIGKILL, a crash, a power cut)
  is marked ``killed`` by the next run to take the lock: holding the lock proves that no earlier run's
  process is still alive. Its ``ended_at`` is then the time it was found so, not the time it died.
- **Resumable**: a re-run asks :meth:`StudyStore.done_ids` and computes only what is missing.
- **Reproducible exports**: :meth:`StudyStore.export` writes ``results.csv`` and ``results.parquet`` sorted in
  the spec's scenario order and with the deterministic columns only (no wall times, pids or timestamps), so
  two runs of a spec, in any order, on any executor, give byte-identical files. Files are written to a
  temporary name and renamed (:func:`trikedyn.study.files.atomic_write`), so a kill never leaves a
  half-written export (a kill between the two files can leave a new CSV beside the previous Parquet file;
  the next run, which finds every scenario stored, writes both again).
- **No planted links**: the store, its ``-wal``/``-shm``/``-journal`` files, the lock and the exports are
  never written through a symbolic link (:class:`~trikedyn.errors.InputError` naming the file). An output
  folder that cannot be created or written is an ``InputError`` naming it, not a traceback.

Tables
------
``results``: ``scenario_id`` (text, primary key), ``scenario`` (JSON: the scenario's fields), ``status``
(``"ok"`` or ``"error"``), ``result`` (JSON: :meth:`ThresholdResult.to_dict`, null on error), ``error``
(one line, null when ok), ``traceback``, ``wall_time_s`` [s], ``worker`` (host:pid), ``run_token`` (the run
that computed it) and ``finished_at`` [s since the epoch].
A study with a metric other than the threshold (:mod:`trikedyn.study.metrics`) exports three more columns
after the overrides: ``metric`` (its label, e.g. ``peak_ri(speed_kmh=40)``), then after ``status``,
``value`` and ``unit``; the threshold's own columns stay, empty on the other metrics' rows. A study of the
threshold alone (every spec without ``metrics``) exports exactly the columns it always had.
``runs``: one row per run: ``run_token``, ``pid``, ``host``, ``executor``, ``planned`` (scenarios it set
out to compute), ``started_at``, ``ended_at`` [s since the epoch] and ``outcome``: ``running``,
``completed``, ``interrupted`` (SIGINT/SIGTERM), ``incomplete`` (workers lost), ``failed`` (an exception
ended it) or ``killed`` (it died without saying; found so by a later run).
``meta``: the study name and the schema version.

The SQLite file itself (its tables, the connection's journal mode, transactions) and the folder's writer lock
are :mod:`trikedyn.study.engine.database`'s; this module is what is written into it and read out of it.
"""

from __future__ import annotations

import json
import os
import socket
import time
from pathlib import Path

from ..._files import atomic_write, ensure_folder, refuse_symlink
from ...errors import InputError
from .database import DB_COMPANIONS, DB_NAME, connect, mark_killed_runs, take_lock, transaction
from .table import (  # noqa: F401  (the columns are the store's: re-exported)
    EXPORT_COLUMNS,
    METRIC_COLUMNS,
    RESULT_KEYS,
    RUN_INFO_COLUMNS,
    SCENARIO_COLUMNS,
    SEARCH_COLUMNS,
    _unit,
)

__all__ = ["DB_NAME", "EXPORT_COLUMNS", "RESULT_KEYS", "StudyStore"]

EXPORT_NAMES = {"csv": "results.csv", "parquet": "results.parquet"}
"""The exports' file names, by kind."""

_LEGACY = {"metric": "threshold", "metric_options": {}, "metric_label": "threshold"}
"""What a scenario stored before metrics existed measured."""


def _json(value) -> str:
    return json.dumps(value, sort_keys=False, separators=(",", ":"), allow_nan=True)


class StudyStore:
    """The SQLite result store of one study folder (see the module docstring for its guarantees).

    Parameters
    ----------
    folder : path
        Output folder; created if missing. The database is ``folder/study.sqlite``.
    study : str, optional
        The study's name. A folder that holds another study's results is refused (``InputError``).
    lock : bool
        Take the folder's writer lock (a run does; a reader need not). Taking it also marks the runs
        that are still ``running`` as ``killed`` (see :attr:`found_killed`) and checks that no export
        file is a symbolic link.

    Attributes
    ----------
    found_killed : list of str
        Tokens of the earlier runs found still ``running`` when the lock was taken, now ``killed``.

    Raises
    ------
    InputError
        The folder cannot be created or written (naming it); the lock, the store or an export file is a
        symbolic link (naming it); the store is not a study store; another run holds the lock; the folder
        holds another study.
    """

    def __init__(self, folder: str | Path, study: str | None = None, *, lock: bool = False):
        self._conn = None
        self._lock_fd = None
        self.found_killed: list[str] = []
        self.folder = ensure_folder(folder)
        self.path = self.folder / DB_NAME
        try:
            self._lock_fd = take_lock(self.folder) if lock else None
            for name in (DB_NAME, *(DB_NAME + suffix for suffix in DB_COMPANIONS)):
                refuse_symlink(self.folder / name)
            if lock:
                for name in EXPORT_NAMES.values():
                    refuse_symlink(self.folder / name)
            self._conn = connect(self.path, study)
            stored = self.meta().get("study")
            if study is not None and stored != study:
                raise InputError(f"holds the results of study '{stored}', not '{study}'; use another folder",
                                 where=str(self.folder))
            if self._lock_fd is not None:
                self.found_killed = mark_killed_runs(self._conn)
        except BaseException:
            self.close()
            raise

    def close(self) -> None:
        """Close the database and release the writer lock."""
        conn = getattr(self, "_conn", None)
        if conn is not None:
            conn.close()
            self._conn = None
        if getattr(self, "_lock_fd", None) is not None:
            os.close(self._lock_fd)
            self._lock_fd = None

    def __enter__(self) -> StudyStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # -- writing ----------------------------------------------------------------------------------
    def put(self, row: dict) -> bool:
        """Store one finished scenario's row, in its own transaction.

        Parameters
        ----------
        row : dict
            As :func:`trikedyn.study.designs.runner.run_scenario` returns it, flat: the scenario's fields,
            ``status``, the threshold result's keys (kept as the ``result`` JSON when ``status`` is
            ``"ok"``), ``error``, ``traceback``, ``wall_time_s``, ``worker``, ``run_token``, ``finished_at``.

        Returns
        -------
        bool
            True if written, False if the scenario was stored already (the stored row is kept).
        """
        with transaction(self._conn):
            return self._insert(row)

    def _insert(self, row: dict) -> bool:
        from ..scenarios import SCENARIO_KEYS

        scenario = {k: row.get(k, _LEGACY.get(k)) for k in SCENARIO_KEYS}
        if row["status"] == "ok":
            skip = {*SCENARIO_KEYS, "status", "error", "traceback", *RUN_INFO_COLUMNS}
            result = {k: v for k, v in row.items() if k not in skip}
        else:
            result = None
        cur = self._conn.execute(
            "INSERT OR IGNORE INTO results (scenario_id, scenario, status, result, error, traceback, wall_time_s,"
            " worker, run_token, finished_at) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
            (
                row["scenario_id"], _json(scenario), row["status"],
                None if result is None else _json(result),
                row.get("error"), row.get("traceback"), row.get("wall_time_s"), row.get("worker"),
                row.get("run_token"), row.get("finished_at", time.time()),
            ),
        )
        return cur.rowcount == 1

    def begin_run(self, token: str, planned: int, executor: str) -> None:
        """Record the start of a run (``planned``: scenarios it will compute).

        Parameters
        ----------
        token : str
            The run's token.
        planned : int
            Scenarios it will compute.
        executor : str
            The executor's description.
        """
        with transaction(self._conn) as c:
            c.execute("INSERT INTO runs VALUES (?, ?, ?, ?, ?, ?, NULL, 'running')",
                      (token, os.getpid(), socket.gethostname(), executor, planned, time.time()))

    def end_run(self, token: str, outcome: str) -> None:
        """Record how a run ended: ``"completed"``, ``"interrupted"``, ``"incomplete"`` or ``"failed"``.

        Parameters
        ----------
        token : str
            The run's token.
        outcome : str
            How it ended.
        """
        with transaction(self._conn) as c:
            c.execute("UPDATE runs SET ended_at = ?, outcome = ? WHERE run_token = ?", (time.time(), outcome, token))

    # -- reading ----------------------------------------------------------------------------------
    def meta(self) -> dict[str, str]:
        """The ``meta`` table as a dict.

        Returns
        -------
        dict of str to str
            The table.
        """
        return dict(self._conn.execute("SELECT key, value FROM meta").fetchall())

    def done_ids(self) -> set[str]:
        """Ids of the scenarios stored (finished, ``ok`` or ``error``).

        Returns
        -------
        set of str
            The ids.
        """
        return {r[0] for r in self._conn.execute("SELECT scenario_id FROM results")}

    def __len__(self) -> int:
        return self._conn.execute("SELECT COUNT(*) FROM results").fetchone()[0]

    def runs(self) -> list[dict]:
        """The runs recorded, oldest first.

        Returns
        -------
        list of dict
            The runs.
        """
        cur = self._conn.execute("SELECT * FROM runs ORDER BY started_at")
        names = [d[0] for d in cur.description]
        return [dict(zip(names, r, strict=True)) for r in cur.fetchall()]

    def rows(self) -> list[dict]:
        """Every stored row, flat: scenario fields, ``status``, the result's keys, ``error`` and run info.

        Returns
        -------
        list of dict
            The rows.
        """
        cur = self._conn.execute(
            "SELECT scenario, status, result, error, traceback, wall_time_s, worker, run_token, finished_at"
            " FROM results")
        out = []
        for scenario, status, result, error, tb, wall, worker, token, finished in cur.fetchall():
            row = {**_LEGACY, **json.loads(scenario)}
            row["status"] = status
            row.update(json.loads(result) if result is not None else dict.fromkeys(RESULT_KEYS))
            if row["metric"] == "threshold" and "value" not in row:  # stored before metrics existed
                row.update(value=row.get("threshold_speed_kmh"), unit="km/h")
            row.update(error=error, traceback=tb, wall_time_s=wall, worker=worker, run_token=token,
                       finished_at=finished)
            out.append(row)
        return out

    def to_pandas(self, order: list[str] | None = None, *, run_info: bool = False):
        """The results as a tidy table, one row per scenario.

        Parameters
        ----------
        order : list of str, optional
            Scenario ids in the wanted order (the spec's); stored rows not listed are left out. All rows,
            sorted by id, if None.
        run_info : bool
            Add ``wall_time_s`` [s], ``worker``, ``run_token`` and ``finished_at`` [s since the epoch]; these
            differ from run to run, so the exports leave them out.

        Returns
        -------
        pandas.DataFrame
            Columns: ``EXPORT_COLUMNS`` with one column per override path (named by it) after
            ``damping_scale``; ``n_runs`` is a nullable integer. When a row measures another metric than
            the threshold: ``metric`` (its label) after the overrides, ``value`` and ``unit`` after
            ``status`` (see the module docstring).
        """
        from .table import results_table

        return results_table(self.rows(), order, run_info=run_info)

    def export(self, order: list[str], folder: str | Path | None = None) -> dict[str, Path]:
        """Write ``results.csv`` and ``results.parquet`` (spec order, deterministic columns only), each
        atomically (a temporary file in the same folder, renamed into place).

        Parameters
        ----------
        order : list of str
            Scenario ids in the spec's order.
        folder : str or Path, optional
            Where to write (beside the store by default).

        Returns
        -------
        dict
            ``{"csv": path, "parquet": path}``.

        Raises
        ------
        InputError
            An export file is a symbolic link, or the folder cannot be written (naming it); the previous
            files are then left as they were.
        """
        folder = ensure_folder(folder) if folder is not None else self.folder
        out = {kind: refuse_symlink(folder / name) for kind, name in EXPORT_NAMES.items()}
        frame = self.to_pandas(order)
        atomic_write(out["csv"], lambda fh: frame.to_csv(fh, index=False, lineterminator="\n"), binary=False)
        atomic_write(out["parquet"], lambda fh: frame.to_parquet(fh, index=False))
        return out
