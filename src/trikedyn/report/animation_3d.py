"""The 3d view of an animation (``trikedyn animate RUN --view 3d``): the trike through the cones in perspective.

The body is a see-through box over the footprint (:attr:`~trikedyn.report.scene.Scene.footprint_m`), from
axle height to twice the CG height, at least 1 m tall (as in the rear view), rolled and pitched by the run's
angles about the reference point at axle height, then turned by the yaw; the wheels are discs in their own
planes (the steered ones turned by the steer angle), standing on the ground and shaded by their vertical load
(red when lifted, as in the other views); the cones are small pyramids on the ground (red once struck), with
the lanes and the reference line. The camera looks from behind and to the right of the vehicle and follows
it, turning with its yaw; the course is cut to the window around the vehicle (mplot3d draws beyond its axes
otherwise). Bars of the wheel loads stand beside the view; time, speed, roll and pitch are in its corner.

Used by :func:`trikedyn.report.animation.animate`; matplotlib is imported inside the functions.
"""

from __future__ import annotations

import math

import numpy as np

from ._drawing import CONE, LIFTED, load_bars, plain

__all__ = ["ELEVATION_DEG", "HALF_SPAN_M", "draw_3d"]

HALF_SPAN_M = 5.0
"""Half the width of the ground window around the vehicle [m]."""
AHEAD = 0.45
"""The window's centre is this fraction of its half width ahead of the vehicle: the course ahead is seen."""
HEIGHT_M = 2.0
"""Height of the view [m]."""
ELEVATION_DEG = 22.0
"""Camera elevation above the ground [deg]."""
CAMERA_BEHIND_DEG = 145.0
"""Camera azimuth from the vehicle's heading, towards its right [deg]: 180 is straight behind."""
CONE_BASE_M, CONE_HEIGHT_M = 0.3, 0.5
DISC_SIDES = 18
BODY = "#b0b0b0"
GROUND = "#e6e6e6"


def _rotation(roll, pitch, yaw):
    """``Rz(yaw) Ry(pitch) Rx(roll)``: chassis axes (x forward, y left, z up) to ground axes; pitch > 0 nose
    down."""
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw),
                              math.sin(yaw))
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    return rz @ ry @ rx


def _box_faces(corners):
    """The six faces of a box from its eight corners (bottom four, then top four, in the same order)."""
    b, t = corners[:4], corners[4:]
    return [b, t] + [np.array([b[k], b[(k + 1) % 4], t[(k + 1) % 4], t[k]]) for k in range(4)]


def _cone(x, y):
    """The four sides of a square pyramid standing at ``(x, y)`` on the ground."""
    h = CONE_BASE_M / 2
    base = np.array([(x - h, y - h, 0.0), (x + h, y - h, 0.0), (x + h, y + h, 0.0), (x - h, y + h, 0.0)])
    apex = np.array([x, y, CONE_HEIGHT_M])
    return [np.array([base[k], base[(k + 1) % 4], apex]) for k in range(4)]


def _inside(x, y, window):
    x0, x1, y0, y1 = window
    return (x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)


def _clipped(x, y, window):
    """``x, y`` with NaN where outside ``window = (x0, x1, y0, y1)`` (the line breaks there)."""
    keep = _inside(x, y, window)
    return np.where(keep, x, np.nan), np.where(keep, y, np.nan)


def draw_3d(fig, scene):
    """Draw the 3d view of ``scene`` on ``fig``; returns ``update(i)``, which moves everything to sample i.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure to draw on.
    scene : Scene
        The run's scene.

    Returns
    -------
    callable
        ``update(i)``: moves everything to sample ``i`` and returns the artists changed.
    """
    from mpl_toolkits.mplot3d.art3d import Line3D, Poly3DCollection

    grid = fig.add_gridspec(1, 2, width_ratios=(5.0, 1.0), wspace=0.1, left=0.0, right=0.93, top=0.93,
                            bottom=0.06)
    ax, side = fig.add_subplot(grid[0, 0], projection="3d"), fig.add_subplot(grid[0, 1])
    ax.computed_zorder = False  # drawn in this order: ground, course, wheels, the see-through body
    ax.set_title(plain(scene.title or "run"), fontsize=8, pad=0)
    ax.set_box_aspect((2 * HALF_SPAN_M, 2 * HALF_SPAN_M, HEIGHT_M), zoom=1.75)  # one scale on all axes
    ax.tick_params(labelsize=6, pad=0)
    ax.set_zticks([0.0, 1.0, 2.0])
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_pane_color((0.97, 0.97, 0.97, 1.0))
    ax.set_xlabel("x [m]", fontsize=7, labelpad=-6)
    ax.set_ylabel("y [m]", fontsize=7, labelpad=-6)

    lanes = ax.add_collection3d(Poly3DCollection([], facecolors=GROUND, edgecolors="none", zorder=0))
    path = ax.add_line(Line3D([], [], [], ls="--", lw=0.7, color="0.5", zorder=1))
    trail = ax.add_line(Line3D([], [], [], lw=1.2, color="#2ca02c", zorder=1))
    cones = ax.add_collection3d(Poly3DCollection([], edgecolors="k", linewidths=0.3, zorder=2))
    discs = {n: ax.add_collection3d(Poly3DCollection([], edgecolors="k", linewidths=1.0, zorder=3))
             for n in scene.wheels}
    body = ax.add_collection3d(Poly3DCollection([], facecolors=BODY, edgecolors="k", linewidths=0.7, alpha=0.3,
                                                zorder=4))
    cg, = ax.plot([], [], [], "o", ms=4, color="k", zorder=5)
    text = ax.text2D(0.01, 0.97, "", transform=ax.transAxes, va="top", fontsize=8, family="monospace",
                     bbox={"fc": "white", "ec": "0.6", "alpha": 0.85, "pad": 2})

    bars, colour = load_bars(side, scene, list(range(len(scene.loads_N))), 0.7)
    side.yaxis.tick_right()
    side.set_title("Fz [kN]", fontsize=7, pad=2)

    x_rear, x_front, half = scene.footprint_m
    pivot = max(w[2] for w in scene.wheels.values())  # roll and pitch drawn about the axle height
    top = max(2.0 * scene.cg_m[2], pivot + 1.0)
    corners = np.array([(x, y, z) for z in (0.0, top - pivot)
                        for x, y in ((x_rear, -half), (x_front, -half), (x_front, half), (x_rear, half))])
    cg_local = np.array([scene.cg_m[0], scene.cg_m[1], scene.cg_m[2] - pivot])
    angle = np.linspace(0.0, 2.0 * math.pi, DISC_SIDES, endpoint=False)
    cgx, cgy = scene.cg_xy
    pitch = np.zeros_like(scene.time_s) if scene.pitch_rad is None else scene.pitch_rad
    cone_faces = [_cone(x, y) for x, y in scene.cones_xy]

    def update(i):
        """Draw sample ``i``."""
        t, x, y, yaw = scene.time_s[i], scene.x_m[i], scene.y_m[i], float(scene.yaw_rad[i])
        roll, theta = float(scene.roll_rad[i]), float(pitch[i])
        cx, cy = x + AHEAD * HALF_SPAN_M * math.cos(yaw), y + AHEAD * HALF_SPAN_M * math.sin(yaw)
        window = (cx - HALF_SPAN_M, cx + HALF_SPAN_M, cy - HALF_SPAN_M, cy + HALF_SPAN_M)
        ax.set(xlim=window[:2], ylim=window[2:], zlim=(0.0, HEIGHT_M))
        ax.view_init(elev=ELEVATION_DEG, azim=math.degrees(yaw) - CAMERA_BEHIND_DEG)

        lanes.set_verts([[(a, c, 0.0), (b, c, 0.0), (b, d, 0.0), (a, d, 0.0)]
                         for a, b, c, d in ((max(x0, window[0]), min(x1, window[1]), max(y0, window[2]),
                                             min(y1, window[3])) for x0, x1, y0, y1 in scene.corridors)
                         if a < b and c < d])
        if scene.path_xy is not None:
            px, py = _clipped(scene.path_xy[:, 0], scene.path_xy[:, 1], window)
            path.set_data_3d(px, py, np.zeros_like(px))
        tx, ty = _clipped(cgx[: i + 1], cgy[: i + 1], window)
        trail.set_data_3d(tx, ty, np.zeros_like(tx))
        shown = np.flatnonzero(_inside(scene.cones_xy[:, 0], scene.cones_xy[:, 1], window))
        cones.set_verts([face for k in shown for face in cone_faces[k]])
        cones.set_facecolor([LIFTED if scene.cone_hit_s[k] <= t else CONE for k in shown for _ in range(4)])

        origin = np.array([x, y, pivot])
        turn = _rotation(roll, theta, yaw)
        body.set_verts(_box_faces(origin + corners @ turn.T))
        g = origin + turn @ cg_local
        cg.set_data_3d([g[0]], [g[1]], [g[2]])
        heading = _rotation(0.0, 0.0, yaw)
        lifted = []
        for name, (wx, wy, radius, steered) in scene.wheels.items():
            steer = float(scene.steer_rad[i]) if steered else 0.0
            rim = np.column_stack((wx + radius * np.cos(angle) * math.cos(steer),
                                   wy + radius * np.cos(angle) * math.sin(steer),
                                   radius + radius * np.sin(angle)))
            discs[name].set_verts([np.array([x, y, 0.0]) + rim @ heading.T])
            fz = float(scene.loads_N[name][i])
            discs[name].set_facecolor(colour(fz))
            lifted += [name] if fz <= 0.0 else []
        bars(i)
        lines = [f"t = {t:6.2f} s   v = {3.6 * scene.speed_mps[i]:5.1f} km/h",
                 f"roll = {math.degrees(roll):+5.2f} deg  pitch = {math.degrees(theta):+5.2f} deg"]
        lines += [f"cones struck {int(np.sum(scene.cone_hit_s <= t))}"] if scene.cones_xy.shape[0] else []
        lines += [plain(f"LIFT: {', '.join(lifted)}")] if lifted else []
        text.set_text("\n".join(lines))
        text.get_bbox_patch().set_edgecolor(LIFTED if lifted else "0.6")

    return update
