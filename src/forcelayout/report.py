"""Per-rule satisfaction of a finished layout (used by reports and validation)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from forcelayout.bindings import compile_plan
from forcelayout.rules.base import State

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
    verdict = compile_plan(plan).judge(layout_state(layout))
    return [RuleResult(k, s.rule, s.object, s.target, verdict.get(k))
            for k, s in enumerate(plan.rules)]
