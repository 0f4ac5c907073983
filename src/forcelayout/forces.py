"""A plan compiled to numpy arrays: the net force and torque of eqs. (2)–(3).

:class:`ForceModel` groups the plan's rule bindings by rule, so each rule is
called once per step with index arrays over all of its bindings, and adds the
always-on physical terms. It knows nothing about Box2D; the solver asks it for
forces and torques and moves the bodies.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from forcelayout import rules as registry
from forcelayout.geometry import RoomGeometry
from forcelayout.plan import SURFACE_RULES, Plan
from forcelayout.rules.base import ParamArrays, Rule, State
from forcelayout.rules.physical import PhysicalWeights, physical, repulsion

__all__ = ["RuleGroup", "ForceModel", "binding_weight", "SOFT_TORQUE_ON_HARD"]

#: Scale of soft rules' torques on objects that a hard rule (``Rule.hard``) orients.
SOFT_TORQUE_ON_HARD = 0.2


@dataclass
class RuleGroup:
    """All bindings of one rule within a simulation.

    Attributes
    ----------
    rule : Rule
    i : ndarray of int, shape (B,)
        Row of each bound object in the state arrays.
    j : ndarray of int, shape (B,), or None
        Row of each target (binary rules).
    params : ParamArrays
        Parameters per binding; ``params.weight`` holds the base weights.
    spec_index : ndarray of int, shape (B,)
        Index of each binding in ``plan.rules``.
    """

    rule: Rule
    i: np.ndarray
    j: np.ndarray | None
    params: ParamArrays
    spec_index: np.ndarray
    unique_i: bool = field(init=False)

    def __post_init__(self) -> None:
        self.unique_i = len(np.unique(self.i)) == len(self.i)

    def at_temperature(self, temperature: float) -> ParamArrays:
        """Params with the weights multiplied by the annealing temperature."""
        return ParamArrays(self.params._fields, self.params.weight * temperature)


def binding_weight(plan: Plan, k: int, rule: Rule) -> float:
    """Effective weight of ``plan.rules[k]``.

    The binding's own ``weight`` if given, else the plan's ``weights[rule]``,
    else the rule's default :attr:`Rule.weight`.
    """
    spec = plan.rules[k]
    if spec.weight is not None:
        return float(spec.weight)
    return float(plan.weights.get(spec.rule, rule.weight))


class ForceModel:
    """Net force and torque on a set of objects of a plan.

    Parameters
    ----------
    plan : Plan
    ids : sequence of str, optional
        The objects simulated together (rows of the state arrays). Defaults to
        the plan's floor objects. Bindings whose object or target is not among
        them are left out (they belong to another simulation).
    room : RoomGeometry, optional
        Defaults to the plan's room.
    relations : bool, default True
        ``False`` zeroes object-object (binary) rules — the paper's
        −Relations ablation.
    physical_weights : PhysicalWeights, optional
        Strengths of the always-on terms; the plan's ``weights`` may scale
        ``repulsion``, ``boundary`` and ``alignment``.
    """

    def __init__(
        self,
        plan: Plan,
        ids: Sequence[str] | None = None,
        *,
        room: RoomGeometry | None = None,
        relations: bool = True,
        physical_weights: PhysicalWeights | None = None,
    ):
        self.plan = plan
        self.ids = tuple(ids) if ids is not None else tuple(o.id for o in plan.floor_objects())
        self.room = room if room is not None else RoomGeometry.from_room(plan.room)
        self.size = np.array([plan.object(i).size for i in self.ids], dtype=float).reshape(-1, 3)
        row = {oid: r for r, oid in enumerate(self.ids)}
        self.physical_weights = (physical_weights or PhysicalWeights()).scaled(plan.weights)
        n = len(self.ids)
        self.pi, self.pj = (a.astype(int) for a in np.triu_indices(n, k=1))

        buckets: dict[str, list[int]] = {}
        for k, spec in enumerate(plan.rules):
            if spec.rule in SURFACE_RULES or spec.object not in row:
                continue
            rule = registry.get_rule(spec.rule)
            if rule.kind == "surface":
                continue
            if rule.kind == "binary" and (spec.target not in row or not relations):
                continue
            buckets.setdefault(spec.rule, []).append(k)
        self.groups: list[RuleGroup] = []
        for name, ks in buckets.items():
            rule = registry.get_rule(name)
            specs = [plan.rules[k] for k in ks]
            i = np.array([row[s.object] for s in specs], dtype=int)
            j = (np.array([row[s.target] for s in specs], dtype=int)  # type: ignore[index]
                 if rule.kind == "binary" else None)
            params = [rule.Params.model_validate(s.params) for s in specs]
            w = np.array([binding_weight(plan, k, rule) for k in ks])
            self.groups.append(RuleGroup(rule, i, j, ParamArrays.from_models(params, w),
                                         np.array(ks, dtype=int)))

        # pairs that a binary rule relates may stand close; others keep walking room apart
        related = np.zeros((n, n), dtype=bool)
        for g in self.groups:
            if g.j is not None:
                related[g.i, g.j] = related[g.j, g.i] = True
        # soft torques yield on objects whose heading a hard rule fixes
        held = np.zeros(n, dtype=bool)
        for g in self.groups:
            if g.rule.hard:
                held[g.i] = True
        self.soft_torque_scale = np.where(held, SOFT_TORQUE_ON_HARD, 1.0)
        free = ~related[self.pi, self.pj]
        self.qi, self.qj = self.pi[free], self.pj[free]  # pairs that get walking room

    @property
    def n(self) -> int:
        """Number of simulated objects."""
        return len(self.ids)

    def state(self, pos: np.ndarray, yaw: np.ndarray) -> State:
        """A :class:`State` of these objects at the given poses."""
        return State(np.asarray(pos, dtype=float), np.asarray(yaw, dtype=float), self.size,
                     self.room, self.ids)

    def semantic(self, state: State, temperature: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
        """Sum of the rule forces and torques, scaled by ``temperature``.

        Includes the walking-room term between objects no rule relates
        (:class:`PhysicalWeights` ``passage``), annealed like the rules.
        """
        f = np.zeros((state.n, 2))
        tau = np.zeros(state.n)
        for g in self.groups:
            p = g.at_temperature(temperature)
            fi, ti = g.rule.force(state, g.i, g.j, p)
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
        w = self.physical_weights
        if w.passage > 0 and self.qi.size:  # walking room between unrelated objects
            fp, _ = repulsion(state, self.qi, self.qj, w, w.passage_range,
                              w.passage * temperature)
            f += fp
        return f, tau

    def net(self, state: State, temperature: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
        """Net force (N, 2) and torque (N,) on every object: eqs. (2) and (3).

        Semantic terms are scaled by the annealing ``temperature``; the
        physical terms (repulsion, boundary, alignment, door clearance) are
        not.
        """
        f, tau = self.semantic(state, temperature)
        fp, tp = self.physical(state)
        return f + fp, tau + tp

    def physical(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """The always-on terms alone (repulsion, boundary, alignment, door clearance)."""
        return physical(state, self.pi, self.pj, self.physical_weights)

    def satisfied(self, state: State) -> dict[int, bool]:
        """Whether each simulated binding is met: ``{plan rule index: bool}``."""
        out: dict[int, bool] = {}
        for g in self.groups:
            ok = np.asarray(g.rule.satisfied(state, g.i, g.j, g.params), dtype=bool)
            out.update(zip(g.spec_index.tolist(), ok.tolist(), strict=True))
        return out
