"""Options with units and bounds: what an entry of a registry takes (a manoeuvre's ``run_in_m``, a study
metric's ``speed_kmh``) and what the named values that travel are made of (the search settings, a vehicle
variant). An option is stated once, with its default, unit, bounds and choices; :meth:`Option.parse` checks a
value against it, :func:`checked` does so naming the setting, :func:`find_option` finds one by name with a
close match in its error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from .errors import InputError, did_you_mean

__all__ = ["Option", "checked", "find_option"]


@dataclass(frozen=True)
class Option:
    """One option of a registered entry (a manoeuvre, a study metric): stated once, with its unit and bounds.

    Parameters
    ----------
    name : str
        The option's name, its unit in it where it has one (``run_in_m``).
    default : float or str or None
        The value when not given; None: the option is required. Its type is the option's kind (a number or
        a word) unless ``kind`` says otherwise.
    unit : str
        The unit [``m``, ``km/h``, ...], ``""`` for none.
    help : str
        What it means, one line.
    choices : tuple of str
        The words allowed (a word option), empty for any.
    minimum, maximum : float, optional
        Bounds of a number option, inclusive [in ``unit``].
    kind : type, optional
        ``float`` or ``str``; by default the type of ``default`` (``float`` when there is none).
    """

    name: str
    default: float | str | None = None
    unit: str = ""
    help: str = ""
    choices: tuple[str, ...] = ()
    minimum: float | None = None
    maximum: float | None = None
    kind: type | None = None

    @property
    def is_word(self) -> bool:
        """Whether the option takes a word (``str``) rather than a number."""
        return (self.kind or (str if isinstance(self.default, str) else float)) is str

    @property
    def required(self) -> bool:
        """Whether the option has no default."""
        return self.default is None

    def parse(self, value: Any, where: str, *, text: bool = True) -> float | str:
        """``value`` checked and converted: a finite number within the bounds, or one of the choices.

        Parameters
        ----------
        value : Any
            The value given (a number, or text from the command line).
        where : str
            What the error names (``dlc.run_in_m``).
        text : bool
            Whether a number may come as text (``"15"``, the command line); False for typed files (TOML).

        Returns
        -------
        float or str

        Raises
        ------
        InputError
            A value that is not a number (word) of the option's kind, not finite, or out of its bounds.
        """
        if self.is_word:
            if not isinstance(value, str) and not text:
                raise InputError(f"expected a word, got {value!r}", where=where)
            word = str(value)
            if self.choices and word not in self.choices:
                raise InputError(f"expected one of {', '.join(self.choices)}, got {word!r}"
                                 + did_you_mean(word, self.choices), where=where)
            return word
        if isinstance(value, bool) or (not text and not isinstance(value, int | float)):
            raise InputError(f"expected a number, got {value!r}", where=where)
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise InputError(f"expected a number, got {value!r}", where=where) from None
        if not math.isfinite(number):
            raise InputError(f"expected a finite number, got {value!r}", where=where)
        low = -math.inf if self.minimum is None else self.minimum
        high = math.inf if self.maximum is None else self.maximum
        if not low <= number <= high:
            unit = f" {self.unit}" if self.unit else ""
            bound = (f"within [{low:g}, {high:g}]{unit}" if math.isfinite(low) and math.isfinite(high)
                     else f">= {low:g}{unit}" if math.isfinite(low) else f"<= {high:g}{unit}")
            raise InputError(f"option '{self.name}' must be {bound}, got {number:g}", where=where)
        return number

    def to_dict(self) -> dict:
        """The option as JSON-safe data (``trikedyn manoeuvres --json``).

        Returns
        -------
        dict
            Name, default, unit, help, and choices and bounds where it has them.
        """
        out = {"name": self.name, "default": self.default, "unit": self.unit, "help": self.help}
        if self.choices:
            out["choices"] = list(self.choices)
        if self.minimum is not None:
            out["minimum"] = self.minimum
        if self.maximum is not None:
            out["maximum"] = self.maximum
        return out


def checked(opt: Option, value: Any) -> float | str:
    """``value`` parsed by ``opt`` as a typed file gives it (a number as a number), the error naming the setting.

    Parameters
    ----------
    opt : Option
        The setting.
    value : Any
        The value given.

    Returns
    -------
    float or str
        The value, checked.

    Raises
    ------
    InputError
        ``where`` the setting's name: ``high_kmh: must be within [1, 400] km/h, got 500``.
    """
    try:
        return opt.parse(value, where=opt.name, text=False)
    except InputError as exc:
        raise InputError(exc.reason.replace(f"option '{opt.name}' ", "", 1), where=opt.name) from None


def find_option(options, name: str, owner: str, where: str) -> Option:
    """The option ``name`` of ``options``; an :class:`InputError` naming ``owner`` with a close match.

    Parameters
    ----------
    options : iterable of Option
    name : str
    owner : str
        What has the options, for the message (``manoeuvre 'dlc'``).
    where : str
        The error's ``where``.

    Returns
    -------
    Option
        The option.
    """
    options = tuple(options)
    for opt in options:
        if opt.name == name:
            return opt
    names = [o.name for o in options]
    tip = did_you_mean(name, names) or (f"; it takes {', '.join(names)}" if names else "; it takes no options")
    raise InputError(f"{owner} has no option '{name}'{tip}", where=where)
