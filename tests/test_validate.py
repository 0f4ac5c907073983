"""Deterministic checks on hand-built layouts (no solver involved)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcelayout import Layout, Plan, Pose
from forcelayout.validate import CHECKS, CheckReport, check_layout, occupancy_mask

SQUARE = [[0, 0], [4, 0], [4, 4], [0, 4]]
DOOR = {"wall": 0, "offset": 2.5, "width": 0.9}  # swing square x 2.05..2.95, y 0..0.9


def make_plan(objects: list[dict], *, polygon=SQUARE, doors=(DOOR,), rules=()) -> Plan:
    return Plan.model_validate({
        "name": "test_room",
        "room": {"polygon": polygon, "height": 2.7, "doors": list(doors),
                 "windows": [{"wall": 2, "offset": 2.0, "width": 1.2}] if polygon is SQUARE
                 else []},
        "objects": objects,
        "rules": list(rules),
    })


def obj(oid: str, w: float, d: float, *, primary: bool = False, h: float = 0.8) -> dict:
    return {"id": oid, "category": oid.rstrip("_0123456789"), "size": [w, d, h],
            "primary": primary}


BEDROOM_OBJECTS = [
    obj("bed", 1.6, 2.0, primary=True, h=0.5),
    obj("desk", 1.2, 0.6, primary=True, h=0.75),
    obj("chair_1", 0.5, 0.5, h=0.9),
    obj("wardrobe", 1.2, 0.6, primary=True, h=2.0),
    obj("nightstand", 0.45, 0.4, h=0.5),
    obj("lamp", 0.2, 0.2, h=0.4),
    obj("painting", 0.9, 0.04, h=0.6),
    obj("light", 0.4, 0.4, h=0.15),
]
BEDROOM_RULES = [
    {"rule": "on_top", "object": "lamp", "target": "nightstand"},
    {"rule": "on_ceiling", "object": "light"},
]
CLEAN = {
    "bed": Pose(0.8, 3.0, math.pi),                 # head against the top wall, at the left
    "nightstand": Pose(1.85, 3.8, math.pi),
    "desk": Pose(3.7, 2.0, math.pi / 2),            # against the right wall, facing -x
    "chair_1": Pose(3.0, 2.0, -math.pi / 2),
    "wardrobe": Pose(0.3, 0.9, -math.pi / 2),       # against the left wall
    "lamp": Pose(1.85, 3.8, 0.0, 0.5, "nightstand"),
    "painting": Pose(0.02, 3.0, -math.pi / 2, 1.2, "wall:3"),
    "light": Pose(2.0, 2.0, 0.0, 2.55, "ceiling"),
}


def bedroom(**changes: Pose) -> Layout:
    plan = make_plan(BEDROOM_OBJECTS, rules=BEDROOM_RULES)
    return Layout(plan, {**CLEAN, **changes})


def of(report: CheckReport, check: str) -> list[str]:
    return [f for f in report.failures if f.startswith(check + ": ")]


def test_clean_layout_passes_every_check():
    rep = check_layout(bedroom())
    assert rep.ok, rep.failures
    assert rep.failures == []
    assert rep.unreachable == []
    assert 0.3 < rep.free_fraction < 1.0
    assert rep.free_mask is not None and rep.free_mask.dtype == bool
    assert bool(rep) is True
    assert all(v == [] for v in rep.by_check().values())


def test_overlapping_pair_is_a_collision_naming_both():
    rep = check_layout(bedroom(chair_1=Pose(3.25, 2.0, 0.3)))
    assert not rep.ok
    fails = of(rep, "collision")
    assert len(fails) == 1
    assert "'desk'" in fails[0] and "'chair_1'" in fails[0] and "m²" in fails[0]
    assert rep.failed("collision") and not rep.failed("outside")


def test_touching_objects_do_not_collide():
    # the chair's front edge exactly meets the desk's front edge
    rep = check_layout(bedroom(chair_1=Pose(3.4 - 0.25, 2.0, -math.pi / 2)))
    assert of(rep, "collision") == []


def test_object_outside_the_room():
    rep = check_layout(bedroom(wardrobe=Pose(0.1, 0.9, -math.pi / 2)))
    fails = of(rep, "outside")
    assert len(fails) == 1 and "'wardrobe'" in fails[0]
    assert "pokes" in fails[0]


def test_object_across_a_reflex_corner_is_outside_even_with_all_corners_inside():
    l_room = [[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]]
    plan = make_plan([obj("shelf", 2.0, 0.1)], polygon=l_room)
    # a thin shelf along x + y = 4 through the reflex corner (2, 2)
    lay = Layout(plan, {"shelf": Pose(2.0, 2.0, -math.pi / 4)})
    corners = lay.corners("shelf")
    assert lay.room.contains(corners).all()
    fails = of(check_layout(lay), "outside")
    assert len(fails) == 1 and "'shelf'" in fails[0]


def test_object_in_a_door_square_blocks_the_door():
    rep = check_layout(bedroom(chair_1=Pose(2.5, 0.5, 0.0)))
    fails = of(rep, "door")
    assert fails == ["door: 'chair_1' blocks the swing area of door 0"]
    off = check_layout(bedroom(chair_1=Pose(2.5, 0.5, 0.0)), door_clearance=False)
    assert of(off, "door") == []


def test_crowded_room_is_not_navigable():
    objects = [obj(f"stool_{k}", 0.3, 0.3) for k in range(25)]
    poses = {f"stool_{k}": Pose(0.5 + 0.75 * (k % 5), 0.5 + 0.75 * (k // 5), 0.0)
             for k in range(25)}
    plan = make_plan(objects)
    rep = check_layout(Layout(plan, poses))
    assert rep.free_fraction < 0.3
    fails = of(rep, "navigable")
    assert len(fails) == 1
    assert "radius 0.2 m" in fails[0] and "need 30%" in fails[0]


def walled_in(doors=(DOOR,)) -> Layout:
    objects = [obj("safe", 0.2, 0.2, primary=True), obj("shelf_a", 1.2, 0.2),
               obj("shelf_b", 0.2, 1.1), obj("sofa", 1.8, 0.8, primary=True)]
    poses = {"safe": Pose(0.3, 0.3, 0.0),
             "shelf_a": Pose(0.6, 1.0, 0.0),      # x 0..1.2, y 0.9..1.1
             "shelf_b": Pose(1.3, 0.55, 0.0),     # x 1.2..1.4, y 0..1.1
             "sofa": Pose(2.0, 3.5, math.pi)}
    return Layout(make_plan(objects, doors=list(doors)), poses)


def test_primary_object_walled_in_is_unreachable():
    rep = check_layout(walled_in())
    assert rep.unreachable == ["safe"]
    assert of(rep, "reachable") == ["reachable: 'safe' cannot be reached from door 0"]
    assert of(rep, "collision") == [] and of(rep, "door") == []


def test_room_without_door_uses_largest_free_region():
    rep = check_layout(walled_in(doors=()))
    assert rep.unreachable == ["safe"]
    assert of(rep, "reachable") == [
        "reachable: 'safe' cannot be reached from the largest free region"]
    no_door = Layout(make_plan(BEDROOM_OBJECTS, doors=(), rules=BEDROOM_RULES), CLEAN)
    assert check_layout(no_door).ok


def test_blocked_door_makes_every_primary_unreachable_from_it():
    lay = bedroom(chair_1=Pose(2.5, 0.3, 0.0))
    rep = check_layout(lay)
    assert set(rep.unreachable) == {"bed", "desk", "wardrobe"}


def test_every_door_must_reach_every_primary_object():
    second = {"wall": 2, "offset": 3.5, "width": 0.8}  # top wall, near the right corner
    objects = [obj("safe", 0.2, 0.2, primary=True), obj("shelf_a", 3.9, 0.2)]
    poses = {"safe": Pose(1.0, 0.5, 0.0), "shelf_a": Pose(2.0, 2.0, 0.0)}  # splits the room
    rep = check_layout(Layout(make_plan(objects, doors=[DOOR, second]), poses))
    assert of(rep, "reachable") == ["reachable: 'safe' cannot be reached from door 1"]


def test_surface_objects_are_not_floor_obstacles():
    # the ceiling light above the bed and the painting on the wall behind it
    rep = check_layout(bedroom(light=Pose(0.8, 3.0, 0.0, 2.55, "ceiling")))
    assert rep.ok, rep.failures


def test_object_overhanging_its_parent():
    rep = check_layout(bedroom(lamp=Pose(2.1, 3.8, 0.0, 0.5, "nightstand")))
    fails = of(rep, "surface")
    assert len(fails) == 1 and "'lamp'" in fails[0] and "'nightstand'" in fails[0]


def test_parent_not_placed_and_bad_walls_are_reported():
    poses = {k: v for k, v in CLEAN.items() if k != "nightstand"}
    rep = check_layout(Layout(make_plan(BEDROOM_OBJECTS, rules=BEDROOM_RULES), poses))
    assert any("'lamp'" in f and "not placed" in f for f in of(rep, "surface"))
    rep = check_layout(bedroom(painting=Pose(0.02, 3.0, -math.pi / 2, 1.2, "wall:9")))
    assert any("wall 9" in f for f in of(rep, "surface"))
    rep = check_layout(bedroom(painting=Pose(2.0, 2.0, 0.0, 1.2, "wall:3")))
    assert any("'painting'" in f and "from wall 3" in f for f in of(rep, "surface"))
    rep = check_layout(bedroom(painting=Pose(0.02, 3.0, -math.pi / 2, 2.5, "wall:3")))
    assert any("ceiling" in f for f in of(rep, "surface"))


def test_thresholds_are_honoured():
    lay = bedroom()
    base = check_layout(lay)
    assert base.ok
    strict = check_layout(lay, min_free_fraction=0.95)
    assert of(strict, "navigable") and not strict.ok
    wider = check_layout(lay, agent_radius=0.35)
    assert wider.free_fraction < base.free_fraction
    nudged = bedroom(chair_1=Pose(3.16, 2.0, -math.pi / 2))  # 0.01 x 0.5 m into the desk
    assert of(check_layout(nudged), "collision")
    assert not of(check_layout(nudged, max_overlap=0.01), "collision")


def test_invalid_parameters_raise_with_the_name():
    lay = bedroom()
    with pytest.raises(ValueError, match="grid"):
        check_layout(lay, grid=0.0)
    with pytest.raises(ValueError, match="min_free_fraction"):
        check_layout(lay, min_free_fraction=1.5)
    with pytest.raises(ValueError, match="agent_radius"):
        check_layout(lay, agent_radius=float("nan"))
    with pytest.raises(ValueError, match="unknown check"):
        check_layout(lay).failed("collisions")


def test_layout_check_method_and_check_names():
    assert bedroom().check().ok
    assert set(CHECKS) == {"collision", "outside", "door", "surface", "navigable", "reachable"}


def test_occupancy_mask_matches_the_free_cells():
    lay = bedroom()
    mask, origin = occupancy_mask(lay)
    rep = check_layout(lay)
    assert mask.shape == rep.free_mask.shape == (80, 80)
    np.testing.assert_allclose(origin, [0.0, 0.0])
    assert not (mask & rep.free_mask).any()
    assert mask.any()
    empty, _ = occupancy_mask(Layout(lay.plan, {"light": CLEAN["light"]}))
    assert not empty.any()
    wider, _ = occupancy_mask(lay, agent_radius=0.4)
    assert wider.sum() > mask.sum() and (wider | mask).sum() == wider.sum()


def translated(lay: Layout, dx: float, dy: float) -> Layout:
    data = lay.plan.model_dump(mode="json")
    room = data["room"]
    room["polygon"] = [[x + dx, y + dy] for x, y in room["polygon"]]
    poses = {k: Pose(p.x + dx, p.y + dy, p.yaw, p.z, p.surface) for k, p in lay.poses.items()}
    return Layout(Plan.model_validate(data), poses)


@settings(max_examples=20, deadline=None)
@given(dx=st.floats(-50, 50), dy=st.floats(-50, 50))
def test_translating_a_whole_scene_keeps_the_verdict(dx, dy):
    for lay in (bedroom(), walled_in()):
        base = check_layout(lay)
        moved = check_layout(translated(lay, dx, dy))
        assert moved.ok == base.ok
        assert moved.failures == base.failures
        assert abs(moved.free_fraction - base.free_fraction) < 0.01


def test_ceiling_object_poking_out_of_the_room():
    rep = check_layout(bedroom(light=Pose(3.9, 2.0, 0.0, 2.55, "ceiling")))
    fails = of(rep, "surface")
    assert len(fails) == 1 and "'light'" in fails[0] and "ceiling" in fails[0]
