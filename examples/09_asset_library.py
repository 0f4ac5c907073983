"""An asset library of procedural meshes, a plan grounded to it, a scene with the real meshes.

Builds a small asset library (``assets.json`` + one mesh file per asset) out
of trimesh primitives: every piece of furniture is a handful of boxes and
cylinders, described in ``assets.json`` by what it really looks like. Some
files use other conventions on purpose (a y-up GLB facing +z, an OBJ in
centimetres, a PLY facing -y), as real libraries do; ``assets.json`` says so
and the library turns them to the plan's frame (metres, z up, front +y).

Then it grounds the bundled living-room plan to the library (each object gets
its best asset, scaled uniformly to its planned size), generates one valid layout
of the grounded plan and writes it as GLB with the meshes in place. Retrieval
uses the packaged sentence-embedding model with ``forcelayout[grounding]``
installed, and a lexical fallback without it.

Needs trimesh (``pip install "forcelayout[grounding]"`` or ``[export]``).

Run: ``python examples/09_asset_library.py [OUT_DIR]`` — the library lands
in ``OUT_DIR/assets``. ``build_library(folder)`` is importable on its own.
"""

# %%
from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

import numpy as np
import trimesh

# %% Primitives: every part is given by its size and where its bottom centre sits.


def box(w: float, d: float, h: float, x: float = 0.0, y: float = 0.0, z: float = 0.0):
    """A box of size (w, d, h) whose bottom centre is at (x, y, z)."""
    m = trimesh.creation.box(extents=(w, d, h))
    m.apply_translation((x, y, z + h / 2))
    return m


def cyl(r: float, h: float, x: float = 0.0, y: float = 0.0, z: float = 0.0, sections: int = 24):
    """An upright cylinder of radius r and height h whose bottom centre is at (x, y, z)."""
    m = trimesh.creation.cylinder(radius=r, height=h, sections=sections)
    m.apply_translation((x, y, z + h / 2))
    return m


def legs(w: float, d: float, h: float, t: float = 0.05, inset: float = 0.03):
    """Four square legs under a w x d top, h high."""
    dx, dy = w / 2 - inset - t / 2, d / 2 - inset - t / 2
    return [box(t, t, h, sx * dx, sy * dy) for sx in (-1, 1) for sy in (-1, 1)]


def join(*parts):
    return trimesh.util.concatenate([p for part in parts
                                     for p in (part if isinstance(part, list) else [part])])


# %% The furniture, in the plan's frame: metres, z up, front along +y, bottom at z = 0.


def sofa(w: float, d: float = 0.9, h: float = 0.85, seats: int = 3):
    arm = 0.18
    parts = [box(w, d, 0.42),                                      # seat base
             box(w, 0.2, h - 0.42, 0, -d / 2 + 0.1, 0.42),          # back
             box(arm, d, 0.62, -w / 2 + arm / 2), box(arm, d, 0.62, w / 2 - arm / 2)]
    cw = (w - 2 * arm) / seats
    parts += [box(cw - 0.02, d - 0.25, 0.12, -w / 2 + arm + cw * (k + 0.5), 0.1, 0.42)
              for k in range(seats)]                                 # cushions
    return join(parts)


def armchair(w: float = 0.8, d: float = 0.8, h: float = 0.95, wing: bool = False):
    parts = [box(w, d, 0.42), box(w, 0.18, h - 0.42, 0, -d / 2 + 0.09, 0.42),
             box(0.15, d, 0.62, -w / 2 + 0.075), box(0.15, d, 0.62, w / 2 - 0.075)]
    if wing:
        parts += [box(0.08, 0.25, 0.35, sx * (w / 2 - 0.04), -d / 2 + 0.2, h - 0.35)
                  for sx in (-1, 1)]
    return join(parts)


def bed(w: float, d: float = 2.0, h: float = 0.55):
    return join(box(w, d - 0.05, 0.3), box(w - 0.04, d - 0.1, 0.2, 0, 0.02, 0.3),  # frame, mattress
                box(w, 0.06, h + 0.45, 0, -d / 2 + 0.03),                       # headboard
                box(0.5, 0.35, 0.1, -w / 4, -d / 2 + 0.3, 0.5) if w > 1.2 else [],
                box(0.5, 0.35, 0.1, w / 4 if w > 1.2 else 0, -d / 2 + 0.3, 0.5))


def cabinet(w: float, d: float, h: float, drawers: int = 0, doors: int = 0):
    parts = [box(w, d, h)]
    for k in range(drawers):  # drawer fronts on the front face
        parts.append(box(w - 0.06, 0.02, h / drawers - 0.04, 0, d / 2 + 0.01,
                         k * h / drawers + 0.02))
    for k in range(doors):
        dw = w / doors
        parts.append(box(dw - 0.03, 0.02, h - 0.06, -w / 2 + dw * (k + 0.5), d / 2 + 0.01, 0.03))
    return join(parts)


def table(w: float, d: float, h: float, top: float = 0.04):
    return join(box(w, d, top, 0, 0, h - top), legs(w, d, h - top))


def round_table(r: float, h: float, pedestal: bool = True):
    parts = [cyl(r, 0.04, 0, 0, h - 0.04)]
    parts += [cyl(0.06, h - 0.04), cyl(r * 0.5, 0.03)] if pedestal else legs(r * 1.4, r * 1.4, h)
    return join(parts)


def chair(w: float = 0.45, d: float = 0.45, h: float = 0.9, office: bool = False):
    if office:
        base = [box(0.6, 0.06, 0.05), box(0.06, 0.6, 0.05), cyl(0.03, 0.4, 0, 0, 0.05)]
        return join(base, box(w, d, 0.08, 0, 0, 0.45), box(w, 0.06, h - 0.53, 0, -d / 2, 0.53))
    return join(legs(w, d, 0.45, t=0.04), box(w, d, 0.04, 0, 0, 0.45),
                box(w, 0.04, h - 0.49, 0, -d / 2 + 0.02, 0.49))


def bookshelf(w: float, d: float, h: float, shelves: int = 5):
    t = 0.02
    parts = [box(t, d, h, -w / 2 + t / 2), box(t, d, h, w / 2 - t / 2),
             box(w, 0.01, h, 0, -d / 2 + 0.005)]
    parts += [box(w, d, t, 0, 0, k * (h - t) / shelves) for k in range(shelves + 1)]
    return join(parts)


def plant(r: float, h: float):
    return join(cyl(r * 0.6, h * 0.3), trimesh.creation.icosphere(subdivisions=1, radius=r)
                .apply_translation((0, 0, h - r)))


def lamp(r: float, h: float, floor: bool = False):
    shade = trimesh.creation.cone(radius=r, height=r * 1.2, sections=16)
    shade.apply_translation((0, 0, h - r * 1.2))
    return join(cyl(r * (0.8 if floor else 0.5), 0.03), cyl(0.012, h - r * 1.2), shade)


def panel(w: float, d: float, h: float, frame: float = 0.03):
    return join(box(w, d, h), box(w - 2 * frame, d * 0.5, h - 2 * frame, 0, d * 0.5, frame))


def pendant(r: float, h: float):
    return join(cyl(0.01, h * 0.6, 0, 0, h * 0.4), cyl(r, h * 0.4, sections=32))


# %% The library: id, file, category, honest description, tags, and the mesh.

ASSETS = [
    ("sofa_3seat", "sofa_3seat.glb", "sofa",
     "three-seat fabric sofa with two armrests, a low back and three seat cushions",
     ["fabric", "living room"],
     lambda: sofa(2.1, 0.9, 0.85, 3)),
    ("sofa_2seat", "sofa_2seat.glb", "sofa",
     "small two-seat loveseat in grey fabric with two seat cushions", ["fabric", "compact"],
     lambda: sofa(1.5, 0.85, 0.8, 2)),
    ("armchair_club", "armchair_club.glb", "armchair",
     "deep upholstered club armchair with wide arms, a comfortable lounge seat for "
     "relaxing", ["fabric"], lambda: armchair()),
    ("armchair_wing", "armchair_wing.obj", "armchair",
     "wingback armchair with a high back and side wings, for reading by the fire",
     ["fabric", "reading"],
     lambda: armchair(0.75, 0.75, 1.1, wing=True)),
    ("bed_double", "bed_double.glb", "bed",
     "double bed for two people with a wooden headboard and two pillows", ["wood", "bedroom"],
     lambda: bed(1.6)),
    ("bed_single", "bed_single.glb", "bed",
     "narrow single bed for one person, with a headboard and one pillow",
     ["bedroom", "child"], lambda: bed(0.95)),
    ("nightstand_wood", "nightstand_wood.glb", "nightstand",
     "small wooden nightstand with two drawers, stands beside a bed", ["wood", "bedroom"],
     lambda: cabinet(0.45, 0.4, 0.5, drawers=2)),
    ("wardrobe_2door", "wardrobe_2door.glb", "wardrobe",
     "tall two-door wardrobe cabinet with a hanging rail, a bedroom cupboard for storing "
     "clothes", ["bedroom", "storage"],
     lambda: cabinet(1.2, 0.6, 2.0, doors=2)),
    ("dresser_4drawer", "dresser_4drawer.glb", "dresser",
     "low dresser, a chest of four drawers for folded clothes", ["bedroom", "storage"],
     lambda: cabinet(0.9, 0.45, 0.8, drawers=4)),
    ("desk_study", "desk_study.glb", "desk",
     "rectangular study desk on four legs, a work table for a computer or homework",
     ["office", "work"], lambda: table(1.2, 0.6, 0.75)),
    ("chair_office", "chair_office.glb", "chair",
     "swivel office chair with a padded seat and a high back on a cross-shaped base, for working "
     "at a desk", ["office"],
     lambda: chair(0.55, 0.55, 1.05, office=True)),
    ("chair_dining", "chair_dining.ply", "chair",
     "wooden dining chair with four legs and a straight back, to sit at a table",
     ["wood", "dining"],
     lambda: chair()),
    ("table_round", "table_round.glb", "table",
     "round dining table on a central pedestal, seats four", ["dining", "wood"],
     lambda: round_table(0.5, 0.75)),
    ("table_rect", "table_rect.glb", "table",
     "long rectangular dining table on four legs, seats six people for meals", ["dining", "wood"],
     lambda: table(1.8, 0.9, 0.75)),
    ("coffee_table_low", "coffee_table_low.glb", "coffee_table",
     "low rectangular oak coffee table to stand in front of a sofa", ["living room", "wood"],
     lambda: table(1.1, 0.6, 0.42, top=0.05)),
    ("side_table_round", "side_table_round.glb", "side_table",
     "small round side table on one leg, to stand beside an armchair or "
     "sofa", ["living room"], lambda: round_table(0.25, 0.55)),
    ("tv_stand_low", "tv_stand_low.glb", "tv_stand",
     "low media cabinet with three doors, a stand for a television and a games "
     "console", ["living room"],
     lambda: cabinet(1.6, 0.45, 0.5, doors=3)),
    ("bookshelf_tall", "bookshelf_tall.glb", "bookshelf",
     "tall open bookshelf with five shelves for books", ["storage", "books"],
     lambda: bookshelf(1.0, 0.35, 2.0)),
    ("cabinet_filing", "cabinet_filing.obj", "cabinet",
     "metal filing cabinet with three drawers for documents and folders", ["office", "documents"],
     lambda: cabinet(0.45, 0.6, 0.7, drawers=3)),
    ("sideboard_long", "sideboard_long.glb", "sideboard",
     "long low sideboard cabinet with two doors, storage for dishes and tableware in a dining "
     "room", ["dining", "storage"],
     lambda: cabinet(1.6, 0.45, 0.8, doors=2)),
    ("plant_potted", "plant_potted.glb", "plant",
     "leafy green indoor plant growing in a round pot",
     ["green", "decor"], lambda: plant(0.25, 1.0)),
    ("lamp_table", "lamp_table.glb", "lamp",
     "small table lamp with a cone-shaped fabric shade, gives light for reading",
     ["light", "bedroom"], lambda: lamp(0.12, 0.4)),
    ("lamp_floor", "lamp_floor.glb", "floor_lamp",
     "tall floor lamp with a shade on a heavy round base, lights a corner of a living room",
     ["light", "living room"],
     lambda: lamp(0.2, 1.7, floor=True)),
    ("painting_framed", "painting_framed.glb", "painting",
     "framed landscape picture, a piece of decoration to hang on a wall", ["decor", "art"],
     lambda: panel(0.9, 0.04, 0.6)),
    ("light_pendant", "light_pendant.glb", "ceiling_light",
     "round pendant light hanging from the ceiling on a "
     "cord", ["light"], lambda: pendant(0.25, 0.3)),
    ("fridge_tall", "fridge_tall.glb", "refrigerator",
     "tall kitchen refrigerator with a freezer, keeps food cold", ["kitchen", "appliance"],
     lambda: cabinet(0.6, 0.65, 1.8, doors=1)),
    ("tv_flat", "tv_flat.glb", "television",
     "flat-screen television for watching films and shows", ["living "
     "room", "screen"], lambda: panel(1.2, 0.06, 0.7)),
    ("monitor_27", "monitor_27.glb", "monitor",
     "computer monitor, a flat display on a small stand on a desk", ["office", "screen"],
     lambda: join(box(0.25, 0.2, 0.02), box(0.04, 0.04, 0.12, 0, -0.05, 0.02),
                  box(0.62, 0.03, 0.36, 0, -0.05, 0.1))),
    ("whiteboard_wall", "whiteboard_wall.glb", "whiteboard",
     "wall-mounted whiteboard to write on with markers", ["office"], lambda: panel(1.2, 0.03, 0.9)),
    ("rug_woven", "rug_woven.glb", "rug",
     "rectangular woven floor rug, a textile covering the "
     "floor", ["textile"], lambda: box(2.0, 1.4, 0.01)),
    ("vase_ceramic", "vase_ceramic.glb", "vase",
     "tall ceramic flower vase", ["decor"], lambda: cyl(0.08, 0.3, sections=20)),
]

#: Files written in another convention than metres / z up / front +y, and how.
CONVENTIONS = {
    "sofa_2seat": {"up": "+y", "front": "+z"},   # a glTF-style asset: y up, facing +z
    "armchair_wing": {"units": "cm"},            # an OBJ in centimetres
    "chair_dining": {"front": "-y"},             # a PLY that faces -y
}


def _to_convention(mesh, conv: dict) -> None:
    """Turn a mesh from the plan's frame into the file's convention (the library undoes it)."""
    from forcelayout.grounding.library import axis_frame

    m = np.eye(4)
    m[:3, :3] = axis_frame(conv.get("up", "+z"), conv.get("front", "+y")).T
    mesh.apply_transform(m)
    if conv.get("units") == "cm":
        mesh.apply_scale(100.0)


def build_library(folder: str | Path) -> Path:
    """Write the example asset library (meshes + assets.json) into ``folder``; returns it."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    meta = []
    for aid, file, category, description, tags, make in ASSETS:
        mesh = make()
        conv = CONVENTIONS.get(aid, {})
        _to_convention(mesh, conv)
        mesh.export(str(folder / file))
        meta.append({"id": aid, "file": file, "category": category,
                     "description": description, "tags": tags, **conv})
    (folder / "assets.json").write_text(json.dumps(meta, indent=2) + "\n", encoding="utf-8")
    return folder


# %% Build, ground the living room, solve one layout, export it with the meshes.
if __name__ == "__main__":
    import forcelayout as fl
    from forcelayout.grounding import ground_plan, scene_assets

    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    library = build_library(out / "assets")
    print(f"asset library: {len(ASSETS)} assets in {library}")

    report = ground_plan("living_room", library)
    print(f"grounded with {report.embedder} in {report.seconds:.2f} s:")
    for line in report.lines():
        print("  " + line)
    report.plan.save(out / "living_room_grounded.json")

    layout = fl.generate(report.plan, 1, seed=0, progress=False).layouts[0]
    print(layout)
    try:
        from forcelayout import export
    except ImportError:
        print("(no export extra: skipping the GLB)")
    else:
        glb = export.export_glb(layout, out / "living_room.glb",
                                assets=scene_assets(report.plan, library))
        print(f"scene with meshes -> {glb}")
