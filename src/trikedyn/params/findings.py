"""An audit finding (:func:`trikedyn.params.audit.audit`) and its levels."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

__all__ = ["INCONSISTENT", "NOTE", "OK", "WARNING", "Finding"]

OK, NOTE, WARNING, INCONSISTENT = "ok", "note", "warning", "inconsistent"


@dataclass(frozen=True)
class Finding:
    """One audit finding: its level, topic, a one-line message and the numbers behind it."""

    level: str
    topic: str
    message: str
    values: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The finding as a plain dict (JSON-ready once its numbers are finite).

        Returns
        -------
        dict
            The fields.
        """
        return asdict(self)
