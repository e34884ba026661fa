"""The paper's figures, redrawn from trikedyn's results (matplotlib, Agg, imported here only).

* :func:`time_histories` -- longitudinal velocity, lateral acceleration and yaw rate (Figs. 7-8); the judged
  window (entry to exit gate) shaded grey;
* :func:`rollover_index` -- the rollover index of Eq. 5 over time, with its static value (Fig. 9);
* :func:`threshold_study` -- threshold velocity against freight for each stiffness and each damping level
  (Fig. 10).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["save", "time_histories", "rollover_index", "threshold_study"]


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save(fig, path: Path, dpi: int = 110) -> Path:
    """Write a figure atomically (a temporary file renamed into place), in the format its suffix names
    (PNG without one), and close it.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (closed afterwards).
    path : Path
        The file.
    dpi : int
        Resolution of raster formats [dots per inch].

    Returns
    -------
    Path
        The file written.
    """
    from .._files import atomic_write
    from ..errors import InputError

    path = Path(path)
    kind = path.suffix.lstrip(".").lower() or "png"
    try:
        atomic_write(path, lambda fh: fig.savefig(fh, dpi=dpi, format=kind))
    except ValueError as exc:  # a format matplotlib cannot write
        raise InputError(f"cannot write this kind of figure: {exc}", where=str(path)) from None
    finally:
        _plt().close(fig)
    return path


def shade_window(ax, result) -> None:
    """Shade the judged window (entry to exit gate) of a run on a time axis."""
    if "judged" not in result.channels:
        return
    inside = np.nonzero(np.asarray(result["judged"]) > 0.5)[0]
    if inside.size:
        ax.axvspan(result.time_s[inside[0]], result.time_s[inside[-1]], color="0.85", alpha=0.5, lw=0, zorder=0)


def time_histories(runs: dict, path: Path, title: str = "") -> Path:
    """Figs. 7-8: speed [km/h], lateral acceleration [m/s^2] and yaw rate [deg/s] of each run.

    ``runs`` maps a label to a :class:`~trikedyn.simulate.result.Result`; the accelerations and rates
    are those of the emulated seat sensor, as the paper's were.

    Parameters
    ----------
    runs : dict of str to Result
        Label -> run.
    path : Path
        The image file.
    title : str
        Figure title.

    Returns
    -------
    Path
        The file written.
    """
    plt = _plt()
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7.5, 6.5))
    for label, run in runs.items():
        t = run.time_s
        axes[0].plot(t, run["speed_mps"] * 3.6, label=label)
        axes[1].plot(t, run["imu_ay_mps2"], label=label)
        axes[2].plot(t, np.degrees(run["imu_wz_radps"]), label=label)
    if len(runs) == 1:
        for ax in axes:
            shade_window(ax, next(iter(runs.values())))
        title = f"{title}\n(grey: the judged window, entry to exit gate)" if title else "grey: the judged window"
    for ax, name in zip(axes, ("(a) longitudinal velocity [km/h]", "(b) lateral acceleration [m/s²]",
                               "(c) yaw rate [deg/s]"), strict=True):
        ax.set_ylabel(name, fontsize=8)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return save(fig, path)


def rollover_index(runs: dict, static_ri: float, path: Path, title: str = "") -> Path:
    """Fig. 9: the rollover index (Eq. 5) over time, and its static value (dashed).

    Parameters
    ----------
    runs : dict of str to Result
        Label -> run.
    static_ri : float
        Static rollover index, dimensionless.
    path : Path
        The image file.
    title : str
        Figure title.

    Returns
    -------
    Path
        The file written.
    """
    plt = _plt()
    fig, axes = plt.subplots(len(runs), 1, sharex=False, figsize=(7.5, 2.6 * len(runs)), squeeze=False)
    for ax, (label, run) in zip(axes[:, 0], runs.items(), strict=True):
        shade_window(ax, run)
        ax.plot(run.time_s, run["ri"], label="RI")
        ax.axhline(static_ri, color="r", ls="--", lw=1, label=f"static {static_ri:+.3f}")
        ax.set_ylim(-1.05, 1.05)
        ax.set_ylabel("RI [-]")
        ax.set_title(label, fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return save(fig, path)


def threshold_study(table, path: Path, title: str = "") -> Path:
    """Fig. 10: threshold velocity against freight mass; one panel per (group, manoeuvre), one line per level.

    ``table`` is the study's tidy table (columns ``group``/``groups``, ``manoeuvre``, ``freight_kg``,
    ``stiffness_scale``, ``damping_scale``, ``threshold_speed_kmh``).

    Parameters
    ----------
    table : pandas.DataFrame
        The study's tidy table (speeds [km/h], freight [kg], scales dimensionless).
    path : Path
        The image file.
    title : str
        Figure title.

    Returns
    -------
    Path
        The file written.
    """
    plt = _plt()
    manoeuvres = sorted(table["manoeuvre"].unique())
    panels = [("stiffness", "stiffness_scale", "damping_scale"), ("damping", "damping_scale", "stiffness_scale")]
    fig, axes = plt.subplots(len(panels), len(manoeuvres), figsize=(5.2 * len(manoeuvres), 7.5), squeeze=False)
    for row, (group, varied, fixed) in enumerate(panels):
        for col, man in enumerate(manoeuvres):
            ax = axes[row, col]
            sub = table[(table["manoeuvre"] == man) & (table[fixed] == 1.0)]
            for level in sorted(sub[varied].unique()):
                line = sub[sub[varied] == level].sort_values("freight_kg")
                ax.plot(line["freight_kg"], line["threshold_speed_kmh"], marker="o", label=f"{group} {level:.0%}")
            ax.set_title(f"({'ab'[row]}) {group}, {man.upper()}", fontsize=9)
            ax.set_xlabel("freight mass [kg]")
            ax.set_ylabel("threshold velocity [km/h]")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return save(fig, path)
