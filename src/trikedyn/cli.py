"""The ``trikedyn`` command: a thin command map over the Python API.

Every command has ``--help`` and ``--json``. A user's mistake (file, field, value) prints one line,
``trikedyn: error: WHERE: WHAT``, and exits with code 2; nothing else is printed.
"""

from __future__ import annotations

import json
import sys
from typing import Annotated

import typer

from . import __version__
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
from .commands._common import WARNINGS, emit  # noqa: E402

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


def _show_warning(message, category, filename, lineno, file=None, line=None):  # noqa: ARG001
    text = " ".join(str(message).split())
    WARNINGS.append(text)
    typer.echo(f"trikedyn: warning: {category.__name__}: {text}", err=True)


def main(argv: list[str] | None = None) -> int:
    """Entry point: the one error boundary of the command line.

    A user's mistake or environment (a bad file, field or value; a file that cannot be written; a
    simulation that cannot start or that fails) prints one line ``trikedyn: error: WHERE: WHAT`` on stderr
    and exits with code 2; with ``--json`` the same error is also a JSON object ``{"error", "where"}`` on
    stdout. Warnings print as one line each. A genuine bug keeps its traceback (exit code 1).
    """
    import warnings

    args = list(sys.argv[1:] if argv is None else argv)
    as_json = "--json" in args
    WARNINGS.clear()
    from .errors import SimulationError

    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = _show_warning
        try:
            result = app(args=args, prog_name="trikedyn", standalone_mode=False)
        except InputError as exc:
            return _fail(str(exc), as_json, exc.where)
        except SimulationError as exc:
            return _fail(f"simulation: {exc}", as_json, "simulation")
        except OSError as exc:
            from ._files import describe_os_error

            where = exc.filename if exc.filename is not None else "file system"
            return _fail(f"{where}: {describe_os_error(exc)}", as_json, str(where))
        except MemoryError:
            return _fail("input: too large to process in memory", as_json, "input")
        except KeyboardInterrupt:
            typer.echo("trikedyn: interrupted", err=True)
            return 130
        except SystemExit as exc:
            return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except Exception as exc:  # click's usage errors (unknown option, missing argument) and Exit
            if hasattr(exc, "format_message") and hasattr(exc, "exit_code"):
                ctx = getattr(exc, "ctx", None)
                where = ctx.command_path if ctx is not None else "trikedyn"
                return _fail(f"{where}: {exc.format_message()}", as_json, where)
            if type(exc).__name__ == "Abort":
                typer.echo("trikedyn: aborted", err=True)
                return 130
            if hasattr(exc, "exit_code") and type(exc).__name__ == "Exit":
                return int(exc.exit_code)
            raise
    return result if isinstance(result, int) else 0


def _console():  # pragma: no cover - console-script shim
    sys.exit(main())
