"""The study store's SQLite file and its folder's writer lock (:mod:`trikedyn.study.engine.store` builds on them).

- :func:`connect` opens ``study.sqlite`` in WAL mode with ``synchronous=FULL`` (a kill at any moment leaves
  the last committed state; an interrupted transaction is rolled back when the file is next opened), creates
  the tables and records the schema version and the study's name in ``meta``.
- :func:`transaction` is ``BEGIN IMMEDIATE`` ... ``COMMIT``, rolled back on any exception.
- :func:`take_lock` takes the exclusive lock on ``study.lock`` (``fcntl.flock``: released by the OS even on
  SIGKILL), so that two runs cannot write into one folder at once; :func:`mark_killed_runs`, called with it
  held, marks the runs still ``running`` as ``killed``.

Tables: ``results`` (one row per finished scenario, keyed by ``scenario_id``), ``runs`` (one row per run)
and ``meta`` (key, value); their columns are described in :mod:`trikedyn.study.engine.store`.
"""

from __future__ import annotations

import contextlib
import errno
import os
import sqlite3
import time
from collections.abc import Iterator
from pathlib import Path

from ..._files import open_nofollow
from ...errors import InputError

__all__ = ["DB_COMPANIONS", "DB_NAME", "LOCK_NAME", "SCHEMA_VERSION", "connect", "mark_killed_runs", "take_lock",
           "transaction"]

DB_NAME = "study.sqlite"
"""The store's file in an output folder."""
LOCK_NAME = "study.lock"
"""The file a writing run holds locked."""
DB_COMPANIONS = ("-wal", "-shm", "-journal")
"""Files SQLite keeps beside the database (``study.sqlite-wal``, ...)."""
SCHEMA_VERSION = "1"
"""The version of the tables, recorded in ``meta``."""

_SCHEMA = """
CREATE TABLE IF NOT EXISTS results (
    scenario_id TEXT PRIMARY KEY,
    scenario    TEXT NOT NULL,
    status      TEXT NOT NULL CHECK (status IN ('ok', 'error')),
    result      TEXT,
    error       TEXT,
    traceback   TEXT,
    wall_time_s REAL,
    worker      TEXT,
    run_token   TEXT,
    finished_at REAL
);
CREATE TABLE IF NOT EXISTS runs (
    run_token   TEXT PRIMARY KEY,
    pid         INTEGER,
    host        TEXT,
    executor    TEXT,
    planned     INTEGER,
    started_at  REAL,
    ended_at    REAL,
    outcome     TEXT
);
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
"""


def connect(path: Path, study: str | None) -> sqlite3.Connection:
    """Open the store (WAL, ``synchronous=FULL``, autocommit), create its tables, record the schema version
    and the study's name (if none is recorded yet).

    Parameters
    ----------
    path : Path
        The database file (``folder/study.sqlite``).
    study : str, optional
        The study's name, recorded in ``meta`` when the store is new.

    Returns
    -------
    sqlite3.Connection
        The connection; transactions are :func:`transaction`'s.

    Raises
    ------
    InputError
        The folder or the file cannot be written, the file is not a database, or a folder has its name.
    """
    conn = None
    try:
        conn = sqlite3.connect(path, isolation_level=None, timeout=30.0)
        conn.execute("PRAGMA journal_mode=WAL")
        conn.execute("PRAGMA synchronous=FULL")
        with transaction(conn):
            for statement in _SCHEMA.split(";"):
                if statement.strip():
                    conn.execute(statement)
            conn.execute("INSERT OR IGNORE INTO meta VALUES ('schema_version', ?)", (SCHEMA_VERSION,))
            if study is not None:
                conn.execute("INSERT OR IGNORE INTO meta VALUES ('study', ?)", (study,))
    except sqlite3.DatabaseError as exc:  # unwritable folder or file, not a database, a folder by that name
        if conn is not None:
            conn.close()
        raise InputError(f"cannot open the study store ({exc})", where=str(path)) from None
    return conn


@contextlib.contextmanager
def transaction(conn: sqlite3.Connection) -> Iterator[sqlite3.Connection]:
    """``BEGIN IMMEDIATE`` ... ``COMMIT``; rolled back on any exception.

    Parameters
    ----------
    conn : sqlite3.Connection
        An autocommit connection (:func:`connect`'s).

    Yields
    ------
    sqlite3.Connection
        The same connection, inside the transaction.
    """
    conn.execute("BEGIN IMMEDIATE")
    try:
        yield conn
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    conn.execute("COMMIT")


def take_lock(folder: Path) -> int | None:
    """Take the folder's exclusive writer lock on ``study.lock`` without waiting.

    Parameters
    ----------
    folder : Path
        The output folder.

    Returns
    -------
    int or None
        The locked file's descriptor, held until it is closed (the OS releases it when the process dies);
        None where there is no ``fcntl`` (not POSIX: no cross-process lock).

    Raises
    ------
    InputError
        Another run holds the lock, the lock file is a symbolic link, or it cannot be locked (naming it).
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX: no cross-process lock
        return None
    fd = open_nofollow(folder / LOCK_NAME)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError as exc:
        os.close(fd)
        if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
            raise InputError("another study run is writing into this folder; wait for it or use another "
                             "folder", where=str(folder)) from None
        raise InputError(f"cannot lock ({exc.strerror or exc})", where=str(folder / LOCK_NAME)) from None
    return fd


def mark_killed_runs(conn: sqlite3.Connection) -> list[str]:
    """Mark the runs still ``running`` as ``killed``, ended now.

    Called with the folder's lock held: every run holds that lock from before it records its start until
    after it records its end, and the OS releases it when its process dies, so a run still ``running`` now
    is one whose process is gone (pid and host are not checked: pids are reused).

    Parameters
    ----------
    conn : sqlite3.Connection
        The store's connection.

    Returns
    -------
    list of str
        The tokens of the runs so marked.
    """
    with transaction(conn) as c:
        tokens = [r[0] for r in c.execute("SELECT run_token FROM runs WHERE outcome = 'running'")]
        c.execute("UPDATE runs SET outcome = 'killed', ended_at = ? WHERE outcome = 'running'", (time.time(),))
    return tokens
