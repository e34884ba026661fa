"""Delta against tadpole on one vehicle: static tip-over, tilt-table angle and threshold velocities.

:func:`compare_layouts` takes a vehicle of either layout, builds its mirror
(:func:`trikedyn.params.layouts.mirror_layout`: the wheel pair at the other end, on the same mass, CG,
wheelbase and track) and puts the two side by side:

* ``static_tip_over_g``: the rigid vehicle's lowest lateral tip-over threshold over the edges of its support
  triangle, ``a_y / g`` (:func:`trikedyn.params.audit.tip_over_thresholds`; ``d T / (2 h L)`` for a centred
  CG at ``d`` from the single wheel's axle);
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
from ..params.schema import VehicleParameters

__all__ = ["LayoutComparison", "LayoutRow", "compare_layouts", "static_tip_over_g"]


def static_tip_over_g(params: VehicleParameters) -> tuple[float, str]:
    """The rigid vehicle's lowest lateral tip-over threshold ``a_y / g`` [1] and the edge it tips about."""
    from ..params.audit import tip_over_thresholds

    lateral = [e for e in tip_over_thresholds(params) if e["lateral"]]
    edge = min(lateral, key=lambda e: e["acceleration_g"])
    return float(edge["acceleration_g"]), edge["edge"]


@dataclass(frozen=True)
class LayoutRow:
    """One layout's results.

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

    def to_dict(self) -> dict:
        return {
            "layout": self.layout, "name": self.name, "static_tip_over_g": self.static_tip_over_g,
            "tip_over_edge": self.tip_over_edge, "tilt_angle_deg": self.tilt_angle_deg,
            "rigid_tilt_angle_deg": self.rigid_tilt_angle_deg,
            "threshold_speed_kmh": dict(self.threshold_speed_kmh), "threshold_detail": dict(self.threshold_detail),
            "threshold_limit": dict(self.threshold_limit),
        }


@dataclass(frozen=True)
class LayoutComparison:
    """A vehicle and its mirror layout side by side (the given vehicle first).

    Attributes
    ----------
    rows : tuple of LayoutRow
    manoeuvres : tuple of str
    mass_kg, cg_height_m, cg_x_fraction, wheelbase_m, track_m : float
        What both share: mass [kg], CG height [m], CG x as a fraction of the wheelbase from the rear axle,
        wheelbase [m] and track [m].
    mirror : VehicleParameters
        The mirror vehicle.
    """

    rows: tuple[LayoutRow, ...]
    manoeuvres: tuple[str, ...]
    mass_kg: float
    cg_height_m: float
    cg_x_fraction: float
    wheelbase_m: float
    track_m: float
    mirror: VehicleParameters | None = None

    def to_dict(self) -> dict:
        return {
            "layouts": [r.to_dict() for r in self.rows], "manoeuvres": list(self.manoeuvres),
            "shared": {"mass_kg": self.mass_kg, "cg_height_m": self.cg_height_m, "cg_x_fraction": self.cg_x_fraction,
                       "wheelbase_m": self.wheelbase_m, "track_m": self.track_m},
        }

    def table(self) -> str:
        """The comparison as a text table."""
        def num(value, fmt):
            return "-" if value is None or not math.isfinite(value) else format(value, fmt)

        head = ["", *(f"{r.layout} ({r.name})" for r in self.rows)]
        body = [
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
        shared = (f"shared: {self.mass_kg:.1f} kg, CG {self.cg_height_m:.3f} m high at {100 * self.cg_x_fraction:.1f} % "
                  f"of the wheelbase from the rear, wheelbase {self.wheelbase_m:.3f} m, track {self.track_m:.3f} m")
        return "\n".join([shared, *lines])

    def plot(self):
        """Bar charts: static tip-over [g], tilt angle [deg] and threshold velocities [km/h] per layout."""
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 2 + bool(self.manoeuvres), figsize=(11, 3.6))
        labels = [r.layout for r in self.rows]
        axes[0].bar(labels, [r.static_tip_over_g for r in self.rows], color="0.5")
        axes[0].set_ylabel("rigid static tip-over a_y/g [1]")
        axes[1].bar(labels, [r.tilt_angle_deg or 0.0 for r in self.rows], color="0.5")
        axes[1].set_ylabel("tilt-table angle [deg]")
        if self.manoeuvres:
            width = 0.8 / len(self.rows)
            for k, r in enumerate(self.rows):
                xs = [i + (k - (len(self.rows) - 1) / 2) * width for i in range(len(self.manoeuvres))]
                axes[2].bar(xs, [r.threshold_speed_kmh.get(m) or 0.0 for m in self.manoeuvres], width, label=r.layout)
            axes[2].set_xticks(range(len(self.manoeuvres)), list(self.manoeuvres))
            axes[2].set_ylabel("threshold velocity [km/h]")
            axes[2].legend(fontsize="small", loc="lower right")
        for ax in axes:
            ax.grid(axis="y", alpha=0.3)
        fig.suptitle(f"{self.rows[0].name}: delta and tadpole on the same mass, CG, wheelbase and track")
        fig.tight_layout()
        return fig


def _with_limit(value: str, limit: str | None) -> str:
    """A threshold in the table with what limits it: ``41.1 (cone strike)``."""
    return value if limit is None or value == "-" else f"{value} ({limit})"


def _row(pset: ParameterSet, manoeuvres, options, tilt: bool, search: dict) -> LayoutRow:
    from .threshold import threshold_velocity
    from .tilt import tilt_table

    params = pset.params
    tip_g, edge = static_tip_over_g(params)
    tilt_deg = rigid_deg = None
    if tilt:
        result = tilt_table(pset)
        tilt_deg, rigid_deg = result.tilt_angle_deg, result.rigid_tilt_angle_deg
    speeds, details, limits = {}, {}, {}
    for m in manoeuvres:
        found = threshold_velocity(pset, m, options=options.get(m), **search)
        speeds[m], details[m], limits[m] = found.threshold_speed_kmh, found.detail, found.limit
    return LayoutRow(params.layout, params.name, tip_g, edge, tilt_deg, rigid_deg, speeds, details, limits)


def compare_layouts(vehicle: ParameterSet | VehicleParameters, manoeuvres=("dlc", "slc"), *,
                    options: dict | None = None, tilt: bool = True, low_kmh: float = 10.0, high_kmh: float = 90.0,
                    step_kmh: float = 10.0, resolution_kmh: float = 0.1, criterion: str = "course",
                    speed_control: str = "driver") -> LayoutComparison:
    """A vehicle and its mirror layout side by side (see the module docstring).

    Parameters
    ----------
    vehicle : ParameterSet or VehicleParameters
        The vehicle, payload included; either layout.
    manoeuvres : sequence of str
        Registered manoeuvres (or path ``.csv`` files) for the threshold velocity; may be empty.
    options : dict, optional
        Manoeuvre -> its options.
    tilt : bool
        Run the tilt-table test (about 0.3 s per layout once compiled).
    low_kmh, high_kmh, step_kmh, resolution_kmh : float
        The threshold search [km/h] (:func:`trikedyn.analysis.threshold.threshold_velocity`).
    criterion, speed_control : str
        The search's pass rule (``"course"``, ``"lift-off"``, ``"both"``) and speed control (``"driver"``,
        ``"ideal"``).

    Returns
    -------
    LayoutComparison

    Raises
    ------
    ParameterError
        When the mirror is not a valid vehicle.
    InputError
        For an unknown manoeuvre or a bad search range.
    """
    from ..params.layouts import mirror_layout
    from ..params.ops import mass_properties

    if isinstance(vehicle, VehicleParameters):
        vehicle = ParameterSet(vehicle, {}, vehicle.name)
    if not isinstance(vehicle, ParameterSet):
        raise InputError(f"expected a ParameterSet or VehicleParameters, got {type(vehicle).__name__}",
                         where="vehicle")
    manoeuvres = tuple(str(m) for m in manoeuvres)
    mirror = mirror_layout(vehicle)
    mirror_set = ParameterSet(mirror, {}, f"mirror of {vehicle.origin or vehicle.name}")
    search = dict(low_kmh=low_kmh, high_kmh=high_kmh, step_kmh=step_kmh, resolution_kmh=resolution_kmh,
                  criterion=criterion, speed_control=speed_control)
    options = options or {}
    rows = tuple(_row(p, manoeuvres, options, tilt, search) for p in (vehicle, mirror_set))
    mp = mass_properties(vehicle.params)
    base = vehicle.params
    return LayoutComparison(
        rows=rows, manoeuvres=manoeuvres, mass_kg=float(mp.mass_kg), cg_height_m=float(mp.cg_m[2]),
        cg_x_fraction=float(mp.cg_m[0]) / base.wheelbase_m, wheelbase_m=base.wheelbase_m, track_m=base.track_m,
        mirror=mirror,
    )
