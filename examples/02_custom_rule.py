"""Writing a rule: one small class, registered by name, used in a plan.

Shows the plugin pattern of forcelayout: a ``Rule`` subclass with a
``Params`` model (defaults and units), a vectorised ``force`` (all bindings of
the rule at once, numpy arrays in, force and torque out) and a ``satisfied``
check, registered with ``@register``. The new rule ``look_out_window`` puts
an object near the nearest window and turns it to face it (a reading chair
looking out). ``check_rule`` verifies the rule keeps the contract before it
is used. Needs only the core install; runs headless in a few seconds.

Run: ``python examples/02_custom_rule.py``
"""

# %%
import numpy as np
from pydantic import Field

import forcelayout as fl
from forcelayout.rules import ParamArrays, Rule, StartHint, State, register
from forcelayout.rules.shaping import ramp, signed_angle, turn, unit
from forcelayout.testing import check_rule


# %% The rule: one class. Arrays are indexed by binding: i (B,) are object rows.
@register("look_out_window")
class LookOutWindow(Rule):
    """Near the nearest window and facing it: centre within ``distance`` m, within 30°."""

    target = "none"  # relates an object to the room ("required": bindings name a target j)
    start = StartHint(place="window")  # start poses put the object near a window
    weight = 1.5  # soft placement; physical repulsion stays the strongest term

    class Params(Rule.Params):
        distance: float = Field(1.5, gt=0, description="Largest centre-to-window distance, m.")
        max_angle: float = Field(30.0, gt=0, le=180,
                                 description="Largest angle between front and window, deg.")

    @staticmethod
    def _window(state: State, i: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Vector to the nearest window's centre (B, 2) and its length (B,), metres."""
        d = state.room.windows.centre[None, :, :] - state.pos[i, None, :]  # (B, K, 2)
        k = np.argmin((d * d).sum(2), axis=1)
        v = d[np.arange(len(i)), k]
        return v, np.sqrt((v * v).sum(1))

    def force(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        if len(state.room.windows) == 0:  # nothing to look at: no force
            return np.zeros((len(i), 2)), np.zeros(len(i))
        v, dist = self._window(state, i)
        u, _ = unit(v)
        # pull until a little inside `distance`, linear and clipped so nothing explodes
        pull = ramp(dist - (p.distance - 0.1))
        # turn the front towards the window (CCW torque for a target on the left),
        # leaving small errors alone
        err = signed_angle(state.front[i], v)
        torque = turn(err, 0.25 * np.radians(p.max_angle), p.weight)
        return u * (p.weight * pull)[:, None], torque

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        if len(state.room.windows) == 0:
            return np.zeros(len(i), dtype=bool)
        v, dist = self._window(state, i)
        err = signed_angle(state.front[i], v)
        return (dist <= p.distance) & (np.abs(err) <= np.radians(p.max_angle))


# %% Check the rule keeps the contract: finite forces of the right shapes,
# translation invariance, no pull where its own check is met.
report = check_rule("look_out_window", n_states=10, seed=0)
print(f"check_rule: {report['satisfied_before']:.0%} -> {report['satisfied_after']:.0%} of "
      "random bindings met after following the rule's force")

# %% Use it in a plan like any built-in rule.
plan = fl.Plan.from_dict({
    "name": "reading_nook",
    "room": {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]], "height": 2.7,
             "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}],
             "windows": [{"wall": 2, "offset": 2.0, "width": 1.2}]},
    "objects": [
        {"id": "armchair", "category": "armchair", "size": [0.8, 0.8, 0.9], "primary": True},
        {"id": "side_table", "category": "side_table", "size": [0.45, 0.45, 0.55]},
        {"id": "bookshelf", "category": "bookshelf", "size": [0.8, 0.35, 1.8]},
    ],
    "rules": [
        {"rule": "look_out_window", "object": "armchair"},
        {"rule": "next_to", "object": "side_table", "target": "armchair"},
        {"rule": "at_wall", "object": "bookshelf"},
    ],
})

# %% Solve a few samples (fixed seeds) and print how each rule fared.
for seed in range(3):
    layout = fl.solve(plan, seed, check=False)
    met = ", ".join(f"{r.rule}({r.object}): {'met' if r.satisfied else 'unmet'}"
                    for r in layout.rule_report())
    chair = layout.poses["armchair"]
    print(f"seed {seed}: armchair at ({chair.x:.2f}, {chair.y:.2f}) m, "
          f"yaw {np.degrees(chair.yaw):.0f} deg; {met}")
