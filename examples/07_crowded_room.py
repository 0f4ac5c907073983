"""A crowded kids' room with a rug: walkable covers, access zones, repairs, and saying why.

Shows what keeps a small room usable: the rug is a walkable cover (furniture
stands on it, the checks ignore it) laid ``under`` the play table; the beds,
wardrobe and desk keep their access zones free; a sample whose floor fails a
check or a rule is repaired (only the objects at fault move) before it is
given up, and the report says how. Before sampling, ``feasibility`` says how
tight the plan is; after a short run, ``result.why`` names the dominant
cause. Needs only the core install; runs headless in a few seconds.

Run: ``python examples/07_crowded_room.py``
"""

# %%
import warnings

import forcelayout as fl
from forcelayout.diagnose import feasibility

plan = fl.Plan.from_dict({
    "name": "kids_room",
    "room": {"polygon": [[0, 0], [3.4, 0], [3.4, 3.2], [0, 3.2]], "height": 2.6,
             "doors": [{"wall": 0, "offset": 2.9, "width": 0.8}],
             "windows": [{"wall": 2, "offset": 1.7, "width": 1.2, "sill": 0.9}]},
    "objects": [
        {"id": "bed_1", "category": "bed", "size": [0.9, 2.0, 0.45], "primary": True},
        {"id": "bed_2", "category": "bed", "size": [0.9, 2.0, 0.45], "primary": True},
        {"id": "wardrobe", "category": "wardrobe", "size": [1.0, 0.55, 1.9], "primary": True},
        {"id": "table", "category": "play_table", "size": [0.7, 0.5, 0.5]},
        {"id": "rug", "category": "rug", "size": [1.4, 1.0, 0.01]},
    ],
    "rules": [
        {"rule": "at_wall", "object": "bed_1"},
        {"rule": "at_wall", "object": "bed_2"},
        {"rule": "at_wall", "object": "wardrobe"},
        {"rule": "under", "object": "rug", "target": "table"},
    ],
})

# %% How tight is it, before any simulation?
print(feasibility(plan))
print("rug is walkable:", plan.object("rug").is_walkable)

# %% Sample, and see what the repairs did.
with warnings.catch_warnings():
    warnings.simplefilter("ignore")  # a short run warns; result.why says the same
    result = fl.generate(plan, 4, seed=0, max_attempts=12)
print(f"{len(result)} layouts from {result.attempted} samples")
for report in result.reports:
    status = "ok" if report.valid else "; ".join(report.failures[:1])
    print(f"  seed {report.seed}: {status}" + (f"  [{'; '.join(report.repairs)}]"
                                              if report.repairs else ""))
if result.why:
    print("why fewer:", result.why)

# %% Pictures draw the rug beneath the furniture.
if len(result):
    result[0].picture("kids_room.png")
    print("wrote kids_room.png")
