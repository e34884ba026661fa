"""A CSV log a long run appends a row to as each piece of work finishes, read back to resume after a kill.

Used by the sampled studies (:class:`SampleLog`) and the layout optimiser
(:class:`~trikedyn.study.designs.optimise_log.EvaluationLog`): each row is flushed at once; a row cut short by a kill
(the last, without its line end) is dropped on reading and stays a line of its own when appending goes on.
Every row's third column is its status, ``ok`` or ``failed``. A log is read by the bounded reader
(:mod:`trikedyn._reading`), at most :data:`MAX_LOG_BYTES`: a FIFO or a device put in its place is refused,
never waited on.
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from ...errors import InputError

__all__ = ["MAX_LOG_BYTES", "AppendedCsv", "SampleLog"]

MAX_LOG_BYTES = 512 << 20
"""Largest log a resumed run reads [bytes] (100,000 samples of 40 factors are about 100 MiB)."""


class AppendedCsv:
    """The file at ``path`` with the header ``columns`` (``earlier``: the header an earlier trikedyn wrote for
    the same run, which a resumed run refuses with its own reason)."""

    def __init__(self, path: str | os.PathLike, columns: list[str], earlier: list[str] | None = None):
        self.path = Path(path)
        self.columns = list(columns)
        self.earlier = None if earlier is None or list(earlier) == self.columns else list(earlier)
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
        from ..._files import refuse_symlink

        if not refuse_symlink(self.path).exists():
            return []
        from ..._reading import read_bytes

        text = read_bytes(self.path, max_bytes=MAX_LOG_BYTES, expected="a run's log (CSV)").decode(
            "utf-8", errors="replace")
        if text and not text.endswith("\n"):
            text = text[: text.rfind("\n") + 1]  # the last row, cut short by a kill: done again
        rows = list(csv.reader(io.StringIO(text)))
        if not rows:
            return []
        if self.earlier is not None and rows[0] == self.earlier:
            raise InputError("was written by an earlier trikedyn, which named a metric's value as a threshold speed "
                             f"({', '.join(c for c in self.earlier if c not in self.columns)}); it cannot be resumed: "
                             "use --force (start again) or another --out", where=str(self.path))
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
        from ..._files import open_nofollow

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


# ------------------------------------------------------------------------------------------------
# the log of samples (CSV, appended as rows finish) and the run
# ------------------------------------------------------------------------------------------------
class SampleLog(AppendedCsv):
    """The samples of a run as a CSV file: one row per evaluated sample, appended (and flushed) as it finishes.

    Columns: ``sample`` (row index), ``group`` (Morris trajectory or Sobol block), ``status`` (``ok`` or
    ``failed``), ``threshold_speed_kmh`` [km/h] (another ``metric``'s value is named by it:
    :func:`~trikedyn.study.designs.named.column`), ``limit`` (what failed above the threshold, or empty:
    :meth:`~trikedyn.study.designs.sample_runs.Search.outcome`), ``error``, then each factor's value [its unit].
    """

    def __init__(self, path: str | os.PathLike, factors: Iterable, group: int, metric: str = "threshold"):
        from .named import column

        self.names = [f.name for f in factors]
        self.group = group
        columns = ["sample", "group", "status", "threshold_speed_kmh", "limit", "error", *self.names]
        super().__init__(path, [column(c, metric) if c == "threshold_speed_kmh" else c for c in columns], columns)

    def read(self, X: np.ndarray) -> dict[int, tuple[float | None, str | None, str]]:
        """The samples logged already: index -> ``(threshold or None, error or None, limit)``.

        A row cut short by a kill (the last, without its line end) is skipped: evaluated again. A row whose
        inputs are not those of ``X`` means the file belongs to another run.

        Parameters
        ----------
        X : numpy.ndarray
            The run's inputs, one row per sample [factor units].

        Returns
        -------
        dict
            Index -> ``(threshold [km/h] or None, error or None, limit)``.

        Raises
        ------
        InputError
            The file's columns or rows are not those of this run.
        """
        known = {}
        for row in self.logged_rows("use another --out or --force (other parameters?)"):
            try:
                i = int(row[0])
                inputs = np.array([float(v) for v in row[6:]])
                y = float(row[3]) if row[2] == "ok" else None
            except ValueError:
                continue
            if not (0 <= i < X.shape[0]) or not np.allclose(inputs, X[i], rtol=1e-12, atol=0.0):
                raise InputError(f"sample {i} is not this run's (another seed, method or range?); use another --out "
                                 "or --force", where=str(self.path))
            known[i] = (y, row[5] or None, row[4])
        return known

    def append(self, index: int, x, threshold: float | None, error: str | None, limit: str = "") -> None:
        """Log one finished sample (flushed at once).

        Parameters
        ----------
        index : int
            The sample's row.
        x : sequence of float
            Its inputs [factor units].
        threshold : float or None
            Threshold [km/h].
        error : str or None
            Why it has none.
        limit : str
            What limits it.
        """
        status = "ok" if threshold is not None else "failed"
        self.write([index, index // self.group, status, "" if threshold is None else repr(float(threshold)), limit,
                    " ".join((error or "").split()), *(repr(float(v)) for v in x)])
