"""Names of vibration modes, from how their kinetic energy is shared among what moves.

A mode is named after the motion that carries most of its kinetic energy, not after its largest
coordinate (a suspension's travel is large in every body mode, yet its unsprung parts carry little
energy). The modal velocity ``u`` (the velocity part of the eigenvector) is expressed in physical
coordinates ``w`` with ``u = T w``:

* the chassis' roll, pitch and yaw rates [rad/s] (chassis axes) and the velocity of the whole vehicle's
  centre of mass [m/s] (chassis axes: fore-aft, lateral, vertical = bounce); referring the translation to
  the centre of mass decouples it from the rotations in the mass matrix, so a pure pitch about the CG
  carries no "bounce";
* each joint's rate relative to its parent: a wheel station's suspension (its wheel's hop, relative to the
  chassis), the steering heads (steer), the wheels' spin.

With ``M = T^T H T`` (``H`` the joint-space mass matrix at the linearisation state, from
:func:`~trikedyn.model.dynamics.crba`), the share of coordinate ``i`` is ``M_ii |w_i|^2 / sum_j M_jj
|w_j|^2``: the kinetic energy ``(1/2) M_ii |w_i|^2`` [J per unit of modal amplitude] of that motion alone,
normalised so that the shares add up to one. Shares of one group (e.g. both steering heads) add up.

Some names must be unique (bounce, pitch, roll, each wheel's hop): :func:`assign_names` gives each to the
mode with the largest share of it among the modes that want it (deferred acceptance: every mode asks for
its motions in order of share; a unique name goes to the mode with the largest share of it, the loser asks
for its next motion). A mode whose largest share names another mode, or whose own name carries less than
half its energy with a second motion at least half as large, is called after its two largest shares,
e.g. ``"roll + lateral"``: a combination never repeats a unique name on its own.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .dynamics import crba

__all__ = ["ModalCoordinates", "assign_names", "energy_shares", "modal_coordinates"]

WEAK_SHARE = 0.5
"""A mode whose (non-unique) name carries less than this share of its kinetic energy is named after its two
largest shares when the second is at least :data:`SECOND_SHARE` of the first [1]."""
SECOND_SHARE = 0.5
""":data:`WEAK_SHARE` [1]."""
MIN_UNIQUE = 0.1
"""A unique name (bounce, pitch, roll, a wheel's hop) never goes to a mode with less than this share of it [1]."""


@dataclass(frozen=True)
class ModalCoordinates:
    """Physical velocity coordinates of a vehicle at one state, for sharing a mode's kinetic energy.

    Attributes
    ----------
    groups : tuple of str
        The motions modes are named after ("bounce", "pitch", "roll", "yaw", "lateral", "fore-aft",
        "<wheel> wheel hop", "steer", "<wheel> wheel spin", other joints by body name).
    unique : frozenset of str
        The groups that name at most one mode: bounce, pitch, roll and each wheel's hop.
    transform : ndarray (n, n)
        ``T`` with ``u = T w`` (``u`` the model's generalised velocities, ``w`` the physical ones).
    mass : ndarray (n,)
        Diagonal of ``T^T H T`` [kg or kg m^2].
    group_of : ndarray (n,) of int
        Index into ``groups`` of each coordinate of ``w``.
    """

    groups: tuple[str, ...]
    unique: frozenset
    transform: np.ndarray
    mass: np.ndarray
    group_of: np.ndarray


def _skew(c: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -c[2], c[1]], [c[2], 0.0, -c[0]], [-c[1], c[0], 0.0]])


def modal_coordinates(model, state: np.ndarray) -> ModalCoordinates:
    """The physical coordinates ``w`` of ``model`` (a :class:`~trikedyn.model.vehicle.VehicleModel`) at
    ``state``, with the mass each carries (see the module docstring).

    Parameters
    ----------
    model : VehicleModel
        The vehicle.
    state : numpy.ndarray, shape (n_states,)
        The state (only the positions ``q`` are read).

    Returns
    -------
    ModalCoordinates
        The groups, the transform ``u = T w`` and the mass of each coordinate [kg or kg m^2].
    """
    tree = model.tree
    n = model.n_dof
    h = crba(np.ascontiguousarray(state[:n], dtype=float), *tree.arrays())
    mass = h[3, 3]
    # Featherstone's base inertia at the chassis origin: [[I_O, m c~], [m c~^T, m 1]]; c is the CG [m]
    cg = np.array([h[2, 4], h[0, 5], h[1, 3]]) / mass
    t = np.eye(n)
    t[3:6, 0:3] = _skew(cg)  # v_origin = v_cg + c x omega
    m_w = np.diag(t.T @ h @ t).copy()

    labels = ["roll", "pitch", "yaw", "fore-aft", "lateral", "bounce"] + list(tree.body_names[1:])
    unique = {"bounce", "pitch", "roll"}
    for w in tree.wheels:
        hop = f"{w.name} wheel hop"
        labels[5 + w.spring_body] = hop
        labels[5 + w.wheel_body] = f"{w.name} wheel spin"
        if w.steer_body >= 0:
            labels[5 + w.steer_body] = "steer"
        unique.add(hop)
    groups = tuple(dict.fromkeys(labels))
    group_of = np.array([groups.index(label) for label in labels])
    return ModalCoordinates(groups, frozenset(unique), t, m_w, group_of)


def energy_shares(coords: ModalCoordinates, velocity: np.ndarray) -> np.ndarray:
    """Each group's share of a mode's kinetic energy, dimensionless (adding up to one; zeros when nothing moves).

    Parameters
    ----------
    coords : ModalCoordinates
        The physical coordinates at the state the mode belongs to.
    velocity : ndarray (n,), complex
        The modal generalised velocities ``u`` (any scale and phase), so any unit [rad/s, m/s].

    Returns
    -------
    numpy.ndarray, shape (len(coords.groups),)
        Share of each group, dimensionless.
    """
    w = np.linalg.solve(coords.transform, velocity)
    energy = 0.5 * coords.mass * np.abs(w) ** 2
    shares = np.bincount(coords.group_of, weights=energy, minlength=len(coords.groups))
    total = shares.sum()
    return shares / total if total > 0 else shares


def assign_names(shares: np.ndarray, groups, unique) -> list[str]:
    """Names of modes from their kinetic-energy shares, each unique name used at most once.

    Parameters
    ----------
    shares : ndarray (modes, groups)
        Rows from :func:`energy_shares`.
    groups : sequence of str
    unique : set of str
        The names that may name one mode only.

    Returns
    -------
    list of str
        One name per mode: a group, or ``"a + b"`` for a mode whose own name is taken or weak (see the
        module docstring).
    """
    shares = np.asarray(shares, dtype=float)
    n_modes = shares.shape[0]
    prefs = [list(np.argsort(-shares[k], kind="stable")) for k in range(n_modes)]
    nxt = [0] * n_modes
    got: dict[int, int] = {}
    holder: dict[int, int] = {}
    free = list(range(n_modes))[::-1]
    while free:
        k = free.pop()
        if nxt[k] == len(groups):  # every motion it has is unique and taken (a contrived set of groups)
            got[k] = int(prefs[k][0])
            continue
        g = int(prefs[k][nxt[k]])
        nxt[k] += 1
        if groups[g] not in unique:
            got[k] = g
        elif shares[k, g] < MIN_UNIQUE:
            free.append(k)
        elif g not in holder:
            holder[g], got[k] = k, g
        elif shares[k, g] > shares[holder[g], g]:
            loser = holder[g]
            del got[loser]
            free.append(loser)
            holder[g], got[k] = k, g
        else:
            free.append(k)
    names = []
    for k in range(n_modes):
        g, top, second = got[k], int(prefs[k][0]), int(prefs[k][min(1, len(groups) - 1)])
        if groups[g] in unique and holder.get(g) == k:  # won it
            names.append(groups[g])
        elif g != top:  # its largest share names another mode: say what it shares
            names.append(f"{groups[top]} + {groups[second]}")
        elif shares[k, g] < WEAK_SHARE and shares[k, second] >= SECOND_SHARE * shares[k, g]:
            names.append(f"{groups[g]} + {groups[second]}")
        else:
            names.append(groups[g])
    return names
