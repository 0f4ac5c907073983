"""The net force and torque of eqs. (2)–(3): a sum of force terms.

A :class:`ForceModel` holds the objects of one simulation (rows of the state
arrays), the room and a list of **force terms**. :meth:`ForceModel.net` is
the one entry point the solver calls: it sums every term. Three kinds of
term are built in —

* :class:`RuleTerm`: the rule bindings, grouped by rule so each rule is
  called once per step over all its bindings (annealed);
* :class:`PassageTerm`: walking room between objects no rule relates
  (annealed, like the rules);
* :class:`PhysicalTerm`: repulsion, boundary, alignment and door clearance
  (always on, not annealed);

and a caller adds its own with :meth:`ForceModel.add_term` (the surface
planes add a spring to eye level or over a target; a user may add anything).
A term is any object with a boolean attribute ``annealed`` and a method
``__call__(state, temperature) -> (F (N, 2), tau (N,))``. Annealed terms are
sampled every ``SolverConfig.semantic_interval`` steps (multiple time
stepping); the others every step. Each term decides how it uses the
temperature.

The model knows nothing about Box2D; the solver asks it for forces and moves
the bodies.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import Protocol, runtime_checkable

import numpy as np

from forcelayout.access import AccessTerm, access_term, related_pairs
from forcelayout.bindings import Binding, CompiledPlan, RuleGroup, compile_plan, group_bindings
from forcelayout.clearance import WindowTerm
from forcelayout.geometry import RoomGeometry, corners_from_axes
from forcelayout.plan import Plan
from forcelayout.rules.base import ParamArrays, State, stacked_rows
from forcelayout.rules.physical import PhysicalWeights, closing, physical, repulsion
from forcelayout.validate.checks import window_zones

__all__ = [
    "ForceTerm",
    "RuleTerm",
    "PassageTerm",
    "PhysicalTerm",
    "ClosingTerm",
    "ForceModel",
    "StackedForces",
    "stack_term",
    "join_terms",
    "RuleGroup",
    "SOFT_TORQUE_ON_HARD",
]

#: Scale of soft rules' torques on objects that a hard rule (``Rule.hard``) orients.
SOFT_TORQUE_ON_HARD = 0.2


@runtime_checkable
class ForceTerm(Protocol):
    """What :meth:`ForceModel.net` sums: a callable with an ``annealed`` flag.

    Attributes
    ----------
    annealed : bool
        ``True`` for semantic terms (sampled every ``semantic_interval``
        steps, usually scaled by the temperature); ``False`` for physical
        terms (every step).
    """

    annealed: bool

    def __call__(self, state: State, temperature: float) -> tuple[np.ndarray, np.ndarray]:
        """Force (N, 2) and torque (N,) on every object of ``state``."""
        ...


class RuleTerm:
    """The rule bindings of a simulation, one call per rule per step (annealed).

    The weights are multiplied by the temperature. On objects whose heading
    a hard rule fixes (``Rule.hard``), the torques of soft rules are scaled
    by :data:`SOFT_TORQUE_ON_HARD`. A binding's ``reaction`` pushes back on
    its target.
    """

    annealed = True

    def __init__(self, groups: Sequence[RuleGroup], n: int):
        self.groups = list(groups)
        held = np.zeros(n, dtype=bool)
        for g in self.groups:
            if g.rule.hard:
                held[g.i] = True
        self.soft_torque_scale = np.where(held, SOFT_TORQUE_ON_HARD, 1.0)
        #: Per group, the group of one sample for rules that are not ``batched``
        #: (called once per sample), else None.
        self._single: list[RuleGroup | None] = [None] * len(self.groups)
        self._samples = 1

    def stack(self, samples: int, rows: int) -> RuleTerm:
        """The same bindings over ``samples`` stacked samples of ``rows`` rows each."""
        out = RuleTerm([g.stack(samples, rows) for g in self.groups], samples * rows)
        out._single = [None if g.rule.batched else g for g in self.groups]
        out._samples = samples
        return out

    def __call__(self, state: State, temperature: float) -> tuple[np.ndarray, np.ndarray]:
        f = np.zeros((state.n, 2))
        tau = np.zeros(state.n)
        for g, one in zip(self.groups, self._single, strict=True):
            if one is None:
                fi, ti = g.rule.force(state, g.i, g.j, g.at_temperature(temperature))
            else:  # a rule that sees one sample at a time
                p = one.at_temperature(temperature)
                parts = [g.rule.force(state.sample(b), one.i, one.j, p)
                         for b in range(self._samples)]
                fi = np.concatenate([np.asarray(x[0], dtype=float).reshape(-1, 2)
                                     for x in parts])
                ti = np.concatenate([np.asarray(x[1], dtype=float).reshape(-1)
                                     for x in parts])
            if not g.rule.hard:
                ti = ti * self.soft_torque_scale[g.i]
            if g.unique_i:  # one binding per object: plain fancy-index add
                f[g.i] += fi
                tau[g.i] += ti
            else:
                np.add.at(f, g.i, fi)
                np.add.at(tau, g.i, ti)
            if g.j is not None and g.rule.reaction:
                np.add.at(f, g.j, -g.rule.reaction * fi)
        return f, tau


class PassageTerm:
    """Walking room between the pairs ``(qi, qj)`` that no rule relates (annealed).

    The same logarithmic push as repulsion, with ``w.passage`` and
    ``w.passage_range`` (about an agent's width).
    """

    annealed = True

    def __init__(self, qi: np.ndarray, qj: np.ndarray, weights: PhysicalWeights):
        self.qi, self.qj, self.weights = qi, qj, weights

    def stack(self, samples: int, rows: int) -> PassageTerm:
        """The same pairs in each of ``samples`` stacked samples of ``rows`` rows."""
        out = PassageTerm(stacked_rows(self.qi, samples, rows),
                          stacked_rows(self.qj, samples, rows), self.weights)
        out.annealed = self.annealed  # an instance may hold all through (repair rounds)
        return out

    def __call__(self, state: State, temperature: float) -> tuple[np.ndarray, np.ndarray]:
        w = self.weights
        if w.passage <= 0 or not self.qi.size:
            return np.zeros((state.n, 2)), np.zeros(state.n)
        return repulsion(state, self.qi, self.qj, w, w.passage_range, w.passage * temperature)


class PhysicalTerm:
    """The always-on terms (repulsion, boundary, alignment, door clearance); not annealed.

    Repulsion acts between the pairs ``(pi, pj)`` (the model passes the pairs no
    rule relates: related pairs are spaced by their rules, kept apart by contacts);
    the door clearance pushes the ``solid`` rows (walkable floor covers may lie in a
    door's swing), and the ``slide`` rows (held at a wall by a hard rule) only along the wall.
    The alignment leaves the ``unaligned`` rows as they turn (a beanbag a rule turns
    towards the TV on the wall, which is hung after the floor settles).
    """

    annealed = False

    def __init__(self, pi: np.ndarray, pj: np.ndarray, weights: PhysicalWeights,
                 solid: np.ndarray | None = None, slide: np.ndarray | None = None,
                 entry: bool | np.ndarray = True, unaligned: np.ndarray | None = None):
        self.pi, self.pj, self.weights = pi, pj, weights
        self.solid = None if solid is None or solid.all() else solid.astype(float)
        self.slide = None if slide is None or not slide.any() else slide
        self.unaligned = None if unaligned is None or not unaligned.any() else unaligned
        #: Whether doors keep their entry zones clear (else their swing squares): for
        #: every row, or per row (N,) (an object a rule wants by a door keeps out of the
        #: swing square alone, as the checks ask)
        self.entry: bool | np.ndarray = bool(entry.all()) if isinstance(
            entry, np.ndarray) and (entry.all() or not entry.any()) else entry

    def stack(self, samples: int, rows: int) -> PhysicalTerm:
        """The same terms in each of ``samples`` stacked samples of ``rows`` rows."""
        out = PhysicalTerm(stacked_rows(self.pi, samples, rows),
                           stacked_rows(self.pj, samples, rows), self.weights,
                           entry=self.entry if isinstance(self.entry, bool)
                           else np.tile(self.entry, samples))
        out.solid = None if self.solid is None else np.tile(self.solid, samples)
        out.slide = None if self.slide is None else np.tile(self.slide, samples)
        out.unaligned = None if self.unaligned is None else np.tile(self.unaligned, samples)
        return out

    def swing_squares_only(self) -> PhysicalTerm:
        """The same terms with doors keeping only their swing squares clear."""
        out = copy.copy(self)
        out.entry = False
        return out

    def __call__(self, state: State, temperature: float) -> tuple[np.ndarray, np.ndarray]:
        return physical(state, self.pi, self.pj, self.weights, self.solid, self.slide,
                        self.entry, self.unaligned)


class ClosingTerm:
    """A pull that closes slivers of floor too narrow for the agent, between the pairs
    ``(qi, qj)`` and between the ``solid`` rows and the walls
    (:func:`~forcelayout.rules.physical.closing`); not annealed.

    The gradient of the free floor the ``navigable`` check counts: repair
    rounds of an arrangement short of free floor simulate with it.
    """

    annealed = False

    def __init__(self, qi: np.ndarray, qj: np.ndarray, solid: np.ndarray, radius: float,
                 strength: float):
        self.qi, self.qj, self.solid = qi, qj, np.asarray(solid, dtype=bool)
        self.radius, self.strength = radius, strength

    def stack(self, samples: int, rows: int) -> ClosingTerm:
        """The same pulls in each of ``samples`` stacked samples of ``rows`` rows."""
        return ClosingTerm(stacked_rows(self.qi, samples, rows),
                           stacked_rows(self.qj, samples, rows),
                           np.tile(self.solid, samples), self.radius, self.strength)

    def __call__(self, state: State, temperature: float) -> tuple[np.ndarray, np.ndarray]:
        return closing(state, self.qi, self.qj, self.solid, self.radius, self.strength)


class _EachOwn:
    """Each sample's own term, each run on its sample of a stacked state (the same term
    for every sample: a term without a stacked form, called once per sample)."""

    def __init__(self, terms: Sequence[ForceTerm]):
        self.terms = list(terms)
        self.annealed = self.terms[0].annealed

    def __call__(self, state: State, temperature: float) -> tuple[np.ndarray, np.ndarray]:
        parts = [t(state.sample(b), temperature) for b, t in enumerate(self.terms)]
        return (np.concatenate([np.asarray(f, dtype=float).reshape(-1, 2) for f, _ in parts]),
                np.concatenate([np.asarray(t, dtype=float).reshape(-1) for _, t in parts]))


def join_terms(terms: Sequence[ForceTerm]) -> ForceTerm:
    """One term for a stacked state from each sample's own term (sample ``b``'s is ``terms[b]``).

    Where the terms' class has a classmethod ``join(terms)`` (an
    :class:`~forcelayout.surfaces.AnchorTerm` does: its anchors are
    concatenated), that gives one term for every sample; otherwise each term
    is called on its own sample's rows. Either way sample ``b``'s forces are
    those ``terms[b]`` gives it alone, bit for bit.
    """
    if len(terms) == 1:
        return terms[0]
    join = getattr(type(terms[0]), "join", None)
    if callable(join) and all(type(t) is type(terms[0]) for t in terms):
        return join(terms)
    return _EachOwn(terms)


def stack_term(term: ForceTerm, samples: int, rows: int) -> ForceTerm:
    """``term`` for a state that stacks ``samples`` samples of ``rows`` rows each.

    A term with a method ``stack(samples, rows)`` gives its own stacked form
    (the built-in terms do: one call then serves every sample); any other
    term is called once per sample with that sample's state.
    """
    if samples == 1:
        return term
    stack = getattr(term, "stack", None)
    if callable(stack):
        return stack(samples, rows)
    return _EachOwn([term] * samples)


class ForceModel:
    """The objects, room and force terms of one simulation.

    Parameters
    ----------
    plan : Plan or CompiledPlan
    ids : sequence of str, optional
        The objects simulated together (rows of the state arrays). Defaults
        to the plan's floor objects.
    sizes : mapping of str to (width, depth, height), optional
        Sizes of the rows, for objects that are not the plan's or that a
        plane sees differently (a wall object's ``[width, height, depth]``).
    bindings : iterable of Binding, optional
        The rule bindings to simulate; by default the plan's floor bindings
        among ``ids``. Bindings whose object or target is not a row are left
        out (they belong to another simulation).
    room : RoomGeometry, optional
        Defaults to the plan's room.
    relations : bool, default True
        ``False`` drops object-object bindings — the paper's −Relations
        ablation.
    physical_weights : PhysicalWeights, optional
        Strengths of the always-on terms; the plan's ``weights`` may scale
        ``repulsion``, ``passage``, ``boundary``, ``alignment`` and ``door``.
    terms : iterable of ForceTerm, optional
        Extra terms, summed with the built-in ones (see :meth:`add_term`).
    """

    def __init__(
        self,
        plan: Plan | CompiledPlan,
        ids: Sequence[str] | None = None,
        *,
        sizes: Mapping[str, Sequence[float]] | None = None,
        bindings: Iterable[Binding] | None = None,
        room: RoomGeometry | None = None,
        relations: bool = True,
        physical_weights: PhysicalWeights | None = None,
        terms: Iterable[ForceTerm] = (),
    ):
        self.compiled = compile_plan(plan)
        self.plan = self.compiled.plan
        self.ids = tuple(ids) if ids is not None else self.compiled.floor_ids
        self.room = room if room is not None else self.compiled.room
        #: Convex polygons (K, 2) no solid row may enter, static in the simulation as the
        #: walls are: the doors' swing squares, which the checks keep clear (a push
        #: alone, however steep, lets a row pressed by preferences rest a few millimetres
        #: inside). Only in the plan's own room (a plane has no doors).
        self.keep_out: list[np.ndarray] = []
        if self.room is self.compiled.room and len(self.room.doors):
            self.keep_out = list(corners_from_axes(*self.room.door_squares))
        if sizes is None:
            self.size = self.compiled.size(self.ids)
        else:
            self.size = np.array([sizes[i] for i in self.ids], dtype=float).reshape(-1, 3)
        row = {oid: r for r, oid in enumerate(self.ids)}
        if bindings is None:
            bindings = self.compiled.floor_bindings(self.ids, relations=relations)
        elif not relations:
            bindings = [b for b in bindings if b.target is None or b.rule.target == "none"]
        self.bindings = tuple(bindings)
        self.groups = group_bindings(self.bindings, row)
        self.physical_weights = (physical_weights or PhysicalWeights()).scaled(self.plan.weights)
        n = len(self.ids)
        objects = {o.id: o for o in self.plan.objects}
        #: Walkable floor covers (rugs): no obstacle to furniture, walls hold them in.
        #: (A thin object resting on a top or hanging on a wall is no cover.)
        self.walkable = np.array([oid in objects and objects[oid].is_walkable
                                  and self.compiled.surface_of(oid) is None
                                  for oid in self.ids], dtype=bool)
        pi, pj = (a.astype(int) for a in np.triu_indices(n, k=1))
        solid = ~(self.walkable[pi] | self.walkable[pj])  # covers neither push nor are pushed
        self.pi, self.pj = pi[solid], pj[solid]
        # pairs that a rule relates may stand close; others keep walking room apart
        related = np.zeros((n, n), dtype=bool)
        for g in self.groups:
            if g.j is not None:
                related[g.i, g.j] = related[g.j, g.i] = True
        #: Pairs of rows some binding relates (they may stand close).
        self.related = related
        free = ~related[self.pi, self.pj]
        self.rules = RuleTerm(self.groups, n)
        #: Rows a hard placement rule holds (at a wall, in a corner): keep-out zones push
        #: them along the wall, never off it.
        self.held = self.rules.soft_torque_scale < 1.0
        #: Bindings whose rule turns a row towards a wall object (``facing(bed, tv)``;
        #: :meth:`CompiledPlan.wall_views`): :mod:`forcelayout.initial` starts the row
        #: turned to where that object will hang.
        self.wall_views = self.compiled.wall_views(row)
        #: Rows some binding of ``wall_views`` turns: those held at no wall keep the
        #: heading they start with.
        self.turned_to_wall = np.zeros(n, dtype=bool)
        for b in self.wall_views:
            self.turned_to_wall[row[b.object]] = True
        w_window = self.physical_weights.window
        self.terms: list[ForceTerm] = [
            self.rules,
            PassageTerm(self.pi[free], self.pj[free], self.physical_weights),
            PhysicalTerm(self.pi[free], self.pj[free], self.physical_weights, ~self.walkable,
                         self.held, entry=~self.wanted_at("door"),
                         unaligned=self.turned_to_wall & ~self.held),
        ]
        if self.room is self.compiled.room and self.plan.room.windows and w_window > 0:
            self.terms.append(self._window_term(w_window))
        if self.physical_weights.access > 0:  # free floor in front of wardrobes, desks, ...
            acc = access_term(objects, self.ids, self.bindings, self.walkable,
                              related_pairs(self.ids, self.bindings, objects))
            if acc is not None:
                acc.strength *= self.physical_weights.access
                self.terms.append(acc)
        for t in terms:
            self.add_term(t)
        self._stacks: dict[tuple[int, ...], StackedForces] = {}

    def wanted_at(self, place: str) -> np.ndarray:
        """Rows a binding wants at ``place``, its rule's start place (``"door"`` for
        ``near_door``, ``"window"`` for ``near_window``, ``"wall"``, ...), shape (N,) bool.

        The door's entry zone does not push the rows wanted by a door off their
        spot beside its swing square; an unmet ``near_window`` does not blame
        the rows wanted by a window for standing there.
        """
        out = np.zeros(len(self.ids), dtype=bool)
        for g in self.groups:
            if g.rule.start is not None and g.rule.start.place == place:
                out[g.i] = True
        return out

    def _window_term(self, strength: float) -> WindowTerm:
        """Floor objects taller than a window's sill kept out of its clearance zone."""
        centre, along, into, half, sill = window_zones(self.plan.room)  # what the check uses
        return WindowTerm(centre, along, into, half, sill, self.size[:, 2], self.walkable,
                          10.0 * strength, slide=self.held)

    @property
    def n(self) -> int:
        """Number of simulated objects."""
        return len(self.ids)

    def add_term(self, term: ForceTerm) -> None:
        """Add a force term; :meth:`net` sums it with the others from then on.

        Raises
        ------
        TypeError
            If ``term`` is not callable or has no boolean ``annealed``.
        """
        if not callable(term) or not isinstance(getattr(term, "annealed", None), bool):
            raise TypeError("a force term is a callable term(state, temperature) -> (F, tau) "
                            f"with a boolean attribute 'annealed'; got {term!r}")
        self.terms.append(term)

    @contextmanager
    def without(self, *kinds: type) -> Iterator[None]:
        """Leave out the terms of the given classes while the ``with`` block runs."""
        kept = self.terms
        self.terms = [t for t in kept if not isinstance(t, kinds)]
        try:
            yield
        finally:
            self.terms = kept

    def leaving_out(self, *kinds: type) -> ForceModel:
        """A copy of this model without the terms of the given classes (the rest shared)."""
        out = copy.copy(self)
        out.terms = [t for t in self.terms if not isinstance(t, kinds)]
        out._stacks = {}
        return out

    def settling(self) -> ForceModel:
        """The model a start that already passes is settled by (squared up, pressed to its
        walls), without rearranging it.

        A copy without the walking-room and access terms, whose doors keep
        only their swing squares clear (what the checks ask), not the deeper
        entry zone: those terms make room where the start may already have
        enough, and pushing a bed that stands clear of a door's swing out of
        the zone beyond it slides it along its wall into its neighbours.
        """
        out = self.leaving_out(PassageTerm, AccessTerm)
        out.terms = [t.swing_squares_only() if isinstance(t, PhysicalTerm) else t
                     for t in out.terms]
        return out

    def muting(self, positions: Iterable[int]) -> ForceModel:
        """A copy whose bindings at ``positions`` (in :attr:`bindings`) pull with no weight.

        Settling a start that passes with a binding unmet (within the
        sample's tolerance) mutes that binding: its force would drag its
        object across the room, breaking the bindings the start meets.
        """
        mute = set(int(k) for k in positions)
        out = copy.copy(self)
        terms = []
        for t in self.terms:
            if isinstance(t, RuleTerm):
                groups = []
                for g in t.groups:
                    off = np.isin(g.position, list(mute))
                    if off.any():
                        g = dataclasses.replace(g, params=ParamArrays(
                            g.params._fields, np.where(off, 0.0, g.params.weight)))
                    groups.append(g)
                t = RuleTerm(groups, self.n)
            terms.append(t)
        out.terms = terms
        out._stacks = {}
        return out

    def stacked(self, samples: int) -> ForceModel | StackedForces:
        """The forces of this model on ``samples`` samples at once (the batched engine).

        Returns this model for one sample, else a :class:`StackedForces`
        whose :meth:`~StackedForces.state` stacks the samples' rows; each
        sample's forces are those this model gives it alone, bit for bit.
        """
        if samples == 1:
            return self
        key = (samples, *map(id, self.terms))
        out = self._stacks.get(key)
        if out is None or any(a is not b for a, b in zip(out.source, self.terms, strict=True)):
            # (an id may be reused by a new term once an old one is gone)
            if len(self._stacks) > 64:
                self._stacks.clear()
            out = self._stacks[key] = StackedForces(self, samples)
        return out

    def state(self, pos: np.ndarray, yaw: np.ndarray) -> State:
        """A :class:`State` of these objects at the given poses."""
        return State(np.asarray(pos, dtype=float), np.asarray(yaw, dtype=float), self.size,
                     self.room, self.ids)

    def net(self, state: State, temperature: float = 1.0, *, annealed: bool | None = None
            ) -> tuple[np.ndarray, np.ndarray]:
        """Net force (N, 2) and torque (N,) on every object: eqs. (2) and (3).

        The sum of every term. ``annealed=True`` sums only the annealed
        (semantic) terms, ``annealed=False`` only the others; the solver
        calls both, the first less often (multiple time stepping).
        """
        return _net(self.terms, state, temperature, annealed)

    def semantic(self, state: State, temperature: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
        """The annealed terms alone (``net(..., annealed=True)``)."""
        return self.net(state, temperature, annealed=True)

    def physical(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """The always-on terms alone (``net(..., annealed=False)``)."""
        return self.net(state, 1.0, annealed=False)

    def satisfied(self, state: State) -> dict[int, bool]:
        """Whether each simulated binding is met, by the rule's own check.

        Returns ``{k: met}`` keyed by position in :attr:`bindings`
        (``self.bindings[k].index`` is the binding's index in ``plan.rules``).
        """
        out: dict[int, bool] = {}
        for g in self.groups:
            out.update(zip(g.position.tolist(), g.satisfied(state).tolist(), strict=True))
        return out


def _net(terms: Sequence[ForceTerm], state: State, temperature: float, annealed: bool | None
         ) -> tuple[np.ndarray, np.ndarray]:
    f = np.zeros((state.n, 2))
    tau = np.zeros(state.n)
    for term in terms:
        if annealed is None or term.annealed == annealed:
            fk, tk = term(state, temperature)
            f += fk
            tau += tk
    return f, tau


class StackedForces:
    """The force terms of a :class:`ForceModel` over many samples stacked as one state.

    Built by :meth:`ForceModel.stacked`. Sample ``b`` of the state takes
    rows ``b * rows .. (b + 1) * rows - 1``; every term is stacked with
    :func:`stack_term`, so no term relates rows of different samples.

    Attributes
    ----------
    model : ForceModel
    samples, rows : int
    terms : list of ForceTerm
    """

    def __init__(self, model: ForceModel, samples: int):
        self.model, self.samples, self.rows = model, int(samples), model.n
        self.source = tuple(model.terms)  # the terms stacked here
        self.size = np.tile(model.size, (self.samples, 1))
        self.ids = model.ids * self.samples
        self.terms = [stack_term(t, self.samples, self.rows) for t in model.terms]

    @property
    def n(self) -> int:
        """Rows of the stacked state."""
        return self.samples * self.rows

    def state(self, pos: np.ndarray, yaw: np.ndarray) -> State:
        """The stacked :class:`State` of poses ``(samples * rows, 2)`` and ``(samples * rows,)``."""
        return State(np.asarray(pos, dtype=float), np.asarray(yaw, dtype=float), self.size,
                     self.model.room, self.ids, samples=self.samples)

    def net(self, state: State, temperature: float = 1.0, *, annealed: bool | None = None
            ) -> tuple[np.ndarray, np.ndarray]:
        """As :meth:`ForceModel.net`, for every stacked sample."""
        return _net(self.terms, state, temperature, annealed)

    def satisfied(self, state: State) -> dict[int, np.ndarray]:
        """As :meth:`ForceModel.satisfied`, for every stacked sample: ``{k: met}`` with
        ``met`` of shape (samples,); a rule that is not ``batched`` is judged once per
        sample on that sample's state."""
        # the model's rule groups as stacked for the forces
        rules = next(t for src, t in zip(self.source, self.terms, strict=True)
                     if src is self.model.rules)
        out: dict[int, np.ndarray] = {}
        for g, s in zip(self.model.groups, rules.groups, strict=True):
            out.update(zip(g.position.tolist(), g.satisfied_stacked(state, s).T, strict=True))
        return out
