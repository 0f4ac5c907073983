"""An example forcelayout rule plugin: ``near_plant``.

Installed with ``pip install -e examples/plugin``, it registers the rule
through the entry-point group ``forcelayout.rules``; forcelayout imports this
module only when a plan names ``near_plant``.
"""

from __future__ import annotations

import numpy as np
from pydantic import Field

from forcelayout.rules import ParamArrays, Rule, StartHint, State
from forcelayout.rules.shaping import ramp, unit

__all__ = ["NearPlant"]


class NearPlant(Rule):
    """Beside a potted plant: footprint gap to the target plant at most `distance` metres.

    A soft relation for reading corners (an armchair by a ficus). The force
    pulls the object towards the plant until the gap is a little below
    ``distance`` and is zero from there on; the plant itself does not move.
    """

    target = "required"  # every binding names the plant
    # start near the plant, anywhere within `distance` of it (a weak bond, like `near`)
    start = StartHint(parent=6, reach="distance")
    relation = True  # counted by the relational diversity metric
    closeness = "close"  # keeps the object close: contradicts far_from the same plant
    aliases = ("by_plant",)  # a near-miss name the plan autofix reads as this rule
    weight = 1.0  # a soft relation: weaker than at_wall (3.0) and physical repulsion

    class Params(Rule.Params):
        distance: float = Field(0.5, gt=0, description="Largest footprint gap to the plant, m.")

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        u, _ = unit(state.pos[j] - state.pos[i])  # (B, 2): every binding at once
        gap = state.separation(i, j)  # fast lower bound of the gap, metres
        goal = p.distance - np.minimum(0.1, 0.5 * p.distance)  # aim a little inside
        pull = ramp(gap - goal)  # linear, clipped: nothing explodes
        return u * (p.weight * pull)[:, None], np.zeros(len(i))

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        return state.gap(i, j) <= p.distance  # the exact gap
