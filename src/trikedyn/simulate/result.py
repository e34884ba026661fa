"""Simulation results: channels by name, a pandas DataFrame, and plots (matplotlib imported lazily)."""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from ..errors import InputError, did_you_mean
from .channels import BASE_CHANNELS, IMU_CHANNELS, WHEEL_CHANNELS

__all__ = ["Result", "rollover_index", "load_transfer_ratio", "state_names"]


def rollover_index(fz_right, fz_left):
    """Rollover index (paper Eq. 5): ``RI = (F_R - F_L) / (F_R + F_L)``; |RI| = 1 when a wheel lifts.

    Returns NaN where both wheels are off the ground.

    Parameters
    ----------
    fz_right : array_like
        Vertical force on the right wheel of the pair [N].
    fz_left : array_like
        Vertical force on the left wheel of the pair [N].

    Returns
    -------
    numpy.ndarray
        RI, dimensionless, in [-1, 1].
    """
    fr = np.asarray(fz_right, dtype=float)
    fl = np.asarray(fz_left, dtype=float)
    total = fr + fl
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(total > 0, (fr - fl) / np.where(total > 0, total, 1.0), np.nan)


def load_transfer_ratio(fz_right_total, fz_left_total):
    """Load transfer ratio over all wheels: ``(sum F_right - sum F_left) / sum F``.

    Parameters
    ----------
    fz_right_total : array_like
        Sum of the right wheels' vertical forces [N].
    fz_left_total : array_like
        Sum of the left wheels' vertical forces [N].

    Returns
    -------
    numpy.ndarray
        LTR, dimensionless, in [-1, 1].
    """
    return rollover_index(fz_right_total, fz_left_total)


def state_names(model) -> tuple[str, ...]:
    """Labels of the state vector: positions, velocities, transient slips
    (:func:`trikedyn.model.packing.state_labels`).

    Parameters
    ----------
    model : VehicleModel
        The vehicle.

    Returns
    -------
    tuple of str
        The labels.
    """
    return model.state_names


@dataclass(frozen=True)
class Result:
    """A simulation's recorded channels (immutable: judging a run returns figures, it never writes here).

    Attributes
    ----------
    time_s : ndarray
    channels : Mapping[str, ndarray]
        ``BASE_CHANNELS`` by name; per wheel ``<wheel>_<quantity>`` (e.g. ``rear_left_fz_N``);
        ``ri`` (Eq. 5 over the two-wheel axle) and ``ltr``; for a manoeuvre with a path ``path_s_m``
        (progress of the CG along it) and ``path_error_m``; ``judged`` (1 inside the judged window).
        Read-only.
    states : ndarray
        The raw state at each sample, labelled by ``state_names``.
    status : str
        ``"ok"`` or why the run stopped early.
    meta : dict
        Vehicle name, time step, wheel names.
    state_names : tuple of str
        Labels of the columns of ``states`` (see :func:`state_names`).
    manoeuvre : Manoeuvre, optional
        What was driven (None for open-loop :func:`~trikedyn.simulate.run.simulate` runs).
    params : VehicleParameters
        The vehicle that was driven (with its payload).
    """

    time_s: np.ndarray
    channels: dict
    states: np.ndarray
    status: str = "ok"
    meta: dict = field(default_factory=dict)
    state_names: tuple = ()
    manoeuvre: object = None
    params: object = None

    def __post_init__(self):
        object.__setattr__(self, "channels", MappingProxyType(dict(self.channels)))
        for array in (self.time_s, self.states, *self.channels.values()):
            array.setflags(write=False)
        object.__setattr__(self, "_derived", {})

    def derived(self, key: str, compute):
        """A figure derived from this run, computed once: ``compute()`` the first time ``key`` is asked for, the
        kept value after.

        Judging a run asks for some figures more than once (a threshold search's verdict and its count of cone
        strikes both need the cones struck, :func:`trikedyn.analysis.window.cone_strikes`); the run is
        immutable, so each is computed once. The channels stay as they are.

        Parameters
        ----------
        key : str
            The figure's name; ``compute`` must depend on this run alone.
        compute : callable
            ``compute()`` returns the figure.

        Returns
        -------
        object
            The figure (shared between callers: do not modify it).
        """
        kept = self._derived
        if key not in kept:
            kept[key] = compute()
        return kept[key]

    @property
    def success(self) -> bool:
        """True when the run went to its end (no rollover, no divergence)."""
        return self.status == "ok"

    @property
    def message(self) -> str:
        """What happened: ``"ok"`` or why the run stopped, with the time."""
        if self.success:
            return "ok"
        return f"stopped at t = {float(self.time_s[-1]):.3f} s: {self.status}"

    def state(self, name: str) -> np.ndarray:
        """One column of ``states`` by its label.

        Parameters
        ----------
        name : str
            A label of ``state_names``.

        Returns
        -------
        numpy.ndarray
            The column, in that state's unit.

        Raises
        ------
        InputError
            For an unknown name (with a close-match hint).
        """
        try:
            return self.states[:, self.state_names.index(name)]
        except ValueError:
            raise InputError(f"no state '{name}'" + did_you_mean(name, list(self.state_names)),
                             where="state") from None

    @classmethod
    def from_arrays(cls, model, times, states, base, wheels, commands, imu, *, status, dt, meta=None,
                    extra=None, manoeuvre=None) -> Result:
        """Assemble a result from the compiled loop's arrays: the channels (base, per wheel, RI, LTR, IMU, commands).

        Parameters
        ----------
        model : VehicleModel
            The vehicle run.
        times : numpy.ndarray
            Record times [s].
        states : numpy.ndarray
            Recorded states.
        base : numpy.ndarray
            Chassis channels (:data:`BASE_CHANNELS` columns).
        wheels : numpy.ndarray, dtype WHEEL_OUT
            Per-wheel outputs at each record.
        commands : numpy.ndarray
            Steer [rad], drive [N m] and brake [N m] commands at each record.
        imu : numpy.ndarray
            IMU readings (:data:`IMU_CHANNELS` columns).
        status : str
            The loop's status (``"ok"`` or why it stopped).
        dt : float
            Time step [s].
        meta : dict, optional
            Metadata kept with the result.
        extra : callable, optional
            ``extra(times, channels)`` returning more channels.
        manoeuvre : Manoeuvre, optional
            The manoeuvre driven.

        Returns
        -------
        Result
            The result.
        """
        # one transposed copy per block, each channel a contiguous row of it (not a copy per strided column)
        rows = base.T.copy()
        channels = {name: rows[i] for i, name in enumerate(BASE_CHANNELS)}
        names = model.wheel_names
        per_wheel = {field_name: wheels[field_name].T.copy() for field_name in WHEEL_CHANNELS.values()}
        for k, wname in enumerate(names):
            for quantity, field_name in WHEEL_CHANNELS.items():
                channels[f"{wname}_{quantity}"] = per_wheel[field_name][k]
        fz = per_wheel["fz"]  # a contiguous row a wheel: the strided field's reductions cost ten times more
        ys = np.array([w.y_m for w in (model.params.wheel(n) for n in names)])
        pair = [k for k, n in enumerate(names) if not model.params.wheel(n).steered] if model.params.layout == "delta" \
            else [k for k, n in enumerate(names) if model.params.wheel(n).steered]
        left = max(pair, key=lambda k: ys[k])
        right = min(pair, key=lambda k: ys[k])
        channels["ri"] = rollover_index(fz[right], fz[left])
        channels["ltr"] = load_transfer_ratio(fz[ys < 0].sum(axis=0), fz[ys > 0].sum(axis=0))
        channels["min_wheel_load_N"] = fz.min(axis=0)
        rows = imu.T.copy()
        for j, name in enumerate(IMU_CHANNELS):
            channels[f"imu_{name}"] = rows[j]
        rows = commands[:, :3].T.copy()
        channels["steer_cmd_rad"], channels["drive_torque_Nm"], channels["brake_torque_Nm"] = rows
        channels.update(extra or {})
        info = {"vehicle": model.params.name, "dt_s": dt, "wheels": list(names), "left": names[left],
                "right": names[right], **(meta or {})}
        return cls(times.copy(), channels, states.copy(), status, info, state_names(model), manoeuvre, model.params)

    def __getitem__(self, name: str) -> np.ndarray:
        if name == "time_s":
            return self.time_s
        if name not in self.channels:
            raise InputError(f"no channel '{name}'" + did_you_mean(name, list(self.channels)), where="channel")
        return self.channels[name]

    def imu_log(self, rate_hz: float | None = None, *, noise_std: float = 0.0, gyro_noise_std: float = 0.0,
                bias: tuple = (0.0, 0.0, 0.0), seed=None):
        """The emulated IMU as a log table (``time_s`` and the SI names of :mod:`trikedyn.measure.logs`).

        Parameters
        ----------
        rate_hz : float, optional
            Output rate [Hz]; the run's own rate by default. Point-sampled (no anti-alias filter), by
            linear interpolation of the recorded channels.
        noise_std, gyro_noise_std : float
            White noise on the accelerometer [m/s^2] and on the gyroscope [rad/s].
        bias : tuple of 3 floats
            Accelerometer bias (x, y, z) [m/s^2].
        seed : int, optional
            Seed of the noise.

        Returns
        -------
        pandas.DataFrame
            Writable with :func:`trikedyn.measure.logs.write_log`.
        """
        import pandas as pd

        times = self.time_s if rate_hz is None else np.arange(self.time_s[0], self.time_s[-1] + 1e-9, 1.0 / rate_hz)
        rng = np.random.default_rng(seed)
        data = {"time_s": times - times[0]}
        for j, name in enumerate(IMU_CHANNELS):
            values = np.interp(times, self.time_s, self.channels[f"imu_{name}"])
            if j < 3:
                values = values + bias[j] + (rng.normal(0.0, noise_std, times.size) if noise_std else 0.0)
            elif j < 6 and gyro_noise_std:
                values = values + rng.normal(0.0, gyro_noise_std, times.size)
            data[name] = values
        return pd.DataFrame(data)

    def to_pandas(self):
        """All channels as a DataFrame indexed by time [s].

        Returns
        -------
        pandas.DataFrame
            One column a channel; ``attrs`` hold the metadata and the status.
        """
        import pandas as pd

        frame = pd.DataFrame(dict(self.channels), index=pd.Index(self.time_s, name="time_s"))
        frame.attrs.update(self.meta, status=self.status)
        return frame

    def plot(self, channels=("speed_mps", "ay_mps2", "yaw_rate_radps", "ri"), axes=None):
        """Time histories of ``channels`` (one axis each); returns the Figure.

        Parameters
        ----------
        channels : sequence of str
            Channel names.
        axes : sequence of matplotlib Axes, optional
            Where to draw (new figure by default).

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        import matplotlib.pyplot as plt

        if axes is None:
            fig, axes = plt.subplots(len(channels), 1, sharex=True, figsize=(7, 1.8 * len(channels)))
        axes = np.atleast_1d(axes)
        judged = np.nonzero(np.asarray(self.channels["judged"]) > 0.5)[0] if "judged" in self.channels else []
        for ax, name in zip(axes, channels, strict=False):
            if len(judged):  # the judged window, entry to exit gate
                ax.axvspan(self.time_s[judged[0]], self.time_s[judged[-1]], color="0.85", alpha=0.5, lw=0, zorder=0)
            ax.plot(self.time_s, self[name])
            ax.set_ylabel(name)
            ax.grid(alpha=0.3)
        axes[-1].set_xlabel("time [s]")
        axes[0].set_title(f"{self.meta.get('vehicle', '')} ({self.status})")
        fig = axes[0].figure
        fig.tight_layout()
        return fig
