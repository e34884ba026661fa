"""Drawing pieces the animation's views share (plan, rear, 3d): colours, the bars of the wheel loads, and
text made safe for matplotlib (a ``$`` in a vehicle's or wheel's name would start mathtext)."""

from __future__ import annotations

__all__ = ["CONE", "LIFTED", "load_bars", "plain", "wheel_label"]

LIFTED = "#d62728"
CONE = "#ff7f0e"


def plain(text) -> str:
    """``text`` as matplotlib draws it literally: ``$`` escaped (no mathtext)."""
    return str(text).replace("$", r"\$")


def wheel_label(name: str) -> str:
    """A wheel's short label from its name: the initials of its parts (``rear_left`` -> ``RL``)."""
    initials = "".join(part[0].upper() for part in str(name).split("_") if part)
    return plain(initials or str(name)[:3] or "?")


def load_bars(ax, scene, positions, width):
    """Bars of the wheel loads [kN] on ``ax``; returns ``update(i)`` and ``colour(fz)`` (a shade of blue
    darker with the load [N], red when lifted)."""
    from matplotlib import colormaps

    names, cmap = list(scene.loads_N), colormaps["Blues"]
    top = max(float(max(v.max() for v in scene.loads_N.values())), 1.0)

    def colour(fz):
        """The shade of a wheel carrying ``fz`` [N]."""
        return LIFTED if fz <= 0.0 else cmap(0.35 + 0.65 * min(fz / top, 1.0))

    bars = ax.bar(positions, [0.0] * len(names), width=width, color="0.5")
    ax.set_ylim(0.0, 1.15 * top / 1000)
    ax.set_xticks(positions, [wheel_label(n) for n in names])  # RL
    ax.tick_params(labelsize=7)

    def update(i):
        """The bars at sample ``i``."""
        for bar, name in zip(bars, names, strict=True):
            fz = float(scene.loads_N[name][i])
            bar.set_height(fz / 1000 if fz > 0.0 else 0.03 * top / 1000)  # a lifted wheel: a red stub
            bar.set_color(colour(fz))

    return update, colour
