"""Objects on walls: each wall unfolded into a 2D plane and simulated.

A wall is a rectangle of wall length x room height (``u`` along the wall from
``polygon[i]``, ``v`` up from the floor). Doors, windows and the floor
objects standing within ``reach`` metres of the wall (projected as
``[u0, u1] x [0, top]`` zones) are static obstacles. Each wall object starts
at a free spot of its height band and settles under an annealed pull to eye
level; an object hung on a wall *above a target* (a wall rule with a target,
such as ``above``) starts over the target's centre and is pulled there too.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from forcelayout.batching import SampleTask, SimRequest
from forcelayout.bindings import Binding, CompiledPlan
from forcelayout.geometry import RoomGeometry, box_corners, front_vectors, rays_to_walls
from forcelayout.layout import Pose
from forcelayout.options import SolverConfig
from forcelayout.plan import Plan
from forcelayout.rules.surface import middle_span
from forcelayout.surfaces.plane import (
    AnchorTerm,
    SurfacePlacement,
    plane_model,
    plane_solver,
    rect,
)

__all__ = ["EYE_LEVEL", "REACH", "MARGIN", "wall_pose", "wall_band", "binding_walls",
           "fits_band", "free_wall_stretches", "hanging_centres", "hidden_heights", "back_wall",
           "place_on_walls", "unhung", "Unhung", "unseen", "Unseen", "PinnedTie", "pinned_ties",
           "unreached", "beyond_reach"]

#: Eye level, metres: wall objects settle with their centre near this height.
EYE_LEVEL = 1.6
#: How far from a wall (metres) a floor object stands in the way of the wall objects above
#: it (the default ``reach`` of placing them), and the gap they keep to what blocks them.
REACH, MARGIN = 0.3, 0.02

Block = tuple[float, float, float, float]  # (u0, u1, v0, v1) metres


def wall_pose(room: RoomGeometry, wall: int, u: float, z: float, depth: float) -> Pose:
    """The pose of a wall object whose centre is ``u`` metres along wall ``wall``.

    Parameters
    ----------
    room : RoomGeometry
    wall : int
        Wall index ``i`` (``polygon[i]`` -> ``polygon[i+1]``).
    u : float
        Distance of the object's centre from ``polygon[i]`` along the wall, m.
    z : float
        Height of the object's bottom edge, m.
    depth : float
        The object's depth off the wall, m (its footprint centre lies
        ``depth / 2`` into the room).

    Returns
    -------
    Pose
        Back against the wall, front facing into the room, ``surface="wall:<i>"``.
    """
    n = room.normal[wall]
    c = room.a[wall] + room.tangent[wall] * u + n * depth * 0.5
    return Pose(float(c[0]), float(c[1]), float(math.atan2(-n[0], n[1])), float(z),
                f"wall:{wall}")


def wall_band(binding: Binding, room_height: float, target_top: float | None = None,
              height: float = 0.0) -> tuple[float, float]:
    """Lowest bottom and highest top (metres) a wall binding allows.

    Read from the rule's ``low`` and ``high`` params where it has them
    (``low`` 0, ``high`` the ceiling otherwise); with ``target_top``, the
    height of the target's top, the bottom also clears it by the rule's
    ``clearance`` (:func:`target_clearance`) and, where the rule has a
    ``max_gap``, lies at most that far above it: the top then lies at most
    ``max_gap`` plus the object's ``height`` above the target's top.
    """
    high = getattr(binding.params, "high", None)
    high = room_height if high is None else min(float(high), room_height)
    low = float(getattr(binding.params, "low", 0.0))
    if target_top is not None:
        low = max(low, target_top + target_clearance(binding))
        gap = getattr(binding.params, "max_gap", None)
        if gap is not None:
            high = min(high, target_top + float(gap) + height)
    return low, high


def binding_walls(binding: Binding, n_walls: int) -> list[int]:
    """The walls a wall binding's object may hang on: the one its rule's ``wall`` param
    pins, else every wall of the room."""
    pinned = getattr(binding.params, "wall", None)
    return [int(pinned)] if pinned is not None else list(range(n_walls))


def target_clearance(binding: Binding) -> float:
    """Smallest gap (metres) above the target of a wall binding (its ``clearance`` param)."""
    return float(getattr(binding.params, "clearance", 0.0))


def target_middle(binding: Binding) -> float:
    """The share of its target's extent along the wall, about its middle, over which a wall
    binding's object hangs (the ``above`` rule's ``middle``; 1, anywhere over the target,
    where the rule has none)."""
    return float(getattr(binding.params, "middle", 1.0))


def target_stand(binding: Binding) -> tuple[float, float]:
    """How a wall binding's target stands by the wall the object hangs on: the largest gap
    (metres) between them and the largest angle (degrees) between the target's front and
    the wall's inward normal (the rule's ``wall_gap`` and ``max_angle`` params; any where
    the rule has none)."""
    return (float(getattr(binding.params, "wall_gap", math.inf)),
            float(getattr(binding.params, "max_angle", 180.0)))


def opening_blocks(plan: Plan, wall: int) -> list[Block]:
    """Doors and windows of a wall as ``(u0, u1, v0, v1)`` zones, metres."""
    out = []
    for d in plan.room.doors:
        if d.wall == wall:
            out.append((d.offset - d.width / 2, d.offset + d.width / 2, 0.0, d.height))
    for w in plan.room.windows:
        if w.wall == wall:
            out.append((w.offset - w.width / 2, w.offset + w.width / 2, w.sill, w.sill + w.height))
    return out


def _object_blocks(room: RoomGeometry, wall: int, corners: np.ndarray, tops: np.ndarray,
                   reach: float) -> list[Block]:
    """Objects within ``reach`` metres of a wall projected onto it as ``(u0, u1, 0, top)``."""
    if len(corners) == 0:
        return []
    n, t = room.normal[wall], room.tangent[wall]
    s = corners @ n - room.normal_offset[wall]  # (K, 4)
    u = corners @ t - room.tangent_offset[wall]
    near = s.min(axis=1) <= reach
    u0 = np.clip(u.min(axis=1), 0.0, room.length[wall])
    u1 = np.clip(u.max(axis=1), 0.0, room.length[wall])
    keep = near & (u1 - u0 > 1e-3)
    return [(float(a), float(b), 0.0, float(h))
            for a, b, h in zip(u0[keep], u1[keep], tops[keep], strict=True)]


def free_intervals(length: float, blocks: list[Block], v0: float, v1: float,
                   margin: float = MARGIN) -> list[tuple[float, float]]:
    """Intervals of ``[0, length]`` not blocked by any zone overlapping heights ``(v0, v1)``."""
    cuts = sorted((b[0] - margin, b[1] + margin) for b in blocks
                  if b[2] < v1 - 1e-9 and b[3] > v0 + 1e-9)
    out, start = [], 0.0
    for a, b in cuts:
        if a > start:
            out.append((start, min(a, length)))
        start = max(start, b)
        if start >= length:
            break
    if start < length:
        out.append((start, length))
    return [(a, b) for a, b in out if b - a > 1e-9]


def fits_band(low: float, high: float, height: float) -> bool:
    """Whether an object ``height`` tall fits between heights ``low`` and ``high`` (metres;
    one exactly as tall as the band does, whatever the rounding of ``high - low``)."""
    return high - low >= height - 1e-9


def free_wall_stretches(plan: Plan, wall: int, low: float, high: float, height: float,
                        margin: float = 0.0) -> list[tuple[float, float]]:
    """Stretches of a wall where an object ``height`` tall fits in the band, ignoring furniture.

    A door or window blocks its stretch, widened by ``margin`` metres each
    side, unless the object fits above or below it inside ``[low, high]``
    metres.

    Returns
    -------
    list of (u0, u1)
        Free stretches in metres from ``polygon[wall]``.
    """
    blocks = []
    for u0, u1, v0, v1 in opening_blocks(plan, wall):
        below = fits_band(low, min(high, v0), height)
        above = fits_band(max(low, v1), high, height)
        if not (below or above):
            blocks.append((u0, u1, -1.0, math.inf))
    return free_intervals(plan.room.wall_length(wall), blocks, 0.0, 1.0, margin=margin)


def hanging_centres(plan: Plan, binding: Binding, target_top: float | None) -> np.ndarray:
    """Where on the walls the object of ``binding`` can hang above a target ``target_top`` tall
    (``None``: in its band, with no target).

    The stretches along each wall (doors and windows cut out as
    :func:`place_on_walls` cuts them, furniture ignored) over which the
    object's centre can lie with the object in its band and clear of the
    target's top.

    Returns
    -------
    ndarray, shape (R, 3)
        ``(wall, u0, u1)`` rows: the centre may lie anywhere in ``[u0, u1]``
        metres from ``polygon[wall]``.
    """
    w, _, h = plan.object(binding.object).size
    low, high = wall_band(binding, plan.room.height, target_top, h)
    rows = [(wall, a + w / 2, b - w / 2)
            for wall in binding_walls(binding, len(plan.room.polygon))
            if fits_band(low, high, h)
            for a, b in free_wall_stretches(plan, wall, low, high, h, margin=MARGIN)
            if b - a >= w]
    return np.array(rows, dtype=float).reshape(-1, 3)


def corners_tops(cp: CompiledPlan, poses: dict[str, Pose], ids: list[str]
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Footprint corners (K, 4, 2) and top heights (K,) of placed objects."""
    if not ids:
        return np.zeros((0, 4, 2)), np.zeros(0)
    size = cp.size(ids)
    pos = np.array([[poses[i].x, poses[i].y] for i in ids])
    yaw = np.array([poses[i].yaw for i in ids])
    tops = np.array([poses[i].z for i in ids]) + size[:, 2]
    return box_corners(pos, yaw, size[:, :2] * 0.5), tops


def back_wall(room: RoomGeometry, corners: np.ndarray, front: np.ndarray, gap: float,
              turn: float = 180.0) -> tuple[np.ndarray, np.ndarray]:
    """The wall an object hangs on above each footprint: the wall behind it.

    Of the walls the footprint's front faces away from (within ``turn``
    degrees of the wall's inward normal), the nearest one within ``gap``
    metres of it (the ``above`` rule's ``wall_gap`` and ``max_angle``); where
    there is none, the nearest wall.

    Parameters
    ----------
    corners : ndarray, shape (..., 4, 2)
    front : ndarray, shape (..., 2)
        Unit front directions of the footprints.
    gap, turn : float

    Returns
    -------
    wall : ndarray of int, shape (...)
    behind : ndarray of bool, shape (...)
        Whether ``wall`` is behind the footprint within ``gap`` (the rule can be met).
    """
    d = room.wall_distance(corners)[0].min(axis=-2)  # (..., W)
    ok = (front @ room.normal.T >= np.cos(np.radians(turn)) - 1e-9) & (d <= gap + 1e-9)
    behind = ok.any(axis=-1)
    wall = np.where(behind, np.argmin(np.where(ok, d, np.inf), axis=-1), np.argmin(d, axis=-1))
    return wall, behind


def place_on_walls(cp: CompiledPlan, poses: dict[str, Pose], rng: np.random.Generator,
                   relations: bool, cfg: SolverConfig, reach: float,
                   out: SurfacePlacement, models: dict | None = None) -> SampleTask[None]:
    """Place every object that hangs on a wall, one spot after the other, then settle.

    A sample task (:mod:`forcelayout.batching`): each wall's settling is a
    :class:`~forcelayout.batching.SimRequest`, with the sample's own spots
    (anchors) and obstacles. Samples given the same ``models`` dict share the
    force model of a wall with the same objects on it, so their simulations
    run as one batch.
    """
    models = {} if models is None else models
    plan = cp.plan
    room = cp.room
    H = plan.room.height
    specs = cp.on("wall")
    if not specs:
        return
    ground = [i for i in poses if not poses[i].surface.startswith(("wall:", "ceiling"))]
    corners, tops = corners_tops(cp, poses, ground)
    blocks = {w: opening_blocks(plan, w) + _object_blocks(room, w, corners, tops, reach)
              for w in range(room.n_walls)}
    # initial spots, one object after the other (placed objects block the next)
    placed: dict[int, list[_Spot]] = {}
    for b in specs:
        oid = b.object
        w, d, h = cp.size([oid])[0]
        span: tuple[float, float] | None = None
        walls: list[int]
        if b.target is not None:
            if b.target not in poses:
                out.missing.append(f"{oid}: its target {b.target!r} was not placed")
                continue
            tc, tt = corners_tops(cp, poses, [b.target])
            front = front_vectors(poses[b.target].yaw)
            walls = [int(back_wall(room, tc[0], front, *target_stand(b))[0])]
            low, high = wall_band(b, H, float(tt[0]), h)
            _, high_any = wall_band(b, H)  # with no max_gap
        else:
            low, high = wall_band(b, H)
            pinned = getattr(b.params, "wall", None)
            walls = [int(pinned)] if pinned is not None else rng.permutation(room.n_walls).tolist()
        spot = None
        related = _floor_relations(cp, oid, poses) if relations and b.target is None else []
        # the spot that meets the most of its rules with floor objects, if any is free
        chosen = (_related_spot(cp, oid, poses, related, blocks, (w, d, h), (low, high),
                                walls, rng) if related else None)
        if chosen is not None:
            walls = [chosen[0]]
        for wall in walls:
            if b.target is not None:
                u = tc[0] @ room.tangent[wall] - room.tangent_offset[wall]
                lo, hi = middle_span(u.min(), u.max(), target_middle(b))
                span = (float(lo), float(hi))
            spot = (chosen[1] if chosen is not None else
                    _wall_spot(room.length[wall], blocks[wall], w, h, low, high, span, rng))
            if spot is None and span is not None:
                # no room over the target's middle, or none within its max_gap (a window
                # there): anywhere over the target, then higher, its rule unmet, rather
                # than not hung at all
                whole = (float(u.min()), float(u.max()))
                for span_, high_ in ((whole, high), (whole, high_any)):
                    if (span_, high_) != (span, high):
                        spot = _wall_spot(room.length[wall], blocks[wall], w, h, low, high_,
                                          span_, rng)
                        if spot is not None:
                            span, high = span_, high_
                            break
            if spot is not None:
                u, v = spot
                blocks[wall].append((u - w / 2, u + w / 2, v, v + h))
                goal_u = u if span is None else 0.5 * (span[0] + span[1])
                v_goal = float(np.clip(EYE_LEVEL, low + h / 2, high - h / 2))
                stiff = np.array([0.0 if span is None else 1.0, 0.5])
                placed.setdefault(wall, []).append(
                    _Spot(b, u, v, np.array([goal_u, v_goal, *stiff]), (low, high), span))
                break
        if spot is None:
            band = f"{low:.2f}..{high:.2f} m"
            where = (f"walls {walls} near {b.target!r}" if b.target is not None
                     else f"wall {walls[0]}" if len(walls) == 1 else "any wall")
            out.missing.append(f"{oid}: no free stretch {w:g} m wide on {where} in the band "
                               f"{band} (doors, windows and furniture block it)")
    for wall, items in placed.items():
        own = {(u - cp.size([b.object])[0, 0] / 2, u + cp.size([b.object])[0, 0] / 2, v,
                v + cp.size([b.object])[0, 2]) for b, u, v, *_ in items}
        static = [blk for blk in blocks[wall] if blk not in own]
        yield from _wall_plane(cp, wall, items, static, relations, cfg, poses, out, models)


class _Spot(NamedTuple):
    """A wall object's first spot: its binding, ``(u centre, v bottom)``, its anchor
    ``(u, v, stiffness u, stiffness v)``, its band of heights (bottom, top) and the
    extent along the wall of its target (None without one)."""

    binding: Binding
    u: float
    v: float
    goal: np.ndarray
    band: tuple[float, float]
    span: tuple[float, float] | None


#: Spots drawn for a wall object whose rules tie it to floor objects, the best kept.
_RELATED_SPOTS = 24
#: How far from a floor object that a close rule ties a wall object to (a towel rack near
#: the bathtub) its spots beside that object are drawn: walls within this many metres of
#: the object's footprint, this far past its ends along the wall.
_NEAR_REACH = 1.0


def _floor_relations(cp: CompiledPlan, oid: str, poses: dict[str, Pose]) -> list[int]:
    """The plan rules (indices) of floor rules between a wall object and a placed floor
    object, either way round (a towel rack ``near`` the bathtub; a bed ``facing`` the TV)."""
    return [b.index for b in cp.bindings
            if b.rule.surface == "floor" and b.index >= 0
            and ((b.object == oid and b.target in poses) or (b.target == oid and b.object in poses
                                                             and b.object != oid))]


def _related_spot(cp: CompiledPlan, oid: str, poses: dict[str, Pose], related: list[int],
                  blocks: dict[int, list[Block]], size: tuple[float, float, float],
                  band: tuple[float, float], walls: list[int], rng: np.random.Generator
                  ) -> tuple[int, tuple[float, float]] | None:
    """Where a wall object goes whose rules tie it to floor objects: of a few free spots
    on ``walls`` (first those where the floor objects turned towards it look,
    :func:`_look_spots`; then beside the floor objects a close rule ties it to,
    :func:`_near_spots`; then random walls, each spot on the next of them; on a wall,
    each free stretch as likely as the next, however short: the one short stretch a bed
    faces beside the wardrobe), the first meeting the most of the ``related`` rules,
    judged with the poses placed so far (the floor and the tops); ``(wall, (u, v))``, or
    None where no spot is free."""
    from forcelayout.layout import Layout
    from forcelayout.report import judge_rules_many

    room = cp.room
    w, d, h = size
    spots = _look_spots(cp, oid, poses, blocks, size, band, walls)
    spots += _near_spots(cp, oid, poses, related, blocks, size, band, walls, rng)
    for k in range(_RELATED_SPOTS):
        wall = walls[k % len(walls)]
        spot = _wall_spot(room.length[wall], blocks[wall], w, h, band[0], band[1], None, rng,
                          even=True)
        if spot is not None:
            spots.append((wall, spot))
    if not spots:
        return None
    layouts = [Layout(cp.plan, {**poses, oid: wall_pose(room, wall, u, v, d)})
               for wall, (u, v) in spots]
    unmet = [sum(results[k].satisfied is False for k in related)
             for results in judge_rules_many(layouts)]
    return spots[int(np.argmin(unmet))]


def _look_spots(cp: CompiledPlan, oid: str, poses: dict[str, Pose],
                blocks: dict[int, list[Block]], size: tuple[float, float, float],
                band: tuple[float, float], walls: list[int]
                ) -> list[tuple[int, tuple[float, float]]]:
    """The free spots nearest where each placed floor object that a rule turns towards
    wall object ``oid`` looks (the first wall its front meets; a beanbag, an exercise bike
    and an armchair facing one TV), at the first height of the band with room there."""
    room = cp.room
    w, _, h = size
    out = []
    for b in cp.bindings:
        if b.target != oid or b.object not in poses or b.rule.start is None \
                or b.rule.start.turn != "face_target":
            continue
        pose = poses[b.object]
        wall, u, _ = rays_to_walls(room, np.array([[pose.x, pose.y]]),
                                   front_vectors(np.array([pose.yaw])))
        wall = int(wall[0])
        if wall not in walls:
            continue
        for v in _heights(blocks[wall], h, band[0], band[1]):
            ranges = _centres(room.length[wall], blocks[wall], w, h, v, None)
            if ranges:
                at = min((float(np.clip(u[0], a, c)) for a, c in ranges),
                         key=lambda x: abs(x - float(u[0])))
                out.append((wall, (at, float(v))))
                break
    return out


def _near_spots(cp: CompiledPlan, oid: str, poses: dict[str, Pose], related: list[int],
                blocks: dict[int, list[Block]], size: tuple[float, float, float],
                band: tuple[float, float], walls: list[int], rng: np.random.Generator
                ) -> list[tuple[int, tuple[float, float]]]:
    """A free spot beside each placed floor object that a rule of ``related``
    (:func:`_floor_relations`) keeping the two close (``closeness="close"``: ``near``,
    ``next_to``) ties to wall object ``oid``, on each
    of ``walls`` within :data:`_NEAR_REACH` of its footprint: the free spot nearest its
    extent along the wall (anywhere along it where it is free there), at the first
    height of the band with room there. A towel rack near a bathtub in a corner has a
    stretch of wall or two beside the tub: a few random spots over the whole room seldom
    land there, and one at the far end of that stretch may settle out of reach."""
    room = cp.room
    w, _, h = size
    out = []
    rules = set(related)
    for b in cp.bindings:
        if b.index not in rules or b.rule.closeness != "close":
            continue
        other = b.target if b.object == oid else b.object
        if other not in poses:
            continue
        p = poses[other]
        corners = box_corners(np.array([[p.x, p.y]]), np.array([p.yaw]),
                              cp.size([other])[:, :2] * 0.5)[0]  # (4, 2)
        dist = room.wall_distance(corners)[0].min(axis=0)  # (W,)
        for wall in walls:
            if dist[wall] > _NEAR_REACH:
                continue
            u = corners @ room.tangent[wall] - room.tangent_offset[wall]
            t0, t1 = float(u.min()), float(u.max())
            for v in _heights(blocks[wall], h, band[0], band[1]):
                ranges = _centres(room.length[wall], blocks[wall], w, h, v,
                                  (t0 - _NEAR_REACH, t1 + _NEAR_REACH))
                if ranges:  # the nearest point of each free range, the nearest of them
                    near = [(max(a, t0), min(c, t1)) if a <= t1 and c >= t0 else
                            (c, c) if c < t0 else (a, a) for a, c in ranges]
                    lo, hi = min(near, key=lambda r: max(t0 - r[1], r[0] - t1, 0.0))
                    out.append((wall, (float(rng.uniform(lo, hi)), float(v))))
                    break
    return out


def _wall_spot(length: float, blocks: list[Block], w: float, h: float, low: float,
               high: float, span: tuple[float, float] | None, rng: np.random.Generator,
               *, even: bool = False) -> tuple[float, float] | None:
    """A free ``(u centre, v bottom)`` for a ``w x h`` object in the band, or None.

    Heights are tried at eye level first, then just above or below each
    obstacle, then the band's ends, then at random. The centre lies in one of
    the free stretches, the longer ones the likelier (``even``: each as
    likely). With a ``span`` (the target's extent along the wall) the
    object's centre stays inside it, as close to the span's middle as the
    free stretch allows.
    """
    if not fits_band(low, high, h):
        return None
    top = max(low, high - h)  # the highest bottom (the lowest, in a band as tall as it)
    heights = [*_heights(blocks, h, low, high), *rng.uniform(low, top, 4).tolist()]
    for v in heights:
        ranges = _centres(length, blocks, w, h, v, span)
        if not ranges:
            continue
        lens = np.array([b - a for a, b in ranges]) + 1e-6
        k = int(rng.choice(len(ranges), p=None if even else lens / lens.sum()))
        u = float(rng.uniform(*ranges[k]))
        if span is not None:  # centred over the target where the free stretch allows
            mid = 0.5 * (span[0] + span[1])
            u = min((float(np.clip(mid, a, b)) for a, b in ranges), key=lambda x: abs(x - mid))
        return u, float(v)
    return None


def _heights(blocks: list[Block], h: float, low: float, high: float) -> list[float]:
    """The bottoms :func:`_wall_spot` tries first for an object ``h`` tall in the band: eye
    level, just above or below each obstacle (nearest eye level first), the band's ends."""
    top = max(low, high - h)
    pref = float(np.clip(EYE_LEVEL - h / 2, low, top))
    edges = [b[3] for b in blocks] + [b[2] - h for b in blocks]
    edges = sorted({float(e) for e in edges if low <= e <= top},
                   key=lambda e: abs(e + h / 2 - EYE_LEVEL))
    return [pref, *edges[:16], low, top]


def _centres(length: float, blocks: list[Block], w: float, h: float, v: float,
             span: tuple[float, float] | None) -> list[tuple[float, float]]:
    """Where the centre of a ``w x h`` object with its bottom at ``v`` can lie on a wall
    (inside ``span`` where given), as ``(u0, u1)`` ranges."""
    ranges = [(a + w / 2, b - w / 2) for a, b in free_intervals(length, blocks, v, v + h)
              if b - a >= w]
    if span is not None:
        ranges = [(max(a, span[0]), min(b, span[1])) for a, b in ranges]
        ranges = [(a, b) for a, b in ranges if b >= a]
    return ranges


def unhung(cp: CompiledPlan, ids: list[str], pos: np.ndarray, yaw: np.ndarray,
           reach: float = REACH) -> list[list[tuple[str, str | None, list[str]]]]:
    """The wall objects that would find no free stretch of wall, for floor arrangements.

    Judged as :func:`place_on_walls` looks for a first spot, with the doors,
    windows and the floor objects within ``reach`` metres of a wall, and what
    stands on them (where on their tops is not known yet: each such object as
    wide as it is, over the middle of its parent, on the parent's top), each
    wall object on its own: one that hangs above a floor object (``above``)
    anywhere over it on the wall behind it, any other on its own wall or on any
    wall. Wall objects whose target is not on the floor are not judged.

    Parameters
    ----------
    cp : CompiledPlan
    ids : list of str
        The floor objects (rows of ``pos``).
    pos : ndarray, shape (B, N, 2)
    yaw : ndarray, shape (B, N)
        B floor arrangements.
    reach : float
        As for :func:`place_on_walls`.

    Returns
    -------
    list of list of Unhung
        Per arrangement, each wall object with no room.
    """
    specs = [b for b in cp.on("wall") if b.target is None or b.target in ids]
    out: list[list[Unhung]] = [[] for _ in range(len(pos))]
    if not specs:
        return out
    room, plan = cp.room, cp.plan
    size = cp.size(ids)
    tops = size[:, 2]
    row = {oid: k for k, oid in enumerate(ids)}
    openings = {w: opening_blocks(plan, w) for w in range(room.n_walls)}
    # what stands on each floor object: (row, width, top of it)
    loads = [(row[b.target], float(cp.size([b.object])[0, 0]),
              float(tops[row[b.target]] + cp.size([b.object])[0, 2]))
             for b in cp.on("top") if b.target in row]
    high_top = tops.copy()  # each floor object's top, or of what stands on it
    for r, _, top in loads:
        high_top[r] = max(high_top[r], top)
    sizes = cp.size([b.object for b in specs])  # of the wall objects, as specs
    for k in range(len(pos)):
        corners = box_corners(pos[k], yaw[k], size[:, :2] * 0.5)
        blocks: dict[int, list[Block]] = {}  # of the walls looked at
        for b, (w, _, h) in zip(specs, sizes, strict=True):
            if b.target is not None:
                t = row[b.target]
                low, high = wall_band(b, plan.room.height, float(tops[t]), h)
                front = front_vectors(np.array([yaw[k, t]]))
                wall = int(back_wall(room, corners[t:t + 1], front, *target_stand(b))[0][0])
                u = corners[t] @ room.tangent[wall] - room.tangent_offset[wall]
                spans: list[tuple[float, float] | None] = [(float(u.min()), float(u.max()))]
                walls = [wall]
            else:
                low, high = wall_band(b, plan.room.height)
                walls = binding_walls(b, room.n_walls)
                spans = [None]
            for wall in walls:
                if wall not in blocks:
                    blocks[wall] = (openings[wall]
                                    + _object_blocks(room, wall, corners, tops, reach)
                                    + _load_blocks(room, wall, corners, loads, reach))
            if not _fits(room, blocks, walls, spans, w, h, low, high):
                near = [] if b.target is not None else [
                    ids[r] for r in range(len(ids)) if high_top[r] > low
                    and any(_object_blocks(room, wall, corners[r:r + 1], tops[r:r + 1], reach)
                            for wall in walls)]
                higher = b.target is not None and _fits(room, blocks, walls, spans, w, h, low,
                                                        wall_band(b, plan.room.height)[1])
                out[k].append(Unhung(b, near, higher))
    return out


def hidden_heights(cp: CompiledPlan, ids: Sequence[str]) -> np.ndarray:
    """How high on its wall each floor object of ``ids`` hides the wall, metres, shape
    (K,): its height, or where something hangs on the wall above it (``above``), the top
    of that object at the lowest it hangs (a dresser 0.8 m tall with a 0.9 m mirror 0.1 m
    above it: 1.8 m)."""
    row = {oid: k for k, oid in enumerate(ids)}
    size = cp.size(ids)
    out = size[:, 2].copy()
    for b in cp.on("wall"):
        if b.target in row:
            t = row[b.target]
            out[t] = max(out[t], float(size[t, 2]) + target_clearance(b)
                         + float(cp.size([b.object])[0, 2]))
    return out


def unseen(cp: CompiledPlan, ids: list[str], pos: np.ndarray, yaw: np.ndarray,
           reach: float = REACH) -> list[list[Unseen]]:
    """The rules turning floor objects towards a wall object that its one spot cannot meet,
    for floor arrangements (a bed ``facing`` the TV on the wall, a dresser with a mirror
    above it on the stretch of wall the bed looks at; two beds facing one TV from
    different walls).

    The wall object hangs after the floor settles: such a rule is met only where it
    finds a free stretch on the wall the floor object's front meets, its centre within
    the rule's ``max_angle`` of that front or half its width beyond (the rule judges the
    nearest point of its footprint), and one spot serves every object turned to it. Judged as
    :func:`unhung` judges a first spot, with what hangs above a floor object (``above``)
    over that object too, up to the lowest it hangs: of the spots meeting the most of
    those rules (the first object's where they tie), the rules it leaves unmet.

    Parameters are as for :func:`unhung`.

    Returns
    -------
    list of list of Unseen
        Per arrangement, each such rule left unmet.
    """
    out: list[list[Unseen]] = [[] for _ in range(len(pos))]
    row = {oid: k for k, oid in enumerate(ids)}
    views: dict[str, list[Binding]] = {}  # per wall object, the bindings turning to it
    for b in cp.wall_views(ids):
        hangs = cp.surface_of(b.target)
        if hangs is not None and hangs.target is None:  # not hung above a floor object
            views.setdefault(b.target, []).append(b)
    if not views:
        return out
    room, plan = cp.room, cp.plan
    size = cp.size(ids)
    tops = hidden_heights(cp, ids)
    # per wall object, what no arrangement changes: its size, its band on the wall, the
    # rows turned to it and the tangents of their rules' angles
    looked_at = []
    for target, bindings in views.items():
        w, _, h = cp.size([target])[0]
        low, high = wall_band(cp.surface_of(target), plan.room.height)
        tan = np.tan(np.radians(np.minimum(
            [float(getattr(b.params, "max_angle", 90.0)) for b in bindings], 89.0)))
        looked_at.append((bindings, w, h, low, high, [row[b.object] for b in bindings], tan))
    for k in range(len(pos)):
        corners = box_corners(pos[k], yaw[k], size[:, :2] * 0.5)
        blocks: dict[int, list[Block]] = {}
        for bindings, w, h, low, high, rows, tan in looked_at:
            wall, u, dist = rays_to_walls(room, pos[k, rows], front_vectors(yaw[k, rows]))
            cone = dist * tan
            # where each lets its centre be: the rules judge the nearest point of the wall
            # object's footprint, up to half its width from its centre
            spans = np.stack([u - cone - w / 2, u + cone + w / 2], axis=1)
            best: set[int] = set()
            for wl in dict.fromkeys(int(x) for x in wall if x >= 0):
                if wl not in blocks:
                    blocks[wl] = opening_blocks(plan, wl) + _object_blocks(room, wl, corners,
                                                                           tops, reach)
                free = [rg for v in _heights(blocks[wl], h, low, high)
                        for rg in _centres(float(room.length[wl]), blocks[wl], w, h, v, None)]
                mine = np.flatnonzero(wall == wl)
                for a, c in free:  # the free centres that meet the most of the rules here
                    points = np.clip(np.concatenate([spans[mine].ravel(), [a, c]]), a, c)
                    inside = ((spans[mine, 0][None] <= points[:, None] + 1e-9)
                              & (points[:, None] <= spans[mine, 1][None] + 1e-9))
                    met = {int(mine[j]) for j in np.flatnonzero(
                        inside[int(np.argmax(inside.sum(axis=1)))])}
                    if (len(met), 0 in met) > (len(best), 0 in best):
                        best = met
            for j, b in enumerate(bindings):
                if j in best:
                    continue
                wl = int(wall[j])
                near = [] if wl < 0 else [
                    ids[q] for q in range(len(ids)) if q != rows[j]
                    for u0, u1, _, top in _object_blocks(room, wl, corners[q:q + 1],
                                                         tops[q:q + 1], reach)
                    if top > low and u0 < spans[j, 1] + w / 2 and u1 > spans[j, 0] - w / 2]
                out[k].append(Unseen(b, near))
    return out


class PinnedTie(NamedTuple):
    """A close rule between a floor object and a wall object that hangs on the one wall
    its rule names (a teacher's desk ``near`` the whiteboard ``on_wall`` wall 3): the
    floor object must stand within ``reach`` of that wall for the rule to be met."""

    binding: Binding
    floor: str  #: the floor object's id
    wall: int  #: the wall the wall object hangs on
    reach: float  #: metres from the wall's line the floor object's footprint may be


def pinned_ties(cp: CompiledPlan, ids: Sequence[str]) -> list[PinnedTie]:
    """The close rules (``closeness="close"``: ``near``, ``next_to``) between the floor
    objects ``ids`` and wall objects that hang on one wall the plan names (their surface
    rule's ``wall``), either way round; the floor object's reach is the rule's ``distance``
    (:data:`REACH` where it has none) and the wall object's depth."""
    floor = set(ids)
    out = []
    for b in cp.bindings:
        if b.rule.closeness != "close" or b.target is None:
            continue
        for oid, other in ((b.object, b.target), (b.target, b.object)):
            hangs = cp.surface_of(other)
            wall = None if hangs is None or hangs.target is not None \
                else getattr(hangs.params, "wall", None)
            if oid in floor and wall is not None and 0 <= int(wall) < cp.room.n_walls:
                reach = float(getattr(b.params, "distance", REACH))
                out.append(PinnedTie(b, oid, int(wall),
                                     reach + float(cp.plan.object(other).size[1])))
    return out


def unreached(cp: CompiledPlan, ids: list[str], pos: np.ndarray, yaw: np.ndarray
              ) -> list[list[PinnedTie]]:
    """Per floor arrangement (``pos`` (B, N, 2), ``yaw`` (B, N) of the floor objects
    ``ids``), the :func:`pinned_ties` it leaves unmet: the floor object's footprint
    farther than its reach from the wall, or past either end of it."""
    ties = pinned_ties(cp, ids)
    out: list[list[PinnedTie]] = [[] for _ in range(len(pos))]
    if not ties:
        return out
    row = {oid: k for k, oid in enumerate(ids)}
    for tie in ties:
        r = row[tie.floor]
        far = beyond_reach(cp.room, tie.wall, tie.reach, pos[:, r], front_vectors(yaw[:, r]),
                           0.5 * cp.size([tie.floor])[0, :2])
        for b in np.flatnonzero(far):
            out[b].append(tie)
    return out


def beyond_reach(room: RoomGeometry, wall: int, reach: float, pos: np.ndarray,
                 front: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Whether footprints (centres ``pos`` (..., 2), fronts ``front`` (..., 2), half size
    ``half`` (2,)) lie farther than ``reach`` metres from a wall's line, or past either end
    of the wall, shape (...)."""
    n, t = room.normal[wall], room.tangent[wall]
    rgt = np.stack([front[..., 1], -front[..., 0]], axis=-1)
    hx, hy = float(half[0]), float(half[1])
    gap = pos @ n - room.normal_offset[wall] - hx * np.abs(rgt @ n) - hy * np.abs(front @ n)
    along = pos @ t - room.tangent_offset[wall]
    wide = hx * np.abs(rgt @ t) + hy * np.abs(front @ t)
    return (gap > reach + 1e-9) | (along + wide < 0.0) | (along - wide > room.length[wall])


class Unseen(NamedTuple):
    """A rule turning a floor object towards a wall object that the wall object's spot
    leaves unmet on a floor arrangement (:func:`unseen`): its binding, and the other
    floor objects by the wall the floor object looks at that reach into the wall
    object's band within the rule's angle."""

    binding: Binding
    near: list[str]


def _fits(room: RoomGeometry, blocks: dict[int, list[Block]], walls: list[int],
          spans: list[tuple[float, float] | None], w: float, h: float, low: float,
          high: float) -> bool:
    """Whether a ``w`` x ``h`` wall object finds a first spot on one of ``walls``, in the
    band ``low..high`` and over one of ``spans`` (None: anywhere)."""
    return fits_band(low, high, h) and any(
        _centres(float(room.length[wall]), blocks[wall], w, h, v, span)
        for wall in walls for span in spans for v in _heights(blocks[wall], h, low, high))


class Unhung(NamedTuple):
    """A wall object that finds no first spot on a floor arrangement (:func:`unhung`):
    its binding, the floor objects by the walls it looked at that reach into its band
    (for one without a target), and whether it finds one higher than its rule's
    ``max_gap`` above its target (where :func:`place_on_walls` hangs it, its rule
    unmet)."""

    binding: Binding
    near: list[str]
    higher: bool


def _load_blocks(room: RoomGeometry, wall: int, corners: np.ndarray,
                 loads: list[tuple[int, float, float]], reach: float) -> list[Block]:
    """What stands on the floor objects within ``reach`` of a wall, as :func:`unhung`
    guesses it: ``(row, width, top)`` each over the middle of its parent's extent."""
    out = []
    for r, width, top in loads:
        for u0, u1, _, _ in _object_blocks(room, wall, corners[r:r + 1], np.zeros(1), reach):
            mid, half = 0.5 * (u0 + u1), 0.5 * min(width, u1 - u0)
            out.append((mid - half, mid + half, 0.0, top))
    return out


def _wall_plane(cp: CompiledPlan, wall: int,
                items: list[_Spot], static: list[Block],
                relations: bool, cfg: SolverConfig, poses: dict[str, Pose],
                out: SurfacePlacement, models: dict) -> SampleTask[None]:
    room = cp.room
    L, H = float(room.length[wall]), cp.plan.room.height
    ids = [it.binding.object for it in items]
    size = cp.size(ids)
    pos = np.array([[it.u, it.v + size[k, 2] / 2] for k, it in enumerate(items)])
    goal = np.array([it.goal for it in items])
    obstacles = [rect(max(a, 0.0), max(b0, 0.0), min(b, L), min(b1, H)) for a, b, b0, b1 in static
                 if min(b, L) - max(a, 0.0) > 1e-3 and min(b1, H) - max(b0, 0.0) > 1e-3]
    # on the plane an object's extent is its width along the wall and its height up it
    sizes = {o: (s[0], s[2], s[1]) for o, s in zip(ids, size.tolist(), strict=True)}
    model = plane_model(models, ("wall", id(cp), wall, tuple(ids), relations), cp, ids,
                        rect(0.0, 0.0, L, H), relations, sizes=sizes)
    res = yield SimRequest(model, pos, np.zeros(len(ids)), plane_solver(cfg),
                           obstacles=obstacles, terms=(AnchorTerm(goal[:, :2], goal[:, 2:]),))
    out.steps += res.steps
    out.converged &= res.converged
    final = res.pos
    if not _wall_ok(final, res.yaw, size, static, L, items):
        final = pos
    for k, o in enumerate(ids):
        u, vc = final[k]
        poses[o] = wall_pose(room, wall, float(u), float(vc - size[k, 2] / 2), size[k, 1])


def _wall_ok(pos: np.ndarray, yaw: np.ndarray, size: np.ndarray, static: list[Block],
             length: float, items: list[_Spot]) -> bool:
    """Whether settled wall objects lie on the wall, in their bands (above their targets'
    tops by the rules' clearance), centred over their targets' extents, clear of all else."""
    if np.abs(yaw).max() > 0.02 or not np.isfinite(pos).all():
        return False
    u0, u1 = pos[:, 0] - size[:, 0] / 2, pos[:, 0] + size[:, 0] / 2
    v0, v1 = pos[:, 1] - size[:, 2] / 2, pos[:, 1] + size[:, 2] / 2
    if (u0 < -1e-3).any() or (u1 > length + 1e-3).any():
        return False
    for k, it in enumerate(items):
        low, high = it.band
        if v0[k] < low - 1e-3 or v1[k] > high + 1e-3:
            return False
        if it.span is not None and not it.span[0] - 1e-3 <= pos[k, 0] <= it.span[1] + 1e-3:
            return False
        for a, b, c, d in static:
            if u0[k] < b - 1e-3 and u1[k] > a + 1e-3 and v0[k] < d - 1e-3 and v1[k] > c + 1e-3:
                return False
    for a in range(len(pos)):
        for b in range(a + 1, len(pos)):
            if (u0[a] < u1[b] - 1e-3 and u1[a] > u0[b] + 1e-3 and v0[a] < v1[b] - 1e-3
                    and v1[a] > v0[b] + 1e-3):
                return False
    return True
