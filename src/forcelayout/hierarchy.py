"""Hierarchical generation (paper §III-B-3): scene graph, area variants, assembly.

1. :func:`scene_graph` turns a plan into a :class:`networkx.DiGraph`. Strong
   dependencies are parent → child edges (``strong=True``): ``on_top`` and
   ``above`` (target → object), and *bonds* — binary rules whose spec has
   ``bond: true``, or, when a spec says nothing, ``next_to``,
   ``in_front_of`` and ``around`` between two floor objects of the same
   functional area (a default bond that would close a cycle stays a peer
   relation). Every other binary rule (``facing``, ``near``, ...) is a
   peer constraint (``strong=False``, object → target).
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
from typing import TYPE_CHECKING

import networkx as nx
import numpy as np

from forcelayout import rules as registry
from forcelayout.errors import PlanError, Problem
from forcelayout.forces import ForceModel
from forcelayout.geometry import RoomGeometry, box_corners
from forcelayout.layout import Pose
from forcelayout.plan import SURFACE_RULES, Plan, RuleSpec, SceneObject
from forcelayout.solver import SolverConfig, simulate

if TYPE_CHECKING:
    from forcelayout.sampling import Options

__all__ = [
    "DEFAULT_BONDS",
    "AreaVariant",
    "VariantLibrary",
    "scene_graph",
    "area_units",
    "area_variants",
    "assemble",
    "sample_floor",
]

#: Binary rules that bond an object to its target (parent) when the spec does not say.
DEFAULT_BONDS = frozenset({"next_to", "in_front_of", "around"})
#: Unary rules kept in an area's local frame (the others need the real room).
_LOCAL_UNARY = frozenset({"at_wall"})
_FREE = "@"


def _is_bond(spec: RuleSpec, plan: Plan, floor: set[str]) -> bool | None:
    explicit = getattr(spec, "bond", None)
    if explicit is not None:
        return bool(explicit)
    if spec.rule not in DEFAULT_BONDS or spec.target is None:
        return False
    if spec.object not in floor or spec.target not in floor:
        return False
    if plan.object(spec.object).area != plan.object(spec.target).area:
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
    floor = {o.id for o in plan.floor_objects()}
    for o in plan.objects:
        g.add_node(o.id, category=o.category, area=o.area, surface=plan.surface_of(o.id),
                   primary=o.primary, decor=o.decor)
    ids = set(plan.ids)
    strong = nx.DiGraph()
    pending: list[RuleSpec] = []
    for spec in plan.rules:
        if spec.target is None or spec.target not in ids:
            continue
        if spec.rule in ("on_top", "above"):
            _add(g, spec.target, spec.object, spec.rule, True)
            strong.add_edge(spec.target, spec.object)
            continue
        if spec.rule in SURFACE_RULES:
            continue
        bond = _is_bond(spec, plan, floor)
        if bond:
            _add(g, spec.target, spec.object, spec.rule, True)
            strong.add_edge(spec.target, spec.object)
        elif bond is None:
            pending.append(spec)
        else:
            _add(g, spec.object, spec.target, spec.rule, False)
    try:
        cycle = nx.find_cycle(strong)
    except nx.NetworkXNoCycle:
        cycle = None
    if cycle:
        chain = " -> ".join([cycle[0][0], *(b for _, b in cycle)])
        raise PlanError([Problem("rules", f"bond cycle {chain}: an object cannot be the parent "
                                 "of its own parent; set 'bond': false on one of these rules")])
    for spec in pending:  # default bonds, unless they close a cycle or give a second parent
        tgt, obj = spec.target, spec.object
        if strong.has_node(obj) and strong.in_degree(obj) > 0 or (
                strong.has_node(obj) and strong.has_node(tgt) and nx.has_path(strong, obj, tgt)):
            _add(g, obj, tgt, spec.rule, False)  # type: ignore[arg-type]
            continue
        strong.add_edge(tgt, obj)
        _add(g, tgt, obj, spec.rule, True)  # type: ignore[arg-type]
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


def _local_rules(plan: Plan, ids: set[str], roots: set[str], relations: bool
                 ) -> list[RuleSpec]:
    """Rules simulated in an area's frame: object-object rules, and the roots' ``at_wall``."""
    out = []
    for s in plan.rules:
        if s.object not in ids or s.rule in SURFACE_RULES:
            continue
        kind = registry.get_rule(s.rule).kind
        if kind == "binary" and relations and s.target in ids:
            out.append(s)
        elif kind == "unary" and s.rule in _LOCAL_UNARY and s.object in roots:
            out.append(s)
    return out


def _sub_plan(plan: Plan, rules: list[RuleSpec]) -> Plan:
    return plan.model_copy(update={"rules": rules})


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
    at_wall = {s.object for s in plan.rules if s.rule == "at_wall"}
    roots = {m for m in members if depth.get(m, 0) == 0}
    sub = _sub_plan(plan, _local_rules(plan, set(members), roots, relations))
    facing: dict[str, list[str]] = {}
    for s_ in plan.rules:
        if s_.rule == "facing" and s_.object in roots and s_.target in roots:
            facing.setdefault(s_.object, []).append(s_.target)  # type: ignore[arg-type]
            facing.setdefault(s_.target, []).append(s_.object)  # type: ignore[arg-type]
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
            model = ForceModel(sub, ids, room=frame, relations=relations)
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


def _unit_plan(plan: Plan, variants: dict[str, AreaVariant], relations: bool
               ) -> tuple[Plan, list[str], dict[str, str]]:
    """A plan (unvalidated) whose objects are area rectangles and the free floor objects."""
    unit_of: dict[str, str] = {}
    objs: list[SceneObject] = []
    for name, var in variants.items():
        uid = _FREE + name
        for m in var.ids:
            unit_of[m] = uid
        objs.append(SceneObject.model_construct(
            id=uid, category="area", description="", size=(*var.extent, var.height), area=name,
            primary=False, decor=False))
    for o in plan.floor_objects():
        if o.id not in unit_of:
            unit_of[o.id] = o.id
            objs.append(o)
    rules: list[RuleSpec] = []
    for name, var in variants.items():
        area = next((a for a in plan.areas if a.name == name), None)
        area_rules = list(area.rules) if area is not None else []
        if var.back_at_wall and not any(ar.rule in ("at_wall", "in_middle") for ar in area_rules):
            rules.append(RuleSpec.model_construct(rule="at_wall", object=_FREE + name,
                                                  target=None, params={}, weight=None))
        for ar in area_rules:
            if registry.get_rule(ar.rule).kind == "surface":
                continue
            tgt = unit_of.get(ar.target, _FREE + ar.target if ar.target in variants else None) \
                if ar.target is not None else None
            rules.append(RuleSpec.model_construct(rule=ar.rule, object=_FREE + name, target=tgt,
                                                  params=ar.params, weight=ar.weight))
    seen: set[tuple[str, str, str | None]] = set()
    for s in plan.rules:
        if s.rule in SURFACE_RULES or s.object not in unit_of:
            continue
        a = unit_of[s.object]
        kind = registry.get_rule(s.rule).kind
        if kind == "unary":
            if a == s.object:
                rules.append(s)
            continue
        b = unit_of.get(s.target or "", _FREE + s.target if s.target in variants else None)
        if b is None or a == b or not relations or (s.rule, a, b) in seen:
            continue
        seen.add((s.rule, a, b))
        rules.append(RuleSpec.model_construct(rule=s.rule, object=a, target=b, params=s.params,
                                              weight=s.weight))
    units = [o.id for o in objs]
    sub = Plan.model_construct(name=plan.name, description="", room=plan.room, objects=objs,
                               rules=rules, areas=[], weights=plan.weights)
    return sub, units, unit_of


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
    from forcelayout.initial import initial_poses

    cfg = solver or SolverConfig()
    sub, units, _ = _unit_plan(plan, variants, relations)
    model = ForceModel(sub, units, relations=relations)
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
    full = ForceModel(plan, floor, relations=relations)
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
    v = int(getattr(opts, "variants", 6))
    seed = int(getattr(opts, "variant_seed", 0))
    relations = bool(getattr(opts, "relations", True))
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
                                  relations=bool(getattr(opts, "relations", True)),
                                  solver=opts.solver)
    return poses, steps, conv, {"variants": t1 - t0, "assembly": time.perf_counter() - t1}
