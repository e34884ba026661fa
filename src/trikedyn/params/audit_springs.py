"""The audit of the springs (part of :func:`trikedyn.params.audit.audit`): Eq. 3 with the tyre in series, Eq. 4,
and the CG that Eq. 3 implies.

The vehicle file's K and C are the suspension's own, the tyre in series (:mod:`trikedyn.params.springs`). Per
wheel with a measured ``natural_frequency_hz``, the sprung mass that K and f_n imply is found twice:

* with the tyre in series (the model's quarter car, :class:`~trikedyn.params.springs.QuarterCar`: K, C, the
  tyre's K_t and C_t, the unsprung mass): the check, ``|M_series / M_cg - 1| <= 10 %``;
* by the paper's rigid-tyre Eq. 3, ``M_s = K / (2 pi f_n)^2``: reported beside it.

A K that fits the rigid-tyre Eq. 3 and not the series is *tyre-inclusive* (how the paper, and its Table 1
in the presets, give K): a warning, with the bounce the model will have and the suspension's own spring
that f_n needs. Neither fits: inconsistent. Eq. 4 and the CG from Eq. 3 then follow each suspension's
reading (the series where K reads as the suspension's own or fits neither, the rigid tyre where it reads
as tyre-inclusive), so one cause is flagged once.
"""

from __future__ import annotations

import math

from .findings import INCONSISTENT, OK, WARNING, Finding
from .schema import VehicleParameters
from .springs import suspension_quarter_car, wheel_quarter_car

__all__ = ["MASS_TOLERANCE", "DAMPING_TOLERANCE", "CG_TOLERANCE", "spring_findings"]

MASS_TOLERANCE = 0.10
"""Largest relative difference of the sprung masses from Eq. 3 and from the masses and the CG."""

DAMPING_TOLERANCE = 0.05
"""Largest relative difference of the damping given and the damping Eq. 4 gives."""

CG_TOLERANCE = 0.02
"""Largest difference of the CG x that Eq. 3 implies from the set's, as a share of the wheelbase."""

SERIES, RIGID = "series", "rigid tyre"


def _ratio(a, b):
    return a / b if a is not None and b > 0 else None


def _close(ratio, tolerance):
    return ratio is not None and abs(ratio - 1.0) <= tolerance


def _reading(params: VehicleParameters, name: str) -> str | None:
    """How the K of suspension ``name`` reads against its f_n: SERIES (the suspension's own spring), RIGID
    (tyre-inclusive) or None (neither, or no f_n), on the suspension's quarter car (its wheels' mean sprung
    mass); where both fit within the tolerance, the closer (on the springs soft against the tyre)."""
    s = params.suspension[name]
    if s.natural_frequency_hz is None:
        return None
    car = suspension_quarter_car(params, name)
    if not car.sprung_mass_kg > 0:
        return None
    gaps = {}
    m_series = car.sprung_mass_for(s.natural_frequency_hz)
    if m_series is not None:
        gaps[SERIES] = abs(m_series / car.sprung_mass_kg - 1.0)
    gaps[RIGID] = abs(s.stiffness_N_per_m / (2 * math.pi * s.natural_frequency_hz) ** 2 / car.sprung_mass_kg - 1.0)
    fits = [r for r in (SERIES, RIGID) if r in gaps and gaps[r] <= MASS_TOLERANCE]
    return min(fits, key=gaps.get) if fits else None


def _sprung_mass(params: VehicleParameters, wheel, reading: str | None) -> tuple[Finding, float | None]:
    """The sprung-mass finding of one wheel, in its suspension's reading, and the sprung mass K and f_n imply
    in that reading (with the tyre in series when K fits neither)."""
    s = params.suspension[wheel.suspension]
    car = wheel_quarter_car(params, wheel.name)
    m_cg, kt = car.sprung_mass_kg, car.tyre_stiffness_N_per_m
    row = {"wheel": wheel.name, "sprung_mass_from_cg_kg": m_cg, "unsprung_mass_kg": car.unsprung_mass_kg,
           "tyre_stiffness_N_per_m": kt}
    positive = m_cg > 0
    start = (f"{wheel.name}: sprung mass {m_cg:.1f} kg from masses and CG"
             + ("" if positive else " (not positive: the CG is outside the support or the unsprung parts are too "
                                    "heavy)"))
    f_model, _ = car.body_mode()
    f = s.natural_frequency_hz
    if f is None:
        f_rigid = math.sqrt(s.stiffness_N_per_m / m_cg) / (2 * math.pi) if positive else None
        row |= {"natural_frequency_from_cg_hz": f_model if positive else None,
                "natural_frequency_rigid_tyre_hz": f_rigid}
        tail = (f"; with K the model's quarter car bounces at {f_model:.2f} Hz (the tyre in series; "
                f"{f_rigid:.2f} Hz by the paper's rigid-tyre Eq. 3)" if positive else "")
        return Finding(OK if positive else INCONSISTENT, "sprung mass", start + tail, row), None
    m_rigid = s.stiffness_N_per_m / (2 * math.pi * f) ** 2
    m_series = car.sprung_mass_for(f)
    r_rigid, r_series = _ratio(m_rigid, m_cg), _ratio(m_series, m_cg)
    row |= {"reading": reading, "sprung_mass_eq3_kg": m_rigid, "ratio_eq3_to_cg": r_rigid,
            "sprung_mass_series_kg": m_series, "ratio_series_to_cg": r_series,
            "natural_frequency_model_hz": f_model if positive else None}
    series = (f"{m_series:.1f} kg from K and f_n with the tyre in series (Eq. 3" if m_series is not None
              else "no sprung mass from K and f_n with the tyre in series (f_n above what this spring and tyre "
                   "can give; Eq. 3")
    series += f", ratio {r_series:.2f})" if r_series is not None else ")"
    rigid = f"{m_rigid:.1f} kg by the paper's rigid-tyre Eq. 3" + (f" (ratio {r_rigid:.2f})" if r_rigid else "")
    if reading == RIGID:
        xi = s.damping_ratio if s.damping_ratio is not None else car.body_mode()[1]
        own = own_c = None
        if positive:
            from ..measure.suspension import suspension_from_body_mode  # scipy.signal: only when needed

            own, own_c = (float(v) for v in suspension_from_body_mode(
                f, xi, m_cg, kt, tyre_damping=car.tyre_damping_Ns_per_m, unsprung_mass_kg=car.unsprung_mass_kg))
            own, own_c = (own, own_c) if own > 0 and own_c >= 0 else (None, None)
        row |= {"stiffness_own_for_frequency_N_per_m": own, "damping_own_for_frequency_Ns_per_m": own_c}
        need = (f"the suspension's own spring and damper for {f:g} Hz and xi {xi:.3g} are {own:.0f} N/m and "
                f"{own_c:.0f} N s/m" if own is not None else f"no spring in series with this tyre gives {f:g} Hz")
        level = WARNING if positive and _close(r_rigid, MASS_TOLERANCE) else INCONSISTENT
        message = (f"{start}, {rigid} but {series}: K reads as tyre-inclusive; the model adds the tyre "
                   f"({kt:.0f} N/m) in series, so its quarter car bounces at {f_model:.2f} Hz, not {f:g} Hz ({need}; "
                   "`trikedyn identify --into` writes them)")
        return Finding(level, "sprung mass", message, row), m_rigid
    level = OK if positive and _close(r_series, MASS_TOLERANCE) else INCONSISTENT
    return Finding(level, "sprung mass", f"{start}, {series}; {rigid}", row), m_series


def _damping(params: VehicleParameters, name: str, reading: str) -> Finding:
    """Eq. 4 of one suspension with a measured f_n and xi, in its reading."""
    s = params.suspension[name]
    f, xi, k, given = s.natural_frequency_hz, s.damping_ratio, s.stiffness_N_per_m, s.damping_Ns_per_m
    m_rigid = k / (2.0 * math.pi * f) ** 2
    c_eq4 = 2.0 * xi * math.sqrt(k * m_rigid)
    r_rigid = c_eq4 / given if given > 0 else (1.0 if c_eq4 == 0 else None)
    xi_rigid = given / (2.0 * math.sqrt(k * m_rigid))
    wheel = next(w for w in params.wheels if w.suspension == name)
    car = wheel_quarter_car(params, wheel.name)
    m_series = car.sprung_mass_for(f)
    c_series = xi_series = r_series = None
    if m_series is not None:
        from ..measure.suspension import suspension_from_body_mode

        _, c = suspension_from_body_mode(f, xi, m_series, car.tyre_stiffness_N_per_m,
                                         tyre_damping=car.tyre_damping_Ns_per_m, unsprung_mass_kg=car.unsprung_mass_kg)
        c_series = float(c)
        xi_series = car.body_mode(m_series)[1]
        r_series = c_series / given if given > 0 else (1.0 if c_series == 0 else None)
    values = {"suspension": name, "reading": reading, "damping_Ns_per_m": given, "damping_eq4_Ns_per_m": c_eq4,
              "ratio_eq4_to_given": r_rigid, "sprung_mass_eq3_kg": m_rigid, "damping_ratio_stated": xi,
              "damping_ratio_of_given_C": xi_rigid, "damping_series_Ns_per_m": c_series,
              "ratio_series_to_given": r_series, "sprung_mass_series_kg": m_series,
              "damping_ratio_model": xi_series}
    paper = (f"Eq. 4 gives 2 xi sqrt(K M_s) = {c_eq4:.2f} N s/m (xi = {xi:.2f}, M_s = {m_rigid:.2f} kg by the paper's "
             "rigid-tyre Eq. 3)")
    if reading == RIGID or m_series is None:
        ratio = r_rigid
        message = (f"{name}: C = {given:.2f} N s/m, {paper}: "
                   + (f"{ratio:.2f}x" if ratio is not None else "no damper given")
                   + f"; the C given means xi = {xi_rigid:.3f}"
                   + (" (K read as tyre-inclusive)" if reading == RIGID else " (no sprung mass in series)"))
    else:
        ratio = r_series
        message = (f"{name}: C = {given:.2f} N s/m; with the tyre in series, f_n = {f:g} Hz, xi = {xi:.3g} and "
                   f"M_s = {m_series:.2f} kg need C = {c_series:.2f} N s/m: "
                   + (f"{ratio:.2f}x" if ratio is not None else "no damper given")
                   + f"; the C given means xi = {xi_series:.3f}; the paper's rigid-tyre {paper}")
    level = OK if _close(ratio, DAMPING_TOLERANCE) else INCONSISTENT
    return Finding(level, "damping (Eq. 4)", message, values)


def spring_findings(params: VehicleParameters, total_kg: float, cg_x: float) -> list[Finding]:
    """The sprung-mass finding of each wheel, Eq. 4 of each suspension with a measured f_n and xi, and the CG
    x that Eq. 3 implies (each suspension in its reading) against ``cg_x`` [m] of the ``total_kg`` [kg] set.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    total_kg : float
        Total mass of the set [kg].
    cg_x : float
        CG x of the set [m].

    Returns
    -------
    list of Finding
        The findings.
    """
    readings = {name: _reading(params, name) for name in params.suspension
                if any(w.suspension == name for w in params.wheels)}
    findings, implied = [], {}
    for w in params.wheels:
        finding, mass = _sprung_mass(params, w, readings[w.suspension])
        findings.append(finding)
        if mass is not None:
            implied[w.name] = mass + finding.values["unsprung_mass_kg"]
    for name, reading in readings.items():
        s = params.suspension[name]
        if s.natural_frequency_hz is not None and s.damping_ratio is not None:
            findings.append(_damping(params, name, reading or SERIES))
    # the CG that Eq. 3 implies: the front share of the wheel loads (the steered wheels are the front ones, the
    # rear axle at x = 0 in either layout, so the CG is that share of the wheelbase ahead of the rear axle)
    front = [w for w in params.wheels if w.steered]
    if len(implied) == len(params.wheels) and front:
        total = sum(implied.values())
        share = sum(implied[w.name] for w in front) / total
        x_eq3 = share * params.wheelbase_m
        rigid = [name for name, r in readings.items() if r == RIGID]
        how = ("by the paper's rigid-tyre Eq. 3 (K reads as tyre-inclusive)" if len(rigid) == len(readings) else
               "with the tyre in series" + (f" ({', '.join(rigid)} by the rigid-tyre Eq. 3, as its K reads)"
                                            if rigid else ""))
        level = OK if abs(x_eq3 - cg_x) <= CG_TOLERANCE * params.wheelbase_m else INCONSISTENT
        findings.append(Finding(
            level, "CG from Eq. 3",
            f"K and f_n imply {total:.1f} kg on the wheels {how} with {100 * share:.1f} % on the front, i.e. CG x = "
            f"{x_eq3:.3f} m; the set has {total_kg:.1f} kg and CG x = {cg_x:.4f} m "
            f"({100 * cg_x / params.wheelbase_m:.1f} % front)",
            {"mass_eq3_kg": total, "front_share_eq3": share, "cg_x_eq3_m": x_eq3, "mass_kg": total_kg,
             "cg_x_m": cg_x, "readings": dict(readings)},
        ))
    return findings
