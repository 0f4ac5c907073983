"""Surface rules: objects placed off the floor (on a parent's top, on a wall, on the ceiling).

These rules put no force on the floor simulation: the surface stage
(:mod:`forcelayout.surfaces`) places their objects in 2D simulations on the
parent's top, on a wall unfolded into a plane, or on the ceiling. Here they
judge a finished layout, whose :class:`~forcelayout.rules.State` carries each
object's ``z`` (height of its bottom, metres) and ``surfaces`` (``"floor"``,
a parent id, ``"wall:<i>"`` or ``"ceiling"``).

A wall object's ``size`` is ``[width along the wall, depth off the wall,
height]``; its pose is the centre of its footprint, its back against the
wall and its front facing into the room; ``z`` is its bottom edge.
"""

from __future__ import annotations

import numpy as np
from pydantic import Field, model_validator

from forcelayout.rules.base import ParamArrays, Rule, StartHint, State

__all__ = ["OnTop", "OnWall", "OnWallMid", "Above", "OnCeiling", "wall_index", "wall_band"]

_Z_TOL = 1e-3


def wall_index(surfaces: tuple[str, ...] | None, i: np.ndarray) -> np.ndarray:
    """Wall number of each object ``i`` whose surface is ``"wall:<k>"``, else -1."""
    out = np.full(len(i), -1, dtype=int)
    if surfaces is None:
        return out
    for b, r in enumerate(np.asarray(i).tolist()):
        s = surfaces[r]
        if s.startswith("wall:") and s[5:].isdigit():
            out[b] = int(s[5:])
    return out


def wall_band(p: ParamArrays, room_height: float) -> tuple[np.ndarray, np.ndarray]:
    """Lowest bottom and highest top (metres) of each binding; ``high=None`` is the ceiling."""
    low = np.asarray(p.low, dtype=float)
    high = np.array([room_height if v is None else float(v) for v in np.atleast_1d(p.high)])
    return low, high


def middle_span(lo: np.ndarray | float, hi: np.ndarray | float, share: np.ndarray | float
                ) -> tuple[np.ndarray, np.ndarray]:
    """The middle ``share`` of the spans ``[lo, hi]`` (metres along a wall): where the
    ``above`` rule wants the centre of what hangs over a target spanning them."""
    mid, half = 0.5 * (np.asarray(lo) + hi), 0.5 * np.asarray(share) * (np.asarray(hi) - lo)
    return mid - half, mid + half


def _on_wall_geometry(state: State, i: np.ndarray, tol: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Whether each object hangs flat on its wall (back on it, facing in, within its length).

    Returns ``(ok, wall)``; ``wall`` is -1 where the surface is not a wall.
    """
    room = state.room
    wall = wall_index(state.surfaces, i)
    ok = (wall >= 0) & (wall < room.n_walls)
    w = np.where(ok, wall, 0)
    n, t = room.normal[w], room.tangent[w]
    c = state.corners[i]  # (B, 4, 2)
    s = np.einsum("bck,bk->bc", c, n) - room.normal_offset[w][:, None]  # off the wall
    u = np.einsum("bck,bk->bc", c, t) - room.tangent_offset[w][:, None]  # along it
    back = s[:, :2]
    ok &= (np.abs(back) <= tol[:, None]).all(axis=1)
    ok &= np.einsum("bk,bk->b", state.front[i], n) >= np.cos(np.radians(5.0))
    ok &= (u.min(axis=1) >= -tol) & (u.max(axis=1) <= room.length[w] + tol)
    return ok, np.where(ok, wall, -1)


def _zeros(i: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.zeros((len(i), 2)), np.zeros(len(i))


class _SurfaceRule(Rule):
    surface = "wall"
    weight = 1.0

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        """No floor force: the surface stage places these objects."""
        return _zeros(i)


class OnTop(_SurfaceRule):
    """Rest on the target's top: footprint inside the target's top, bottom at its height.

    Satisfied when the object's footprint lies inside the target's top (within
    ``tolerance`` metres), its surface is the target's id and its ``z`` equals
    the target's ``z`` plus its height.
    """

    aliases = ("on", "on_top_of", "ontop")
    closeness = "close"

    surface = "top"
    target = "required"
    bond = True
    relation = True

    class Params(Rule.Params):
        tolerance: float = Field(0.01, ge=0, description="Slack at the top's edges, m.")

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        c = state.corners[i] - state.pos[j][:, None, :]
        x = np.einsum("bck,bk->bc", c, state.right[j])
        y = np.einsum("bck,bk->bc", c, state.front[j])
        half = state.half[j]
        tol = np.asarray(p.tolerance, dtype=float)[:, None]
        ok = ((np.abs(x) <= half[:, 0:1] + tol) & (np.abs(y) <= half[:, 1:2] + tol)).all(axis=1)
        if state.surfaces is not None:
            ok &= np.array([state.surfaces[a] == state.ids[b]
                            for a, b in zip(i.tolist(), j.tolist(), strict=True)], dtype=bool)
        if state.z is not None:
            ok &= np.abs(state.z[i] - (state.z[j] + state.size[j, 2])) <= _Z_TOL
        return ok


class OnWall(_SurfaceRule):
    """Hang on a wall, bottom at least ``low`` and top at most ``high`` metres above the floor.

    Satisfied when the surface is ``"wall:<i>"``, the back lies on wall ``i``
    (within ``tolerance`` metres, facing into the room), the object lies
    within the wall's length, and its height band holds. ``wall`` pins the
    wall; by default any wall with a free stretch wide enough is used. Within
    its band the object hangs as near eye level (its centre at 1.6 m) as the
    band and what is on the wall allow: give ``high`` to hang it low (a towel
    radiator 1.1 m tall with ``high`` 1.4 hangs from 0.3 m).
    """

    aliases = ("hang_on_wall",)

    surface = "wall"
    relation = True

    class Params(Rule.Params):
        low: float = Field(0.3, ge=0, description="Lowest bottom edge above the floor, m.")
        high: float | None = Field(None, gt=0,
                                   description="Highest top edge, m; None is the ceiling.")
        wall: int | None = Field(None, ge=0, description="Wall index to hang on; None: any.")
        tolerance: float = Field(0.02, gt=0, description="Largest gap behind the object, m.")

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        tol = np.asarray(p.tolerance, dtype=float)
        ok, wall = _on_wall_geometry(state, i, tol)
        low, high = wall_band(p, state.room.height)
        if state.z is None:
            return np.zeros(len(i), dtype=bool)
        z = state.z[i]
        ok &= (z >= low - _Z_TOL) & (z + state.size[i, 2] <= high + _Z_TOL)
        pinned = np.array([-1 if v is None else int(v) for v in np.atleast_1d(p.wall)])
        ok &= (pinned < 0) | (pinned == wall)
        return ok


class OnWallMid(OnWall):
    """Hang on a wall at eye level: bottom at least 0.9 m, top at most 2.1 m (by default).

    The same check as ``on_wall`` with a mid-height band.
    """

    class Params(OnWall.Params):
        low: float = Field(0.9, ge=0, description="Lowest bottom edge above the floor, m.")
        high: float | None = Field(2.1, gt=0,
                                   description="Highest top edge, m; None is the ceiling.")


class Above(_SurfaceRule):
    """Hang on a wall above the target (e.g. a painting above the bed).

    Satisfied when the object hangs flat on a wall (as ``on_wall``), the
    target stands with its back to that wall (its front within ``max_angle``
    degrees of the wall's inward normal, its footprint at most ``wall_gap``
    metres from it: a cabinet on the side wall beside a counter's end, or on
    the wall across the corner from a washer a metre out, is not above it), the
    object's centre lies over the middle ``middle`` share of the target's
    extent along that wall (the middle half by default: a mirror over a
    dresser, not hanging off its end beside a window), and its bottom is at
    least ``clearance`` and at most ``max_gap`` metres above the target's top
    (1 m by default: a shelf over a desk within reach, not over the window
    behind it; and its top at most ``high``, default the ceiling).
    """

    surface = "wall"
    target = "required"
    bond = True
    start = StartHint(clear_wall_above_target=True)

    class Params(Rule.Params):
        clearance: float = Field(0.1, ge=0, description="Smallest gap above the target, m.")
        max_gap: float | None = Field(1.0, ge=0,
                                      description="Largest gap between the target's top and "
                                                  "the object's bottom, m; None: any.")
        high: float | None = Field(None, gt=0,
                                   description="Highest top edge, m; None is the ceiling.")
        tolerance: float = Field(0.02, gt=0, description="Largest gap behind the object, m.")
        wall_gap: float = Field(0.3, ge=0, description="Largest gap between the target's "
                                "footprint and the wall the object hangs on, m.")
        max_angle: float = Field(45.0, gt=0, le=180,
                                 description="Largest angle between the target's front and "
                                             "the inward normal of that wall, degrees.")
        middle: float = Field(0.5, gt=0, le=1,
                              description="Share of the target's extent along the wall, "
                                          "about its middle, the object's centre lies "
                                          "over (1: anywhere over the target).")

        @model_validator(mode="after")
        def _gap_above_clearance(self) -> Above.Params:
            if self.max_gap is not None and self.max_gap < self.clearance:
                raise ValueError(f"max_gap ({self.max_gap:g} m) is below clearance "
                                 f"({self.clearance:g} m): no height is left between them; "
                                 "raise max_gap or lower clearance")
            return self

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        room = state.room
        tol = np.asarray(p.tolerance, dtype=float)
        ok, wall = _on_wall_geometry(state, i, tol)
        if state.z is None:
            return np.zeros(len(i), dtype=bool)
        w = np.maximum(wall, 0)
        t = room.tangent[w]
        toff = room.tangent_offset[w]
        off = np.einsum("bck,bk->bc", state.corners[j], room.normal[w]) \
            - room.normal_offset[w][:, None]
        ok &= off.min(axis=1) <= np.asarray(p.wall_gap, dtype=float) + _Z_TOL
        ok &= np.einsum("bk,bk->b", state.front[j], room.normal[w]) \
            >= np.cos(np.radians(np.asarray(p.max_angle, dtype=float))) - 1e-9
        ut = np.einsum("bck,bk->bc", state.corners[j], t) - toff[:, None]
        uc = np.einsum("bk,bk->b", state.pos[i], t) - toff
        lo, hi = middle_span(ut.min(axis=1), ut.max(axis=1), np.asarray(p.middle, dtype=float))
        ok &= (uc >= lo - _Z_TOL) & (uc <= hi + _Z_TOL)
        top_j = state.z[j] + state.size[j, 2]
        _, high = wall_band(ParamArrays({"low": np.zeros(len(i)), "high": p.high}, p.weight),
                            room.height)
        ok &= state.z[i] >= top_j + np.asarray(p.clearance, dtype=float) - _Z_TOL
        gap = np.array([np.inf if v is None else float(v) for v in np.atleast_1d(p.max_gap)])
        ok &= state.z[i] <= top_j + gap + _Z_TOL
        ok &= state.z[i] + state.size[i, 2] <= high + _Z_TOL
        return ok


class OnCeiling(_SurfaceRule):
    """Hang from the ceiling, centred over the room (or over the target object).

    Satisfied when the surface is ``"ceiling"``, the top touches the ceiling
    (``z`` = room height − object height), the footprint lies inside the
    room and, if ``centred``, the centre lies within ``tolerance`` metres of
    the room's centroid; with a target object, within ``tolerance`` of the
    target's long centre line and over the target along it (within its half
    length, or ``tolerance`` if more): two pendants over one island each
    hang over one half of it. A target may also name a functional area; the
    light is then centred over that area's objects (such bindings are placed
    but not judged).
    """

    aliases = ("ceiling",)

    surface = "ceiling"
    target = "optional"
    relation = True

    class Params(Rule.Params):
        centred: bool = Field(True, description="Centre over the room or the target.")
        tolerance: float = Field(0.3, gt=0, description="Largest distance from the centre, m.")

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        room = state.room
        ok = room.contains(state.corners[i]).all(axis=1)
        if state.surfaces is not None:
            ok &= np.array([state.surfaces[r] == "ceiling" for r in i.tolist()], dtype=bool)
        if state.z is not None:
            ok &= np.abs(state.z[i] + state.size[i, 2] - room.height) <= _Z_TOL
        tol = np.asarray(p.tolerance, dtype=float)
        if j is None:
            near = np.linalg.norm(state.pos[i] - room.centroid[None, :], axis=1) <= tol
        else:  # along the target's long axis over it, across within the tolerance
            d = state.pos[i] - state.pos[j]
            x, y = np.abs((d * state.right[j]).sum(1)), np.abs((d * state.front[j]).sum(1))
            hw, hd = state.half[j, 0], state.half[j, 1]
            along, across = np.where(hw >= hd, x, y), np.where(hw >= hd, y, x)
            near = (across <= tol) & (along <= np.maximum(tol, np.maximum(hw, hd)))
        return ok & (~np.asarray(p.centred, dtype=bool) | near)
