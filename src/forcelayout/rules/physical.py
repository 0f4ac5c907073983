"""Physical terms that are always on (paper eq. 2–3): repulsion, boundary, alignment.

They are not scaled by the annealing temperature. Besides the paper's three
terms there is a door-clearance push that keeps each door's swing square
free, because a layout that blocks a door is rejected by validation anyway.

All functions take a :class:`~forcelayout.rules.base.State` and return
``(F, tau)`` with shapes (N, 2) and (N,).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from forcelayout import geometry as geo
from forcelayout.rules.base import State

__all__ = ["PhysicalWeights", "repulsion", "boundary", "alignment", "door_clearance", "physical"]

_EPS = 1e-3


@dataclass(frozen=True)
class PhysicalWeights:
    """Strengths and ranges of the always-on terms.

    Attributes
    ----------
    repulsion : float
        Strength of the logarithmic repulsion between footprints (the
        strongest term, per the paper).
    repulsion_range : float
        Clearance in metres below which repulsion acts.
    boundary : float
        Strength of the inverse-square wall potential, in N·m².
    boundary_range : float
        Distance from a wall in metres below which the potential acts.
    alignment : float
        Strength of the torque settling objects at cardinal angles.
    door : float
        Strength of the push out of door swing squares.
    """

    repulsion: float = 6.0
    repulsion_range: float = 0.12
    boundary: float = 2e-5
    boundary_range: float = 0.08
    alignment: float = 0.6
    door: float = 6.0

    def scaled(self, overrides: dict[str, float]) -> PhysicalWeights:
        """A copy with ``{"repulsion": x, "boundary": y, "alignment": z}`` multiplied in."""
        return PhysicalWeights(
            repulsion=self.repulsion * overrides.get("repulsion", 1.0),
            repulsion_range=self.repulsion_range,
            boundary=self.boundary * overrides.get("boundary", 1.0),
            boundary_range=self.boundary_range,
            alignment=self.alignment * overrides.get("alignment", 1.0),
            door=self.door * overrides.get("door", 1.0),
        )


def _torque(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    """z-component of r x f."""
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]


def repulsion(
    state: State, pi: np.ndarray, pj: np.ndarray, w: PhysicalWeights
) -> tuple[np.ndarray, np.ndarray]:
    """Short-range logarithmic repulsion between all pairs ``(pi, pj)``.

    The force on each body of a pair grows as ``w.repulsion * ln(r0 / g)`` as
    the clearance ``g`` falls below ``r0 = w.repulsion_range``, pointing
    from the other body's centre to its own; zero beyond ``r0``.
    """
    n = state.n
    f = np.zeros((n, 2))
    if pi.size == 0:
        return f, np.zeros(n)
    sep = state.separation(pi, pj)
    active = sep < w.repulsion_range
    if not active.any():
        return f, np.zeros(n)
    pi, pj, sep = pi[active], pj[active], sep[active]
    d = state.pos[pi] - state.pos[pj]
    dist = np.linalg.norm(d, axis=1, keepdims=True)
    u = np.where(dist > 1e-9, d / np.maximum(dist, 1e-9), np.array([[1.0, 0.0]]))
    mag = w.repulsion * np.log(w.repulsion_range / np.maximum(sep, _EPS))
    fi = u * mag[:, None]
    np.add.at(f, pi, fi)
    np.add.at(f, pj, -fi)
    return f, np.zeros(n)


def boundary(state: State, w: PhysicalWeights) -> tuple[np.ndarray, np.ndarray]:
    """Inverse-square potential from the walls acting on footprint corners.

    Each corner within ``w.boundary_range`` of a wall is pushed along the
    wall's inward normal by ``w.boundary * (1/d² - 1/range²)``; corners
    outside the room are pushed towards the room's centroid. Forces at the
    corners also give torques, which square objects up against walls.
    """
    room = state.room
    c = state.corners  # (N, 4, 2)
    d, _ = room.wall_distance(c)  # (N, 4, W)
    near = d < w.boundary_range
    mag = np.where(near, w.boundary * (1.0 / np.maximum(d, _EPS) ** 2
                                       - 1.0 / w.boundary_range**2), 0.0)
    fc = np.einsum("ncw,wk->nck", mag, room.normal)  # (N, 4, 2)
    outside = ~room.contains(c)
    if outside.any():
        to_c = room.centroid - c
        to_c /= np.maximum(np.linalg.norm(to_c, axis=-1, keepdims=True), 1e-9)
        fc = np.where(outside[..., None], to_c * w.repulsion * 2.0, fc)
    r = c - state.pos[:, None, :]
    return fc.sum(axis=1), _torque(r, fc).sum(axis=1)


def alignment(state: State, w: PhysicalWeights) -> tuple[np.ndarray, np.ndarray]:
    """Torque ``-w.alignment * sin(4 yaw)`` settling objects at 0°, 90°, 180°, 270°."""
    return np.zeros((state.n, 2)), -w.alignment * np.sin(4.0 * state.yaw)


def door_clearance(state: State, w: PhysicalWeights) -> tuple[np.ndarray, np.ndarray]:
    """Push footprints out of each door's swing square (door width deep into the room).

    The push runs along the wall, away from the door's centre, so objects
    standing at that wall slide aside rather than into the room.
    """
    doors = state.room.doors
    n = state.n
    f = np.zeros((n, 2))
    if len(doors) == 0 or n == 0:
        return f, np.zeros(n)
    centre, dr, df, dh = state.room.door_squares
    sep = geo.obb_separation(
        centre[None] - state.pos[:, None], state.right[:, None], state.front[:, None],
        state.half[:, None], dr[None], df[None], dh[None])  # (N, D)
    margin = 0.05
    active = sep < margin
    if not active.any():
        return f, np.zeros(n)
    rel = state.pos[:, None, :] - centre[None, :, :]  # (N, D, 2)
    along = np.einsum("ndk,dk->nd", rel, doors.tangent)
    sign = np.where(along >= 0, 1.0, -1.0)
    depth = np.clip(margin - sep, 0.0, 1.0)
    push = (sign * depth * w.door * 10.0)[..., None] * doors.tangent[None]
    push += (depth * w.door * 2.0)[..., None] * doors.normal[None]  # and off the door's wall
    f = np.where(active[..., None], push, 0.0).sum(axis=1)
    return f, np.zeros(n)


def physical(
    state: State, pi: np.ndarray, pj: np.ndarray, w: PhysicalWeights
) -> tuple[np.ndarray, np.ndarray]:
    """Sum of all always-on terms: repulsion, boundary, alignment, door clearance."""
    f = np.zeros((state.n, 2))
    tau = np.zeros(state.n)
    for fk, tk in (repulsion(state, pi, pj, w), boundary(state, w), alignment(state, w),
                   door_clearance(state, w)):
        f += fk
        tau += tk
    return f, tau
