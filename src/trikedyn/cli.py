"""The ``trikedyn`` command: a thin command map over the Python API.

Every command has ``--help`` and ``--json``. A user's mistake (file, field, value) prints one line,
``trikedyn: error: WHERE: WHAT``, and exits with code 2; nothing else is printed. Ctrl-C (SIGINT) prints one
line, ``trikedyn: interrupted`` (and what was kept, where a command says so: :func:`~trikedyn.commands._common.
on_interrupt`), under ``--json`` also a JSON object ``{"error": "interrupted...", "where": "SIGINT",
"interrupted": true}`` on stdout, and exits with code 130. SIGTERM (``timeout``, ``kill``) does the same at
once, its line ``trikedyn: interrupted by SIGTERM``, and exits with code 143 (128 + the signal's number, as a
shell reports a process ended by it).
"""

from __future__ import annotations

import contextlib
import functools
import gc
import json
import os
import signal
import sys
import threading
from typing import Annotated

import typer

from ._version import __version__
from .errors import InputError

app = typer.Typer(
    name="trikedyn",
    help="Stability analysis of three-wheeled vehicles: measure, model, drive, judge, study.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    add_completion=False,
    rich_markup_mode=None,  # help text is plain: units in brackets ([kg], [km/h]) stay visible
)


def _version(value: bool):
    if value:
        typer.echo(f"trikedyn {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Show the version and exit.")
    ] = False,
):
    """trikedyn: how fast can a three-wheeler safely go, and why."""


# ------------------------------------------------------------------------------------------------
# the command map: each group lives in trikedyn.commands
# ------------------------------------------------------------------------------------------------
from .commands import (  # noqa: E402
    animate,
    assess,
    cg,
    drive,
    layouts,
    loading,
    logs,
    optimise,
    performance,
    sensitivity,
    stability,
    studies,
    tyre,
    uncertainty,
    vehicle,
)
from .commands._common import INTERRUPT_NOTES, WARNINGS, emit  # noqa: E402

app.add_typer(vehicle.vehicle_app, name="vehicle")
app.add_typer(cg.cg_app, name="cg")
app.add_typer(logs.log_app, name="log")
app.add_typer(tyre.tyre_app, name="tyre")
app.command("identify")(logs.identify)
app.command("modes")(drive.modes_cmd)
app.command("manoeuvres")(drive.manoeuvres_cmd)
app.command("simulate")(drive.simulate_cmd)
app.command("plot")(drive.plot_cmd)
app.command("animate")(animate.animate_cmd)
app.command("compare")(drive.compare_cmd)
app.command("threshold")(stability.threshold_cmd)
app.command("handling")(stability.handling_cmd)
app.command("tilt")(stability.tilt_cmd)
app.command("performance")(performance.performance_cmd)
app.command("compare-layouts")(layouts.compare_layouts_cmd)
app.command("sensitivity")(sensitivity.sensitivity_cmd)
app.command("study")(studies.study_cmd)
app.command("reproduce")(studies.reproduce_cmd)
app.command("loading-chart")(loading.loading_chart_cmd)
app.command("optimise")(optimise.optimise_cmd)
app.command("uncertainty")(uncertainty.uncertainty_cmd)
app.command("assess")(assess.assess_cmd)

_emit = emit  # the older name
_flatten = vehicle._flatten


# ------------------------------------------------------------------------------------------------
def _fail(message: str, as_json: bool, where: str | None = None) -> int:
    """One line on stderr (and, under --json, a JSON object on stdout); exit code 2."""
    line = " ".join(message.split())
    typer.echo(f"trikedyn: error: {line}", err=True)
    if as_json:
        typer.echo(json.dumps({"error": line, "where": where}, allow_nan=False))
    return 2


def _exit_code(signame: str | None) -> int:
    """The exit code of a command ended by the signal ``signame`` (``"SIGINT"``, ``"SIGTERM"``; None: SIGINT):
    128 + its number, as a shell reports it (130, 143)."""
    return 128 + int(signal.Signals[signame or "SIGINT"])


def _interrupted(as_json: bool, signame: str | None = None) -> int:
    """One line ``trikedyn: interrupted`` (``interrupted by SIGTERM``) on stderr, with what the command kept
    (and, under --json, a JSON object on stdout saying so); exit code 128 + the signal's number (130, 143)."""
    said = "interrupted" if signame in (None, "SIGINT") else f"interrupted by {signame}"
    line = "; ".join([said, *(" ".join(n.split()) for n in INTERRUPT_NOTES)])
    typer.echo(f"trikedyn: {line}", err=True)
    if as_json:
        typer.echo(json.dumps({"error": line, "where": signame or "SIGINT", "interrupted": True}, allow_nan=False))
    return _exit_code(signame)


class _SigintSeen:
    """While a command runs, SIGINT and SIGTERM raise the KeyboardInterrupt Python's own SIGINT handler would,
    and the signal is noted (:attr:`seen`: its name).

    The CLI library turns a KeyboardInterrupt into a silent exit code 130 (``typer``: ``Exit(130)``, returned
    as the command's result): the note is how :func:`main` tells an interrupt from a command that returned 130,
    and says so. SIGTERM, whose default would end the process without a word (and leave a pool's workers to
    notice), ends every command the way Ctrl-C does: what is stored is kept. Each handler is installed only
    over the default one (Python's for SIGINT, none for SIGTERM), in the main thread (a signal ignored by
    the shell that started us stays ignored); a handler a command installs for itself (the study's: stop
    after the scenarios in flight) takes over while it runs.
    """

    _DEFAULTS = {signal.SIGINT: signal.default_int_handler, signal.SIGTERM: signal.SIG_DFL}

    def __init__(self):
        self.seen: str | None = None
        self.lost = False
        self._installed: list = []

    def _handler(self, signum, frame):  # noqa: ARG002
        self.seen = signal.Signals(signum).name
        raise KeyboardInterrupt

    def _unraisable(self, unraisable):
        """A KeyboardInterrupt raised where Python cannot pass it on (a weakref callback or ``__del__`` run by
        the garbage collector when the signal came) would be printed as "Exception ignored" with a traceback and
        lost, and the command would end as if nothing was pressed: it is noted instead (:attr:`lost`), and
        :func:`run_command` reports the interrupt when the command returns (its work then done and kept)."""
        if isinstance(unraisable.exc_value, KeyboardInterrupt) and self.seen:
            self.lost = True
            return
        self._hook(unraisable)

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for sig, default in self._DEFAULTS.items():
                if signal.getsignal(sig) is default:
                    signal.signal(sig, self._handler)
                    self._installed.append(sig)
            if self._installed:
                self._hook = sys.unraisablehook
                sys.unraisablehook = self._unraisable
        return self

    def __exit__(self, *exc):
        for sig in self._installed:
            signal.signal(sig, self._DEFAULTS[sig])
        if self._installed:
            sys.unraisablehook = self._hook
        self._installed = []


def _show_warning(message, category, filename, lineno, file=None, line=None):  # noqa: ARG001
    text = " ".join(str(message).split())
    WARNINGS.append(text)
    typer.echo(f"trikedyn: warning: {category.__name__}: {text}", err=True)


def main(argv: list[str] | None = None) -> int:
    """Entry point: the one error boundary of the command line (:func:`run_command`); an interrupted command
    (exit code 130 or 143) also ends the worker processes it started, before this process exits.

    A pool's worker whose start was cut short by the interrupt (the fork server was still importing, so the
    worker is forked after this process has gone) finds the pool's semaphores gone and prints a traceback
    (``SemLock._rebuild``: ``FileNotFoundError``) onto the terminal after the command's one line. So the fork
    server is ended too, before it forks it.

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name; ``sys.argv[1:]`` by default.

    Returns
    -------
    int
        The exit code (see :func:`run_command`).
    """
    code = run_command(argv)
    if code in (130, 143):
        _stop_children()
    return code


def _stop_children(timeout_s: float = 5.0) -> None:
    """End the processes this process started through ``multiprocessing`` (a pool's workers), waiting at most
    ``timeout_s`` [s] for them to go before killing the rest."""
    mp = sys.modules.get("multiprocessing")
    if mp is None:
        return
    import time

    server = sys.modules.get("multiprocessing.forkserver")
    server_pid = getattr(getattr(server, "_forkserver", None), "_forkserver_pid", None)
    if server_pid:
        with contextlib.suppress(OSError):
            os.kill(server_pid, signal.SIGKILL)
        for pid in _children_of(server_pid):  # forked, but their start was cut short: not in active_children
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
    children = mp.active_children()
    for child in children:
        child.terminate()
    deadline = time.monotonic() + timeout_s
    for child in children:
        child.join(max(0.0, deadline - time.monotonic()))
        if child.is_alive():
            child.kill()
            child.join(1.0)


def _children_of(pid: int) -> list[int]:
    """The processes whose parent is ``pid``, from ``/proc`` (none where there is no ``/proc``)."""
    found = []
    with contextlib.suppress(OSError):
        for entry in os.scandir("/proc"):
            if entry.name.isdigit():
                with contextlib.suppress(OSError, ValueError, IndexError):
                    with open(f"/proc/{entry.name}/stat", "rb") as stat:  # "pid (name) state ppid ..."
                        if int(stat.read(4096).rsplit(b")", 1)[1].split()[1]) == pid:
                            found.append(int(entry.name))
    return found


@functools.cache
def _click_command():
    """The command tree, built from ``app`` once per process (Typer rebuilds it on every call: ~0.1 s, most of
    a quick command's time when commands run in one process, as the tests and the fuzz campaign do)."""
    return typer.main.get_command(app)


def run_command(argv: list[str] | None = None) -> int:
    """Run one command: the one error boundary of the command line.

    A user's mistake or environment (a bad file, field or value; a file that cannot be written; a
    simulation that cannot start or that fails) prints one line ``trikedyn: error: WHERE: WHAT`` on stderr
    and exits with code 2; with ``--json`` the same error is also a JSON object ``{"error", "where"}`` on
    stdout. Warnings print as one line each. Ctrl-C (SIGINT) prints one line ``trikedyn: interrupted`` (with
    what the command kept), under ``--json`` also a JSON object saying so, and exits with code 130; SIGTERM
    likewise (``interrupted by SIGTERM``), exit code 143. A genuine
    bug keeps its traceback (exit code 1).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name; ``sys.argv[1:]`` by default.

    Returns
    -------
    int
        The exit code: 0 on success, 2 on a user's error, 130 on an interrupt, else the code a command exits with.
    """
    import warnings

    args = list(sys.argv[1:] if argv is None else argv)
    as_json = "--json" in args
    WARNINGS.clear()
    INTERRUPT_NOTES.clear()
    from .errors import RunIncomplete, SimulationError

    with warnings.catch_warnings(), _SigintSeen() as sigint:
        warnings.simplefilter("default")
        warnings.showwarning = _show_warning
        try:
            try:
                result = _click_command().main(args=args, prog_name="trikedyn", standalone_mode=False)
            except Exception as exc:  # a Ctrl-C in compiled code comes back as an error caused by it
                from .study.designs.sample_runs import raise_interrupt

                raise_interrupt(exc)
                raise
            if sigint.seen and (result == 130 or sigint.lost):  # the CLI library's silent exit for a
                return _interrupted(as_json, sigint.seen)  # KeyboardInterrupt, or one lost in a callback
        except InputError as exc:
            return _fail(str(exc), as_json, exc.where)
        except RunIncomplete as exc:  # the workers were lost; what finished is kept: exit 1, as the study's
            typer.echo(f"trikedyn: {exc}", err=True)
            if as_json:
                typer.echo(json.dumps({"error": str(exc), "where": "executor", "incomplete": True}, allow_nan=False))
            return 1
        except SimulationError as exc:
            return _fail(f"simulation: {exc}", as_json, "simulation")
        except OSError as exc:
            from ._files import describe_os_error

            where = exc.filename if exc.filename is not None else "file system"
            return _fail(f"{where}: {describe_os_error(exc)}", as_json, str(where))
        except MemoryError:
            return _fail("input: too large to process in memory", as_json, "input")
        except KeyboardInterrupt:
            return _interrupted(as_json, sigint.seen)
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
            return _interrupted(as_json, sigint.seen) if sigint.seen and code == 130 else code
        except Exception as exc:  # click's usage errors (unknown option, missing argument) and Exit
            if hasattr(exc, "format_message") and hasattr(exc, "exit_code"):
                ctx = getattr(exc, "ctx", None)
                where = ctx.command_path if ctx is not None else "trikedyn"
                return _fail(f"{where}: {exc.format_message()}", as_json, where)
            if type(exc).__name__ == "Abort":
                typer.echo("trikedyn: aborted", err=True)
                return 130
            if hasattr(exc, "exit_code") and type(exc).__name__ == "Exit":
                return _interrupted(as_json, sigint.seen) if sigint.seen and int(exc.exit_code) == 130 \
                    else int(exc.exit_code)
            raise
    return result if isinstance(result, int) else 0


def _console():  # pragma: no cover - console-script shim
    code = main()
    # The command is done: its files are closed and its output is written. At exit the interpreter's last
    # garbage collection would walk every object the command loaded (numba, scipy, pandas, matplotlib: 0.1-0.15 s
    # each, 0.3 s after a threshold search); frozen, it skips them and the process ends that much sooner.
    gc.freeze()
    sys.exit(code)
