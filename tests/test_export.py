"""forcelayout.export: 3D scenes of layouts (GLB, OBJ, Habitat, USD, MJCF, isometric picture)."""

from __future__ import annotations

import importlib
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from forcelayout.layout import Layout, Pose
from forcelayout.plan import Plan

trimesh = pytest.importorskip("trimesh")
export = importlib.import_module("forcelayout.export")

HEIGHT = 2.6
DOOR = {"wall": 0, "offset": 1.0, "width": 0.9, "height": 2.0}
WINDOW = {"wall": 2, "offset": 2.0, "width": 1.2, "sill": 0.9, "height": 1.2}
OBJECTS = [
    {"id": "bed", "category": "bed", "size": [1.6, 2.0, 0.5]},
    {"id": "desk", "category": "desk", "size": [1.2, 0.6, 0.75]},
    {"id": "lamp", "category": "lamp", "size": [0.3, 0.3, 0.4]},
    {"id": "poster-1.a", "category": "poster", "size": [0.6, 0.05, 0.8]},
]


def make_plan(polygon, doors=(DOOR,), windows=(WINDOW,), objects=OBJECTS, name="test_room"):
    return Plan.from_dict({
        "name": name,
        "room": {"polygon": polygon, "height": HEIGHT, "doors": list(doors),
                 "windows": list(windows)},
        "objects": list(objects),
    })


RECT = [[0, 0], [4, 0], [4, 3.5], [0, 3.5]]
L_SHAPE = [[0, 0], [5, 0], [5, 2], [2, 2], [2, 4], [0, 4]]


@pytest.fixture
def layout():
    plan = make_plan(RECT)
    return Layout(plan, {
        "bed": Pose(1.2, 2.4, 0.0),
        "desk": Pose(3.2, 1.5, math.pi / 2),
        "lamp": Pose(3.2, 1.5, 0.0, 0.75, "desk"),
        "poster-1.a": Pose(3.97, 2.8, math.pi / 2, 1.2, "wall:1"),
    }, seed=7)


def world_boxes(sc, prefix):
    """(name, inverse transform, half extents) of every node whose name starts with prefix."""
    out = []
    for node in sc.graph.nodes_geometry:
        if not str(node).startswith(prefix):
            continue
        T, geom = sc.graph[node]
        lo, hi = sc.geometry[geom].bounds
        out.append((node, np.linalg.inv(T), lo, hi))
    return out


def inside_any(boxes, point):
    p = np.append(np.asarray(point, float), 1.0)
    hits = []
    for name, inv, lo, hi in boxes:
        q = (inv @ p)[:3]
        if np.all(q > lo + 1e-9) and np.all(q < hi - 1e-9):
            hits.append(name)
    return hits


def world_bounds(sc, node):
    T, geom = sc.graph[node]
    v = trimesh.transform_points(sc.geometry[geom].vertices, T)
    return v.min(0), v.max(0)


# -- scene ---------------------------------------------------------------------


def test_one_node_per_placed_object_named_by_id(layout):
    sc = export.scene(layout)
    objects = {n for n in sc.graph.nodes_geometry if not n.startswith("room")}
    assert objects == set(layout.poses)
    assert sc.geometry["bed"].metadata["category"] == "bed"
    assert sc.geometry["bed"].metadata["plan"] == "test_room"
    assert sc.metadata["plan"] == "test_room" and sc.metadata["up"] == "+z"
    assert "room/floor" in sc.graph.nodes_geometry


def test_unplaced_objects_are_left_out(layout):
    partial = Layout(layout.plan, {"bed": layout.poses["bed"]})
    sc = export.scene(partial)
    assert {n for n in sc.graph.nodes_geometry if not n.startswith("room")} == {"bed"}


@pytest.mark.parametrize("yaw, swapped", [(0.0, False), (math.pi / 2, True), (math.pi, False),
                                          (-math.pi / 2, True)])
def test_box_extents_follow_yaw_and_bottom_is_at_z(layout, yaw, swapped):
    poses = dict(layout.poses, desk=Pose(2.0, 1.0, yaw, 0.3))
    sc = export.scene(Layout(layout.plan, poses))
    lo, hi = world_bounds(sc, "desk")
    w, d, h = 1.2, 0.6, 0.75
    expected = [d, w, h] if swapped else [w, d, h]
    np.testing.assert_allclose(hi - lo, expected, atol=1e-9)
    np.testing.assert_allclose((lo + hi)[:2] / 2, [2.0, 1.0], atol=1e-9)
    assert lo[2] == pytest.approx(0.3) and hi[2] == pytest.approx(0.3 + h)


@settings(max_examples=30, deadline=None)
@given(yaw=st.floats(-math.pi, math.pi), x=st.floats(0.5, 3.5), y=st.floats(0.5, 3.0))
def test_object_front_faces_minus_sin_cos_yaw(yaw, x, y):
    plan = make_plan(RECT, objects=OBJECTS[:1])
    sc = export.scene(Layout(plan, {"bed": Pose(x, y, yaw)}))
    T, _ = sc.graph["bed"]
    np.testing.assert_allclose(T[:3, 1], [-math.sin(yaw), math.cos(yaw), 0.0], atol=1e-9)
    np.testing.assert_allclose(T[:3, 3], [x, y, 0.0], atol=1e-9)


def test_floor_object_stands_on_floor_and_wall_object_at_its_height(layout):
    sc = export.scene(layout)
    assert world_bounds(sc, "bed")[0][2] == pytest.approx(0.0)
    lo, hi = world_bounds(sc, "poster-1.a")
    assert lo[2] == pytest.approx(1.2) and hi[2] == pytest.approx(2.0)
    assert hi[0] - lo[0] == pytest.approx(0.05)  # thin box turned to face the room (-x)
    floor_lo, floor_hi = world_bounds(sc, "room/floor")
    assert floor_hi[2] == pytest.approx(0.0) and floor_lo[2] < 0


# -- walls and openings ----------------------------------------------------------


def test_door_is_a_full_height_gap_with_wall_above(layout):
    walls = world_boxes(export.scene(layout, wall_thickness=0.1), "room/wall")
    # door on wall 0 (y = 0, outside is y < 0), centre x = 1.0, width 0.9, height 2.0
    assert inside_any(walls, [1.0, -0.05, 1.0]) == []
    assert inside_any(walls, [1.0, -0.05, 0.05]) == []
    assert inside_any(walls, [0.4, -0.05, 1.0])     # beside the door
    assert inside_any(walls, [1.6, -0.05, 1.0])
    assert inside_any(walls, [1.0, -0.05, 2.3])     # above the door


def test_window_is_a_gap_between_sill_and_top(layout):
    walls = world_boxes(export.scene(layout), "room/wall")
    # window on wall 2 (y = 3.5, runs from x = 4 to 0): centre 2.0 m from (4, 3.5) -> x = 2.0
    assert inside_any(walls, [2.0, 3.55, 1.5]) == []
    assert inside_any(walls, [2.0, 3.55, 0.5])      # below the sill
    assert inside_any(walls, [2.0, 3.55, 2.4])      # above the window
    assert inside_any(walls, [1.2, 3.55, 1.5])      # beside it


@pytest.mark.parametrize("clockwise", [False, True])
def test_walls_reach_room_height_and_stay_outside_the_floor(clockwise):
    polygon = RECT[::-1] if clockwise else RECT
    sc = export.scene(Layout(make_plan(polygon, doors=[], windows=[]), {}))
    walls = world_boxes(sc, "room/wall")
    tops = [world_bounds(sc, n)[1][2] for n, *_ in walls]
    assert max(tops) == pytest.approx(HEIGHT)
    xs, ys = np.meshgrid(np.linspace(0.01, 3.99, 15), np.linspace(0.01, 3.49, 15))
    for x, y in zip(xs.ravel(), ys.ravel(), strict=True):
        assert inside_any(walls, [x, y, 1.0]) == []


@pytest.mark.parametrize("wall_thickness", [0.05, 0.2])
def test_l_shaped_room_walls_are_closed_at_every_corner(wall_thickness):
    plan = make_plan(L_SHAPE, doors=[{"wall": 4, "offset": 1.0}], windows=[])
    walls = world_boxes(export.scene(Layout(plan, {}), wall_thickness=wall_thickness),
                        "room/wall")
    poly = np.asarray(L_SHAPE, float)
    shape = plan.room.shape
    t = wall_thickness
    for k, v in enumerate(poly):
        # points just outside the corner, in the wall band (diagonal and along both walls)
        for dx in (-t / 2, 0.0, t / 2):
            for dy in (-t / 2, 0.0, t / 2):
                p = v + [dx, dy]
                if shape.buffer(1e-6).contains(shapely.Point(p)):
                    continue
                assert inside_any(walls, [*p, 1.0]), f"corner {k} open at {p}"
    # nothing of the walls inside the L
    for p in [(0.5, 0.5), (4.5, 1.5), (1.9, 3.9), (1.99, 1.99), (3.0, 1.95)]:
        assert inside_any(walls, [*p, 1.0]) == []
    # the door on wall 4, which runs (2, 4) -> (0, 4): its centre is at x = 1.0
    assert inside_any(walls, [1.0, 4.0 + t / 2, 1.0]) == []
    assert inside_any(walls, [1.0, 4.0 + t / 2, 2.3])


@settings(max_examples=20, deadline=None)
@given(w=st.floats(2.5, 8.0), d=st.floats(2.5, 8.0), frac=st.floats(0.0, 1.0),
       width=st.floats(0.6, 1.2), wall=st.integers(0, 3))
def test_any_door_leaves_a_gap_and_keeps_the_wall_beside_it(w, d, frac, width, wall):
    poly = [[0, 0], [w, 0], [w, d], [0, d]]
    plan = make_plan(poly, doors=[], windows=[], objects=OBJECTS[:1])
    length = plan.room.wall_length(wall)
    offset = width / 2 + frac * (length - width)
    plan = make_plan(poly, doors=[{"wall": wall, "offset": offset, "width": width}], windows=[],
                     objects=OBJECTS[:1])
    walls = world_boxes(export.scene(Layout(plan, {})), "room/wall")
    a, b = np.asarray(poly[wall], float), np.asarray(poly[(wall + 1) % 4], float)
    tangent = (b - a) / length
    outward = np.array([tangent[1], -tangent[0]])  # CCW polygon: outside is to the right
    centre = a + tangent * offset + outward * 0.05
    assert inside_any(walls, [*centre, 1.0]) == []
    assert inside_any(walls, [*centre, 2.3])
    if offset - width / 2 > 0.05:
        assert inside_any(walls, [*(centre - tangent * (width / 2 + 0.03)), 1.0])


def test_bad_wall_thickness_is_refused(layout):
    with pytest.raises(ValueError, match="wall_thickness"):
        export.scene(layout, wall_thickness=0.0)


# -- frames ----------------------------------------------------------------------


def test_y_up_scene_turns_z_to_y(layout):
    zup, yup = export.scene(layout), export.scene(layout, y_up=True)
    assert yup.metadata["up"] == "+y"
    np.testing.assert_allclose(yup.bounds[1][1], HEIGHT, atol=1e-9)
    lo, hi = world_bounds(zup, "bed")
    lo2, hi2 = world_bounds(yup, "bed")
    np.testing.assert_allclose(lo2, [lo[0], lo[2], -hi[1]], atol=1e-9)
    np.testing.assert_allclose(hi2, [hi[0], hi[2], -lo[1]], atol=1e-9)


# -- files -----------------------------------------------------------------------


def test_glb_is_written_and_loads_back(layout, tmp_path):
    path = export.export_glb(layout, tmp_path / "sub" / "room.glb")
    assert path.exists()
    loaded = trimesh.load(path)
    assert isinstance(loaded, trimesh.Scene)
    assert set(layout.poses) <= set(loaded.graph.nodes_geometry)
    np.testing.assert_allclose(loaded.bounds, export.scene(layout, y_up=True).bounds, atol=1e-5)
    _, geom = loaded.graph["bed"]
    assert loaded.geometry[geom].metadata.get("category") == "bed"


def test_obj_is_written_with_a_group_per_object(layout, tmp_path):
    path = export.export_obj(layout, tmp_path / "room.obj", y_up=False)
    text = path.read_text()
    for oid in layout.poses:
        assert f"o {oid}" in text
    np.testing.assert_allclose(trimesh.load(path, force="mesh").bounds,
                               export.scene(layout).bounds, atol=1e-6)


def _quat_matrix(q):
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def test_habitat_scene_instance(layout, tmp_path):
    out = export.export_habitat(layout, tmp_path / "hab")
    assert out.name == "test_room_7.scene_instance.json"
    data = json.loads(out.read_text())
    inst = data["object_instances"]
    assert len(inst) == len(layout.poses)
    assert data["translation_origin"] == "asset_local"
    root = tmp_path / "hab"
    stage_cfg = json.loads((root / data["stage_instance"]["template_name"]).read_text())
    assert (root / "stages" / stage_cfg["render_asset"]).exists()
    assert (root / "test_room.scene_dataset_config.json").exists()
    C = export.Z_UP_TO_Y_UP[:3, :3]
    for rec in inst:
        oid = rec["user_defined"]["id"]
        pose = layout.poses[oid]
        q = np.asarray(rec["rotation"])
        assert np.linalg.norm(q) == pytest.approx(1.0)
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        rz = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
        np.testing.assert_allclose(_quat_matrix(q), C @ rz @ C.T, atol=1e-9)
        np.testing.assert_allclose(rec["translation"], [pose.x, pose.z, -pose.y], atol=1e-9)
        cfg_path = root / rec["template_name"]
        cfg = json.loads(cfg_path.read_text())
        mesh = trimesh.load(cfg_path.parent / cfg["render_asset"], force="mesh")
        w, d, h = layout.plan.object(oid).size
        np.testing.assert_allclose(mesh.bounds, [[-w / 2, 0, -d / 2], [w / 2, h, d / 2]],
                                   atol=1e-6)


def _habitat_files(root):
    """Every JSON config of a Habitat folder, by kind."""
    return {kind: sorted(root.rglob(f"*.{kind}.json"))
            for kind in ("scene_dataset_config", "stage_config", "object_config",
                         "scene_instance")}


def test_habitat_paths_are_relative_and_exist(layout, tmp_path):
    root = tmp_path / "hab"
    export.export_habitat(layout, root)
    files = _habitat_files(root)
    (dataset,) = files["scene_dataset_config"]
    config = json.loads(dataset.read_text())
    for kind in ("stages", "objects", "scene_instances"):
        for folder in config[kind]["paths"][".json"]:
            assert not Path(folder).is_absolute() and (root / folder).is_dir()
    for cfg_path in files["stage_config"] + files["object_config"]:
        cfg = json.loads(cfg_path.read_text())
        for key in ("render_asset", "collision_asset"):
            assert not Path(cfg[key]).is_absolute()
            assert (cfg_path.parent / cfg[key]).is_file()  # relative to the config's folder
    (scene_path,) = files["scene_instance"]
    data = json.loads(scene_path.read_text())
    names = [data["stage_instance"]["template_name"]]
    names += [rec["template_name"] for rec in data["object_instances"]]
    configs = [str(p.relative_to(root)) for p in files["stage_config"] + files["object_config"]]
    for name in names:  # habitat-sim takes the first config whose handle contains the name
        assert [c for c in configs if name in c] == [name]


def test_habitat_template_names_are_unambiguous(tmp_path):
    objects = [{"id": "desk", "category": "desk", "size": [1.0, 0.5, 0.7]},
               {"id": "desk_2", "category": "desk", "size": [1.0, 0.5, 0.7]}]
    plan = make_plan(RECT, objects=objects)
    lay = Layout(plan, {"desk": Pose(1.0, 1.0, 0.0), "desk_2": Pose(3.0, 1.0, 0.0)})
    out = export.export_habitat(lay, tmp_path)
    configs = [str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*.object_config.json")]
    for rec in json.loads(out.read_text())["object_instances"]:
        assert sum(rec["template_name"] in c for c in configs) == 1


def test_habitat_is_y_up_with_w_first_quaternions(layout, tmp_path):
    root = tmp_path / "hab"
    out = export.export_habitat(layout, root)
    files = _habitat_files(root)
    for cfg_path in files["stage_config"] + files["object_config"]:
        cfg = json.loads(cfg_path.read_text())
        assert cfg["up"] == [0.0, 1.0, 0.0] and cfg["front"] == [0.0, 0.0, -1.0]
    (stage_cfg,) = files["stage_config"]
    stage = trimesh.load(stage_cfg.parent / json.loads(stage_cfg.read_text())["render_asset"])
    lo, hi = stage.bounds
    assert lo[1] == pytest.approx(-0.05) and hi[1] == pytest.approx(HEIGHT)  # y is up
    np.testing.assert_allclose([lo[2], hi[2]], [-3.6, 0.1], atol=1e-6)  # -z: the plan's +y
    rotation = {rec["user_defined"]["id"]: rec["rotation"]
                for rec in json.loads(out.read_text())["object_instances"]}
    assert rotation["bed"] == [1.0, 0.0, 0.0, 0.0]          # yaw 0: w first
    np.testing.assert_allclose(rotation["desk"], [math.sqrt(0.5), 0, math.sqrt(0.5), 0])


def test_habitat_motion_types_and_mass(layout, tmp_path):
    out = export.export_habitat(layout, tmp_path, movable=["lamp"])
    data = json.loads(out.read_text())
    motion = {rec["user_defined"]["id"]: rec["motion_type"] for rec in data["object_instances"]}
    assert motion == {"bed": "STATIC", "desk": "STATIC", "lamp": "DYNAMIC",
                      "poster-1.a": "STATIC"}
    lamp = json.loads((tmp_path / "objects" / "test_room_lamp.object_config.json").read_text())
    assert lamp["mass"] == pytest.approx(100.0 * 0.3 * 0.3 * 0.4)
    assert lamp["use_bounding_box_for_collision"] is True
    out = export.export_habitat(layout, tmp_path, motion_type="kinematic", movable="lamp,bed")
    motion = [rec["motion_type"] for rec in json.loads(out.read_text())["object_instances"]]
    assert motion == ["DYNAMIC", "KINEMATIC", "DYNAMIC", "KINEMATIC"]


def test_habitat_refuses_unknown_motion_type(layout, tmp_path):
    with pytest.raises(ValueError, match="motion_type"):
        export.export_habitat(layout, tmp_path, motion_type="floating")


# -- USD (usd-core) -------------------------------------------------------------


@pytest.fixture
def pxr():
    pytest.importorskip("pxr.Usd")
    import pxr as module
    from pxr import Gf, Usd, UsdGeom, UsdPhysics  # noqa: F401

    return module


def _usd_objects(stage):
    """{object id: its Xform prim} of an exported stage."""
    return {p.GetCustomDataByKey("id"): p
            for p in stage.GetPrimAtPath("/World/Objects").GetChildren()}


def test_usd_stage_is_z_up_metres_with_a_physics_scene(layout, tmp_path, pxr):
    from pxr import Usd, UsdGeom, UsdPhysics

    path = export.export_usd(layout, tmp_path / "sub" / "room.usda")
    stage = Usd.Stage.Open(str(path))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert UsdPhysics.GetStageKilogramsPerUnit(stage) == 1.0
    assert stage.GetDefaultPrim().GetPath() == "/World"
    scenes = [p for p in stage.Traverse() if p.IsA(UsdPhysics.Scene)]
    assert [str(p.GetPath()) for p in scenes] == ["/physicsScene"]
    scene = UsdPhysics.Scene(scenes[0])
    assert tuple(scene.GetGravityDirectionAttr().Get()) == (0.0, 0.0, -1.0)
    assert scene.GetGravityMagnitudeAttr().Get() == pytest.approx(9.81)
    assert stage.GetDefaultPrim().GetCustomDataByKey("plan") == "test_room"


def test_usd_room_and_furniture_collide_and_are_static(layout, tmp_path, pxr):
    from pxr import Usd, UsdGeom, UsdPhysics

    from forcelayout.export._boxes import room_boxes

    stage = Usd.Stage.Open(str(export.export_usd(layout, tmp_path / "room.usda")))
    room = stage.GetPrimAtPath("/World/Room")
    names = {p.GetName() for p in room.GetChildren()}
    assert names == {"floor"} | {b.name for b in room_boxes(layout.plan.room)}
    for prim in room.GetChildren():
        assert prim.HasAPI(UsdPhysics.CollisionAPI)
    assert stage.GetPrimAtPath("/World/Room/floor").IsA(UsdGeom.Mesh)
    objects = _usd_objects(stage)
    assert set(objects) == set(layout.poses)
    for prim in objects.values():
        assert prim.GetChild("box").HasAPI(UsdPhysics.CollisionAPI)
    assert not [p for p in stage.Traverse() if p.HasAPI(UsdPhysics.RigidBodyAPI)]


def test_usd_transforms_are_the_layout_poses(layout, tmp_path, pxr):
    from pxr import Usd, UsdGeom

    stage = Usd.Stage.Open(str(export.export_usd(layout, tmp_path / "room.usda")))
    cache = UsdGeom.BBoxCache(Usd.TimeCode.Default(), [UsdGeom.Tokens.default_])
    sc = export.scene(layout)
    for oid, prim in _usd_objects(stage).items():
        pose = layout.poses[oid]
        m = np.array(UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(
            Usd.TimeCode.Default())).T  # USD matrices act on row vectors
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        np.testing.assert_allclose(m[:3, :3], [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-9)
        np.testing.assert_allclose(m[:3, 3], [pose.x, pose.y, pose.z], atol=1e-9)
        box = cache.ComputeWorldBound(prim.GetChild("box")).ComputeAlignedRange()
        lo, hi = world_bounds(sc, oid)
        np.testing.assert_allclose([box.GetMin(), box.GetMax()], [lo, hi], atol=1e-6)
        assert prim.GetCustomDataByKey("category") == layout.plan.object(oid).category
        assert prim.GetCustomDataByKey("plan") == "test_room"
    walls = [p for p in stage.GetPrimAtPath("/World/Room").GetChildren()
             if p.GetName().startswith("wall")]
    for prim in walls:
        rng = cache.ComputeWorldBound(prim).ComputeAlignedRange()
        lo, hi = world_bounds(sc, f"room/{prim.GetName()}")
        np.testing.assert_allclose([rng.GetMin(), rng.GetMax()], [lo, hi], atol=1e-6)


def test_usd_movable_categories_are_rigid_bodies_with_mass(layout, tmp_path, pxr):
    from pxr import Usd, UsdPhysics

    path = export.export_usd(layout, tmp_path / "room.usda", movable=("lamp", "sofa"))
    stage = Usd.Stage.Open(str(path))  # held: prims live only as long as their stage
    objects = _usd_objects(stage)
    for oid, prim in objects.items():
        assert prim.HasAPI(UsdPhysics.RigidBodyAPI) == (oid == "lamp")
        assert prim.HasAPI(UsdPhysics.MassAPI) == (oid == "lamp")
    mass = UsdPhysics.MassAPI(objects["lamp"]).GetMassAttr().Get()
    assert mass == pytest.approx(100.0 * 0.3 * 0.3 * 0.4, rel=1e-6)
    with pytest.raises(ValueError, match="density"):
        export.export_usd(layout, tmp_path / "x.usda", movable="lamp", density=0.0)


def test_usd_names_are_valid_and_keep_ids(layout, pxr):
    from pxr import Sdf, Usd

    stage = Usd.Stage.Open(Sdf.Layer.CreateAnonymous(".usda"))
    stage.GetRootLayer().ImportFromString(export.usda_text(layout))
    prim = stage.GetPrimAtPath("/World/Objects/poster_1_a")
    assert prim and prim.GetCustomDataByKey("id") == "poster-1.a"
    assert prim.GetCustomDataByKey("surface") == "wall:1"


@pytest.mark.parametrize("suffix, magic", [(".usda", b"#usda"), (".usdc", b"PXR-USDC"),
                                           (".usd", b"PXR-USDC")])
def test_usd_suffix_picks_the_encoding(layout, tmp_path, pxr, suffix, magic):
    from pxr import Usd

    path = export.export_usd(layout, tmp_path / f"room{suffix}")
    assert path.read_bytes().startswith(magic)
    assert set(_usd_objects(Usd.Stage.Open(str(path)))) == set(layout.poses)
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temporary left


def test_usd_refuses_other_suffixes(layout, tmp_path):
    with pytest.raises(ValueError, match="usda"):
        export.export_usd(layout, tmp_path / "room.glb")
    assert not list(tmp_path.iterdir())


def test_missing_usd_core_names_the_extra(layout, tmp_path, monkeypatch):
    for name in list(sys.modules):
        if name == "pxr" or name.startswith("pxr."):
            monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "pxr", None)
    with pytest.raises(ImportError, match=r'usd-core.*pip install "forcelayout\[export\]"'):
        export.export_usd(layout, tmp_path / "room.usda")
    assert export.export_glb(layout, tmp_path / "room.glb").exists()  # the rest still works


# -- MJCF (mujoco) ---------------------------------------------------------------


@pytest.fixture
def mujoco():
    return pytest.importorskip("mujoco")


def _geom(mujoco, model, name):
    return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name)


def _custom_text(mujoco, model, name):
    i = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TEXT, name)
    start = model.text_adr[i]
    return bytes(model.text_data[start:start + model.text_size[i] - 1]).decode()


def test_mjcf_loads_steps_and_matches_the_layout(layout, tmp_path, mujoco):
    from forcelayout.export._boxes import object_boxes, room_boxes

    path = export.export_mjcf(layout, tmp_path / "sub" / "room.xml")
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    for _ in range(100):
        mujoco.mj_step(model, data)
    assert model.nq == 0 and model.njnt == 0  # everything static by default
    for b in object_boxes(layout) + room_boxes(layout.plan.room):
        g = _geom(mujoco, model, b.name if b.kind == "object" else f"room/{b.name}")
        assert g >= 0, b.name
        assert model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX
        np.testing.assert_allclose(data.geom_xpos[g], b.centre, atol=1e-9)
        np.testing.assert_allclose(model.geom_size[g], b.extents / 2, atol=1e-9)
        np.testing.assert_allclose(data.geom_xmat[g].reshape(3, 3), b.transform()[:3, :3],
                                   atol=1e-9)
    n_walls = len(room_boxes(layout.plan.room))
    assert model.ngeom == 1 + n_walls + len(layout.poses)
    assert _custom_text(mujoco, model, "plan") == "test_room"
    assert _custom_text(mujoco, model, "category:poster-1.a") == "poster"


def test_mjcf_floor_top_is_at_zero_and_door_is_a_gap(layout, mujoco):
    model = mujoco.MjModel.from_xml_string(export.mjcf_text(layout))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    g = _geom(mujoco, model, "room/floor")
    mesh = model.geom_dataid[g]
    start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
    verts = model.mesh_vert[start:start + count] @ data.geom_xmat[g].reshape(3, 3).T
    verts = verts + data.geom_xpos[g]
    np.testing.assert_allclose([verts.min(0), verts.max(0)], [[0, 0, -0.05], [4, 3.5, 0]],
                               atol=1e-6)
    # the door on wall 0 is centred at x = 1.0, 0.9 wide, 2.0 high: no wall geom there
    for name in (model.geom(i).name for i in range(model.ngeom)):
        if not name.startswith("room/wall"):
            continue
        i = _geom(mujoco, model, name)
        q = data.geom_xmat[i].reshape(3, 3).T @ (np.array([1.0, -0.05, 1.0]) - data.geom_xpos[i])
        assert not np.all(np.abs(q) < model.geom_size[i]), name


def test_mjcf_movable_objects_get_a_free_joint_and_rest(layout, tmp_path, mujoco):
    path = export.export_mjcf(layout, tmp_path / "room.xml", movable="lamp, sofa")
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.njnt == 1 and model.joint(0).name == "lamp"
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "lamp")
    assert model.body_mass[body] == pytest.approx(100.0 * 0.3 * 0.3 * 0.4)
    data = mujoco.MjData(model)
    for _ in range(500):  # one second: the lamp stands on the desk, it does not fall through
        mujoco.mj_step(model, data)
    np.testing.assert_allclose(data.geom_xpos[_geom(mujoco, model, "lamp")],
                               [3.2, 1.5, 0.75 + 0.2], atol=5e-3)


def test_mjcf_l_shaped_room_with_an_asset_mesh(tmp_path, mujoco):
    plan = make_plan(L_SHAPE, doors=[{"wall": 4, "offset": 1.0}], windows=[],
                     objects=OBJECTS[:3])
    lay = Layout(plan, {"bed": Pose(1.0, 2.5, 0.3), "lamp": Pose(4.0, 1.0, 1.0)})
    sphere = trimesh.creation.icosphere(radius=2.0)
    path = export.export_mjcf(lay, tmp_path / "l.xml", assets={"lamp": sphere})
    assert (tmp_path / "l_meshes" / "lamp.stl").is_file()
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data)
    g = _geom(mujoco, model, "lamp")
    assert model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH
    mesh = model.geom_dataid[g]
    start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
    verts = model.mesh_vert[start:start + count] @ data.geom_xmat[g].reshape(3, 3).T
    verts = verts + data.geom_xpos[g]
    lo, hi = world_bounds(export.scene(lay, assets={"lamp": sphere}), "lamp")
    np.testing.assert_allclose([verts.min(0), verts.max(0)], [lo, hi], atol=1e-5)
    with pytest.raises(KeyError, match="sofa"):
        export.export_mjcf(lay, tmp_path / "m.xml", assets={"sofa": sphere})


def test_rugs_do_not_collide_and_hanging_objects_stay_static(tmp_path, pxr, mujoco):
    from pxr import Usd, UsdPhysics

    objects = [*OBJECTS, {"id": "rug", "category": "rug", "size": [2.0, 1.4, 0.01]}]
    plan = make_plan(RECT, objects=objects)
    lay = Layout(plan, {"desk": Pose(2.0, 1.5, 0.0), "rug": Pose(2.0, 1.5, 0.0),
                        "poster-1.a": Pose(3.97, 2.8, math.pi / 2, 1.2, "wall:1")})
    movable = ["desk", "rug", "poster"]
    stage = Usd.Stage.Open(str(export.export_usd(lay, tmp_path / "r.usda", movable=movable)))
    objs = _usd_objects(stage)
    assert not objs["rug"].GetChild("box").HasAPI(UsdPhysics.CollisionAPI)
    assert objs["desk"].GetChild("box").HasAPI(UsdPhysics.CollisionAPI)
    assert [o for o, p in objs.items() if p.HasAPI(UsdPhysics.RigidBodyAPI)] == ["desk"]

    model = mujoco.MjModel.from_xml_string(export.mjcf_text(lay, movable=movable))
    rug = _geom(mujoco, model, "rug")
    assert model.geom_contype[rug] == 0 and model.geom_conaffinity[rug] == 0
    assert [model.joint(i).name for i in range(model.njnt)] == ["desk"]
    data = mujoco.MjData(model)
    for _ in range(200):  # the desk stands on the floor through the rug, not pushed up
        mujoco.mj_step(model, data)
    assert data.geom_xpos[_geom(mujoco, model, "desk")][2] == pytest.approx(0.375, abs=2e-3)

    out = export.export_habitat(lay, tmp_path / "hab", movable=movable)
    motion = {r["user_defined"]["id"]: r["motion_type"]
              for r in json.loads(out.read_text())["object_instances"]}
    assert motion == {"desk": "DYNAMIC", "rug": "STATIC", "poster-1.a": "STATIC"}
    rug_cfg = tmp_path / "hab" / "objects" / "test_room_rug.object_config.json"
    assert json.loads(rug_cfg.read_text())["is_collidable"] is False


# -- write_exports ---------------------------------------------------------------


def test_write_exports_writes_every_format_beside_the_stem(layout, tmp_path, pxr, mujoco):
    assert export.EXPORT_FORMATS == ("glb", "usd", "mjcf", "habitat")
    stem = tmp_path / "out" / "room.0007"
    written = export.write_exports(layout, stem, export.EXPORT_FORMATS, movable=("lamp",))
    assert [p.name for p in written] == ["room.0007.glb", "room.0007.usda", "room.0007.xml",
                                         "room.0007.habitat"]
    assert written == export.export_paths(stem, "glb,usd,mjcf,habitat")
    assert all(p.exists() for p in written)
    assert (written[3] / "scenes" / "test_room_7.scene_instance.json").is_file()
    assert mujoco.MjModel.from_xml_path(str(written[2])).njnt == 1
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == sorted(
        p.name for p in written)  # nothing else, no temporaries
    # written again: replaced in place
    again = export.write_exports(layout, stem, "habitat, mjcf,habitat")
    assert [p.name for p in again] == ["room.0007.habitat", "room.0007.xml"]


def test_write_exports_writes_the_same_bytes_twice(layout, tmp_path, pxr):
    def files(root):
        return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
                if p.is_file()}

    for run in ("a", "b"):
        export.write_exports(layout, tmp_path / run / "room", export.EXPORT_FORMATS,
                             movable="lamp")
    assert files(tmp_path / "a") == files(tmp_path / "b")


def test_write_exports_refuses_unknown_formats_before_writing(layout, tmp_path):
    with pytest.raises(ValueError, match="accepted: glb, usd, mjcf, habitat"):
        export.write_exports(layout, tmp_path / "room", ["glb", "fbx"])
    assert not list(tmp_path.iterdir())


def test_a_failed_write_leaves_the_old_file_and_no_temporary(layout, tmp_path, monkeypatch):
    from forcelayout.export import mjcf

    stem = tmp_path / "room"
    (xml,) = export.write_exports(layout, stem, ["mjcf"])
    before = xml.read_bytes()

    def killed(root):
        raise KeyboardInterrupt

    monkeypatch.setattr(mjcf, "_text", killed)
    with pytest.raises(KeyboardInterrupt):
        export.write_exports(layout, stem, ["mjcf"])
    assert xml.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["room.xml"]


def test_a_failed_habitat_write_leaves_no_folder_under_the_final_name(layout, tmp_path,
                                                                     monkeypatch):
    from forcelayout.export import habitat

    real, calls = habitat._write_json, []

    def dies_on_the_third(path, data):
        calls.append(path)
        if len(calls) == 3:
            raise OSError("disk full")
        real(path, data)

    monkeypatch.setattr(habitat, "_write_json", dies_on_the_third)
    with pytest.raises(OSError, match="disk full"):
        export.write_exports(layout, tmp_path / "room", ["habitat"])
    assert not list(tmp_path.iterdir())


# -- assets ----------------------------------------------------------------------


def test_assets_are_scaled_uniformly_into_the_object_size(layout):
    sphere = trimesh.creation.icosphere(radius=3.0)
    sc = export.scene(layout, assets={"lamp": sphere})
    lo, hi = world_bounds(sc, "lamp")
    np.testing.assert_allclose(hi - lo, [0.3, 0.3, 0.3], atol=1e-6)  # fits 0.3 x 0.3 x 0.4
    assert lo[2] == pytest.approx(0.75)
    with pytest.raises(KeyError, match="sofa"):
        export.scene(layout, assets={"sofa": sphere})


# -- picture ---------------------------------------------------------------------


def test_isometric_png_is_written(layout, tmp_path):
    from matplotlib.figure import Figure

    fig = export.isometric(layout, tmp_path / "iso.png")
    assert isinstance(fig, Figure)
    assert (tmp_path / "iso.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    texts = {t.get_text() for t in fig.axes[0].texts}
    assert set(layout.poses) <= texts
    with pytest.raises(ValueError, match="elevation"):
        export.isometric(layout, elevation=0.0)


def test_isometric_draws_l_shaped_room_without_saving():
    plan = make_plan(L_SHAPE, doors=[], windows=[], objects=OBJECTS[:1])
    fig = export.isometric(Layout(plan, {"bed": Pose(1.0, 2.5, 0.3)}), labels=False)
    assert len(fig.axes[0].collections[0].get_paths()) > 10


# -- the extra -------------------------------------------------------------------


def test_missing_trimesh_names_the_extra(monkeypatch):
    for name in list(sys.modules):
        if name == "forcelayout.export" or name.startswith("forcelayout.export."):
            monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "trimesh", None)
    with pytest.raises(ImportError, match=r'pip install "forcelayout\[export\]"'):
        importlib.import_module("forcelayout.export")


@pytest.mark.parametrize("polygon", [RECT, RECT[::-1], L_SHAPE])
def test_meshes_are_closed_with_outward_faces(polygon):
    plan = make_plan(polygon, doors=[], windows=[], objects=OBJECTS[:1])
    sc = export.scene(Layout(plan, {"bed": Pose(1.0, 1.5, 0.4)}), floor_thickness=0.05)
    floor = sc.geometry["room/floor"]
    assert floor.is_watertight
    assert floor.volume == pytest.approx(plan.room.shape.area * 0.05)
    for name in ("bed", "room/wall_0_0"):
        assert sc.geometry[name].is_watertight and sc.geometry[name].volume > 0
