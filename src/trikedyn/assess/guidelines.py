"""Guidelines in words, derived from a dossier's results: the speed limit per payload, where to put the freight
and the heavy components, what to change first, and which assumed values to measure.

Pure functions of the assessment's data (:func:`trikedyn.assess.dossier.assess`): nothing is computed anew, so
every number in a guideline is one the dossier shows elsewhere.
"""

from __future__ import annotations

__all__ = ["derive_guidelines", "freight_advice", "measure_advice", "speed_advice", "change_advice"]


def speed_advice(limits: list[dict]) -> list[str]:
    """The speed to print on the vehicle, per payload.

    Parameters
    ----------
    limits : list of dict
        :func:`trikedyn.assess.studies.speed_limits`.

    Returns
    -------
    list of str
        One sentence per payload.
    """
    out = []
    for row in limits:
        failed = row.get("failed_everywhere") or []
        if row["speed_limit_kmh"] is None:
            text = f"With {row['payload_kg']:g} kg of freight no manoeuvre has a threshold: no speed limit can be derived."
        else:
            text = (f"With {row['payload_kg']:g} kg of freight: at most {row['speed_limit_kmh']:.0f} km/h "
                    f"({row['limiting']} threshold {row[row['limiting'] + '_threshold_kmh']:.1f} km/h less "
                    f"{row['margin_kmh']:g} km/h).")
        if failed:
            text += (f" {', '.join(failed)} failed already at the lowest speed searched: the vehicle must not be "
                     "driven through such a manoeuvre at any speed (see the dynamic stability section).")
        out.append(text)
    return out


def freight_advice(positions: list[dict], chart: dict | None, mass_kg: float) -> list[str]:
    """Where to put the freight: the best and worst places by rigid static stability, and by the loading
    chart's safe speed when it was drawn.

    Parameters
    ----------
    positions : list of dict
        :func:`trikedyn.assess.studies.freight_positions`.
    chart : dict or None
        The loading chart's data (``trikedyn loading-chart --json``), or None (``--quick``).
    mass_kg : float
        The freight mass of ``positions`` [kg].

    Returns
    -------
    list of str
        Sentences.
    """
    out = []
    if positions:
        best = max(positions, key=lambda r: r["static_stability_g"])
        worst = min(positions, key=lambda r: r["static_stability_g"])
        lowest = min(r["z_m"] for r in positions)
        where = []
        if best["z_m"] == lowest:
            where.append("as low as the body allows")
        if best["x_m"] != worst["x_m"]:
            where.append("toward the " + ("front" if best["x_m"] > worst["x_m"] else "rear"))
        out.append(f"With {mass_kg:g} kg of freight, the rigid tilt angle is highest with the freight at x = "
                   f"{best['x_m']:.2f} m, z = {best['z_m']:.2f} m ({best['rigid_tilt_angle_deg']:.1f} deg) and "
                   f"lowest at x = {worst['x_m']:.2f} m, z = {worst['z_m']:.2f} m "
                   f"({worst['rigid_tilt_angle_deg']:.1f} deg)" + (f": put freight and heavy modules "
                   f"{' and '.join(where)}." if where else "."))
    cells = [c for c in (chart or {}).get("cells", []) if c.get("safe_speed_kmh") is not None]
    if cells:
        heavy = max(c["freight_kg"] for c in cells)
        at = [c for c in cells if c["freight_kg"] == heavy]
        best = max(at, key=lambda c: c["safe_speed_kmh"])
        worst = min(at, key=lambda c: c["safe_speed_kmh"])
        (bx, bz), (wx, wz) = best["freight_position_m"], worst["freight_position_m"]
        out.append(f"Loading chart (DLC), {heavy:g} kg: safe speed {best['safe_speed_kmh']:.1f} km/h with the freight "
                   f"at x = {bx:.2f} m, z = {bz:.2f} m, {worst['safe_speed_kmh']:.1f} km/h at "
                   f"x = {wx:.2f} m, z = {wz:.2f} m.")
    return out


def change_advice(changes: list[dict]) -> list[str]:
    """What to change first: the design changes ranked by the DLC threshold they gain, then by tilt angle.

    Parameters
    ----------
    changes : list of dict
        :func:`trikedyn.assess.studies.design_changes`.

    Returns
    -------
    list of str
        The ranking in sentences, the best first.
    """
    done = [c for c in changes if "new_tilt_angle_deg" in c]
    ranked = sorted(done, key=lambda c: (c["dlc_gain_kmh"] if c["dlc_gain_kmh"] is not None else float("-inf"),
                                         c["tilt_gain_deg"]), reverse=True)
    out = []
    for k, c in enumerate(ranked, 1):
        dlc = "no DLC threshold" if c["dlc_gain_kmh"] is None else f"{c['dlc_gain_kmh']:+.1f} km/h DLC threshold"
        out.append(f"{k}. {c['change']}: {dlc}, {c['tilt_gain_deg']:+.1f} deg tilt angle.")
    out += [f"{c['change']}: not possible on this vehicle ({c['error']})." for c in changes if "new_tilt_angle_deg" not in c]
    return out


def measure_advice(sensitivity: dict | None, top: int = 3) -> list[str]:
    """Which assumed values to measure first: the top of the sensitivity ranking, and what it would buy.

    Parameters
    ----------
    sensitivity : dict or None
        ``trikedyn sensitivity --json`` (Morris), or None (``--quick``).
    top : int
        How many.

    Returns
    -------
    list of str
        Sentences; one saying the study was left out when ``sensitivity`` is None.
    """
    if not sensitivity:
        return ["The sensitivity was left out (--quick): run without --quick to rank the assumed values."]
    out = []
    for k, row in enumerate(sensitivity["indices"][:top], 1):
        out.append(f"{k}. {row['parameter']}: over its assumed range it moves the DLC threshold by mu* = "
                   f"{row['mu_star']:.1f} km/h on average; measuring it removes that much doubt from the threshold.")
    return out


def derive_guidelines(data: dict) -> dict:
    """Every guideline of a dossier.

    Parameters
    ----------
    data : dict
        The assessment (``speed_limits``, ``freight_positions``, ``freight_mass_kg``, ``loading_chart``,
        ``design_changes``, ``sensitivity``).

    Returns
    -------
    dict
        ``speed``, ``freight``, ``changes``, ``measure``: lists of sentences.
    """
    return {"speed": speed_advice(data["speed_limits"]),
            "freight": freight_advice(data["freight_positions"], data.get("loading_chart"), data["freight_mass_kg"]),
            "changes": change_advice(data["design_changes"]),
            "measure": measure_advice(data.get("sensitivity"))}
