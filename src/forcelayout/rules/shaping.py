"""Shaping helpers for rule forces: clipped pulls, dead-band torques, unit vectors, angles.

The built-in rules shape their forces with these, and a plugin should too:
a pull that grows linearly with the violation and saturates (so nothing
explodes and the physical terms always win), a torque with a dead band (so
an object that nearly meets an orientation rule is left alone), unit
vectors that stay finite at zero length, signed angles between directions,
and the half extent of a footprint along a direction. Everything works on
arrays with a leading binding axis ``B``.

Units: metres, radians CCW; forces and torques are per unit binding weight.

Examples
--------
>>> import numpy as np
>>> from forcelayout.rules.shaping import ramp, turn
>>> ramp(np.array([-0.1, 0.1, 1.0])).tolist()
[0.0, 0.4, 1.5]
>>> float(turn(np.array([0.5]), np.array([0.1]), np.array([1.0]))[0])
2.0
"""

from __future__ import annotations

import numpy as np

from forcelayout import geometry as geo
from forcelayout.rules.base import State

__all__ = [
    "GAIN",
    "CAP",
    "HARD_GAIN",
    "TURN",
    "TURN_CAP",
    "TURN_HARD",
    "ramp",
    "turn",
    "unit",
    "signed_angle",
    "square_error",
    "extent",
    "view_blockers",
]

#: Force per metre of violation of a soft rule (times the binding weight).
GAIN = 4.0
#: Largest force of one binding (times the binding weight).
CAP = 1.5
#: Steeper gain of the hard placement rules (at_wall, in_corner): they saturate within a
#: few centimetres of their goal, so a soft pull (weight x CAP at most) cannot hold them
#: off it.
HARD_GAIN = 20.0
#: Torque per radian of heading error of a soft orientation rule (times the weight).
TURN = 5.0
#: Largest heading error a soft torque answers to, radians.
TURN_CAP = 1.5
#: Torque per radian of heading error of the hard placement rules (times the weight):
#: stronger than the soft orientation rules' (facing: 5 x 1.5), so a soft torque cannot
#: turn an object's back off its wall.
TURN_HARD = 3.0


def ramp(excess: np.ndarray, gain: float = GAIN) -> np.ndarray:
    """Clipped linear pull: 0 for ``excess <= 0``, ``gain * excess`` up to :data:`CAP`.

    Parameters
    ----------
    excess : ndarray
        How far each binding is from being met, metres (<= 0: met).
    gain : float
        Force per metre of excess.

    Returns
    -------
    ndarray
        Magnitudes in ``[0, CAP]``, the shape of ``excess``.
    """
    return np.minimum(np.maximum(excess, 0.0) * gain, CAP)


def turn(err: np.ndarray, dead: np.ndarray | float, w: np.ndarray) -> np.ndarray:
    """Torque reducing a heading error beyond a dead band.

    Parameters
    ----------
    err : ndarray, shape (B,)
        Signed heading error, radians CCW (the torque turns the object by +err).
    dead : ndarray or float
        Errors smaller than this are left alone, radians.
    w : ndarray, shape (B,)
        Binding weights.

    Returns
    -------
    ndarray, shape (B,)
        ``w * TURN * clip(err beyond dead, -TURN_CAP, TURN_CAP)``.
    """
    e = np.sign(err) * np.maximum(np.abs(err) - dead, 0.0)
    return (w * TURN) * np.minimum(np.maximum(e, -TURN_CAP), TURN_CAP)


def unit(d: np.ndarray, fallback: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors of ``d`` (B, 2) and their lengths (B,).

    Zero vectors stay zero, or map to +x with ``fallback=True`` (for pushes
    that need a direction even at a shared centre).
    """
    n = np.sqrt((d * d).sum(1))
    u = d / np.maximum(n, 1e-9)[:, None]
    if fallback:
        u[n < 1e-9] = (1.0, 0.0)
    return u, n


def signed_angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle from directions ``a`` to ``b`` (..., 2), radians CCW in [-pi, pi].

    Neither needs unit length.
    """
    cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    dot = (a * b).sum(-1)
    return np.arctan2(cross, dot)


def square_error(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Signed angle from heading ``a`` to the nearest of ``b + k * 90°``, radians in [-pi/4, pi/4].

    How far an object must turn (CCW positive) to be square with another
    object or a wall of direction ``b``.
    """
    rel = 4.0 * (np.asarray(b) - np.asarray(a))
    return np.arctan2(np.sin(rel), np.cos(rel)) / 4.0


def extent(state: State, i: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Half extent of footprints ``i`` along unit directions ``u`` (B, 2), metres."""
    f, h = state.front[i], state.size[i]
    fx, fy, ux, uy = f[:, 0], f[:, 1], u[:, 0], u[:, 1]
    # right = (fy, -fx)
    return (np.abs(fx * ux + fy * uy) * (0.5 * h[:, 1])
            + np.abs(fy * ux - fx * uy) * (0.5 * h[:, 0]))


def view_blockers(state: State, i: np.ndarray, j: np.ndarray, height: np.ndarray | float,
                  width: float = 0.1) -> np.ndarray:
    """Which objects stand between ``i`` and ``j`` and are taller than ``height``.

    The line of sight is the segment between the two footprint centres,
    ``width`` metres wide; an object blocks it when its footprint overlaps
    that strip and it is taller than ``height`` metres (seated eye level is
    about 1.1 m). The objects ``i`` and ``j`` themselves never block, nor, in a
    finished layout (``state.surfaces`` given), what does not stand on the
    floor: the TV on the stand looked at, a lamp hung from the ceiling.

    Returns
    -------
    ndarray of bool, shape (B, rows)
        ``[k, m]``: object ``m`` of the binding's sample (row
        ``state.peers(i)[k, m]``) blocks binding ``k``.
    """
    b, n = len(i), state.rows
    if b == 0 or n == 0:
        return np.zeros((b, n), dtype=bool)
    d = state.pos[j] - state.pos[i]
    u, length = unit(d, fallback=True)
    mid = 0.5 * (state.pos[i] + state.pos[j])
    perp = np.stack([u[:, 1], -u[:, 0]], axis=1)
    half = np.stack([np.full(b, 0.5 * width), 0.5 * length], axis=1)
    rows = state.peers(i)  # (B, n): the objects of each binding's sample
    sep = geo.obb_separation(state.pos[rows] - mid[:, None, :], perp[:, None], u[:, None],
                             half[:, None], state.right[rows], state.front[rows],
                             state.half[rows])
    tall = state.size[rows, 2] > np.asarray(height, dtype=float).reshape(-1, 1)
    if state.surfaces is not None:  # a finished layout: its floor objects only
        tall &= np.array([s == "floor" for s in state.surfaces], dtype=bool)[rows]
    out = (sep < 0.0) & tall
    first = rows[:, 0]
    out[np.arange(b), i - first] = False
    out[np.arange(b), j - first] = False
    return out
