"""Consistency audit of a parameter set (``trikedyn vehicle check``).

What a careful engineer checks before trusting a parameter set, each as a :class:`Finding` with numbers:

* the sprung masses that ``K`` and ``f_n`` imply (Eq. 3) against those that the masses and the CG imply
  (static axle loads less the unsprung masses): with the tyre in series, as the model has it (the vehicle
  file's K is the suspension's own spring, :mod:`trikedyn.params.springs`), the paper's rigid-tyre Eq. 3
  beside it; damping against Eq. 4 where the set gives the measured ``xi`` and ``f_n``; the CG position that
  Eq. 3 would imply (:mod:`trikedyn.params.audit_springs`);
* mass bookkeeping (curb mass, body mass, wheels, unsprung parts);
* the CG inside the support triangle, with the rigid-vehicle static tip-over threshold for each edge
  (``a_y / g = d / h``, ``d`` the CG's lateral distance to the edge: ``a T / (2 L)`` for a centred CG, ``a``
  its distance along x from the single wheel's axle, in front for a delta, at the rear for a tadpole);
* static spring and tyre deflections against the travel, and the Magic Formula's nominal load against the
  static wheel loads.

Every number in a finding is finite: what cannot be computed (a sprung mass that is not positive, a damper
of zero against Eq. 4) is said in the message, its value is None, and a value that still came out
non-finite is replaced by None with an ``inconsistent`` finding that names it.
"""

from __future__ import annotations

import math

import numpy as np

from ..units import STANDARD_GRAVITY
from .audit_springs import spring_findings
from .findings import INCONSISTENT, NOTE, OK, WARNING, Finding  # noqa: F401 - the levels, importable from here
from .io import ParameterSet
from .ops import mass_properties, static_wheel_loads, unsprung_mass  # the last two re-exported
from .schema import VehicleParameters
from .springs import wheel_tyre

__all__ = ["Finding", "audit", "static_wheel_loads", "tip_over_thresholds", "unsprung_mass"]

def tip_over_thresholds(params: VehicleParameters) -> list[dict]:
    """Rigid-vehicle static tip-over per edge of the support triangle.

    For each edge: the CG projection's perpendicular distance to it [m] (negative when outside), the
    lateral distance along y [m], and the lateral acceleration that tips the vehicle about it,
    ``a_y / g = d_y / h`` (edges with no y component are tipped by longitudinal acceleration instead,
    ``a_x / g = d_x / h``).

    It holds for either layout: for a CG on the centre line at height ``h``, ``d`` from the single wheel's
    axle along x, with wheelbase ``L`` and track ``T``, each side edge gives ``a_y / g = d T / (2 h L)``
    (``d`` behind the front wheel of a delta, ahead of the rear wheel of a tadpole).

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.

    Returns
    -------
    list of dict
        Per edge: its name, distances [m], the tipping acceleration ``acceleration_g`` (dimensionless),
        whether it is ``lateral`` and the side it ``tips_toward``.
    """
    pts = np.array([(w.x_m, w.y_m) for w in params.wheels])
    names = [w.name for w in params.wheels]
    centroid = pts.mean(axis=0)
    mp = mass_properties(params)
    cg = mp.cg_m[:2]
    h = mp.cg_m[2]
    edges = []
    for i in range(3):
        for j in range(i + 1, 3):
            p, q = pts[i], pts[j]
            direction = (q - p) / np.linalg.norm(q - p)
            normal = np.array([-direction[1], direction[0]])
            if np.dot(centroid - p, normal) < 0:
                normal = -normal  # inward
            d = float(np.dot(cg - p, normal))
            lateral = bool(abs(normal[1]) > 1e-9 and abs(normal[1]) >= abs(normal[0]) * 0.5)
            comp = abs(normal[1]) if lateral else abs(normal[0])
            along = d / comp
            side = (
                ("left" if normal[1] < 0 else "right") if lateral else ("rear" if normal[0] > 0 else "front")
            )
            edges.append(
                {
                    "edge": f"{names[i]}-{names[j]}",
                    "tips_toward": side,
                    "distance_m": d,
                    "axis_distance_m": along,
                    "acceleration_g": along / h,
                    "lateral": lateral,
                }
            )
    return edges


def audit(pset: ParameterSet | VehicleParameters) -> list[Finding]:
    """Audit a parameter set for consistency; see the module docstring for the checks.

    Parameters
    ----------
    pset : ParameterSet or VehicleParameters
        The vehicle.

    Returns
    -------
    list of Finding
        Each check's finding (values in SI units, the paper's Eqs. 3-4 where they apply).
    """
    params = pset.params if isinstance(pset, ParameterSet) else pset
    g = STANDARD_GRAVITY
    findings: list[Finding] = []
    loads = static_wheel_loads(params, g)
    mp = mass_properties(params)
    total_kg, cg_x = mp.mass_kg, float(mp.cg_m[0])

    # 1-2. Eq. 3 (the tyre in series; the paper's rigid-tyre Eq. 3 beside it), Eq. 4, the CG from Eq. 3
    findings += spring_findings(params, total_kg, cg_x)

    # 3. mass bookkeeping
    wheels = sum(w.mass_kg for w in params.wheels)
    if params.mass.body_kg is not None:
        diff = params.mass.curb_kg - wheels - params.mass.body_kg
        findings.append(
            Finding(
                OK if abs(diff) <= 0.5 else WARNING,
                "mass bookkeeping",
                f"curb {params.mass.curb_kg:g} kg - wheels {wheels:.2f} kg = {params.mass.curb_kg - wheels:.2f} kg"
                f" against body {params.mass.body_kg:g} kg (difference {diff:+.2f} kg)",
                {"curb_kg": params.mass.curb_kg, "wheels_kg": wheels, "body_kg": params.mass.body_kg, "difference_kg": diff},
            )
        )
    heads = sum(w.steered for w in params.wheels)  # the model builds one steering head per steered wheel
    parts = wheels + heads * params.steering.head_mass_kg + sum(
        params.suspension[w.suspension].moving_mass_kg for w in params.wheels
    )
    chassis = total_kg - parts
    findings.append(
        Finding(
            OK if chassis > 0.5 * total_kg else WARNING,
            "mass bookkeeping",
            f"chassis (sprung body with driver and payload) {chassis:.1f} kg of {total_kg:.1f} kg; "
            f"wheels, fork{'s' if heads > 1 else ''}, arms and steering head{'s' if heads > 1 else ''} {parts:.1f} kg",
            {"chassis_kg": chassis, "parts_kg": parts, "total_kg": total_kg},
        )
    )

    # 4. support triangle and tip-over
    for edge in tip_over_thresholds(params):
        inside = edge["distance_m"] > 0
        kind = "lateral" if edge["lateral"] else "longitudinal"
        level = (OK if edge["acceleration_g"] >= 0.5 else WARNING) if inside else INCONSISTENT
        findings.append(
            Finding(
                level,
                "tip-over (rigid, static)",
                f"edge {edge['edge']}: CG {edge['distance_m'] * 1000:.0f} mm inside; tips toward the "
                f"{edge['tips_toward']} at {kind} a/g = {edge['acceleration_g']:.3f}"
                if inside
                else f"edge {edge['edge']}: CG {-edge['distance_m'] * 1000:.0f} mm OUTSIDE the support triangle",
                edge,
            )
        )

    # 5. static deflections and tyre load range
    tyres = {w.name: wheel_tyre(params, w) for w in params.wheels}
    for w in params.wheels:
        s = params.suspension[w.suspension]
        sprung = loads[w.name] - unsprung_mass(params, w.name) * g
        sag = sprung / s.stiffness_N_per_m
        tyre = loads[w.name] / tyres[w.name].stiffness_N_per_m
        findings.append(
            Finding(
                OK if tyre < 0.3 * w.radius_m else WARNING,
                "static deflection",
                f"{w.name}: load {loads[w.name]:.0f} N, spring sag {sag * 1000:.1f} mm, tyre deflection "
                f"{tyre * 1000:.1f} mm, bump travel {s.bump_travel_m * 1000:.0f} mm",
                {"wheel": w.name, "load_N": loads[w.name], "spring_sag_m": sag, "tyre_deflection_m": tyre},
            )
        )
    by_tyre: dict[tuple, list[str]] = {}
    for name, tyre in tyres.items():
        fz0, label = tyre.nominal_load_N, tyre.label
        by_tyre.setdefault((fz0, label), []).append(name)
    for (fz0, label), names in by_tyre.items():
        fz = np.array([loads[n] for n in names])
        findings.append(
            Finding(
                OK if 0.33 <= fz0 / fz.mean() <= 3.0 else WARNING,
                "tyre",
                f"{label} ({', '.join(names)}): nominal load {fz0:.0f} N; static wheel loads {fz.min():.0f} to "
                f"{fz.max():.0f} N",
                {"tyre": label, "wheels": names, "nominal_load_N": fz0, "min_static_load_N": float(fz.min()),
                 "max_static_load_N": float(fz.max())},
            )
        )
    if params.steering.trail_m <= 0:
        findings.append(
            Finding(WARNING, "steering", f"trail {params.steering.trail_m:g} m <= 0: no self-centring", {})
        )
    return _finite(findings)


def _finite(findings: list[Finding]) -> list[Finding]:
    """The findings with every non-finite number replaced by None, and a finding naming each."""
    out = []
    for f in findings:
        bad = [k for k, v in f.values.items() if isinstance(v, float | np.floating) and not math.isfinite(v)]
        if not bad:
            out.append(f)
            continue
        values = {k: (None if k in bad else v) for k, v in f.values.items()}
        out.append(Finding(f.level, f.topic, f.message, values))
        out.append(Finding(INCONSISTENT, f.topic, f"{f.topic}: {', '.join(bad)} could not be computed (not finite)",
                           {"values": bad}))
    return out
