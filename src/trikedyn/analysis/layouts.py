"""Delta against tadpole on one vehicle: static tip-over, tilt-table angle and threshold velocities.

:func:`compare_layouts` takes a vehicle of either layout, builds its mirror
(:func:`trikedyn.params.layouts.mirror_layout`: the wheel pair at the other end, on the same mass, CG height,
wheelbase and track) and puts the two side by side. What the mirror keeps of the CG's place is ``keep``:

* ``"pair-distance"`` (the default, :data:`~trikedyn.params.layouts.DEFAULT_KEEP`): the CG at the same
  distance from the two-wheel axle (the body mirrored end for end with the wheels). The static load split
  and the rigid tip-over are then the same by construction, and what differs is the layout's own: the
  compliant tilt angle, the dynamics, the threshold velocities. This compares the layouts.
* ``"cg"``: the CG where it is on the vehicle (the same x ahead of the rear axle); only the wheels move. A CG
  near one layout's pair is near the other's single wheel, so this compares two CG positions as much as two
  layouts: whichever layout has the CG nearer its single wheel loses.
* ``"both"``: the vehicle and both mirrors.

Reported per vehicle:

* ``static_tip_over_g``: the rigid vehicle's lowest lateral tip-over threshold over the edges of its support
  triangle, ``a_y / g`` (:func:`trikedyn.params.audit.tip_over_thresholds`; ``a T / (2 h L)`` for a centred
  CG at ``a`` from the single wheel's axle, ``h`` high, wheelbase ``L``, track ``T``);
* ``cg_from_single_m``, ``cg_from_pair_m``, ``single_wheel_load_fraction``: where the CG is (``a`` and
  ``L - a`` [m]) and the share of the weight on the single wheel (``1 - a / L``);
* ``tilt_angle_deg``: the tilt-table angle of the compliant model at which the first wheel lifts
  (:func:`trikedyn.analysis.tilt.tilt_table`, the lower side);
* ``threshold_speed_kmh``: per manoeuvre, the threshold velocity of
  :func:`trikedyn.analysis.threshold.threshold_velocity` (None when even the lowest speed fails).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import InputError
from ..params.io import ParameterSet
from ..params.layouts import DEFAULT_KEEP, KEEPS, check_keep
from ..params.schema import VehicleParameters
from .search_settings import SEARCH_DEFAULTS as _D
from .search_settings import SearchSettings

__all__ = ["KEEP_WORDS", "LayoutComparison", "LayoutRow", "compare_layouts", "static_tip_over_g"]

KEEP_WORDS = {
    "pair-distance": "the CG at the same distance from the two-wheel axle (same load split and rigid tip-over: "
                     "the layouts compared)",
    "cg": "the CG where it is on the vehicle (same x ahead of the rear axle: the layouts and two CG places "
          "compared)",
}
"""What each ``keep`` means, in the words of the text output."""


def static_tip_over_g(params: VehicleParameters) -> tuple[float, str]:
    """The rigid vehicle's lowest lateral tip-over threshold ``a_y / g`` [1] and the edge it tips about.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.

    Returns
    -------
    threshold_g : float
        ``a_y / g``, dimensionless.
    edge : str
        The tip edge.
    """
    from ..params.audit import tip_over_thresholds

    lateral = [e for e in tip_over_thresholds(params) if e["lateral"]]
    edge = min(lateral, key=lambda e: e["acceleration_g"])
    return float(edge["acceleration_g"]), edge["edge"]


def _cg_place(params: VehicleParameters) -> tuple[float, float, float]:
    """CG x ahead of the rear axle [m] (payload included), its distance from the single wheel's axle and from
    the pair's [m]."""
    from ..params.ops import mass_properties

    x = float(mass_properties(params).cg_m[0])
    length = params.wheelbase_m
    single = length - x if params.layout == "delta" else x
    return x, single, length - single


@dataclass(frozen=True)
class LayoutRow:
    """One vehicle's results.

    Attributes
    ----------
    layout, name : str
        ``delta`` or ``tadpole``; the vehicle's name.
    static_tip_over_g : float
        Lowest rigid lateral tip-over threshold [g], about ``tip_over_edge``.
    tilt_angle_deg, rigid_tilt_angle_deg : float or None
        Tilt-table angle of the compliant model and of the rigid vehicle [deg] (None: not computed).
    threshold_speed_kmh : dict
        Manoeuvre -> threshold velocity [km/h] (None: fails at the lowest speed searched).
    threshold_detail : dict
        Manoeuvre -> what limits it (the first failing run), in words.
    threshold_limit : dict
        Manoeuvre -> the limit's name (``"lift-off"``, ``"cone strike"``, ``"top speed"``, ...; None: none
        found in the range).
    keep : str or None
        None for the vehicle as given; for a mirror, what it keeps of the CG's place (``"pair-distance"``,
        ``"cg"``).
    cg_x_m, cg_from_single_m, cg_from_pair_m : float
        CG ahead of the rear axle, and its distance along x from the single wheel's axle (``a``) and from the
        pair's (``L - a``) [m], payload included.
    single_wheel_load_fraction : float
        Share of the static weight on the single wheel, ``1 - a / L`` [1].
    """

    layout: str
    name: str
    static_tip_over_g: float
    tip_over_edge: str
    tilt_angle_deg: float | None
    rigid_tilt_angle_deg: float | None
    threshold_speed_kmh: dict = field(default_factory=dict)
    threshold_detail: dict = field(default_factory=dict)
    threshold_limit: dict = field(default_factory=dict)
    keep: str | None = None
    cg_x_m: float = math.nan
    cg_from_single_m: float = math.nan
    cg_from_pair_m: float = math.nan
    single_wheel_load_fraction: float = math.nan

    @property
    def label(self) -> str:
        """How the table and the figure name this vehicle: ``delta``, ``tadpole mirror (CG kept)`` ..."""
        if self.keep is None:
            return self.layout
        return f"{self.layout} mirror ({'CG kept' if self.keep == 'cg' else 'pair distance kept'})"

    def to_dict(self) -> dict:
        """The row as plain JSON types (floats in the units of the attributes).

        Returns
        -------
        dict
            The row, JSON-safe.
        """
        return {
            "layout": self.layout, "name": self.name, "keep": self.keep, "label": self.label,
            "cg_x_m": self.cg_x_m, "cg_from_single_m": self.cg_from_single_m, "cg_from_pair_m": self.cg_from_pair_m,
            "single_wheel_load_fraction": self.single_wheel_load_fraction,
            "static_tip_over_g": self.static_tip_over_g, "tip_over_edge": self.tip_over_edge,
            "tilt_angle_deg": self.tilt_angle_deg, "rigid_tilt_angle_deg": self.rigid_tilt_angle_deg,
            "threshold_speed_kmh": dict(self.threshold_speed_kmh), "threshold_detail": dict(self.threshold_detail),
            "threshold_limit": dict(self.threshold_limit),
        }


@dataclass(frozen=True)
class LayoutComparison:
    """A vehicle and its mirror layout(s) side by side (the given vehicle first).

    Attributes
    ----------
    rows : tuple of LayoutRow
        The vehicle as given, then one row per mirror (``keep`` order: as asked; ``"both"``: pair-distance,
        then cg).
    manoeuvres : tuple of str
    keep : str
        What the mirror keeps: ``"pair-distance"``, ``"cg"`` or ``"both"``.
    mass_kg, cg_height_m, wheelbase_m, track_m : float
        What every row shares: mass [kg], CG height [m], wheelbase [m] and track [m].
    cg_x_fraction : float
        The given vehicle's CG x as a fraction of the wheelbase from the rear axle [1] (each row's CG:
        :attr:`LayoutRow.cg_x_m`).
    mirrors : dict
        ``keep`` -> the mirror vehicle (VehicleParameters).
    """

    rows: tuple[LayoutRow, ...]
    manoeuvres: tuple[str, ...]
    mass_kg: float
    cg_height_m: float
    cg_x_fraction: float
    wheelbase_m: float
    track_m: float
    keep: str = DEFAULT_KEEP
    mirrors: dict = field(default_factory=dict)

    @property
    def mirror(self) -> VehicleParameters | None:
        """The (first) mirror vehicle."""
        return next(iter(self.mirrors.values()), None)

    def to_dict(self) -> dict:
        """The comparison as plain JSON types: ``keep``, ``keep_means``, ``layouts`` (the rows), ``manoeuvres``
        and ``shared``.

        Returns
        -------
        dict
            The comparison, JSON-safe.
        """
        keeps = KEEPS if self.keep == "both" else (self.keep,)
        return {
            "keep": self.keep, "keep_means": {k: KEEP_WORDS[k] for k in keeps},
            "layouts": [r.to_dict() for r in self.rows], "manoeuvres": list(self.manoeuvres),
            "shared": {"mass_kg": self.mass_kg, "cg_height_m": self.cg_height_m, "wheelbase_m": self.wheelbase_m,
                       "track_m": self.track_m},
        }

    def table(self) -> str:
        """The comparison as a text table, with what the mirror keeps and the default said.

        Returns
        -------
        str
            The table.
        """
        def num(value, fmt):
            """A number for the table, ``-`` when there is none."""
            return "-" if value is None or not math.isfinite(value) else format(value, fmt)

        head = ["", *(f"{r.label} ({r.name})" if r.keep is None else r.label for r in self.rows)]
        body = [
            ["CG from the single wheel's axle, a [m]", *(num(r.cg_from_single_m, ".3f") for r in self.rows)],
            ["weight on the single wheel [%]", *(num(100 * r.single_wheel_load_fraction, ".1f") for r in self.rows)],
            ["static tip-over (rigid) [g]", *(num(r.static_tip_over_g, ".3f") for r in self.rows)],
            ["tilt-table angle [deg]", *(num(r.tilt_angle_deg, ".1f") for r in self.rows)],
            ["  rigid [deg]", *(num(r.rigid_tilt_angle_deg, ".1f") for r in self.rows)],
            *([f"threshold {m} [km/h]", *(_with_limit(num(r.threshold_speed_kmh.get(m), ".1f"),
                                                        r.threshold_limit.get(m)) for r in self.rows)]
              for m in self.manoeuvres),
        ]
        widths = [max(len(row[i]) for row in (head, *body)) for i in range(len(head))]
        lines = ["  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(row, widths,
                                                                                              strict=True)))
                 for row in (head, *body)]
        shared = (f"shared: {self.mass_kg:.1f} kg, CG {self.cg_height_m:.3f} m high, wheelbase {self.wheelbase_m:.3f} m, "
                  f"track {self.track_m:.3f} m")
        keeps = KEEPS if self.keep == "both" else (self.keep,)
        said = [f"mirror ({'default' if k == DEFAULT_KEEP else '--keep ' + k}): {KEEP_WORDS[k]}" for k in keeps]
        return "\n".join([shared, *said, *lines])

    def plot(self):
        """Bar charts: static tip-over [g], tilt angle [deg] and threshold velocities [km/h] per vehicle.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 2 + bool(self.manoeuvres), figsize=(11 + 1.5 * (len(self.rows) - 2), 3.8))
        labels = [r.layout if r.keep is None else f"{r.layout}\n({'CG kept' if r.keep == 'cg' else 'pair distance'})"
                  for r in self.rows]
        axes[0].bar(labels, [r.static_tip_over_g for r in self.rows], color="0.5")
        axes[0].set_ylabel("rigid static tip-over a_y/g [1]")
        axes[1].bar(labels, [r.tilt_angle_deg or 0.0 for r in self.rows], color="0.5")
        axes[1].set_ylabel("tilt-table angle [deg]")
        for ax in axes[:2]:
            ax.tick_params(axis="x", labelsize="small")
        if self.manoeuvres:
            width = 0.8 / len(self.rows)
            for k, r in enumerate(self.rows):
                xs = [i + (k - (len(self.rows) - 1) / 2) * width for i in range(len(self.manoeuvres))]
                axes[2].bar(xs, [r.threshold_speed_kmh.get(m) or 0.0 for m in self.manoeuvres], width, label=r.label)
            axes[2].set_xticks(range(len(self.manoeuvres)), list(self.manoeuvres))
            axes[2].set_ylabel("threshold velocity [km/h]")
            top = max((v for r in self.rows for v in r.threshold_speed_kmh.values() if v), default=1.0)
            axes[2].set_ylim(0.0, 1.35 * top)  # room for the legend above the bars
            axes[2].legend(fontsize="small", loc="upper center", ncol=1)
        for ax in axes:
            ax.grid(axis="y", alpha=0.3)
        kept = {"pair-distance": "the mirror's CG at the same distance from its two-wheel axle",
                "cg": "the mirror's CG where it is on the vehicle",
                "both": "mirrors with the CG at the same distance from the two-wheel axle and where it is"}[self.keep]
        fig.suptitle(f"{self.rows[0].name}: delta and tadpole on the same mass, wheelbase and track;\n{kept}")
        fig.tight_layout()
        return fig


def _with_limit(value: str, limit: str | None) -> str:
    """A threshold in the table with what limits it: ``41.1 (cone strike)``."""
    return value if limit is None or value == "-" else f"{value} ({limit})"


def _row(pset: ParameterSet, manoeuvres, options, tilt: bool, search: dict, keep: str | None) -> LayoutRow:
    from .threshold import threshold_velocity
    from .tilt import tilt_table

    params = pset.params
    tip_g, edge = static_tip_over_g(params)
    x, single, pair = _cg_place(params)
    tilt_deg = rigid_deg = None
    if tilt:
        result = tilt_table(pset)
        tilt_deg, rigid_deg = result.tilt_angle_deg, result.rigid_tilt_angle_deg
    speeds, details, limits = {}, {}, {}
    for m in manoeuvres:
        found = threshold_velocity(pset, m, options=options.get(m), **search)
        speeds[m], details[m], limits[m] = found.threshold_speed_kmh, found.detail, found.limit
    return LayoutRow(params.layout, params.name, tip_g, edge, tilt_deg, rigid_deg, speeds, details, limits,
                     keep=keep, cg_x_m=x, cg_from_single_m=single, cg_from_pair_m=pair,
                     single_wheel_load_fraction=1.0 - single / params.wheelbase_m)


def compare_layouts(vehicle: ParameterSet | VehicleParameters, manoeuvres=("dlc", "slc"), *,
                    keep: str = DEFAULT_KEEP, options: dict | None = None, tilt: bool = True,
                    low_kmh: float = _D["low_kmh"], high_kmh: float = _D["high_kmh"], step_kmh: float = _D["step_kmh"],
                    resolution_kmh: float = _D["resolution_kmh"], criterion: str = _D["criterion"],
                    speed_control: str = _D["speed_control"]) -> LayoutComparison:
    """A vehicle and its mirror layout(s) side by side (see the module docstring).

    Parameters
    ----------
    vehicle : ParameterSet or VehicleParameters
        The vehicle, payload included; either layout.
    manoeuvres : sequence of str
        Registered manoeuvres (or path ``.csv`` files) for the threshold velocity; may be empty.
    keep : {"pair-distance", "cg", "both"}
        What the mirror keeps of the CG's place: its distance from the two-wheel axle (the default: the
        layouts compared on the same load split and rigid tip-over), its place on the vehicle (the same x
        ahead of the rear axle), or both mirrors.
    options : dict, optional
        Manoeuvre -> its options.
    tilt : bool
        Run the tilt-table test (about 0.3 s per vehicle once compiled).
    low_kmh, high_kmh, step_kmh, resolution_kmh : float
        The threshold search [km/h] (:func:`trikedyn.analysis.threshold.threshold_velocity`), defaults and
        bounds those of :class:`~trikedyn.analysis.search_settings.SearchSettings`.
    criterion, speed_control : str
        The search's pass rule (``"course"``, ``"lift-off"``, ``"both"``) and speed control (``"driver"``,
        ``"ideal"``).

    Returns
    -------
    LayoutComparison

    Raises
    ------
    ParameterError
        When a mirror is not a valid vehicle.
    InputError
        For an unknown ``keep`` or manoeuvre, or a bad search range.
    """
    from ..params.layouts import mirror_layout
    from ..params.ops import mass_properties

    check_keep(keep, allow_both=True)
    if isinstance(vehicle, VehicleParameters):
        vehicle = ParameterSet(vehicle, {}, vehicle.name)
    if not isinstance(vehicle, ParameterSet):
        raise InputError(f"expected a ParameterSet or VehicleParameters, got {type(vehicle).__name__}",
                         where="vehicle")
    manoeuvres = tuple(str(m) for m in manoeuvres)
    keeps = KEEPS if keep == "both" else (keep,)
    mirrors = {k: mirror_layout(vehicle, k) for k in keeps}
    sets = [(vehicle, None), *((ParameterSet(m, {}, f"mirror of {vehicle.origin or vehicle.name}"), k)
                               for k, m in mirrors.items())]
    search = SearchSettings(low_kmh=low_kmh, high_kmh=high_kmh, step_kmh=step_kmh, resolution_kmh=resolution_kmh,
                            criterion=criterion, speed_control=speed_control).threshold_kwargs()
    options = options or {}
    rows = tuple(_row(p, manoeuvres, options, tilt, search, k) for p, k in sets)
    mp = mass_properties(vehicle.params)
    base = vehicle.params
    return LayoutComparison(
        rows=rows, manoeuvres=manoeuvres, mass_kg=float(mp.mass_kg), cg_height_m=float(mp.cg_m[2]),
        cg_x_fraction=float(mp.cg_m[0]) / base.wheelbase_m, wheelbase_m=base.wheelbase_m, track_m=base.track_m,
        keep=keep, mirrors=mirrors,
    )
