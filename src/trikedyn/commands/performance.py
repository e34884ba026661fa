"""``trikedyn performance``: top speed and what limits it, acceleration 0-30 km/h, braking from 30 km/h."""

from __future__ import annotations

from typing import Annotated

import typer

from ._common import FreightAliasOpt, JsonOpt, PayloadOpt, VehicleArg, emit, payload_kg, within

GradeOpt = Annotated[
    float,
    typer.Option("--grade-percent", callback=within(-50, 100, "%"),
                 help="Road grade [%]: tan(slope) = grade / 100, negative downhill (-50 .. 100)."),
]


def performance_cmd(
    vehicle: VehicleArg,
    payload: PayloadOpt = 0.0,
    freight: FreightAliasOpt = None,
    grade: GradeOpt = 0.0,
    as_json: JsonOpt = False,
):
    """Straight-line performance: top speed and its limit (power, torque, traction), 0-30 km/h, braking from 30 km/h.

    Quasi-static balances of the model's own forces (drive limits, tyres, rolling resistance, drag, load
    transfer), no simulation; see trikedyn.analysis.performance.
    """
    payload = payload_kg(payload, freight)
    from ..analysis.performance import performance
    from ..params import load_vehicle, with_freight

    pset = with_freight(load_vehicle(vehicle), payload)
    result = performance(pset, grade_percent=grade)
    data = result.to_dict() | {"vehicle": pset.name, "payload_kg": payload}

    def text() -> str:
        """The result for reading: the top speed and its limit first."""
        top, acc, brk = result.top_speed, result.acceleration, result.braking
        where = "on the flat" if grade == 0 else f"{'up' if grade > 0 else 'down'} a {abs(grade):g} % grade"
        if top.top_speed_kmh is None or top.top_speed_kmh == 0.0:
            lines = [f"top speed: {top.detail}"]
        else:
            lines = [f"top speed {top.top_speed_kmh:.1f} km/h {where} ({top.detail})"]
        if acc.time_s is None:
            lines.append(f"0-{acc.to_kmh:g} km/h: {acc.detail}")
        else:
            how = (f"power-limited from {acc.power_limited_from_kmh:.1f} km/h" if acc.power_limited_from_kmh is not None
                   else "torque-limited throughout")
            if acc.traction_limited:
                how += "; a driven wheel at its grip limit"
            lines.append(f"0-{acc.to_kmh:g} km/h in {acc.time_s:.2f} s over {acc.distance_m:.1f} m ({how})")
        if brk.distance_m is None:
            lines.append(f"braking from {brk.from_kmh:g} km/h: {brk.detail}")
        else:
            locks = ", ".join(brk.locked_wheels) or "no wheel"
            lines.append(f"braking from {brk.from_kmh:g} km/h: {brk.distance_m:.2f} m in {brk.time_s:.2f} s, mean "
                         f"{brk.mean_deceleration_mps2:.2f} m/s^2 ({locks} locked)")
        lines.append(f"  {pset.name}, {result.mass_kg:.0f} kg" + (f" with {payload:g} kg freight" if payload else ""))
        return "\n".join(lines)

    emit(data, as_json, text)
