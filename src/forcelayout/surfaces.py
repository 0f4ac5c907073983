"""Surface placement (paper §III-B-4): objects on tops, on walls and on the ceiling.

Every surface is a 2D plane solved with the same annealed simulation as the
floor (:func:`forcelayout.solver.simulate`):

* **a parent's top** is a rectangle "room" of the parent's width x depth in
  the parent's frame; its ``on_top`` children are simulated there with
  their rules between each other (``at_wall`` means "at the top's edge"),
  then carried to the room at ``z`` = parent's ``z`` + parent's height;
* **a wall** is unfolded into a rectangle of wall length x room height
  (``u`` along the wall from ``polygon[i]``, ``v`` up from the floor);
  doors, windows and the floor objects standing within ``reach`` metres of
  the wall (projected as ``[u0, u1] x [0, top]`` zones) are static
  obstacles; ``on_wall``/``on_wall_mid``/``above`` objects start at a free
  spot of their height band and settle under a pull towards eye level (and,
  for ``above``, towards the target's centre);
* **the ceiling** is the floor polygon seen from below; ``on_ceiling``
  objects are pulled to the room's centroid, the target object's centre or
  a functional area's centre.

An object that cannot be placed is reported as missing with the reason;
:func:`check_surfaces` catches what can be known before any simulation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from forcelayout import rules as registry
from forcelayout.errors import PlanError, Problem
from forcelayout.forces import ForceModel
from forcelayout.geometry import RoomGeometry, box_corners
from forcelayout.layout import Pose
from forcelayout.plan import SURFACE_RULES, Plan, RuleSpec, SceneObject
from forcelayout.rules.base import State
from forcelayout.solver import SolverConfig, simulate

__all__ = [
    "WALL_RULES",
    "SurfacePlacement",
    "check_surfaces",
    "free_wall_stretches",
    "place_surfaces",
    "wall_pose",
]

#: Rules that hang an object on a wall.
WALL_RULES = frozenset({"on_wall", "on_wall_mid", "above"})
#: Eye level, metres: wall objects settle with their centre near this height.
EYE_LEVEL = 1.6
_MARGIN = 0.02


@dataclass
class SurfacePlacement:
    """Poses of the off-floor objects and how their placement went.

    Attributes
    ----------
    poses : dict of str to Pose
        Every pose (the floor poses given in, plus the surface objects placed).
    missing : list of str
        ``"<id>: <reason>"`` per object that could not be placed.
    steps : int
        Simulation steps over all surface planes.
    converged : bool
        Whether every surface simulation settled.
    stages : dict of str to float
        Seconds spent on ``"on_top"``, ``"walls"`` and ``"ceiling"``.
    """

    poses: dict[str, Pose]
    missing: list[str] = field(default_factory=list)
    steps: int = 0
    converged: bool = True
    stages: dict[str, float] = field(default_factory=dict)


class _PlaneModel(ForceModel):
    """A force model with an extra annealed spring pulling objects to anchor points."""

    anchor: np.ndarray
    stiffness: np.ndarray

    def net(self, state: State, temperature: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
        f, tau = super().net(state, temperature)
        f = f + self.stiffness * (self.anchor - state.pos) * max(temperature, 0.25)
        return f, tau


def _surrogate(plan: Plan, objects: list[tuple[str, tuple[float, float, float]]],
               rules: list[RuleSpec]) -> Plan:
    """A plan (unvalidated) of the given objects and sizes, for a plane simulation."""
    objs = [SceneObject.model_construct(id=i, category=plan.object(i).category, description="",
                                        size=tuple(s), area=None, primary=False, decor=False)
            for i, s in objects]
    return Plan.model_construct(name=plan.name, description="", room=plan.room, objects=objs,
                                rules=rules, areas=[], weights=plan.weights)


def _plane_model(plan: Plan, objects: list[tuple[str, tuple[float, float, float]]],
                 rules: list[RuleSpec], room: RoomGeometry, relations: bool,
                 anchor: np.ndarray, stiffness: np.ndarray) -> _PlaneModel:
    sur = _surrogate(plan, objects, rules)
    m = _PlaneModel(sur, [i for i, _ in objects], room=room, relations=relations)
    m.anchor = np.asarray(anchor, dtype=float).reshape(-1, 2)
    m.stiffness = np.asarray(stiffness, dtype=float).reshape(-1, 2)
    return m


def _surface_solver(cfg: SolverConfig) -> SolverConfig:
    return replace(cfg, min_steps=min(cfg.min_steps, 10), max_steps=min(cfg.max_steps, 120),
                   patience=min(cfg.patience, 5))


def _rect(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=float)


# -- wall geometry -------------------------------------------------------------------------


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


def _opening_blocks(plan: Plan, wall: int) -> list[tuple[float, float, float, float]]:
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
                   reach: float) -> list[tuple[float, float, float, float]]:
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


def _free(length: float, blocks: list[tuple[float, float, float, float]], v0: float, v1: float,
          margin: float = _MARGIN) -> list[tuple[float, float]]:
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


def _band(spec: RuleSpec, room_height: float) -> tuple[float, float]:
    rule = registry.get_rule(spec.rule)
    p = rule.Params.model_validate(spec.params)
    high = getattr(p, "high", None)
    high = room_height if high is None else min(float(high), room_height)
    return float(getattr(p, "low", 0.0)), high


def free_wall_stretches(plan: Plan, wall: int, low: float, high: float, height: float
                        ) -> list[tuple[float, float]]:
    """Stretches of a wall where an object ``height`` tall fits in the band, ignoring furniture.

    A door or window blocks its stretch unless the object fits above or
    below it inside ``[low, high]`` metres.

    Returns
    -------
    list of (u0, u1)
        Free stretches in metres from ``polygon[wall]``.
    """
    blocks = []
    for u0, u1, v0, v1 in _opening_blocks(plan, wall):
        below = min(high, v0) - low >= height
        above = high - max(low, v1) >= height
        if not (below or above):
            blocks.append((u0, u1, -1.0, math.inf))
    return _free(plan.room.wall_length(wall), blocks, 0.0, 1.0, margin=0.0)


def check_surfaces(plan: Plan) -> None:
    """Raise :class:`~forcelayout.errors.PlanError` for surface bindings that cannot be met.

    Checks, before any simulation, that each wall object fits its height
    band, that a pinned wall exists, and that the object is not wider than
    every free stretch of the walls it may use (doors and windows taken out).

    Raises
    ------
    PlanError
        Listing every problem with its ``rules[k]`` path.
    """
    problems: list[Problem] = []
    room = plan.room
    n_walls = len(room.polygon)
    ids = set(plan.ids)
    for k, spec in enumerate(plan.rules):
        if spec.rule not in WALL_RULES or spec.object not in ids:
            continue
        path = f"rules[{k}] ({spec.rule})"
        w, _, h = plan.object(spec.object).size
        low, high = _band(spec, room.height)
        if spec.rule == "above" and spec.target in ids:
            clearance = float(registry.get_rule("above").Params.model_validate(spec.params)
                              .clearance)  # type: ignore[attr-defined]
            t = plan.object(spec.target)
            low = max(low, t.size[2] + clearance if plan.surface_of(t.id) == "floor" else low)
        if high - low < h - 1e-9:
            problems.append(Problem(f"{path}.params", f"{spec.object!r} is {h:g} m tall but its "
                                    f"band on the wall is {low:.2f}..{high:.2f} m; lower 'low', "
                                    "raise 'high' or use a smaller object"))
            continue
        pinned = spec.params.get("wall")
        if pinned is not None and int(pinned) >= n_walls:
            problems.append(Problem(f"{path}.params.wall", f"wall {pinned} does not exist; the "
                                    f"room has walls 0..{n_walls - 1}"))
            continue
        walls = [int(pinned)] if pinned is not None else list(range(n_walls))
        widest = max((b - a for wl in walls
                      for a, b in free_wall_stretches(plan, wl, low, high, h)), default=0.0)
        if w > widest + 1e-9:
            where = f"wall {pinned}" if pinned is not None else "any wall"
            problems.append(Problem(path, f"{spec.object!r} is {w:g} m wide but the widest free "
                                    f"stretch of {where} is {widest:.2f} m (doors and windows "
                                    "taken out); use a narrower object or another wall"))
    if problems:
        raise PlanError(problems)


# -- placement ---------------------------------------------------------------------------


def _corners_tops(plan: Plan, poses: dict[str, Pose], ids: list[str]
                  ) -> tuple[np.ndarray, np.ndarray]:
    if not ids:
        return np.zeros((0, 4, 2)), np.zeros(0)
    size = np.array([plan.object(i).size for i in ids], dtype=float)
    pos = np.array([[poses[i].x, poses[i].y] for i in ids])
    yaw = np.array([poses[i].yaw for i in ids])
    tops = np.array([poses[i].z for i in ids]) + size[:, 2]
    return box_corners(pos, yaw, size[:, :2] * 0.5), tops


def _place_on_top(plan: Plan, poses: dict[str, Pose], rng: np.random.Generator,
                  relations: bool, cfg: SolverConfig, out: SurfacePlacement) -> None:
    children: dict[str, list[str]] = {}
    for s in plan.rules:
        if s.rule == "on_top" and s.target is not None:
            children.setdefault(s.target, []).append(s.object)
    done: set[str] = set()
    for _ in range(len(children) + 1):  # parents in order: a parent must be placed first
        ready = [p for p in children if p not in done and p in poses]
        if not ready:
            break
        for parent in ready:
            done.add(parent)
            _top_plane(plan, parent, children[parent], poses, rng, relations, cfg, out)
    for parent, kids in children.items():
        if parent not in done:
            out.missing.extend(f"{c}: its parent {parent!r} was not placed" for c in kids)


def _top_plane(plan: Plan, parent: str, kids: list[str], poses: dict[str, Pose],
               rng: np.random.Generator, relations: bool, cfg: SolverConfig,
               out: SurfacePlacement) -> None:
    pw, pd, ph = plan.object(parent).size
    room = RoomGeometry(_rect(-pw / 2, -pd / 2, pw / 2, pd / 2), height=1.0)
    kid_set = set(kids)
    rules = [s for s in plan.rules if s.object in kid_set and s.rule not in SURFACE_RULES
             and ((s.target in kid_set) or (s.target is None and s.rule == "at_wall"))]
    size = np.array([plan.object(k).size for k in kids], dtype=float)
    pos = np.zeros((len(kids), 2))
    yaw = np.zeros(len(kids))
    for r in range(len(kids)):
        best, best_gap = None, -np.inf
        for _ in range(12):
            y = float(rng.integers(4)) * np.pi / 2
            w, d = (size[r, 0], size[r, 1]) if int(round(y / (np.pi / 2))) % 2 == 0 \
                else (size[r, 1], size[r, 0])
            if w > pw + 1e-9 or d > pd + 1e-9:
                continue
            p = rng.uniform([-(pw - w) / 2, -(pd - d) / 2], [(pw - w) / 2, (pd - d) / 2])
            gap = _min_gap(np.vstack([pos[:r], p]), np.append(yaw[:r], y), size[: r + 1])
            if gap > best_gap:
                best, best_gap = (p, y), gap
            if gap > 0.01:
                break
        if best is None:
            out.missing.append(f"{kids[r]}: does not fit on top of {parent!r} in any orientation")
            return
        pos[r], yaw[r] = best
    model = _plane_model(plan, [(k, plan.object(k).size) for k in kids], rules, room, relations,
                         pos, np.zeros((len(kids), 2)))
    res = simulate(model, pos, yaw, _surface_solver(cfg))
    out.steps += res.steps
    out.converged &= res.converged
    fpos, fyaw = res.pos, res.yaw
    if not _fits_rect(fpos, fyaw, size, pw, pd):
        fpos, fyaw = pos, yaw
    if not _fits_rect(fpos, fyaw, size, pw, pd):
        out.missing.extend(f"{k}: no room for it on top of {parent!r} beside the other objects "
                           "there" for k in kids)
        return
    P = poses[parent]
    c, s = math.cos(P.yaw), math.sin(P.yaw)
    z = P.z + ph
    for k, (x, y), t in zip(kids, fpos.tolist(), fyaw.tolist(), strict=True):
        a = (t + P.yaw + np.pi) % (2 * np.pi) - np.pi
        poses[k] = Pose(P.x + c * x - s * y, P.y + s * x + c * y, float(a), float(z), parent)


def _min_gap(pos: np.ndarray, yaw: np.ndarray, size: np.ndarray) -> float:
    if len(pos) < 2:
        return np.inf
    st = State(pos, yaw, size, RoomGeometry(_rect(-1, -1, 1, 1)))
    m = st.separations.copy()
    np.fill_diagonal(m, np.inf)
    return float(m[-1].min())


def _fits_rect(pos: np.ndarray, yaw: np.ndarray, size: np.ndarray, w: float, d: float) -> bool:
    c = box_corners(pos, yaw, size[:, :2] * 0.5)
    inside = (np.abs(c[..., 0]) <= w / 2 + 1e-3).all() and (np.abs(c[..., 1]) <= d / 2 + 1e-3).all()
    return bool(inside) and _min_gap_all(pos, yaw, size) >= -1e-3


def _min_gap_all(pos: np.ndarray, yaw: np.ndarray, size: np.ndarray) -> float:
    if len(pos) < 2:
        return np.inf
    st = State(pos, yaw, size, RoomGeometry(_rect(-1, -1, 1, 1)))
    m = st.separations.copy()
    np.fill_diagonal(m, np.inf)
    return float(m.min())


def _target_walls(room: RoomGeometry, corners: np.ndarray) -> list[int]:
    """The two walls nearest to a footprint, nearest first."""
    d, _ = room.wall_distance(corners)  # (4, W)
    return np.argsort(d.min(axis=0), kind="stable")[:2].tolist()


def _place_walls(plan: Plan, poses: dict[str, Pose], rng: np.random.Generator,
                 relations: bool, cfg: SolverConfig, reach: float,
                 out: SurfacePlacement) -> None:
    room = RoomGeometry.from_room(plan.room)
    H = plan.room.height
    specs = [s for s in plan.rules if s.rule in WALL_RULES]
    if not specs:
        return
    ground = [i for i in poses if not poses[i].surface.startswith(("wall:", "ceiling"))]
    corners, tops = _corners_tops(plan, poses, ground)
    blocks = {w: _opening_blocks(plan, w) + _object_blocks(room, w, corners, tops, reach)
              for w in range(room.n_walls)}
    # initial spots, one object after the other (placed objects block the next)
    placed: dict[int, list[tuple[str, float, float, np.ndarray]]] = {}
    for spec in specs:
        oid = spec.object
        w, d, h = plan.object(oid).size
        low, high = _band(spec, H)
        span: tuple[float, float] | None = None
        walls: list[int]
        if spec.rule == "above":
            if spec.target not in poses:
                out.missing.append(f"{oid}: its target {spec.target!r} was not placed")
                continue
            tc, tt = _corners_tops(plan, poses, [spec.target])  # type: ignore[list-item]
            walls = _target_walls(room, tc[0])
            clearance = float(registry.get_rule("above").Params.model_validate(spec.params)
                              .clearance)  # type: ignore[attr-defined]
            low = max(low, float(tt[0]) + clearance)
        else:
            pinned = spec.params.get("wall")
            walls = [int(pinned)] if pinned is not None else rng.permutation(room.n_walls).tolist()
        spot = None
        for wall in walls:
            if spec.rule == "above":
                u = tc[0] @ room.tangent[wall] - room.tangent_offset[wall]
                span = (float(u.min()), float(u.max()))
            spot = _wall_spot(room.length[wall], blocks[wall], w, h, low, high, span, rng)
            if spot is not None:
                u, v = spot
                blocks[wall].append((u - w / 2, u + w / 2, v, v + h))
                goal_u = u if span is None else float(np.clip((span[0] + span[1]) / 2,
                                                              span[0], span[1]))
                v_goal = float(np.clip(EYE_LEVEL, low + h / 2, high - h / 2))
                stiff = np.array([0.0 if span is None else 1.0, 0.5])
                placed.setdefault(wall, []).append((oid, u, v, np.array([goal_u, v_goal, *stiff])))
                break
        if spot is None:
            band = f"{low:.2f}..{high:.2f} m"
            where = (f"wall {walls[0]}" if len(walls) == 1 else "any wall"
                     if spec.rule != "above" else f"walls {walls} near {spec.target!r}")
            out.missing.append(f"{oid}: no free stretch {w:g} m wide on {where} in the band "
                               f"{band} (doors, windows and furniture block it)")
    for wall, items in placed.items():
        static = [b for b in blocks[wall] if b not in [
            (u - plan.object(o).size[0] / 2, u + plan.object(o).size[0] / 2, v,
             v + plan.object(o).size[2]) for o, u, v, _ in items]]
        _wall_plane(plan, room, wall, items, static, relations, cfg, poses, out)


def _wall_spot(length: float, blocks: list[tuple[float, float, float, float]], w: float,
               h: float, low: float, high: float, span: tuple[float, float] | None,
               rng: np.random.Generator) -> tuple[float, float] | None:
    """A free ``(u centre, v bottom)`` for a ``w x h`` object in the band, or None."""
    if high - low < h:
        return None
    pref = float(np.clip(EYE_LEVEL - h / 2, low, high - h))
    # eye level first, then just above / below each obstacle, then the band's ends, then random
    edges = [b[3] for b in blocks] + [b[2] - h for b in blocks]
    edges = sorted({float(e) for e in edges if low <= e <= high - h},
                   key=lambda e: abs(e + h / 2 - EYE_LEVEL))
    heights = [pref, *edges[:16], low, high - h, *rng.uniform(low, high - h, 4).tolist()]
    for v in heights:
        ranges = [(a + w / 2, b - w / 2) for a, b in _free(length, blocks, v, v + h)
                  if b - a >= w]
        if span is not None:
            ranges = [(max(a, span[0]), min(b, span[1])) for a, b in ranges]
            ranges = [(a, b) for a, b in ranges if b >= a]
        if not ranges:
            continue
        lens = np.array([b - a for a, b in ranges]) + 1e-6
        k = int(rng.choice(len(ranges), p=lens / lens.sum()))
        return float(rng.uniform(*ranges[k])), float(v)
    return None


def _wall_plane(plan: Plan, room: RoomGeometry, wall: int,
                items: list[tuple[str, float, float, np.ndarray]],
                static: list[tuple[float, float, float, float]], relations: bool,
                cfg: SolverConfig, poses: dict[str, Pose], out: SurfacePlacement) -> None:
    L, H = float(room.length[wall]), plan.room.height
    plane = RoomGeometry(_rect(0.0, 0.0, L, H), height=1.0)
    ids = [o for o, _, _, _ in items]
    size = np.array([plan.object(o).size for o in ids], dtype=float)
    pos = np.array([[u, v + size[k, 2] / 2] for k, (_, u, v, _) in enumerate(items)])
    goal = np.array([g for _, _, _, g in items])
    obstacles = [_rect(max(a, 0.0), max(b0, 0.0), min(b, L), min(b1, H)) for a, b, b0, b1 in static
                 if min(b, L) - max(a, 0.0) > 1e-3 and min(b1, H) - max(b0, 0.0) > 1e-3]
    sizes = [(o, (s[0], s[2], s[1])) for o, s in zip(ids, size.tolist(), strict=True)]
    model = _plane_model(plan, sizes, [], plane, relations, goal[:, :2], goal[:, 2:])
    res = simulate(model, pos, np.zeros(len(ids)), _surface_solver(cfg), obstacles=obstacles)
    out.steps += res.steps
    out.converged &= res.converged
    final = res.pos
    if not _wall_ok(final, res.yaw, size, static, L, plan, items):
        final = pos
    for k, o in enumerate(ids):
        u, vc = final[k]
        poses[o] = wall_pose(room, wall, float(u), float(vc - size[k, 2] / 2), size[k, 1])


def _wall_ok(pos: np.ndarray, yaw: np.ndarray, size: np.ndarray,
             static: list[tuple[float, float, float, float]], length: float, plan: Plan,
             items: list[tuple[str, float, float, np.ndarray]]) -> bool:
    if np.abs(yaw).max() > 0.02 or not np.isfinite(pos).all():
        return False
    u0, u1 = pos[:, 0] - size[:, 0] / 2, pos[:, 0] + size[:, 0] / 2
    v0, v1 = pos[:, 1] - size[:, 2] / 2, pos[:, 1] + size[:, 2] / 2
    if (u0 < -1e-3).any() or (u1 > length + 1e-3).any():
        return False
    for k, (o, _, _, _) in enumerate(items):
        spec = next(s for s in plan.rules if s.object == o and s.rule in WALL_RULES)
        low, high = _band(spec, plan.room.height)
        if v0[k] < low - 1e-3 or v1[k] > high + 1e-3:
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


def _place_ceiling(plan: Plan, poses: dict[str, Pose], rng: np.random.Generator,
                   relations: bool, cfg: SolverConfig, out: SurfacePlacement) -> None:
    specs = [s for s in plan.rules if s.rule == "on_ceiling"]
    if not specs:
        return
    room = RoomGeometry.from_room(plan.room)
    plane = RoomGeometry(room.polygon, height=1.0)
    H = plan.room.height
    areas = {a.name for a in plan.areas}
    ids, anchor, stiff = [], [], []
    for spec in specs:
        p = registry.get_rule("on_ceiling").Params.model_validate(spec.params)
        centre = room.centroid
        if spec.target in areas:
            members = [o.id for o in plan.objects if o.area == spec.target and o.id in poses
                       and poses[o.id].surface == "floor"]
            if members:
                centre = np.mean([[poses[m].x, poses[m].y] for m in members], axis=0)
        elif spec.target is not None:
            if spec.target not in poses:
                out.missing.append(f"{spec.object}: its target {spec.target!r} was not placed")
                continue
            centre = np.array([poses[spec.target].x, poses[spec.target].y])
        if not p.centred:  # type: ignore[attr-defined]
            lo, hi = room.bounds[:2], room.bounds[2:]
            for _ in range(50):
                centre = rng.uniform(lo, hi)
                if room.contains(centre):
                    break
        ids.append(spec.object)
        anchor.append(centre)
        stiff.append([1.0, 1.0] if p.centred else [0.0, 0.0])  # type: ignore[attr-defined]
    if not ids:
        return
    size = np.array([plan.object(o).size for o in ids], dtype=float)
    pos = np.array(anchor) + rng.normal(0.0, 0.02, (len(ids), 2))
    model = _plane_model(plan, [(o, plan.object(o).size) for o in ids], [], plane, relations,
                         np.array(anchor), np.array(stiff))
    res = simulate(model, pos, np.zeros(len(ids)), _surface_solver(cfg))
    out.steps += res.steps
    out.converged &= res.converged
    inside = room.contains(box_corners(res.pos, res.yaw, size[:, :2] * 0.5)).all(axis=1)
    for k, o in enumerate(ids):
        if not inside[k]:
            out.missing.append(f"{o}: does not fit on the ceiling")
            continue
        poses[o] = Pose(float(res.pos[k, 0]), float(res.pos[k, 1]), float(res.yaw[k]),
                        float(H - size[k, 2]), "ceiling")


def place_surfaces(
    plan: Plan,
    floor: dict[str, Pose],
    rng: np.random.Generator,
    *,
    relations: bool = True,
    solver: SolverConfig | None = None,
    reach: float = 0.3,
) -> SurfacePlacement:
    """Place every off-floor object of the plan, given the floor objects' poses.

    Parameters
    ----------
    plan : Plan
    floor : dict of str to Pose
        Poses of the floor objects (not modified).
    rng : numpy.random.Generator
        Source of all randomness of this stage.
    relations : bool
        ``False`` zeroes the object-object rules on surfaces too.
    solver : SolverConfig, optional
        Base simulation parameters; surface planes use at most 120 steps.
    reach : float
        Floor objects closer than this to a wall (metres) are obstacles on it.

    Returns
    -------
    SurfacePlacement
        All poses; objects that could not be placed are in ``missing``.
    """
    import time

    cfg = solver or SolverConfig()
    out = SurfacePlacement(dict(floor))
    t = time.perf_counter()
    _place_on_top(plan, out.poses, rng, relations, cfg, out)
    t1 = time.perf_counter()
    _place_walls(plan, out.poses, rng, relations, cfg, reach, out)
    t2 = time.perf_counter()
    _place_ceiling(plan, out.poses, rng, relations, cfg, out)
    t3 = time.perf_counter()
    out.stages = {"on_top": t1 - t, "walls": t2 - t1, "ceiling": t3 - t2}
    placed = set(out.poses)
    reasons = {m.split(":")[0] for m in out.missing}
    for o in plan.objects:
        if o.id not in placed and o.id not in reasons:
            out.missing.append(f"{o.id}: placed by {plan.surface_of(o.id)!r}, which no stage "
                               "placed")
    return out
