"""A plan compiled once: rule bindings resolved to rule instances, params and rows.

Everything that works on a plan's rules — the force model of every
simulation (floor, tops, walls, ceiling, area variants), the rule judge of
finished layouts, start poses and the scene graph — shares one
:class:`CompiledPlan`: each ``plan.rules`` entry becomes a :class:`Binding`
whose params are validated once and whose rule instance comes from the
registry. Simulations take the bindings they need (a subset, or bindings the
engine adds, such as an area's rectangle against a wall) and group them by
rule into index arrays with :func:`group_bindings`.

Examples
--------
>>> from forcelayout.bindings import compile_plan
>>> from forcelayout.examples import load_example
>>> cp = compile_plan(load_example("bedroom"))
>>> cp.surface_of("lamp").rule.surface
'top'
>>> sorted(b.rule.name for b in cp.bindings if b.object == "bed")
['at_wall']
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from pydantic import BaseModel

from forcelayout import rules as registry
from forcelayout.geometry import RoomGeometry
from forcelayout.plan import Plan, _binding_label
from forcelayout.rules.base import ParamArrays, Rule, State, stacked_rows

__all__ = ["Binding", "RuleGroup", "CompiledPlan", "compile_plan", "group_bindings"]


@dataclass(frozen=True)
class Binding:
    """One rule binding, resolved: the rule instance, validated params and weight.

    Attributes
    ----------
    index : int
        Position in ``plan.rules``; ``-1`` for a binding the engine adds
        (e.g. an area's rectangle held against a wall).
    rule : Rule
        The registered rule instance.
    object : str
        Id of the bound object.
    target : str or None
        Id of the target object (or functional area), if any.
    params : pydantic model
        The rule's validated ``Params``.
    weight : float
        Effective strength: the binding's ``weight``, else the plan's
        ``weights[rule]``, else the rule's default.
    bond : bool or None
        The spec's explicit ``bond``; ``None`` means the rule's default.
    required : bool
        The spec's ``required``: a layout that leaves it unmet is rejected, whatever
        share of the rules the acceptance lets go unmet.
    """

    index: int
    rule: Rule
    object: str
    target: str | None
    params: BaseModel
    weight: float
    bond: bool | None = None
    required: bool = False

    @classmethod
    def make(cls, rule: Rule | str, object: str, target: str | None = None,
             params: Mapping[str, Any] | None = None, weight: float | None = None,
             *, index: int = -1, bond: bool | None = None, required: bool = False
             ) -> Binding:
        """A binding from a rule (instance or registered name) and raw params."""
        inst = registry.get_rule(rule) if isinstance(rule, str) else rule
        p = inst.Params.model_validate(dict(params or {}))
        return cls(index, inst, object, target, p,
                   float(inst.weight if weight is None else weight), bond, bool(required))

    def __str__(self) -> str:
        return _binding_label(self.rule.name, self.object, self.target)


@dataclass
class RuleGroup:
    """All bindings of one rule within a simulation, as index arrays.

    Attributes
    ----------
    rule : Rule
    i : ndarray of int, shape (B,)
        Row of each bound object in the state arrays.
    j : ndarray of int, shape (B,), or None
        Row of each target (rules with targets).
    params : ParamArrays
        Parameters per binding; ``params.weight`` holds the base weights.
    index : ndarray of int, shape (B,)
        Index of each binding in ``plan.rules`` (``-1`` for added bindings).
    position : ndarray of int, shape (B,)
        Position of each binding in the sequence given to :func:`group_bindings`.
    unique_i : bool
        Whether each object is bound at most once (a plain fancy-index add
        then sums the forces).
    """

    rule: Rule
    i: np.ndarray
    j: np.ndarray | None
    params: ParamArrays
    index: np.ndarray
    position: np.ndarray
    unique_i: bool = field(init=False)

    def __post_init__(self) -> None:
        self.unique_i = len(np.unique(self.i)) == len(self.i)

    @property
    def spec_index(self) -> np.ndarray:
        """Alias of :attr:`index` (index of each binding in ``plan.rules``)."""
        return self.index

    def at_temperature(self, temperature: float) -> ParamArrays:
        """Params with the weights multiplied by the annealing temperature."""
        return ParamArrays(self.params._fields, self.params.weight * temperature)

    def stack(self, samples: int, rows: int) -> RuleGroup:
        """The same bindings in each of ``samples`` stacked samples of ``rows`` rows."""
        p = self.params
        fields = {k: np.tile(v, samples) for k, v in p._fields.items()}
        return RuleGroup(self.rule, stacked_rows(self.i, samples, rows),
                         None if self.j is None else stacked_rows(self.j, samples, rows),
                         ParamArrays(fields, np.tile(p.weight, samples)),
                         np.tile(self.index, samples), np.tile(self.position, samples))

    def satisfied(self, state: State) -> np.ndarray:
        """The rule's own check of every binding of the group, shape (B,) of bool."""
        return np.asarray(self.rule.satisfied(state, self.i, self.j, self.params), dtype=bool)

    def satisfied_stacked(self, state: State, stacked: RuleGroup | None = None) -> np.ndarray:
        """The rule's own check of every binding in every sample of a stacked state, shape
        (samples, B) of bool. ``stacked`` is the group as stacked for that state (made with
        :meth:`stack` when not given); a rule that is not ``batched`` is judged once per
        sample on that sample's state."""
        n = state.samples
        if not self.rule.batched:
            return np.stack([self.satisfied(state.sample(b)) for b in range(n)])
        s = stacked if stacked is not None else self.stack(n, state.rows)
        ok = np.asarray(self.rule.satisfied(state, s.i, s.j, s.params), dtype=bool)
        return ok.reshape(n, len(self.i))


def group_bindings(bindings: Iterable[Binding], row: Mapping[str, int]) -> list[RuleGroup]:
    """Group bindings by rule into index arrays over the rows ``row[id]``.

    Bindings whose object (or, for a rule with a target, target) has no row
    are left out; a target that has no row on a rule with an optional target
    drops the target (the binding relates the object to the room).
    """
    buckets: dict[str, list[tuple[Binding, int | None, int]]] = {}
    rules: dict[str, Rule] = {}
    for k, b in enumerate(bindings):
        if b.object not in row:
            continue
        j = row.get(b.target) if b.target is not None else None
        if b.rule.target == "required" and j is None:
            continue
        buckets.setdefault(b.rule.name, []).append((b, j, k))
        rules[b.rule.name] = b.rule
    groups = []
    for name, items in buckets.items():
        rule = rules[name]
        with_j = [it for it in items if it[1] is not None]
        # a rule with an optional target is called once with targets, once without
        for part in (with_j, [it for it in items if it[1] is None]):
            if not part:
                continue
            i = np.array([row[b.object] for b, _, _ in part], dtype=int)
            j = (np.array([jj for _, jj, _ in part], dtype=int) if part[0][1] is not None
                 else None)
            params = ParamArrays.from_models([b.params for b, _, _ in part],
                                             np.array([b.weight for b, _, _ in part]))
            groups.append(RuleGroup(rule, i, j, params,
                                    np.array([b.index for b, _, _ in part], dtype=int),
                                    np.array([k for _, _, k in part], dtype=int)))
    return groups


class CompiledPlan:
    """A plan compiled once; use :func:`compile_plan` (it caches per plan).

    Attributes
    ----------
    plan : Plan
    ids : tuple of str
        Object ids in plan order.
    bindings : tuple of Binding
        One per ``plan.rules`` entry, in order.
    """

    def __init__(self, plan: Plan):
        self.plan = plan
        self.ids = tuple(o.id for o in plan.objects)
        self._size = {o.id: o.size for o in plan.objects}
        self.bindings = tuple(
            Binding.make(s.rule, s.object, s.target, s.params,
                         s.weight if s.weight is not None else plan.weights.get(s.rule),
                         index=k, bond=s.bond, required=s.required)
            for k, s in enumerate(plan.rules))

    @cached_property
    def room(self) -> RoomGeometry:
        """The room as arrays (computed once)."""
        return RoomGeometry.from_room(self.plan.room)

    def size(self, ids: Sequence[str]) -> np.ndarray:
        """Sizes ``[width, depth, height]`` of the given objects, shape (K, 3), metres."""
        return np.array([self._size[i] for i in ids], dtype=float).reshape(-1, 3)

    @cached_property
    def _surface(self) -> dict[str, Binding]:
        out: dict[str, Binding] = {}
        for b in self.bindings:
            if b.rule.surface != "floor" and b.object not in out:
                out[b.object] = b
        return out

    def surface_of(self, object_id: str) -> Binding | None:
        """The binding that takes an object off the floor, or ``None`` for a floor object."""
        return self._surface.get(object_id)

    @cached_property
    def floor_ids(self) -> tuple[str, ...]:
        """Objects that stand on the floor, in plan order."""
        return tuple(i for i in self.ids if i not in self._surface)

    def wall_views(self, ids: Iterable[str]) -> tuple[Binding, ...]:
        """The bindings whose rule turns one of ``ids`` towards an object hung on a wall
        (``facing(bed, tv)``: its start hint turns the object to its target), in plan
        order. The wall object is hung after the floor settles, so no term of the floor
        turns the object; start poses and floor judges look to it instead."""
        keep = set(ids)
        return tuple(b for b in self.bindings
                     if b.object in keep and b.target is not None
                     and (hangs := self.surface_of(b.target)) is not None
                     and hangs.rule.surface == "wall" and b.rule.start is not None
                     and b.rule.start.turn == "face_target")

    def on(self, surface: str) -> list[Binding]:
        """The off-floor bindings that place objects on ``surface`` ("top", "wall", "ceiling")."""
        return [b for b in self._surface.values() if b.rule.surface == surface]

    def floor_bindings(self, ids: Iterable[str] | None = None, *, relations: bool = True
                       ) -> list[Binding]:
        """Floor-rule bindings among ``ids`` (default: the floor objects).

        ``relations=False`` leaves out bindings between two objects (the
        paper's −Relations ablation).
        """
        keep = set(self.floor_ids if ids is None else ids)
        out = []
        for b in self.bindings:
            if b.rule.surface != "floor" or b.object not in keep:
                continue
            if b.target is not None and b.rule.target != "none" and (
                    b.target not in keep or not relations):
                if b.rule.target == "required":
                    continue
            out.append(b)
        return out

    def judged(self, ids: Iterable[str]) -> list[Binding]:
        """The bindings a finished state of objects ``ids`` judges: those whose object and
        target (if any) are among them; a binding whose target names a functional area
        rather than an object is not judged."""
        placed = set(ids)
        return [b for b in self.bindings if b.object in placed
                and (b.target is None or b.target in placed)  # an unplaced object, an area
                and not (b.rule.target == "required" and b.target is None)]

    def judge(self, state: State) -> dict[int, bool]:
        """Every binding's own check on a finished state: ``{plan rule index: met}``.

        Bindings whose object or target is not a row of ``state`` are not
        judged (absent from the result), nor are bindings whose target names
        a functional area rather than an object.
        """
        row = {oid: k for k, oid in enumerate(state.ids)}
        out: dict[int, bool] = {}
        for g in group_bindings(self.judged(row), row):
            out.update(zip(g.index.tolist(), g.satisfied(state).tolist(), strict=True))
        return out


_CACHE: dict[int, CompiledPlan] = {}


def compile_plan(plan: Plan | CompiledPlan) -> CompiledPlan:
    """Compile a plan once (cached per plan object; a compiled plan is returned as is)."""
    if isinstance(plan, CompiledPlan):
        return plan
    hit = _CACHE.get(id(plan))
    if hit is not None and hit.plan is plan:
        return hit
    if len(_CACHE) > 64:
        _CACHE.clear()
    out = _CACHE[id(plan)] = CompiledPlan(plan)
    return out
