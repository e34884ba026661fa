"""The mirror layout of a trike: a delta as a tadpole and a tadpole as a delta, all else kept.

:func:`mirror_layout` moves the pair of wheels to the other end and the single wheel to this end, on the
same mass, inertia, wheelbase and track, so that the layouts can be compared on one vehicle (the paper's
introduction: delta against tadpole, Huston et al. 1982). Where the CG goes is a choice, ``keep``:

* ``"pair-distance"`` (:data:`DEFAULT_KEEP`): the body is mirrored end for end with the wheels (x -> L - x):
  the CG keeps its distance from the two-wheel axle, and so its distance ``a`` from the single wheel's axle,
  its static load split between the pair and the single wheel, and its rigid tip-over threshold
  ``a_y / g = a T / (2 h L)``. The components, the payload, the freight site and the sensor are mirrored
  with it (the same distance from the pair; a delta's trunk over its rear pair becomes a tadpole's over its
  front pair), and the products of inertia ``Ixy``, ``Ixz`` change sign (a mirror image). The layouts then
  differ only in which end has two wheels: what a comparison finds is the layout's.
* ``"cg"``: the body stays where it is and only the wheels move: the CG keeps its x ahead of the rear axle
  (its fraction of the wheelbase from the rear), and with it the components, payload, freight site and
  sensor. A CG near the pair of one layout is then near the single wheel of the other (``a = L - x``
  becomes ``a = x``), and the comparison is as much about where the mass is as about the layout.

What both keep and derive:

* **Geometry**: the front wheel(s) stay at the front axle's x (the wheelbase ``L``), the rear wheel(s) at
  x = 0 (the origin is below the rear axle in both layouts). The pair keeps its two y positions (its track
  ``T`` and its centre), the single wheel its y; the CG keeps its y and height.
* **Mass**: ``[mass]``'s masses and principal inertias are kept. The static load on the single wheel
  follows the CG (for a CG at ``x``: ``1 - x / L`` of the weight on a delta's front wheel, ``x / L`` on a
  tadpole's rear wheel).
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
* **Declared ranges** (``[ranges]``) follow their values: a wheel's range goes to each new wheel that copies
  that wheel (its ``y_m`` to the wheel at its place), the front wheel's ``x_m`` becomes ``wheelbase_m``; a rate's range
  is scaled with the rate; a mirrored x's range is mirrored; ranges of values the mirror no longer has
  (the other end's second wheel, a dropped suspension or measured frequency) are dropped.
"""

from __future__ import annotations

import statistics

from pydantic import ValidationError

from ..errors import InputError, ParameterError
from ..units import STANDARD_GRAVITY
from .io import ParameterSet, _describe
from .ops import static_wheel_loads, unsprung_mass
from .schema import VehicleParameters

__all__ = ["DEFAULT_KEEP", "KEEPS", "LAYOUTS", "WHEEL_NAMES", "check_keep", "mirror_layout", "mirror_name"]

LAYOUTS = ("delta", "tadpole")
WHEEL_NAMES = {"delta": ("front", "rear_left", "rear_right"), "tadpole": ("front_left", "front_right", "rear")}
"""Wheel names of each layout, in the order :func:`mirror_layout` writes them."""
KEEPS = ("pair-distance", "cg")
"""What a mirror keeps of the CG's place (see the module docstring)."""
DEFAULT_KEEP = "pair-distance"
"""The CG at the same distance from the two-wheel axle: the layouts compared, not two CG positions."""

_MIN_HEAD_MASS_KG, _MIN_HEAD_INERTIA_KGM2 = 0.1, 0.001  # the schema's least values
_PAIR = "+"  # a range key for both wheels of a pair: wheels.LEFT+RIGHT.ATTR (trikedyn.study.designs.factors)
_RATES = ("stiffness_N_per_m", "damping_Ns_per_m", "bump_stop_stiffness_N_per_m")


def check_keep(keep: str, where: str = "keep", allow_both: bool = False) -> str:
    """``keep`` if it names what a mirror keeps (:data:`KEEPS`, and ``"both"`` when allowed), else an
    :class:`~trikedyn.errors.InputError` naming ``where``.

    Parameters
    ----------
    keep : str
        What the mirror keeps.
    where : str
        Error location.
    allow_both : bool
        Accept ``"both"``.

    Returns
    -------
    str
        ``keep``.
    """
    allowed = (*KEEPS, "both") if allow_both else KEEPS
    if keep not in allowed:
        raise InputError(f"expected one of {', '.join(allowed)}, got {keep!r}", where=where)
    return keep


def mirror_name(name: str, layout: str, keep: str | None = None) -> str:
    """The name of the mirror of vehicle ``name`` in ``layout`` (``keep`` named when it is ``"cg"``).

    Parameters
    ----------
    name : str
        The vehicle's name.
    layout : str
        ``"delta"`` or ``"tadpole"``.
    keep : str, optional
        What the mirror keeps.

    Returns
    -------
    str
        The name, at most 100 characters.
    """
    suffix = f" ({layout} mirror{', CG kept' if keep == 'cg' else ''})"
    return name[: 100 - len(suffix)] + suffix


def _sprung_masses(params: VehicleParameters) -> dict[str, float]:
    """Static sprung mass per wheel [kg] of the vehicle without payload."""
    bare = params.model_copy(update={"payload": ()})
    loads = static_wheel_loads(bare, STANDARD_GRAVITY)
    return {w.name: loads[w.name] / STANDARD_GRAVITY - unsprung_mass(bare, w.name) for w in bare.wheels}


def _mirror_body(data: dict, wheelbase_m: float) -> None:
    """Mirror every mass and point of the body end for end (x -> L - x) in a model_dump, in place."""
    mass = data["mass"]
    mass["cg_x_m"] = wheelbase_m - mass["cg_x_m"]
    for key in ("roll_pitch_product_kgm2", "roll_yaw_product_kgm2"):  # Ixy, Ixz: odd in x
        mass[key] = -mass[key] + 0.0  # + 0.0: no -0.0 in a file
    for item in (*data["components"], *data["payload"], data["freight"], data["sensor"]):
        item["x_m"] = wheelbase_m - item["x_m"]


def mirror_layout(vehicle: ParameterSet | VehicleParameters, keep: str = DEFAULT_KEEP) -> VehicleParameters:
    """The vehicle with its wheel layout mirrored (delta -> tadpole, tadpole -> delta); see the module
    docstring for what is kept and what is derived.

    Parameters
    ----------
    vehicle : ParameterSet or VehicleParameters
        A valid vehicle, either layout.
    keep : {"pair-distance", "cg"}
        Where the CG goes: at the same distance from the two-wheel axle (the body mirrored with the wheels,
        the default: same rigid tip-over), or where it is on the vehicle (the same x ahead of the rear axle).

    Returns
    -------
    VehicleParameters
        The mirror vehicle: same mass, CG height [m], inertia, wheelbase [m] and track [m].

    Raises
    ------
    InputError
        For an unknown ``keep``.
    ParameterError
        When the mirror is not a valid vehicle (e.g. a CG so far forward that a tadpole's rear wheel, or
        so far back that a delta's front wheel, carries less than its own unsprung mass), naming the field.
    """
    check_keep(keep)
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
        layout_rows = [(names[0], old_front, front_x, pair[0]), (names[1], old_front, front_x, pair[1]),
                       (names[2], old_rear, rear_x, single)]
    else:
        layout_rows = [(names[0], old_front, front_x, single), (names[1], old_rear, rear_x, pair[0]),
                       (names[2], old_rear, rear_x, pair[1])]
    wheels = []
    for name, template, x, place in layout_rows:
        data = template.model_dump()
        data.update(name=name, x_m=x, y_m=place.y_m)
        wheels.append(data)

    data = params.model_dump()
    data.update(layout=new_layout, wheels=wheels, name=mirror_name(params.name, new_layout, keep))
    kept = ("the CG at the same distance from the two-wheel axle (the body mirrored)" if keep == "pair-distance"
            else "the CG where it is on the vehicle")
    data["description"] = _cut(f"{params.description} -- mirrored to the {new_layout} layout on the same "
                               f"mass, wheelbase and track, {kept}", 2000)
    data["source"] = _cut(f"trikedyn.params.layouts.mirror_layout(keep='{keep}') of '{params.name}' "
                          f"({params.source})", 2000)
    if keep == "pair-distance":
        _mirror_body(data, params.wheelbase_m)

    # steered parts: the same total mass and inertia, split over the new number of heads
    factor = len(steered) / (2 if new_layout == "tadpole" else 1)
    steering = data["steering"]
    steering["head_mass_kg"] = max(steering["head_mass_kg"] * factor, _MIN_HEAD_MASS_KG)
    steering["head_inertia_kgm2"] = max(steering["head_inertia_kgm2"] * factor, _MIN_HEAD_INERTIA_KGM2)

    # suspension: only those used by the new wheels, rates scaled to keep frequency, sag and damping ratio
    old_sprung = _sprung_masses(params)
    data["suspension"] = {w["suspension"]: dict(data["suspension"][w["suspension"]]) for w in wheels}
    data["ranges"] = {}
    try:
        unscaled = VehicleParameters.model_validate(data)
    except ValidationError as exc:
        raise ParameterError(_describe(exc, data), where=f"mirror_layout({params.name})") from None
    new_sprung = _sprung_masses(unscaled)
    ratios = {}
    for susp_name, susp in data["suspension"].items():
        before = statistics.fmean(m for w, m in old_sprung.items() if params.wheel(w).suspension == susp_name)
        after = statistics.fmean(m for w, m in new_sprung.items() if unscaled.wheel(w).suspension == susp_name)
        if before <= 0 or after <= 0:
            raise ParameterError(
                f"suspension '{susp_name}': sprung mass {before:.1f} kg as a {params.layout}, {after:.1f} kg as a "
                f"{new_layout}; the CG must leave each wheel more than its unsprung mass", where="mirror_layout"
            )
        ratios[susp_name] = after / before
        for key in _RATES:
            susp[key] *= ratios[susp_name]
        susp.update(natural_frequency_hz=None, damping_ratio=None)
    data["ranges"] = _mirror_ranges(params, layout_rows, ratios, factor, keep)
    try:
        return VehicleParameters.model_validate(data)
    except ValidationError as exc:
        raise ParameterError(_describe(exc, data), where=f"mirror_layout({params.name})") from None


def _mirror_ranges(params: VehicleParameters, layout_rows, ratios: dict, head_factor: float, keep: str) -> dict:
    """The declared ranges of the mirror (see the module docstring); each range is ``(low, high)`` or a
    :class:`~trikedyn.params.ranges.RelativeRange`."""
    copies: dict[str, list[str]] = {}  # old wheel -> new wheels that copy it
    places: dict[str, list[str]] = {}  # old wheel -> new wheel at its y
    for name, template, _, place in layout_rows:
        copies.setdefault(template.name, []).append(name)
        places.setdefault(place.name, []).append(name)
    front = {w.name for w in params.wheels if w.steered}
    length = params.wheelbase_m

    def mirrored_x(key: str) -> float | None:
        """The value a range of a mirrored x names (None: not a mirrored x)."""
        parts = key.split(".")
        if keep != "pair-distance":
            return None
        if key == "mass.cg_x_m":
            return params.mass.cg_x_m
        if key == "cg_x_fraction":
            return params.mass.cg_x_m / length
        if key in ("freight.x_m", "sensor.x_m"):
            return getattr(params, parts[0]).x_m
        if len(parts) == 3 and parts[2] == "x_m" and parts[0] in ("component", "components", "payload"):
            items = params.payload if parts[0] == "payload" else params.components
            return next((i.x_m for i in items if i.name == parts[1]), None)
        return None

    out: dict = {}
    for key, spec in params.ranges.items():
        parts = key.split(".")
        rel = getattr(spec, "rel", None)
        value = mirrored_x(key)
        if value is not None:
            whole = 1.0 if key == "cg_x_fraction" else length
            low, high = sorted((value * (1 - rel), value * (1 + rel))) if rel is not None else spec
            out[key] = (whole - high, whole - low)
        elif parts[0] == "wheels" and len(parts) == 3:
            old = parts[1].split(_PAIR)
            if parts[2] == "x_m":
                if front & set(old) and "wheelbase_m" not in params.ranges:
                    out["wheelbase_m"] = spec  # the front wheel's x is the wheelbase; the rear's is the origin
                continue
            table = places if parts[2] == "y_m" else copies
            for name in dict.fromkeys(n for o in old for n in table.get(o, ())):
                out[f"wheels.{name}.{parts[2]}"] = spec  # one key per wheel, as a file declares a pair's
        elif parts[0] == "suspension" and len(parts) == 3:
            if parts[1] not in ratios or parts[2] in ("natural_frequency_hz", "damping_ratio"):
                continue
            ratio = ratios[parts[1]] if parts[2] in _RATES else 1.0
            out[key] = spec if rel is not None else (spec[0] * ratio, spec[1] * ratio)
        elif key in ("steering.head_mass_kg", "steering.head_inertia_kgm2") and rel is None:
            out[key] = (spec[0] * head_factor, spec[1] * head_factor)
        else:
            out[key] = spec
    return out


def _cut(text: str, limit: int) -> str:
    return text if len(text) <= limit else text[: limit - 3] + "..."
