"""Binary rules: an object related to a target object."""

from __future__ import annotations

import numpy as np
from pydantic import Field

from forcelayout.rules.base import ParamArrays, Rule, State

__all__ = ["NextTo"]


class NextTo(Rule):
    """Stand beside the target: footprint gap at most ``distance`` metres."""

    kind = "binary"
    weight = 1.5
    reaction = 0.2

    class Params(Rule.Params):
        distance: float = Field(0.15, gt=0, description="Largest footprint gap, m.")

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        d = state.pos[j] - state.pos[i]
        u = d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-9)
        gap = state.gap(i, j)
        pull = np.clip(gap - 0.5 * p.distance, 0.0, 2.0)
        return u * (p.weight * 4.0 * pull)[:, None], np.zeros(len(i))

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        return state.gap(i, j) <= p.distance
