"""Libraries a design's main process will need after its evaluations, imported while the workers compute.

A design's main process waits while its workers evaluate, then analyses and plots. Importing what it will
need then (pandas and pyarrow for a study's table, SALib's analysis and scipy.stats for a sensitivity,
matplotlib for the figures: 0.5-1.5 s) in a thread of the main process during the evaluations takes it off
the end of the run, where nothing else would be running. On a machine whose cores the workers fill, the
import still takes a core's time, but shared with the workers instead of after them.
"""

from __future__ import annotations

import contextlib
import importlib
import threading

__all__ = ["import_in_background"]


def _import_all(modules: tuple[str, ...]) -> None:
    """Import ``modules`` in turn; one that fails is left to fail where it is used (with its own error)."""
    for name in modules:
        with contextlib.suppress(Exception):
            importlib.import_module(name)


def import_in_background(*modules: str) -> threading.Thread:
    """Import ``modules`` (dotted names) in a daemon thread of this process, now.

    Parameters
    ----------
    *modules : str
        The modules, in the order they are needed.

    Returns
    -------
    threading.Thread
        The started thread (a daemon: it does not keep the process alive).
    """
    thread = threading.Thread(target=_import_all, args=(tuple(modules),), daemon=True,
                              name="trikedyn-background-imports")
    thread.start()
    return thread
