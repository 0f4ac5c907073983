"""Access zones: the free floor a person needs beside an object to use it.

A wardrobe is opened from its front, a desk is sat at from its front, a bed
is got into from a long side. Each such object has an **access zone** — a
rectangle as wide as the side and ``depth`` metres deep in front of it — and
:class:`AccessTerm`, a force term of the floor simulation (full strength at every
temperature, sampled with the rules every ``semantic_interval`` steps), pushes
every other solid object out of it (sideways or further out, whichever is
shorter), except objects a rule relates to the owner (the chair in front of
the desk, the nightstand beside the bed) and walkable covers. An object with
several sides (a bed's two long sides) needs one of them: the term keeps
clear the side that is least obstructed at each step, a side facing a wall
counting as obstructed.

Where an object's access comes from, first match wins:

1. the plan: ``SceneObject.access`` (``{"sides": [...], "depth": d}``, or
   ``false`` for none);
2. a rule bound to the object whose class declares ``access``
   (:class:`forcelayout.rules.Access`);
3. the object's category, by :data:`CATEGORY_ACCESS` (matched on the words
   of the category, last word first: ``kitchen_counter`` is a counter).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from forcelayout import geometry as geo
from forcelayout.bindings import Binding, compile_plan
from forcelayout.clearance import push_out
from forcelayout.plan import SceneObject
from forcelayout.rules.base import Access, StartHint, State, stacked_rows

if TYPE_CHECKING:
    from forcelayout.layout import Layout

__all__ = ["CATEGORY_ACCESS", "NO_ACCESS_WORDS", "access_of", "access_zones", "AccessZones",
           "zone_boxes", "related_pairs", "layout_zones", "ZoneState", "zone_states",
           "blocked_objects", "AccessTerm", "access_term"]

_FRONT = ("front",)
#: How far (metres) a front zone reaches past what a rule stands in front of its owner
#: with that object's back held at a wall.
_SLIVER = 0.05
_LONG_SIDES = ("left", "right")  # of a footprint deeper than wide, as a bed's is
#: Default access by category word: which sides need free floor, and how deep (metres).
#: A bed's sides are its long sides: left and right, or front and back for one wider
#: than deep (a sofa bed or a crib along a wall).
#: Doors or drawers open into the zones of wardrobes, fridges, ovens, dishwashers, washers,
#: dryers, dressers, cabinets and lockers (``Access.doors``).
CATEGORY_ACCESS: dict[str, Access] = {
    **{w: Access(_LONG_SIDES, 0.5) for w in ("bed", "beds", "bunk", "crib", "cot", "daybed",
                                             "sofabed")},
    **{w: Access(_FRONT, 0.6) for w in (
        "desk", "workbench", "counter", "countertop", "worktop", "sink", "vanity", "shower",
        "bathtub", "tub", "changing")},
    **{w: Access(_FRONT, 0.6, doors=True) for w in (
        "wardrobe", "closet", "armoire", "dishwasher", "washer", "dryer", "laundry")},
    **{w: Access(_FRONT, 0.7) for w in ("cooktop", "hob")},
    **{w: Access(_FRONT, 0.7, doors=True) for w in ("fridge", "refrigerator", "freezer",
                                                     "stove", "oven", "range")},
    **{w: Access(_FRONT, 0.5) for w in (
        "bookshelf", "bookcase", "shelves", "shelving", "sofa", "couch", "loveseat",
        "sectional", "toilet", "piano", "armchair", "recliner", "beanbag")},
    **{w: Access(_FRONT, 0.5, doors=True) for w in (
        "dresser", "drawers", "chest", "cabinet", "sideboard", "locker", "pantry", "hutch")},
}

#: Category words of things used from above or carried, that need no free side whatever
#: word before them says (a ``laundry_basket`` is no laundry machine, a ``kitchen_bin`` no
#: kitchen counter).
NO_ACCESS_WORDS = frozenset({"basket", "hamper", "bin", "can", "bag", "mat"})

_DIRS = {"front": (0.0, 1.0), "back": (0.0, -1.0), "left": (-1.0, 0.0), "right": (1.0, 0.0)}


def access_of(obj: SceneObject, bindings: Sequence[Binding] = ()) -> Access | None:
    """The access an object needs: from the plan, its rules, or its category.

    The category is looked up whole with its separators dropped (a
    ``bean_bag`` is a ``beanbag``), then word by word from the last. A
    category's long sides (a bed's) are the left and right sides of a
    footprint deeper than wide, the front and back of one wider than deep
    (a sofa bed, a crib along a wall).

    Parameters
    ----------
    obj : SceneObject
    bindings : sequence of Binding
        The bindings of the object (a rule that declares ``access`` counts).

    Returns
    -------
    Access or None
        ``None`` when the object needs no access zone.
    """
    if obj.access is False:
        return None
    if obj.access is not None:
        return Access(tuple(obj.access.sides), float(obj.access.depth), obj.access.doors)
    for b in bindings:
        if b.object == obj.id and b.rule.access is not None:
            return b.rule.access
    words = re.split(r"[^a-z0-9]+", obj.category.lower())
    # the whole category first (a 'bean_bag' is a beanbag, not a bag), then its words
    for word in ["".join(words), *reversed(words)]:
        if word in NO_ACCESS_WORDS:
            return None
        if word in CATEGORY_ACCESS:
            acc = CATEGORY_ACCESS[word]
            if acc.sides == _LONG_SIDES and obj.size[0] > obj.size[1]:
                return Access(("front", "back"), acc.depth, acc.doors)  # its long sides
            return acc
    return None


def zone_boxes(pos: np.ndarray, right: np.ndarray, front: np.ndarray, half: np.ndarray,
               direction: np.ndarray, depth: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The access zones of owners at the given poses.

    Parameters
    ----------
    pos, right, front, half : ndarray, shape (..., 2)
        Each zone's owner: centre, unit axes and half size.
    direction : ndarray, shape (..., 2)
        The zone's side in its owner's frame (``(0, 1)`` is the front).
    depth : ndarray, shape (...)
        Depth of each zone, metres.

    Returns
    -------
    centre, out, lateral, half : ndarray, shape (..., 2)
        Each zone's centre, outward and lateral unit axes, and half size
        (along ``lateral``, along ``out``).
    """
    lx, ly = direction[..., 0:1], direction[..., 1:2]
    out = lx * right + ly * front
    half = np.broadcast_to(half, np.broadcast_shapes(half.shape, out.shape))
    along = np.abs(ly[..., 0]) * half[..., 1] + np.abs(lx[..., 0]) * half[..., 0]
    wide = np.abs(ly[..., 0]) * half[..., 0] + np.abs(lx[..., 0]) * half[..., 1]
    centre = pos + out * (along + 0.5 * depth)[..., None]
    lateral = np.empty(out.shape)  # filled in place: two stacks cost more than the rest
    lateral[..., 0] = out[..., 1]
    np.negative(out[..., 0], out=lateral[..., 1])
    size = np.empty((*wide.shape, 2))
    size[..., 0] = wide
    size[..., 1] = 0.5 * depth
    return centre, out, lateral, size


class AccessTerm:
    """Pushes solid objects out of the access zones of the others.

    Not weakened by the annealing; ``annealed = True`` only means it is
    sampled with the rules (every ``SolverConfig.semantic_interval`` steps):
    the zones move slowly.

    Parameters
    ----------
    owner : ndarray of int, shape (Z,)
        Row of the object each zone belongs to.
    direction : ndarray, shape (Z, 2)
        The zone's side in its owner's frame (``(0, 1)`` is the front).
    depth : ndarray, shape (Z,)
        Depth of each zone, metres.
    exempt : ndarray of bool, shape (Z, N)
        Rows a zone does not push (its owner, the objects a rule keeps close to it, covers).
    strength : float
        Force per metre of intrusion (capped at ``1.5 * strength / 10``).
    """

    annealed = True

    def __init__(self, owner: np.ndarray, direction: np.ndarray, depth: np.ndarray,
                 exempt: np.ndarray, strength: float = 10.0):
        self.owner = np.asarray(owner, dtype=int)
        self.direction = np.asarray(direction, dtype=float).reshape(-1, 2)
        self.depth = np.asarray(depth, dtype=float)
        self.exempt = np.asarray(exempt, dtype=bool)
        self.strength = float(strength)
        # zones of one owner compete: only the least obstructed one is kept clear
        self.multi = len(np.unique(self.owner)) < len(self.owner)

    def zones(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Centres (Z, 2), outward axes (Z, 2), lateral axes (Z, 2), half sizes (Z, 2)."""
        o = self.owner
        return zone_boxes(state.pos[o], state.right[o], state.front[o], state.half[o],
                          self.direction, self.depth)

    def __call__(self, state: State, temperature: float) -> tuple[np.ndarray, np.ndarray]:
        n = state.n
        f = np.zeros((n, 2))
        if not len(self.owner):
            return f, np.zeros(n)
        centre, out, lateral, half = self.zones(state)
        rows = state.peers(self.owner)  # (Z, rows): the objects of each zone's sample
        sep = geo.obb_separation(state.pos[rows] - centre[:, None, :], lateral[:, None],
                                 out[:, None], half[:, None], state.right[rows],
                                 state.front[rows], state.half[rows])
        pen = np.where(self.exempt, 0.0, np.maximum(0.02 - sep, 0.0))
        active = pen > 0
        if self.multi:
            keep = self._least_obstructed(state, centre, out, lateral, half, pen)
            active &= keep[:, None]
        if not active.any():
            return f, np.zeros(n)
        push_out(f, state, centre, out, lateral, half, pen, active, self.strength, cols=rows)
        return f, np.zeros(n)

    def stack(self, samples: int, rows: int) -> AccessTerm:
        """The same zones for ``samples`` stacked samples of ``rows`` rows each."""
        return AccessTerm(stacked_rows(self.owner, samples, rows),
                          np.tile(self.direction, (samples, 1)), np.tile(self.depth, samples),
                          np.tile(self.exempt, (samples, 1)), self.strength)

    def _least_obstructed(self, state, centre, out, lateral, half, pen) -> np.ndarray:
        """For owners with several zones, keep the one with the least intrusion (walls too)."""
        corners = geo.corners_from_axes(centre, lateral, out, half)  # (Z, 4, 2)
        outside = (~state.room.contains(corners.reshape(-1, 2))).reshape(-1, 4).sum(1)
        cost = pen.sum(1) + outside * 1.0
        # per owner, its cheapest zone (the first of equals)
        order = np.lexsort((np.arange(len(cost)), cost, self.owner))
        first = np.ones(len(order), dtype=bool)
        first[1:] = self.owner[order[1:]] != self.owner[order[:-1]]
        keep = np.zeros(len(self.owner), dtype=bool)
        keep[order[first]] = True
        return keep


def access_zones(plan_objects: dict[str, SceneObject], ids: Sequence[str],
                 bindings: Sequence[Binding], walkable: np.ndarray, related: np.ndarray
                 ) -> AccessZones | None:
    """The access zones of rows ``ids``: what :class:`AccessTerm` pushes out of and the
    ``access`` check (:func:`forcelayout.validate.check_layout`) keeps free.

    Parameters
    ----------
    plan_objects : dict of str to SceneObject
    ids : sequence of str
        The object of each row.
    bindings : sequence of Binding
        The plan's bindings (a rule may declare access; an object a rule stands in
        front of its target and lets into its zones, the chair at the desk, deepens the
        target's front zone by its depth: the free floor a person needs starts behind
        it).
    walkable : ndarray of bool, shape (N,)
        Walkable covers: they own no zone and block none.
    related : ndarray of bool, shape (N, N)
        ``[owner, other]``: ``other`` does not block ``owner``'s zones
        (:func:`related_pairs`). Nor does what a rule keeps an owner close to and a
        rule turns it to face (``near`` and ``facing``, ``around``) block its front
        zone: the coffee table before the armchair that faces it.

    Returns
    -------
    AccessZones or None
        ``None`` when no row needs access.
    """
    owner, direction, depth, sides = [], [], [], []
    row = {oid: r for r, oid in enumerate(ids)}
    in_front: dict[str, float] = {}
    walled = {b.object for b in bindings if b.rule.start is not None
              and b.rule.start.place in ("wall", "corner")}
    backed: dict[str, bool] = {}  # whether each in front of it stands with its back at a wall
    for b in bindings:
        hint = b.rule.start
        if b.target in row and b.object in row and hint is not None \
                and hint.place == "front" and b.object in plan_objects \
                and related[row[b.target], row[b.object]]:
            in_front[b.target] = max(in_front.get(b.target, 0.0),
                                     float(plan_objects[b.object].size[1]))
            backed[b.target] = backed.get(b.target, True) and b.object in walled
    for r, oid in enumerate(ids):
        obj = plan_objects.get(oid)
        if obj is None or walkable[r]:
            continue
        acc = access_of(obj, [b for b in bindings if b.object == oid])
        if acc is None:
            continue
        for side in acc.sides:
            owner.append(r)
            direction.append(_DIRS[side])
            if side == "front" and backed.get(oid, False):
                # what stands in front of it is held at a wall behind it (the chair behind a
                # reception desk): used where it stands, with no floor free beyond it
                depth.append(in_front[oid] + _SLIVER)
            else:
                depth.append(acc.depth + (in_front.get(oid, 0.0) if side == "front" else 0.0))
            sides.append(side)
    if not owner:
        return None
    own = np.array(owner, dtype=int)
    exempt = related[own].copy() | walkable[None, :]
    exempt[np.arange(len(own)), own] = True
    # what a seat is kept close to and turned to face stands in its front zone as the
    # coffee table stands before an armchair: what it is used with, not in its way
    close = {(b.object, b.target) for b in bindings if b.rule.closeness == "close"}
    for b in bindings:
        hint = b.rule.start
        if hint is None or hint.turn != "face_target" or (b.object, b.target) not in close \
                or b.object not in row or b.target not in row:
            continue
        front = (own == row[b.object]) & np.array([sd == "front" for sd in sides])
        exempt[front, row[b.target]] = True
    return AccessZones(own, np.array(direction, dtype=float), np.array(depth, dtype=float),
                       exempt, tuple(sides))


@dataclass(frozen=True)
class AccessZones:
    """The access zones of a set of rows (see :func:`access_zones`).

    Attributes
    ----------
    owner : ndarray of int, shape (Z,)
    direction : ndarray, shape (Z, 2)
        The zone's side in its owner's frame (``(0, 1)`` is the front).
    depth : ndarray, shape (Z,)
    exempt : ndarray of bool, shape (Z, N)
        Rows that do not block the zone (its owner, the objects a rule keeps close to it, covers).
    sides : tuple of str
        The side name of each zone (``"front"``, ``"left"``, ...).
    """

    owner: np.ndarray
    direction: np.ndarray
    depth: np.ndarray
    exempt: np.ndarray
    sides: tuple[str, ...]


def related_pairs(ids: Sequence[str], bindings: Sequence[Binding],
                  plan_objects: dict[str, SceneObject] | None = None) -> np.ndarray:
    """Which rows may stand in which rows' access zones: ``[owner, other]``.

    A rule that keeps its object close to its target (``closeness="close"``:
    ``next_to``, ``near``, ``in_front_of``, ``around``, ...) lets the object
    stand in the target's zones (the chair at the desk, the nightstand at the
    head of the bed, the run of counters next to a corner unit), not the target
    in the object's. An object that a rule stands in front of or behind its
    target (``in_front_of``, ``behind``: its start place) and that needs a zone
    of its own (``access_of``: from the plan or its category) is used where it
    stands, and keeps out of the target's zones all the same: a kitchen island
    in front of a counter stands beyond the counter's zone. Where doors or
    drawers open into the target's zones (``Access.doors``: a wardrobe, a
    fridge), only a rule that stands its object beside the target (start place
    ``beside``, ``left``, ``right``: ``next_to``, the next unit of a run) lets
    it in: a bench ``in_front_of`` a wardrobe or a basket ``near`` it keeps
    out. A rule that keeps no closeness (``facing``, ``aligned_with``) lets
    neither: a dresser that a bed faces does not block the bed's side.

    Parameters
    ----------
    ids : sequence of str
        The object of each row.
    bindings : sequence of Binding
    plan_objects : dict of str to SceneObject, optional
        The plan's objects, to tell which need a zone of their own and which
        open doors into theirs; without them every close rule lets its object
        in.

    Returns
    -------
    ndarray of bool, shape (N, N)
    """
    row = {oid: k for k, oid in enumerate(ids)}
    related = np.zeros((len(ids), len(ids)), dtype=bool)
    doors: dict[str, bool] = {}  # per target: whether doors open into its zones
    for b in bindings:
        if b.object not in row or b.target not in row or b.rule.closeness != "close":
            continue
        hint = b.rule.start
        if plan_objects is not None and b.target in plan_objects:
            if b.target not in doors:
                acc = access_of(plan_objects[b.target],
                                [c for c in bindings if c.object == b.target])
                doors[b.target] = acc is not None and acc.doors
            if doors[b.target] and (hint is None or hint.place not in StartHint.SIDE_PLACES):
                continue  # not in front of its doors, whichever rule keeps it close
        if plan_objects is not None and b.object in plan_objects and hint is not None \
                and hint.place in ("front", "back") \
                and access_of(plan_objects[b.object]) is not None:
            continue  # used itself, from the plan or its category (not the room a rule
            # asks of it there: a chair around a desk, pulled out, is still at the desk)
        related[row[b.target], row[b.object]] = True
    return related


def layout_zones(layout: Layout) -> list[tuple[str, str, np.ndarray]]:
    """The access zones of a layout's floor objects at their poses.

    The zones the ``access`` check keeps free (:func:`access_zones`): a
    rectangle in front of each side an object is used from, as wide as the
    side and as deep as its access asks (deeper by an object a rule stands
    in front of it, the chair at the desk).

    Parameters
    ----------
    layout : Layout

    Returns
    -------
    list of (str, str, ndarray)
        Per zone: the object's id, the side (``"front"``, ``"left"``, ...) and
        the zone's corners, shape (4, 2), metres.

    Examples
    --------
    >>> import forcelayout as fl
    >>> from forcelayout.access import layout_zones
    >>> lay = fl.solve(fl.examples.load_example("bedroom"), seed=0)
    >>> sorted({oid for oid, _, _ in layout_zones(lay)})
    ['bed', 'desk', 'dresser', 'wardrobe']
    """
    plan = layout.plan
    ids = [oid for oid in layout.ids() if layout.poses[oid].surface == "floor"]
    objects = {o.id: o for o in plan.objects}
    bindings = compile_plan(plan).bindings
    walkable = np.array([objects[oid].is_walkable for oid in ids], dtype=bool)
    zones = access_zones(objects, ids, bindings, walkable,
                         related_pairs(ids, bindings, objects))
    if zones is None:
        return []
    o = zones.owner
    poses = [layout.poses[ids[r]] for r in o.tolist()]
    yaw = np.array([p.yaw for p in poses], dtype=float)
    pos = np.array([[p.x, p.y] for p in poses], dtype=float)
    half = 0.5 * np.array([objects[ids[r]].size[:2] for r in o.tolist()], dtype=float)
    centre, out, lateral, zh = zone_boxes(pos, geo.right_vectors(yaw), geo.front_vectors(yaw),
                                          half, zones.direction, zones.depth)
    corners = geo.corners_from_axes(centre, lateral, out, zh)
    return [(ids[r], side, c) for r, side, c in zip(o.tolist(), zones.sides, corners,
                                                    strict=True)]


@dataclass(frozen=True)
class ZoneState:
    """The ``access`` check's verdict on one access zone (see :func:`zone_states`).

    Attributes
    ----------
    object : str
        The zone's owner.
    side : str
        ``"front"``, ``"left"``, ...
    depth : float
        Metres.
    corners : ndarray, shape (4, 2)
        The zone's rectangle, metres (it may reach past a wall).
    free : bool
        Whether some stretch of it ``access_width`` wide (the whole side if
        narrower) has at most ``max_access_overlap`` m², and at most a third of its
        area, covered or off the floor.
    covered_by : list of (str, float)
        What covers it, largest first: an object's id or ``"wall"`` (the part
        off the floor), with the m² covered.
    """

    object: str
    side: str
    depth: float
    corners: np.ndarray
    free: bool
    covered_by: list[tuple[str, float]]


def zone_states(layout: Layout, *, max_access_overlap: float = 0.1, access_width: float = 0.6
                ) -> list[ZoneState]:
    """Each access zone of a layout's floor objects, free or blocked, as the check judges it.

    The ``access`` check (``check_layout(..., access_clearance=True)``) fails
    an object all of whose zones are blocked; this gives the verdict on every
    zone, so a picture, a report or a benchmark can say which side is free
    and what covers the others.

    Parameters
    ----------
    layout : Layout
    max_access_overlap, access_width : float
        As for :func:`forcelayout.validate.check_layout`.

    Returns
    -------
    list of ZoneState
        In the order of :func:`layout_zones`.

    Examples
    --------
    >>> import forcelayout as fl
    >>> from forcelayout.access import zone_states
    >>> lay = fl.solve(fl.examples.load_example("bedroom"), seed=0)
    >>> [(z.object, z.side) for z in zone_states(lay) if z.object == "bed"]
    [('bed', 'left'), ('bed', 'right')]
    """
    from forcelayout.validate.checks import zone_states as judge

    return [ZoneState(*z) for z in judge(layout, max_access_overlap=max_access_overlap,
                                         access_width=access_width)]


def blocked_objects(layout: Layout, *, max_access_overlap: float = 0.1,
                    access_width: float = 0.6) -> dict[str, list[tuple[str, float]]]:
    """The objects of a layout with no access zone free, each with what covers its zones:
    the objects the ``access`` check fails.

    Parameters
    ----------
    layout : Layout
    max_access_overlap, access_width : float
        As for :func:`forcelayout.validate.check_layout`.

    Returns
    -------
    dict of str to list of (str, float)
        Per such object, in the order of :func:`layout_zones`, what covers each of its
        zones (an object's id or ``"wall"``, m²; each zone's largest first, as
        :attr:`ZoneState.covered_by`).

    Examples
    --------
    >>> import forcelayout as fl
    >>> from forcelayout.access import blocked_objects
    >>> lay = fl.solve(fl.examples.load_example("bedroom"), seed=0)
    >>> blocked_objects(lay)
    {}
    """
    zones = zone_states(layout, max_access_overlap=max_access_overlap,
                        access_width=access_width)
    free = {z.object for z in zones if z.free}
    out: dict[str, list[tuple[str, float]]] = {}
    for z in zones:
        if z.object not in free:
            out.setdefault(z.object, []).extend(z.covered_by)
    return out


def access_term(plan_objects: dict[str, SceneObject], ids: Sequence[str],
                bindings: Sequence[Binding], walkable: np.ndarray,
                related: np.ndarray) -> AccessTerm | None:
    """The access term of a simulation's rows, or ``None`` when no row needs access."""
    z = access_zones(plan_objects, ids, bindings, walkable, related)
    return None if z is None else AccessTerm(z.owner, z.direction, z.depth, z.exempt)
