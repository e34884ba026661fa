"""trikedyn.study.engine.executors: where the process pool's workers come from, and how they end.

That the workers exit when the main process is killed is shown by the kill tests of ``test_resume`` and
``test_acceptance`` (the whole process group gone); the executor interface by ``test_metrics``.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import os
import subprocess
import sys

import pytest

from trikedyn.study.engine import executors
from trikedyn.study.engine.executors import PRELOAD, ProcessPool, pool_context

from .test_resume import _group_gone

HAS_FORK_SERVER = "forkserver" in multiprocessing.get_all_start_methods()
LOADED = "[m in __import__('sys').modules for m in {names!r}]"


def _run(pool: ProcessPool, fn, *args):
    fut = pool.submit(fn, *args)
    cf.wait([fut], timeout=60)
    return fut.result()


@pytest.mark.skipif(not HAS_FORK_SERVER, reason="this platform has no fork server: the workers are spawned")
def test_workers_fork_from_a_server_that_imported_the_simulation():
    pool = ProcessPool(1)
    try:
        assert pool_context().get_start_method() == "forkserver"
        assert _run(pool, os.getppid) != os.getpid()  # the fork server's child, not ours
        # eval is a builtin: the call itself imports nothing, so what is loaded came from the server
        assert _run(pool, eval, LOADED.format(names=list(PRELOAD))) == [True] * len(PRELOAD)
    finally:
        pool.shutdown()


@pytest.mark.skipif(not HAS_FORK_SERVER, reason="this platform has no fork server: the workers are spawned")
def test_workers_inherit_numbas_contexts_from_the_server():
    """numba's typing context has its registries installed before the worker's first compiled call (the
    0.27 s a worker paid at its first run); a fresh process has none."""
    registries = ("len(getattr(__import__('numba.core.registry', fromlist=['x']).cpu_target.typing_context, "
                  "'_registries', {}))")
    fresh = subprocess.run([sys.executable, "-c", f"import numba.core.registry; print({registries})"],
                           capture_output=True, text=True, check=True)
    assert fresh.stdout.strip() == "0"  # the attribute this test reads is the one numba fills
    pool = ProcessPool(1)
    try:
        assert _run(pool, eval, registries) > 0
    finally:
        pool.shutdown()


@pytest.mark.skipif(not HAS_FORK_SERVER, reason="this platform has no fork server: the workers are spawned")
def test_the_servers_heap_is_frozen_before_it_forks_the_workers():
    """The simulation's objects are in the collector's permanent generation: a worker's collections do not
    traverse (and copy) them."""
    pool = ProcessPool(1)
    try:
        assert _run(pool, eval, "__import__('gc').get_freeze_count()") > 10_000
    finally:
        pool.shutdown()


def test_workers_are_spawned_when_the_fork_server_cannot_start(monkeypatch):
    from multiprocessing import forkserver

    def no_socket():
        raise OSError(30, "Read-only file system")

    monkeypatch.setattr(forkserver, "ensure_running", no_socket)
    monkeypatch.setattr(executors, "_fork_server_failed", False)
    pool = ProcessPool(1)
    try:
        assert pool_context().get_start_method() == "spawn"
        assert _run(pool, os.getppid) == os.getpid()
        assert _run(pool, eval, "1 + 1") == 2
    finally:
        pool.shutdown()


def test_a_killed_main_process_takes_its_fork_server_and_workers_with_it(tmp_path):
    """SIGKILL the main process while its workers compute: nothing of its process group is left."""
    script = tmp_path / "main.py"
    script.write_text(
        "import os, time\n"
        "from trikedyn.study.engine.executors import ProcessPool\n"
        "if __name__ == '__main__':\n"
        "    pool = ProcessPool(2)\n"
        "    futures = [pool.submit(time.sleep, 600) for _ in range(2)]\n"
        "    while len(pool._processes) < 2 or not all(f.running() for f in futures):\n"
        "        time.sleep(0.05)\n"
        "    print(os.getpid(), flush=True)\n"
        "    time.sleep(600)\n", encoding="utf-8")
    proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        assert proc.stdout.readline().strip() == str(proc.pid)  # both workers in time.sleep(600)
        proc.kill()
        proc.wait(timeout=30)
        assert _group_gone(proc.pid, timeout_s=15.0), "the fork server or a worker outlived the killed main process"
    finally:
        try:
            os.killpg(proc.pid, 9)
        except ProcessLookupError:
            pass


def test_the_main_process_reads_a_spec_without_loading_the_simulation():
    """The study's main process hands the searches to its workers: reading and checking the paper's spec (its
    search settings, its overrides) loads neither numba nor the model, whose imports (about 0.7 s of CPU) would
    compete with the fork server's on a two-core machine."""
    import subprocess
    import sys

    code = ("import sys\nfrom trikedyn.study.spec import load_spec\nspec = load_spec('paper')\n"
            "from trikedyn.analysis.search_settings import SearchSettings\nSearchSettings(low_kmh=10, high_kmh=60)\n"
            "print(sorted(m for m in ('numba', 'trikedyn.model.rhs', 'trikedyn.tyre', 'scipy.optimize')"
            " if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_the_fork_server_and_its_workers_stay_quiet_when_the_main_process_vanishes(capsys):
    """An interrupted command can vanish in the middle of asking the fork server for a worker: the server's
    EOFError is not printed as a traceback (tests/test_interrupts.py met it); any other error still is."""
    from trikedyn.study.engine import warm

    assert not warm.in_the_fork_server()  # this process: Python's own hook, untouched
    pool = ProcessPool(1)
    try:
        assert _run(pool, eval, "__import__('trikedyn.study.engine.warm', fromlist=['x']).in_the_fork_server()")
        assert _run(pool, eval, "type(__import__('sys').excepthook).__name__") == "QuietWhenTheClientVanishes"
    finally:
        pool.shutdown()
    ended = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    gone_client = int(ended.stdout)  # a process that has ended (and been reaped)
    try:
        raise ValueError("a real bug")
    except ValueError as exc:
        bug = exc
    for client, quiet in ((None, False), (os.getpid(), False), (gone_client, True)):
        hook = warm.QuietWhenTheClientVanishes(client=client, wait_s=0.05)
        for gone in (EOFError(), BrokenPipeError(), ConnectionResetError()):  # the other end closed: quiet
            hook(type(gone), gone, None)
        assert capsys.readouterr().err == ""
        hook(ValueError, bug, bug.__traceback__)  # anything else: printed while the client runs
        err = capsys.readouterr().err
        assert (err == "") if quiet else ("Traceback" in err and "ValueError: a real bug" in err), (client, err)


VANISHING_CLIENT = """
import socket, sys, time
from multiprocessing import forkserver
from trikedyn.study.engine.executors import pool_context
if __name__ == "__main__":
    pool_context()  # the fork server, started
    with socket.socket(socket.AF_UNIX) as s:  # a client that connects and vanishes before it sends anything
        s.connect(forkserver._forkserver._forkserver_address)
    time.sleep(1.5)
    print("done", file=sys.stderr)
"""


def test_a_client_vanishing_in_its_request_leaves_no_traceback(tmp_path):
    script = tmp_path / "vanish.py"
    script.write_text(VANISHING_CLIENT)
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and "done" in done.stderr
    assert "Traceback" not in done.stderr and "EOFError" not in done.stderr, done.stderr
