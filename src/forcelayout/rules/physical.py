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

__all__ = ["PhysicalWeights", "repulsion", "boundary", "alignment", "door_clearance", "physical",
           "closing", "wall_gaps", "SWING_MARGIN"]

_EPS = 1e-3


@dataclass(frozen=True)
class PhysicalWeights:
    """Strengths and ranges of the always-on terms (and of the walking-room term).

    Attributes
    ----------
    repulsion : float
        Strength of the short-range logarithmic repulsion between all
        footprints (the strongest term, per the paper).
    repulsion_range : float
        Clearance in metres below which repulsion acts.
    repulsion_floor : float
        Clearance in metres below which the repulsion stops growing. Box2D
        contacts keep bodies apart; the floor keeps the explicit step stable.
    passage : float
        Strength of the walking-room term between objects that no rule
        relates. Unlike the physical terms it is a preference, not a
        constraint, and is annealed with the rule forces.
    passage_range : float
        Clearance in metres below which the walking-room term acts: about an
        agent's width, so unrelated objects either stand far enough apart to
        walk between or are drawn together by their own rules.
    boundary : float
        Strength of the inverse-square wall potential, in N·m².
    boundary_range : float
        Distance from a wall in metres below which the potential acts.
    boundary_floor : float
        Distance in metres below which the wall potential stops growing.
    alignment : float
        Strength of the torque settling objects at cardinal angles.
    door : float
        Strength of the push out of each door's entry zone.
    window : float
        Strength of the push of floor objects taller than a window's sill out
        of its clearance zone (:class:`forcelayout.clearance.WindowTerm`).
    access : float
        Strength of the push out of objects' access zones (free floor in front
        of a wardrobe, beside a bed; see :mod:`forcelayout.access`); 0 turns
        them off.
    """

    repulsion: float = 1.5
    repulsion_range: float = 0.1
    repulsion_floor: float = 0.04
    passage: float = 1.5
    passage_range: float = 0.4
    boundary: float = 2e-5
    boundary_range: float = 0.08
    boundary_floor: float = 0.015
    alignment: float = 0.6
    door: float = 2.0
    window: float = 1.0
    access: float = 1.0

    def scaled(self, overrides: dict[str, float]) -> PhysicalWeights:
        """A copy with the plan's ``weights`` for ``repulsion``, ``passage``,
        ``boundary``, ``alignment``, ``door``, ``window`` and ``access`` multiplied in."""
        from dataclasses import replace

        return replace(
            self,
            repulsion=self.repulsion * overrides.get("repulsion", 1.0),
            passage=self.passage * overrides.get("passage", 1.0),
            boundary=self.boundary * overrides.get("boundary", 1.0),
            alignment=self.alignment * overrides.get("alignment", 1.0),
            door=self.door * overrides.get("door", 1.0),
            window=self.window * overrides.get("window", 1.0),
            access=self.access * overrides.get("access", 1.0),
        )


def _torque(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    """z-component of r x f."""
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]


def repulsion(
    state: State,
    pi: np.ndarray,
    pj: np.ndarray,
    w: PhysicalWeights,
    reach: float | None = None,
    strength: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Short-range logarithmic repulsion between all pairs ``(pi, pj)``.

    The force on each body of a pair grows as ``strength * ln(r0 / g)`` as
    the clearance ``g`` falls below ``r0`` (defaults ``w.repulsion`` and
    ``w.repulsion_range``; ``g`` floored at ``w.repulsion_floor``), pointing
    from the other body's centre to its own; zero beyond ``r0``. The
    walking-room term is the same function with ``w.passage`` and
    ``w.passage_range``.
    """
    n = state.n
    if pi.size == 0:
        return np.zeros((n, 2)), np.zeros(n)
    r0 = w.repulsion_range if reach is None else reach
    k = w.repulsion if strength is None else strength
    sep = state.separation(pi, pj)
    active = sep < r0
    f = np.zeros((n, 2))
    if not active.any():
        return f, np.zeros(n)
    pi, pj, sep = pi[active], pj[active], sep[active]
    d = state.pos[pi] - state.pos[pj]
    u = d / np.maximum(np.sqrt((d * d).sum(1)), 1e-9)[:, None]
    fi = u * (k * np.log(r0 / np.maximum(sep, w.repulsion_floor)))[:, None]
    np.add.at(f, pi, fi)
    np.add.at(f, pj, -fi)
    return f, np.zeros(n)


def boundary(state: State, w: PhysicalWeights) -> tuple[np.ndarray, np.ndarray]:
    """Inverse-square potential from the walls acting on footprint corners.

    Each corner within ``w.boundary_range`` of a wall (measured along the
    wall's inward normal, where the corner lies beside the wall) is pushed
    along that normal by ``w.boundary * (1/d² - 1/range²)``. Forces at the
    corners also give torques, which square objects up against walls. The
    walls themselves are solid in the simulation; this term keeps objects
    from pressing into them.
    """
    room = state.room
    n = state.n
    c = state.corners.reshape(-1, 2)  # (4N, 2)
    s = c @ room.normal.T - room.normal_offset  # distance from each wall's line, inward +
    t = c @ room.tangent.T - room.tangent_offset  # position along each wall
    near = (s < w.boundary_range) & (s > -0.05) & (t >= 0.0) & (t <= room.length)
    if not near.any():
        return np.zeros((n, 2)), np.zeros(n)
    inv = 1.0 / np.maximum(s, w.boundary_floor)
    mag = np.where(near, w.boundary * (inv * inv - 1.0 / w.boundary_range**2), 0.0)
    fc = (mag @ room.normal).reshape(n, 4, 2)
    r = state.corners - state.pos[:, None, :]
    return fc.sum(axis=1), _torque(r, fc).sum(axis=1)


def alignment(state: State, w: PhysicalWeights) -> tuple[np.ndarray, np.ndarray]:
    """Torque ``-w.alignment * sin(4 yaw)`` settling objects at 0°, 90°, 180°, 270°."""
    return np.zeros((state.n, 2)), -w.alignment * np.sin(4.0 * state.yaw)


#: Clearance from a door's swing square below which ``door_clearance(entry=False)`` pushes,
#: metres: what start poses keep (an object settling from a start that passes is stopped
#: before it reaches the square, not pushed only once inside it).
SWING_MARGIN = 0.05


def door_clearance(state: State, w: PhysicalWeights, slide: np.ndarray | None = None,
                   entry: bool | np.ndarray = True) -> tuple[np.ndarray, np.ndarray]:
    """Push footprints out of each door's entry zone (:attr:`RoomGeometry.door_zones`: the swing
    square and an agent's width deeper) or, with ``entry=False``, out of the swing square
    alone (:attr:`RoomGeometry.door_squares`, what the checks ask); ``entry`` may also
    mark, per row (N,), the rows kept out of the entry zone.

    The push runs along the square's axis of least penetration: sideways
    along the wall for an object beside the door, straight into the room for
    an object in front of it. Rows marked in ``slide`` (objects a hard rule
    holds at a wall) are pushed along their own wall: sideways when it is
    the door's wall, through the square's far side when it runs across it.
    """
    room = state.room
    n = state.n
    if len(room.doors) == 0 or n == 0:
        return np.zeros((n, 2)), np.zeros(n)
    if not isinstance(entry, bool | np.bool_):  # per row: the zone, or the square alone
        fz, tz = door_clearance(state, w, slide, True)
        fs, ts = door_clearance(state, w, slide, False)
        return np.where(entry[:, None], fz, fs), np.where(entry, tz, ts)
    if entry:
        margin = 0.02
        centre, dr, df, dh = room.door_zones
        sep = state.door_separations  # (N, D)
    else:
        margin = SWING_MARGIN
        centre, dr, df, dh = room.door_squares
        sep = geo.obb_separation(centre[None] - state.pos[:, None], state.right[:, None],
                                 state.front[:, None], state.half[:, None], dr[None], df[None],
                                 dh[None])
    depth = margin - sep
    if not (depth > 0).any():
        return np.zeros((n, 2)), np.zeros(n)
    depth = np.clip(depth, 0.0, 1.0) * (w.door * 10.0)
    along = state.pos @ dr.T - (centre * dr).sum(1)  # (N, D) offset along the door's wall
    ahead = state.pos @ df.T - (centre * df).sum(1)  # (N, D) offset into the room
    # an object's half extent along each axis of the square
    ext_a = np.abs(state.right @ dr.T) * state.half[:, :1] + np.abs(state.front @ dr.T) \
        * state.half[:, 1:]
    ext_b = np.abs(state.right @ df.T) * state.half[:, :1] + np.abs(state.front @ df.T) \
        * state.half[:, 1:]
    pen_a = dh[None, :, 0] + ext_a - np.abs(along)  # overlap if pushed sideways
    pen_b = dh[None, :, 1] + ext_b - ahead  # overlap if pushed into the room
    sideways = pen_a <= pen_b
    if slide is not None:
        # objects held at a wall leave along their own wall, never off it: sideways past
        # the square's end when they stand on the door's wall, out through its far side
        # when their wall runs across it (a bed at the wall beside a door in the corner)
        along_door = np.abs(state.right @ dr.T) >= np.abs(state.right @ df.T)
        sideways = np.where(slide[:, None], along_door, sideways)
    fa = np.where(sideways, np.where(along >= 0, depth, -depth), 0.0)
    fb = np.where(sideways, 0.0, depth)
    return fa @ dr + fb @ df, np.zeros(n)


def closing(state: State, pi: np.ndarray, pj: np.ndarray, solid: np.ndarray, radius: float,
            strength: float, touching: float = 0.03) -> tuple[np.ndarray, np.ndarray]:
    """Pull that closes slivers of floor too narrow for an agent of ``radius``.

    The free floor the ``navigable`` check counts is the floor farther than
    ``radius`` from every footprint, so a gap narrower than the agent's width
    between two footprints, or narrower than its radius between a footprint and
    a wall, is lost whole, and closing it frees floor as fast as it closes (the
    gradient of the free area). Each pair ``(pi, pj)`` at a clearance between
    ``touching`` and ``2 * radius`` is drawn together, and each ``solid`` row
    (N,) beside a wall at a clearance between ``touching`` and ``radius`` is
    drawn to it, with a constant force ``strength``; wider gaps feel nothing.
    """
    n = state.n
    f = np.zeros((n, 2))
    if pi.size:
        sep = state.separation(pi, pj)
        on = (sep > touching) & (sep < 2.0 * radius)
        if on.any():
            a, b = pi[on], pj[on]
            d = state.pos[b] - state.pos[a]
            u = d / np.maximum(np.sqrt((d * d).sum(1)), 1e-9)[:, None] * strength
            np.add.at(f, a, u)
            np.add.at(f, b, -u)
    gap = wall_gaps(state)
    near = (gap > touching) & (gap < radius) & solid[:, None]
    f -= (near.astype(float) @ state.room.normal) * strength
    return f, np.zeros(n)


def wall_gaps(state: State) -> np.ndarray:
    """Clearance from each footprint to each wall beside it, shape (N, W), metres.

    The smallest distance of the footprint's corners from the wall's line
    (inward positive) where the footprint's centre lies along the wall,
    ``inf`` where it does not (the wall is not beside the object).
    """
    room = state.room
    s = np.einsum("nkd,wd->nkw", state.corners, room.normal) - room.normal_offset  # (N, 4, W)
    t = state.pos @ room.tangent.T - room.tangent_offset  # (N, W): along each wall
    return np.where((t > 0.0) & (t < room.length), s.min(axis=1), np.inf)


def physical(
    state: State, pi: np.ndarray, pj: np.ndarray, w: PhysicalWeights,
    solid: np.ndarray | None = None, slide: np.ndarray | None = None,
    entry: bool | np.ndarray = True, unaligned: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Sum of all always-on terms: repulsion, boundary, alignment, door clearance.

    ``solid`` (N,) marks the rows the door clearance pushes (all by default);
    walkable floor covers may lie in a door's swing. ``slide`` (N,) marks rows
    pushed out of door squares along their wall only, and ``entry`` says whether
    doors keep their entry zones or only their swing squares clear (see
    :func:`door_clearance`); the alignment turns no ``unaligned`` (N,) row.
    """
    f = np.zeros((state.n, 2))
    tau = np.zeros(state.n)
    fd, td = door_clearance(state, w, slide, entry)
    if solid is not None:
        fd = fd * solid[:, None]
    fa, ta = alignment(state, w)
    if unaligned is not None:
        ta = np.where(unaligned, 0.0, ta)
    for fk, tk in (repulsion(state, pi, pj, w), boundary(state, w), (fa, ta), (fd, td)):
        f += fk
        tau += tk
    return f, tau
