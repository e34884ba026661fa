"""How a study reports its progress: a bar on a terminal, a plain line otherwise (a log, CI, a pipe).

A reporter is what :func:`trikedyn.study.designs.runner.run_study` takes as ``progress``: a callable
``(done, total)`` called at the start, after each stored scenario and at the end, with optional ``note(text)``
(e.g. "SIGINT: stopping after the scenarios in flight") and ``close()``. :func:`reporter` makes the default
one; the runner itself never prints.

Without a terminal, the line is :class:`ProgressLine` (also the sampled studies' line)
(every few seconds and at the end), with the time spent and an estimate of the time left::

    study: 12/50 scenarios, 8.1 s, ~25 s left
"""

from __future__ import annotations

import sys
import time

__all__ = ["BarProgress", "LineProgress", "ProgressLine", "reporter"]


class ProgressLine:
    """``LABEL: 12/45 UNIT`` on stderr at the start, every ``every_s`` seconds, and at the end (a line, not a
    bar: it also works without a terminal)."""

    def __init__(self, label: str, unit: str = "runs", every_s: float = 5.0):
        self.label, self.unit, self.every_s = label, unit, every_s
        self.last = None
        self.shown = None

    def __call__(self, done: int, total: int) -> None:
        now = time.monotonic()
        if (done, total) == self.shown:
            return
        if self.last is None or done == total or now - self.last >= self.every_s:
            print(f"{self.label}: {done}/{total} {self.unit}", file=sys.stderr, flush=True)
            self.last, self.shown = now, (done, total)


class LineProgress:
    """``study: 12/50 scenarios, 8.1 s, ~25 s left`` on stderr every ``every_s`` seconds and at the end."""

    def __init__(self, label: str = "study", every_s: float = 5.0):
        self._line = ProgressLine(label, "scenarios", every_s=every_s)
        self._start = time.monotonic()
        self._first: int | None = None

    def __call__(self, done: int, total: int) -> None:
        if self._first is None:
            self._first = done  # already stored: not part of this run's pace
        elapsed = time.monotonic() - self._start
        pace = (done - self._first) / elapsed if elapsed > 0 else 0.0
        unit = f"scenarios, {elapsed:.1f} s"
        if 0 < done < total and pace > 0:
            unit += f", ~{(total - done) / pace:.0f} s left"
        self._line.unit = unit  # the shared line's text after the counts
        self._line(done, total)

    def note(self, text: str) -> None:
        """Print ``text`` as a line (stderr).

        Parameters
        ----------
        text : str
            The note.
        """
        print(text, file=sys.stderr, flush=True)

    def close(self) -> None:
        """Nothing to close (lines are printed as they come)."""
        return None


class BarProgress:
    """A tqdm bar on stderr (a terminal)."""

    def __init__(self, label: str = "study"):
        self._label = label
        self._bar = None

    def __call__(self, done: int, total: int) -> None:
        if self._bar is None:
            from tqdm import tqdm

            self._bar = tqdm(total=total, initial=done, file=sys.stderr, unit="scenario", desc=self._label,
                             dynamic_ncols=True)
        self._bar.update(done - self._bar.n)

    def note(self, text: str) -> None:
        """Print ``text`` on its own line below the bar (stderr).

        Parameters
        ----------
        text : str
            The note.
        """
        print(f"\n{text}", file=sys.stderr, flush=True)

    def close(self) -> None:
        """Close the bar."""
        if self._bar is not None:
            self._bar.close()


def reporter(progress=True, label: str = "study"):
    """The reporter for ``progress``: True -> a bar on a terminal, a line every 5 s otherwise; False or None
    -> None (silent); anything else (a callable ``(done, total)``) is used as it is.

    Parameters
    ----------
    progress : bool or callable
        What the caller asked for.
    label : str
        What is counted, for the bar or line.

    Returns
    -------
    callable or None
        ``(done, total)`` reporter.
    """
    if progress is True:
        return BarProgress(label) if sys.stderr.isatty() else LineProgress(label)
    if progress is False or progress is None:
        return None
    return progress
