"""Unary rules: an object related to the room (walls, corners, middle, openings).

Every rule here is one small class: a ``Params`` model (defaults and units in
the field descriptions), a vectorised :meth:`force` that runs every
simulation step over all bindings at once, and a :meth:`satisfied` check that
judges finished layouts. Forces pull a little *inside* the satisfied region
(so the check still passes after the physical terms push back) and vanish
once it is reached; they are clipped so nothing explodes.

Units: metres, radians CCW (angles in ``Params`` are degrees, as people write
them); the object's front is its local +y.
"""

from __future__ import annotations

import numpy as np
from pydantic import Field

from forcelayout import geometry as geo
from forcelayout.rules.base import ParamArrays, Rule, StartHint, State
from forcelayout.rules.shaping import (
    CAP,
    HARD_GAIN,
    TURN_HARD,
    extent,
    ramp,
    square_error,
    unit,
)

__all__ = ["AtWall", "InCorner", "InMiddle", "NearWindow", "NearDoor", "AwayFromDoor",
           "AwayFromWindow"]

def _wall_pull(state: State, i: np.ndarray, wall: np.ndarray, w: np.ndarray,
               inside: float = 0.005) -> np.ndarray:
    """Force pulling footprints `i` flat against walls `wall` (one per binding).

    The pull is along the wall's outward normal, proportional to the gap
    between the footprint and the wall's line, aiming ``inside`` metres past
    the line (the wall itself stops the object).
    """
    room = state.room
    n = room.normal[wall]
    s = (state.pos[i] * n).sum(1) - room.normal_offset[wall]
    gap = s - extent(state, i, n)
    return -n * (w * ramp(gap + inside, HARD_GAIN))[:, None]


class AtWall(Rule):
    """Back against the nearest wall, front facing into the room.

    Satisfied when the object's back edge (local -y side) lies within
    ``tolerance`` metres of a wall and within ``max_angle`` degrees of
    parallel to it, with the front facing into the room. The force pulls the
    footprint onto the nearest wall long enough to take its width; the
    torque turns its back to that wall.
    """

    aliases = ("against_wall", "wall", "by_wall", "near_wall")
    opposite = "in_middle"
    feature = "wall"
    specialises = ("near", "next_to")

    hard = True
    relation = True
    start = StartHint(place="wall")
    weight = 3.0

    class Params(Rule.Params):
        tolerance: float = Field(0.05, gt=0, description="Largest back-edge gap to the wall, m.")
        max_angle: float = Field(10.0, gt=0, le=90,
                                 description="Largest angle between back edge and wall, deg.")

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        room = state.room
        w = p.weight
        f, size = state.front[i], state.size[i]
        # the wall nearest to the back edge's middle (so a long object whose head is at
        # one wall is not turned to the wall along its side), preferring walls long
        # enough to take the object's width
        back = state.pos[i] - f * (0.5 * size[:, 1:2])
        s = back @ room.normal.T - room.normal_offset
        t = back @ room.tangent.T - room.tangent_offset
        beyond = np.maximum(np.maximum(-t, t - room.length), 0.0)
        dist = np.sqrt(s * s + beyond * beyond)
        # ties (a back edge at a corner) go to the wall the object already turns its back to
        facing_away = 0.01 * (1.0 - f @ room.normal.T)
        wall = np.argmin(dist + facing_away + (room.length < 0.9 * size[:, :1]) * 100.0, axis=1)
        n, t = room.normal[wall], room.tangent[wall]
        fx, fy, nx, ny = f[:, 0], f[:, 1], n[:, 0], n[:, 1]
        fn = fx * nx + fy * ny  # front . normal
        rn = fy * nx - fx * ny  # right . normal
        hw, hd = 0.5 * size[:, 0], 0.5 * size[:, 1]
        # pull the footprint onto the wall's line, aiming 5 mm past it (the wall stops it)
        pos = state.pos[i]
        gap = (pos * n).sum(1) - room.normal_offset[wall] - np.abs(fn) * hd - np.abs(rn) * hw
        # turn the front to the wall's inward normal; while turned well away from
        # it, pull only gently, so a long object pressed corner-first into the
        # wall can still swing round instead of jamming at an angle
        err = np.arctan2(-rn, fn)
        settle = np.minimum(np.maximum(1.5 - 3.0 * np.abs(err), 0.2), 1.0)
        force = n * (-w * settle * ramp(gap + 0.005, HARD_GAIN))[:, None]
        # slide back along the wall if the footprint reaches beyond its ends
        along = (pos * t).sum(1) - room.tangent_offset[wall]
        half = np.abs(rn) * hd + np.abs(fn) * hw  # extent along the wall
        out = np.maximum(half - along, 0.0) - np.maximum(along + half - room.length[wall], 0.0)
        force += t * (w * np.minimum(np.maximum(out * HARD_GAIN, -CAP), CAP))[:, None]
        return force, (w * TURN_HARD) * np.minimum(np.maximum(err, -1.5), 1.5)

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        room = state.room
        c = state.corners[i]  # (B, 4, 2)
        d, _ = room.wall_distance(c[:, :2, :])  # back-left, back-right: (B, 2, W)
        tang = c[:, 1, :] - c[:, 0, :]
        tang /= np.maximum(np.sqrt((tang * tang).sum(1, keepdims=True)), 1e-12)
        par = np.abs(tang @ room.tangent.T)  # |cos| to each wall
        ok_angle = par >= np.cos(np.radians(p.max_angle))[:, None]
        ok_dist = d.max(axis=1) <= p.tolerance[:, None]
        facing_in = state.front[i] @ room.normal.T > 0
        return np.any(ok_angle & ok_dist & facing_in, axis=1)


class InCorner(Rule):
    """Tucked into a room corner: two adjacent sides against two walls.

    Satisfied when two adjacent sides of the footprint each lie within
    ``tolerance`` metres of two different walls (either orientation). The
    force pulls the object into the nearest convex corner; the torque squares
    it up with the corner's walls.
    """

    aliases = ("corner", "at_corner")
    opposite = "in_middle"
    feature = "corner"
    specialises = ("near", "next_to")
    fallback = "at_wall"  # the extra ones when the room has too few corners

    hard = True
    relation = True
    start = StartHint(place="corner")
    weight = 3.0

    class Params(Rule.Params):
        tolerance: float = Field(0.05, gt=0, description="Largest side-to-wall gap, m.")

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        b = len(i)
        k, vert, prev, angle = state.room.convex_corners
        if len(k) == 0:
            return np.zeros((b, 2)), np.zeros(b)
        d = state.pos[i, None, :] - vert[None, :, :]
        c = np.argmin((d * d).sum(2), axis=1)
        w = p.weight
        f = _wall_pull(state, i, prev[c], w) + _wall_pull(state, i, k[c], w)
        # turn to the nearest multiple of 90 degrees relative to the corner's walls
        err = square_error(state.yaw[i], angle[c])
        return f, w * TURN_HARD * err

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        room = state.room
        d, _ = room.wall_distance(state.corners[i])  # (B, 4 corners, W)
        tol = p.tolerance[:, None, None]
        side = np.maximum(d, np.roll(d, -1, axis=1)) <= tol  # side s = corners s, s+1
        nxt = np.roll(side, -1, axis=1)  # the adjacent side s+1
        pair = side[:, :, :, None] & nxt[:, :, None, :]
        pair &= ~np.eye(room.n_walls, dtype=bool)
        return pair.any(axis=(1, 2, 3))


class InMiddle(Rule):
    """In the middle of the room, away from the walls.

    Satisfied when the object's centre lies within ``fraction`` of the
    room's extent from the floor's centroid, on each axis (x and y
    separately). For L-shaped rooms the centroid may lie near the inner
    corner. The force pulls the centre towards the centroid.
    """

    aliases = ("center", "centre", "in_center", "in_centre", "middle")

    relation = True
    start = StartHint(place="middle", reach="fraction")
    weight = 2.0

    class Params(Rule.Params):
        fraction: float = Field(0.25, gt=0, le=0.5,
                                description="Allowed offset from the centroid per axis, "
                                            "as a fraction of the room's extent on that axis.")

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        room = state.room
        ext = room.bounds[2:] - room.bounds[:2]
        d = state.pos[i] - room.centroid
        limit = p.fraction[:, None] * ext[None, :]
        limit = limit - np.minimum(0.1, 0.2 * limit)  # aim a little inside
        f = -np.sign(d) * ramp(np.abs(d) - limit) * p.weight[:, None]
        return f, np.zeros(len(i))

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        room = state.room
        ext = room.bounds[2:] - room.bounds[:2]
        d = np.abs(state.pos[i] - room.centroid)
        return np.all(d <= p.fraction[:, None] * ext[None, :], axis=1)


class _NearOpening(Rule):
    """Centre within `distance` of an opening (doors or windows): the nearest one,
    or the one the binding picks by its index (``start.which`` names that parameter)."""

    relation = True
    weight = 1.5
    _openings = "windows"

    class Params(Rule.Params):
        distance: float = Field(1.5, gt=0,
                                description="Largest distance from the object's centre to the "
                                            "opening's centre, m.")

    def _nearest(self, state: State, i: np.ndarray, p: ParamArrays
                 ) -> tuple[np.ndarray, np.ndarray] | None:
        """The centre of each binding's opening and the distance to it, or None (no
        openings of the kind)."""
        o = getattr(state.room, self._openings)
        if len(o) == 0:
            return None
        d = state.pos[i, None, :] - o.centre[None, :, :]
        dist2 = (d * d).sum(2)
        k = np.argmin(dist2, axis=1)
        if self.start is not None and self.start.which is not None:
            pick = getattr(p, self.start.which).astype(int)
            # an index past the room's openings is refused with the plan; guarded all the same
            k = np.where((pick >= 0) & (pick < len(o)), pick, k)
        return o.centre[k], np.sqrt(dist2[np.arange(len(i)), k])

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        b = len(i)
        near = self._nearest(state, i, p)
        if near is None:
            return np.zeros((b, 2)), np.zeros(b)
        centre, dist = near
        u, _ = unit(centre - state.pos[i])
        target = p.distance - np.minimum(0.1, 0.25 * p.distance)
        return u * (p.weight * ramp(dist - target))[:, None], np.zeros(b)

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        near = self._nearest(state, i, p)
        if near is None:
            return np.zeros(len(i), dtype=bool)
        return near[1] <= p.distance


class NearWindow(_NearOpening):
    """Near a window: centre within `distance` metres of the nearest window's centre,
    or of the window `window` (its index in ``room.windows``) when given.

    Never satisfied in a room without windows (and then applies no force).
    """

    aliases = ("by_window",)
    feature = "window"
    specialises = ("near", "next_to", "facing")

    class Params(_NearOpening.Params):
        window: int = Field(-1, ge=-1, description=(
            "Index in room.windows of the window meant (0 is the first); -1: any, the "
            "nearest."))

    _openings = "windows"
    start = StartHint(place="window", reach="distance", which="window")


class NearDoor(_NearOpening):
    """Near a door: centre within `distance` metres of the nearest door's centre, or
    of the door `door` (its index in ``room.doors``) when given: the front door of a
    hall with two.

    Never satisfied in a room without doors (and then applies no force). The
    always-on door clearance still keeps the door's swing square free.
    """

    aliases = ("by_door",)
    opposite = "away_from_door"
    feature = "door"
    specialises = ("near", "next_to")

    class Params(_NearOpening.Params):
        door: int = Field(-1, ge=-1, description=(
            "Index in room.doors of the door meant (0 is the first); -1: any, the nearest."))

    _openings = "doors"
    start = StartHint(place="door", reach="distance", which="door")


class AwayFromDoor(Rule):
    """Away from every door: centre at least `distance` metres from each door's centre.

    Always satisfied in a room without doors. The force pushes the object
    away from the nearest door that is too close.
    """

    feature = "door"
    specialises = ("far_from",)

    weight = 1.5

    class Params(Rule.Params):
        distance: float = Field(2.0, gt=0,
                                description="Smallest distance from the object's centre to "
                                            "any door's centre, m.")

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        b = len(i)
        doors = state.room.doors
        if len(doors) == 0:
            return np.zeros((b, 2)), np.zeros(b)
        d = state.pos[i, None, :] - doors.centre[None, :, :]
        dist2 = (d * d).sum(2)
        k = np.argmin(dist2, axis=1)
        away = d[np.arange(b), k]
        # at a door's centre itself, push straight into the room
        away = np.where((away * away).sum(1, keepdims=True) < 1e-12, doors.normal[k], away)
        u, dist = unit(away, fallback=True)
        target = p.distance + 0.1
        return u * (p.weight * ramp(target - dist))[:, None], np.zeros(b)

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        doors = state.room.doors
        if len(doors) == 0:
            return np.ones(len(i), dtype=bool)
        d = state.pos[i, None, :] - doors.centre[None, :, :]
        return np.sqrt((d * d).sum(2)).min(axis=1) >= p.distance


class AwayFromWindow(Rule):
    """Out of the zone in front of every window: its footprint clear of a box as wide as
    the window and `distance` metres deep into the room.

    The ``window`` check keeps that zone free of objects taller than the sill;
    this rule keeps its object out of it whatever its height: a low stand a TV
    stands on, a dresser under a mirror, a desk whose lamp would stand in the
    light. Always satisfied in a room without windows. The force slides the
    object along the window's wall, out of the zone by the nearer side.
    """

    feature = "window"
    specialises = ("far_from",)

    weight = 1.5

    class Params(Rule.Params):
        distance: float = Field(0.5, gt=0,
                                description="Depth of the zone in front of each window, m "
                                            "(the window check's zone is 0.5 m deep).")

    batched = True  # relates rows through i, j and per-sample pairs only

    @staticmethod
    def _zones(state: State, i: np.ndarray, p: ParamArrays
               ) -> tuple[np.ndarray, np.ndarray] | None:
        """Each window's zone against each binding's footprint: the clearance (K, B),
        metres (negative inside), and the object's offset along the window's wall from
        its centre (K, B); None without windows."""
        w = state.room.windows
        if len(w) == 0:
            return None
        centre, half = w.zones(p.distance[None, :])  # (K, B, 2)
        d = state.pos[i][None, :, :] - centre
        sep = geo.obb_separation(d, w.tangent[:, None, :], w.normal[:, None, :], half,
                                 state.right[i][None], state.front[i][None],
                                 state.half[i][None])
        return sep, (d * w.tangent[:, None, :]).sum(2)

    def force(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        b = len(i)
        z = self._zones(state, i, p)
        if z is None:
            return np.zeros((b, 2)), np.zeros(b)
        sep, along = z
        # from 5 cm before the zone (the rules lean on it), along the wall: out by the
        # nearer end of the window
        push = ramp(0.05 - sep) * np.where(along < 0.0, -1.0, 1.0)  # (K, B)
        f = (push[:, :, None] * state.room.windows.tangent[:, None, :]).sum(0)
        return f * p.weight[:, None], np.zeros(b)

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        z = self._zones(state, i, p)
        if z is None:
            return np.ones(len(i), dtype=bool)
        return (z[0] >= -1e-6).all(axis=0)
