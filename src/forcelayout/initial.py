"""Random start poses for a simulation: parents anywhere, children near their parents.

Paper §III-B-3: "to ensure diversity, parent objects are placed randomly,
while child objects are placed near their parents to accelerate
convergence". How an object starts is what its rules declare in their
:class:`~forcelayout.rules.StartHint`: a rule with ``parent`` set makes its
target the object's parent (``next_to``, ``around``, ``in_front_of``, ...),
``place`` says where to start (against a wall, in a corner, beside or in
front of the parent, ...) and ``turn`` how to face. Starting a nightstand
beside its bed rather than across the room keeps it from settling against
the wrong wall. A plugin rule gets the same help by declaring a hint.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely

from forcelayout import geometry as geo
from forcelayout.access import AccessTerm, zone_boxes
from forcelayout.batching import SampleTask, drive
from forcelayout.clearance import WindowTerm
from forcelayout.forces import ForceModel, RuleGroup
from forcelayout.rules.base import ParamArrays, StartHint, State
from forcelayout.rules.shaping import unit
from forcelayout.rules.surface import middle_span
from forcelayout.surfaces.walls import (
    MARGIN,
    REACH,
    back_wall,
    beyond_reach,
    hanging_centres,
    hidden_heights,
    pinned_ties,
    target_middle,
    target_stand,
    wall_band,
)
from forcelayout.verdict import FloorVerdict, JudgeRequest

__all__ = ["parents", "initial_poses", "start_poses", "propose_poses", "relocate", "Starts",
           "ProposeRequest", "RelocateRequest"]

#: Start places beside the parent, where wall length is kept free next to it.
_SIDE_PLACES = StartHint.SIDE_PLACES
#: Clearance a start pose keeps to other objects, metres (less a rounding tolerance: a pose
#: flush against a wall beside a door zone sits right at it). Of a door's swing square it
#: keeps clear only, as the door check asks.
_CLEAR = 0.05 - 1e-6
#: Rank of a clear candidate that meets every rule it can be judged by, its children's room
#: included (each miss takes 2 off).
_ALL_MET = 20.0
#: How far (metres) a footprint may reach into an access zone before it counts as standing
#: in it.
_INTRUDE = 0.02
#: How far (metres) the front of an object a rule turns towards a wall object starts from
#: where that object will hang, at the least.
_VIEWING = 0.8
#: Uniform numbers each sample's generator gives at a time for a candidate draw (``_Draws``).
_BLOCK = 256
#: Gaps a child starts at beside or in front of its parent, metres (drawn uniformly).
_GAP = (0.02, 0.1)
#: Wall a child beside its parent takes besides its width: the closest gap it starts at
#: and the clearance a start keeps to whatever stands beyond it, metres.
_BESIDE = _GAP[0] + 0.05


@dataclass
class _Wants:
    """What the rules of one object ask of its start (from their start hints)."""

    places: set[str] = field(default_factory=set)
    turns: set[str] = field(default_factory=set)
    related: set[int] = field(default_factory=set)  # every target row
    # per object hanging on the wall above this one: where its centre can go, (wall, u0, u1)
    # rows (surfaces.walls.hanging_centres), how far and how turned this one may stand
    # from that wall (surfaces.walls.target_stand), and the share of its extent, about its
    # middle, the centre goes over (surfaces.walls.target_middle)
    hanging: list[tuple[np.ndarray, tuple[float, float], float]] = field(default_factory=list)
    reach: float = 0.0  # how far from its start place its rules let it be (0: unsaid)
    # the one window or door a rule picks, by kind ("window", "door") -> index in the room's
    picks: dict[str, int] = field(default_factory=dict)
    # per target row it is turned towards, the largest angle its rule lets the target lie
    # off its front (StartHint.cone), degrees
    cones: dict[int, float] = field(default_factory=dict)
    # standing in front of or behind its parent: the depth of its own access zone on its
    # side towards the parent, or of the parent's zone on that side where it may not stand
    # in it, the deeper (an island in front of a counter; :func:`_own_gaps`), metres; the
    # start keeps that much floor between the two
    own_gap: float = 0.0
    # standing in front of or behind its parent: the largest footprint gap its rules allow
    # (StartHint.reach there), metres
    gap: float = np.inf
    # per target row, the smallest footprint gap a rule asks of it (StartHint.least), metres:
    # kept where it starts in front of or behind that target
    apart: dict[int, float] = field(default_factory=dict)
    # per target row it starts all round (a rule with StartHint.reach and no place: near),
    # the largest footprint gap a rule allows, metres: the start's gap spreads over it
    around: dict[int, float] = field(default_factory=dict)
    # per wall object hung on one wall the plan names that a close rule ties it to (a
    # teacher's desk near the whiteboard on the front wall): that wall, and how far (metres)
    # its footprint may be from the wall's line for the rule to be met
    pinned: list[tuple[int, float]] = field(default_factory=list)
    # the wall objects (ids) it is turned towards by a rule (a beanbag facing the TV on the
    # wall): they are hung after the floor settles, where they meet the most such rules
    views: set[str] = field(default_factory=set)
    # per such rule, what the wall object needs (_Sight)
    sights: list[_Sight] = field(default_factory=list)


@dataclass(frozen=True)
class _Sight:
    """A wall object a floor object is turned towards by a rule, as a start sees it."""

    #: the wall object's id
    target: str
    #: where its centre can go: (wall, u0, u1) rows of the walls' stretches clear of doors
    #: and windows (surfaces.walls.hanging_centres)
    spots: np.ndarray
    #: the rule's largest angle off the floor object's front, degrees
    angle: float
    #: its width, metres
    width: float
    #: the tallest a floor object at its wall may be with room for it above (the top of its
    #: band less its height), metres
    top: float
    #: floor objects taller than this between the two block the view (the rule's
    #: ``view_height``; none where it has none), metres
    view_height: float


def parents(model: ForceModel) -> np.ndarray:
    """The parent row of each simulated object (``-1`` for none), shape (N,).

    Each object's parent is the target of the rule with the lowest
    ``start.parent`` among its rules (:class:`~forcelayout.rules.StartHint`);
    bindings that would close a cycle are ignored.
    """
    n = model.n
    parent = np.full(n, -1, dtype=int)
    rank = np.full(n, np.iinfo(np.int64).max, dtype=np.int64)
    for g in model.groups:
        hint = g.rule.start
        if g.j is None or hint is None or hint.parent is None:
            continue
        r = int(hint.parent)
        for i, j in zip(g.i.tolist(), g.j.tolist(), strict=True):
            if r >= rank[i] or _reaches(parent, j, i):
                continue
            parent[i], rank[i] = j, r
    return parent


def _reaches(parent: np.ndarray, start: int, goal: int) -> bool:
    """Whether following parents from ``start`` reaches ``goal`` (bounded walk)."""
    cur = start
    for _ in range(parent.shape[0] + 1):
        if cur == goal:
            return True
        if cur < 0:
            return False
        cur = int(parent[cur])
    return False


def _order(parent: np.ndarray, area: np.ndarray, walkable: np.ndarray) -> list[int]:
    """Largest groups first, each root followed at once by its descendants (largest first).

    A group is as large as the largest object in it that takes floor (a rug
    under a table takes none): a small TV stand that a sofa faces is placed
    when the sofa's size says, not after every cabinet.
    Children come right after their parent, so the room kept free beside a
    parent is taken by its children before any unrelated object can take it.
    """
    n = parent.shape[0]
    kids: dict[int, list[int]] = {}
    taken = np.where(walkable, 0.0, area)
    big = taken.copy()  # largest footprint in each subtree
    for r in range(n):
        kids.setdefault(int(parent[r]), []).append(r)
        up = int(parent[r])
        for _ in range(n):  # parents() never forms a cycle; bounded all the same
            if up < 0:
                break
            big[up] = max(big[up], taken[r])
            up = int(parent[up])
    for v in kids.values():
        v.sort(key=lambda r: (-big[r], -area[r], r))
    out: list[int] = []
    stack = list(reversed(kids.get(-1, [])))
    while stack and len(out) < n:
        r = stack.pop()
        out.append(r)
        stack.extend(reversed(kids.get(r, [])))
    seen = set(out)  # parents() never forms a cycle; this only guards the bound above
    return out + [r for r in range(n) if r not in seen]


def _wants(model: ForceModel) -> list[_Wants]:
    """For each row: what its simulated bindings' start hints ask of its start."""
    out = [_Wants() for _ in range(model.n)]
    for g in model.groups:
        hint = g.rule.start
        js = g.j.tolist() if g.j is not None else [-1] * len(g.i)
        for b, (i, j) in enumerate(zip(g.i.tolist(), js, strict=True)):
            w = out[i]
            if j >= 0:
                w.related.add(j)
            if hint is None:
                continue
            if hint.place is not None:
                w.places.add(hint.place)
            if hint.turn is not None:
                w.turns.add(hint.turn)
            if hint.reach is not None and hint.place in ("front", "back"):
                w.gap = min(w.gap, float(getattr(g.params, hint.reach)[b]))
            elif hint.reach is not None and hint.place is None:
                if j >= 0:
                    w.around[j] = min(w.around.get(j, np.inf),
                                      float(getattr(g.params, hint.reach)[b]))
            elif hint.reach is not None:
                w.reach = max(w.reach, float(getattr(g.params, hint.reach)[b]))
            if hint.least is not None and j >= 0:
                w.apart[j] = max(w.apart.get(j, 0.0), float(getattr(g.params, hint.least)[b]))
            if hint.cone is not None and j >= 0:
                w.cones[j] = min(w.cones.get(j, 180.0), float(getattr(g.params, hint.cone)[b]))
            if hint.which is not None and getattr(g.params, hint.which)[b] >= 0:
                w.picks[hint.place] = int(getattr(g.params, hint.which)[b])
    # two objects each in front of the other, or each behind the other (desks back to
    # back): the one that starts at its parent's side is turned about to it
    sides = {(int(i), int(j)): g.rule.start.place for g in model.groups
             if g.j is not None and g.rule.start is not None
             and g.rule.start.place in ("front", "back")
             for i, j in zip(g.i.tolist(), g.j.tolist(), strict=True)}
    for (i, j), place in sides.items():
        if sides.get((j, i)) == place:
            out[i].turns.add("about")
    row = {oid: k for k, oid in enumerate(model.ids)}
    for b in model.wall_views:  # floor objects turned towards a wall object
        out[row[b.object]].views.add(b.target)
        hangs = model.compiled.surface_of(b.target)
        if hangs is not None and hangs.target is None:
            w, _, h = model.plan.object(b.target).size
            high = wall_band(hangs, model.plan.room.height)[1]
            out[row[b.object]].sights.append(_Sight(
                b.target, hanging_centres(model.plan, hangs, None),
                float(getattr(b.params, "max_angle", 90.0)), float(w), high - float(h),
                float(getattr(b.params, "view_height", np.inf))))
    for tie in pinned_ties(model.compiled, model.ids):  # tied to a wall object that hangs
        # on the one wall its rule names (a teacher's desk near the whiteboard)
        out[row[tie.floor]].pinned.append((tie.wall, tie.reach))
    for b in model.compiled.bindings:  # objects that something hangs on the wall above
        if b.rule.start is not None and b.rule.start.clear_wall_above_target \
                and b.target in row:
            top = float(model.plan.object(b.target).size[2])
            out[row[b.target]].hanging.append((hanging_centres(model.plan, b, top),
                                               target_stand(b), target_middle(b)))
    return out


def _side_room(model: ForceModel, parent: np.ndarray, wants: list[_Wants]
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Wall length to keep free on each side of a parent for the children standing beside it.

    A child that stands at the wall to the ``left`` or ``right`` of its parent
    needs its width on that side, plus ``_BESIDE`` (the closest gap it starts
    at and the clearance a start keeps); children that may stand on either
    side (``beside``) are shared out, widest first, to the side that
    needs less so far (two nightstands: one each side; one nightstand: one
    side, either one).

    Returns
    -------
    sides : ndarray, shape (N, 2)
        Metres to keep free on the left (local -x) and the right (local +x).
    count : ndarray, shape (N, 2)
        How many children stand on each side.
    either : ndarray of bool, shape (N,)
        Whether the sides may be swapped (some child may stand on either side).
    depth : ndarray, shape (N,)
        How deep the deepest of those children is, metres: they stand with their backs
        level with the parent's, so that much of its depth is kept free beside it.
    """
    n = model.n
    sides = np.zeros((n, 2))
    depth = np.zeros(n)
    count = np.zeros((n, 2))
    either = np.zeros(n, dtype=bool)
    free: dict[int, list[int]] = {}
    for c in range(n):
        q, places = int(parent[c]), wants[c].places
        if q < 0 or "wall" not in places or not places & _SIDE_PLACES:
            continue
        need = float(model.size[c, 0]) + _BESIDE
        depth[q] = max(depth[q], float(model.size[c, 1]))
        if "left" in places:
            sides[q, 0] += need
            count[q, 0] += 1
        elif "right" in places:
            sides[q, 1] += need
            count[q, 1] += 1
        else:
            free.setdefault(q, []).append(c)
    for q, kids in free.items():
        either[q] = True
        for c in sorted(kids, key=lambda c: (-model.size[c, 0], c)):
            k = int(sides[q, 1] < sides[q, 0])
            sides[q, k] += float(model.size[c, 0]) + _BESIDE
            count[q, k] += 1
    return sides, count, either, np.minimum(depth, model.size[:, 1])


def _ray_to_walls(room, p: np.ndarray, yaw: float) -> np.ndarray | None:
    """Where the ray from ``p`` (2,) along the front of heading ``yaw`` first meets a wall,
    (2,), or None (a point outside the room looking away from it)."""
    f = np.array([[-np.sin(yaw), np.cos(yaw)]])
    _, _, s = geo.rays_to_walls(room, p[None], f)
    return None if not np.isfinite(s[0]) else p + s[0] * f[0]


def _opening_turn(room, turns: set[str], places: set[str]) -> np.ndarray | None:
    """The centres (M, 2) of the openings an object's start turns its front towards
    (``face_window`` / ``face_door``), or None: none asked, none in the room, the object
    backed against a wall, or a rule turning it towards its target."""
    if places & {"wall", "corner"} or turns & {"face_target", "target_heading"}:
        return None
    for turn, kind in StartHint.OPENING_TURNS.items():
        openings = getattr(room, kind)
        if turn in turns and len(openings):
            return openings.centre
    return None


def _opening_centres(room, w: _Wants) -> np.ndarray | None:
    """The centres (K, 2) of the openings an object starts near: the windows if its
    rules ask for one, else the doors (every one of the kind, or the one a rule picks);
    None if neither."""
    for kind, o in (("window", room.windows), ("door", room.doors)):
        if kind in w.places and len(o):
            return o.centres(w.picks.get(kind, -1))
    return None


class _Draws:
    """Random numbers of B samples, each from its own generator, drawn for all at once.

    Each sample's generator gives a block of uniform numbers at a time (one
    call per sample, where a draw per sample for each kind of number was a
    tenth of a crowded plan's CPU); the methods take the next ones of every
    sample's block, so sample ``b``'s numbers depend on ``rngs[b]`` and on
    what it took before only, never on the other samples of its batch. What
    is left of a block when the object is dropped is not used.
    """

    def __init__(self, rngs: Sequence[np.random.Generator], block: int = _BLOCK):
        self.rngs, self.block = list(rngs), block
        self.buf = np.empty((len(self.rngs), 0))
        self.at = 0

    def random(self, shape: int | tuple[int, ...]) -> np.ndarray:
        """Uniform numbers in [0, 1) of shape (B, *shape)."""
        shape = (shape,) if isinstance(shape, int) else tuple(shape)
        n = math.prod(shape)
        if self.at + n > self.buf.shape[1]:  # every sample draws its next block
            fresh = np.stack([g.random(max(n, self.block)) for g in self.rngs])
            self.buf = np.concatenate([self.buf[:, self.at:], fresh], axis=1)
            self.at = 0
        out = self.buf[:, self.at: self.at + n]
        self.at += n
        return out.reshape(len(self.rngs), *shape)

    def uniform(self, lo: Any, hi: Any, shape: int | tuple[int, ...]) -> np.ndarray:
        """Uniform numbers in [lo, hi), shape (B, *shape)."""
        return lo + (np.asarray(hi) - lo) * self.random(shape)

    def integers(self, n: int, shape: int | tuple[int, ...]) -> np.ndarray:
        """Whole numbers in [0, n), shape (B, *shape)."""
        return np.minimum((self.random(shape) * n).astype(np.int64), n - 1)

    def normal(self, sd: float, shape: int | tuple[int, ...]) -> np.ndarray:
        """Normal numbers of mean 0 and deviation ``sd`` (Box-Muller), shape (B, *shape)."""
        u, v = self.random(shape), self.random(shape)
        return sd * np.sqrt(-2.0 * np.log1p(-u)) * np.cos(2.0 * np.pi * v)


def _snap_to_wall(
    room, cand: np.ndarray, half: np.ndarray, walls: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Put candidates (..., 2) backs against a wall (the nearest, or ``walls``, (...)),
    fronts inward."""
    shape = cand.shape[:-1]
    cand = cand.reshape(-1, 2)
    if walls is None:
        s = cand @ room.normal.T - room.normal_offset
        t = cand @ room.tangent.T - room.tangent_offset
        beyond = np.maximum(np.maximum(-t, t - room.length), 0.0)
        walls = np.argmin(np.abs(s) + beyond + (room.length < 2 * half[0]) * 100.0, axis=1)
    else:
        walls = np.broadcast_to(walls, shape).reshape(-1)
    n, tan, length = room.normal[walls], room.tangent[walls], room.length[walls]
    along = cand[:, 0] * tan[:, 0] + cand[:, 1] * tan[:, 1] - room.tangent_offset[walls]
    lo = np.minimum(half[0] + 0.01, length * 0.5)  # clear of the wall at its end
    along = np.minimum(np.maximum(along, lo), length - lo)
    pos = room.a[walls] + tan * along[:, None] + n * (half[1] + 0.01)
    return pos.reshape(*shape, 2), geo.yaw_facing(n).reshape(shape)


def _wall_candidates(
    room,
    draws: _Draws,
    k: int,
    half: np.ndarray,
    near: np.ndarray | None,
    sides: np.ndarray | None = None,
    weight: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """``k`` poses per sample (B, k) with the back against a random wall (or the wall
    nearest each of the ``near`` points, (B, k, 2), if given). ``weight`` (B, W), where
    given, draws each sample's walls by it instead of by their lengths.

    ``sides`` (metres to keep free on the left and the right, see
    :func:`_side_room`) asks for walls long enough for the object and the
    children standing beside it; the room both sides share is left free at
    either end of the wall.
    """
    if near is not None:
        return _snap_to_wall(room, near, half)
    left, right = (0.0, 0.0) if sides is None else (float(sides[0]), float(sides[1]))
    ok = room.length >= 2 * half[0] + left + right + 0.02
    end = half[0] + 0.01  # the centre's distance from either end of the wall
    if ok.any():
        end += min(left, right)
    else:  # no wall takes its children too: any wall that takes the object
        ok = room.length >= 2 * half[0] + 0.02
    if weight is None:  # a wall drawn by its length
        by_length = np.where(ok, room.length, 0.0)
        if by_length.sum() <= 0:
            by_length = room.length.copy()
        weight = (by_length / by_length.sum())[None]
    cdf = np.cumsum(weight, axis=1)  # (B or 1, W)
    cdf /= cdf[:, -1:]
    walls = np.minimum((draws.random(k)[..., None] >= cdf[:, None, :]).sum(axis=2),
                       len(room.length) - 1)
    slack = np.maximum(room.length[walls] - 2 * end, 0.0)
    along = end + draws.random(k) * slack
    cand = room.a[walls] + room.tangent[walls] * along[..., None]
    return _snap_to_wall(room, cand, half, walls)


def _near_opening(draws: _Draws, k: int, centre: np.ndarray, reach: float) -> np.ndarray:
    """``k`` points per sample (B, k, 2) near random openings of ``centre`` (M, 2): spread
    evenly over the disc of radius ``reach`` where the rules say how far the object may be,
    else close around."""
    pick = centre[draws.integers(len(centre), k)]
    if reach <= 0:
        return pick + draws.normal(0.6, (k, 2))
    r = reach * np.sqrt(draws.random(k))
    a = draws.uniform(-np.pi, np.pi, k)
    return pick + r[..., None] * np.stack([np.cos(a), np.sin(a)], axis=-1)


def _back_access(access: AccessTerm | None, n: int) -> np.ndarray:
    """The depth (N,) of the access zone behind each of ``n`` rows (0 for none): the room a
    chair at a table needs behind it to be pulled out."""
    out = np.zeros(n)
    if access is not None:
        back = access.direction[:, 1] < -0.5
        np.maximum.at(out, access.owner[back], access.depth[back])
    return out


def _own_gaps(access: AccessTerm | None, parent: np.ndarray, wants: list[_Wants]) -> None:
    """Set ``own_gap`` of each row that starts in front of or behind its parent: the
    depth of its access zone on its side towards the parent (its front where it turns
    to face the parent, else its back in front of the parent and its front behind it),
    or of the parent's zone on that side where the row may not stand in it, the deeper
    (an island in front of a counter, used itself: :func:`forcelayout.access.related_pairs`)."""
    if access is None:
        return
    for c, w in enumerate(wants):
        q = int(parent[c])
        if q < 0 or not w.places & {"front", "back"}:
            continue
        towards = 1.0 if "face_target" in w.turns or "back" in w.places else -1.0
        mine = (access.owner == c) & (access.direction[:, 1] * towards > 0.5)
        side = -1.0 if "back" in w.places else 1.0
        theirs = (access.owner == q) & (access.direction[:, 1] * side > 0.5) \
            & ~access.exempt[:, c]
        # the two zones may be one stretch of floor (the aisle between island and counter)
        w.own_gap = float(access.depth[mine | theirs].max()) if (mine | theirs).any() else 0.0


def _corner_candidates(
    room, draws: _Draws, k: int, half: np.ndarray
) -> tuple[np.ndarray, np.ndarray] | None:
    """``k`` poses per sample (B, k) tucked into random convex corners, backs against one
    of the walls."""
    convex = room.convex_corners[0]
    if convex.size == 0:
        return None
    v = convex[draws.integers(convex.size, k)]
    back_first = draws.random(k) < 0.5
    w1, w2 = (v - 1) % room.n_walls, v  # the two walls meeting at vertex v
    wb = np.where(back_first, w1, w2)  # wall behind the object
    ws = np.where(back_first, w2, w1)  # wall at its side
    pos = (room.a[v] + room.normal[wb] * (half[1] + 0.01)
           + room.normal[ws] * (half[0] + 0.01))
    return pos, geo.yaw_facing(room.normal[wb].reshape(-1, 2)).reshape(wb.shape)


def _back_walls(room, p: np.ndarray, yaw: np.ndarray, half: np.ndarray) -> np.ndarray:
    """The wall each object at pose (p (B, 2), yaw (B,), half extents (B, 2)) stands with
    its back against, or -1, (B,)."""
    f = geo.front_vectors(yaw)
    s = p @ room.normal.T - room.normal_offset - half[:, 1:2]  # (B, W)
    t = p @ room.tangent.T - room.tangent_offset
    ok = (f @ room.normal.T > 0.9) & (np.abs(s) < 0.15) & (t > -0.1) & (t < room.length + 0.1)
    return np.where(ok.any(1), np.argmin(np.where(ok, np.abs(s), np.inf), axis=1), -1)


def _child_candidates(room, draws: _Draws, k, wants: _Wants, q: np.ndarray, r, pos, yaw, half,
                      radius, spread) -> tuple[np.ndarray, np.ndarray]:
    """Poses (B, k) for object ``r`` around its parent ``q`` (a row per sample, (B,)),
    laid out as its rules ask."""
    places, turns = wants.places, wants.turns
    nb = len(q)
    bi = np.arange(nb)
    yq, pq, hq = yaw[bi, q], pos[bi, q][:, None, :], half[q]  # (B,), (B, 1, 2), (B, 2)
    fq = geo.front_vectors(yq)[:, None, :]  # (B, 1, 2)
    rq = geo.right_vectors(yq)[:, None, :]
    side = np.where(draws.random(k) < 0.5, -1.0, 1.0)  # (B, k)
    if "right" in places:
        side[:] = 1.0
    elif "left" in places:
        side[:] = -1.0
    gap = draws.uniform(_GAP[0], _GAP[1], k)[..., None]  # (B, k, 1)
    same = np.repeat(yq[:, None], k, axis=1)
    if "beneath" in places:  # centred under the parent, square with it
        return pq + draws.normal(0.05, (k, 2)), same
    if places & {"front", "back"}:
        sign = -1.0 if "back" in places else 1.0
        # beyond its own zone (or the parent's), within the gap its rules allow, a little
        # less as their forces aim (two rows of seats 0.6 m apart)
        lo, hi = wants.own_gap + 0.1, wants.own_gap + 0.1 + spread
        if np.isfinite(wants.gap):
            cap = wants.gap - min(0.1, 0.5 * wants.gap)
            lo, hi = min(lo, cap), max(min(hi, cap), min(lo, cap))
        # and at least as far as a rule keeps it from that parent (a viewing distance)
        least = np.array([wants.apart.get(int(p), 0.0) for p in q])[:, None]  # (B, 1)
        lo = np.maximum(lo, least + np.where(least > 0, 0.05, 0.0))
        hi = np.maximum(hi, lo)
        dist = hq[:, 1:2] + half[r, 1] + draws.uniform(lo, hi, k)
        # centred, or anywhere along the parent's width (three stools at one island)
        reach = np.maximum(hq[:, 0] - half[r, 0], 0.0)[:, None]
        centred = draws.random(k) < 0.5
        lat = np.where(centred, draws.normal(0.15, k), draws.uniform(-reach, reach, k))
        cand = pq + sign * fq * dist[..., None] + rq * lat[..., None]
        if "face_target" in turns:  # towards the nearest point of the parent (facing)
            return cand, _facing(cand, pq, rq, fq, hq)
        if "about" in turns:  # back to back (or face to face) with it
            return cand, same + np.pi
        return cand, same
    if places & _SIDE_PLACES and "face_target" in turns and "wall" not in places:
        # at the side, turned to it: anywhere along it (three stools on the left of an
        # island), square to it
        reach = np.maximum(hq[:, 1] - half[r, 0], 0.0)[:, None]
        cand = (pq + rq * (side[..., None] * (hq[:, None, 0:1] + half[r, 1] + gap))
                + fq * draws.uniform(-reach, reach, k)[..., None])
        return cand, _facing(cand, pq, rq, fq, hq)
    if places & _SIDE_PLACES:
        wall = (_back_walls(room, pos[bi, q], yq, hq) if "wall" in places
                else np.full(nb, -1))
        # beside it with the backs level (a nightstand at the head of the bed, a side
        # table at the sofa's arm), not at the middle of its side
        cand = (pq + rq * (side[..., None] * (hq[:, None, 0:1] + half[r, 0] + gap))
                - fq * (hq[:, None, 1:2] - half[r, 1]))
        # half the draws on the parent's wall; the other half against whichever wall is
        # nearest beside the parent's side, towards its back (a nightstand at the side
        # wall of a bed near a corner); every other one of those, where a wall runs right
        # past that side, just past the parent's front edge on it (a fridge round the
        # corner from a counter that fills its corner)
        m = k // 2
        # drawn by every sample, its parent at a wall or not: what a sample draws never
        # depends on the other samples of its batch
        back_share = draws.random((m, 1))
        at = np.flatnonzero(wall >= 0)
        if len(at) == 0:
            return cand, same
        c, sd, gp = cand[at], side[at], gap[at]
        pa, fa, ra, ha = pq[at], fq[at], rq[at], hq[at][:, None, :]
        on_wall = _snap_to_wall(room, c[:, m:], half[r], np.repeat(wall[at, None], k - m, 1))
        out = pa + ra * (sd[:, :m, None] * (ha[..., 0:1] + half[r, 1] + gp[:, :m]))
        back = back_share[at] * half[q[at], 1][:, None, None]
        near_side = _snap_to_wall(room, out - fa * back, half[r])
        past = out + fa * (ha[..., 1:2] + half[r, 0] + gp[:, :m])
        round_corner = _snap_to_wall(room, past, half[r])
        moved = round_corner[0] - past  # onto a wall across that side, facing the parent
        facing = geo.yaw_facing((-sd[:, :m, None] * ra).reshape(-1, 2)).reshape(len(at), m)
        use = ((np.arange(m) % 2 == 1) & (np.abs(np.sin(round_corner[1] - facing)) < 0.1)
               & (np.cos(round_corner[1] - facing) > 0)
               & (np.hypot(moved[..., 0], moved[..., 1]) <= 2.0 * half[r, 1] + _BESIDE
                  + _GAP[1]))
        # round the corner last: the first of equally good candidates is taken, and a
        # child at its parent's side is the usual arrangement (two beds share a nightstand)
        keep = np.concatenate([~use, np.ones((len(at), k - m), dtype=bool), use], axis=1)
        order = np.argsort(~keep, axis=1, kind="stable")[:, :k]
        every = np.concatenate([near_side[0], on_wall[0], round_corner[0]], axis=1)
        turned = np.concatenate([near_side[1], on_wall[1], round_corner[1]], axis=1)
        cyaw = same.copy()
        cand[at] = np.take_along_axis(every, order[..., None], axis=1)
        cyaw[at] = np.take_along_axis(turned, order, axis=1)
        return cand, cyaw
    if "all_round" in places:  # at a side of the parent (by its length), square to it
        out_c, out_y = np.empty((nb, k, 2)), np.empty((nb, k))
        which, along = draws.random(k), draws.uniform(-1.0, 1.0, k)
        for b in range(nb):  # the sides of each sample's parent
            normals, axes, lengths, depths = geo.box_sides(rq[b, 0], fq[b, 0], hq[b])
            cdf = np.cumsum(lengths / lengths.sum())
            s = np.minimum(cdf.searchsorted(which[b], side="right"), 3)
            reach = np.maximum(lengths[s] - half[r, 0], 0.0)
            out_c[b] = (pq[b] + normals[s] * (depths[s] + half[r, 1] + gap[b, :, 0])[:, None]
                        + axes[s] * (along[b] * reach)[:, None])
            out_y[b] = geo.yaw_facing(-normals[s])
        return out_c, out_y
    if "wall" in places and "face_target" in turns:  # across the room, on the wall it faces
        span = float(np.hypot(*(room.bounds[2:] - room.bounds[:2])))
        cand = pq + fq * draws.uniform(1.0, span, (k, 1)) + rq * draws.normal(0.3, (k, 1))
        cone = np.array([wants.cones.get(int(p), 0.0) for p in q])
        if not cone.any():
            return _snap_to_wall(room, cand, half[r])
        # half of them straight across, the other half anywhere along that wall the
        # rule's cone reaches (as far to the side as its force leaves it, 0.6 of the cone,
        # past the parent's half width: the nearest point of the parent is aimed at)
        across, _ = _snap_to_wall(room, cand, half[r])
        ahead = np.maximum(((across - pq) * fq).sum(-1), 0.0)  # (B, k)
        tan = np.tan(np.radians(np.minimum(0.6 * cone, 80.0)))[:, None]
        wide = draws.random(k) < 0.5
        lat = draws.uniform(-1.0, 1.0, k) * (hq[:, None, 0] + ahead * tan)
        cand = np.where(wide[..., None], across + rq * lat[..., None], cand)
        return _snap_to_wall(room, cand, half[r])
    ang = draws.uniform(-np.pi, np.pi, k)
    # all round it, as far beyond touching as ``spread`` or, where farther, a rule's
    # largest gap (a beanbag near the TV stand, within 1.5 m)
    far = np.array([max(spread, wants.around.get(int(p), 0.0)) for p in q])[:, None]
    dist = radius[q][:, None] * 0.8 + radius[r] + draws.random(k) * far
    cand = pq + dist[..., None] * np.stack([np.cos(ang), np.sin(ang)], axis=-1)
    if "wall" in places:
        return _snap_to_wall(room, cand, half[r])
    if "face_target" in turns:
        return cand, _facing(cand, pq, rq, fq, hq)
    if "target_heading" in turns:
        return cand, same
    return cand, draws.uniform(-np.pi, np.pi, k)


def _facing(cand: np.ndarray, pq: np.ndarray, rq: np.ndarray, fq: np.ndarray,
            hq: np.ndarray) -> np.ndarray:
    """Headings (B, K) of candidates (B, K, 2) turned towards the nearest point of their
    parent's footprint (centres ``pq``, axes ``rq``, ``fq`` and half sizes ``hq``, each
    (B, 1, 2) or (B, 2)): what ``facing`` aims at."""
    shape = cand.shape[:-1]
    pq, rq, fq, hq = (np.broadcast_to(a.reshape(len(cand), -1, 2), cand.shape)
                      for a in (pq, rq, fq, hq))
    aim = geo.facing_point(cand, pq, rq, fq, hq)
    return geo.yaw_facing((aim - cand).reshape(-1, 2)).reshape(shape)


def _unmet(room, wants: _Wants, cand, fwd, rgt, half_r) -> np.ndarray:
    """Candidates of an object that something hangs on the wall above, with no room for it, (K,).

    The wall object hangs on the wall behind this object (the ``above`` rule;
    :func:`~forcelayout.surfaces.walls.back_wall`, as
    :func:`forcelayout.surfaces.walls.place_on_walls` chooses it) with its
    centre over the middle of the footprint's extent along that wall (the
    rule's ``middle`` share of it); it has room where a stretch of that wall
    clear of doors and windows
    (:func:`~forcelayout.surfaces.walls.hanging_centres`) meets that middle.
    1 where a candidate leaves some hanging object no room, else 0.
    """
    unmet = np.zeros(len(cand))
    if not wants.hanging:
        return unmet
    corners = geo.corners_from_axes(cand, rgt, fwd, np.broadcast_to(half_r, cand.shape))
    for spots, (gap, turn), middle in wants.hanging:
        wall, behind = back_wall(room, corners, fwd, gap, turn)  # (K,)
        u = np.einsum("kcd,kd->kc", corners, room.tangent[wall]) \
            - room.tangent_offset[wall][:, None]  # (K, 4)
        lo, hi = middle_span(u.min(axis=1)[:, None], u.max(axis=1)[:, None], middle)
        fits = ((wall[:, None] == spots[:, 0]) & (spots[:, 1] <= hi)
                & (spots[:, 2] >= lo)).any(axis=1)
        unmet += ~(fits & behind)
    return unmet


def _sight_spot(room, sight: _Sight, p: np.ndarray, f: np.ndarray, corners: np.ndarray,
                tops: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Where the wall object of ``sight`` would hang for an object at ``p`` (C, 2) looking
    along ``f`` (C, 2), with floor objects of footprints ``corners`` (C, M, 4, 2) and
    heights ``tops`` (M,) standing where ``counts`` (C, M) says: of the spots of its
    stretches clear of doors and windows within the rule's angle of the front, the one
    nearest where the front's ray meets the wall that no object too tall for it standing
    at that wall (within the reach wall objects keep clear of) covers, widened by half
    its width. Its centre on the wall line, (C, 2); NaN where there is none (a bed whose
    foot faces the window, the TV it faces to hang on that wall; a wardrobe at that wall)."""
    wall, u, dist = geo.rays_to_walls(room, p, f)
    hit = wall >= 0
    w = np.where(hit, wall, 0)
    u, dist = np.where(hit, u, 0.0), np.where(hit, dist, 0.0)
    cone = dist * np.tan(np.radians(min(sight.angle, 89.0)))
    spots = sight.spots  # (J, 3)
    lo = np.maximum(spots[None, :, 1], (u - cone)[:, None])  # (C, J)
    hi = np.minimum(spots[None, :, 2], (u + cone)[:, None])
    ok = (spots[None, :, 0] == w[:, None]) & (lo <= hi)
    if corners.shape[1]:
        s = np.einsum("cmkd,cd->cmk", corners, room.normal[w]) \
            - room.normal_offset[w][:, None, None]
        a = np.einsum("cmkd,cd->cmk", corners, room.tangent[w]) \
            - room.tangent_offset[w][:, None, None]
        length = room.length[w][:, None]
        widen = sight.width / 2 + MARGIN
        b0 = np.clip(a.min(axis=2), 0.0, length)  # (C, M)
        b1 = np.clip(a.max(axis=2), 0.0, length)
        blocks = counts & (s.min(axis=2) <= REACH) & (tops[None] > sight.top + 1e-9) \
            & (b1 - b0 > 1e-3)
        b0, b1 = b0 - widen, b1 + widen
    else:
        b0 = b1 = np.zeros((len(p), 0))
        blocks = np.zeros((len(p), 0), dtype=bool)
    x = np.concatenate([u[:, None], lo, hi, b0 - 1e-6, b1 + 1e-6], axis=1)  # (C, P)
    allowed = ((lo[:, None] <= x[..., None]) & (x[..., None] <= hi[:, None])
               & ok[:, None]).any(axis=2)
    covered = ((b0[:, None] < x[..., None]) & (x[..., None] < b1[:, None])
               & blocks[:, None]).any(axis=2)
    off = np.where(allowed & ~covered & hit[:, None], np.abs(x - u[:, None]), np.inf)
    k = np.argmin(off, axis=1)
    rows = np.arange(len(p))
    best = x[rows, k]
    point = room.a[w] + room.tangent[w] * best[:, None]
    return np.where(np.isfinite(off[rows, k])[:, None], point, np.nan)


def _across(a: np.ndarray, b: np.ndarray, pos: np.ndarray, right: np.ndarray,
            front: np.ndarray, half: np.ndarray, width: float = 0.1) -> np.ndarray:
    """Whether rectangles (C, M) at ``pos`` (C, M, 2) with unit axes ``right``, ``front``
    (C, M, 2) and half extents ``half`` (M, 2) stand on the lines of sight from ``a`` to
    ``b`` (C, 2 each), strips ``width`` metres wide (as
    :func:`~forcelayout.rules.shaping.view_blockers` sees them)."""
    u, length = unit(b - a, fallback=True)
    mid = 0.5 * (a + b)
    perp = np.stack([u[:, 1], -u[:, 0]], axis=1)
    strip = np.stack([np.full(len(a), 0.5 * width), 0.5 * length], axis=1)
    return geo.obb_separation(pos - mid[:, None], perp[:, None], u[:, None], strip[:, None],
                              right, front, np.broadcast_to(half, pos.shape)) < 0.0


def _bindings_of(model: ForceModel) -> list[list[tuple[RuleGroup, int]]]:
    """For each row, the (group, position in the group) of every binding it takes part in."""
    out: list[list[tuple[RuleGroup, int]]] = [[] for _ in range(model.n)]
    for g in model.groups:
        js = g.j.tolist() if g.j is not None else [-1] * len(g.i)
        for b, (i, j) in enumerate(zip(g.i.tolist(), js, strict=True)):
            out[i].append((g, b))
            if j >= 0 and j != i:
                out[j].append((g, b))
    return out


def _rooms(placed: Sequence[Sequence[int]]) -> tuple[list[int], list[set[int]] | None]:
    """The rows placed in some sample (``placed[b]``: sample ``b``'s), and each sample's
    set of them; the first sample's rows in its order and None when all placed the same."""
    first = list(placed[0])
    if all(pl is placed[0] or list(pl) == first for pl in placed):
        return first, None
    sets = [set(pl) for pl in placed]
    return sorted(set().union(*sets)), sets


def _unmet_rules(model: ForceModel, bindings: list[tuple[RuleGroup, int]], r: int,
                 cand: np.ndarray, cyaw: np.ndarray, pos: np.ndarray, yaw: np.ndarray,
                 placed: Sequence[Sequence[int]]) -> np.ndarray:
    """How many of object ``r``'s bindings each candidate pose misses, by the rules' own checks.

    Every binding the object takes part in (as object or as target) whose
    other object stands in the sample's room (``placed[b]``: the rows placed in
    sample ``b``) is judged. Candidates (B, K, 2) and (B, K) of B samples with
    poses (B, N, 2) and (B, N); each candidate is judged against its own sample's
    objects alone (one stacked state of B K rooms: no candidate stands in the line
    of sight of another; where a rule is not ``batched``, each sample's candidates
    stand side by side in its room and the rule is called once per sample).
    Where samples have placed different objects, each sample's state holds the
    rows placed in any of them, those not placed in it far outside the room
    (no built-in rule judges a binding by objects that far away); a plugin
    rule that is not ``batched`` is judged on each sample's own rows.
    Shape (B, K).
    """
    nb, k = cyaw.shape
    unmet = np.zeros((nb, k))
    rows, sets = _rooms(placed)
    done = set(rows)

    def other(g: RuleGroup, b: int) -> int:  # the binding's other object, -1 for the room
        if g.j is None:
            return -1
        return int(g.j[b]) if int(g.i[b]) == r else int(g.i[b])

    judged = [(g, b) for g, b in bindings if g.j is None or other(g, b) in done]
    if not judged:
        return unmet
    if sets is not None and not all(g.rule.batched for g, _ in judged):
        same: dict[tuple[int, ...], list[int]] = {}  # each sample's own rows, as alone
        for b, pl in enumerate(placed):
            same.setdefault(tuple(pl), []).append(b)
        for pl, bs in same.items():
            unmet[bs] = _unmet_rules(model, bindings, r, cand[bs], cyaw[bs], pos[bs],
                                     yaw[bs], [list(pl)] * len(bs))
        return unmet
    at = {p: q for q, p in enumerate(rows)}
    here = pos[:, rows]
    live = None
    if sets is not None:  # rows placed in some other sample only: far outside this one's room
        live = np.array([[p in sb for p in rows] for sb in sets], dtype=bool).reshape(nb, -1)
        far = model.room.bounds[2:] + 1e6 + 10.0 * np.arange(len(rows))[:, None]
        here = np.where(live[:, :, None], here, far[None])
    batched = all(g.rule.batched for g, _ in judged) and nb * k > 1
    if batched:  # each candidate in a room of its own: the placed objects and it alone
        m = len(rows) + 1
        size = np.concatenate([model.size[rows], model.size[r:r + 1]])
        state = State(np.concatenate([np.repeat(here[:, None], k, 1), cand[:, :, None]],
                                     axis=2).reshape(nb * k * m, 2),
                      np.concatenate([np.repeat(yaw[:, None, rows], k, 1), cyaw[:, :, None]],
                                     axis=2).reshape(nb * k * m),
                      np.tile(size, (nb * k, 1)), model.room, model.ids, samples=nb * k)
        base = np.arange(nb * k) * m  # (B K,) first row of each candidate's room
        me = base + len(rows)
    else:  # a sample's candidates side by side in its room (a rule seeing one at a time)
        m = len(rows) + k
        size = np.concatenate([model.size[rows], np.repeat(model.size[r:r + 1], k, 0)])
        state = State(np.concatenate([here, cand], axis=1).reshape(nb * m, 2),
                      np.concatenate([yaw[:, rows], cyaw], axis=1).reshape(nb * m),
                      np.tile(size, (nb, 1)), model.room, model.ids, samples=nb)
        base = np.repeat(np.arange(nb) * m, k)  # (B K,) first row of each candidate's sample
        me = base + np.tile(np.arange(len(rows), m), nb)
    for g, b in judged:
        if g.j is None:
            i, j = me, None
        elif int(g.i[b]) == r:  # this object is the binding's object
            i, j = me, base + at[other(g, b)]
        else:  # this object is the binding's target
            i, j = base + at[other(g, b)], me
        p = ParamArrays({f: np.repeat(v[b:b + 1], nb * k) for f, v in g.params._fields.items()},
                        np.repeat(g.params.weight[b:b + 1], nb * k))
        if batched or nb == 1:
            ok = g.rule.satisfied(state, i, j, p)
        else:  # a rule that sees one sample at a time
            one = ParamArrays({f: v[:k] for f, v in p._fields.items()}, p.weight[:k])
            ok = np.concatenate([
                np.asarray(g.rule.satisfied(state.sample(s), i[:k], None if j is None
                                            else j[:k], one), dtype=bool)
                for s in range(nb)])
        miss = ~np.asarray(ok, dtype=bool).reshape(nb, k)
        if live is not None and g.j is not None:  # judged only where the other one stands
            miss &= live[:, at[other(g, b)]][:, None]
        unmet += miss
    return unmet


def initial_poses(
    model: ForceModel,
    rng: np.random.Generator,
    *,
    tries: int = 16,
    spread: float = 0.3,
    restarts: int = 32,
    fixes: int = 2,
) -> tuple[np.ndarray, np.ndarray]:
    """Random start poses that already lean towards the rules; the best of ``restarts``.

    The first start of :func:`start_poses` with no failure, else the one
    with the fewest failures (the first on ties). So a bed that landed in a
    corner with no room for its second nightstand, or a sofa that can only
    face its TV from in front of a window, is tried elsewhere before any
    simulation time is spent on it.
    """
    best, best_score = None, -np.inf
    for pos, yaw, verdict in start_poses(model, rng, tries=tries, spread=spread,
                                         restarts=restarts, fixes=fixes):
        if verdict.ok:
            return pos, yaw
        if -len(verdict.failures) > best_score:
            best, best_score = (pos, yaw), -float(len(verdict.failures))
    return best  # type: ignore[return-value]


def start_poses(
    model: ForceModel,
    rng: np.random.Generator,
    *,
    tries: int = 16,
    spread: float = 0.3,
    restarts: int = 32,
    fixes: int = 2,
    misses: int = 0,
) -> Iterator[tuple[np.ndarray, np.ndarray, FloorVerdict]]:
    """Up to ``restarts`` independent starts, each with its verdict.

    Each start comes from :func:`propose_poses` and is judged as a settled
    floor is (:func:`forcelayout.verdict.judge_floor`: the deterministic
    checks and every rule's own check); unless it passes every check with at
    most ``misses`` unmet bindings (:meth:`FloorVerdict.passes`), up to
    ``fixes`` times the objects at fault (those blocking a path, colliding,
    in a door swing or a window zone, or with an unmet rule) and the objects
    that start beside them (the second time their parents too) are drawn
    again elsewhere (:func:`relocate`), kept if fewer failures remain. A
    start that passes with bindings unmet, as ``misses`` allows, has the
    objects of those drawn once more (with ``fixes`` > 0), kept if it still
    passes with fewer unmet. The caller stops drawing when it has what it
    needs.

    Yields
    ------
    pos : ndarray, shape (N, 2)
    yaw : ndarray, shape (N,)
    verdict : FloorVerdict
    """
    starts = Starts(model, rng, tries=tries, spread=spread, restarts=restarts, fixes=fixes,
                    misses=misses)
    while True:
        got = drive([starts.next()])[0]
        if got is None:
            return
        yield got


class Starts:
    """The starts of one sample, one at a time: what :func:`start_poses` yields.

    :meth:`next` is a sample task (:mod:`forcelayout.batching`): it asks for
    each set of start poses with a :class:`ProposeRequest` and for each fix
    with a :class:`RelocateRequest`, so the samples of a batch that draw a
    start (or fix one) at the same time draw together. Give the
    samples of a batch the same ``placer`` (:meth:`placer_of`) for that.

    With ``ahead`` > 1, a sample whose first two starts fail draws each next
    one from several (2, 4, ... up to ``ahead``), all judged together: the
    first that passes is its next start, else the first with the fewest
    failures, fixed as one start is; ``restarts`` counts these rounds, and
    no more than ``2 * restarts`` starts are drawn in all. A sample that needs
    many starts then draws them in a few large batches rather than in many
    small ones once the rest of its batch is done.
    """

    def __init__(self, model: ForceModel, rng: np.random.Generator, *,
                 placer: _Placer | None = None, tries: int = 16, spread: float = 0.3,
                 restarts: int = 32, fixes: int = 2, misses: int = 0, ahead: int = 1):
        self.model, self.rng = model, rng
        self.placer = placer if placer is not None or model.n == 0 else _Placer(model)
        self.tries, self.spread, self.fixes, self.misses = tries, spread, fixes, misses
        self.left = max(1, restarts)
        self.ahead = max(1, int(ahead))
        self.drawn = 0  # starts drawn so far (a sample's first draw is one start)
        # drawn at most twice as many as one at a time would: a sample that never passes
        # spends no more than that on its starts
        self.most = self.left if self.ahead == 1 else 2 * self.left

    @staticmethod
    def placer_of(model: ForceModel) -> _Placer:
        """The candidate drawer of a model, to share among the samples of a batch."""
        return _Placer(model)

    def next(self) -> SampleTask[tuple[np.ndarray, np.ndarray, FloorVerdict] | None]:
        """The next start ``(pos, yaw, verdict)``, or None once ``restarts`` are drawn."""
        model, rng = self.model, self.rng
        if self.left <= 0 or self.drawn >= self.most:
            return None
        if model.n == 0:
            self.left = 0
            return np.zeros((0, 2)), np.zeros(0), FloorVerdict()
        placer = self.placer
        # once two starts have failed, the next from 2, 4, ... up to ``ahead`` drawn at once:
        # a sample that needs many starts draws them in a few large batches, not in many
        # small ones once the other samples of its batch are done
        m = min(self.ahead, max(1, self.drawn), self.most - self.drawn)
        self.left -= 1  # a restart: one start fixed, however many were drawn for it
        self.drawn += m
        if m == 1:
            yaw = rng.uniform(-np.pi, np.pi, model.n)
            pos, yaw = yield ProposeRequest(placer, rng, yaw, self.tries, self.spread)
            verdict = yield _judging(model, pos, yaw)
        else:
            yaws = rng.uniform(-np.pi, np.pi, (m, model.n))
            poss, yaws = yield ProposeRequest(placer, rng, yaws, self.tries, self.spread)
            # judged without naming what blocks the way to an unreachable object (a path
            # search each): only the chosen one's objects at fault are needed, below
            verdicts = yield _judging(model, poss, yaws, blockers=False)
            # the first that passes, else the first with the fewest failures, fixed below
            k = next((i for i, v in enumerate(verdicts) if v.passes(self.misses)),
                     int(np.argmin([len(v.failures) for v in verdicts])))
            pos, yaw, verdict = poss[k], yaws[k], verdicts[k]
            if not verdict.passes(self.misses):
                verdict = yield _judging(model, pos, yaw)
        for f in range(max(0, self.fixes)):
            if verdict.passes(self.misses) or not verdict.at_fault:
                break
            p2, y2, again = yield from self._redrawn(verdict.at_fault, pos, yaw,
                                                     with_parents=f % 2 == 1)  # 2nd time
            if len(again.failures) < len(verdict.failures):
                pos, yaw, verdict = p2, y2, again
        for f in range(max(0, self.fixes)):
            if not (verdict.unmet and verdict.passes(self.misses)):
                break
            # passes with rules unmet, as the sample allows: the objects of those rules
            # are drawn again as a failing start's are (the second time with their
            # parents), kept if it still passes with fewer unmet (a bin left in mid-floor
            # finds a spot at a wall, a desk turns its front to the wall its chair stands
            # at), so the rules a start drops are those it cannot meet rather than the
            # first it missed
            p2, y2, again = yield from self._redrawn(verdict.at_fault, pos, yaw,
                                                     with_parents=f % 2 == 1)
            if again.passes(self.misses) and again.unmet < verdict.unmet:
                pos, yaw, verdict = p2, y2, again
        return pos, yaw, verdict

    def _redrawn(self, at_fault: set[int], pos: np.ndarray, yaw: np.ndarray, *,
                 with_parents: bool = False
                 ) -> SampleTask[tuple[np.ndarray, np.ndarray, FloorVerdict]]:
        """The start with the rows ``at_fault`` and those that start beside them (with
        ``with_parents``, their parents too: :func:`_movers`) drawn again, and its
        verdict."""
        rows = np.zeros(self.model.n, dtype=bool)
        rows[sorted(at_fault)] = True
        rows = _movers(self.placer.parent, rows, with_parents=with_parents)
        p2, y2 = yield RelocateRequest(self.placer, self.rng,
                                       tuple(np.flatnonzero(rows).tolist()), pos, yaw,
                                       self.tries, self.spread)
        again = yield _judging(self.model, p2, y2)
        return p2, y2, again


def _front_at_wall(w: _Wants) -> bool:
    """Whether a child stands in front of its parent with its back at a wall."""
    return "front" in w.places and "wall" in w.places


def _movers(parent: np.ndarray, rows: np.ndarray, *, with_parents: bool = False
            ) -> np.ndarray:
    """The objects drawn again with ``rows`` (bool, (N,)): their children, which start beside
    them, and with ``with_parents`` their parents and the parents' children too (a sofa that
    can only face its TV from under a low window moves with the TV)."""
    rows = rows.copy()
    if with_parents:
        up = parent[rows]
        rows[up[up >= 0]] = True
    return rows | np.isin(parent, np.flatnonzero(rows))


def _judging(model: ForceModel, pos: np.ndarray, yaw: np.ndarray, *, blockers: bool = True
             ) -> JudgeRequest:
    """The ask for the verdict on start poses; only the rules where rows are not the plan's
    objects.

    Rows that are not objects of the plan (an area's rectangle) are not
    checked here: their members are checked once the area is carried into
    the room. Nor are the wall objects' stretches of wall: the simulation and
    the repair still move what stands under a window; the candidates already
    lean away from leaving an object above them no room.
    """
    known = set(model.plan.ids)
    return JudgeRequest(model, pos, yaw, checks=all(oid in known for oid in model.ids),
                        blockers=blockers, walls=False)


def propose_poses(
    model: ForceModel, rng: np.random.Generator, *, tries: int = 16, spread: float = 0.3
) -> tuple[np.ndarray, np.ndarray]:
    """Random start poses inside the room that already lean towards the rules.

    Objects are placed parents first. Each draws ``tries`` candidate poses at
    once from a proposal chosen by its rules — a child around its parent (at
    most ``spread`` metres beyond touching), an ``in_corner`` object in a random
    convex corner, an ``at_wall`` object against a random wall (near the window
    or door if it should be), an ``in_middle`` object around the centroid (over
    the share of the room its rule allows), anything else uniformly in the room;
    objects that should stand at a wall are turned with their backs to it,
    objects that face a target are turned towards it. The first candidate whose
    footprint lies inside the floor, clear of the objects placed so far and of
    the door swing squares is kept (else the one with the most clearance), so
    the start is random — which wall, which corner, where along it — but close
    to a valid arrangement. Where no candidate is clear and meets every rule
    it can be judged by, a second draw is made; nothing loops beyond those two
    draws of ``tries`` candidates (and their fall-backs) per object.

    Returns
    -------
    pos : ndarray, shape (N, 2)
    yaw : ndarray, shape (N,)
    """
    n = model.n
    pos = np.zeros((n, 2))
    yaw = rng.uniform(-np.pi, np.pi, n)
    if n == 0:
        return pos, yaw
    pos, yaw = _propose(_Placer(model), [rng], pos[None], yaw[None], tries, spread)
    return pos[0], yaw[0]


def _propose(placer: _Placer, rngs: list[np.random.Generator], pos: np.ndarray,
             yaw: np.ndarray, tries: int, spread: float) -> tuple[np.ndarray, np.ndarray]:
    """Place every row of each sample (poses (B, N, 2) and (B, N)), parents first."""
    placed: list[int] = []
    for r in placer.order:
        placer.place(r, [placed] * len(rngs), pos, yaw, rngs, tries, spread)
        placed.append(r)
    return pos, yaw


class _DrawerRequest:
    """What the requests of one candidate drawer share: they run as one batch."""

    placer: _Placer
    tries: int
    spread: float

    def key(self) -> tuple:
        """Requests with equal keys are placed as one batch."""
        return (id(self.placer), self.tries, self.spread)


@dataclass
class ProposeRequest(_DrawerRequest):
    """A sample's ask for one set of start poses (:func:`propose_poses`), batched by
    :func:`forcelayout.batching.drive` with the asks of other samples of the same model.

    Attributes
    ----------
    placer : _Placer
        The model's candidate drawer; requests of the same one run as one batch.
    rng : numpy.random.Generator
        The sample's generator (each sample draws from its own only).
    yaw : ndarray, shape (N,) or (M, N)
        Headings before placing (kept where an object's draw sets none): one set of start
        poses, answered as ``(pos (N, 2), yaw (N,))``, or M sets, answered as
        ``(pos (M, N, 2), yaw (M, N))``, drawn one after another from ``rng``.
    tries, spread
        As for :func:`propose_poses`.
    """

    placer: _Placer
    rng: np.random.Generator
    yaw: np.ndarray
    tries: int
    spread: float

    @staticmethod
    def run(requests: list[ProposeRequest]) -> list[tuple[np.ndarray, np.ndarray]]:
        """Start poses ``(pos, yaw)`` for each request of one key, placed together."""
        first = requests[0]
        n = first.placer.model.n
        counts = [len(q.yaw) if q.yaw.ndim == 2 else 1 for q in requests]
        yaw = np.concatenate([q.yaw.reshape(-1, n) for q in requests])
        pos = np.zeros((len(yaw), n, 2))
        rngs = [q.rng for q, c in zip(requests, counts, strict=True) for _ in range(c)]
        pos, yaw = _propose(first.placer, rngs, pos, yaw, first.tries, first.spread)
        out, at = [], 0
        for q, c in zip(requests, counts, strict=True):
            out.append((pos[at: at + c], yaw[at: at + c]) if q.yaw.ndim == 2
                       else (pos[at], yaw[at]))
            at += c
        return out


def relocate(model: ForceModel, rows: list[int] | np.ndarray, pos: np.ndarray, yaw: np.ndarray,
             rng: np.random.Generator, *, tries: int = 16, spread: float = 0.3
             ) -> tuple[np.ndarray, np.ndarray]:
    """New start poses for some objects, the others staying where they are.

    Each object of ``rows`` (parents first) draws candidates from the
    proposal its rules choose and takes the best one, judged as in
    :func:`propose_poses` against every other object: used to repair a
    sample by moving an object that settled in a bad spot somewhere else.

    Returns
    -------
    pos, yaw : ndarray
        Copies of the poses with the rows moved.
    """
    return _relocate(model, _Placer(model), rows, pos, yaw, rng, tries, spread)


def _relocate(model: ForceModel, placer: _Placer, rows: list[int] | np.ndarray,
              pos: np.ndarray, yaw: np.ndarray, rng: np.random.Generator, tries: int,
              spread: float) -> tuple[np.ndarray, np.ndarray]:
    pos, yaw = _relocate_many(placer, [rows], pos[None], yaw[None], [rng], tries, spread)
    return pos[0], yaw[0]


def _relocate_many(placer: _Placer, rows: Sequence[Iterable[int]], pos: np.ndarray,
                   yaw: np.ndarray, rngs: list[np.random.Generator], tries: int, spread: float
                   ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`relocate` for B samples, sample ``b`` moving ``rows[b]``: poses (B, N, 2) and
    (B, N) (copies), each sample drawing from its own generator. Object by object in the
    drawer's order, the samples that move it draw for it together, each judged against
    the objects standing in its own room."""
    pos, yaw = pos.copy(), yaw.copy()
    moving = [{int(r) for r in rs} for rs in rows]
    placed = [[r for r in range(placer.model.n) if r not in m] for m in moving]
    for r in placer.order:
        sub = [b for b, m in enumerate(moving) if r in m]
        if not sub:
            continue
        p, y = pos[sub], yaw[sub]
        placer.place(r, [placed[b] for b in sub], p, y, [rngs[b] for b in sub], tries, spread)
        pos[sub], yaw[sub] = p, y
        for b in sub:
            placed[b].append(r)
    return pos, yaw


@dataclass
class RelocateRequest(_DrawerRequest):
    """A sample's ask to draw some of its objects again (:func:`relocate`), batched by
    :func:`forcelayout.batching.drive` with the asks of other samples of the same candidate
    drawer (whichever objects they move).

    Attributes
    ----------
    placer : _Placer
        The model's candidate drawer.
    rng : numpy.random.Generator
        The sample's generator.
    rows : tuple of int
        The rows to draw again, sorted; the others stay where they are.
    pos : ndarray, shape (N, 2)
    yaw : ndarray, shape (N,)
        The sample's poses before.
    tries, spread
        As for :func:`propose_poses`.
    """

    placer: _Placer
    rng: np.random.Generator
    rows: tuple[int, ...]
    pos: np.ndarray
    yaw: np.ndarray
    tries: int
    spread: float

    @staticmethod
    def run(requests: list[RelocateRequest]) -> list[tuple[np.ndarray, np.ndarray]]:
        """New poses ``(pos, yaw)`` for each request of one key, placed together."""
        first = requests[0]
        pos, yaw = _relocate_many(first.placer, [q.rows for q in requests],
                                  np.stack([q.pos for q in requests]),
                                  np.stack([q.yaw for q in requests]),
                                  [q.rng for q in requests], first.tries, first.spread)
        return [(pos[b], yaw[b]) for b in range(len(requests))]


class _Placer:
    """Draws and judges candidate poses for one object at a time."""

    def __init__(self, model: ForceModel):
        room = model.room
        n = model.n
        self.model, self.room = model, room
        self.half = half = model.size[:, :2] * 0.5
        self.radius = np.hypot(half[:, 0], half[:, 1])
        self.parent = parent = parents(model)
        self.wants = wants = _wants(model)
        # how high on its wall each row hides the wall, what hangs above it included (a
        # dresser 0.8 m tall with a mirror above it: about 1.8 m); a row not of the plan
        # (an area) its height
        floor = model.compiled.floor_ids
        hidden = dict(zip(floor, hidden_heights(model.compiled, floor).tolist(), strict=True))
        self.wall_top = np.array([max(h, hidden.get(oid, h)) for oid, h in
                                  zip(model.ids, model.size[:, 2].tolist(), strict=True)])
        self.walkable = model.walkable
        self.by_object = _bindings_of(model)
        self.window = next((t for t in model.terms if isinstance(t, WindowTerm)), None)
        self.access = next((t for t in model.terms if isinstance(t, AccessTerm)), None)
        self.viewers = [r for r in range(n) if wants[r].sights]
        self.order = _order(parent, model.size[:, 0] * model.size[:, 1], model.walkable)
        self.sides, self.side_count, self.either, self.side_depth = _side_room(model, parent,
                                                                               wants)
        # the rows a side-by-side binding ties to each row, either way round, other than
        # its parent: where it may also stand beside one that is placed
        self.side_others: list[list[int]] = [[] for _ in range(n)]
        for r in range(n):
            for g, b in self.by_object[r]:
                hint = g.rule.start
                if g.j is None or hint is None or hint.place not in _SIDE_PLACES:
                    continue
                i, j = int(g.i[b]), int(g.j[b])
                other = j if i == r else i
                if other != parent[r] and other not in self.side_others[r]:
                    self.side_others[r].append(other)
        # floor to keep free in front of a parent for children standing in front of it
        front, n_front, front_width = np.zeros(n), np.zeros(n), np.zeros(n)
        # and on every side of it for its children all round (the chairs at a table)
        around, n_around = np.zeros(n), np.zeros(n)
        # and, side by side, beyond them for their access zones behind them (room to pull
        # a chair out): how deep, and how wide a chair is with room beside it
        behind, zoned, seat = _back_access(self.access, n), np.zeros(n), np.zeros(n)
        _own_gaps(self.access, parent, wants)
        for c in range(n):
            # (a walkable cover in front, the mat at a shower, keeps no floor free: it may
            # lie in a door's swing and furniture may stand on it)
            if parent[c] >= 0 and "front" in wants[c].places and not model.walkable[c]:
                front[parent[c]] = max(front[parent[c]],
                                       model.size[c, 1] + 0.15 + wants[c].own_gap)
                front_width[parent[c]] = max(front_width[parent[c]], model.size[c, 0] + 0.1)
                n_front[parent[c]] += 1
            if parent[c] >= 0 and "all_round" in wants[c].places:
                around[parent[c]] = max(around[parent[c]], model.size[c, 1] + _GAP[0])
                zoned[parent[c]] = max(zoned[parent[c]],
                                       model.size[c, 1] + _GAP[0] + behind[c])
                seat[parent[c]] = max(seat[parent[c]], model.size[c, 0] + 0.1)
                n_around[parent[c]] += 1
        # children standing in front of a parent, turned to it, that face a wall object
        # too (an office chair at the desk facing the whiteboard): (child, sight) per parent
        self.front_sights: list[list[tuple[int, _Sight]]] = [[] for _ in range(n)]
        for c in range(n):
            if parent[c] >= 0 and "front" in wants[c].places \
                    and "face_target" in wants[c].turns:
                self.front_sights[parent[c]] += [(c, sight) for sight in wants[c].sights]
        self.front_margin, self.around_margin = front, around
        # a parent whose child in front of it belongs at a wall (a receptionist's chair
        # against the wall behind the desk) also draws spots facing a wall that margin off
        self.front_to_wall = np.zeros(n, dtype=bool)
        for c in range(n):
            if parent[c] >= 0 and _front_at_wall(wants[c]):
                self.front_to_wall[parent[c]] = True
        # one child in front needs a stretch of that floor as wide as itself, anywhere along
        # the parent (``in_front_of`` lets it stand off the centre line); several, all of it
        self.front_width = np.where(n_front == 1, front_width, np.inf)
        self.zoned_margin = np.where(zoned > around, zoned, 0.0)
        self.seat = seat
        self.n_front, self.n_around = n_front, n_around
        self.lo, self.hi = room.bounds[:2], room.bounds[2:]
        # a floor that is its own bounding box: a footprint lies on it when its corners lie
        # within the bounds (the sign of each comparison exact, as shapely's test is)
        self.box_floor = bool(room.shape.equals(shapely.box(*room.bounds)))

    def _clearance(self, cand: np.ndarray, rgt: np.ndarray, fwd: np.ndarray, ext: np.ndarray,
                   solid: list[int], slack: np.ndarray, pos: np.ndarray, yaw: np.ndarray,
                   doors: bool, present: np.ndarray | None = None
                   ) -> tuple[np.ndarray, np.ndarray]:
        """Whether footprints of half extent ``ext`` at the candidates (B, K, 2) lie inside
        the floor, and their clearance (at most 0.3 m) to the ``solid`` rows of their sample
        (those ``present`` (B, S) marks, all by default) and the door swing squares (what
        the door check asks; the simulation keeps a deeper entry zone free); both (B, K)."""
        hr, hf = rgt * ext[0], fwd * ext[1]
        corners = np.stack([cand - hr - hf, cand + hr - hf, cand + hr + hf, cand - hr + hf],
                           axis=2)
        bk = cand.shape[:2]
        if self.box_floor:
            inside = ((corners >= self.lo) & (corners <= self.hi)).all(axis=(2, 3))
        else:  # a corner within 1e-9 m of a wall is on it
            inside = self.room.contains_boxes(corners)
        clear = np.full(bk, 0.3)
        if solid:
            oy = yaw[:, solid]  # (B, S)
            sep = geo.obb_separation(pos[:, solid][:, None] - cand[:, :, None],
                                     rgt[:, :, None], fwd[:, :, None], ext[None, None, None],
                                     geo.right_vectors(oy)[:, None],
                                     geo.front_vectors(oy)[:, None],
                                     self.half[solid][None, None])  # (B, K, S)
            if present is not None:  # rows that stand in another sample's room only
                sep = np.where(present[:, None, :], sep, np.inf)
            # objects this one is related to may stand right beside it
            clear = np.minimum(clear, (sep + slack).min(axis=2))
        dc, dr, df, dh = self.room.door_squares
        if len(dc) and doors:
            dsep = geo.obb_separation(dc[None, None] - cand[:, :, None], rgt[:, :, None],
                                      fwd[:, :, None], ext[None, None, None], dr[None, None],
                                      df[None, None], dh[None, None])
            # clear of the swing square is what the door check asks; the simulation then
            # keeps its deeper entry zone free
            clear = np.minimum(clear, dsep.min(axis=2) + _CLEAR)
        return inside, clear

    def _access_misses(self, r: int, cand: np.ndarray, rgt: np.ndarray, fwd: np.ndarray,
                       solid: list[int], pos: np.ndarray, yaw: np.ndarray,
                       present: np.ndarray | None) -> np.ndarray:
        """How many objects each candidate (B, K) of row ``r`` leaves with no access zone
        free: placed objects whose last free zone it stands in, and ``r`` itself when every
        one of its zones there runs off the floor or into a placed object (the ``solid``
        rows, those ``present`` (B, S) marks in each sample). A zone is free of what
        :class:`~forcelayout.access.AccessTerm` does not push (the objects a rule keeps
        close to the owner, covers). Shape (B, K)."""
        acc, half = self.access, self.half
        misses = np.zeros(cand.shape[:2])
        if acc is None or self.walkable[r] or not (len(solid) or (acc.owner == r).any()):
            return misses
        rows = np.array(solid, dtype=int)
        s_rgt, s_fwd = geo.right_vectors(yaw[:, rows]), geo.front_vectors(yaw[:, rows])
        seen = np.ones((len(cand), len(rows)), dtype=bool) if present is None else present

        def blocked(zc, zo, zl, zh, zones):  # zones (..., 2) -> run off the floor or intruded
            # a far corner off the floor (the near ones are on the owner's side; a wall across
            # the zone with its corners on the floor, at the notch of a U-shaped room, goes
            # unseen: starts only lean)
            far = zc + zo * zh[..., 1:]
            off = ~self.room.contains(np.stack([far - zl * zh[..., :1], far + zl * zh[..., :1]],
                                               axis=-2)).all(-1)
            if not len(rows):
                return off
            lead = zc.ndim - 2  # axes between the sample axis and the rows
            at = (slice(None),) + (None,) * lead
            sep = geo.obb_separation(pos[:, rows][at] - zc[..., None, :], zl[..., None, :],
                                     zo[..., None, :], zh[..., None, :], s_rgt[at], s_fwd[at],
                                     half[rows])  # (B, ..., Z, S)
            hit = (sep < -_INTRUDE) & ~acc.exempt[zones][:, rows] & seen[at]
            return off | hit.any(-1)

        standing = np.zeros(len(half), dtype=bool)
        standing[rows] = True
        theirs = np.flatnonzero(standing[acc.owner] & ~acc.exempt[:, r])
        if len(theirs):  # placed objects' zones the candidate would stand in
            o = acc.owner[theirs]
            index = {k: i for i, k in enumerate(solid)}
            at = [index[k] for k in o]
            zc, zo, zl, zh = zone_boxes(pos[:, o], s_rgt[:, at], s_fwd[:, at], half[o],
                                        acc.direction[theirs], acc.depth[theirs])
            free = ~blocked(zc, zo, zl, zh, theirs) & seen[:, at]  # (B, Za)
            inside = geo.obb_separation(zc[:, None] - cand[:, :, None], rgt[:, :, None],
                                        fwd[:, :, None], half[r], zl[:, None], zo[:, None],
                                        zh[:, None]) < -_INTRUDE  # (B, K, Za)
            left = free[:, None] & ~inside
            # per owner: a zone free before, none left free with the candidate there
            order = np.argsort(o, kind="stable")
            first = np.flatnonzero(np.r_[True, o[order][1:] != o[order][:-1]])
            was = np.logical_or.reduceat(free[:, order], first, axis=1)  # (B, U)
            still = np.logical_or.reduceat(left[:, :, order], first, axis=2)  # (B, K, U)
            misses += (was[:, None] & ~still).sum(-1)
        mine = np.flatnonzero(acc.owner == r)
        if len(mine):  # its own zones at the candidate
            zc, zo, zl, zh = zone_boxes(cand[:, :, None], rgt[:, :, None], fwd[:, :, None],
                                        half[r], acc.direction[mine], acc.depth[mine])
            misses += blocked(zc, zo, zl, zh, mine).all(-1)
        return misses

    def _side_partners(self, r: int, placed: Sequence[int]) -> list[int]:
        """Placed rows that a side-by-side binding (start place ``beside``) ties to ``r``,
        either way round, other than its parent (in the order of its bindings)."""
        others = self.side_others[r]
        if not others:
            return []
        done = set(placed)
        return [o for o in others if o in done]

    def place(self, r: int, placed: Sequence[Sequence[int]], pos: np.ndarray, yaw: np.ndarray,
              rngs: list[np.random.Generator], tries: int, spread: float) -> None:
        """Choose a pose for row ``r`` of each sample given its placed rows (``placed[b]``
        for sample ``b``); writes ``pos[:, r], yaw[:, r]`` (poses (B, N, 2) and (B, N), one
        generator per sample). A candidate that leaves an object with no access zone
        free (its own, or a placed object's it stands in) ranks as one that misses a rule,
        but calls for no second draw.

        Where no candidate of the first draw is clear and meets every rule it can
        be judged by, with room for its children, a second draw is made and the
        better of the two kept (two beds that should stand apart: few spots along
        the walls are far enough from the first). Each sample draws from its own
        generator and is judged against its own objects only.
        """
        if any(pl is not placed[0] for pl in placed):  # samples that draw a different
            # number of candidates (their side partners differ) are placed apart
            extra = [min(len(self._side_partners(r, pl)), 2) for pl in placed]
            if len(set(extra)) > 1:
                for e in sorted(set(extra)):
                    bs = [b for b, x in enumerate(extra) if x == e]
                    p, y = pos[bs], yaw[bs]
                    self.place(r, [placed[b] for b in bs], p, y, [rngs[b] for b in bs],
                               tries, spread)
                    pos[bs], yaw[bs] = p, y
                return
        rank, score, cand, cyaw, access = self._best(r, placed, pos, yaw, rngs, tries, spread)
        # a blocked access zone is no reason for a second draw (that cost 20-50 % more time
        # for a few per cent fewer blocked zones): it only chooses among the candidates
        again = np.flatnonzero(rank + 2.0 * access < _ALL_MET)
        if len(again):
            r2, s2, c2, y2, _ = self._best(r, [placed[b] for b in again], pos[again],
                                           yaw[again], [rngs[b] for b in again], tries, spread)
            blocked = np.maximum(rank[again], r2) <= -10.0  # neither clear: the more clearance
            take = (r2 > rank[again]) | (blocked & (s2 > score[again]))
            sel = again[take]
            rank[sel], score[sel], cand[sel], cyaw[sel] = r2[take], s2[take], c2[take], y2[take]
        ok = np.isfinite(score)
        pos[ok, r], yaw[ok, r] = cand[ok], cyaw[ok]
        # no candidate inside the floor: the centroid, and let the walls push
        pos[~ok, r] = self.room.centroid

    def _draw(self, r: int, placed: Sequence[Sequence[int]], pos: np.ndarray, yaw: np.ndarray,
              rngs: list[np.random.Generator], tries: int, spread: float
              ) -> tuple[np.ndarray, np.ndarray, int]:
        """Each sample's draw of candidate poses for row ``r`` (sample ``b`` from
        ``rngs[b]``, around its own objects): positions (B, K, 2), headings (B, K) and how
        many of the first were drawn with no wall kept free beside them."""
        room, half, w = self.room, self.half, self.wants[r]
        places = w.places
        nb = len(rngs)
        draws = _Draws(rngs)
        q = int(self.parent[r])
        sides = self.sides[r]  # wall to keep free on the left and the right, metres
        opening = _opening_centres(room, w)
        corner = "corner" in places
        # an object taller than the sill of a window it should stand near draws twice as
        # many spots near it, and keeps those clear of the windows' zones first: near a
        # wide window most spots are in front of it
        tall_by_window = (opening is not None and "window" in places and not corner and q < 0
                          and self.window is not None and bool(self.window.tall[:, r].any()))
        k0 = 2 * tries if tall_by_window else tries
        # square with the room, as settled
        cyaw = draws.integers(4, k0) * (0.5 * np.pi)
        corner = _corner_candidates(room, draws, tries, half[r]) if corner else None
        loose = 0  # the first candidates, drawn with no wall kept free beside them
        if corner is not None:
            cand, cyaw = corner
        elif q >= 0:
            cand, cyaw = _child_candidates(room, draws, tries, w, np.full(nb, q), r, pos, yaw,
                                           half, self.radius, spread)
        elif "wall" in places:
            near = None if opening is None else _near_opening(draws, k0, opening, w.reach)
            cand, cyaw = _wall_candidates(room, draws, k0 if near is not None else tries,
                                          half[r], near, sides)
            if self.either[r] and near is None:
                # half the draws anywhere along a wall: the children that may stand on
                # either side may also stand at another wall beside it (a bed near a corner)
                loose = tries // 2
                cand[:, :loose], cyaw[:, :loose] = _wall_candidates(room, draws, loose,
                                                                    half[r], None)
        elif opening is not None:
            cand = _near_opening(draws, k0, opening, w.reach)
        elif "middle" in places:
            if w.reach > 0:  # evenly over the share of the room's extent its rules allow
                ext = w.reach * (room.bounds[2:] - room.bounds[:2])
                cand = room.centroid + draws.uniform(-ext, ext, (tries, 2))
            else:
                cand = room.centroid + draws.normal(0.3, (tries, 2))
        else:
            cand = draws.uniform(self.lo, self.hi, (tries, 2))
        # beside the placed objects it should stand beside other than its parent
        # (the second bed beside the nightstand that already stands by the first); as
        # many for every sample (``place`` sees to it), which ones its own
        partners = [self._side_partners(r, pl)[:2] for pl in placed]
        for k in range(len(partners[0])):
            wp = _Wants(places={"beside"} | (places & {"wall"}), turns=w.turns)
            more, more_yaw = _child_candidates(room, draws, tries // 2, wp,
                                               np.array([p[k] for p in partners]), r, pos,
                                               yaw, half, self.radius, spread)
            cand = np.concatenate([cand, more], axis=1)
            cyaw = np.concatenate([cyaw, more_yaw], axis=1)
        # where the wall object its first such rule turns it to will hang, for a placed
        # object facing it too
        spot = self._shared_spots(r, w.sights[0], placed, pos, yaw) if w.sights else None
        if spot is not None and not corner:
            more, more_yaw = self._toward_spot(r, draws, tries // 2, spot)
            cand = np.concatenate([cand, more], axis=1)
            cyaw = np.concatenate([cyaw, more_yaw], axis=1)
        if self.wants[r].pinned and q < 0 and not corner:
            # within reach of the wall a wall object tied to it by a close rule hangs on
            more, more_yaw = self._near_pinned(r, draws, tries // 2)
            cand = np.concatenate([cand, more], axis=1)
            cyaw = np.concatenate([cyaw, more_yaw], axis=1)
        if self.front_to_wall[r] and q < 0 and not corner:
            # its front to a wall, as far off it as the child in front of it needs, the
            # child's back at the wall (a reception desk with its chair against the wall)
            more, more_yaw = self._facing_a_wall(r, draws, tries // 2, opening, w.reach)
            cand = np.concatenate([cand, more], axis=1)
            cyaw = np.concatenate([cyaw, more_yaw], axis=1)
        # fall-backs after the proposals: anywhere at a wall for objects that
        # belong at one, anywhere in the room for the rest
        extra = tries // 2
        if "wall" in places:
            more, more_yaw = _wall_candidates(room, draws, extra, half[r], None)
        else:
            more = draws.uniform(self.lo, self.hi, (extra, 2))
            more_yaw = draws.uniform(-np.pi, np.pi, extra)
        cand = np.concatenate([cand, more], axis=1)
        cyaw = np.concatenate([cyaw, more_yaw], axis=1)
        toward = _opening_turn(room, w.turns, places)
        if toward is not None:  # front towards the nearest window (or door)
            cyaw = geo.yaw_facing(geo.toward_nearest(cand, toward))
        elif w.views and not places & {"wall", "corner"} \
                and not w.turns & {"face_target", "target_heading"}:
            cyaw = self._toward_views(r, placed, pos, yaw, cand, cyaw, spot)
        if tall_by_window:
            cand, cyaw = self._clear_of_windows(r, cand, cyaw, k0, tries)
        return cand, cyaw, loose

    def _facing_a_wall(self, r: int, draws: _Draws, k: int, opening: np.ndarray | None,
                       reach: float) -> tuple[np.ndarray, np.ndarray]:
        """``k`` candidate poses (B, k) of row ``r`` turned to face a wall (near an opening
        where its rules ask for one), its front as far off the wall as its children in front
        of it need (``front_margin``)."""
        half, margin = self.half[r], self.front_margin[r]
        near = None if opening is None else _near_opening(draws, k, opening, reach)
        deep = np.array([half[0], half[1] + 0.5 * margin])  # the object and its front room
        cand, cyaw = _wall_candidates(self.room, draws, k, deep, near)
        back = geo.front_vectors(cyaw)  # out of the wall: the object's back, once turned
        return cand + back * (0.5 * margin), cyaw + np.pi

    def _toward_views(self, r: int, placed: Sequence[Sequence[int]], pos: np.ndarray,
                      yaw: np.ndarray, cand: np.ndarray, cyaw: np.ndarray,
                      spot: np.ndarray | None) -> np.ndarray:
        """Headings (B, K) of row ``r``'s candidates (B, K, 2) turned towards ``spot``
        (B, 2), where a wall object it is turned to by a rule will hang for a placed object
        facing it too (the first such one in its sample; :meth:`_shared_spots`), else
        where that object looks: a beanbag turned to the wall at the foot of the bed,
        where the TV goes. A sample with none such placed keeps its headings."""
        w = self.wants[r]
        out = cyaw.copy()
        if spot is None:
            spot = np.full((len(placed), 2), np.nan)
        for b, rows in enumerate(placed):
            aim: np.ndarray | None = spot[b]
            if not np.isfinite(spot[b, 0]):
                other = next((c for c in rows if c != r and self.wants[c].views & w.views),
                             None)
                aim = None if other is None else _ray_to_walls(self.room, pos[b, other],
                                                                yaw[b, other])
            if aim is not None:
                out[b] = geo.yaw_facing(aim - cand[b])
        return out

    def _toward_spot(self, r: int, draws: _Draws, k: int, spot: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray]:
        """``k`` candidate poses (B, k) of row ``r`` from where the wall object of its first
        such rule can be seen, at ``spot`` (B, 2) where a placed object faces it too
        (:meth:`_shared_spots`; NaN where none does): at a wall that looks towards that
        spot for an object that stands at a wall (the second bed, backed against the wall
        across from the TV), else in front of the spot within the rule's angle, 1-3 m off,
        turned to it. A sample with no such spot draws
        at any wall, or anywhere, instead (every sample draws as many numbers)."""
        room, half = self.room, self.half[r]
        sight = self.wants[r].sights[0]
        found = np.isfinite(spot[:, 0])
        at = np.where(found[:, None], spot, room.centroid)
        if "wall" in self.wants[r].places:
            mid = 0.5 * (room.a + room.b)  # (W, 2)
            to = at[:, None] - mid[None]  # (B, W, 2)
            look = (to * room.normal[None]).sum(2) \
                >= np.cos(np.radians(45.0)) * np.hypot(to[..., 0], to[..., 1])
            ok = look & found[:, None] & (room.length >= 2 * half[0] + 0.02)[None]
            weight = np.where(ok.any(axis=1)[:, None], ok * room.length, room.length)
            return _wall_candidates(room, draws, k, half, None, weight=weight)
        # in front of the spot: off the normal of its wall by up to 0.7 of the rule's angle
        d = room.a[None] - at[:, None]  # (B, W, 2): the wall the spot lies on
        along = np.clip((-d * room.tangent[None]).sum(2), 0.0, room.length[None])
        off = room.a[None] + room.tangent[None] * along[..., None] - at[:, None]
        wall = np.argmin(np.hypot(off[..., 0], off[..., 1]), axis=1)
        n = room.normal[wall][:, None]  # (B, 1, 2)
        turn = draws.uniform(-1.0, 1.0, k) * 0.7 * np.radians(min(sight.angle, 60.0))
        dist = draws.uniform(1.0, 3.0, k) + half[1]
        c, s_ = np.cos(turn), np.sin(turn)
        ray = np.stack([c * n[..., 0] - s_ * n[..., 1], s_ * n[..., 0] + c * n[..., 1]], axis=2)
        cand = at[:, None] + ray * dist[..., None]
        anywhere = draws.uniform(self.lo, self.hi, (k, 2))
        cand = np.where(found[:, None, None], cand, anywhere)
        cyaw = geo.yaw_facing((at[:, None] - cand).reshape(-1, 2)).reshape(cand.shape[:2])
        return cand, cyaw

    def _first_viewers(self, r: int, target: str, placed: Sequence[Sequence[int]]
                       ) -> list[tuple[int, _Sight] | None]:
        """For each sample, the first object it placed, other than ``r``, turned by a rule
        towards the wall object ``target``, with that rule's sight (None: none placed)."""
        out: list[tuple[int, _Sight] | None] = []
        for rows in placed:
            out.append(next(((c, sg) for c in rows if c != r
                             for sg in self.wants[c].sights if sg.target == target), None))
        return out

    def _shared_spots(self, r: int, sight: _Sight, placed: Sequence[Sequence[int]],
                      pos: np.ndarray, yaw: np.ndarray) -> np.ndarray:
        """Where the wall object of ``sight`` will hang in each sample (poses (B, N, 2),
        (B, N)) for the first placed object facing it other than ``r``
        (:func:`_sight_spot`, with the placed floor objects standing), (B, 2); NaN
        where no such object is placed or it leaves no spot."""
        out = np.full((len(placed), 2), np.nan)
        firsts = self._first_viewers(r, sight.target, placed)
        for q in {f[0] for f in firsts if f is not None}:
            bs = np.array([b for b, f in enumerate(firsts) if f is not None and f[0] == q])
            own = next(f[1] for f in firsts if f is not None and f[0] == q)
            solid = [c for c in range(self.model.n) if not self.walkable[c] and c != q]
            counts = np.array([[c in placed[b] for c in solid] for b in bs],
                              dtype=bool).reshape(len(bs), len(solid))
            rows = np.array(solid, dtype=int)
            out[bs] = _sight_spot(self.room, own, pos[bs, q], geo.front_vectors(yaw[bs, q]),
                                  self._footprints(rows, pos[bs], yaw[bs]),
                                  self.wall_top[rows], counts)
        return out

    def _footprints(self, rows: np.ndarray, pos: np.ndarray, yaw: np.ndarray) -> np.ndarray:
        """Footprint corners (B, M, 4, 2) of ``rows`` (M,) at poses (B, N, 2), (B, N)."""
        b, m = len(pos), len(rows)
        c = geo.corners_from_axes(pos[:, rows].reshape(-1, 2),
                                  geo.right_vectors(yaw[:, rows]).reshape(-1, 2),
                                  geo.front_vectors(yaw[:, rows]).reshape(-1, 2),
                                  np.tile(self.half[rows], (b, 1)))
        return c.reshape(b, m, 4, 2)

    def _clear_of_windows(self, r: int, cand: np.ndarray, cyaw: np.ndarray, k0: int,
                          tries: int) -> tuple[np.ndarray, np.ndarray]:
        """The first ``k0`` candidates (B, K) of row ``r`` cut to ``tries``: those clear of
        the zones of the windows it is too tall for first, each group in draw order; the
        candidates after the first ``k0`` as they are."""
        head, head_yaw = cand[:, :k0], cyaw[:, :k0]
        inside = self._in_window_zone(r, head, geo.right_vectors(head_yaw),
                                      geo.front_vectors(head_yaw))
        order = np.argsort(inside, axis=1, kind="stable")[:, :tries]
        cand = np.concatenate([np.take_along_axis(head, order[..., None], axis=1),
                               cand[:, k0:]], axis=1)
        cyaw = np.concatenate([np.take_along_axis(head_yaw, order, axis=1), cyaw[:, k0:]],
                              axis=1)
        return cand, cyaw

    def _best(self, r: int, placed: Sequence[Sequence[int]], pos: np.ndarray, yaw: np.ndarray,
              rngs: list[np.random.Generator], tries: int, spread: float
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """One draw of candidates for row ``r`` per sample, judged: the rank, clearance,
        position and heading of each sample's best one, and the access zones it leaves
        blocked (counted in its rank), shapes (B,), (B,), (B, 2), (B,), (B,)."""
        half, walkable = self.half, self.walkable
        w = self.wants[r]
        cand, cyaw, loose = self._draw(r, placed, pos, yaw, rngs, tries, spread)
        rgt, fwd = geo.right_vectors(cyaw), geo.front_vectors(cyaw)
        # walkable covers are no obstacle (furniture stands on them); the rows standing in
        # some sample's room, and which stand in each one's
        rows, sets = _rooms(placed)
        solid = [] if walkable[r] else [p for p in rows if not walkable[p]]
        present = None if sets is None else np.array(
            [[p in sb for p in solid] for sb in sets], dtype=bool).reshape(len(sets), len(solid))
        slack = np.array([0.045 if p in w.related else 0.0 for p in solid])

        inside0, clear0 = self._clearance(cand, rgt, fwd, half[r], solid, slack, pos, yaw,
                                          not walkable[r], present)
        score = np.where(inside0, clear0, -np.inf)
        # the rest is judged for the clear candidates only, each with its own sample's
        # objects (a candidate that is not clear ranks by its clearance alone): the
        # clear ones as C samples of one candidate each
        bk = cand.shape[:2]
        sb, sk = np.nonzero(score >= _CLEAR)
        unmet = np.zeros(bk)
        access = np.zeros(bk)
        if len(sb):
            penalty, miss = self._judge(r, sb, sk, loose, cand, cyaw, rgt, fwd, solid, slack,
                                        pos, yaw, present, placed)
            unmet[sb, sk] = penalty
            access[sb, sk] = miss
        # first clear candidate meeting the most of the rules it can be judged by, its
        # children's counted too; else the one with the most clearance
        rank = np.where(score >= _CLEAR, _ALL_MET - 2.0 * (unmet + access),
                        np.where(np.isfinite(score), -10.0, -99.0))
        k = np.where(rank.max(axis=1) > -10.0, np.argmax(rank, axis=1),
                     np.argmax(score, axis=1))
        b = np.arange(len(k))
        return rank[b, k], score[b, k], cand[b, k], cyaw[b, k], access[b, k]

    def _judge(self, r: int, sb: np.ndarray, sk: np.ndarray, loose: int, cand: np.ndarray,
               cyaw: np.ndarray, rgt: np.ndarray, fwd: np.ndarray, solid: list[int],
               slack: np.ndarray, pos: np.ndarray, yaw: np.ndarray,
               present: np.ndarray | None, placed: Sequence[Sequence[int]]
               ) -> tuple[np.ndarray, np.ndarray]:
        """The misses of the clear candidates ``(sb, sk)`` (sample, candidate) of row
        ``r``, shapes (C,): the rules they miss and the rooms their children lack (each a
        miss), and the objects they leave with no access zone free."""
        model, half, walkable, window = self.model, self.half, self.walkable, self.window
        w = self.wants[r]
        sides = self.sides[r]
        # judge footprints widened by the room their children need, as well as the
        # footprint alone
        cand, cyaw = cand[sb, sk][:, None], cyaw[sb, sk][:, None]  # (C, 1, 2), (C, 1)
        rgt, fwd = rgt[sb, sk][:, None], fwd[sb, sk][:, None]
        pos, yaw = pos[sb], yaw[sb]
        present = None if present is None else present[sb]
        n = len(sb)

        def roomy(centres: np.ndarray, ext: np.ndarray) -> np.ndarray:
            # whether footprints of half extent ext at the centres, turned as the
            # candidates are, lie inside the floor and clear of what stands there
            ins, cl = self._clearance(centres, rgt, fwd, ext, solid, slack, pos, yaw,
                                      not walkable[r], present)
            return (ins & (cl >= _CLEAR))[:, 0]

        # children that would find no room where their rules put them, per candidate:
        # each side child on a side without its stretch of wall, each front or all-round
        # child of a parent without its margin (every one costs its parent a rule)
        cramped = np.zeros(n)
        if sides.max() > 0:
            left, right = sides
            nl, nr = self.side_count[r]

            deep = self.side_depth[r]

            def side(metres: float, sign: float) -> np.ndarray:  # room on one side, as
                # deep as the children standing there with their backs level with its back
                if metres <= 0:
                    return np.ones(n, dtype=bool)
                return roomy(cand + rgt * (0.5 * sign * metres) - fwd * (half[r, 1] - 0.5 * deep),
                             np.array([half[r, 0] + 0.5 * metres, 0.5 * deep]))

            cramped = nl * ~side(left, -1.0) + nr * ~side(right, 1.0)
            if self.either[r] and (left, nl) != (right, nr):  # or the other way round
                cramped = np.minimum(cramped, nr * ~side(right, -1.0) + nl * ~side(left, 1.0))
            cramped[sk < loose] = 0.0  # drawn with no wall kept beside them
        fm = self.front_margin[r]
        if fm > 0:  # in front of it for its front children (the chair at the desk): at
            # either end of its front or in the middle
            hw = min(0.5 * self.front_width[r], half[r, 0])
            ext = np.array([hw, half[r, 1] + 0.5 * fm])
            free = np.zeros(n, dtype=bool)
            for sign in (0.0, -1.0, 1.0) if hw < half[r, 0] else (0.0,):
                free |= roomy(cand + fwd * (0.5 * fm) + rgt * (sign * (half[r, 0] - hw)), ext)
            cramped += self.n_front[r] * ~free
        def seats(margin: float) -> np.ndarray:  # how many of its children all round find
            # room ``margin`` deep along its sides, each side seating as many as it is long
            out = np.zeros(n)
            hx, hy = half[r]
            for axis, h, other in ((fwd, hy, hx), (rgt, hx, hy)):
                fits = max(1.0, np.floor((2.0 * other + 0.1) / self.seat[r]))
                ext = np.array([other, 0.5 * margin]) if axis is fwd \
                    else np.array([0.5 * margin, other])
                for sign in (-1.0, 1.0):
                    out += fits * roomy(cand + sign * axis * (h + 0.5 * margin), ext)
            return out

        am = self.around_margin[r]
        if am > 0:  # room for its children all round (the chairs at a table): on as many
            # sides as seat them all (a table for two may stand against a wall), each one
            # without a seat a miss
            cramped += np.maximum(self.n_around[r] - seats(am), 0.0)
        zm = self.zoned_margin[r]
        zoned = np.zeros(n, dtype=bool)
        if zm > 0:  # and sides with room for them all and their access zones beyond them
            # a blocked zone: chooses among the candidates, calls for no second draw (which
            # asked for room all round and made crowded studios half as slow)
            zoned = seats(zm) < self.n_around[r]
        # no room above it for the object that hangs there: that object goes missing and
        # the sample fails, so this ranks with a spot in a window zone (below)
        unmet = 4.0 * _unmet(self.room, w, cand.reshape(-1, 2), fwd.reshape(-1, 2),
                             rgt.reshape(-1, 2), half[r])
        if w.pinned:  # beyond reach of the wall a wall object it is tied to hangs on
            unmet += self._pinned_misses(r, cand[:, 0], fwd[:, 0])
        unmet += self._sight_misses(r, cand, rgt, fwd, solid, pos, yaw, present,
                                    [placed[b] for b in sb])
        if self.front_sights[r]:
            unmet += self._front_sight_misses(r, cand, rgt, fwd, solid, pos, yaw, present)
        unmet += _unmet_rules(model, self.by_object[r], r, cand, cyaw, pos, yaw,
                              [placed[b] for b in sb])[:, 0]
        access = self._access_misses(r, cand, rgt, fwd, solid, pos, yaw, present)[:, 0] + zoned
        if window is not None and window.tall[:, r].any():  # tall: not in front of a window
            # a failed check rejects a sample, an unmet rule may be within its tolerance:
            # a spot in a window zone ranks below one that misses any few rules
            unmet += 4.0 * self._in_window_zone(r, cand, rgt, fwd)[:, 0]
        return unmet + cramped, access

    def _sight_misses(self, r: int, cand: np.ndarray, rgt: np.ndarray, fwd: np.ndarray,
                      solid: list[int], pos: np.ndarray, yaw: np.ndarray,
                      present: np.ndarray | None, placed: Sequence[Sequence[int]]
                      ) -> np.ndarray:
        """The rules towards wall objects each candidate (C, 1, 2) of row ``r`` would make
        miss, each in its own sample's room (poses (C, N, 2), (C, N); the ``solid`` rows
        standing where ``present`` (C, S) says, ``placed[c]`` in placing order), shape (C,).

        Of placed objects turned towards a wall object: those it leaves with no spot for
        the wall object where they look (a wardrobe at the wall the bed faces, where the
        TV is to hang) or whose view of that spot it stands in, taller than the rule's
        ``view_height``. Of its own such rules: those with no spot for the wall object
        (where a placed object facing it too looks, else where it looks itself), the spot
        outside its angle or the view of it blocked by a placed object.
        """
        n = len(cand)
        out = np.zeros(n)
        w = self.wants[r]
        viewers = [p for p in self.viewers if p != r and p in solid]
        if not (viewers or w.sights):
            return out
        h, room = self.model.size[:, 2], self.room
        rows = np.array(solid, dtype=int)
        m = len(rows)
        seen = np.ones((n, m), dtype=bool) if present is None else present
        corners = self._footprints(rows, pos, yaw)  # (C, M, 4, 2)
        tops = self.wall_top[rows]  # what hangs above an object hides the wall too
        c, f, rg = cand[:, 0], fwd[:, 0], rgt[:, 0]
        viewing = [] if self.walkable[r] else viewers
        if viewing:  # the same with the candidate standing there too, for walls it hides
            corners_c, tops_c, seen_c = self._with_candidate(r, cand, rgt, fwd, corners, tops,
                                                             seen)
        for p in viewing:
            k = solid.index(p)
            counts = seen.copy()
            counts[:, k] = False  # not in its own way
            at, front = pos[:, p], geo.front_vectors(yaw[:, p])
            for sight in self.wants[p].sights:
                hides, in_view = self.wall_top[r] > sight.top, h[r] > sight.view_height
                if not (hides or in_view):
                    continue
                spot = _sight_spot(room, sight, at, front, corners, tops, counts)
                had = seen[:, k] & np.isfinite(spot[:, 0])
                if hides:
                    counts_c = seen_c.copy()
                    counts_c[:, k] = False
                    after = _sight_spot(room, sight, at, front, corners_c, tops_c, counts_c)
                    gone = np.isnan(after[:, 0])
                    moved = ~gone & (np.abs(after - spot).max(axis=1) > 0.05)
                    out += had * (gone + 0.5 * moved)
                if in_view:
                    out += had & _across(at, np.where(had[:, None], spot, at), c[:, None],
                                         rg[:, None], f[:, None], self.half[r][None])[:, 0]
        right, front_rows = geo.right_vectors(yaw[:, rows]), geo.front_vectors(yaw[:, rows])
        for sight in w.sights:
            spot = self._shared_spots(r, sight, placed, pos, yaw)
            own = np.isnan(spot[:, 0])  # none placed facing it (or no spot for it there)
            if own.any():
                spot[own] = _sight_spot(room, sight, c[own], f[own], corners[own], tops,
                                        seen[own])
            found = np.isfinite(spot[:, 0])
            d = np.where(found[:, None], spot - c, f)
            off = np.abs(np.arctan2(f[:, 0] * d[:, 1] - f[:, 1] * d[:, 0], (f * d).sum(1)))
            tall = seen & (h[rows][None] > sight.view_height)
            blocked = (_across(c, np.where(found[:, None], spot, c), pos[:, rows], right,
                               front_rows, self.half[rows]) & tall).any(axis=1)
            # its front no nearer the wall object than a viewer sits (an armchair with its
            # knees at the TV's wall; a treadmill's console under the TV, in the view of
            # the others facing it)
            close = np.hypot(d[:, 0], d[:, 1]) < self.half[r, 1] + _VIEWING
            out += ~found | (off > np.radians(sight.angle)) | blocked | (found & close)
        return out

    def _with_candidate(self, r: int, cand: np.ndarray, rgt: np.ndarray, fwd: np.ndarray,
                        corners: np.ndarray, tops: np.ndarray, seen: np.ndarray
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The footprints (C, M, 4, 2), wall tops (M,) and presence (C, M) of placed rows
        with row ``r`` standing at each candidate (C, 1, 2) too (turned by its right and
        front vectors, (C, 1, 2)): shapes (C, M + 1, 4, 2), (M + 1,), (C, M + 1)."""
        n = len(cand)
        mine = geo.corners_from_axes(cand[:, 0], rgt[:, 0], fwd[:, 0],
                                     np.tile(self.half[r], (n, 1)))[:, None]
        return (np.concatenate([corners, mine], axis=1), np.append(tops, self.wall_top[r]),
                np.concatenate([seen, np.ones((n, 1), dtype=bool)], axis=1))

    def _front_sight_misses(self, r: int, cand: np.ndarray, rgt: np.ndarray, fwd: np.ndarray,
                            solid: list[int], pos: np.ndarray, yaw: np.ndarray,
                            present: np.ndarray | None) -> np.ndarray:
        """The rules towards wall objects that the children in front of row ``r``, turned
        to it, would miss for each candidate (C, 1, 2) of it, each in its own sample's room
        (poses (C, N, 2), (C, N); the ``solid`` rows standing where ``present`` (C, S)
        says), shape (C,): those left no spot for the wall object where they look, over
        the candidate (an office chair at a desk under the window, facing the whiteboard
        that cannot hang there)."""
        n = len(cand)
        rows = np.array(solid, dtype=int)
        seen = np.ones((n, len(rows)), dtype=bool) if present is None else present
        c, f = cand[:, 0], fwd[:, 0]
        corners, tops, counts = self._with_candidate(r, cand, rgt, fwd,
                                                     self._footprints(rows, pos, yaw),
                                                     self.wall_top[rows], seen)
        out = np.zeros(n)
        for k, sight in self.front_sights[r]:
            at = c + f * (self.half[r, 1] + _GAP[1] + self.half[k, 1])
            spot = _sight_spot(self.room, sight, at, -f, corners, tops, counts)
            out += np.isnan(spot[:, 0])
        return out

    def _pinned_misses(self, r: int, cand: np.ndarray, fwd: np.ndarray) -> np.ndarray:
        """How many of the walls row ``r`` should stand near (``_Wants.pinned``: where a
        wall object a close rule ties it to hangs) footprints at the candidates (C, 2),
        turned by their front vectors (C, 2), are out of reach of, shape (C,)."""
        out = np.zeros(len(cand))
        for wall, reach in self.wants[r].pinned:
            out += beyond_reach(self.room, wall, reach, cand, fwd, self.half[r])
        return out

    def _near_pinned(self, r: int, draws: _Draws, k: int) -> tuple[np.ndarray, np.ndarray]:
        """``k`` candidate poses (B, k) of row ``r`` within reach of the first wall it should
        stand near (``_Wants.pinned``): its back to that wall, up to four fifths of the
        reach off it, half of them turned about to face it."""
        room, half = self.room, self.half[r]
        wall, reach = self.wants[r].pinned[0]
        weight = np.zeros((1, room.n_walls))
        weight[0, wall] = 1.0
        cand, cyaw = _wall_candidates(room, draws, k, half, None, weight=weight)
        off = draws.uniform(0.0, 0.8 * max(reach, 0.0), k)
        cand = cand + room.normal[wall] * off[..., None]
        about = draws.random(k) < 0.5
        return cand, np.where(about, cyaw + np.pi, cyaw)

    def _in_window_zone(self, r: int, cand: np.ndarray, rgt: np.ndarray, fwd: np.ndarray
                        ) -> np.ndarray:
        """Whether footprints of row ``r`` at the candidates (B, K, 2), turned by their
        right and front vectors (B, K, 2), reach into the zone of a window it is too tall
        for (by more than 2 cm); shape (B, K)."""
        window = self.window
        z = window.tall[:, r]
        sep = geo.obb_separation(window.centre[z][None, None] - cand[:, :, None],
                                 rgt[:, :, None], fwd[:, :, None],
                                 self.half[r][None, None, None], window.lateral[z][None, None],
                                 window.out[z][None, None], window.half[z][None, None])
        return (sep < -0.02).any(axis=2)
