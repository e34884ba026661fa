"""A real Dask cluster on 127.0.0.1 for the tests and the cluster benchmark: a ``dask scheduler`` and
``dask worker`` processes (one thread each, no nanny: the worker's process id is the worker), each a subprocess
in its own session, stopped by their process ids (SIGTERM, then SIGKILL).

Usage::

    with DaskProcesses(folder, workers=2) as cluster:
        run(["trikedyn", ..., "--scheduler", cluster.address])
        cluster.kill_worker(0)  # SIGKILL
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

__all__ = ["DaskProcesses"]

START_TIMEOUT_S = 90.0
"""Longest wait for the scheduler's address, or for the workers to register [s] (a loaded machine)."""

STOP_GRACE_S = 10.0
"""Wait after SIGTERM before SIGKILL [s]."""


class DaskProcesses:
    """A scheduler and ``workers`` single-threaded workers as subprocesses; :meth:`start` waits until every
    worker is registered, :meth:`stop` (or leaving the ``with`` block) ends them by their process ids.

    Parameters
    ----------
    folder : Path
        Where the logs (``scheduler.log``, ``worker-<name>.log``) and the workers' local directories go.
    workers : int
        Worker processes.
    """

    def __init__(self, folder: Path, workers: int = 2):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.n_workers = workers
        self.scheduler: subprocess.Popen | None = None
        self.address: str | None = None
        self.workers: dict[str, subprocess.Popen] = {}
        self._count = 0

    def _spawn(self, log: Path, *args: str) -> subprocess.Popen:
        env = {**os.environ, "NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
        with log.open("w") as fh:
            return subprocess.Popen([sys.executable, "-m", "dask", *args], cwd=self.folder, stdout=fh,
                                    stderr=subprocess.STDOUT, start_new_session=True, env=env)

    def start(self) -> DaskProcesses:
        """Start the scheduler (a free port) and the workers; wait until all are registered.

        Returns
        -------
        DaskProcesses
            Itself.
        """
        self.start_scheduler()
        self.start_workers()
        return self

    def start_scheduler(self) -> str:
        """Start the scheduler alone (:meth:`start_workers` later), on a free port; its address.

        Returns
        -------
        str
            ``tcp://127.0.0.1:PORT``.
        """
        log = self.folder / f"scheduler{self._count}.log"
        self._count += 1
        self.scheduler = self._spawn(log, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard")
        deadline = time.monotonic() + START_TIMEOUT_S
        while self.address is None:
            found = re.search(r"Scheduler at:\s+(tcp://127\.0\.0\.1:\d+)", log.read_text())
            if found:
                self.address = found.group(1)
            elif self.scheduler.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"the scheduler gave no address: {log.read_text()[-2000:]}")
            else:
                time.sleep(0.1)
        return self.address

    def start_workers(self) -> None:
        """Start the workers and wait until they are registered."""
        for _ in range(self.n_workers - len(self.workers)):
            self.start_worker()
        self.wait_for_workers()

    def start_worker(self) -> str:
        """Start one more worker (not waiting for it to register).

        Returns
        -------
        str
            Its name.
        """
        name = f"w{self._count}"
        self._count += 1
        self.workers[name] = self._spawn(self.folder / f"worker-{name}.log", "worker", self.address, "--name", name,
                                         "--nthreads", "1", "--no-nanny", "--no-dashboard",
                                         "--local-directory", str(self.folder / name))
        return name

    def registered(self) -> set[str]:
        """The names of the workers the scheduler knows now."""
        from distributed import Client

        with Client(self.address, timeout="30s") as client:
            return {info["name"] for info in client.scheduler_info(n_workers=-1)["workers"].values()}

    def client_tasks(self) -> list[int]:
        """How many tasks each client of the scheduler holds (but the one asking)."""
        from distributed import Client

        def count(dask_scheduler):
            return {cid: len(state.wants_what) for cid, state in dask_scheduler.clients.items()}

        with Client(self.address, timeout="30s") as client:
            return [n for cid, n in client.run_on_scheduler(count).items()
                    if cid != client.id and not cid.startswith("fire-and-forget")]

    def wait_for_workers(self) -> None:
        """Wait until the scheduler knows exactly the live workers (a killed one gone, a new one registered)."""
        deadline = time.monotonic() + START_TIMEOUT_S
        while True:
            live = {name for name, proc in self.workers.items() if proc.poll() is None}
            if self.registered() == live and len(live) == self.n_workers:
                return
            dead = [name for name, proc in self.workers.items() if proc.poll() is not None]
            if time.monotonic() > deadline:
                logs = {n: (self.folder / f"worker-{n}.log").read_text()[-1000:] for n in self.workers}
                raise RuntimeError(f"workers not registered in time (dead: {dead}): {logs}")
            time.sleep(0.2)

    def ensure_workers(self) -> None:
        """Replace the workers that died (or were killed), and wait until they are registered."""
        for name, proc in list(self.workers.items()):
            if proc.poll() is not None:
                del self.workers[name]
                self.start_worker()
        self.wait_for_workers()

    def kill_worker(self, index: int = 0) -> int:
        """SIGKILL the worker ``index`` (in start order); its process id.

        Parameters
        ----------
        index : int
            Which worker.

        Returns
        -------
        int
            The killed process's id.
        """
        proc = list(self.workers.values())[index]
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
        return proc.pid

    def kill_scheduler(self) -> None:
        """SIGKILL the scheduler (the workers are left running, as on a cluster whose scheduler host died)."""
        os.kill(self.scheduler.pid, signal.SIGKILL)
        self.scheduler.wait(timeout=30)

    def stop(self) -> None:
        """End every process by its id: SIGTERM, then SIGKILL after :data:`STOP_GRACE_S`."""
        for procs in (list(self.workers.values()), [self.scheduler] if self.scheduler else []):
            # the workers first: terminated together with the scheduler, they wait for it to the grace's end
            for proc in procs:
                if proc.poll() is None:
                    with contextlib.suppress(ProcessLookupError):
                        os.kill(proc.pid, signal.SIGTERM)
            deadline = time.monotonic() + STOP_GRACE_S
            for proc in procs:
                try:
                    proc.wait(timeout=max(deadline - time.monotonic(), 0.1))
                except subprocess.TimeoutExpired:
                    with contextlib.suppress(ProcessLookupError):
                        os.kill(proc.pid, signal.SIGKILL)
                    proc.wait(timeout=30)
        self.workers.clear()
        self.scheduler, self.address = None, None

    def __enter__(self) -> DaskProcesses:
        try:
            return self.start()
        except BaseException:
            self.stop()
            raise

    def __exit__(self, *exc) -> None:
        self.stop()
