"""A CSV log a long run appends a row to as each piece of work finishes, read back to resume after a kill.

Used by the sampled studies (:class:`~trikedyn.study.sample_runs.SampleLog`) and the layout optimiser
(:class:`~trikedyn.study.optimise_log.EvaluationLog`): each row is flushed at once; a row cut short by a kill
(the last, without its line end) is dropped on reading and stays a line of its own when appending goes on.
Every row's third column is its status, ``ok`` or ``failed``. A log is read by the bounded reader
(:mod:`trikedyn._reading`), at most :data:`MAX_LOG_BYTES`: a FIFO or a device put in its place is refused,
never waited on.
"""

from __future__ import annotations

import csv
import io
import os
from pathlib import Path

from ..errors import InputError

__all__ = ["MAX_LOG_BYTES", "AppendedCsv"]

MAX_LOG_BYTES = 512 << 20
"""Largest log a resumed run reads [bytes] (100,000 samples of 40 factors are about 100 MiB)."""


class AppendedCsv:
    """The file at ``path`` with the header ``columns``."""

    def __init__(self, path: str | os.PathLike, columns: list[str]):
        self.path = Path(path)
        self.columns = list(columns)
        self._fh = None

    def logged_rows(self, mismatch: str) -> list[list[str]]:
        """The complete rows logged already, header left out (none when there is no file).

        Parameters
        ----------
        mismatch : str
            What to do when the header differs, for the error.

        Returns
        -------
        list of list of str
            The rows.

        Raises
        ------
        InputError
            The header is not :attr:`columns` (``mismatch`` says what to do).
        """
        from .._files import refuse_symlink

        if not refuse_symlink(self.path).exists():
            return []
        from .._reading import read_bytes

        text = read_bytes(self.path, max_bytes=MAX_LOG_BYTES, expected="a run's log (CSV)").decode(
            "utf-8", errors="replace")
        if text and not text.endswith("\n"):
            text = text[: text.rfind("\n") + 1]  # the last row, cut short by a kill: done again
        rows = list(csv.reader(io.StringIO(text)))
        if not rows:
            return []
        if rows[0] != self.columns:
            raise InputError(f"its columns are not those of this run; {mismatch}", where=str(self.path))
        return [row for row in rows[1:] if len(row) == len(self.columns) and row[2] in ("ok", "failed")]

    def open(self, fresh: bool) -> None:
        """Open for appending (``fresh``: empty it first), writing the header into an empty file.

        Parameters
        ----------
        fresh : bool
            Empty the file first.
        """
        from .._files import open_nofollow

        fd = open_nofollow(self.path)
        if fresh:
            os.ftruncate(fd, 0)
        size = os.lseek(fd, 0, os.SEEK_END)
        ends_cleanly = True
        if size:
            os.lseek(fd, size - 1, os.SEEK_SET)
            ends_cleanly = os.read(fd, 1) == b"\n"
            os.lseek(fd, 0, os.SEEK_END)
        self._fh = os.fdopen(fd, "a", encoding="utf-8", newline="")
        if not ends_cleanly:
            self._fh.write("\n")  # a line cut short by a kill stays a line of its own
        if not size:
            csv.writer(self._fh).writerow(self.columns)
        self._fh.flush()

    def write(self, row: list) -> None:
        """Append one row, flushed at once.

        Parameters
        ----------
        row : list
            The cells.
        """
        csv.writer(self._fh).writerow(row)
        self._fh.flush()

    def close(self) -> None:
        """Close the file (again: nothing)."""
        if self._fh is not None:
            self._fh.close()
            self._fh = None
