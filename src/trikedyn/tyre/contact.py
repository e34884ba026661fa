"""Where a wheel touches the road and how its contact point moves: the tyre's geometry (compiled).

A wheel is a disc of unloaded radius ``R`` on a road surface ``z = h(x, y)``: flat, or a ``(1 - cos) / 2``
bump across the road (a :data:`~trikedyn.model.packing.ROAD` record, read by its field names). The
contact point is the lowest point of the disc along the road normal; the tyre axes are ``ex = axle x n``
(forward, in the road plane), ``ey = n x ex`` (left) and the road normal ``n`` (up). The deflection is the
road height at the contact point less its height, along the normal.

Slips are transient (first-order relaxation, Pacejka 2006 ch. 7): per wheel two states, the longitudinal
slip ``kappa'`` and the tangent of the slip angle ``s' = tan(alpha')``, with
``sigma_x dkappa'/dt = (omega R_e - v_x) - v_ref kappa'`` and ``sigma_y ds'/dt = -v_y - v_ref s'``
(``v_ref = (v_x^4 + v_low^4)^(1/4)``, :func:`~trikedyn.tyre.magic_formula.slip_quantities`). In steady
state they equal the slips of :func:`~trikedyn.tyre.magic_formula.slip_quantities`.
"""

from __future__ import annotations

import math

from .._jit import jit

__all__ = ["contact_geometry", "road_height", "slip_rates"]


@jit(inline="always")
def road_height(x, y, road):
    """Road height [m] and its slopes ``dh/dx``, ``dh/dy`` at ``(x, y)`` [m] on a road record.

    Parameters
    ----------
    x, y : float
        Point in the world [m].
    road : record
        The :data:`~trikedyn.model.packing.ROAD` record.

    Returns
    -------
    height : float
        Road height [m].
    dh_dx, dh_dy : float
        Slopes, dimensionless.
    """
    if road.bump != 0 and road.y_min <= abs(y) <= road.y_max:
        s = (x - road.start) / road.length
        if 0.0 < s < 1.0:
            height = road.height
            return (
                0.5 * height * (1.0 - math.cos(2.0 * math.pi * s)),
                height * math.pi / road.length * math.sin(2.0 * math.pi * s),
                0.0,
            )
    return 0.0, 0.0, 0.0


@jit(inline="always")
def contact_geometry(radius, road, e, cx, cy, cz, vb):
    """Contact point, tyre axes and contact kinematics of a wheel.

    Parameters
    ----------
    radius : float
        Unloaded radius [m].
    road : record
        The road (:data:`~trikedyn.model.packing.ROAD`).
    e : ndarray (3, 3)
        World -> wheel rotation (row 1: the spin axis in world coordinates).
    cx, cy, cz : float
        Wheel centre in the world [m].
    vb : ndarray (6,)
        Wheel spatial velocity in its own axes (angular, then linear of the centre).

    Returns
    -------
    tuple
        ``(rx, ry, rz)`` centre -> contact [m]; ``(nx, ny, nz)`` road normal; ``(exx, exy, exz)``,
        ``(eyx, eyy, eyz)`` tyre axes; ``(ax, ay, az)`` spin axis; deflection [m] and its rate [m/s];
        ``vx``, ``vy`` [m/s] of the centre in tyre axes; spin rate [rad/s]; inclination [rad] (ISO: about
        ``ex``, positive with the wheel top leaning right), all in world coordinates.
    """
    ax, ay, az = e[1, 0], e[1, 1], e[1, 2]  # wheel spin axis in world coordinates
    flat = road.bump == 0
    if flat:
        hx, hy = 0.0, 0.0
    else:
        _, hx, hy = road_height(cx, cy, road)
    nn = 1.0 / math.sqrt(hx * hx + hy * hy + 1.0)
    nx, ny, nz = -hx * nn, -hy * nn, nn
    dot = nx * ax + ny * ay + nz * az
    dx, dy, dz = nx - dot * ax, ny - dot * ay, nz - dot * az
    dn = -radius / math.sqrt(dx * dx + dy * dy + dz * dz)
    rx, ry, rz = dx * dn, dy * dn, dz * dn  # centre -> contact point
    px, py, pz = cx + rx, cy + ry, cz + rz
    if flat:
        hp, hpx, hpy = 0.0, 0.0, 0.0
    else:
        hp, hpx, hpy = road_height(px, py, road)
    deflection = (hp - pz) * nz
    # wheel angular velocity and centre velocity in world coordinates
    wx = e[0, 0] * vb[0] + e[1, 0] * vb[1] + e[2, 0] * vb[2]
    wy = e[0, 1] * vb[0] + e[1, 1] * vb[1] + e[2, 1] * vb[2]
    wz = e[0, 2] * vb[0] + e[1, 2] * vb[1] + e[2, 2] * vb[2]
    vcx = e[0, 0] * vb[3] + e[1, 0] * vb[4] + e[2, 0] * vb[5]
    vcy = e[0, 1] * vb[3] + e[1, 1] * vb[4] + e[2, 1] * vb[5]
    vcz = e[0, 2] * vb[3] + e[1, 2] * vb[4] + e[2, 2] * vb[5]
    rate = (hpx * vcx + hpy * vcy - vcz) * nz
    # tyre axes: ex = axle x n (forward), ey = n x ex
    exx, exy, exz = ay * nz - az * ny, az * nx - ax * nz, ax * ny - ay * nx
    en = 1.0 / math.sqrt(exx * exx + exy * exy + exz * exz)
    exx, exy, exz = exx * en, exy * en, exz * en
    eyx, eyy, eyz = ny * exz - nz * exy, nz * exx - nx * exz, nx * exy - ny * exx
    vx = vcx * exx + vcy * exy + vcz * exz
    vy = vcx * eyx + vcy * eyy + vcz * eyz
    spin = wx * ax + wy * ay + wz * az
    camber = math.asin(min(max(dot, -1.0), 1.0))
    return (rx, ry, rz, nx, ny, nz, exx, exy, exz, eyx, eyy, eyz, ax, ay, az, deflection, rate, vx, vy, spin,
            camber)


@jit(inline="always")
def slip_rates(kappa, tan_alpha, vx, vy, spin, r_eff, v_low, sigma_x, sigma_y):
    """Rates of the transient slips (see the module docstring) and ``v_ref`` [m/s].

    Parameters
    ----------
    kappa : float
        Transient longitudinal slip, dimensionless.
    tan_alpha : float
        Tangent of the transient slip angle, dimensionless.
    vx, vy : float
        Contact-point velocity along the wheel's heading and across it [m/s].
    spin : float
        Wheel spin rate [rad/s].
    r_eff : float
        Effective rolling radius [m].
    v_low : float
        Regularisation speed [m/s].
    sigma_x, sigma_y : float
        Longitudinal and lateral relaxation lengths [m].

    Returns
    -------
    dkappa, dtan_alpha : float
        [1/s].
    v_ref : float
        The regularised speed [m/s].
    """
    v_ref = math.sqrt(math.sqrt(vx * vx * vx * vx + v_low * v_low * v_low * v_low))
    return (spin * r_eff - vx - v_ref * kappa) / sigma_x, (-vy - v_ref * tan_alpha) / sigma_y, v_ref
