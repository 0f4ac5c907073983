"""Baselines to judge the method against, run in the same process on the same plans.

Random placement with rejection already reaches high validity and high
diversity, so a figure of the method means something only beside a baseline
measured the same way:

* :func:`random_layout` — the paper's *Random* baseline: uniform random
  poses, no rule guides them (one draw, not judged);
* :func:`rule_aware_layout` — one draw of a *rule-aware* random layout:
  random poses that lean towards the rules the way a person writing a
  sampler in an afternoon would (objects with a wall or corner start hint
  snapped against a random wall or into a random convex corner, children of
  ``next_to``/``in_front_of``-like rules dropped near their target), then the
  library's own surface stage for objects on tops, walls and the ceiling;
* :func:`rejection_sample` — rule-aware draws, kept only when they pass
  :func:`forcelayout.validate.check_layout` AND meet at least 95 % of their
  rules: the *rule-aware rejection sampler* of the benchmarks
  (``benchmarks/suite.py``), with a capped, seeded budget.

What a rule asks of the start is read from the rule registry (each rule
class's ``surface``, ``target`` and :class:`~forcelayout.rules.StartHint`),
never from rule names, so plugin rules get the same help as built-ins.

Units: metres, radians (CCW, yaw 0 = front faces +y), seconds.

Examples
--------
>>> import forcelayout as fl
>>> from forcelayout.baselines import rejection_sample
>>> plan = fl.examples.load_example("bedroom")
>>> result = rejection_sample(plan, 2, seed=0, max_tries=200)   # doctest: +SKIP
>>> result.tries, len(result), result.failures                   # doctest: +SKIP
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from forcelayout import geometry as geo
from forcelayout import rules as registry
from forcelayout._heap import older_objects_frozen
from forcelayout.geometry import RoomGeometry
from forcelayout.layout import Layout, Pose, SampleReport
from forcelayout.plan import Plan
from forcelayout.rules.base import StartHint
from forcelayout.views import Summary

if TYPE_CHECKING:
    from forcelayout.rules.base import Rule

__all__ = ["random_layout", "rule_aware_layout", "rejection_sample", "RejectionResult"]

#: Start places relative to the room (see StartHint.place); the others are relative to the
#: target: a side of it, all round it (``all_round``, as for no place), or (a place that names
#: no side, such as a rug's) centred on it.
_ROOM_PLACES = frozenset({"wall", "corner", "middle", "window", "door"})
_SIDE_PLACES = frozenset({"beside", "left", "right", "front", "back"})
_TARGET_PLACES = StartHint.PLACES - _ROOM_PLACES - {"all_round"}
#: Metres from an opening's centre a draw near it reaches where no rule says how far.
_OPENING_REACH = 1.4
#: Gap a wall-snapped footprint keeps from its wall, metres (the at_wall check allows 0.05).
_WALL_GAP = 0.005


def _rng(seed: int | np.random.Generator) -> np.random.Generator:
    return seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)


def _rule_class(name: str) -> type[Rule]:
    return type(registry.get_rule(name))


def _off_floor(plan: Plan) -> dict[str, tuple[type[Rule], str | None]]:
    """Objects an off-floor rule places: id -> (its first such rule class, its target)."""
    out: dict[str, tuple[type[Rule], str | None]] = {}
    for spec in plan.rules:
        cls = _rule_class(spec.rule)
        if cls.surface != "floor":
            out.setdefault(spec.object, (cls, spec.target))
    return out


def _door_boxes(room: RoomGeometry) -> np.ndarray:
    """Each door's swing square as box corners, shape (D, 4, 2)."""
    return geo.corners_from_axes(*room.door_squares)


# -- the Random baseline ------------------------------------------------------------------


def random_layout(
    plan: Plan,
    seed: int | np.random.Generator = 0,
    *,
    max_tries: int = 200,
    reject: bool = True,
) -> Layout:
    """Random poses for every object of a plan: the paper's Random baseline.

    Floor objects, in plan order, get a uniform random centre and a random
    cardinal yaw (0, π/2, π, 3π/2); a draw is rejected while its footprint
    leaves the room or (with ``reject``) overlaps an object placed before it
    or a door's swing square, at most ``max_tries`` draws per object (the
    last draw is kept otherwise). No rule guides the placement: judge the
    result with :func:`forcelayout.validate.check_layout` and
    :attr:`Layout.rule_satisfaction` like any other sample. Objects that a
    rule places on another object's top (``surface = "top"``) land at a
    random point of the parent's top; wall objects on a random wall at a
    random height; ceiling objects at a random point under the ceiling.

    Parameters
    ----------
    plan : Plan
    seed : int or numpy.random.Generator
    max_tries : int
        Draws per floor object before giving up.
    reject : bool
        Reject draws that collide with earlier objects or door squares
        (``False``: only keep footprints inside the room).

    Returns
    -------
    Layout
        Its report is a fresh :class:`SampleReport` (not yet judged).

    Examples
    --------
    >>> import forcelayout as fl
    >>> plan = fl.examples.load_example("bedroom")
    >>> random_layout(plan, 3) == random_layout(plan, 3)
    True
    """
    if max_tries < 1:
        raise ValueError(f"max_tries must be >= 1, got {max_tries}")
    rng = _rng(seed)
    room = RoomGeometry.from_room(plan.room)
    xmin, ymin, xmax, ymax = room.bounds
    poses: dict[str, Pose] = {}
    parent = _off_floor(plan)
    floor = [o for o in plan.objects if o.id not in parent]
    placed = _door_boxes(room)  # boxes already on the floor, door swing squares first
    if not reject:
        placed = placed[:0]
    for o in floor:
        half = np.array([o.size[0], o.size[1]]) / 2
        yaw = rng.integers(0, 4, size=max_tries) * (math.pi / 2)
        draws = rng.random((max_tries, 2)) * [xmax - xmin, ymax - ymin] + [xmin, ymin]
        corners = geo.box_corners(draws, yaw, np.repeat(half[None], max_tries, axis=0))
        ok = room.contains(corners).all(axis=1)
        if reject and len(placed):
            sep = geo.box_separation(corners[:, None], placed[None])  # (T, M)
            ok &= (sep > 0).all(axis=1)
        k = int(np.argmax(ok)) if ok.any() else max_tries - 1
        poses[o.id] = Pose(float(draws[k, 0]), float(draws[k, 1]), float(yaw[k]))
        placed = np.concatenate([placed, corners[k: k + 1]]) if reject else placed
    rest = [o for o in plan.objects if o.id in parent]
    for _ in range(len(rest) + 1):  # parents before children; bounded by the count
        pending = [o for o in rest if o.id not in poses]
        if not pending:
            break
        for o in pending:
            cls, target = parent[o.id]
            if cls.surface == "top":
                if target not in poses:
                    continue
                tp = poses[target]
                tsize = plan.object(target).size
                u = (rng.random(2) - 0.5) * np.maximum(np.array(tsize[:2]) - o.size[:2], 0.0)
                c, s = math.cos(tp.yaw), math.sin(tp.yaw)
                x = tp.x + c * u[0] - s * u[1]
                y = tp.y + s * u[0] + c * u[1]
                yaw = tp.yaw + float(rng.integers(0, 4)) * math.pi / 2
                poses[o.id] = Pose(x, y, yaw, tp.z + tsize[2], target)
            elif cls.surface == "ceiling":
                draws = rng.random((max_tries, 2)) * [xmax - xmin, ymax - ymin] + [xmin, ymin]
                half = np.repeat(np.array(o.size[:2])[None] / 2, max_tries, axis=0)
                ok = room.contains(geo.box_corners(draws, np.zeros(max_tries), half)).all(1)
                k = int(np.argmax(ok)) if ok.any() else max_tries - 1
                poses[o.id] = Pose(float(draws[k, 0]), float(draws[k, 1]), 0.0,
                                   plan.room.height - o.size[2], "ceiling")
            else:  # on a wall, back to it
                w = int(rng.integers(0, room.n_walls))
                t = float(rng.uniform(min(o.size[0] / 2, room.length[w] / 2),
                                      max(room.length[w] - o.size[0] / 2, room.length[w] / 2)))
                xy = room.a[w] + room.tangent[w] * t + room.normal[w] * o.size[1] / 2
                n = room.normal[w]
                yaw = math.atan2(-n[0], n[1])  # front along the inward normal
                z = float(rng.uniform(0.0, max(plan.room.height - o.size[2], 0.0)))
                poses[o.id] = Pose(float(xy[0]), float(xy[1]), yaw, z, f"wall:{w}")
    return Layout(plan, poses, seed if isinstance(seed, int) else 0)


# -- rule-aware draws ---------------------------------------------------------------------


@dataclass(frozen=True)
class _Hint:
    """What the rules of one floor object ask of its start (read from the registry)."""

    places: frozenset[str] = frozenset()  # room places: wall, corner, middle, window, door
    parent: str | None = None  # the target it starts near
    near: str | None = None  # which side of the parent: beside, left, ..., all_round, None
    turns: tuple[tuple[str | None, str | None], ...] = ()  # (turn, target id)
    # how far from its room place its rules let it be: metres from an opening, a share of
    # the room's extent from the middle (StartHint.reach); 0 where no rule says
    reach: float = 0.0
    # the one window or door a rule picks by its index (StartHint.which): (kind, index)
    picks: tuple[tuple[str, int], ...] = ()


@dataclass(frozen=True)
class _Compiled:
    """A plan read once for rule-aware draws."""

    plan: Plan
    room: RoomGeometry
    order: tuple[str, ...]  # floor objects, parents before their children
    half: dict[str, np.ndarray]
    hints: dict[str, _Hint]
    walkable: frozenset[str]
    doors: np.ndarray  # door swing squares as corners (D, 4, 2)
    corners: tuple[np.ndarray, np.ndarray, np.ndarray]  # convex vertex, wall before, wall after


def _reaches(parent: dict[str, str], start: str, goal: str) -> bool:
    """Whether following parents from ``start`` reaches ``goal`` (a bounded walk)."""
    cur: str | None = start
    for _ in range(len(parent) + 2):
        if cur == goal:
            return True
        if cur is None:
            return False
        cur = parent.get(cur)
    return False


def _compile(plan: Plan) -> _Compiled:
    room = RoomGeometry.from_room(plan.room)
    off = _off_floor(plan)
    floor = [o.id for o in plan.objects if o.id not in off]
    fset = set(floor)
    rules: dict[str, list[tuple[type[Rule], str | None]]] = {i: [] for i in floor}
    reach: dict[str, float] = {}
    picks: dict[str, dict[str, int]] = {}
    for spec in plan.rules:
        cls = _rule_class(spec.rule)
        if cls.surface == "floor" and spec.object in fset:
            rules[spec.object].append((cls, spec.target))
            hint = cls.start
            if hint is not None and (hint.reach or hint.which) is not None:
                params = cls.Params(**(spec.params or {}))
                if hint.reach is not None and hint.place in ("window", "door", "middle"):
                    bound = float(getattr(params, hint.reach))
                    reach[spec.object] = max(reach.get(spec.object, 0.0), bound)
                if hint.which is not None and int(getattr(params, hint.which)) >= 0:
                    picks.setdefault(spec.object, {})[hint.place] = int(
                        getattr(params, hint.which))
    parent: dict[str, str] = {}
    near: dict[str, str | None] = {}
    for oid in floor:  # the strongest bond (lowest StartHint.parent) that makes no cycle
        bonds = sorted(((cls.start.parent, k, cls, t) for k, (cls, t) in enumerate(rules[oid])
                        if cls.start is not None and cls.start.parent is not None
                        and t in fset and t != oid), key=lambda b: (b[0], b[1]))
        for _, _, cls, t in bonds:
            if not _reaches(parent, t, oid):
                parent[oid] = t
                place = cls.start.place if cls.start is not None else None
                near[oid] = place if place in _TARGET_PLACES or place == "all_round" else None
                break
    hints = {}
    for oid in floor:
        places = frozenset(cls.start.place for cls, _ in rules[oid]
                           if cls.start is not None and cls.start.place in _ROOM_PLACES)
        turns = tuple((cls.start.turn, t) for cls, t in rules[oid]
                      if cls.start is not None and cls.start.turn and t in fset and t != oid)
        # turned towards an opening only where no rule turns it towards a target
        turns = turns or tuple((cls.start.turn, None) for cls, _ in rules[oid]
                               if cls.start is not None
                               and cls.start.turn in StartHint.OPENING_TURNS)
        hints[oid] = _Hint(places, parent.get(oid), near.get(oid), turns, reach.get(oid, 0.0),
                           tuple(sorted(picks.get(oid, {}).items())))
    area = {o.id: o.size[0] * o.size[1] for o in plan.objects}
    kids: dict[str | None, list[str]] = {}
    for oid in floor:
        kids.setdefault(parent.get(oid), []).append(oid)
    for v in kids.values():
        v.sort(key=lambda i: -area[i])  # stable: plan order among equals
    order: list[str] = []
    stack = list(reversed(kids.get(None, [])))
    while stack and len(order) < len(floor):  # largest roots first, each with its children
        oid = stack.pop()
        order.append(oid)
        stack.extend(reversed(kids.get(oid, [])))
    half = {oid: np.array(plan.object(oid).size[:2], dtype=float) / 2 for oid in floor}
    walkable = frozenset(oid for oid in floor if plan.object(oid).is_walkable)
    k, _, before, _ = room.convex_corners
    return _Compiled(plan, room, tuple(order), half, hints, walkable, _door_boxes(room),
                     (k, before, k))


def _cardinal(rng: np.random.Generator, k: int) -> np.ndarray:
    return rng.integers(0, 4, size=k) * (math.pi / 2)


def _extent(yaw: np.ndarray, half: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Half extent of footprints with headings ``yaw`` (K,) along unit directions ``u`` (K, 2)."""
    return (np.abs((u * geo.right_vectors(yaw)).sum(-1)) * half[..., 0]
            + np.abs((u * geo.front_vectors(yaw)).sum(-1)) * half[..., 1])


def _against_wall(room: RoomGeometry, wall: np.ndarray, along: np.ndarray, half: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Back flat against walls ``wall`` at ``along`` metres from their start, front inward."""
    lo = np.minimum(half[0], room.length[wall] * 0.5)
    along = np.clip(along, lo, room.length[wall] - lo)
    n = room.normal[wall]
    pos = room.a[wall] + room.tangent[wall] * along[:, None] + n * (half[1] + _WALL_GAP)
    return pos, geo.yaw_facing(n)


def _snap_nearest_wall(room: RoomGeometry, pos: np.ndarray, half: np.ndarray
                       ) -> tuple[np.ndarray, np.ndarray]:
    """Move points onto the nearest wall long enough for the object, back against it."""
    s = pos @ room.normal.T - room.normal_offset
    t = pos @ room.tangent.T - room.tangent_offset
    beyond = np.maximum(np.maximum(-t, t - room.length), 0.0)
    short = room.length < 2 * half[0] + 0.01
    wall = np.argmin(np.hypot(s, beyond) + short * 100.0, axis=1)
    return _against_wall(room, wall, t[np.arange(len(pos)), wall], half)


def _opening_centres(room: RoomGeometry, hint: _Hint) -> list[np.ndarray]:
    """The centres (K, 2) of the windows, then the doors, that an object's rules ask it
    to start near: every one of the kind, or the one a rule picks."""
    picks = dict(hint.picks)
    out = []
    for kind, o in (("window", room.windows), ("door", room.doors)):
        if kind in hint.places and len(o):
            out.append(o.centres(picks.get(kind, -1)))
    return out


def _near_opening(rng: np.random.Generator, k: int, openings: list[np.ndarray], reach: float
                  ) -> np.ndarray:
    """``k`` points evenly over the disc of radius ``reach`` (1.4 m where no rule says)
    round a random opening of a random kind among ``openings`` (centres of each kind)."""
    centres = openings[int(rng.integers(0, len(openings)))]
    ang = rng.uniform(-math.pi, math.pi, k)
    r = (reach if reach > 0 else _OPENING_REACH) * np.sqrt(rng.random(k))
    return centres[rng.integers(0, len(centres), k)] + r[:, None] * np.stack(
        [np.cos(ang), np.sin(ang)], axis=1)


def _random_wall(c: _Compiled, rng: np.random.Generator, k: int, half: np.ndarray,
                 hint: _Hint) -> tuple[np.ndarray, np.ndarray]:
    """``k`` poses against random walls (near a window/door if the rules ask: within their
    ``reach`` of it, against whichever wall is nearest)."""
    room, reach = c.room, hint.reach
    openings = _opening_centres(room, hint)
    if openings:  # within the rules' reach of an opening, against the nearest wall
        return _snap_nearest_wall(room, _near_opening(rng, k, openings, reach), half)
    need = 2 * half[0] + 0.02
    weight = np.where(room.length >= need, room.length, 0.0)
    if weight.sum() <= 0:
        weight = room.length.copy()
    wall = rng.choice(room.n_walls, size=k, p=weight / weight.sum())
    along = half[0] + rng.random(k) * np.maximum(room.length[wall] - 2 * half[0], 0.0)
    return _against_wall(room, wall, along, half)


def _random_corner(c: _Compiled, rng: np.random.Generator, k: int, half: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray] | None:
    """``k`` poses tucked into random convex corners, back against one of the two walls."""
    vert, before, after = c.corners
    if vert.size == 0:
        return None
    room = c.room
    pick = rng.integers(0, vert.size, k)
    back_first = rng.random(k) < 0.5
    wb = np.where(back_first, before[pick], after[pick])  # the wall behind the object
    ws = np.where(back_first, after[pick], before[pick])  # the wall at its side
    pos = (room.a[vert[pick]] + room.normal[wb] * (half[1] + _WALL_GAP)
           + room.normal[ws] * (half[0] + _WALL_GAP))
    return pos, geo.yaw_facing(room.normal[wb])


def _around_target(rng: np.random.Generator, k: int, tp: Pose, thalf: np.ndarray,
                   half: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``k`` poses at random sides of a placed target (chosen by their length), anywhere
    along them, a few centimetres out, square to the side (as ``around`` asks)."""
    fq = np.array([-math.sin(tp.yaw), math.cos(tp.yaw)])
    rq = np.array([math.cos(tp.yaw), math.sin(tp.yaw)])
    normals, axes, lengths, depths = geo.box_sides(rq, fq, thalf)
    s = rng.choice(4, size=k, p=lengths / lengths.sum())
    gap = rng.uniform(0.02, 0.25, k)
    along = rng.uniform(-1.0, 1.0, k) * np.maximum(lengths[s] - half[0], 0.0)
    pos = (np.array([tp.x, tp.y]) + normals[s] * (depths[s] + half[1] + gap)[:, None]
           + axes[s] * along[:, None])
    return pos, geo.yaw_facing(-normals[s])


def _near_target(rng: np.random.Generator, k: int, where: str | None, tp: Pose,
                 thalf: np.ndarray, half: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """``k`` centres near a placed target: on the side ``where`` asks, centred on it for a
    target place that names no side, all around it for none."""
    fq = np.array([-math.sin(tp.yaw), math.cos(tp.yaw)])
    rq = np.array([math.cos(tp.yaw), math.sin(tp.yaw)])
    if where in ("front", "back"):
        u = np.repeat((fq if where == "front" else -fq)[None], k, axis=0)
        gap, jitter = rng.uniform(0.05, 0.6, k), rng.normal(0.0, 0.15, k)
    elif where in ("beside", "left", "right"):
        if where == "beside":
            side = np.where(rng.random(k) < 0.5, -1.0, 1.0)
        else:
            side = np.full(k, -1.0 if where == "left" else 1.0)
        u = side[:, None] * rq[None]
        gap, jitter = rng.uniform(0.01, 0.12, k), rng.normal(0.0, 0.05, k)
        # backs level, as the start poses put them (side by side, the same heading)
        jitter = jitter - side * (thalf[1] - half[1])  # perp turns with the side
    elif where is not None:  # centred on the target (a cover under it)
        return np.array([tp.x, tp.y]) + rng.normal(0.0, 0.05, (k, 2))
    else:
        ang = rng.uniform(-math.pi, math.pi, k)
        u = np.stack([np.cos(ang), np.sin(ang)], axis=1)
        gap, jitter = rng.uniform(0.02, 0.8, k), np.zeros(k)
    perp = np.stack([-u[:, 1], u[:, 0]], axis=1)
    reach = (np.abs(u @ rq) * thalf[0] + np.abs(u @ fq) * thalf[1]
             + _extent(yaw, np.broadcast_to(half, (k, 2)), u) + gap)
    return np.array([tp.x, tp.y]) + u * reach[:, None] + perp * jitter[:, None]


def _propose(c: _Compiled, oid: str, rng: np.random.Generator, k: int,
             poses: dict[str, Pose]) -> tuple[np.ndarray, np.ndarray]:
    """``k`` candidate poses (centres (k, 2), yaws (k,)) for one floor object."""
    room, hint, half = c.room, c.hints[oid], c.half[oid]
    places = hint.places
    snapped = bool(places & {"wall", "corner"})
    yaw = _cardinal(rng, k)
    parent = hint.parent if hint.parent in poses else None
    out: tuple[np.ndarray, np.ndarray] | None = None
    square = parent is not None and hint.near == "all_round" and not snapped
    if square:  # at a side of its target, square to it
        out = _around_target(rng, k, poses[parent], c.half[parent], half)
    elif parent is not None and (hint.near is not None or not snapped):
        tp = poses[parent]
        where = None if hint.near == "all_round" else hint.near  # (at a wall: all round)
        if where is not None and where != "front":
            yaw = np.full(k, tp.yaw)  # side by side (or under it), facing the same way
        pos = _near_target(rng, k, where, tp, c.half[parent], half, yaw)
        out = _snap_nearest_wall(room, pos, half) if snapped else (pos, yaw)
    elif "corner" in places:
        out = _random_corner(c, rng, k, half)
    if out is None and snapped:  # a wall, or a room without convex corners
        out = _random_wall(c, rng, k, half, hint)
    if out is None:
        xmin, ymin, xmax, ymax = room.bounds
        ext = np.array([xmax - xmin, ymax - ymin])
        openings = _opening_centres(room, hint)
        if "middle" in places:
            share = hint.reach if hint.reach > 0 else 0.25
            pos = room.centroid + (rng.random((k, 2)) * 2 - 1) * share * ext
        elif openings:
            pos = _near_opening(rng, k, openings, hint.reach)
        else:
            pos = rng.random((k, 2)) * ext + [xmin, ymin]
        out = (pos, yaw)
    pos, yaw = out
    if not snapped and not square:  # turn as the rules ask (face a target, share its heading)
        for turn, target in hint.turns:
            kind = StartHint.OPENING_TURNS.get(turn)
            if kind is not None:  # towards the nearest window (door)
                centres = getattr(room, kind).centre
                if len(centres):
                    yaw = geo.yaw_facing(geo.toward_nearest(pos, centres))
                    break
            elif target in poses:
                tp = poses[target]
                yaw = (geo.yaw_facing(np.array([tp.x, tp.y]) - pos) if turn == "face_target"
                       else np.full(k, tp.yaw))
                break
    return pos, yaw


def _fits(c: _Compiled, corners: np.ndarray, obstacles: np.ndarray) -> np.ndarray:
    """Which candidate footprints (K, 4, 2) lie inside the floor and clear of obstacles."""
    room = c.room
    ok = room.contains(corners).all(axis=1)
    # a non-convex floor: no room vertex may lie inside the footprint either
    o = corners[:, 0]
    ex, ey = corners[:, 1] - o, corners[:, 3] - o
    v = room.polygon[None] - o[:, None]
    a = (v * ex[:, None]).sum(-1) / np.maximum((ex * ex).sum(-1), 1e-12)[:, None]
    b = (v * ey[:, None]).sum(-1) / np.maximum((ey * ey).sum(-1), 1e-12)[:, None]
    eps = 1e-6
    ok &= ~((a > eps) & (a < 1 - eps) & (b > eps) & (b < 1 - eps)).any(axis=1)
    if len(obstacles) and ok.any():
        sep = geo.box_separation(corners[:, None], obstacles[None])  # (K, M)
        ok &= (sep > 0).all(axis=1)
    return ok


def _draw_floor(c: _Compiled, rng: np.random.Generator, draws: int
                ) -> tuple[dict[str, Pose], list[str]]:
    """Rule-aware floor poses; ``missing`` names objects with no free spot in ``draws``."""
    poses: dict[str, Pose] = {}
    missing: list[str] = []
    obstacles = c.doors
    for oid in c.order:
        half = c.half[oid]
        pos, yaw = _propose(c, oid, rng, draws, poses)
        corners = geo.box_corners(pos, yaw, np.broadcast_to(half, (draws, 2)))
        walkable = oid in c.walkable
        ok = _fits(c, corners, obstacles[:0] if walkable else obstacles)
        if not ok.any():
            missing.append(f"{oid}: no free spot in {draws} rule-aware draws")
            continue
        k = int(np.argmax(ok))
        poses[oid] = Pose(float(pos[k, 0]), float(pos[k, 1]), float(geo.wrap_angle(yaw[k])))
        if not walkable:
            obstacles = np.concatenate([obstacles, corners[k: k + 1]])
    return poses, missing


def _place_rest(plan: Plan, floor: dict[str, Pose], rng: np.random.Generator
                ) -> tuple[dict[str, Pose], list[str]]:
    """The library's surface stage: objects on tops, walls and the ceiling."""
    from forcelayout.surfaces import place_surfaces

    surf = place_surfaces(plan, floor, rng)
    return surf.poses, list(surf.missing)


def rule_aware_layout(
    plan: Plan | str | dict[str, Any],
    seed: int | np.random.Generator = 0,
    *,
    draws: int = 64,
) -> Layout:
    """One rule-aware random layout of a plan (not judged): a draw of the rejection sampler.

    Floor objects are placed one by one, larger objects first and each
    object's children right after it, at the first of ``draws`` random
    candidate poses whose footprint lies inside the floor and overlaps no
    earlier object (walkable floor covers excepted) and no door's swing
    square. Candidates follow the rules' start hints from the registry
    (:class:`forcelayout.rules.StartHint`):

    * ``place="corner"`` — tucked into a random convex corner, back against
      one of its walls; ``place="wall"`` — back flat against a random wall
      (near a window or door if the rules also ask for one), front facing
      into the room;
    * a rule with ``start.parent`` set (``next_to``, ``in_front_of``, ...):
      dropped near its target at random, on the side the hint's ``place``
      names (``beside``, ``left``, ``right``: with the backs level, as a
      nightstand at the head of a bed; ``front``, ``back``), centred
      on it for a target place that names no side (a rug ``under`` a table),
      all around it otherwise; then against the nearest wall if a wall or
      corner hint asks;
    * ``place="middle"``, ``"window"``, ``"door"`` — a random point of the
      share of the room's extent round its centroid the rule allows
      (``StartHint.reach``: ``in_middle``'s ``fraction``; else a quarter), or
      within the rule's reach of a random window or door (``near_door``'s
      ``distance``; else 1.4 m), against the nearest wall where a wall hint
      asks too;
    * anything else — uniform in the floor polygon; headings are random
      cardinal angles unless snapped to a wall or turned by a hint's
      ``turn`` (``face_target``, ``target_heading``).

    Then :func:`forcelayout.surfaces.place_surfaces` places the objects on
    tops, walls and the ceiling, as the method does.

    Parameters
    ----------
    plan : Plan, path, JSON text, dict or bundled plan name
    seed : int or numpy.random.Generator
        Same plan and seed, same layout.
    draws : int
        Candidate poses per floor object.

    Returns
    -------
    Layout
        ``report.missing`` (and ``report.failures``) name objects without a
        free spot; the layout is not checked nor judged.
    """
    from forcelayout import load_plan

    if draws < 1:
        raise ValueError(f"draws must be >= 1, got {draws}")
    return _draw(_compile(load_plan(plan)), _rng(seed), draws,
                 seed if isinstance(seed, int) else 0)


def _draw(c: _Compiled, rng: np.random.Generator, draws: int, seed: int) -> Layout:
    floor, missing = _draw_floor(c, rng, draws)
    report = SampleReport(seed=seed)
    if missing:
        report.missing = missing
        report.failures = ["placement: " + "; ".join(missing)]
        report.valid = False
        return Layout(c.plan, floor, seed, report)
    poses, more = _place_rest(c.plan, floor, rng)
    if more:
        report.missing = more
        report.failures = ["missing: " + "; ".join(more)]
        report.valid = False
    return Layout(c.plan, poses, seed, report)


# -- rejection sampling -------------------------------------------------------------------


@dataclass
class RejectionResult:
    """The outcome of :func:`rejection_sample`.

    Iterating, ``len()`` and indexing go over the accepted layouts.

    Attributes
    ----------
    plan : Plan
    seed : int
        Seed of the run; try ``k`` used :func:`forcelayout.sampling.sample_seed`
        ``(seed, k)``, which is also the accepted layout's ``seed``.
    layouts : list of Layout
        Accepted layouts (pass the checks and meet enough rules), in try order.
    tries : int
        Draws made (at most ``max_tries``).
    seconds : float
        Wall time of the run.
    failures : dict of str to int
        How many tries each reason rejected: ``"placement"`` (an object
        found no free spot), ``"missing"`` (the surface stage left an object
        out), a check name of :data:`forcelayout.validate.CHECKS`
        (``"collision"``, ``"navigable"``, ...), or ``"rules"`` (too few
        rules met). A try may count under several checks.
    max_tries : int
        The budget.
    n : int
        Layouts wanted; the run stopped early once they were accepted.
    """

    plan: Plan
    seed: int
    layouts: list[Layout]
    tries: int
    seconds: float
    failures: dict[str, int] = field(default_factory=dict)
    max_tries: int = 0
    n: int = 0

    def __iter__(self) -> Iterator[Layout]:
        return iter(self.layouts)

    def __len__(self) -> int:
        return len(self.layouts)

    def __getitem__(self, k: int) -> Layout:
        return self.layouts[k]

    @property
    def accepted(self) -> int:
        """Number of accepted layouts."""
        return len(self.layouts)

    @property
    def yield_per_try(self) -> float:
        """Accepted layouts per try, in [0, 1] (NaN when no try was made)."""
        return self.accepted / self.tries if self.tries else float("nan")

    @property
    def layouts_per_second(self) -> float:
        """Accepted layouts per second of wall time (NaN for an instant run)."""
        return self.accepted / self.seconds if self.seconds > 0 else float("nan")

    def summary(self) -> Summary:
        """Counts, rates, timing and failure counts as plain data.

        A :class:`~forcelayout.views.Summary`: a ``dict`` that prints as a table.
        """
        return Summary({"plan": self.plan.name, "seed": self.seed, "n": self.n,
                "accepted": self.accepted, "tries": self.tries, "max_tries": self.max_tries,
                "yield_per_try": self.yield_per_try, "seconds": self.seconds,
                "layouts_per_second": self.layouts_per_second,
                "failures": dict(sorted(self.failures.items(), key=lambda kv: -kv[1]))})


def rejection_sample(
    plan: Plan | str | dict[str, Any],
    n: int,
    *,
    seed: int = 0,
    max_tries: int = 2000,
    min_rule_satisfaction: float = 0.95,
    draws: int = 64,
    check_kwargs: dict[str, Any] | None = None,
) -> RejectionResult:
    """Rule-aware rejection sampling: draw layouts until ``n`` are good or the budget ends.

    Each try is one :func:`rule_aware_layout` draw from its own seed; it is
    kept only if :func:`forcelayout.validate.check_layout` passes AND the
    layout meets at least ``min_rule_satisfaction`` of its rule bindings
    (:attr:`Layout.rule_satisfaction`). Floor-only checks and the floor
    rules are judged before the surface stage runs, so a try that already
    fails is given up early (the same verdict, sooner).

    Parameters
    ----------
    plan : Plan, path, JSON text, dict or bundled plan name
    n : int
        Layouts wanted (>= 0).
    seed : int
        Seed of the run: try ``k`` draws from
        ``numpy.random.default_rng(sample_seed(seed, k))``, so the result
        does not depend on anything but the plan and the arguments.
    max_tries : int
        Largest number of draws (>= 0).
    min_rule_satisfaction : float
        Fraction of rule bindings an accepted layout meets, in [0, 1].
    draws : int
        Candidate poses per floor object in each try.
    check_kwargs : dict, optional
        Thresholds for :func:`forcelayout.validate.check_layout`.

    Returns
    -------
    RejectionResult
        Accepted layouts (valid reports with their rule satisfaction),
        tries, seconds and failure counts.

    Examples
    --------
    >>> import forcelayout as fl
    >>> plan = fl.examples.load_example("bedroom")
    >>> r = rejection_sample(plan, 1, seed=0, max_tries=50)       # doctest: +SKIP
    >>> r.tries <= 50 and all(lay.check().ok for lay in r)       # doctest: +SKIP
    True
    """
    from forcelayout import load_plan
    from forcelayout.sampling import sample_seed
    from forcelayout.validate import check_layout

    if n < 0:
        raise ValueError(f"n must be >= 0, got {n}")
    if max_tries < 0:
        raise ValueError(f"max_tries must be >= 0, got {max_tries}")
    if draws < 1:
        raise ValueError(f"draws must be >= 1, got {draws}")
    if not 0.0 <= min_rule_satisfaction <= 1.0:
        raise ValueError(f"min_rule_satisfaction must lie in [0, 1], got {min_rule_satisfaction}")
    kw = dict(check_kwargs or {})
    plan = load_plan(plan)
    t0 = time.perf_counter()
    c = _compile(plan)
    n_rules = len(plan.rules)
    accepted: list[Layout] = []
    failures: dict[str, int] = {}
    tries = 0

    def fail(reasons: list[str]) -> None:
        for key in dict.fromkeys(f.split(":", 1)[0] for f in reasons):
            failures[key] = failures.get(key, 0) + 1

    with older_objects_frozen():  # as the library's own runs
        while len(accepted) < n and tries < max_tries:
            s = sample_seed(seed, tries)
            tries += 1
            t1 = time.perf_counter()
            rng = np.random.default_rng(s)
            floor, missing = _draw_floor(c, rng, draws)
            if missing:
                fail(["placement"])
                continue
            # the floor alone: its checks fail exactly as the full layout's would
            early = Layout(plan, floor, s)
            rep = check_layout(early, **kw)
            if not rep.ok:
                fail(rep.failures)
                continue
            unmet = sum(r.satisfied is False for r in early.rule_report())
            if n_rules and 1.0 - unmet / n_rules < min_rule_satisfaction \
                    or early.required_unmet:
                fail(["rules"])
                continue
            poses, more = _place_rest(plan, floor, rng)
            if more:
                fail(["missing"])
                continue
            lay = Layout(plan, poses, s)
            rep = check_layout(lay, **kw) if len(poses) > len(floor) else rep
            if not rep.ok:
                fail(rep.failures)
                continue
            sat = lay.rule_satisfaction
            if sat < min_rule_satisfaction or lay.required_unmet:
                fail(["rules"])
                continue
            lay.report.rule_satisfaction = sat
            lay.report.seconds = time.perf_counter() - t1
            accepted.append(lay)
    return RejectionResult(plan, int(seed), accepted, tries, time.perf_counter() - t0,
                           failures, int(max_tries), int(n))
