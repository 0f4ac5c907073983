"""The :class:`Rule` base class and the numpy state every rule receives.

Conventions (stated once, used everywhere): metres, radians, counter-clockwise
angles, room coordinates. An object's size is ``[width, depth, height]`` along
its local x, local y and z; local +y is its *front*. ``yaw = 0`` means the
front faces world +y, so the front direction is ``(-sin yaw, cos yaw)`` and the
local +x ("right-hand side" seen from behind the object) is
``(cos yaw, sin yaw)``.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict

from forcelayout import geometry as geo

if TYPE_CHECKING:
    from forcelayout.geometry import RoomGeometry

__all__ = [
    "Rule",
    "State",
    "ParamArrays",
    "RuleKind",
    "TargetNeed",
    "Surface",
    "StartHint",
    "Access",
    "Closeness",
    "stacked_rows",
]

#: What a rule relates, for listings: the room ("unary"), a target object ("binary"),
#: or a surface off the floor ("surface"). Derived from :attr:`Rule.target` and
#: :attr:`Rule.surface`; a class may still set it alone (see :class:`Rule`).
RuleKind = Literal["unary", "binary", "surface"]
#: Whether a binding names a target object: never, always, or when the plan wants one.
TargetNeed = Literal["none", "required", "optional"]
#: Where a rule places its object: on the floor, on its target's top, on a wall, on the ceiling.
Surface = Literal["floor", "top", "wall", "ceiling"]
#: Whether a rule keeps its object close to its target or far from it.
Closeness = Literal["close", "far"]


@dataclass(frozen=True)
class StartHint:
    """How a rule's objects start before the simulation (see :mod:`forcelayout.initial`).

    Start poses are random but lean towards the rules, so a run spends its
    steps on settling rather than on crossing the room. A rule says what its
    binding wants of the start; the engine combines the hints of all rules on
    an object.

    Attributes
    ----------
    place : str, optional
        Where the object starts. Relative to the room: ``"wall"`` (back
        against a wall, front into the room), ``"corner"`` (tucked into a
        convex corner), ``"middle"`` (near the floor's centroid),
        ``"window"`` / ``"door"`` (near an opening; with ``"wall"``, on a
        wall near it). Relative to the target: ``"beside"`` (either side),
        ``"left"``, ``"right"`` (that side; these three with the backs level,
        as a nightstand at the head of a bed), ``"front"``, ``"back"`` (its
        side of the target),
        ``"all_round"`` (any side: the target keeps room on every side for it),
        ``"beneath"`` (centred under the target: a walkable cover).
    turn : str, optional
        ``"face_target"`` turns the object's front towards its target;
        ``"target_heading"`` gives it the target's heading; ``"face_window"``
        / ``"face_door"`` turn its front towards the nearest window / door
        (for an object not backed against a wall, and only where no rule
        turns it towards a target).
    parent : int, optional
        The object starts near its target (the target is its *parent*); when
        several rules name different targets, the lowest ``parent`` wins
        (0 is the strongest bond).
    clear_wall_above_target : bool
        The rule hangs its object on the wall above the target (a picture
        above a bed): the target starts where that wall has no door or window.
    reach : str, optional
        The name of the rule's parameter that bounds how far from where it
        starts the object's centre may be; start candidates then spread
        evenly over that region, not only close around its middle. With
        ``place="window"`` or ``"door"``: metres from the opening's centre
        (``"distance"`` of ``near_door``); with ``place="middle"``: a fraction
        of the room's extent from the centroid, per axis (``"fraction"`` of
        ``in_middle``); with ``place="front"`` or ``"back"``: the largest
        footprint gap to the target, metres (``"distance"`` of ``behind``):
        the start's gap stays within it; with no ``place`` and a ``parent``
        (the object starts all round its target): the largest footprint gap
        to that target, metres (``"distance"`` of ``near``): the start's gap
        spreads over it (a beanbag anywhere up to 1.5 m from the TV stand,
        not only beside it).
    least : str, optional
        The name of the rule's parameter that gives the smallest footprint
        gap to the target, metres (``"distance"`` of ``far_from``): an
        object that starts in front of or behind that target (another rule's
        ``place="front"`` or ``"back"``) starts at least that far from it (the
        front row of seats a viewing distance from the screen).
    which : str, optional
        With ``place="window"`` or ``"door"``: the name of the rule's
        parameter that picks one opening of that kind by its index in the
        plan's ``room.windows`` / ``room.doors`` (``"door"`` of
        ``near_door``); -1 there means any, the nearest. Starts are then
        drawn near that opening only, and a plan whose index names no
        opening is refused.
    cone : str, optional
        With ``turn="face_target"``: the name of the rule's parameter that
        gives the largest angle (degrees) between the object's front and its
        target (``"max_angle"`` of ``facing``). An object that starts on the
        wall across the room from its target then starts anywhere its rule
        allows along that wall, not only straight across (a stove facing the
        sink of a galley kitchen from within its cone).
    """

    place: str | None = None
    turn: str | None = None
    parent: int | None = None
    clear_wall_above_target: bool = False
    reach: str | None = None
    which: str | None = None
    cone: str | None = None
    least: str | None = None

    PLACES: ClassVar[frozenset[str]] = frozenset(
        {"wall", "corner", "middle", "window", "door", "beside", "left", "right", "front",
         "back", "all_round", "beneath"})
    #: The places beside the target (its backs level with the target's): where a rule
    #: stands its object beside the target rather than in front of or behind it.
    SIDE_PLACES: ClassVar[frozenset[str]] = frozenset({"beside", "left", "right"})
    #: The places ``reach`` may bound.
    REACH_PLACES: ClassVar[frozenset[str]] = frozenset({"window", "door", "middle", "front",
                                                        "back"})
    #: The turns towards the room's openings, and which openings (``RoomGeometry`` fields).
    OPENING_TURNS: ClassVar[dict[str, str]] = {"face_window": "windows", "face_door": "doors"}
    TURNS: ClassVar[frozenset[str]] = frozenset({"face_target", "target_heading",
                                                 *OPENING_TURNS})

    def __post_init__(self) -> None:
        if self.place is not None and self.place not in self.PLACES:
            raise ValueError(f"StartHint.place {self.place!r} is not one of {sorted(self.PLACES)}")
        if self.turn is not None and self.turn not in self.TURNS:
            raise ValueError(f"StartHint.turn {self.turn!r} is not one of {sorted(self.TURNS)}")
        if self.reach is not None and self.place not in self.REACH_PLACES \
                and not (self.place is None and self.parent is not None):
            raise ValueError("StartHint.reach bounds a start near an opening, the middle or "
                             "its target: give it with place='window', 'door', 'middle', "
                             "'front' or 'back', or with parent=... and no place (all round "
                             f"the target), not place={self.place!r}")
        if self.cone is not None and self.turn != "face_target":
            raise ValueError("StartHint.cone spreads a start over the angle its target may "
                             "lie at: give it with turn='face_target', not "
                             f"turn={self.turn!r}")
        if self.which is not None and self.place not in ("window", "door"):
            raise ValueError("StartHint.which picks one window or door: give it with "
                             f"place='window' or 'door', not place={self.place!r}")


@dataclass(frozen=True)
class Access:
    """Floor a person needs beside an object to use it (kept clear by the engine).

    Attributes
    ----------
    sides : tuple of str
        Sides of the object's footprint that need free floor, any of
        ``"front"``, ``"back"``, ``"left"``, ``"right"``; a person uses one
        of them (e.g. either long side of a bed).
    depth : float
        Depth of the free floor in front of that side, metres.
    doors : bool
        Doors or drawers open into the free floor (a wardrobe, a fridge): only an
        object a rule stands beside the owner (``next_to``: the next unit of a run)
        may stand in it; one a rule puts in front of it or near it keeps out (a bench
        ``in_front_of`` a wardrobe, facing it, stands beyond its doors).
    """

    sides: tuple[str, ...] = ("front",)
    depth: float = 0.6
    doors: bool = False

    SIDES: ClassVar[frozenset[str]] = frozenset({"front", "back", "left", "right"})

    def __post_init__(self) -> None:
        bad = set(self.sides) - self.SIDES
        if bad or not self.sides:
            raise ValueError(f"Access.sides must name some of {sorted(self.SIDES)}, got "
                             f"{self.sides!r}")
        if not self.depth > 0:
            raise ValueError(f"Access.depth must be > 0 metres, got {self.depth!r}")


@dataclass
class State:
    """Poses and sizes of the objects in one simulation, as numpy arrays.

    Rules read it; only the solver writes it. Arrays are indexed by object
    number ``0..N-1`` in the order of :attr:`ids`.

    Attributes
    ----------
    pos : ndarray, shape (N, 2)
        Footprint centres in room coordinates, metres.
    yaw : ndarray, shape (N,)
        Heading, radians CCW; 0 means the front faces +y.
    size : ndarray, shape (N, 3)
        ``[width, depth, height]`` in metres.
    room : RoomGeometry
        Walls, openings and the floor polygon as arrays.
    ids : tuple of str
        Object ids, one per row.
    z : ndarray, shape (N,), optional
        Height of each object's bottom above the floor, metres (finished
        layouts only; ``None`` in floor simulations, where all are 0).
    surfaces : tuple of str, optional
        Where each object rests (``"floor"``, a parent id, ``"wall:<i>"``,
        ``"ceiling"``); finished layouts only.
    samples : int
        Number of samples stacked in the arrays (the batched engine): sample
        ``b`` takes the ``rows`` consecutive rows from ``b * rows``. Objects
        of different samples never interact: pairwise terms use index pairs
        from one sample (the bindings' rows), :meth:`separation`,
        :meth:`gap_estimate`, :meth:`gap` and :meth:`peers`. The all-pairs
        matrices :attr:`separations` and :attr:`gap_estimates` exist for a
        single sample only.
    """

    pos: np.ndarray
    yaw: np.ndarray
    size: np.ndarray
    room: RoomGeometry
    ids: tuple[str, ...] = ()
    z: np.ndarray | None = None
    surfaces: tuple[str, ...] | None = None
    samples: int = 1
    _cache: dict[str, np.ndarray] = field(default_factory=dict, repr=False, compare=False)

    @property
    def n(self) -> int:
        """Number of objects."""
        return int(self.pos.shape[0])

    @property
    def half(self) -> np.ndarray:
        """Half extents ``(width/2, depth/2)``, shape (N, 2), metres."""
        return self.size[:, :2] * 0.5

    def _axes(self) -> None:
        c, s = np.cos(self.yaw), np.sin(self.yaw)
        f = np.empty((c.shape[0], 2))
        f[:, 0] = -s
        f[:, 1] = c
        r = np.empty_like(f)
        r[:, 0] = c
        r[:, 1] = s
        self._cache["front"] = f
        self._cache["right"] = r

    @property
    def front(self) -> np.ndarray:
        """Unit front directions (local +y in the world), shape (N, 2)."""
        if "front" not in self._cache:
            self._axes()
        return self._cache["front"]

    @property
    def right(self) -> np.ndarray:
        """Unit local +x directions in the world, shape (N, 2)."""
        if "right" not in self._cache:
            self._axes()
        return self._cache["right"]

    @property
    def wall_distance(self) -> np.ndarray:
        """Distance from each footprint centre to each wall segment, shape (N, W), metres."""
        d = self._cache.get("wall_distance")
        if d is None:
            room = self.room
            s = self.pos @ room.normal.T - room.normal_offset  # along the inward normal
            t = self.pos @ room.tangent.T - room.tangent_offset  # along the wall
            beyond = np.maximum(np.maximum(-t, t - room.length), 0.0)
            d = self._cache["wall_distance"] = np.sqrt(s * s + beyond * beyond)
        return d

    @property
    def rows(self) -> int:
        """Rows per sample (``n // samples``)."""
        return self.n // self.samples

    def peers(self, i: np.ndarray) -> np.ndarray:
        """Every row of the sample of each row ``i``, shape (len(i), rows).

        For one sample, each line is ``0..n-1``: the objects a row's
        line of sight or access zone may meet.
        """
        m = self.rows
        i = np.asarray(i, dtype=int)
        return (i // m * m)[:, None] + np.arange(m)

    def sample(self, b: int) -> State:
        """The state of stacked sample ``b`` alone (a view of its rows)."""
        if self.samples == 1:
            return self
        m = self.rows
        rows = slice(b * m, (b + 1) * m)

        def own(names: tuple[str, ...] | None) -> tuple[str, ...] | None:
            # names given per stacked row are sliced; names of one sample's rows are shared
            return names[rows] if names is not None and len(names) == self.n else names

        return State(self.pos[rows], self.yaw[rows], self.size[rows], self.room, own(self.ids),
                     None if self.z is None else self.z[rows], own(self.surfaces))

    def _separations(self) -> np.ndarray:
        """Blocks of (rows + doors)^2 separations, shape (samples, M, M)."""
        m = self._cache.get("separations")
        if m is None:
            k, r = self.samples, self.rows
            pos = self.pos.reshape(k, r, 2)
            right, front = self.right.reshape(k, r, 2), self.front.reshape(k, r, 2)
            half = self.half.reshape(k, r, 2)
            dc, dr, df, dh = self.room.door_zones
            if len(dc):
                def more(a: np.ndarray, z: np.ndarray) -> np.ndarray:
                    return np.concatenate([a, np.broadcast_to(z, (k, *z.shape))], axis=1)

                pos, right, front, half = more(pos, dc), more(right, dr), more(front, df), \
                    more(half, dh)
            m, g1, g2 = geo.separation_matrix(pos, right, front, half, with_axis_gaps=True)
            self._cache["separations"] = m
            self._cache["axis_gaps"] = (g1, g2)
        return m

    def _one_sample(self, name: str) -> None:
        if self.samples != 1:
            raise ValueError(f"State.{name} holds one sample's pairs; this state stacks "
                             f"{self.samples} samples: use separation(i, j), "
                             "gap_estimate(i, j) or peers(i)")

    def _estimates(self) -> np.ndarray:
        e = self._cache.get("gap_estimates")
        if e is None:
            self._separations()
            r = self.rows
            g1, g2 = self._cache["axis_gaps"]
            g1, g2 = g1[:, :r, :r], g2[:, :r, :r]
            p1, p2 = np.maximum(g1, 0.0), np.maximum(g2, 0.0)
            e = np.where((g1 > 0) & (g2 > 0), np.sqrt(p1 * p1 + p2 * p2), np.maximum(g1, g2))
            self._cache["gap_estimates"] = e
        return e

    @property
    def gap_estimates(self) -> np.ndarray:
        """Fast estimate of the footprint gap from each object to each other, shape (N, N).

        ``[i, j]`` is the gap between footprint i and the bounding box of
        footprint j in i's frame (Euclidean where they are apart on both of
        i's axes): exact for parallel footprints, the usual case once objects
        settle at cardinal angles, and never more than the true gap.
        Negative values are overlap depths. One sample only (see
        :meth:`gap_estimate`).
        """
        self._one_sample("gap_estimates")
        return self._estimates()[0]

    def gap_estimate(self, i: np.ndarray, j: np.ndarray) -> np.ndarray:
        """:attr:`gap_estimates` ``[i, j]`` for rows of the same sample, any stack."""
        r = self.rows
        b = i // r
        return self._estimates()[b, i - b * r, j - b * r]

    @property
    def separations(self) -> np.ndarray:
        """Signed separating-axis clearance between all footprints, shape (N, N), metres.

        A cheap lower bound on :meth:`gap` (exact when two footprints are
        separated along one of their axes, the usual case); negative values
        are overlap depths; the diagonal is meaningless. Use it in
        :meth:`Rule.force`, and :meth:`gap` in :meth:`Rule.satisfied`. One
        sample only (see :meth:`separation`).
        """
        self._one_sample("separations")
        return self._separations()[0, : self.n, : self.n]

    @property
    def sample_separations(self) -> np.ndarray:
        """:attr:`separations` of each stacked sample's own pairs, shape (samples, rows, rows).

        The ``[b]`` block is :attr:`separations` of :meth:`sample` ``(b)``.
        """
        r = self.rows
        return self._separations()[:, :r, :r]

    @property
    def door_separations(self) -> np.ndarray:
        """Clearance between each footprint and each door's swing square, shape (N, D)."""
        r = self.rows
        m = self._separations()
        return m[:, :r, r:].reshape(self.n, m.shape[2] - r)

    def separation(self, i: np.ndarray, j: np.ndarray) -> np.ndarray:
        """Clearance between footprints ``i`` and ``j`` (see :attr:`separations`), metres.

        ``i`` and ``j`` are rows of the same sample.
        """
        r = self.rows
        b = i // r
        return self._separations()[b, i - b * r, j - b * r]

    @property
    def corners(self) -> np.ndarray:
        """Footprint corners, shape (N, 4, 2), CCW from back-left."""
        c = self._cache.get("corners")
        if c is None:
            c = self._cache["corners"] = geo.corners_from_axes(self.pos, self.right, self.front,
                                                               self.half)
        return c

    def gap(self, i: np.ndarray, j: np.ndarray) -> np.ndarray:
        """Clearance between footprints ``i`` and ``j`` in metres (0 if touching).

        Exact distance between the two oriented rectangles, negative values
        are clipped to 0. Vectorised over index arrays of equal shape.
        """
        return geo.obb_gap(self.pos[j] - self.pos[i], self.right[i], self.front[i],
                           self.half[i], self.right[j], self.front[j], self.half[j])

    def invalidate(self) -> None:
        """Drop cached derived arrays after ``pos`` or ``yaw`` changed."""
        self._cache.clear()


def stacked_rows(index: np.ndarray, samples: int, rows: int) -> np.ndarray:
    """Row indices of one sample, repeated for each of ``samples`` stacked samples.

    The stacking convention of :class:`State`: sample ``b`` takes rows
    ``b * rows .. (b + 1) * rows - 1``, so ``index`` (shape (K,)) becomes
    ``index``, ``index + rows``, ... (shape (samples * K,)).

    Examples
    --------
    >>> stacked_rows(np.array([0, 2]), 3, 4).tolist()
    [0, 2, 4, 6, 8, 10]
    """
    index = np.asarray(index, dtype=int)
    return np.tile(index, samples) + np.repeat(np.arange(samples) * rows, len(index))


class ParamArrays:
    """Rule parameters of many bindings, one numpy array per field.

    ``p.distance`` is an array of shape (B,) holding each binding's value, so
    rule code written for one binding broadcasts over all of them.
    ``p.weight`` holds the per-binding weight.
    """

    def __init__(self, fields: dict[str, np.ndarray], weight: np.ndarray):
        self._fields = fields
        self.weight = weight

    def __getattr__(self, name: str) -> np.ndarray:
        try:
            return self._fields[name]
        except KeyError:
            raise AttributeError(f"rule has no parameter {name!r}") from None

    def __len__(self) -> int:
        return int(self.weight.shape[0])

    @classmethod
    def from_models(cls, params: list[BaseModel], weight: np.ndarray) -> ParamArrays:
        """Stack validated ``Params`` models of many bindings into arrays."""
        fields: dict[str, np.ndarray] = {}
        if params:
            for name in type(params[0]).model_fields:
                values = [getattr(q, name) for q in params]
                if all(isinstance(v, bool) for v in values):
                    fields[name] = np.array(values, dtype=bool)
                elif all(isinstance(v, int | float) for v in values):
                    fields[name] = np.array(values, dtype=float)
                else:
                    fields[name] = np.array(values, dtype=object)
        return cls(fields, np.asarray(weight, dtype=float))


class Rule:
    """Base class of placement rules: one small class per rule.

    A rule turns its bindings (object ``i``, optional target ``j``, params)
    into forces and torques on the objects, vectorised over all bindings of
    the rule at once, and judges whether a finished layout meets it. The same
    class both pulls and judges, so the simulation and the report never
    disagree about what the rule means.

    Subclass attributes
    -------------------
    A rule declares on its class everything the engine needs to know about it;
    start poses, the scene graph, the surface stage, plan validation, the
    metrics and the testing strategies read these attributes and never match
    rule names.

    name : str
        Registry name, set by :func:`forcelayout.rules.register`.
    target : {"none", "required", "optional"}
        Whether a binding names a target object (``"required"`` for rules
        between two objects such as ``next_to``).
    surface : {"floor", "top", "wall", "ceiling"}
        Where the rule places its object. ``"floor"`` rules push and pull in
        the floor simulation; the others take the object off the floor: on
        its target's top, on a wall (above the target if one is given), or
        on the ceiling (over the target if one is given). An object is bound
        by at most one off-floor rule.
    kind : {"unary", "binary", "surface"}
        Derived from ``target`` and ``surface`` (for listings). A class that
        sets only ``kind = "binary"`` gets ``target = "required"``.
    bond : bool
        Whether a binding makes its target the object's *parent* in the
        scene graph (:func:`forcelayout.hierarchy.scene_graph`) when the plan
        does not say (``RuleSpec.bond``). Floor rules bond only objects of
        one functional area.
    start : StartHint, optional
        How start poses lean towards the rule (:class:`StartHint`).
    access : Access, optional
        Free floor the bound object needs to be used (:class:`Access`).
    hard : bool
        Weight class. A hard placement rule (``at_wall``, ``in_corner``)
        fixes the object's heading: on an object bound by one, the torques
        of the soft rules are scaled down
        (:data:`forcelayout.forces.SOFT_TORQUE_ON_HARD`) so a relation such
        as ``facing`` slides the object rather than turning its back off the
        wall.
    relation : bool
        Whether the relational diversity metric
        (:func:`forcelayout.metrics.relation_triples`) counts the rule.
    positional : bool
        Whether the rule places its object at one side of, around or under
        its target (``in_front_of``, ``facing``, ...): plan findings
        (:mod:`forcelayout.sanity`) flag an object bound by one positional
        rule to more than two targets.
    closeness : {None, "close", "far"}
        Whether a binding keeps its object close to its target (``next_to``)
        or far from it (``far_from``). An object both close to and far from
        one target is a contradiction: plan findings report it and
        :func:`forcelayout.autofix.autofix` drops the ``"far"`` rule.
    opposite : str, optional
        The registered rule that contradicts this one on the same object and
        target (``in_front_of`` and ``behind``; ``at_wall`` and
        ``in_middle``). The relation is symmetric: declaring it on one of
        the two rules is enough.
    aliases : tuple of str
        Near-miss names that mean this rule (``"beside"`` for ``next_to``),
        in snake case; :func:`forcelayout.autofix.autofix` reads an unknown
        rule name as the rule declaring it (a name two rules declare is
        ambiguous and left alone). Not inherited: a subclass registered
        under another name declares its own.
    feature : str, optional
        The feature of the room the rule relates its object to: ``"door"``,
        ``"window"``, ``"wall"``, ``"corner"`` (a word a plan may use as a
        target by mistake).
    specialises : tuple of str
        Target rules that, aimed at the room's ``feature`` rather than at an
        object (``near`` with target ``"window"``), mean this rule
        (``near_window``); :func:`forcelayout.autofix.autofix` rewrites them.
        Needs ``feature``.
    fallback : str, optional
        The rule a binding becomes when the room cannot hold every binding
        of this one. Rules whose ``start.place`` is ``"corner"`` are limited
        by the floor's convex corners; the autofix turns the extra ones into
        their ``fallback`` (``in_corner`` -> ``at_wall``).
    weight : float
        Default strength (dimensionless multiplier on the force). The paper's
        order is repulsion > hard placement (``at_wall``) > soft relations
        (``near``); plans may override it per rule or per binding.
    reaction : float
        Fraction of the force on ``i`` applied, reversed, to the target ``j``
        (binary rules only). 0 keeps the target still, 0.5 splits the pull.
    batched : bool
        Whether :meth:`force` and :meth:`satisfied` may be given a state that
        stacks many samples (``State.samples > 1``, the batched engine, which
        also judges start candidates of many samples at once): they relate rows only
        through ``i`` and ``j`` and the state's per-sample methods
        (``separation``, ``gap_estimate``, ``gap``, ``peers``), never through
        the all-pairs matrices or every row at once. The built-in rules are
        batched. A rule that is not (the default, and any subclass that
        overrides ``force`` without saying so) is called once per sample
        with that sample's state, which is correct and slower.
    Params : pydantic model
        Parameters with defaults and units in their descriptions.

    Methods to override
    -------------------
    force(state, i, j, p) -> (F, tau)
        ``F`` shape (B, 2) in newtons-per-weight on object ``i``, ``tau``
        shape (B,) torque on ``i`` (CCW positive). Called every step with the
        annealing temperature already folded into ``p.weight``.
    satisfied(state, i, j, p) -> ndarray of bool, shape (B,)
        Whether each binding is met in the given (finished) state.
    """

    name: ClassVar[str] = ""
    target: ClassVar[TargetNeed] = "none"
    surface: ClassVar[Surface] = "floor"
    kind: ClassVar[RuleKind] = "unary"
    bond: ClassVar[bool] = False
    start: ClassVar[StartHint | None] = None
    access: ClassVar[Access | None] = None
    hard: ClassVar[bool] = False
    relation: ClassVar[bool] = False
    positional: ClassVar[bool] = False
    closeness: ClassVar[Closeness | None] = None
    opposite: ClassVar[str | None] = None
    aliases: ClassVar[tuple[str, ...]] = ()
    feature: ClassVar[str | None] = None
    specialises: ClassVar[tuple[str, ...]] = ()
    fallback: ClassVar[str | None] = None
    weight: ClassVar[float] = 1.0
    reaction: ClassVar[float] = 0.0
    batched: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        own = cls.__dict__
        if "kind" in own and "target" not in own and "surface" not in own:
            if own["kind"] == "binary":  # the first release's spelling of a target rule
                cls.target = "required"
            elif own["kind"] == "unary":
                cls.target = "none"
            elif own["kind"] == "surface":
                raise TypeError(f"{cls.__qualname__}: say where a surface rule places its "
                                "object with surface = 'top', 'wall' or 'ceiling'")
        if cls.target not in ("none", "required", "optional"):
            raise TypeError(f"{cls.__qualname__}.target must be 'none', 'required' or "
                            f"'optional', got {cls.target!r}")
        if cls.surface not in ("floor", "top", "wall", "ceiling"):
            raise TypeError(f"{cls.__qualname__}.surface must be 'floor', 'top', 'wall' or "
                            f"'ceiling', got {cls.surface!r}")
        if cls.surface == "top" and cls.target != "required":
            raise TypeError(f"{cls.__qualname__}: a rule that places its object on a top "
                            "needs target = 'required' (the object it rests on)")
        if cls.start is not None and not isinstance(cls.start, StartHint):
            raise TypeError(f"{cls.__qualname__}.start must be a StartHint or None")
        for attr in ("reach", "which", "cone", "least"):
            named = getattr(cls.start, attr) if cls.start is not None else None
            if named is not None and named not in cls.Params.model_fields:
                raise TypeError(f"{cls.__qualname__}.start.{attr} names {named!r}, which is "
                                f"not a parameter of the rule (its Params: "
                                f"{sorted(cls.Params.model_fields)})")
        if cls.access is not None and not isinstance(cls.access, Access):
            raise TypeError(f"{cls.__qualname__}.access must be an Access or None")
        if cls.closeness not in (None, "close", "far"):
            raise TypeError(f"{cls.__qualname__}.closeness must be None, 'close' or 'far', got "
                            f"{cls.closeness!r}")
        for attr in ("opposite", "feature", "fallback"):
            value = getattr(cls, attr)
            if value is not None and not (isinstance(value, str) and value.isidentifier()):
                raise TypeError(f"{cls.__qualname__}.{attr} must be None or a name such as "
                                f"'behind', got {value!r}")
        if not cls.__module__.startswith("forcelayout."):  # a plugin: its results are checked
            for method in ("force", "satisfied"):
                fn = own.get(method)
                if callable(fn) and not hasattr(fn, "__wrapped__"):
                    setattr(cls, method, _checked(method, fn))
        cls.aliases = own.get("aliases", ())  # names are not inherited
        if "force" in own and "batched" not in own:  # a new force says for itself
            cls.batched = False
        for attr in ("aliases", "specialises"):
            value = getattr(cls, attr)
            if isinstance(value, str) or not all(isinstance(v, str) and v.isidentifier()
                                                 for v in value):
                raise TypeError(f"{cls.__qualname__}.{attr} must be a tuple of names such as "
                                f"('beside',), got {value!r}")
            setattr(cls, attr, tuple(value))
        if cls.specialises and cls.feature is None:
            raise TypeError(f"{cls.__qualname__}: specialises needs feature (the room feature "
                            "a target rule aimed at it means this rule for)")
        cls.kind = ("surface" if cls.surface != "floor"
                    else "binary" if cls.target == "required" else "unary")

    @classmethod
    def takes_target(cls) -> bool:
        """Whether a binding may name a target object."""
        return cls.target != "none"

    class Params(BaseModel):
        """No parameters."""

        model_config = ConfigDict(extra="forbid", frozen=True)

    def force(
        self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays
    ) -> tuple[np.ndarray, np.ndarray]:
        """Force (B, 2) and torque (B,) on each bound object ``i``."""
        raise NotImplementedError(f"rule {self.name!r} does not define force()")

    def satisfied(
        self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays
    ) -> np.ndarray:
        """Whether each binding is met, shape (B,) of bool."""
        raise NotImplementedError(f"rule {self.name!r} does not define satisfied()")

    @classmethod
    def summary(cls) -> str:
        """The rule docstring's summary: its first paragraph, on one line (a summary that
        wraps, as ``near_door``'s, is not cut at the wrap)."""
        doc = (cls.__doc__ or "").strip()
        first = doc.split("\n\n", 1)[0]
        return " ".join(line.strip() for line in first.splitlines())

    @classmethod
    def param_info(cls) -> dict[str, dict[str, Any]]:
        """Parameters as ``{name: {"default": ..., "description": ...}}``."""
        return {
            k: {"default": f.default, "description": f.description or ""}
            for k, f in cls.Params.model_fields.items()
        }

    def __repr__(self) -> str:
        return f"<rule {self.name!r} ({self.kind})>"


_CHECK_HINT = "forcelayout.testing.check_rule() checks a rule before any run (docs/rules.md)"


def _checked(method: str, fn: Any) -> Any:
    """A plugin rule's ``force`` or ``satisfied``, its result checked on every call."""
    if method == "force":
        @functools.wraps(fn)
        def force(self: Rule, state: State, i: np.ndarray, j: np.ndarray | None,
                  p: ParamArrays) -> tuple[np.ndarray, np.ndarray]:
            return _force_result(self, fn(self, state, i, j, p), len(i))
        return force

    @functools.wraps(fn)
    def satisfied(self: Rule, state: State, i: np.ndarray, j: np.ndarray | None,
                  p: ParamArrays) -> np.ndarray:
        return _satisfied_result(self, fn(self, state, i, j, p), len(i))
    return satisfied


def _force_result(rule: Rule, out: Any, b: int) -> tuple[np.ndarray, np.ndarray]:
    """``out`` as ``(F, tau)`` of shapes (b, 2) and (b,), finite; else a RuleOutputError."""
    from forcelayout.errors import RuleOutputError

    name = getattr(rule, "name", type(rule).__name__)
    if not (isinstance(out, tuple) and len(out) == 2):
        raise RuleOutputError(f"rule {name!r}: force() must return a tuple (F, tau), got "
                              f"{type(out).__name__}; {_CHECK_HINT}")
    f, tau = np.asarray(out[0]), np.asarray(out[1])
    if f.shape != (b, 2) or tau.shape != (b,):
        raise RuleOutputError(f"rule {name!r}: force() returned F of shape {f.shape} and tau "
                              f"of shape {tau.shape} for {b} bindings; expected ({b}, 2) and "
                              f"({b},), one force and one torque per binding; {_CHECK_HINT}")
    if not (np.isfinite(f).all() and np.isfinite(tau).all()):
        raise RuleOutputError(f"rule {name!r}: force() returned non-finite values (NaN or "
                              "infinite); guard divisions by distances that can be zero (e.g. "
                              f"objects at the same centre); {_CHECK_HINT}")
    return f, tau


def _satisfied_result(rule: Rule, out: Any, b: int) -> np.ndarray:
    """``out`` as a bool array of shape (b,); else a RuleOutputError."""
    from forcelayout.errors import RuleOutputError

    ok = np.asarray(out)
    if ok.dtype != np.bool_ or ok.shape != (b,):
        name = getattr(rule, "name", type(rule).__name__)
        raise RuleOutputError(f"rule {name!r}: satisfied() must return a bool array of shape "
                              f"({b},), got {ok.dtype} with shape {ok.shape}; e.g. return "
                              f"gap <= p.distance, not the gap itself; {_CHECK_HINT}")
    return ok
