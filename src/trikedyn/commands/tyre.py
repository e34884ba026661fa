"""``trikedyn tyre``: read a tyre property file (``.tir``), evaluate its Magic Formula, plot it.

Signs are ISO (the TYDEX W axes of the property files): a positive slip angle gives a negative lateral
force; see :mod:`trikedyn.tyre.pac2002` for the mapping to trikedyn's own slip-angle sign.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer

from ._common import ForceOpt, JsonOpt, emit, save_figure, within

__all__ = ["forces_cmd", "plot_cmd", "show_cmd", "tyre_app"]

tyre_app = typer.Typer(
    help="Tyre property files (.tir, PAC2002 / MF 5.2 / MF 6.1): show, evaluate the Magic Formula, plot.",
    no_args_is_help=True,
)

SIGN_CONVENTION = ("ISO / TYDEX W axes: x forward, y left, z up; tan(alpha) = Vcy/|Vcx|, so alpha > 0 gives "
                   "Fy < 0 and Mz > 0; kappa > 0 (driving) gives Fx > 0; gamma > 0 leans the wheel top to -y")

TirArg = Annotated[Path, typer.Argument(help="Tyre property file (.tir): PAC2002, MF 5.2 or MF 6.1/6.2.")]
SideOpt = Annotated[
    str | None,
    typer.Option("--side", help="Vehicle side the tyre is mounted on (left or right); mirrored when it differs "
                                "from the file's TYRESIDE. Default: as measured."),
]


def _side(side: str | None) -> str | None:
    from ..errors import InputError

    if side is None:
        return None
    if side.strip().lower() not in ("left", "right"):
        raise InputError(f"must be 'left' or 'right', got {side!r}", where="--side")
    return side.strip().lower()


def _bound(value: float):
    return value if math.isfinite(value) else None


@tyre_app.command("show")
def show_cmd(
    file: TirArg,
    load: Annotated[float | None, typer.Option("--load", callback=within(0, 1e6, "N", above=True),
                                               help="Vertical load [N] for the figures (default: FNOMIN).")] = None,
    side: SideOpt = None,
    as_json: JsonOpt = False,
):
    """Dimensions, format, nominal load, slip stiffnesses, peak friction and forces at a load."""
    from ..tyre import mf_figures, pac2002
    from ..tyre.pac2002_pack import pack
    from ..tyre.tir import read_tir

    tir = read_tir(file)
    side = _side(side)
    fz = tir.fnomin if load is None else float(load)
    packed = pack(tir, side)
    clamped = pac2002.clamped_names(pac2002.mf_forces(fz, 0.0, 0.0, 0.0, 1.0, packed)[5])
    peaks = mf_figures.peak_forces(tir, fz, side=side)
    sigma_k, sigma_a = mf_figures.relaxation_lengths(tir, fz, side=side)
    ky = mf_figures.cornering_stiffness(tir, fz, side=side)
    kx = mf_figures.longitudinal_slip_stiffness(tir, fz, side=side)
    ranges = tir.ranges
    data = {
        "file": str(file), "family": tir.family, "property_file_format": tir.file_format,
        "file_version": tir.file_version, "tyre_side": tir.tyre_side, "mounted_side": side, "use_mode": tir.use_mode,
        "units": dict(tir.units), "dimensions": tir.dimensions, "nominal_load_N": tir.fnomin,
        "unloaded_radius_m": tir.unloaded_radius, "vertical_stiffness_N_per_m": tir.vertical_stiffness,
        "vertical_damping_Ns_per_m": tir.vertical_damping,
        "ranges": {"fz_N": [_bound(v) for v in ranges["fz"]], "kappa": [_bound(v) for v in ranges["kappa"]],
                   "alpha_rad": list(ranges["alpha"]), "gamma_rad": list(ranges["gamma"])},
        "load_N": fz, "clamped": clamped,
        "cornering_stiffness_N_per_rad": ky, "longitudinal_slip_stiffness_N": kx,
        "peak_lateral_force_N": peaks.peak_lateral_N, "peak_longitudinal_force_N": peaks.peak_longitudinal_N,
        "peak_friction_lateral": peaks.mu_y, "peak_friction_longitudinal": peaks.mu_x, "peaks": peaks.to_dict(),
        "relaxation_length_longitudinal_m": sigma_k, "relaxation_length_lateral_m": sigma_a,
        "defaulted": list(tir.defaulted), "ignored_keys": list(tir.ignored_keys),
        "unknown_sections": list(tir.unknown_sections), "notes": list(tir.notes), "sign_convention": SIGN_CONVENTION,
    }

    def text():
        """The text output: the file's family, dimensions and validity ranges, then at the load ``fz`` [N] the
        slip stiffnesses, peak forces [N] and relaxation lengths [m], and the defaulted and ignored keys."""
        d = tir.dimensions
        dims = ", ".join(f"{k.lower().replace('_', ' ')} {v:g}{'' if k == 'ASPECT_RATIO' else ' m'}"
                         for k, v in d.items())
        (flo, fhi), (klo, khi) = ranges["fz"], ranges["kappa"]
        (alo, ahi), (glo, ghi) = ranges["alpha"], ranges["gamma"]
        lines = [
            f"{file}: {tir.family} ({tir.file_format}"
            f"{f', FILE_VERSION {tir.file_version:g}' if tir.file_version is not None else ''}), measured on the "
            f"{tir.tyre_side}{f', mounted {side} (mirrored)' if packed[pac2002.MIRROR] else ''}",
            f"  {dims}" if dims else f"  unloaded radius {tir.unloaded_radius:g} m",
            f"  nominal load FNOMIN {tir.fnomin:g} N; vertical stiffness {tir.vertical_stiffness:g} N/m, "
            f"damping {tir.vertical_damping:g} N s/m",
            f"  valid for Fz {flo:g} to {fhi:g} N, kappa {klo:g} to {khi:g}, alpha {math.degrees(alo):.1f} to "
            f"{math.degrees(ahi):.1f} deg, gamma {math.degrees(glo):.1f} to {math.degrees(ghi):.1f} deg",
            f"at Fz = {fz:g} N, no camber{' (load outside the range: clamped)' if clamped else ''}:",
            f"  cornering stiffness          {ky:12.0f} N/rad ({ky * math.pi / 180:.0f} N/deg; ISO sign)",
            f"  longitudinal slip stiffness  {kx:12.0f} N",
            f"  peak Fx {peaks.fx_max_N:+.0f} N at kappa {peaks.kappa_at_fx_max:+.3f}, {peaks.fx_min_N:+.0f} N at "
            f"kappa {peaks.kappa_at_fx_min:+.3f} (peak friction {peaks.mu_x:.3f})",
            f"  peak Fy {peaks.fy_max_N:+.0f} N at alpha {math.degrees(peaks.alpha_at_fy_max_rad):+.2f} deg, "
            f"{peaks.fy_min_N:+.0f} N at alpha {math.degrees(peaks.alpha_at_fy_min_rad):+.2f} deg "
            f"(peak friction {peaks.mu_y:.3f})",
            "  relaxation lengths: " + ", ".join(
                f"{label} {value:.3f} m" if math.isfinite(value) else f"{label} not in the file"
                for label, value in (("longitudinal", sigma_k), ("lateral", sigma_a))),
            f"defaulted ({len(tir.defaulted)}): {', '.join(tir.defaulted) or 'none'}",
        ]
        if tir.ignored_keys:
            lines.append(f"kept, not used ({len(tir.ignored_keys)}): {', '.join(tir.ignored_keys)}")
        if tir.unknown_sections:
            lines.append(f"unknown sections: {', '.join(tir.unknown_sections)}")
        lines += [f"note: {n}" for n in tir.notes]
        return "\n".join(lines)

    emit(data, as_json, text)


@tyre_app.command("forces")
def forces_cmd(
    file: TirArg,
    load: Annotated[float, typer.Option("--load", callback=within(0, 1e6, "N"), help="Vertical load [N].")],
    slip_angle_deg: Annotated[float, typer.Option("--slip-angle-deg", callback=within(-90, 90, "deg"),
                                                  help="Slip angle [deg], ISO: > 0 when sliding to the left.")] = 0.0,
    slip_ratio: Annotated[float, typer.Option("--slip-ratio", callback=within(-100, 100),
                                              help="Longitudinal slip [-], > 0 driving, -1 locked.")] = 0.0,
    camber_deg: Annotated[float, typer.Option("--camber-deg", callback=within(-90, 90, "deg"),
                                              help="Inclination angle [deg], ISO: > 0 leans the top to the right.")] = 0.0,
    speed: Annotated[float | None, typer.Option("--speed", callback=within(-200, 200, "m/s"),
                                                help="Forward speed [m/s] (default: the file's LONGVL).")] = None,
    side: SideOpt = None,
    as_json: JsonOpt = False,
):
    """Forces and moments of the Magic Formula at one operating point (combined slip, ISO signs)."""
    from ..tyre import pac2002
    from ..tyre.pac2002_pack import pack
    from ..tyre.tir import read_tir

    tir = read_tir(file)
    side = _side(side)
    packed = pack(tir, side)
    vcx = packed[pac2002.LONGVL] if speed is None else float(speed)
    fx, fy, mz, mx, my, mask = pac2002.mf_forces(float(load), float(slip_ratio), math.radians(slip_angle_deg),
                                                 math.radians(camber_deg), vcx, packed)
    clamped = pac2002.clamped_names(mask)
    data = {"file": str(file), "load_N": load, "slip_ratio": slip_ratio, "slip_angle_deg": slip_angle_deg,
            "camber_deg": camber_deg, "speed_mps": vcx, "mounted_side": side, "fx_N": fx, "fy_N": fy, "mz_Nm": mz,
            "mx_Nm": mx, "my_Nm": my, "clamped": clamped, "sign_convention": SIGN_CONVENTION}
    text = (f"Fx {fx:+.1f} N, Fy {fy:+.1f} N, Mz {mz:+.2f} N m, Mx {mx:+.2f} N m, My {my:+.2f} N m "
            f"(ISO signs)" + (f"\nclamped to the file's validity range: {', '.join(clamped)}" if clamped else ""))
    emit(data, as_json, text)


@tyre_app.command("plot")
def plot_cmd(
    file: TirArg,
    out: Annotated[Path, typer.Option("--out", help="Image to write (.png, .pdf, .svg).")],
    side: SideOpt = None,
    force: ForceOpt = False,
    as_json: JsonOpt = False,
):
    """Plot Fy(alpha), Fx(kappa), Mz(alpha) at several loads and the combined-slip friction ellipse."""
    from .._files import check_output
    from ..tyre.mf_figures import plot_characteristics
    from ..tyre.tir import read_tir

    check_output(out, force=force, reads=[file], option="--out")
    tir = read_tir(file)
    save_figure(plot_characteristics(tir, side=_side(side)), out)
    emit({"wrote": str(out)}, as_json, f"wrote {out}")
