"""Consistency audit of a parameter set (``trikedyn vehicle check``).

What a careful engineer checks before trusting a parameter set, each as a :class:`Finding` with numbers:

* damping against Eq. 4, ``C = 2 xi sqrt(K M_s)``, where the set gives the measured ``xi`` and ``f_n``;
* the sprung masses that ``K`` and ``f_n`` imply (Eq. 3) against those that the masses and the CG imply
  (static axle loads less the unsprung masses), and the CG position that Eq. 3 would imply;
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
from dataclasses import asdict, dataclass, field

import numpy as np

from ..units import STANDARD_GRAVITY
from .io import ParameterSet
from .ops import mass_properties, static_wheel_loads, unsprung_mass  # the last two re-exported
from .schema import VehicleParameters

__all__ = ["Finding", "audit", "static_wheel_loads", "tip_over_thresholds", "unsprung_mass"]

OK, NOTE, WARNING, INCONSISTENT = "ok", "note", "warning", "inconsistent"


@dataclass(frozen=True)
class Finding:
    """One audit finding: its level, topic, a one-line message and the numbers behind it."""

    level: str
    topic: str
    message: str
    values: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return asdict(self)


def _tyre_of(params: VehicleParameters, wheel) -> tuple[float, float, str]:
    """Vertical stiffness [N/m], nominal load [N] and a label of one wheel's tyre: its ``.tir`` file, or the
    ``[tyre]`` section's Magic Formula."""
    if wheel.tyre_file is None:
        return params.tyre.vertical_stiffness_N_per_m, params.tyre.nominal_load_N, "Magic Formula of [tyre]"
    from pathlib import Path

    from ..tyre.tir import read_tir

    tir = read_tir(wheel.tyre_file)
    kz = tir.coefficients.get("VERTICAL_STIFFNESS", 0.0) or params.tyre.vertical_stiffness_N_per_m
    return kz, tir.coefficients["FNOMIN"], f"{Path(wheel.tyre_file).name} ({tir.family})"


def tip_over_thresholds(params: VehicleParameters) -> list[dict]:
    """Rigid-vehicle static tip-over per edge of the support triangle.

    For each edge: the CG projection's perpendicular distance to it [m] (negative when outside), the
    lateral distance along y [m], and the lateral acceleration that tips the vehicle about it,
    ``a_y / g = d_y / h`` (edges with no y component are tipped by longitudinal acceleration instead,
    ``a_x / g = d_x / h``).

    It holds for either layout: for a CG on the centre line at height ``h``, ``d`` from the single wheel's
    axle along x, with wheelbase ``L`` and track ``T``, each side edge gives ``a_y / g = d T / (2 h L)``
    (``d`` behind the front wheel of a delta, ahead of the rear wheel of a tadpole).
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
    """Audit a parameter set for consistency; see the module docstring for the checks."""
    params = pset.params if isinstance(pset, ParameterSet) else pset
    g = STANDARD_GRAVITY
    findings: list[Finding] = []
    loads = static_wheel_loads(params, g)
    mp = mass_properties(params)
    total_kg, cg_x = mp.mass_kg, float(mp.cg_m[0])
    two_pi = 2.0 * math.pi

    # 1. Eq. 4 and Eq. 3 per suspension, and the sprung masses
    implied = {}
    for w in params.wheels:
        s = params.suspension[w.suspension]
        from_cg = loads[w.name] / g - unsprung_mass(params, w.name)
        row = {"wheel": w.name, "sprung_mass_from_cg_kg": from_cg}
        positive = from_cg > 0
        if s.natural_frequency_hz is not None:
            m_eq3 = s.stiffness_N_per_m / (two_pi * s.natural_frequency_hz) ** 2
            row["sprung_mass_eq3_kg"] = m_eq3
            row["ratio_eq3_to_cg"] = m_eq3 / from_cg if positive else None
            implied[w.name] = m_eq3 + unsprung_mass(params, w.name)
        else:
            row["natural_frequency_from_cg_hz"] = math.sqrt(s.stiffness_N_per_m / from_cg) / two_pi if positive else None
        ratio = row.get("ratio_eq3_to_cg")
        level = OK if positive and (ratio is None or abs(ratio - 1) <= 0.10) else INCONSISTENT
        msg = (
            f"{w.name}: sprung mass {from_cg:.1f} kg from masses and CG"
            + ("" if positive else " (not positive: the CG is outside the support or the unsprung parts are too heavy)")
            + (f", {row['sprung_mass_eq3_kg']:.1f} kg from K and f_n (Eq. 3)" if "sprung_mass_eq3_kg" in row else "")
            + (f"; with K: f_n = {row['natural_frequency_from_cg_hz']:.2f} Hz"
               if row.get("natural_frequency_from_cg_hz") is not None else "")
            + (f", ratio {ratio:.2f}" if ratio is not None else "")
        )
        findings.append(Finding(level, "sprung mass", msg, row))

    for name, s in params.suspension.items():
        if s.natural_frequency_hz is None or s.damping_ratio is None:
            continue
        m_s = s.stiffness_N_per_m / (two_pi * s.natural_frequency_hz) ** 2
        c_eq4 = 2.0 * s.damping_ratio * math.sqrt(s.stiffness_N_per_m * m_s)
        given = s.damping_Ns_per_m
        ratio = c_eq4 / given if given > 0 else (1.0 if c_eq4 == 0 else None)
        xi_actual = given / (2.0 * math.sqrt(s.stiffness_N_per_m * m_s))
        level = OK if ratio is not None and abs(ratio - 1) <= 0.05 else INCONSISTENT
        findings.append(
            Finding(
                level,
                "damping (Eq. 4)",
                f"{name}: C = {given:.2f} N s/m, Eq. 4 gives 2 xi sqrt(K M_s) = {c_eq4:.2f} N s/m "
                f"(xi = {s.damping_ratio:.2f}, M_s = {m_s:.2f} kg): "
                + (f"{ratio:.2f}x" if ratio is not None else "no damper given")
                + f"; the C given means xi = {xi_actual:.3f}",
                {
                    "suspension": name,
                    "damping_Ns_per_m": s.damping_Ns_per_m,
                    "damping_eq4_Ns_per_m": c_eq4,
                    "ratio_eq4_to_given": ratio,
                    "sprung_mass_eq3_kg": m_s,
                    "damping_ratio_stated": s.damping_ratio,
                    "damping_ratio_of_given_C": xi_actual,
                },
            )
        )

    # 2. the CG that Eq. 3 implies (front share of the axle loads; the front wheels are the steered ones, the
    # rear axle at x = 0 in either layout, so the CG is that share of the wheelbase ahead of the rear axle)
    front = [w for w in params.wheels if w.steered]
    if implied and len(implied) == len(params.wheels) and front:
        total = sum(implied.values())
        share = sum(implied[w.name] for w in front) / total
        x_eq3 = share * params.wheelbase_m
        level = OK if abs(x_eq3 - cg_x) <= 0.02 * params.wheelbase_m else INCONSISTENT
        findings.append(
            Finding(
                level,
                "CG from Eq. 3",
                f"K and f_n imply {total:.1f} kg on the wheels with {100 * share:.1f} % on the front, "
                f"i.e. CG x = {x_eq3:.3f} m; the set has {total_kg:.1f} kg and CG x = "
                f"{cg_x:.4f} m ({100 * cg_x / params.wheelbase_m:.1f} % front)",
                {
                    "mass_eq3_kg": total,
                    "front_share_eq3": share,
                    "cg_x_eq3_m": x_eq3,
                    "mass_kg": total_kg,
                    "cg_x_m": cg_x,
                },
            )
        )

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
    heads = len(front)  # the model builds one steering head per steered wheel
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
    tyres = {w.name: _tyre_of(params, w) for w in params.wheels}
    for w in params.wheels:
        s = params.suspension[w.suspension]
        sprung = loads[w.name] - unsprung_mass(params, w.name) * g
        sag = sprung / s.stiffness_N_per_m
        tyre = loads[w.name] / tyres[w.name][0]
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
    for name, (_, fz0, label) in tyres.items():
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
