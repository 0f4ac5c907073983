"""Hierarchical generation (paper §III-B-3): scene graph, area variants, assembly.

1. :func:`scene_graph` turns a plan into a :class:`networkx.DiGraph`. Strong
   dependencies are parent → child edges (``strong=True``): off-floor rules
   whose class declares ``bond = True`` (``on_top``, ``above``: target →
   object), and *bonds* between floor objects — rules whose spec has
   ``bond: true``, or, when a spec says nothing, whose class declares
   ``bond = True`` (``next_to``, ``in_front_of``, ``around``), between two
   floor objects of the same functional area (a default bond that would
   close a cycle stays a peer relation). Every other rule with a target
   (``facing``, ``near``, ...) is a peer constraint (``strong=False``,
   object → target).
2. :func:`area_variants` makes local variants of one functional area in its
   own frame: parents are placed at random and settled first, then their
   children are introduced next to them and settled, level by level.
3. :func:`assemble` abstracts each chosen variant as its bounding rectangle
   with the area's own rules (e.g. ``at_wall``), arranges the rectangles and
   the objects outside any area in a room-level simulation, carries every
   object into the room and settles all floor objects together briefly with
   every rule of the plan. :class:`VariantLibrary` keeps ``v`` variants per
   area so that the ``v ** areas`` combinations are instantiated cheaply.

:func:`sample_floor` is what :func:`forcelayout.pipeline.realise` runs with
``Options(hierarchy=True)``.
"""

from __future__ import annotations

import hashlib
import itertools
import time
from collections.abc import Iterator
from dataclasses import dataclass, replace

import networkx as nx
import numpy as np

from forcelayout.bindings import Binding, CompiledPlan, compile_plan
from forcelayout.errors import PlanError, Problem
from forcelayout.forces import ForceModel
from forcelayout.geometry import RoomGeometry, box_corners
from forcelayout.initial import initial_poses
from forcelayout.layout import Pose
from forcelayout.options import Options, SolverConfig
from forcelayout.plan import Plan
from forcelayout.rules.unary import AtWall
from forcelayout.solver import simulate

__all__ = [
    "AreaVariant",
    "VariantLibrary",
    "scene_graph",
    "area_units",
    "area_variants",
    "assemble",
    "sample_floor",
]

#: Start places of room rules that keep their meaning in an area's frame (its edges).
_LOCAL_PLACES = frozenset({"wall"})
#: Start places of area rules that already say where an area's rectangle stands.
_AREA_PLACES = frozenset({"wall", "middle"})
_FREE = "@"


def _against_wall(b: Binding) -> bool:
    return b.rule.start is not None and b.rule.start.place in _LOCAL_PLACES


def _is_bond(b: Binding, plan: Plan, floor: set[str]) -> bool | None:
    if b.bond is not None:
        return bool(b.bond)
    if not b.rule.bond or b.target is None:
        return False
    if b.object not in floor or b.target not in floor:
        return False
    if plan.object(b.object).area != plan.object(b.target).area:
        return False
    return None  # a default bond: kept unless it closes a cycle


def scene_graph(plan: Plan) -> nx.DiGraph:
    """The plan's scene graph.

    Nodes are object ids with attributes ``category``, ``area``, ``surface``
    (``"floor"`` or the surface rule), ``primary`` and ``decor``. Each edge
    has ``rules`` (names of the rules behind it) and ``strong``: strong
    edges run parent → child (``on_top``, ``above``, bonds); weak edges run
    object → target (peer constraints such as ``facing`` or ``near``).

    Raises
    ------
    PlanError
        If explicit bonds (``bond: true``) form a cycle.

    Examples
    --------
    >>> from forcelayout.examples import load_example
    >>> g = scene_graph(load_example("bedroom"))
    >>> g.edges["nightstand_1", "lamp"]["strong"]
    True
    """
    g = nx.DiGraph(name=plan.name)
    cp = compile_plan(plan)
    floor = set(cp.floor_ids)
    for o in plan.objects:
        g.add_node(o.id, category=o.category, area=o.area, surface=plan.surface_of(o.id),
                   primary=o.primary, decor=o.decor)
    ids = set(plan.ids)
    strong = nx.DiGraph()
    pending: list[Binding] = []
    for b in cp.bindings:
        if b.target is None or b.target not in ids:
            continue
        if b.rule.surface != "floor":
            if b.rule.bond if b.bond is None else b.bond:
                _add(g, b.target, b.object, b.rule.name, True)
                strong.add_edge(b.target, b.object)
            continue
        bond = _is_bond(b, plan, floor)
        if bond:
            _add(g, b.target, b.object, b.rule.name, True)
            strong.add_edge(b.target, b.object)
        elif bond is None:
            pending.append(b)
        else:
            _add(g, b.object, b.target, b.rule.name, False)
    try:
        cycle = nx.find_cycle(strong)
    except nx.NetworkXNoCycle:
        cycle = None
    if cycle:
        chain = " -> ".join([cycle[0][0], *(b for _, b in cycle)])
        raise PlanError([Problem("rules", f"bond cycle {chain}: an object cannot be the parent "
                                 "of its own parent; set 'bond': false on one of these rules")])
    for b in pending:  # default bonds, unless they close a cycle or give a second parent
        tgt, obj = b.target, b.object
        if strong.has_node(obj) and strong.in_degree(obj) > 0 or (
                strong.has_node(obj) and strong.has_node(tgt) and nx.has_path(strong, obj, tgt)):
            _add(g, obj, tgt, b.rule.name, False)  # type: ignore[arg-type]
            continue
        strong.add_edge(tgt, obj)
        _add(g, tgt, obj, b.rule.name, True)  # type: ignore[arg-type]
    return g


def _add(g: nx.DiGraph, a: str, b: str, rule: str, strong: bool) -> None:
    if g.has_edge(a, b):
        e = g.edges[a, b]
        e["rules"].append(rule)
        e["strong"] = e["strong"] or strong
    elif g.has_edge(b, a) and strong and not g.edges[b, a]["strong"]:
        rules = [*g.edges[b, a]["rules"], rule]
        g.remove_edge(b, a)
        g.add_edge(a, b, rules=rules, strong=True)
    elif g.has_edge(b, a):
        g.edges[b, a]["rules"].append(rule)
    else:
        g.add_edge(a, b, rules=[rule], strong=strong)


def _floor_depths(plan: Plan, graph: nx.DiGraph) -> dict[str, int]:
    floor = {o.id for o in plan.floor_objects()}
    strong = nx.DiGraph([(a, b) for a, b, s in graph.edges(data="strong")
                         if s and a in floor and b in floor])
    strong.add_nodes_from(floor)
    depth: dict[str, int] = {}
    for n in nx.topological_sort(strong):
        preds = list(strong.predecessors(n))
        depth[n] = 1 + max(depth[p] for p in preds) if preds else 0
    return depth


def area_units(plan: Plan, graph: nx.DiGraph | None = None) -> dict[str, list[str]]:
    """Floor objects grouped into functional areas, in plan order.

    An object follows the area of its root parent (so a bonded child stays
    with its parent); floor objects without an area are left out (they are
    placed one by one in the room-level simulation).
    """
    g = graph if graph is not None else scene_graph(plan)
    floor = [o.id for o in plan.floor_objects()]
    fset = set(floor)
    out: dict[str, list[str]] = {}
    for oid in floor:
        root = oid
        for _ in range(len(floor)):
            ps = [p for p in g.predecessors(root) if g.edges[p, root]["strong"] and p in fset]
            if not ps:
                break
            root = ps[0]
        area = plan.object(root).area
        if area is not None:
            out.setdefault(area, []).append(oid)
    return out


@dataclass(frozen=True)
class AreaVariant:
    """One local arrangement of a functional area, in the area's own frame.

    Attributes
    ----------
    area : str
    ids : tuple of str
        The area's floor objects.
    pos : ndarray, shape (K, 2)
        Footprint centres relative to the centre of :attr:`extent`, metres.
    yaw : ndarray, shape (K,)
        Headings in the area's frame, radians CCW.
    extent : tuple of float
        ``(width, depth)`` of the axis-aligned bounding rectangle, metres;
        the rectangle's local −y side is the area's back.
    height : float
        Tallest object, metres.
    steps : int
        Simulation steps it took.
    back_at_wall : bool
        Whether an ``at_wall`` object of the area stands against the area's
        back; the area's rectangle is then kept at a wall of the room.
    """

    area: str
    ids: tuple[str, ...]
    pos: np.ndarray
    yaw: np.ndarray
    extent: tuple[float, float]
    height: float
    steps: int
    back_at_wall: bool = False


def _local_bindings(cp: CompiledPlan, ids: set[str], roots: set[str], relations: bool
                    ) -> list[Binding]:
    """Bindings simulated in an area's frame: object-object rules, and the roots'
    wall rules (the frame's edges stand in for the room's walls)."""
    out = []
    for b in cp.bindings:
        if b.object not in ids or b.rule.surface != "floor":
            continue
        if b.rule.target == "required":
            if relations and b.target in ids:
                out.append(b)
        elif b.target is None and _against_wall(b) and b.object in roots:
            out.append(b)
    return out


def area_variants(
    plan: Plan,
    area: str,
    v: int,
    rng: np.random.Generator,
    *,
    relations: bool = True,
    solver: SolverConfig | None = None,
    graph: nx.DiGraph | None = None,
) -> list[AreaVariant]:
    """``v`` local variants of one functional area.

    The area is simulated in a square frame of its own (about three times
    the members' footprint, at most the room's size) with the members'
    object-object rules and ``at_wall`` (meaning the frame's edges). Parents
    (depth 0 in the scene graph) are placed at random and settled; then each
    level of children is introduced beside its parents and settled with the
    parents held fixed.

    Parameters
    ----------
    plan : Plan
    area : str
        A key of :func:`area_units`.
    v : int
        Number of variants.
    rng : numpy.random.Generator
    relations : bool
        ``False`` drops the object-object rules (the −Relations ablation).
    solver : SolverConfig, optional
    graph : networkx.DiGraph, optional
        The plan's :func:`scene_graph` (computed when omitted).

    Returns
    -------
    list of AreaVariant
    """
    g = graph if graph is not None else scene_graph(plan)
    members = area_units(plan, g).get(area)
    if not members:
        raise KeyError(f"area {area!r} has no floor objects; areas: {sorted(area_units(plan, g))}")
    cfg = solver or SolverConfig()
    depth = _floor_depths(plan, g)
    k = len(members)
    size = np.array([plan.object(m).size for m in members], dtype=float)
    room = RoomGeometry.from_room(plan.room)
    span = float((room.bounds[2:] - room.bounds[:2]).max())
    need = float(np.sqrt(3.0 * (size[:, 0] * size[:, 1]).sum()))
    big = float(size[:, :2].max()) + 0.3
    side_w = min(max(need * 1.3, float(size[:, :2].max(axis=1).sum()) + 0.1 * k, big),
                 max(span, big))
    side_d = min(max(need, big), max(span, big))
    frame = RoomGeometry(np.array([[0, 0], [side_w, 0], [side_w, side_d], [0, side_d]]), 1.0)
    cp = compile_plan(plan)
    at_wall = {b.object for b in cp.bindings if b.target is None and _against_wall(b)}
    roots = {m for m in members if depth.get(m, 0) == 0}
    local = _local_bindings(cp, set(members), roots, relations)
    facing: dict[str, list[str]] = {}
    for b in cp.bindings:
        turn = b.rule.start.turn if b.rule.start is not None else None
        if turn == "face_target" and b.object in roots and b.target in roots:
            facing.setdefault(b.object, []).append(b.target)  # type: ignore[arg-type]
            facing.setdefault(b.target, []).append(b.object)  # type: ignore[arg-type]
    levels = sorted({depth.get(m, 0) for m in members})
    area_of = size[:, 0] * size[:, 1]
    reach = size[:, :2].max(axis=1) / 2 + 0.02
    lo_c, hi_c = reach[:, None], np.array([side_w, side_d])[None, :] - reach[:, None]
    out = []
    for _ in range(max(int(v), 0)):
        pos = np.zeros((k, 2))
        yaw = np.zeros(k)
        steps = 0
        done = np.zeros(k, dtype=bool)
        first_wall = True
        sides: dict[str, int] = {}
        used: dict[int, set[float]] = {}  # sides of each parent already taken by a child
        for lev in levels[:k]:
            new = np.array([depth.get(m, 0) == lev for m in members])
            # largest first, so the biggest at_wall object takes the area's back
            for r in sorted(np.flatnonzero(new).tolist(), key=lambda r: -area_of[r]):
                parents = [members.index(p) for p in g.predecessors(members[r])
                           if p in members and done[members.index(p)]]
                if parents:  # beside the parent, in the parent's frame
                    q = parents[0]
                    wq, dq = size[q, :2] / 2
                    wr, dr = size[r, :2] / 2
                    if members[r] in at_wall and members[q] in at_wall:
                        free = [x for x in (-1.0, 1.0) if x not in used.get(q, ())] or [-1.0, 1.0]
                        side = free[int(rng.integers(len(free)))]
                        used.setdefault(q, set()).add(side)
                        off = np.array([side * (wq + wr + 0.05), dr - dq])
                    else:
                        off = [np.array([-(wq + wr + 0.05), 0.0]),
                               np.array([wq + wr + 0.05, 0.0]),
                               np.array([0.0, dq + dr + 0.05])][int(rng.integers(3))]
                    c, s_ = np.cos(yaw[q]), np.sin(yaw[q])
                    pos[r] = pos[q] + np.array([[c, -s_], [s_, c]]) @ off
                    yaw[r] = yaw[q]
                elif members[r] in at_wall:  # the first against the area's back (local -y)
                    # facing another wall object: the opposite side; else the back first
                    across = [sides[q] for q in facing.get(members[r], ()) if q in sides]
                    side = ((across[0] + 2) % 4 if across else
                            0 if first_wall else int(rng.integers(4)))
                    first_wall = False
                    sides[members[r]] = side
                    pos[r], yaw[r] = _on_frame_wall(side, size[r], side_w, side_d, rng)
                else:
                    pos[r] = rng.uniform(lo_c[r], np.maximum(hi_c[r], lo_c[r]))
                    yaw[r] = rng.integers(4) * np.pi / 2
            active = done | new
            pos[new] = np.clip(pos[new], np.minimum(lo_c[new], hi_c[new]), hi_c[new])
            ids = [m for m, a in zip(members, active, strict=True) if a]
            model = ForceModel(cp, ids, bindings=local, room=frame, relations=relations)
            res = simulate(model, pos[active], yaw[active], cfg, fixed=done[active])
            pos[active], yaw[active] = res.pos, res.yaw
            steps += res.steps
            done = active
        c = box_corners(pos, yaw, size[:, :2] * 0.5).reshape(-1, 2)
        lo, hi = c.min(axis=0), c.max(axis=0)
        out.append(AreaVariant(area, tuple(members), pos - (lo + hi) / 2, yaw.copy(),
                               (float(hi[0] - lo[0]), float(hi[1] - lo[1])),
                               float(size[:, 2].max()), steps,
                               bool(at_wall & roots)))
    return out


def _on_frame_wall(side: int, size: np.ndarray, w: float, d: float, rng: np.random.Generator
                   ) -> tuple[np.ndarray, float]:
    """A pose with the back against side ``side`` (0 = y=0, then CCW) of a ``w x d`` frame."""
    hw, hd = size[0] / 2, size[1] / 2
    if side in (0, 2):
        x = rng.uniform(min(hw, w / 2), max(w - hw, w / 2))
        return np.array([x, hd + 0.02 if side == 0 else d - hd - 0.02]), 0.0 if side == 0 else np.pi
    y = rng.uniform(min(hw, d / 2), max(d - hw, d / 2))
    return (np.array([w - hd - 0.02, y]), np.pi / 2) if side == 1 else \
        (np.array([hd + 0.02, y]), -np.pi / 2)


def _units(cp: CompiledPlan, variants: dict[str, AreaVariant], relations: bool
           ) -> tuple[list[str], dict[str, tuple[float, float, float]], list[Binding]]:
    """The room-level simulation: area rectangles and the floor objects outside any area.

    Returns the unit ids, their sizes and their bindings: each area's own
    rules (held against a wall when the variant's back holds a wall object
    and no area rule says where the area stands), the unary rules of the
    free objects, and one binding per rule between two different units.
    """
    plan = cp.plan
    unit_of: dict[str, str] = {}
    units: list[str] = []
    sizes: dict[str, tuple[float, float, float]] = {}
    for name, var in variants.items():
        uid = _FREE + name
        for m in var.ids:
            unit_of[m] = uid
        units.append(uid)
        sizes[uid] = (*var.extent, var.height)
    for oid in cp.floor_ids:
        if oid not in unit_of:
            unit_of[oid] = oid
            units.append(oid)
            sizes[oid] = tuple(cp.size([oid])[0])  # type: ignore[assignment]
    out: list[Binding] = []
    for name, var in variants.items():
        area = next((a for a in plan.areas if a.name == name), None)
        area_rules = [Binding.make(ar.rule, _FREE + name, None, ar.params,
                                   ar.weight if ar.weight is not None
                                   else plan.weights.get(ar.rule))
                      for ar in (area.rules if area is not None else [])]
        placed = any(b.rule.start is not None and b.rule.start.place in _AREA_PLACES
                     for b in area_rules)
        if var.back_at_wall and not placed:
            out.append(Binding.make(AtWall(), _FREE + name))
        for ar, b in zip(area.rules if area is not None else [], area_rules, strict=True):
            if b.rule.surface != "floor":
                continue
            tgt = (unit_of.get(ar.target, _FREE + ar.target if ar.target in variants else None)
                   if ar.target is not None else None)
            out.append(Binding(b.index, b.rule, b.object, tgt, b.params, b.weight,
                               required=b.required))
    seen: set[tuple[str, str, str | None]] = set()
    for b in cp.bindings:
        if b.rule.surface != "floor" or b.object not in unit_of:
            continue
        u = unit_of[b.object]
        if b.rule.target == "none":
            if u == b.object:
                out.append(b)
            continue
        v = unit_of.get(b.target or "", _FREE + b.target if b.target in variants else None)
        if v is None or u == v or not relations or (b.rule.name, u, v) in seen:
            continue
        seen.add((b.rule.name, u, v))
        out.append(Binding(b.index, b.rule, u, v, b.params, b.weight, required=b.required))
    return units, sizes, out


def assemble(
    plan: Plan,
    variants: dict[str, AreaVariant],
    rng: np.random.Generator,
    *,
    relations: bool = True,
    solver: SolverConfig | None = None,
    arrange_steps: int = 150,
    settle_steps: int = 150,
) -> tuple[dict[str, Pose], int, bool]:
    """Instantiate one combination of area variants in the room.

    A room-level simulation (at most ``arrange_steps`` steps) arranges the
    variants' bounding rectangles (with their areas' rules) and the floor
    objects outside any area, with the doors' swing squares as obstacles;
    every member is carried into the room; then all floor objects settle
    together for at most ``settle_steps`` steps under every rule of the plan.

    Returns
    -------
    poses : dict of str to Pose
        Every floor object of the plan.
    steps : int
    converged : bool
    """
    cfg = solver or SolverConfig()
    cp = compile_plan(plan)
    units, sizes, bindings = _units(cp, variants, relations)
    model = ForceModel(cp, units, sizes=sizes, bindings=bindings, relations=relations)
    p0, y0 = initial_poses(model, rng)
    y0 = np.round(y0 / (np.pi / 2)) * (np.pi / 2)  # rectangles start square to the room
    p0 = _push_inside(model.room, p0, y0, model.size[:, :2] * 0.5)
    doors = _door_obstacles(model.room)
    arrange = replace(cfg, max_steps=max(1, min(cfg.max_steps, arrange_steps)))
    res = simulate(model, p0, y0, arrange, obstacles=doors)
    steps, converged = res.steps, res.converged
    floor = [o.id for o in plan.floor_objects()]
    row = {u: k for k, u in enumerate(units)}
    pos = np.zeros((len(floor), 2))
    yaw = np.zeros(len(floor))
    place = {}
    for name, var in variants.items():
        k = row[_FREE + name]
        c, s = np.cos(res.yaw[k]), np.sin(res.yaw[k])
        rot = np.array([[c, -s], [s, c]])
        for m, p, y in zip(var.ids, var.pos, var.yaw, strict=True):
            place[m] = (res.pos[k] + rot @ p, y + res.yaw[k])
    for u in units:
        if u in row and not u.startswith(_FREE):
            place[u] = (res.pos[row[u]], res.yaw[row[u]])
    for r, oid in enumerate(floor):
        pos[r], yaw[r] = place[oid]
    full = ForceModel(cp, floor, relations=relations)
    pos = _push_inside(full.room, pos, yaw, full.size[:, :2] * 0.5)
    polish = replace(cfg, max_steps=max(1, min(cfg.max_steps, settle_steps)))
    res2 = simulate(full, pos, yaw, polish, obstacles=doors)
    poses = {oid: Pose(float(p[0]), float(p[1]), float(y))
             for oid, p, y in zip(floor, res2.pos, res2.yaw, strict=True)}
    return poses, steps + res2.steps, converged and res2.converged


def _door_obstacles(room: RoomGeometry) -> list[np.ndarray]:
    """Each door's swing square as a static polygon, so no area rectangle settles in it."""
    c, r, f, h = room.door_squares
    return list(box_corners(c, np.arctan2(r[:, 1], r[:, 0]), h * 0.999)) if len(c) else []


def _push_inside(room: RoomGeometry, pos: np.ndarray, yaw: np.ndarray, half: np.ndarray,
                 step: float = 0.05, cap: int = 100) -> np.ndarray:
    """Move footprints that cross a wall towards the room's centroid until they are inside."""
    pos = pos.copy()
    for _ in range(cap):
        out = ~room.contains(box_corners(pos, yaw, half)).all(axis=1)
        if not out.any():
            break
        d = room.centroid - pos[out]
        pos[out] += step * d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-9)
    return pos


class VariantLibrary:
    """``v`` local variants of every functional area of a plan, made once.

    Parameters
    ----------
    plan : Plan
    v : int
        Variants per area.
    seed : int
        Seed of the variants (the same plan, ``v`` and seed give the same library).
    relations : bool
    solver : SolverConfig, optional

    Attributes
    ----------
    variants : dict of str to list of AreaVariant
    seconds : float
        Time it took to make them.
    """

    def __init__(self, plan: Plan, v: int = 6, *, seed: int = 0, relations: bool = True,
                 solver: SolverConfig | None = None):
        if v < 1:
            raise ValueError(f"v must be >= 1, got {v}")
        t0 = time.perf_counter()
        self.plan, self.v = plan, int(v)
        self.graph = scene_graph(plan)
        rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, 7])
        self.variants = {a: area_variants(plan, a, v, rng, relations=relations, solver=solver,
                                          graph=self.graph)
                         for a in area_units(plan, self.graph)}
        self.seconds = time.perf_counter() - t0

    @property
    def n_combinations(self) -> int:
        """Number of distinct combinations of area variants (``v ** areas``)."""
        return int(np.prod([len(vs) for vs in self.variants.values()], dtype=float))

    def combinations(self, budget: int | None = None, rng: np.random.Generator | None = None
                     ) -> Iterator[dict[str, AreaVariant]]:
        """All combinations (at most ``budget``; a random sample when there are more)."""
        names = list(self.variants)
        total = self.n_combinations
        if budget is None or budget >= total:
            for combo in itertools.product(*(range(len(self.variants[a])) for a in names)):
                yield {a: self.variants[a][k] for a, k in zip(names, combo, strict=True)}
            return
        rng = rng or np.random.default_rng(0)
        for _ in range(int(budget)):
            yield self.choose(rng)

    def choose(self, rng: np.random.Generator) -> dict[str, AreaVariant]:
        """One random combination (a variant per area)."""
        return {a: vs[int(rng.integers(len(vs)))] for a, vs in self.variants.items()}


_LIBRARIES: dict[tuple[str, int, int, bool], VariantLibrary] = {}


def _library(plan: Plan, opts: Options) -> VariantLibrary:
    v, seed, relations = int(opts.variants), int(opts.variant_seed), bool(opts.relations)
    key = (hashlib.sha1(plan.to_json(indent=None).encode()).hexdigest(), v, seed, relations)
    lib = _LIBRARIES.get(key)
    if lib is None:
        if len(_LIBRARIES) > 16:
            _LIBRARIES.clear()
        lib = _LIBRARIES[key] = VariantLibrary(plan, v, seed=seed, relations=relations,
                                               solver=opts.solver)
    return lib


def sample_floor(plan: Plan, rng: np.random.Generator, opts: Options
                 ) -> tuple[dict[str, Pose], int, bool, dict[str, float]]:
    """The floor of one sample on the hierarchical path.

    The plan's :class:`VariantLibrary` (``opts.variants`` per area, seeded
    by ``opts.variant_seed``) is made once per process and reused; each
    sample draws one combination with ``rng`` and :func:`assemble` s it.

    Returns
    -------
    poses, steps, converged, stages
        ``stages`` holds ``"variants"`` (0 after the first sample) and ``"assembly"``.
    """
    t0 = time.perf_counter()
    lib = _library(plan, opts)
    t1 = time.perf_counter()
    poses, steps, conv = assemble(plan, lib.choose(rng), rng,
                                  relations=opts.relations,
                                  solver=opts.solver)
    return poses, steps, conv, {"variants": t1 - t0, "assembly": time.perf_counter() - t1}
