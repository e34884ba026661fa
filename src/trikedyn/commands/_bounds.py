"""Command-line options whose defaults and bounds come from the values that travel: the threshold search's
settings (:class:`~trikedyn.analysis.search_settings.SearchSettings`) and the vehicle variant
(:class:`~trikedyn.params.variant.Variant`). Each option is checked by its :class:`~trikedyn.options.Option`,
so ``--high 500`` is refused with the same bounds as ``high_kmh = 500`` in a study or optimise spec."""

from __future__ import annotations

import typer

from ..analysis.search_settings import SEARCH_DEFAULTS  # light: no model, no numpy
from ..errors import InputError

__all__ = ["SEARCH_DEFAULTS", "search_bound", "variant_bound"]


def _search_table():
    from ..analysis.search_settings import search_options

    return search_options()


def _variant_table():  # the params package is heavy: read when an option is checked, not at import
    from ..params.variant import VARIANT_OPTIONS

    return VARIANT_OPTIONS


def _bound(table, name: str):
    def check(ctx: typer.Context, param: typer.CallbackParam, value):
        """Typer callback: ``value`` parsed and checked by the option ``name`` of ``table()``; None and the
        option's own default pass unchecked."""
        if value is None or ctx.resilient_parsing:
            return value
        source = ctx.get_parameter_source(param.name) if param.name else None
        if getattr(source, "name", None) == "DEFAULT":  # the default is the option's own: nothing to check
            return value
        where = max(param.opts, key=len) if param.opts else param.name
        opt = next(o for o in table() if o.name == name)
        try:
            return opt.parse(value, where=where)
        except InputError as exc:
            raise InputError(exc.reason.replace(f"option '{name}' ", "", 1), where=where) from None

    return check


def search_bound(name: str):
    """Typer callback: the option's value checked as the search setting ``name`` (bounds, choices).

    Parameters
    ----------
    name : str
        A setting of :func:`~trikedyn.analysis.search_settings.search_options` (``high_kmh``, ...).

    Returns
    -------
    callable
        The callback; None passes (an option left out).
    """
    return _bound(_search_table, name)


def variant_bound(name: str):
    """Typer callback: the option's value checked as the variant's number ``name`` (bounds).

    Parameters
    ----------
    name : str
        ``stiffness_scale``, ``damping_scale`` or ``freight_kg``.

    Returns
    -------
    callable
        The callback; None passes (an option left out).
    """
    return _bound(_variant_table, name)
