"""One convention for the spring, from the bump test to the model, and the quarter car of each wheel.

**The convention.** A vehicle file's ``[suspension.NAME]`` ``stiffness_N_per_m`` and ``damping_Ns_per_m``
are the suspension's *own* spring and damper, as wheel rates (vertical, at the wheel). The tyre is not in
them: it is in series, with the vertical stiffness and damping of the wheel's tyre (the ``[tyre]`` section,
or the wheel's ``.tir`` file), and the model adds it.

A bump test measures the body mode of the spring and the tyre together. The paper's Eq. 3,
``K = 4 pi^2 f_n^2 M_s``, takes the tyre as rigid (section 2.1: "assumed to be negligible"), so the ``K`` it
gives is *tyre-inclusive*: about ``K_eq``, ``1/K_eq = 1/K_s + 1/K_t``. Written into a vehicle file, a
tyre-inclusive ``K`` makes the model too soft (the model puts the tyre in series once more): 20 % on an
80 kN/m spring on a 200 kN/m tyre. ``trikedyn identify --tyre-stiffness`` (or ``--into FILE``, which
takes the file's tyre) takes the tyre out, and the audit (``trikedyn vehicle check``) checks Eq. 3 with
the tyre in series, the paper's rigid-tyre Eq. 3 reported beside it.

**The quarter car of a wheel** (:func:`wheel_quarter_car`), the model both use: the sprung mass is the
wheel's static load (from the masses and the CG, :func:`~trikedyn.params.ops.static_wheel_loads`) over g
less its unsprung mass (:func:`~trikedyn.params.ops.unsprung_mass`: the wheel plus the fork slider, or
plus half the swing arm); the suspension's K and C join it to the unsprung mass, the tyre's K_t and C_t
join that to the road (:mod:`trikedyn.measure.quarter_car`). Its body mode is the bounce the bump test
sees; the multibody model's own bounce mode (``trikedyn modes``) couples the wheels through the chassis'
pitch and roll, so it differs from each wheel's quarter car.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..units import STANDARD_GRAVITY
from .ops import static_wheel_loads, unsprung_mass
from .schema import VehicleParameters

__all__ = ["QuarterCar", "TyreOfWheel", "series_stiffness", "suspension_quarter_car", "wheel_quarter_car",
           "wheel_tyre"]


def series_stiffness(stiffness_N_per_m: float, tyre_stiffness_N_per_m: float) -> float:
    """Stiffness [N/m] of the suspension's spring and the tyre in series, ``1/K_eq = 1/K_s + 1/K_t``.

    Parameters
    ----------
    stiffness_N_per_m : float
        Suspension stiffness at the wheel [N/m].
    tyre_stiffness_N_per_m : float
        Tyre vertical stiffness [N/m].

    Returns
    -------
    float
        [N/m].
    """
    return 1.0 / (1.0 / stiffness_N_per_m + 1.0 / tyre_stiffness_N_per_m)


@dataclass(frozen=True)
class TyreOfWheel:
    """The vertical spring and damper of one wheel's tyre, as the model has them.

    Attributes
    ----------
    stiffness_N_per_m, damping_Ns_per_m : float
        Vertical stiffness [N/m] and damping [N s/m].
    nominal_load_N : float
        The Magic Formula's nominal load Fz0 [N].
    label : str
        Where they come from: ``"Magic Formula of [tyre]"`` or the ``.tir`` file's name and family.
    """

    stiffness_N_per_m: float
    damping_Ns_per_m: float
    nominal_load_N: float
    label: str


def wheel_tyre(params: VehicleParameters, wheel) -> TyreOfWheel:
    """The tyre of ``wheel`` (a :class:`~trikedyn.params.schema.WheelSpec`): its ``.tir`` file's vertical
    stiffness and damping when it names one (the ``[tyre]`` stiffness where the file gives none), else the
    ``[tyre]`` section's.

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    wheel : WheelSpec
        The wheel.

    Returns
    -------
    TyreOfWheel
        Vertical stiffness [N/m] and damping [N s/m].
    """
    from ..tyre.models import for_wheel  # the tyre model that takes the wheel says

    return TyreOfWheel(*for_wheel(params, wheel).vertical(params, wheel))


@dataclass(frozen=True)
class QuarterCar:
    """The two-mass quarter car of a wheel (or of a suspension: the mean over its wheels).

    Attributes
    ----------
    sprung_mass_kg : float
        Body share on the wheel [kg], from the static load less the unsprung mass (may be <= 0 for a CG
        outside the support; :meth:`body_mode` then has none).
    unsprung_mass_kg : float
        Wheel plus fork slider, or plus half the swing arm [kg].
    stiffness_N_per_m, damping_Ns_per_m : float
        The suspension's own spring and damper at the wheel [N/m, N s/m].
    tyre_stiffness_N_per_m, tyre_damping_Ns_per_m : float
        The tyre's, in series [N/m, N s/m].
    """

    sprung_mass_kg: float
    unsprung_mass_kg: float
    stiffness_N_per_m: float
    damping_Ns_per_m: float
    tyre_stiffness_N_per_m: float
    tyre_damping_Ns_per_m: float

    @property
    def series_stiffness_N_per_m(self) -> float:
        """Spring and tyre in series [N/m]."""
        return series_stiffness(self.stiffness_N_per_m, self.tyre_stiffness_N_per_m)

    def body_mode(self, sprung_mass_kg: float | None = None) -> tuple[float, float]:
        """Undamped natural frequency [Hz] and damping ratio [-] of the body (bounce) mode, with this quarter
        car's sprung mass or ``sprung_mass_kg``; NaN for a sprung mass that is not positive.

        Parameters
        ----------
        sprung_mass_kg : float, optional
            Sprung mass [kg]; this quarter car's by default.

        Returns
        -------
        natural_frequency_hz : float
            [Hz].
        damping_ratio : float
            Dimensionless.
        """
        mass = self.sprung_mass_kg if sprung_mass_kg is None else sprung_mass_kg
        if not mass > 0:
            return math.nan, math.nan
        from ..measure.quarter_car import quarter_car_modes  # scipy: only when a mode is asked for

        modes = quarter_car_modes(mass, self.unsprung_mass_kg, self.stiffness_N_per_m, self.damping_Ns_per_m,
                                  self.tyre_stiffness_N_per_m, self.tyre_damping_Ns_per_m)
        return modes.sprung_frequency_hz, modes.sprung_damping_ratio

    def sprung_mass_for(self, natural_frequency_hz: float) -> float | None:
        """Eq. 3 with the tyre in series: the sprung mass [kg] whose body mode has ``natural_frequency_hz``
        [Hz] (:func:`~trikedyn.measure.quarter_car.sprung_mass_for_frequency`); None if none has.

        Parameters
        ----------
        natural_frequency_hz : float
            Body-mode frequency [Hz].

        Returns
        -------
        float or None
            Sprung mass [kg].
        """
        from ..measure.quarter_car import sprung_mass_for_frequency

        return sprung_mass_for_frequency(natural_frequency_hz, self.unsprung_mass_kg, self.stiffness_N_per_m,
                                         self.damping_Ns_per_m, self.tyre_stiffness_N_per_m,
                                         self.tyre_damping_Ns_per_m)


def wheel_quarter_car(params: VehicleParameters, wheel_name: str) -> QuarterCar:
    """The quarter car of the wheel ``wheel_name`` (see the module docstring).

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    wheel_name : str
        The wheel.

    Returns
    -------
    QuarterCar
        Masses [kg], stiffnesses [N/m], dampings [N s/m].
    """
    wheel = params.wheel(wheel_name)
    susp = params.suspension[wheel.suspension]
    tyre = wheel_tyre(params, wheel)
    unsprung = unsprung_mass(params, wheel_name)
    sprung = static_wheel_loads(params)[wheel_name] / STANDARD_GRAVITY - unsprung
    return QuarterCar(sprung, unsprung, susp.stiffness_N_per_m, susp.damping_Ns_per_m, tyre.stiffness_N_per_m,
                      tyre.damping_Ns_per_m)


def suspension_quarter_car(params: VehicleParameters, suspension: str) -> QuarterCar:
    """The quarter car of the suspension ``suspension``: the mean of its wheels' (a pair's sprung masses
    differ when the CG is off the centre line; a bump test under both sees their mean).

    Parameters
    ----------
    params : VehicleParameters
        The vehicle.
    suspension : str
        The suspension's name.

    Returns
    -------
    QuarterCar
        Masses [kg], stiffnesses [N/m], dampings [N s/m].

    Raises
    ------
    KeyError
        No wheel uses ``suspension``.
    """
    cars = [wheel_quarter_car(params, w.name) for w in params.wheels if w.suspension == suspension]
    if not cars:
        raise KeyError(suspension)

    def _mean(attribute):
        return sum(getattr(c, attribute) for c in cars) / len(cars)

    return QuarterCar(_mean("sprung_mass_kg"), _mean("unsprung_mass_kg"), _mean("stiffness_N_per_m"),
                      _mean("damping_Ns_per_m"), _mean("tyre_stiffness_N_per_m"), _mean("tyre_damping_Ns_per_m"))
