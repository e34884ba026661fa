"""The measured values' standard deviations of an uncertainty run (:mod:`trikedyn.study.designs.uncertainty`),
read from the measurements themselves: a weighing file (:func:`weighing_stds`) and the JSON of ``trikedyn
identify`` (:func:`identification_stds`); :func:`measured_stds` gathers them for a vehicle.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from ...errors import InputError, did_you_mean
from ...params.io import ParameterSet

__all__ = ["IDENTIFICATION_KEYS", "Measured", "identification_stds", "measured_stds", "weighing_stds"]


# ------------------------------------------------------------------------------------------------
# measured sigmas: a weighing file, an identification
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Measured:
    """A measured value's standard deviation and where it came from.

    Attributes
    ----------
    path : str
        The vehicle's parameter (``mass.cg_z_m``, ``suspension.front.stiffness_N_per_m``).
    std : float
        Its standard deviation [the parameter's unit].
    measured : float
        The value the measurement gave (the vehicle's own value is the mean sampled about).
    source : str
        The file and what in it (``weighing.toml: tilted weighings``).
    """

    path: str
    std: float
    measured: float
    source: str

    def to_dict(self) -> dict:
        """The measured sigma as JSON-ready values.

        Returns
        -------
        dict
            ``parameter``, ``std`` [parameter unit], ``measured``, ``source``.
        """
        return {"parameter": self.path, "std": self.std, "measured": self.measured, "source": self.source}


def weighing_stds(path: str | Path) -> list[Measured]:
    """The CG's standard deviations from a weighing file (:mod:`trikedyn.measure.weighing`): x and y from
    the level weighing (the readings' ``reading_std_kg``), z from the ``[[tilted]]`` weighings if any.

    Parameters
    ----------
    path : str or Path
        The weighing file.

    Returns
    -------
    list of Measured
        CG sigmas [m].

    Raises
    ------
    InputError
        ``where=FILE``: the file cannot be read or reduced, or it gives no uncertainty (``reading_std_kg = 0``
        and no scatter).
    """
    from ...measure.weighing import load_weighing, reduce_weighing

    where = str(path)
    result = reduce_weighing(load_weighing(path), where=where)
    lvl = result.level
    found = [Measured("mass.cg_x_m", float(lvl.cg_x_std_m), float(lvl.cg_x_m), f"{where}: level weighing"),
             Measured("mass.cg_y_m", float(lvl.cg_y_std_m), float(lvl.cg_y_m), f"{where}: level weighing")]
    if result.height is not None:
        found.append(Measured("mass.cg_z_m", float(result.height.cg_z_std_m), float(result.height.cg_z_m),
                              f"{where}: tilted weighings"))
    found = [m for m in found if math.isfinite(m.std) and m.std > 0]
    if not found:
        raise InputError("gives the CG without an uncertainty (reading_std_kg = 0 and no scatter): no sigma to "
                         "sample; give reading_std_kg", where=where)
    return found


IDENTIFICATION_KEYS = ("natural_frequency_hz", "natural_frequency_std_hz", "damping_ratio", "damping_ratio_std",
                       "sprung_mass_kg", "stiffness_N_per_m", "damping_Ns_per_m")
"""The keys of an identification's JSON (``trikedyn identify --json``) that its K and C sigmas come from."""


def _identification_file(path: Path) -> Path:
    """The identification JSON: the file itself, or the one ``*.json`` file of a folder."""
    if path.is_dir():
        found = sorted(path.glob("*.json"))
        if len(found) != 1:
            raise InputError(f"expected a folder with one identification JSON, found {len(found)} .json files",
                             where=str(path))
        return found[0]
    return path


def identification_stds(path: str | Path, suspension: str) -> list[Measured]:
    """K and C of suspension ``suspension`` with their standard deviations, from the JSON that ``trikedyn identify
    --json`` writes (a file, or a folder holding one).

    The identification gives the standard errors of the natural frequency and damping ratio (``*_std``); K and
    C are functions of them (Eqs. 3-4, or the quarter car with the tyre in series when ``tyre_stiffness_N_per_m``
    was given: :func:`~trikedyn.measure.suspension.suspension_from_body_mode`), so their sigmas follow to first
    order, f_n and xi taken as independent.

    Parameters
    ----------
    path : str or Path
        The identification JSON, or a folder holding one.
    suspension : str
        The suspension it measured.

    Returns
    -------
    list of Measured
        K [N/m] and C [N s/m] with their sigmas.

    Raises
    ------
    InputError
        ``where=FILE``: not a readable JSON object, a key missing or not a finite number, no uncertainty.
    """
    from ...measure.suspension import damping_coefficient, stiffness_from_frequency, suspension_from_body_mode
    from ...params.tomlfile import is_file, read_text

    file = _identification_file(Path(path))
    where = str(file)
    if not is_file(file):
        raise InputError("no such identification file (the JSON of `trikedyn identify --json`)", where=where)
    text = read_text(file, where)  # at most MAX_FILE_BYTES
    try:
        data = json.loads(text)
    except ValueError as exc:
        raise InputError(f"not JSON ({exc.msg} at line {exc.lineno}); expected the output of `trikedyn identify "
                         "--json`", where=where) from None
    if not isinstance(data, dict):
        raise InputError("expected a JSON object (the output of `trikedyn identify --json`)", where=where)
    values = {}
    for key in IDENTIFICATION_KEYS:
        value = data.get(key)
        if value is None and key.endswith("_std"):
            raise InputError(f"{key}: no uncertainty in this identification (the fit gave none)", where=where)
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise InputError(f"{key}: expected a finite number, got {value!r} (is this the JSON of `trikedyn "
                             "identify --json`?)", where=where)
        values[key] = float(value)
    kt = data.get("tyre_stiffness_N_per_m")
    if kt is not None and (isinstance(kt, bool) or not isinstance(kt, int | float) or not kt > 0):
        raise InputError(f"tyre_stiffness_N_per_m: expected a number > 0 or null, got {kt!r}", where=where)
    extra = {}  # the tyre's damping and the unsprung mass, when the identification had them (exact quarter car)
    for key, name in (("tyre_damping_Ns_per_m", "tyre_damping"), ("unsprung_mass_kg", "unsprung_mass_kg")):
        value = data.get(key)
        if value is not None:
            if isinstance(value, bool) or not isinstance(value, int | float) or not (math.isfinite(value) and value >= 0):
                raise InputError(f"{key}: expected a number >= 0 or null, got {value!r}", where=where)
            extra[name] = float(value)
    f, xi, m = values["natural_frequency_hz"], values["damping_ratio"], values["sprung_mass_kg"]
    sf, sxi = values["natural_frequency_std_hz"], values["damping_ratio_std"]
    if not (f > 0 and 0 < xi < 1 and m > 0 and sf >= 0 and sxi >= 0):
        raise InputError(f"expected f_n > 0, 0 < xi < 1, a sprung mass > 0 and sigmas >= 0; got f_n = {f:g} Hz, "
                         f"xi = {xi:g}, M_s = {m:g} kg", where=where)

    def kc(fn, z):
        """Suspension stiffness [N/m] and damping [N s/m] giving the sprung mass a body mode of ``fn`` [Hz] and
        damping ratio ``z`` (through the tyre when its stiffness is known)."""
        if kt is None:
            k = stiffness_from_frequency(fn, m)
            return float(k), float(damping_coefficient(z, k, m))
        k, c = suspension_from_body_mode(fn, z, m, float(kt), **extra)
        return float(k), float(c)

    hf, hxi = 1e-6 * f, 1e-6 * max(xi, 1e-3)
    (kf1, cf1), (kf0, cf0) = kc(f + hf, xi), kc(f - hf, xi)
    (kx1, cx1), (kx0, cx0) = kc(f, xi + hxi), kc(f, xi - hxi)
    std_k = math.hypot((kf1 - kf0) / (2 * hf) * sf, (kx1 - kx0) / (2 * hxi) * sxi)
    std_c = math.hypot((cf1 - cf0) / (2 * hf) * sf, (cx1 - cx0) / (2 * hxi) * sxi)
    if not (std_k > 0 and std_c > 0):
        raise InputError("no uncertainty in this identification (natural_frequency_std_hz and damping_ratio_std "
                         "are 0)", where=where)
    how = f"identified f_n = {f:.3f} +/- {sf:.3g} Hz, xi = {xi:.3f} +/- {sxi:.3g}"
    return [Measured(f"suspension.{suspension}.stiffness_N_per_m", std_k, values["stiffness_N_per_m"],
                     f"{where}: {how}"),
            Measured(f"suspension.{suspension}.damping_Ns_per_m", std_c, values["damping_Ns_per_m"],
                     f"{where}: {how}")]


def _suspension_of(pset: ParameterSet, item: str) -> tuple[str, str]:
    """``[NAME=]FILE`` of ``--identification`` -> (suspension name, file)."""
    names = list(pset.params.suspension)
    name, sep, file = str(item).partition("=")
    if sep and name.strip() in names:
        return name.strip(), file.strip()
    if sep and "/" not in name and "." not in name:  # NAME=FILE with an unknown NAME
        tip = did_you_mean(name.strip(), names)
        raise InputError(f"no suspension '{name.strip()}' on this vehicle{tip} (it has {', '.join(names)})",
                         where="--identification")
    if len(names) == 1:
        return names[0], str(item)
    raise InputError(f"name the suspension the file identifies: NAME=FILE, NAME one of {', '.join(names)} "
                     f"(e.g. {names[0]}={item})", where="--identification")


def measured_stds(pset: ParameterSet, weighing: str | Path | None = None, identifications: Iterable[str] = (),
                  ) -> list[Measured]:
    """The measured sigmas from a weighing file and identifications (``[NAME=]FILE``, NAME a suspension of the
    vehicle, needed when it has more than one), in that order; a path measured twice keeps the last.

    Parameters
    ----------
    pset : ParameterSet
        The vehicle.
    weighing : str or Path, optional
        A weighing file.
    identifications : iterable of str
        ``[NAME=]FILE`` items.

    Returns
    -------
    list of Measured
        The sigmas.
    """
    found: dict[str, Measured] = {}
    if weighing is not None:
        found.update((m.path, m) for m in weighing_stds(weighing))
    for item in identifications:
        name, file = _suspension_of(pset, item)
        found.update((m.path, m) for m in identification_stds(file, name))
    return list(found.values())
