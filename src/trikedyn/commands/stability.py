"""``trikedyn threshold``, ``handling`` and ``tilt``: how fast, how it handles, how far it tilts."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..errors import InputError
from ._bounds import SEARCH_DEFAULTS, search_bound, variant_bound
from ._common import (
    BandKmhOpt,
    BandPercentOpt,
    CriterionOpt,
    ForceOpt,
    FreightAliasOpt,
    JsonOpt,
    ManoeuvreOpt,
    OptionOpt,
    PayloadOpt,
    SpeedControlOpt,
    VehicleArg,
    emit,
    judging,
    manoeuvre_options,
    payload_kg,
    save_figure,
    within,
)


def threshold_cmd(
    vehicle: VehicleArg,
    manoeuvre: ManoeuvreOpt = "dlc",
    payload: PayloadOpt = 0.0,
    freight: FreightAliasOpt = None,
    option: OptionOpt = [],  # noqa: B006
    stiffness: Annotated[float, typer.Option("--stiffness-scale", callback=variant_bound("stiffness_scale"), help="Suspension stiffness factor (Table 2).")] = 1.0,
    damping: Annotated[float, typer.Option("--damping-scale", callback=variant_bound("damping_scale"), help="Suspension damping factor (Table 2).")] = 1.0,
    low: Annotated[float, typer.Option("--low", callback=search_bound("low_kmh"), help="Lowest speed searched [km/h].")] = SEARCH_DEFAULTS["low_kmh"],
    high: Annotated[float, typer.Option("--high", callback=search_bound("high_kmh"), help="Highest speed searched [km/h].")] = SEARCH_DEFAULTS["high_kmh"],
    resolution: Annotated[float, typer.Option("--resolution", callback=search_bound("resolution_kmh"), help="Resolution [km/h].")] = SEARCH_DEFAULTS["resolution_kmh"],
    criterion: CriterionOpt = SEARCH_DEFAULTS["criterion"],
    speed_control: SpeedControlOpt = SEARCH_DEFAULTS["speed_control"],
    band_percent: BandPercentOpt = SEARCH_DEFAULTS["speed_band_percent"],
    band_kmh: BandKmhOpt = SEARCH_DEFAULTS["speed_band_kmh"],
    as_json: JsonOpt = False,
):
    """Threshold velocity: the highest speed at which the vehicle passes the manoeuvre, under a criterion
    (course: a valid ISO run, the default; lift-off: no wheel lifts, the paper's), quoted with the speed the
    passing run actually drove. With the driver's own speed control the search stops at the top speed."""
    payload = payload_kg(payload, freight)
    from ..analysis.search_settings import SearchSettings
    from ..analysis.threshold import threshold_velocity
    from ..manoeuvres.spec import ManoeuvreSpec
    from ..params import load_vehicle
    from ..params.variant import Variant

    if low >= high:
        raise InputError(f"must be below --high ({high:g} km/h), got {low:g}", where="--low")
    options = manoeuvre_options(manoeuvre, option)
    rules = judging(band_percent, band_kmh)
    settings = SearchSettings(low_kmh=low, high_kmh=high, resolution_kmh=resolution, criterion=criterion,
                              speed_control=speed_control, speed_band_percent=rules.speed_band_percent,
                              speed_band_kmh=rules.speed_band_kmh)
    spec = ManoeuvreSpec(manoeuvre, options)
    pset = Variant(stiffness_scale=stiffness, damping_scale=damping, freight_kg=payload).apply(load_vehicle(vehicle))
    result = threshold_velocity(pset, spec.name, options=spec.options, **settings.threshold_kwargs())
    data = result.to_dict(runs=True) | {"vehicle": pset.name, "manoeuvre": manoeuvre, "options": options,
                                        "payload_kg": payload, "stiffness_scale": stiffness, "damping_scale": damping,
                                        "speed_band": rules.to_dict()}
    lines = [result.headline, f"  {result.detail}"]
    if result.lift_off is not None and result.lift_off.detail != result.detail:
        lines.append(f"  lift-off: {result.lift_off.detail}")
    if result.top_speed_kmh is not None and result.limit != "top speed":
        lines.append(f"  top speed on the flat {result.top_speed_kmh:.1f} km/h"
                     + (" (the ideal speed control drives beyond it)" if speed_control == "ideal"
                        and result.threshold_speed_kmh is not None
                        and result.threshold_speed_kmh > result.top_speed_kmh else ""))
    if result.first_cone_strike_kmh is not None:
        lines.append(f"  first cone strike seen at {result.first_cone_strike_kmh:.1f} km/h")
    lines.append(f"  {len(result.runs)} run{'s' if len(result.runs) != 1 else ''}")
    emit(data, as_json, "\n".join(lines))


def handling_cmd(
    vehicle: VehicleArg,
    radius: Annotated[float, typer.Option("--radius", callback=within(1, 1000, "m"), help="Circle radius [m].")] = 20.0,
    payload: PayloadOpt = 0.0,
    freight: FreightAliasOpt = None,
    start_speed: Annotated[float, typer.Option("--start-speed", callback=within(0, 200, "km/h", above=True), help="Speed at the start [km/h].")] = 15.0,
    plot: Annotated[Path | None, typer.Option("--plot", help="Write the handling diagram (PNG).")] = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """ISO 4138 steady-state circular driving: handling diagram, understeer gradient (linear range and by band of
    lateral acceleration), neutral-steer lateral acceleration, limit behaviour, roll and sideslip gradients."""
    payload = payload_kg(payload, freight)
    import numpy as np

    from ..analysis.handling_tests import steady_state_test
    from ..params import load_vehicle, with_freight

    for value, where in ((radius, "--radius"), (start_speed, "--start-speed")):
        if not np.isfinite(value) or value <= 0:
            raise InputError(f"must be > 0, got {value!r}", where=where)
    if plot is not None:
        from .._files import check_output

        check_output(plot, force=force, reads=[vehicle])
    pset = with_freight(load_vehicle(vehicle), payload)
    test = steady_state_test(pset, radius_m=radius, start_speed_kmh=start_speed)
    data = test.to_dict() | {"vehicle": pset.name, "payload_kg": payload}
    if plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        save_figure(test.plot(), plot, dpi=120)
        data["plot"] = str(plot)
    emit(data, as_json, lambda: test.describe(pset.name))


def tilt_cmd(
    vehicle: VehicleArg,
    payload: PayloadOpt = 0.0,
    freight: FreightAliasOpt = None,
    side: Annotated[str, typer.Option("--side", help="The side that goes down: left, right or both.")] = "both",
    require_deg: Annotated[
        float | None, typer.Option("--require-deg", help="Required tilt angle [deg] (e.g. 35): pass or fail.")
    ] = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Write wheel loads [N] against table angle [deg] (PNG).")] = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Tilt-table test: the table angle at which the first wheel lifts, on the compliant model."""
    payload = payload_kg(payload, freight)
    from ..analysis.tilt import tilt_table
    from ..params import load_vehicle, with_freight

    if side not in ("left", "right", "both"):
        raise InputError(f"expected left, right or both, got '{side}'", where="--side")
    if not np.isfinite(payload) or payload < 0:
        raise InputError(f"must be >= 0 kg, got {payload!r}", where="--payload")
    if require_deg is not None and not (np.isfinite(require_deg) and 0.0 < require_deg < 90.0):
        raise InputError(f"expected an angle between 0 and 90 deg, got {require_deg!r}", where="--require-deg")
    if plot is not None:
        from .._files import check_output

        check_output(plot, force=force, reads=[vehicle])
    pset = with_freight(load_vehicle(vehicle), payload)
    result = tilt_table(pset, side=side, require_deg=require_deg)
    data = result.to_dict() | {"payload_kg": payload}
    if plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        save_figure(result.plot(), plot, dpi=110)
        data["plot"] = str(plot)
    lines = [
        f"tilt angle {result.tilt_angle_deg:.1f} deg ({result.side}; {result.first_lifting_wheel} lifts first); "
        f"rigid {result.rigid_tilt_angle_deg:.1f} deg"
    ]
    for s in result.sides.values():
        lines.append(
            f"  {s.side:<6} {s.tilt_angle_deg:6.2f} deg  {s.first_lifting_wheel} lifts, body roll {s.body_roll_deg:.1f} deg; "
            f"rigid {s.rigid_tilt_angle_deg:.2f} deg about {s.tip_axis}"
        )
    if result.passes is not None:
        lines.append(f"  required {result.require_deg:g} deg: {'passes' if result.passes else 'FAILS'}")
    if plot is not None:
        lines.append(f"  wrote {plot}")
    emit(data, as_json, "\n".join(lines))


# ------------------------------------------------------------------------------------------------
