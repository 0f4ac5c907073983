"""Hierarchy: the scene graph, area variants, combinatorial assembly and surfaces.

Shows stage P in full on the bundled bedroom: the scene graph drawn as a
picture, a few local variants of each functional area, how many distinct
rooms come from combining them, and where the off-floor objects end (the
lamp on the nightstand, the painting above the bed, the ceiling light).
Needs only the core install.

Run: ``python examples/06_hierarchy.py [OUT_DIR]``
"""

# %%
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import networkx as nx  # noqa: E402
import numpy as np  # noqa: E402

import forcelayout as fl  # noqa: E402
from forcelayout.hierarchy import VariantLibrary, assemble, scene_graph  # noqa: E402
from forcelayout.surfaces import place_surfaces  # noqa: E402

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
out.mkdir(parents=True, exist_ok=True)
plan = fl.load_plan("bedroom")

# %% The scene graph: solid edges are parent -> child (on_top, above, bonds),
# dashed ones are peer constraints (facing, near, ...).
g = scene_graph(plan)
for a, b, d in g.edges(data=True):
    print(f"{a:>14} {'->' if d['strong'] else '..'} {b:<14} {', '.join(d['rules'])}")
fig, ax = plt.subplots(figsize=(7, 5))
layout_xy = nx.spring_layout(g, seed=1)
strong = [(a, b) for a, b, s in g.edges(data="strong") if s]
weak = [(a, b) for a, b, s in g.edges(data="strong") if not s]
nx.draw_networkx_nodes(g, layout_xy, ax=ax, node_size=300, node_color="#cde")
nx.draw_networkx_labels(g, layout_xy, ax=ax, font_size=8)
nx.draw_networkx_edges(g, layout_xy, edgelist=strong, ax=ax, arrows=True)
nx.draw_networkx_edges(g, layout_xy, edgelist=weak, ax=ax, style="dashed", arrows=True)
ax.set_axis_off()
fig.savefig(out / "scene_graph.png", dpi=100)
plt.close(fig)

# %% Two local variants per area, made once; 2 ** 3 combinations of them.
lib = VariantLibrary(plan, 2, seed=0)
for area, variants in lib.variants.items():
    print(f"{area}: {[tuple(round(x, 2) for x in v.extent) for v in variants]} (w, d in m)")
print(f"{lib.n_combinations} combinations")

# %% Instantiate every combination: a room-level simulation arranges the
# areas' rectangles, then tops, walls and the ceiling are placed.
rng = np.random.default_rng(0)
rooms = []
for k, combo in enumerate(lib.combinations()):
    floor, _, _ = assemble(plan, combo, rng)
    surf = place_surfaces(plan, floor, rng)
    layout = fl.Layout(plan, surf.poses, seed=k)
    rooms.append(layout)
    layout.picture(out / f"combination_{k}.png")
print(f"{len(rooms)} rooms from {lib.v} variants per area")

# %% Every object ends with a full pose (x, y, yaw, z, surface).
for oid in ("lamp", "painting", "ceiling_light"):
    p = rooms[0].poses[oid]
    print(f"{oid}: surface={p.surface} z={p.z:.2f} m at ({p.x:.2f}, {p.y:.2f})")
print(f"wrote {out}")
