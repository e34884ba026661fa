"""What a tyre property file (``.tir``) gives once read: :class:`TyreProperties` (immutable, SI units: the
model family, the coefficients the Magic Formula evaluator reads, every section as read, the notes) and its bare
tables (:class:`TirTable`). Reading and checking a file: :mod:`trikedyn.tyre.tir`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

__all__ = ["MF52", "MF61", "MF62", "PAC2002", "RANGE_PAIRS", "TirTable", "TyreProperties"]


PAC2002, MF52, MF61, MF62 = "PAC2002", "MF5.2", "MF6.1", "MF6.2"  #: the model families a file can be for
RANGE_PAIRS = (("FZMIN", "FZMAX"), ("KPUMIN", "KPUMAX"), ("ALPMIN", "ALPMAX"), ("CAMMIN", "CAMMAX"))  #: keys of the validity ranges, low and high
@dataclass(frozen=True)
class TirTable:
    """A bare table of a ``.tir`` section: column names from its ``{...}`` header, rows of numbers."""

    columns: tuple[str, ...]
    rows: tuple[tuple[float, ...], ...]


@dataclass(frozen=True, eq=False)
class TyreProperties:
    """A tyre property file as read: immutable, SI units.

    Attributes
    ----------
    path : str
        The file read (or the name given to :func:`~trikedyn.tyre.tir.parse_tir`).
    family : str
        ``'PAC2002'``, ``'MF5.2'``, ``'MF6.1'`` or ``'MF6.2'``: the equations the file's coefficients are for.
    file_format : str
        ``PROPERTY_FILE_FORMAT`` as written (or ``FITTYP=n``).
    file_version : float or None
        ``FILE_VERSION`` of ``[MDI_HEADER]``.
    tyre_side : str
        ``'LEFT'``, ``'RIGHT'`` or ``'SYMMETRIC'``: the side the tyre was measured on.
    use_mode : int or None
        ``USE_MODE`` (recorded; the evaluator always gives combined slip, its sign does not mirror).
    units : Mapping[str, str]
        ``[UNITS]`` as written (lower case).
    coefficients : Mapping[str, float]
        Every value the evaluator reads, SI, defaults filled in.
    sections : Mapping[str, Mapping[str, float | str]]
        Every section's keys as read (dimensional ones converted to SI).
    tables : Mapping[str, TirTable]
        Bare tables by section (``SHAPE``).
    defaulted : tuple of str
        Evaluator keys the file lacks (their defaults are used).
    ignored_keys : tuple of str
        ``SECTION.KEY`` entries kept but not used by the evaluator.
    unknown_sections : tuple of str
        Sections this reader does not know (kept).
    encoding : str
        ``'utf-8'`` or ``'latin-1'``.
    notes : tuple of str
        Anything worth telling a user about how the file was read.
    """

    path: str
    family: str
    file_format: str
    file_version: float | None
    tyre_side: str
    use_mode: int | None
    units: Mapping[str, str]
    coefficients: Mapping[str, float]
    sections: Mapping[str, Mapping[str, float | str]]
    tables: Mapping[str, TirTable]
    defaulted: tuple[str, ...]
    ignored_keys: tuple[str, ...]
    unknown_sections: tuple[str, ...]
    encoding: str
    notes: tuple[str, ...]

    def __getitem__(self, key: str) -> float:
        return self.coefficients[key.upper()]

    @property
    def mf6(self) -> bool:
        """True for MF 6.1 / 6.2 files."""
        return self.family in (MF61, MF62)

    @property
    def fnomin(self) -> float:
        """Nominal load ``FNOMIN`` [N]."""
        return self.coefficients["FNOMIN"]

    @property
    def unloaded_radius(self) -> float:
        """Free tyre radius ``UNLOADED_RADIUS`` [m]."""
        return self.coefficients["UNLOADED_RADIUS"]

    @property
    def vertical_stiffness(self) -> float:
        """``VERTICAL_STIFFNESS`` [N/m] (0 when absent)."""
        return self.coefficients["VERTICAL_STIFFNESS"]

    @property
    def vertical_damping(self) -> float:
        """``VERTICAL_DAMPING`` [N s/m] (0 when absent)."""
        return self.coefficients["VERTICAL_DAMPING"]

    @property
    def dimensions(self) -> dict[str, float]:
        """``[DIMENSION]`` numbers as read (SI): unloaded radius, width, aspect ratio, rim radius and width."""
        return {k: v for k, v in self.sections.get("DIMENSION", {}).items() if isinstance(v, float)}

    @property
    def ranges(self) -> dict[str, tuple[float, float]]:
        """Validity ranges ``fz`` [N], ``kappa`` [1], ``alpha`` [rad], ``gamma`` [rad] (defaults if absent)."""
        c = self.coefficients
        names = ("fz", "kappa", "alpha", "gamma")
        return {n: (c[lo], c[hi]) for n, (lo, hi) in zip(names, RANGE_PAIRS, strict=True)}
