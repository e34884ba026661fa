"""Exceptions of trikedyn.

User mistakes (a bad file, field or value) raise a subclass of :class:`InputError`. Its message is one
line that names *what* is wrong and *where* (file, line, field); the CLI prints it and exits with code 2,
without a traceback. Any other exception is a bug and may show a traceback.
"""

from __future__ import annotations

__all__ = [
    "InputError",
    "close_match",
    "did_you_mean",
    "LogFormatError",
    "ParameterError",
    "RunIncomplete",
    "SimulationError",
    "TrikedynError",
]


class TrikedynError(Exception):
    """Base class of every error raised on purpose by trikedyn."""


class InputError(TrikedynError, ValueError):
    """A user's input is wrong: a file, a field or a value.

    Parameters
    ----------
    message : str
        What is wrong and what is expected, in one line.
    where : str, optional
        The file, line or field that is wrong; it prefixes the message as ``where: message``.
    """

    def __init__(self, message: str, where: str | None = None):
        self.where = where
        self.reason = message
        text = f"{where}: {message}" if where else message
        super().__init__(" ".join(text.split("\n")))


class ParameterError(InputError):
    """A parameter set or a parameter value is unknown, missing or out of range."""


class LogFormatError(InputError):
    """A measurement log cannot be read: format, encoding, columns, time or values."""


class SimulationError(TrikedynError):
    """A simulation stopped: NaN, runaway penetration, rollover or a step too large.

    Parameters
    ----------
    message : str
        The reason.
    time_s : float, optional
        Simulated time [s] at which the run stopped.
    """

    def __init__(self, message: str, time_s: float | None = None):
        self.time_s = time_s
        self.reason = message
        text = f"at t = {time_s:.4f} s: {message}" if time_s is not None else message
        super().__init__(text)


class RunIncomplete(TrikedynError):
    """A design's run lost its workers for good (they kept dying, or the Dask scheduler is gone): what
    finished is kept (logged) and the same command with ``--resume`` goes on. The CLI prints the message in
    one line and exits with code 1, as the study does when it loses its scheduler (not 2: the input was fine).
    """


def did_you_mean(name: str, choices, cutoff: float = 0.6) -> str:
    """``"; did you mean 'X'?"`` for the closest of ``choices`` to a mistyped ``name``, or ``""`` (for the end
    of an error message; :func:`difflib.get_close_matches` with ``cutoff``).

    Parameters
    ----------
    name : str
        What the user typed.
    choices : iterable
        The valid names (converted with ``str``).
    cutoff : float
        Similarity ratio a match must reach, 0 to 1, dimensionless.

    Returns
    -------
    str
        The hint, or an empty string when nothing is close enough.
    """
    hint = close_match(name, choices, cutoff)
    return f"; did you mean '{hint}'?" if hint is not None else ""


def close_match(name: str, choices, cutoff: float = 0.6) -> str | None:
    """The closest of ``choices`` to a mistyped ``name`` (:func:`difflib.get_close_matches`), or None: the one
    close-match search behind :func:`did_you_mean` and the messages that word their hint otherwise.

    Parameters
    ----------
    name : str
        What the user typed.
    choices : iterable
        The valid names (converted with ``str``).
    cutoff : float
        Similarity ratio a match must reach, 0 to 1, dimensionless.

    Returns
    -------
    str or None
        The closest name, or None when nothing is close enough.
    """
    from difflib import get_close_matches

    hint = get_close_matches(str(name), [str(c) for c in choices], n=1, cutoff=cutoff)
    return hint[0] if hint else None
