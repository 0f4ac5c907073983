"""Per-rule satisfaction of a finished layout (used by reports and validation)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from forcelayout.bindings import compile_plan, group_bindings
from forcelayout.rules.base import State

if TYPE_CHECKING:
    from forcelayout.layout import Layout, RuleResult

__all__ = ["judge_rules", "judge_rules_many", "layout_state"]


def layout_state(layout: Layout) -> State:
    """Every placed object of a layout as a :class:`State` (with ``z`` and surfaces)."""
    ids = layout.ids()
    st = layout.state(ids)
    st.z = np.array([layout.poses[i].z for i in ids], dtype=float)
    st.surfaces = tuple(layout.poses[i].surface for i in ids)
    return st


def judge_rules(layout: Layout) -> list[RuleResult]:
    """Judge every rule binding of the layout's plan with the rule's own check.

    Returns one :class:`~forcelayout.layout.RuleResult` per ``plan.rules``
    entry, in order; ``satisfied`` is ``None`` where the object or target is
    not placed or the target is an area rather than an object.
    """
    from forcelayout.layout import RuleResult

    plan = layout.plan
    verdict = compile_plan(plan).judge(layout_state(layout))
    return [RuleResult(k, s.rule, s.object, s.target, verdict.get(k))
            for k, s in enumerate(plan.rules)]


def judge_rules_many(layouts: Sequence[Layout]) -> list[list[RuleResult]]:
    """:func:`judge_rules` of many layouts, the same results, faster.

    Layouts of one plan with the same objects placed are judged on one
    stacked :class:`State` (a rule that is not ``batched`` once per layout).
    """
    from forcelayout.layout import RuleResult

    out: list[list[RuleResult] | None] = [None] * len(layouts)
    groups: dict[tuple[int, tuple[str, ...]], list[int]] = {}
    for k, lay in enumerate(layouts):
        groups.setdefault((id(lay.plan), tuple(lay.ids())), []).append(k)
    for (_, ids), ks in groups.items():
        if len(ks) == 1:
            out[ks[0]] = judge_rules(layouts[ks[0]])
            continue
        plan = layouts[ks[0]].plan
        states = [layout_state(layouts[k]) for k in ks]
        nb = len(states)
        first = states[0]
        stacked = State(np.concatenate([s.pos for s in states]).reshape(-1, 2),
                        np.concatenate([s.yaw for s in states]),
                        np.tile(first.size, (nb, 1)), first.room, ids * nb,
                        np.concatenate([s.z for s in states]),
                        sum((s.surfaces for s in states), ()), samples=nb)
        row = {oid: r for r, oid in enumerate(ids)}
        met: dict[int, np.ndarray] = {}
        for g in group_bindings(compile_plan(plan).judged(ids), row):
            met.update(zip(g.index.tolist(), g.satisfied_stacked(stacked).T, strict=True))
        for b, k in enumerate(ks):
            out[k] = [RuleResult(q, s.rule, s.object, s.target,
                                 bool(met[q][b]) if q in met else None)
                      for q, s in enumerate(plan.rules)]
    return out  # type: ignore[return-value]
