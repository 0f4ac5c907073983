"""Export a layout as a 3D scene: GLB, OBJ, USD with physics, MJCF, Habitat, and a 3D picture.

Shows how to solve a bundled plan once, turn the layout into a trimesh scene
(floor, walls with door and window gaps, a box per object at its pose), write
it in the formats robotics users load (GLB for viewers, USD with UsdPhysics
for Isaac Sim, MJCF for MuJoCo, a habitat-sim scene dataset folder), all of
them at once with ``write_exports``, and draw an isometric picture without a
GPU. Needs the export extra: ``pip install "forcelayout[export]"``.

Run: ``python examples/04_export_scene.py [OUT_DIR]``
"""

# %%
import sys
import tempfile
from pathlib import Path

import forcelayout as fl
from forcelayout import export

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
out.mkdir(parents=True, exist_ok=True)

# %% One layout of the bundled bedroom plan (same seed, same layout).
layout = fl.solve(fl.examples.load_example("bedroom"), seed=0)
print(layout)

# %% The scene in the plan's frame: metres, z up. Node names are the object ids.
scene = export.scene(layout)
objects = [n for n in scene.graph.nodes_geometry if not n.startswith("room")]
print(f"{len(objects)} object boxes, room extent {scene.extents.round(2)} m (x, y, z)")
transform, _ = scene.graph["bed"]
print("bed bottom centre:", transform[:3, 3].round(2))

# %% Files: GLB and OBJ are written y up (glTF's convention), USD and MJCF z up.
# Chairs and lamps become movable bodies in USD, MJCF and Habitat; the rest is static.
glb = export.export_glb(layout, out / "bedroom.glb")
obj = export.export_obj(layout, out / "bedroom.obj")
usda = export.export_usd(layout, out / "bedroom.usda", movable=["chair", "lamp"])
mjcf = export.export_mjcf(layout, out / "bedroom.xml", movable=["chair", "lamp"])
habitat = export.export_habitat(layout, out / "habitat")
for path in (glb, obj, usda, mjcf, habitat):
    print("wrote", path)

# %% Or every simulator format at once, each file moved into place only when complete.
for path in export.write_exports(layout, out / "all" / "bedroom_0", export.EXPORT_FORMATS):
    print("wrote", path)

# %% A 3D picture (parallel projection, painter's algorithm; matplotlib only).
export.isometric(layout, out / "bedroom_3d.png")
layout.picture(out / "bedroom_top.png")
print(f"wrote pictures to {out}")
