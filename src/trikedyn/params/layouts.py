"""The mirror layout of a trike: a delta as a tadpole and a tadpole as a delta, all else kept.

:func:`mirror_layout` moves the pair of wheels to the other end and the single wheel to this end, on the
same mass, CG, inertia, wheelbase and track, so that the layouts can be compared on one vehicle (the paper's
introduction: delta against tadpole, Huston et al. 1982). What it keeps and what it derives:

* **Geometry**: the front wheel(s) stay at the front axle's x (the wheelbase ``L``), the rear wheel(s) at
  x = 0 (the origin is below the rear axle in both layouts). The pair keeps its two y positions (its track
  ``T`` and its centre), the single wheel its y.
* **Mass**: ``[mass]`` is kept as it is, so the CG keeps its height and its fore-aft position as a fraction
  of the wheelbase measured from the rear (``cg_x_m / L``); payload, freight site and sensor are kept.
  The static load on the single wheel changes with the layout (for a CG at ``x``: ``1 - x / L`` of the
  weight on a delta's front wheel, ``x / L`` on a tadpole's rear wheel).
* **Wheels**: each new wheel copies the old wheel at its end (front or rear: radius, masses, brakes, drive,
  ``tyre_file``); steered wheels are the front ones. Wheels are named by the layout's convention (delta:
  ``front``, ``rear_left``, ``rear_right``; tadpole: ``front_left``, ``front_right``, ``rear``).
* **Suspension**: each end keeps its suspension (telescopic at the steered front, swing arm at the rear).
  Its spring and bump-stop rates are multiplied by the ratio of the new to the old sprung mass per wheel at
  that end (vehicle without payload: the springs' preload is that of the vehicle as built), which keeps
  each wheel's natural frequency ``sqrt(K / M_s) / 2 pi`` and its static sag ``M_s g / K``; its damper rate
  by the same ratio, which keeps the damping ratio ``C / (2 sqrt(K M_s))``. The measured
  ``natural_frequency_hz`` and ``damping_ratio`` are dropped: they were measured on the other layout
  (``trikedyn vehicle check`` shows the frequencies that the springs and the CG give).
* **Steering**: the steered parts keep their total mass and inertia: a tadpole's two heads get half the
  delta's ``head_mass_kg`` and ``head_inertia_kgm2`` each, a delta's single head twice the tadpole's (the
  model builds one head per steered wheel). Rake, trail, lock, servo, Ackermann fraction and handlebar ratio
  are kept.
* Tyre, drive (the total drive torque to the driven wheels), aero and body are kept.
"""

from __future__ import annotations

import statistics

from pydantic import ValidationError

from ..errors import ParameterError
from ..units import STANDARD_GRAVITY
from .io import ParameterSet, _describe
from .ops import static_wheel_loads, unsprung_mass
from .schema import VehicleParameters

__all__ = ["LAYOUTS", "WHEEL_NAMES", "mirror_layout", "mirror_name"]

LAYOUTS = ("delta", "tadpole")
WHEEL_NAMES = {"delta": ("front", "rear_left", "rear_right"), "tadpole": ("front_left", "front_right", "rear")}
"""Wheel names of each layout, in the order :func:`mirror_layout` writes them."""

_MIN_HEAD_MASS_KG, _MIN_HEAD_INERTIA_KGM2 = 0.1, 0.001  # the schema's least values


def mirror_name(name: str, layout: str) -> str:
    """The name of the mirror of vehicle ``name`` in ``layout``."""
    suffix = f" ({layout} mirror)"
    return name[: 100 - len(suffix)] + suffix


def _sprung_masses(params: VehicleParameters) -> dict[str, float]:
    """Static sprung mass per wheel [kg] of the vehicle without payload."""
    bare = params.model_copy(update={"payload": ()})
    loads = static_wheel_loads(bare, STANDARD_GRAVITY)
    return {w.name: loads[w.name] / STANDARD_GRAVITY - unsprung_mass(bare, w.name) for w in bare.wheels}


def mirror_layout(vehicle: ParameterSet | VehicleParameters) -> VehicleParameters:
    """The vehicle with its wheel layout mirrored (delta -> tadpole, tadpole -> delta); see the module
    docstring for what is kept and what is derived.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleParameters
        A valid vehicle, either layout.

    Returns
    -------
    VehicleParameters
        The mirror vehicle: same mass, CG, inertia, wheelbase [m] and track [m].

    Raises
    ------
    ParameterError
        When the mirror is not a valid vehicle (e.g. a CG so far forward that a tadpole's rear wheel, or
        so far back that a delta's front wheel, carries less than its own unsprung mass), naming the field.
    """
    params = vehicle.params if isinstance(vehicle, ParameterSet) else vehicle
    new_layout = "tadpole" if params.layout == "delta" else "delta"
    steered = [w for w in params.wheels if w.steered]
    fixed = [w for w in params.wheels if not w.steered]
    pair, single = (fixed, steered[0]) if params.layout == "delta" else (steered, fixed[0])
    pair = sorted(pair, key=lambda w: -w.y_m)  # left first
    front_x, rear_x = params.wheelbase_m, 0.0

    # new wheels: each copies the old wheel at its end; the pair goes to the single wheel's end
    single_end_is_front = params.layout == "delta"
    old_front, old_rear = (single, pair[0]) if single_end_is_front else (pair[0], single)
    names = WHEEL_NAMES[new_layout]
    if new_layout == "tadpole":
        layout_rows = [(names[0], old_front, front_x, pair[0].y_m), (names[1], old_front, front_x, pair[1].y_m),
                       (names[2], old_rear, rear_x, single.y_m)]
    else:
        layout_rows = [(names[0], old_front, front_x, single.y_m), (names[1], old_rear, rear_x, pair[0].y_m),
                       (names[2], old_rear, rear_x, pair[1].y_m)]
    wheels = []
    for name, template, x, y in layout_rows:
        data = template.model_dump()
        data.update(name=name, x_m=x, y_m=y)
        wheels.append(data)

    data = params.model_dump()
    data.update(layout=new_layout, wheels=wheels, name=mirror_name(params.name, new_layout))
    data["description"] = _cut(f"{params.description} -- mirrored to the {new_layout} layout on the same "
                               "mass, CG, wheelbase and track", 2000)
    data["source"] = _cut(f"trikedyn.params.layouts.mirror_layout of '{params.name}' ({params.source})", 2000)

    # steered parts: the same total mass and inertia, split over the new number of heads
    factor = len(steered) / (2 if new_layout == "tadpole" else 1)
    steering = data["steering"]
    steering["head_mass_kg"] = max(steering["head_mass_kg"] * factor, _MIN_HEAD_MASS_KG)
    steering["head_inertia_kgm2"] = max(steering["head_inertia_kgm2"] * factor, _MIN_HEAD_INERTIA_KGM2)

    # suspension: only those used by the new wheels, rates scaled to keep frequency, sag and damping ratio
    old_sprung = _sprung_masses(params)
    data["suspension"] = {w["suspension"]: dict(data["suspension"][w["suspension"]]) for w in wheels}
    try:
        unscaled = VehicleParameters.model_validate(data)
    except ValidationError as exc:
        raise ParameterError(_describe(exc, data), where=f"mirror_layout({params.name})") from None
    new_sprung = _sprung_masses(unscaled)
    for susp_name, susp in data["suspension"].items():
        before = statistics.fmean(m for w, m in old_sprung.items() if params.wheel(w).suspension == susp_name)
        after = statistics.fmean(m for w, m in new_sprung.items() if unscaled.wheel(w).suspension == susp_name)
        if before <= 0 or after <= 0:
            raise ParameterError(
                f"suspension '{susp_name}': sprung mass {before:.1f} kg as a {params.layout}, {after:.1f} kg as a "
                f"{new_layout}; the CG must leave each wheel more than its unsprung mass", where="mirror_layout"
            )
        ratio = after / before
        for key in ("stiffness_N_per_m", "damping_Ns_per_m", "bump_stop_stiffness_N_per_m"):
            susp[key] *= ratio
        susp.update(natural_frequency_hz=None, damping_ratio=None)
    try:
        return VehicleParameters.model_validate(data)
    except ValidationError as exc:
        raise ParameterError(_describe(exc, data), where=f"mirror_layout({params.name})") from None


def _cut(text: str, limit: int) -> str:
    return text if len(text) <= limit else text[: limit - 3] + "..."
