"""What the command modules share: option types, range checks, output (text or valid JSON), figures."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Annotated

import typer

from .._json import finite, json_default
from ..errors import InputError
from ._bounds import search_bound, variant_bound

__all__ = ["INTERRUPT_NOTES", "WARNINGS", "absolute_csv", "BandKmhOpt", "BandPercentOpt", "CriterionOpt", "DaskLocalOpt", "ForceOpt",
           "FreightAliasOpt", "JsonOpt", "ManoeuvreOpt", "OptionOpt", "PayloadOpt", "SpeedControlOpt", "VehicleArg", "choice", "emit",
           "finite", "json_default", "judging", "key_values", "manoeuvre_options", "on_interrupt", "payload_kg",
           "readable", "round_text", "save_figure", "SchedulerOpt", "WorkersOpt", "within"]


def within(low: float, high: float, unit: str = "", *, above: bool = False):
    """Typer callback: the option's value must be finite and within ``[low, high]`` (``(low, high]`` with
    ``above``); None passes (an option left out)."""

    def check(ctx: typer.Context, param: typer.CallbackParam, value):
        """Typer callback: ``value`` unchanged if finite and within the bounds (None passes), else
        :class:`InputError` naming the option."""
        if value is None or ctx.resilient_parsing:
            return value
        name = max(param.opts, key=len) if param.opts else param.name
        number = float(value)
        ok = math.isfinite(number) and (number > low if above else number >= low) and number <= high
        if not ok:
            bound = f"{'>' if above else '>='} {low:g} and <= {high:g}"
            raise InputError(f"must be {bound}{' ' + unit if unit else ''}, got {value!r}", where=name)
        return value

    return check


JsonOpt = Annotated[bool, typer.Option("--json", help="Print machine-readable JSON instead of text.")]
ForceOpt = Annotated[bool, typer.Option("--force", help="Replace output files that exist already.")]
VehicleArg = Annotated[str, typer.Argument(help="Preset name (see `trikedyn vehicle list`) or a .toml file.")]

# Where a study or a sampled design runs (trikedyn.study.engine.executors): at most one of the three; the
# command checks them with check_executor before anything is written.
WorkersOpt = Annotated[int | None, typer.Option("--workers", callback=within(0, 256), help="Processes on this machine (default: all cores; 0: in this process).")]
DaskLocalOpt = Annotated[int | None, typer.Option("--dask-local", callback=within(1, 256), help="Run on a local Dask cluster of N workers.")]
SchedulerOpt = Annotated[str | None, typer.Option("--scheduler", help="Dask scheduler address (tcp://host:port).")]

# One name per quantity: the paper's freight is ``--payload`` on every command. ``--freight``, its older name
# in ``modes`` and ``cg payload``, still works but is hidden from --help. A command that takes freight has
# both parameters, named so: ``payload: PayloadOpt = 0.0, freight: FreightAliasOpt = None``, and reads
# ``payload_kg(payload, freight)``; giving both options is a user error.
def _one_of(other: str):
    """Typer callback: the option's value in range (the variant's ``freight_kg``:
    :data:`~trikedyn.params.variant.VARIANT_OPTIONS`), and ``other`` not given as well."""
    check = variant_bound("freight_kg")

    def callback(ctx: typer.Context, param: typer.CallbackParam, value):
        """Typer callback: ``value`` checked as the variant's ``freight_kg`` [kg]; :class:`InputError` when this
        option and ``other`` are both given."""
        value = check(ctx, param, value)
        if ctx.resilient_parsing:
            return value
        given = [getattr(ctx.get_parameter_source(name), "name", None) in ("COMMANDLINE", "ENVIRONMENT")
                 for name in (param.name, other)]
        if all(given):
            raise InputError("give --payload or its old name --freight, not both", where="--freight")
        return value

    return callback


PayloadOpt = Annotated[
    float, typer.Option("--payload", callback=_one_of("freight"), help="The paper's freight aboard [kg].")
]
FreightAliasOpt = Annotated[
    float | None, typer.Option("--freight", hidden=True, callback=_one_of("payload"), help="Old name of --payload [kg].")
]


def payload_kg(payload: float, freight: float | None) -> float:
    """The freight [kg] given as ``--payload`` or as its hidden old name ``--freight``."""
    return payload if freight is None else freight


WARNINGS: list[str] = []
"""Warnings raised while a command runs (printed as one line each, and listed under ``warnings`` in JSON)."""

INTERRUPT_NOTES: list[str] = []
"""What a command keeps if it is interrupted from here on (:func:`on_interrupt`), said after ``trikedyn:
interrupted``."""


def on_interrupt(note: str) -> None:
    """Say ``note`` (what is kept, how to go on) if the command is interrupted (Ctrl-C) from now on."""
    INTERRUPT_NOTES.append(note)


def emit(data, as_json: bool, text=None) -> None:
    """Print a command's result: JSON (always valid: non-finite numbers become null, with a warning), or
    ``text`` (a string, or a function of nothing that makes it: text is only formatted when asked for)."""
    if as_json:
        clean, bad = finite(data)
        if isinstance(clean, dict) and (bad or WARNINGS):
            notes = [*WARNINGS, *(f"{p or 'value'}: non-finite number replaced by null" for p in bad)]
            clean = {**clean, "warnings": [*clean.get("warnings", []), *notes]}
        typer.echo(json.dumps(clean, indent=2, default=json_default, allow_nan=False))
    elif text is not None:
        typer.echo(round_text(text() if callable(text) else text))
    else:
        typer.echo(json.dumps(finite(data)[0], indent=2, default=json_default, allow_nan=False))


SIGNIFICANT = 4
"""Significant digits of a number in text output (an integer part is never cut; JSON keeps every digit)."""

_LONG_NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")


def readable(value, digits: int = SIGNIFICANT) -> str:
    """A number for reading: ``digits`` significant digits, trailing zeros dropped, the integer part kept
    (``2.657138346546658`` -> ``2.657``, ``10.450000000000001`` -> ``10.45``, ``80289.0`` -> ``80289``);
    scientific notation below 1e-3 and from 1e6. Anything that is not a float is ``str(value)``."""
    if hasattr(value, "item") and not isinstance(value, str):  # numpy scalars
        value = value.item()
    if not isinstance(value, float):
        return str(value)
    if not math.isfinite(value) or value == 0.0:
        return "0" if value == 0.0 else str(value)
    size = abs(value)
    if size < 1e-3 or size >= 1e6:
        mantissa, exponent = f"{value:.{digits - 1}e}".split("e")
        mantissa = mantissa.rstrip("0").rstrip(".") if "." in mantissa else mantissa
        return f"{mantissa}e{int(exponent)}"
    decimals = max(0, digits - 1 - math.floor(math.log10(size)))
    text = f"{value:.{decimals}f}"
    text = text.rstrip("0").rstrip(".") if "." in text else text
    return "0" if text in ("-0", "+0") else text


def _significant(number: str) -> int:
    mantissa = number.lstrip("+-").split("e")[0].split("E")[0]
    return len(mantissa.replace(".", "").lstrip("0"))


def round_text(text: str, longest: int = 7) -> str:
    """``text`` with every decimal number of more than ``longest`` significant digits (an unformatted float
    such as ``10.450000000000001``) rounded by :func:`readable`; numbers a command formatted are kept."""

    def shorten(match: re.Match) -> str:
        """The matched number as written if it has at most ``longest`` significant digits, else rounded by
        :func:`readable` (a leading ``+`` kept)."""
        number = match.group(0)
        if _significant(number) <= longest:
            return number
        shown = readable(float(number))
        return ("+" + shown) if number.startswith("+") and not shown.startswith("-") else shown

    return _LONG_NUMBER.sub(shorten, text)


def _shown(value) -> str:
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_shown(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_shown(v) for v in value) + "]"
    if hasattr(value, "tolist") and not isinstance(value, str):  # numpy arrays
        return _shown(value.tolist())
    return readable(value)


def key_values(data: dict, indent: str = "") -> list[str]:
    """A result as ``key  value`` lines for reading: numbers by :func:`readable`, a nested result (a dict)
    as its own block, indented under its key."""
    width = max((len(str(k)) for k in data), default=0) + 2
    lines = []
    for key, value in data.items():
        if isinstance(value, dict) and value:
            lines.append(f"{indent}{key}")
            lines += key_values(value, indent + "  ")
        else:
            lines.append(f"{indent}{str(key):<{width}}{_shown(value)}")
    return lines


OptionOpt = Annotated[
    list[str], typer.Option("--option", "-o", help="A manoeuvre option KEY=VALUE (see `trikedyn manoeuvres`); repeatable.")
]


def absolute_csv(value):
    """Typer callback: a path ``.csv`` given to ``--manoeuvre`` made absolute (against the working directory
    where the command was typed), so that a worker process or a Dask worker on another machine, whose working
    directory differs, opens the same file; a registered name, or a list of them, passes unchanged. Links are
    kept (not resolved), so the checks that no output overwrites an input still see them."""
    import os

    if isinstance(value, list):
        return [absolute_csv(item) for item in value]
    if isinstance(value, str) and value.lower().endswith(".csv"):
        return os.path.abspath(value)
    return value


ManoeuvreOpt = Annotated[
    str, typer.Option("--manoeuvre", callback=absolute_csv, help="A registered manoeuvre (see `trikedyn manoeuvres`: "
                      "dlc, slc, circle, step, fishhook, ...) or a path .csv file.")
]


def choice(*allowed: str):
    """Typer callback: the option's value must be one of ``allowed`` (a close match is suggested)."""

    def check(ctx: typer.Context, param: typer.CallbackParam, value):
        """Typer callback: ``value`` unchanged if it is one of ``allowed`` (or None), else :class:`InputError`
        suggesting a close match."""
        if value is None or ctx.resilient_parsing or value in allowed:
            return value
        from ..errors import did_you_mean

        name = max(param.opts, key=len) if param.opts else param.name
        raise InputError(f"expected one of {', '.join(allowed)}, got {value!r}" + did_you_mean(str(value), allowed),
                         where=name)

    return check


# the search settings' options: their words and bounds are trikedyn.analysis.search_settings' (one set for the
# command line and the specs)
CriterionOpt = Annotated[str, typer.Option(
    "--criterion", callback=search_bound("criterion"),
    help="What a run must do to pass: course (ISO 3888-1 validity: every wheel down, no cone struck, path kept, "
         "speed held; the default), lift-off (the paper's: no wheel lifts) or both (each threshold).")]
SpeedControlOpt = Annotated[str, typer.Option(
    "--speed-control", callback=search_bound("speed_control"),
    help="driver: the vehicle's own drive and brakes hold the speed, within their limits (a search stops at the "
         "top speed); ideal: unlimited drive and brakes, the speed imposed as a multibody package's kinematic "
         "drive would.")]
BandPercentOpt = Annotated[float, typer.Option(
    "--speed-band-percent", callback=search_bound("speed_band_percent"),
    help="Half-width of the band the speed must stay in through the judged window [% of the target].")]
BandKmhOpt = Annotated[float, typer.Option(
    "--speed-band-kmh", callback=search_bound("speed_band_kmh"),
    help="Smallest half-width of the speed band [km/h]; the band is the larger of the two.")]


def judging(band_percent: float, band_kmh: float):
    """The :class:`~trikedyn.analysis.verdict.Judging` of the speed-band options."""
    from ..analysis.verdict import Judging

    try:
        return Judging(speed_band_percent=band_percent, speed_band_kmh=band_kmh)
    except InputError as exc:
        raise InputError(exc.reason, where="--speed-band-kmh") from None


def manoeuvre_options(manoeuvre: str, pairs: list[str], **legacy) -> dict:
    """``-o KEY=VALUE`` pairs, plus the older shortcuts (``--radius``, ``--steer-deg``) where the manoeuvre
    takes that option."""
    from ..manoeuvres.registry import get, parse_options

    options = parse_options(pairs)
    if manoeuvre.lower().endswith(".csv"):
        return options
    try:
        kind = get(manoeuvre)
    except InputError as exc:
        raise InputError(exc.reason, where="--manoeuvre") from None
    for key, value in legacy.items():
        if value is not None and key not in options and any(o.name == key for o in kind.options):
            options[key] = value
    return options


def save_figure(fig, path: Path, dpi: int = 110) -> None:
    """Save a matplotlib figure atomically and close it (:func:`trikedyn.report.figures.save`)."""
    from ..report.figures import save

    save(fig, path, dpi=dpi)
