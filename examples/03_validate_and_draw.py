"""Validate layouts and draw them: the deterministic checks and top-down pictures.

Shows how to estimate a plan's feasibility before sampling
(:func:`forcelayout.diagnose.feasibility`), run
:func:`forcelayout.validate.check_layout` on a layout you built by hand and
on one the solver made, read its report (failures, free floor fraction,
unreachable objects and what blocks them), see that a rug is no obstacle and
that a wardrobe must keep out of a window's clearance zone, tighten a
threshold, name the dominant cause of failed samples
(:func:`forcelayout.diagnose.dominant_cause`), and draw the layouts as PNG
pictures with the free floor shaded and failures listed. Needs only the core
install.

Run: ``python examples/03_validate_and_draw.py [OUT_DIR]``
"""

# %%
import math
import sys
import tempfile
from pathlib import Path

import forcelayout as fl
from forcelayout.diagnose import dominant_cause, feasibility
from forcelayout.render import draw_layout, draw_many
from forcelayout.validate import check_layout

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
out.mkdir(parents=True, exist_ok=True)

# %% A small bedroom plan, written inline (same format as the bundled plans).
plan = fl.Plan.from_dict({
    "name": "small_bedroom",
    "room": {"polygon": [[0, 0], [4, 0], [4, 3.6], [0, 3.6]], "height": 2.6,
             "doors": [{"wall": 0, "offset": 2.6, "width": 0.9}],
             # nothing taller than the sill may stand within 0.5 m in front of the window
             "windows": [{"wall": 2, "offset": 2.0, "width": 1.2, "sill": 0.9,
                          "clearance": 0.5}]},
    "areas": [{"name": "sleeping"}, {"name": "work"}, {"name": "storage"}],
    "objects": [
        {"id": "bed", "category": "bed", "size": [1.4, 2.0, 0.5], "area": "sleeping",
         "primary": True},
        {"id": "nightstand", "category": "nightstand", "size": [0.45, 0.4, 0.5],
         "area": "sleeping"},
        {"id": "desk", "category": "desk", "size": [1.2, 0.6, 0.75], "area": "work",
         "primary": True},
        {"id": "desk_chair", "category": "chair", "size": [0.5, 0.5, 0.9], "area": "work"},
        {"id": "wardrobe", "category": "wardrobe", "size": [1.0, 0.6, 2.0], "area": "storage",
         "primary": True},
        # a rug is walkable by default (category rug/mat/..., or at most 5 cm high):
        # furniture may stand on it and it blocks no one
        {"id": "rug", "category": "rug", "size": [1.6, 1.2, 0.01], "area": "sleeping"},
    ],
    "rules": [
        {"rule": "at_wall", "object": "bed"},
        {"rule": "next_to", "object": "nightstand", "target": "bed"},
        {"rule": "at_wall", "object": "desk"},
        {"rule": "in_front_of", "object": "desk_chair", "target": "desk"},
        {"rule": "facing", "object": "desk_chair", "target": "desk"},
        {"rule": "at_wall", "object": "wardrobe"},
    ],
})

# %% Before sampling: can the room hold what the plan asks for?
print(feasibility(plan))

# %% A layout by hand: poses are footprint centres (m) and yaw (rad, 0 = front faces +y).
P = fl.Pose
by_hand = fl.Layout(plan, {
    "bed": P(0.7, 2.6, math.pi),             # head against the top wall
    "nightstand": P(1.65, 3.4, math.pi),
    "desk": P(3.7, 1.8, math.pi / 2),        # against the right wall, facing -x
    "desk_chair": P(3.05, 1.8, -math.pi / 2),
    "wardrobe": P(0.3, 0.7, -math.pi / 2),   # against the left wall
    "rug": P(1.2, 1.8, 0.0),                 # under the foot of the bed
})
report = check_layout(by_hand)
print("by hand:", report)

# %% The same layout with the chair pushed into the door's swing area.
blocked = fl.Layout(plan, {**by_hand.poses, "desk_chair": P(2.6, 0.4, 0.0)})
report = check_layout(blocked)
print("blocked:", report)
print("unreachable primary objects:", report.unreachable, "blocked by:", report.blocked_by)

# %% A 2 m wardrobe in front of the window fails the window check; the rug never collides.
at_window = fl.Layout(plan, {**by_hand.poses, "wardrobe": P(2.6, 3.3, math.pi)})
print("wardrobe at the window:", check_layout(at_window))

# %% Thresholds are keyword arguments: a bigger agent needs more free floor.
strict = check_layout(by_hand, agent_radius=0.3, min_free_fraction=0.6)
print(f"agent radius 0.3 m: {strict.free_fraction:.0%} free ->",
      "ok" if strict.ok else strict.failures)

# %% A layout from the solver, checked the same way (fixed seed: same layout every run).
solved = fl.solve(plan, seed=7)
print("solved:", check_layout(solved))

# %% After a run: why did samples fail? One line over all the sample reports.
reports = [fl.solve(plan, seed=s).report for s in range(6)]
print("dominant cause:", dominant_cause(reports) or "no sample failed")

# %% Pictures: one layout with the free floor shaded, and a contact sheet.
draw_layout(by_hand, out / "by_hand.png", show_free_space=True)
draw_layout(blocked, out / "blocked.png")
draw_many([by_hand, blocked, at_window, solved], out / "sheet.png", cols=4)
print(f"wrote {out / 'by_hand.png'}, {out / 'blocked.png'}, {out / 'sheet.png'}")
