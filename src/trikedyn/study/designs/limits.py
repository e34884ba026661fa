"""What limits a threshold, counted over a sampled design's samples (:mod:`trikedyn.analysis.threshold` names
each sample's limit: what failed one resolution above its threshold), and said in words for a summary."""

from __future__ import annotations

__all__ = ["LIMITS", "limit_counts", "limits_line", "regimes"]


LIMITS = ("lift-off", "tracking", "cone strike", "path lost", "spin", "speed not held", "top speed")
"""What can limit a threshold (:mod:`trikedyn.analysis.threshold`), in the order the counts are listed."""

_LIMIT_WORDS = {"lift-off": "a wheel lifted first", "tracking": "the driver lost the path before a wheel lifted",
                "cone strike": "a cone was struck first", "path lost": "the driver lost the path first",
                "spin": "the vehicle spun first", "speed not held": "the speed could not be held",
                "top speed": "it passed at its top speed"}


def limit_counts(limits) -> dict[str, int]:
    """Samples per limit, for every limit that occurs (``{"lift-off": n, "cone strike": m}``; samples without a
    threshold or without a limit left out); ``lift-off`` and ``tracking`` always listed.

    Parameters
    ----------
    limits : iterable of str
        Each sample's limit (empty or None for none).

    Returns
    -------
    dict of str to int
        Limit -> samples.
    """
    found = [str(limit) for limit in limits if limit]
    names = [*LIMITS[:2], *(n for n in LIMITS[2:] if n in found), *sorted(set(found) - set(LIMITS))]
    return {name: found.count(name) for name in names}


def regimes(limits) -> dict[str, int]:
    """The limits that occur with their counts, when there are two or more (else empty).

    Parameters
    ----------
    limits : iterable of str
        Each sample's limit (empty or None for none).

    Returns
    -------
    dict of str to int
        Limit -> samples, empty for fewer than two limits.
    """
    count = {k: v for k, v in limit_counts(limits).items() if v}
    return count if len(count) > 1 else {}


def limits_line(limits, consequence: str = "") -> str | None:
    """The samples' limits in words for a text summary (``consequence`` appended), or None when every sample with
    a threshold had the same one (nothing to say).

    Parameters
    ----------
    limits : iterable of str
        Each sample's limit (empty or None for none).
    consequence : str
        Appended to the line.

    Returns
    -------
    str or None
        The line.
    """
    count = regimes(limits)
    if not count:
        return None
    parts = ", ".join(f"{n} {name} ({_LIMIT_WORDS.get(name, name)})" for name, n in count.items())
    word = "two" if len(count) == 2 else str(len(count))
    return f"limits: {parts}: {word} regimes{consequence}"
