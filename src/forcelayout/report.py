"""Per-rule satisfaction of a finished layout (used by reports and validation)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from forcelayout import rules as registry
from forcelayout.forces import binding_weight
from forcelayout.rules.base import ParamArrays, State

if TYPE_CHECKING:
    from forcelayout.layout import Layout, RuleResult

__all__ = ["judge_rules", "layout_state"]


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
    state = layout_state(layout)
    row = {oid: k for k, oid in enumerate(state.ids)}
    verdict: dict[int, bool | None] = {}
    groups: dict[str, list[int]] = {}
    for k, spec in enumerate(plan.rules):
        rule = registry.get_rule(spec.rule)
        placed = spec.object in row and (spec.target is None or spec.target in row)
        if not placed or (rule.kind == "binary" and spec.target is None):
            verdict[k] = None
            continue
        groups.setdefault(spec.rule, []).append(k)
    for name, ks in groups.items():
        rule = registry.get_rule(name)
        specs = [plan.rules[k] for k in ks]
        i = np.array([row[s.object] for s in specs], dtype=int)
        j = (np.array([row[s.target] for s in specs], dtype=int)  # type: ignore[index]
             if all(s.target is not None for s in specs) else None)
        p = ParamArrays.from_models([rule.Params.model_validate(s.params) for s in specs],
                                    np.array([binding_weight(plan, k, rule) for k in ks]))
        ok = np.asarray(rule.satisfied(state, i, j, p), dtype=bool)
        verdict.update(zip(ks, ok.tolist(), strict=True))
    return [RuleResult(k, s.rule, s.object, s.target, verdict[k]) for k, s in enumerate(plan.rules)]
