"""Deterministic checks on hand-built layouts (no solver involved)."""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from forcelayout import Layout, Plan, Pose
from forcelayout.baselines import random_layout
from forcelayout.testing import plans
from forcelayout.validate import (
    CHECKS,
    CheckReport,
    check_floors,
    check_layout,
    occupancy_mask,
    window_zones,
)

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


def test_object_across_the_notch_of_a_u_shaped_room_is_outside():
    """Every corner on the floor and no wall corner inside it, yet a wall runs across it."""
    u_room = [[0, 0], [6, 0], [6, 4], [4, 4], [4, 2], [2, 2], [2, 4], [0, 4]]
    plan = make_plan([obj("bench", 4.0, 1.0)], polygon=u_room, doors=())
    lay = Layout(plan, {"bench": Pose(3.0, 3.0, 0.0)})
    assert lay.room.contains(lay.corners("bench")).all()
    fails = of(check_layout(lay), "outside")
    assert fails == ["outside: 'bench' pokes 2.00 m² out of the room"]
    assert of(check_layout(Layout(plan, {"bench": Pose(3.0, 1.0, 0.0)})), "outside") == []


def test_object_in_a_door_square_blocks_the_door():
    rep = check_layout(bedroom(chair_1=Pose(2.5, 0.5, 0.0)))
    fails = of(rep, "door")
    assert fails == ["door: 'chair_1' blocks the swing area of door 0"]
    off = check_layout(bedroom(chair_1=Pose(2.5, 0.5, 0.0)), door_clearance=False)
    assert of(off, "door") == []


def crowded() -> Layout:
    objects = [obj(f"stool_{k}", 0.3, 0.3) for k in range(25)]
    poses = {f"stool_{k}": Pose(0.5 + 0.75 * (k % 5), 0.5 + 0.75 * (k // 5), 0.0)
             for k in range(25)}
    return Layout(make_plan(objects), poses)


def test_crowded_room_is_not_navigable():
    rep = check_layout(crowded())
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
    [line] = of(rep, "reachable")
    assert line.startswith("reachable: 'safe' cannot be reached from door 0 (blocked by ")
    # the cheapest way in crosses one of the two shelves, and the failure names it
    assert len(rep.blocked_by["safe"]) == 1
    assert rep.blocked_by["safe"][0] in {"shelf_a", "shelf_b"}
    assert f"'{rep.blocked_by['safe'][0]}'" in line
    assert of(rep, "collision") == [] and of(rep, "door") == []


def test_floors_checked_without_naming_blockers_fail_as_many_checks():
    from forcelayout.validate import check_floors

    layouts = [walled_in(), crowded(), walled_in(doors=())]
    named = check_floors(layouts)
    plain = check_floors(layouts, name_blockers=False)
    for a, b in zip(named, plain, strict=True):
        assert len(a.failures) == len(b.failures) and a.ok == b.ok
        assert a.unreachable == b.unreachable and not b.blocked_by
        assert [f.split(" (blocked by ")[0] for f in a.failures] == b.failures
    assert named[0].blocked_by and not any("blocked by" in f for f in plain[0].failures)


def test_a_floor_verdict_without_blockers_is_the_same_but_for_their_names():
    """``judge_floors(blockers=False)``, as starts and repair rounds are first judged: the
    same failures but for what blocks the way, the same unmet bindings and free floor."""
    from forcelayout.forces import ForceModel
    from forcelayout.verdict import judge_floors

    lay = walled_in()
    model = ForceModel(lay.plan)
    pos = np.array([[[lay.poses[k].x, lay.poses[k].y] for k in model.ids]])
    yaw = np.array([[lay.poses[k].yaw for k in model.ids]])
    [named] = judge_floors(model, pos, yaw)
    [plain] = judge_floors(model, pos, yaw, blockers=False)
    assert any("(blocked by " in f for f in named.failures)
    assert [f.split(" (blocked by ")[0] for f in named.failures] == plain.failures
    assert (named.missed, named.free) == (plain.missed, plain.free)
    assert named.rejecting() == plain.rejecting() and not plain.passes()
    # the blockers named are at fault only where they are named
    shelves = {model.ids.index("shelf_a"), model.ids.index("shelf_b")}
    assert named.at_fault & shelves and not plain.at_fault & shelves


def test_room_without_door_uses_largest_free_region():
    rep = check_layout(walled_in(doors=()))
    assert rep.unreachable == ["safe"]
    [line] = of(rep, "reachable")
    assert line.startswith("reachable: 'safe' cannot be reached from the largest free region "
                           "(blocked by ")
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
    assert of(rep, "reachable") == [
        "reachable: 'safe' cannot be reached from door 1 (blocked by 'shelf_a')",
        "reachable: door 1 cannot be reached from door 0 (blocked by 'shelf_a')"]
    assert rep.blocked_by == {"safe": ["shelf_a"], "door 1": ["shelf_a"]}
    assert rep.unreachable == ["safe"]


def test_a_room_with_two_doors_can_be_walked_through():
    """Door to door, with no primary object at all: a shelf across the room fails it, the
    same shelf with a gap an agent fits through does not."""
    second = {"wall": 2, "offset": 3.5, "width": 0.8}
    doors = [DOOR, second]
    across = Layout(make_plan([obj("shelf_a", 3.9, 0.2)], doors=doors),
                    {"shelf_a": Pose(2.0, 2.0, 0.0)})
    rep = check_layout(across)
    assert of(rep, "reachable") == [
        "reachable: door 1 cannot be reached from door 0 (blocked by 'shelf_a')"]
    assert rep.unreachable == [] and rep.blocked_by == {"door 1": ["shelf_a"]}
    gap = Layout(make_plan([obj("shelf_a", 3.2, 0.2)], doors=doors),
                 {"shelf_a": Pose(1.6, 2.0, 0.0)})  # 0.8 m free at the right wall
    assert check_layout(gap).ok
    [plain] = check_floors([across], name_blockers=False)
    assert plain.failures == ["reachable: door 1 cannot be reached from door 0"]


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
    assert CHECKS == ("collision", "outside", "door", "window", "access", "surface",
                      "navigable", "reachable")


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


# -- walkable floor covers -------------------------------------------------------------


def kids_room(cover: dict | None = None, **changes: Pose) -> Layout:
    """A 3 x 3 m kids' room with two beds and a rug between them, under both and a toy box."""
    plan = Plan.model_validate({
        "name": "kids_room",
        "room": {"polygon": [[0, 0], [3, 0], [3, 3], [0, 3]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 0.6, "width": 0.8}],
                 "windows": [{"wall": 2, "offset": 1.5, "width": 1.0}]},
        "objects": [
            obj("bed_1", 0.8, 1.9, primary=True, h=0.5),
            obj("bed_2", 0.8, 1.9, primary=True, h=0.5),
            obj("desk", 0.9, 0.5, primary=True, h=0.75),
            obj("chair", 0.4, 0.4, h=0.8),
            obj("toy_box", 0.5, 0.35, h=0.5),
            {"id": "rug", "category": "area rug", "size": [1.6, 0.9, 0.01], **(cover or {})},
        ],
    })
    poses = {"bed_1": Pose(0.4, 2.05, 0.0), "bed_2": Pose(2.6, 2.05, 0.0),
             "desk": Pose(2.55, 0.25, math.pi), "chair": Pose(2.55, 0.7, 0.0),
             "toy_box": Pose(1.5, 2.8, math.pi),   # under the window, half on the rug
             "rug": Pose(1.5, 2.3, 0.0)}           # 0.1 m under each bed
    return Layout(plan, {**poses, **changes})


def test_a_rug_under_furniture_is_no_obstacle():
    lay = kids_room()
    assert lay.plan.object("rug").is_walkable
    rep = check_layout(lay)
    assert rep.ok, rep.failures
    mask, _ = occupancy_mask(lay)
    without = Layout(lay.plan, {k: p for k, p in lay.poses.items() if k != "rug"})
    assert (mask == occupancy_mask(without)[0]).all()
    assert rep.free_fraction == check_layout(without).free_fraction


def test_the_same_rug_marked_not_walkable_is_an_obstacle():
    rep = check_layout(kids_room({"walkable": False}))
    assert not rep.ok
    assert {f.split(" overlap")[0] for f in of(rep, "collision")} == {
        "collision: 'bed_1' and 'rug'", "collision: 'bed_2' and 'rug'",
        "collision: 'toy_box' and 'rug'"}
    assert rep.free_fraction < check_layout(kids_room()).free_fraction


def test_walkable_covers_may_overlap_lie_in_a_door_swing_but_not_leave_the_room():
    covers = [{"id": "rug", "category": "rug", "size": [2.0, 1.4, 0.01]},
              {"id": "bath_mat", "category": "bath_mat", "size": [0.6, 0.4, 0.01]},
              {"id": "doormat", "category": "doormat", "size": [0.8, 0.5, 0.02]}]
    plan = make_plan([*BEDROOM_OBJECTS, *covers], rules=BEDROOM_RULES)
    poses = {**CLEAN, "rug": Pose(1.5, 2.2, 0.0),      # under the bed's foot
             "bath_mat": Pose(2.0, 1.6, 0.0),          # on the rug's edge
             "doormat": Pose(2.5, 0.3, 0.0)}           # in the door's swing square
    rep = check_layout(Layout(plan, poses))
    assert rep.ok, rep.failures
    out = check_layout(Layout(plan, {**poses, "doormat": Pose(2.5, 0.1, 0.0)}))
    assert of(out, "outside") == ["outside: 'doormat' pokes 0.12 m² out of the room"]


def test_a_walkable_primary_object_must_still_be_reachable():
    rep = check_layout(kids_room({"primary": True}))
    assert rep.ok, rep.failures
    boxed = kids_room({"primary": True, "size": [0.6, 0.4, 0.01]}, rug=Pose(1.5, 2.8, 0.0),
                      toy_box=Pose(1.5, 2.35, 0.0), bed_1=Pose(0.6, 2.05, 0.0),
                      bed_2=Pose(2.4, 2.05, 0.0))
    # the toy box and the beds close the strip under the window where the rug lies
    rep = check_layout(boxed)
    assert rep.unreachable == ["rug"]
    assert rep.blocked_by["rug"] and "rug" not in rep.blocked_by["rug"]


# -- free fraction as DESIGN.md defines it ---------------------------------------------


def hallway() -> Layout:
    """A 0.6 x 4 m hallway with a coat rack at its end: only the wall band takes room."""
    plan = Plan.model_validate({
        "name": "hallway",
        "room": {"polygon": [[0, 0], [0.6, 0], [0.6, 4], [0, 4]],
                 "doors": [{"wall": 0, "offset": 0.3, "width": 0.6}]},
        "objects": [obj("coat_rack", 0.3, 0.3, primary=True, h=1.8)],
    })
    return Layout(plan, {"coat_rack": Pose(0.3, 3.8, math.pi)})


def test_free_fraction_does_not_inflate_the_walls():
    rep = check_layout(hallway())
    assert rep.ok, rep.failures
    assert rep.free_fraction > 0.8                       # floor minus the inflated coat rack
    assert rep.navigable_fraction < 0.3                  # the wall band, reported only
    assert 0.0 <= rep.navigable_fraction <= rep.free_fraction <= 1.0
    assert "with the wall band" in str(rep)
    banded = check_layout(hallway(), wall_band=True)
    [line] = of(banded, "navigable")
    assert "for the centre of an agent of radius 0.2 m" in line
    assert banded.free_fraction == rep.free_fraction


def test_reachability_keeps_the_wall_band():
    # a 0.35 m wide hallway: the floor is free (nothing but walls) but no agent fits
    plan = Plan.model_validate({
        "name": "slot",
        "room": {"polygon": [[0, 0], [0.35, 0], [0.35, 3], [0, 3]],
                 "doors": [{"wall": 0, "offset": 0.175, "width": 0.35}]},
        "objects": [obj("hook", 0.1, 0.1, primary=True, h=1.5)],
    })
    rep = check_layout(Layout(plan, {"hook": Pose(0.175, 2.9, 0.0)}))
    assert rep.free_fraction > 0.8
    assert rep.unreachable == ["hook"]
    assert of(rep, "reachable") == [
        "reachable: 'hook' cannot be reached from door 0 (the walls leave no way through)"]


NUMBERS = re.compile(r"only ([0-9.]+)% of the floor .* \(need ([0-9.]+)%\)")


@settings(max_examples=30, deadline=None)
@given(margin=st.floats(1e-5, 0.02))
def test_the_shown_free_fraction_is_visibly_below_the_threshold(margin):
    lay = crowded()
    free = check_layout(lay).free_fraction
    need = min(1.0, free + margin)
    [line] = of(check_layout(lay, min_free_fraction=need), "navigable")
    shown, needed = map(float, NUMBERS.search(line).groups())
    assert shown < needed
    assert abs(shown - 100 * free) < 0.5 and abs(needed - 100 * need) < 1e-3


def test_a_default_threshold_reads_30_percent():
    lay = crowded()
    free = check_layout(lay).free_fraction
    [line] = of(check_layout(lay, min_free_fraction=round(free, 3) + 0.0005), "navigable")
    assert "need " in line
    rep = check_layout(lay)
    assert "(need 30%)" in of(rep, "navigable")[0]


# -- window clearance ---------------------------------------------------------------------


def window_room(**poses: Pose) -> Layout:
    # SQUARE's window: wall 2 (top, y = 4), centre x = 2, 1.2 m wide: zone x 1.4..2.6, y 3.5..4
    objects = [obj("wardrobe", 1.2, 0.6, h=2.0), obj("bench", 1.0, 0.4, h=0.45)]
    return Layout(make_plan(objects), {"wardrobe": Pose(3.7, 1.5, math.pi / 2),
                                       "bench": Pose(0.5, 2.0, -math.pi / 2), **poses})


def test_a_wardrobe_in_front_of_a_window_fails_and_a_low_bench_passes():
    assert check_layout(window_room()).ok
    rep = check_layout(window_room(wardrobe=Pose(2.0, 3.7, math.pi)))
    assert of(rep, "window") == [
        "window: 'wardrobe' (2.00 m tall) stands in front of window 0 (sill 0.90 m)"]
    assert rep.failed("window") and not rep.failed("collision")
    assert check_layout(window_room(bench=Pose(2.0, 3.8, math.pi))).ok
    corner = check_layout(window_room(wardrobe=Pose(3.1, 3.7, math.pi)))  # 0.1 m into the zone
    assert of(corner, "window")
    off = check_layout(window_room(wardrobe=Pose(2.0, 3.7, math.pi)), window_clearance=False)
    assert off.ok


def test_window_zone_follows_clearance_and_sill():
    lay = window_room(wardrobe=Pose(2.0, 3.0, math.pi))  # 0.7 m from the wall: y 2.7..3.3
    assert check_layout(lay).ok
    data = lay.plan.model_dump()
    data["room"]["windows"][0]["clearance"] = 0.8
    deep = Layout(Plan.model_validate(data), lay.poses)
    assert of(check_layout(deep), "window")
    data["room"]["windows"][0].update(clearance=0.5, sill=2.05, height=0.6)
    high = Layout(Plan.model_validate(data), {**lay.poses, "wardrobe": Pose(2.0, 3.7, math.pi)})
    assert check_layout(high).ok  # the wardrobe stays below a high window
    data["room"]["windows"][0].update(clearance=0.0, sill=0.9, height=1.2)
    none = Layout(Plan.model_validate(data), {**lay.poses, "wardrobe": Pose(2.0, 3.7, math.pi)})
    assert check_layout(none).ok
    centre, right, front, half, sill = window_zones(Plan.model_validate(data).room)
    assert half.tolist() == [[0.6, 0.0]] and sill.tolist() == [0.9]


def test_window_zones_geometry():
    centre, right, front, half, sill = window_zones(window_room().plan.room)
    np.testing.assert_allclose(centre, [[2.0, 3.75]])
    np.testing.assert_allclose(front, [[0.0, -1.0]], atol=1e-12)  # into the room
    np.testing.assert_allclose(half, [[0.6, 0.25]])
    assert sill.tolist() == [0.9]
    with pytest.raises(TypeError, match=r"layout\.plan\.room"):  # the geometry has no sills
        window_zones(window_room().room)


# -- random plans ---------------------------------------------------------------------------


@settings(max_examples=25, deadline=None)
@given(plan=plans(max_objects=6), seed=st.integers(0, 2**16),
       walkable=st.lists(st.booleans(), min_size=6, max_size=6))
def test_checks_never_crash_on_random_plans_and_fractions_stay_in_range(plan, seed, walkable):
    data = plan.model_dump()
    for o, w in zip(data["objects"], walkable, strict=False):
        o["walkable"] = w
    plan = Plan.model_validate(data)
    lay = random_layout(plan, seed, reject=False)
    rep = check_layout(lay, access_clearance=True)
    assert 0.0 <= rep.navigable_fraction <= rep.free_fraction <= 1.0
    assert rep.ok == (not rep.failures)
    assert set(rep.unreachable) == set(rep.blocked_by)
    for f in rep.failures:
        assert f.split(": ", 1)[0] in CHECKS
        assert f.split(": ", 1)[1]
    for oid, who in rep.blocked_by.items():
        assert oid not in who
        assert not any(plan.object(b).is_walkable for b in who)


@settings(max_examples=25, deadline=None)
@given(plan=plans(max_objects=6), seed=st.integers(0, 2**16), count=st.integers(2, 5))
def test_layouts_checked_together_get_the_reports_they_get_alone(plan, seed, count):
    from forcelayout.validate.checks import check_floors

    lays = [random_layout(plan, seed + k, reject=False) for k in range(count)]
    together = check_floors(lays, access_clearance=True)
    for lay, rep in zip(lays, together, strict=True):
        alone = check_layout(lay, access_clearance=True)
        assert rep.failures == alone.failures and rep.unreachable == alone.unreachable
        assert rep.blocked_by == alone.blocked_by
        assert (rep.free_fraction, rep.navigable_fraction) == (alone.free_fraction,
                                                               alone.navigable_fraction)
        assert np.array_equal(rep.free_mask, alone.free_mask)


def test_crowded_layouts_checked_together_fail_as_they_fail_alone():
    """Collisions, objects outside, in door swings and window zones, blocked paths: the
    same lines, floor by floor, whether checked together or alone."""
    from forcelayout.validate.checks import check_floors

    plan = make_plan(BEDROOM_OBJECTS)
    rng = np.random.default_rng(0)
    lays = [Layout(plan, {o.id: Pose(*rng.uniform(-0.3, 4.3, 2), rng.uniform(-3.2, 3.2))
                          for o in plan.objects}) for _ in range(24)]
    together = check_floors(lays)
    alone = [check_layout(lay) for lay in lays]
    assert [r.failures for r in together] == [r.failures for r in alone]
    kinds = {f.split(":", 1)[0] for r in alone for f in r.failures}
    assert {"collision", "outside", "door", "reachable"} <= kinds


ACCESS_PLAN = Plan.from_dict({
    "name": "access", "room": {"polygon": [[0, 0], [3, 0], [3, 3], [0, 3]]},
    "objects": [{"id": "wardrobe", "category": "wardrobe", "size": [1.0, 0.6, 2.0]},
                {"id": "box", "category": "box", "size": [0.6, 0.6, 0.5]},
                {"id": "bed", "category": "bed", "size": [1.4, 2.0, 0.5]}],
    "rules": []})


def test_access_check_needs_one_free_side_of_each_object():
    ward = Pose(1.5, 0.3, 0.0)  # back to the wall y = 0, front towards +y: zone y 0.6..1.2
    bed = Pose(0.7, 2.0, 0.0)  # left side against the wall x = 0; 0.08 m2 in that zone
    lay = Layout(ACCESS_PLAN, {"wardrobe": ward, "box": Pose(1.5, 1.0, 0.0), "bed": bed})
    assert not [f for f in check_layout(lay).failures if f.startswith("access")]  # opt-in
    rep = check_layout(lay, access_clearance=True)
    lines = rep.by_check()["access"]
    assert any("'wardrobe'" in f and "front (0.60 m deep) blocked by 'box'" in f for f in lines)
    # the box at the foot of the bed's right side leaves the rest of it to get in from
    assert not any(f.startswith("'bed'") for f in lines)
    whole = check_layout(lay, access_clearance=True, access_width=2.0).by_check()["access"]
    assert any("'bed'" in f and "left (0.50 m deep) blocked by the wall (1.00 m² off the floor)"
               in f and "right (0.50 m deep) blocked by 'box' (0.12 m²)" in f for f in whole)
    assert rep.failed("access")
    # the box out of the way: the wardrobe's front and the bed's right side are free; the
    # bed's corner in the wardrobe's zone is no block, unless max_access_overlap is smaller
    clear = Layout(ACCESS_PLAN, {"wardrobe": ward, "box": Pose(2.6, 2.6, 0.0), "bed": bed})
    assert not check_layout(clear, access_clearance=True).failed("access")
    # ... and a 0.6 m stretch of the wardrobe's front is free of it, unless the whole
    # front must be
    assert not check_layout(clear, access_clearance=True, max_access_overlap=0.01).failed(
        "access")
    tight = check_layout(clear, access_clearance=True, max_access_overlap=0.01,
                         access_width=1.0)
    assert tight.by_check()["access"] == [
        "'wardrobe' has no free side to be used from (front (0.60 m deep) blocked by 'bed' "
        "(0.08 m²))"]


_USED = {"sides": ["back"], "depth": 0.9}


@pytest.mark.parametrize("rules, access, blocked", [
    ([], _USED, ["counter", "island"]),
    # a rule that keeps its object close lets it stand in its target's zone (a table in
    # the counter's front), not the target in the object's own ...
    ([{"rule": "in_front_of", "object": "island", "target": "counter",
       "params": {"distance": 1.3}}], False, []),
    ([{"rule": "in_front_of", "object": "counter", "target": "island"}], False, ["counter"]),
    # ... unless the rule stands it in front of (or behind) the target and the object is
    # used itself: an island with free floor behind it for its stools keeps out of the
    # counter's zone as well
    ([{"rule": "in_front_of", "object": "island", "target": "counter",
       "params": {"distance": 1.3}}], _USED, ["counter", "island"]),
    # side by side (next_to, near), each lets the other in: a run of counters at a corner
    ([{"rule": "near", "object": "island", "target": "counter"},
      {"rule": "near", "object": "counter", "target": "island"}], _USED, []),
    # a rule that keeps no closeness lets neither: a bed facing a dresser does not block it
    ([{"rule": "facing", "object": "island", "target": "counter"}], _USED,
     ["counter", "island"]),
])
def test_only_what_a_rule_keeps_close_and_is_not_used_itself_may_stand_in_a_zone(
        rules, access, blocked):
    plan = Plan.from_dict({
        "name": "kitchen", "room": {"polygon": [[0, 0], [4, 0], [4, 4], [0, 4]]},
        "objects": [{"id": "counter", "category": "counter", "size": [1.8, 0.6, 0.9]},
                    {"id": "island", "category": "kitchen_island", "size": [1.8, 0.9, 0.9],
                     "access": access}],
        "rules": rules})
    # the counter's back to the wall y = 0, its front zone y 0.6..1.2; the island 0.3 m in
    # front of it, facing the same way: its back zone (y 0.9..1.8) holds the counter's front
    lay = Layout(plan, {"counter": Pose(2.0, 0.3, 0.0), "island": Pose(2.0, 1.35, 0.0)})
    lines = check_layout(lay, access_clearance=True).by_check().get("access", [])
    assert sorted(f.split("'")[1] for f in lines) == blocked


def test_a_chair_around_a_desk_is_let_into_its_zone_whatever_room_its_rule_asks():
    """``around`` asks room behind a chair to pull it out: that is no use of its own, and
    the chair still stands in the desk's front zone."""
    from forcelayout.access import related_pairs
    from forcelayout.bindings import compile_plan

    plan = Plan.from_dict({
        "name": "office", "room": {"polygon": [[0, 0], [4, 0], [4, 4], [0, 4]]},
        "objects": [{"id": "desk", "category": "desk", "size": [1.6, 0.8, 0.75]},
                    {"id": "chair", "category": "chair", "size": [0.5, 0.5, 0.9]},
                    {"id": "armchair", "category": "armchair", "size": [0.8, 0.8, 0.9]}],
        "rules": [{"rule": "around", "object": "chair", "target": "desk"},
                  {"rule": "in_front_of", "object": "armchair", "target": "desk"}]})
    ids = list(plan.ids)
    rel = related_pairs(ids, compile_plan(plan).bindings, {o.id: o for o in plan.objects})
    desk, chair, arm = (ids.index(i) for i in ("desk", "chair", "armchair"))
    assert rel[desk, chair] and not rel[chair, desk]
    assert not rel[desk, arm]  # an armchair is used itself: its leg room is its own


@pytest.mark.parametrize("rules, free", [
    ([("near", "armchair", "table"), ("facing", "armchair", "table")], True),
    ([("facing", "armchair", "table")], False),  # faced only: in its way
    ([("near", "armchair", "table")], False),  # near only: the table may stand anywhere
    ([("near", "armchair", "table"), ("facing", "armchair", "lamp")], False),
])
def test_what_a_seat_is_kept_near_and_faces_stands_in_its_front_zone(rules, free):
    """An armchair near a coffee table and facing it is used with it: the table, 0.3 m in
    front, leaves its front zone free; any other object there blocks it."""
    from forcelayout.access import zone_states

    plan = Plan.from_dict({
        "name": "corner", "room": {"polygon": [[0, 0], [4, 0], [4, 4], [0, 4]]},
        "objects": [{"id": "armchair", "category": "armchair", "size": [0.8, 0.8, 0.9]},
                    {"id": "table", "category": "coffee_table", "size": [1.0, 0.6, 0.4]},
                    {"id": "lamp", "category": "floor_lamp", "size": [0.3, 0.3, 1.6]}],
        "rules": [{"rule": r, "object": o, "target": t} for r, o, t in rules]})
    lay = Layout(plan, {"armchair": Pose(2.0, 1.0, 0.0), "table": Pose(2.0, 2.0, 0.0),
                        "lamp": Pose(3.5, 3.5, 0.0)})
    (zone,) = [z for z in zone_states(lay) if z.object == "armchair"]
    assert zone.side == "front" and zone.free == free
    assert [c for c, _ in zone.covered_by] == ([] if free else ["table"])


@pytest.mark.parametrize("width, blocked", [(0.6, False), (0.8, False), (1.0, True), (2.0, True)])
def test_an_access_zone_is_free_where_a_stretch_a_person_wide_is(width, blocked):
    # a box in the middle of the bed's free side leaves 0.7 m at either end of it; a stretch
    # of 0.8 m covers 0.1 m x 0.5 m of the box, within max_access_overlap (0.1 m²)
    lay = Layout(ACCESS_PLAN, {"bed": Pose(0.7, 2.0, 0.0), "box": Pose(1.65, 2.0, 0.0)})
    rep = check_layout(lay, access_clearance=True, access_width=width)
    assert rep.failed("access") == blocked
    if blocked:
        assert rep.by_check()["access"] == [
            "'bed' has no free side to be used from (left (0.50 m deep) blocked by the wall "
            "(1.00 m² off the floor); right (0.50 m deep) blocked by 'box' (0.30 m²))"]


@pytest.mark.parametrize("gap, blocked", [(0.25, False), (0.15, True), (0.02, True)])
def test_a_chair_around_a_table_needs_room_behind_it(gap, blocked):
    """A chair around a table owns a zone 0.3 m deep behind it: with its back ``gap`` from
    a wall, the part of the zone off the floor (0.45 m wide) blocks it beyond a third of it
    (0.045 m²; 0.1 m², three quarters of the zone, had let a chair 0.15 m off a wall by)."""
    from forcelayout.access import zone_states

    plan = Plan.from_dict({
        "name": "table", "room": {"polygon": [[0, 0], [3, 0], [3, 3], [0, 3]]},
        "objects": [{"id": "table", "category": "table", "size": [1.2, 0.8, 0.75]},
                    {"id": "chair", "category": "chair", "size": [0.45, 0.5, 0.9]}],
        "rules": [{"rule": "around", "object": "chair", "target": "table"}]})
    # the chair faces +y towards the table, its back towards the wall y = 0
    chair = Pose(1.5, gap + 0.25, 0.0)
    lay = Layout(plan, {"table": Pose(1.5, gap + 0.5 + 0.02 + 0.4, 0.0), "chair": chair})
    (zone,) = [z for z in zone_states(lay) if z.object == "chair"]
    assert zone.side == "back" and zone.depth == pytest.approx(0.3)
    assert zone.free == (not blocked)
    assert check_layout(lay, access_clearance=True).failed("access") == blocked


def test_layout_zones_lie_beside_the_sides_they_serve():
    from forcelayout.access import layout_zones

    plan = _box_in_front_of("desk")
    lay = Layout(plan, {"desk": Pose(1.5, 0.3, 0.0), "box": Pose(1.5, 1.0, 0.0),
                        "bed": Pose(0.7, 2.0, 0.5 * math.pi)})
    zones = {(oid, side): c for oid, side, c in layout_zones(lay)}
    assert set(zones) == {("desk", "front"), ("bed", "left"), ("bed", "right")}
    # the desk's front zone: as wide as the desk, deeper by the box in front of it
    lo, hi = zones["desk", "front"].min(0), zones["desk", "front"].max(0)
    np.testing.assert_allclose([lo, hi], [[1.0, 0.6], [2.0, 1.8]], atol=1e-9)
    # the bed turned a quarter: its long sides face -y and +y, 0.5 m deep, 2 m long
    for side in ("left", "right"):
        c = zones["bed", side]
        assert shapely.Polygon(c).area == pytest.approx(2.0 * 0.5)
        assert shapely.Polygon(c).distance(shapely.Polygon(lay.corners("bed"))) < 1e-9
        assert shapely.Polygon(c).intersection(shapely.Polygon(lay.corners("bed"))).area < 1e-9


def test_zone_states_say_which_zones_are_free_and_what_covers_the_others():
    from forcelayout.access import layout_zones, zone_states

    lay = Layout(ACCESS_PLAN, {"wardrobe": Pose(1.5, 0.3, 0.0), "box": Pose(1.5, 1.0, 0.0),
                               "bed": Pose(0.7, 2.0, 0.0)})
    states = {(z.object, z.side): z for z in zone_states(lay)}
    assert [(z.object, z.side) for z in zone_states(lay)] == [
        (oid, side) for oid, side, _ in layout_zones(lay)]
    assert not states["wardrobe", "front"].free
    assert states["wardrobe", "front"].covered_by[0][0] == "box"
    assert states["bed", "left"].covered_by == [("wall", pytest.approx(1.0))]
    assert not states["bed", "left"].free and states["bed", "right"].free
    assert states["bed", "right"].depth == pytest.approx(0.5)
    # a wider person finds the bed's right side blocked too (the box at its foot)
    wide = {(z.object, z.side): z.free for z in zone_states(lay, access_width=2.0)}
    assert not wide["bed", "right"]
    with pytest.raises(ValueError, match="access_width"):
        zone_states(lay, access_width=0.0)



def test_blocked_objects_are_those_with_no_zone_free_with_what_covers_them():
    from forcelayout.access import blocked_objects, zone_states

    lay = Layout(ACCESS_PLAN, {"wardrobe": Pose(1.5, 0.3, 0.0), "box": Pose(1.5, 1.0, 0.0),
                               "bed": Pose(0.7, 2.0, 0.0)})
    shut = blocked_objects(lay)
    assert list(shut) == ["wardrobe"]  # the bed's right side is free
    assert shut["wardrobe"] == [c for z in zone_states(lay) if z.object == "wardrobe"
                                for c in z.covered_by]
    assert shut["wardrobe"][0][0] == "box"
    assert set(blocked_objects(lay, access_width=2.0)) == {"wardrobe", "bed"}

@given(seed=st.integers(0, 2**16))
@settings(max_examples=25, deadline=None)
def test_an_object_fails_the_access_check_exactly_when_no_zone_of_it_is_free(seed):
    from forcelayout.access import zone_states

    rng = np.random.default_rng(seed)
    lay = Layout(ACCESS_PLAN, {o.id: Pose(*rng.uniform(0.3, 2.7, 2),
                                          float(rng.integers(4)) * 0.5 * math.pi)
                               for o in ACCESS_PLAN.objects})
    zones = zone_states(lay)
    none_free = {z.object for z in zones} - {z.object for z in zones if z.free}
    named = {f.split("'")[1] for f in check_layout(lay, access_clearance=True).failures
             if f.startswith("access:")}
    assert named == none_free


def _box_in_front_of(category: str, rule: str = "in_front_of") -> Plan:
    """:data:`ACCESS_PLAN` with its wardrobe as an object of ``category`` (id the same),
    and the box bound to it by ``rule``."""
    objects = ACCESS_PLAN.model_dump()["objects"]
    objects[0] = {**objects[0], "id": category, "category": category}
    return Plan.from_dict({**ACCESS_PLAN.model_dump(), "objects": objects, "rules": [
        {"rule": rule, "object": "box", "target": category}]})


def test_access_check_lets_related_objects_stand_in_a_zone():
    plan = _box_in_front_of("desk")
    lay = Layout(plan, {"desk": Pose(1.5, 0.3, 0.0), "box": Pose(1.5, 1.0, 0.0)})
    assert not check_layout(lay, access_clearance=True).failed("access")
    # the free floor starts behind the box: the desk's zone is the box deeper
    lay = Layout(plan, {"desk": Pose(1.5, 0.3, 0.0), "box": Pose(1.5, 1.0, 0.0),
                        "bed": Pose(1.5, 2.3, 0.5 * math.pi)})
    assert any("'desk'" in f and "front (1.20 m deep) blocked by 'bed'" in f
               for f in check_layout(lay, access_clearance=True).failures)


@pytest.mark.parametrize("rule, blocked", [("in_front_of", True), ("near", True),
                                           ("next_to", False)])
def test_only_an_object_beside_them_stands_where_doors_open(rule, blocked):
    """Doors open into a wardrobe's zone: a box a rule puts in front of it or near it
    blocks it all the same (a bench in front of a wardrobe stands beyond its doors); one
    standing beside it, the next unit of a run, may reach into it."""
    from forcelayout import rules
    from forcelayout.access import access_of

    beside = rules.get_rule(rule).start.place in rules.StartHint.SIDE_PLACES
    assert beside == (not blocked)
    plan = _box_in_front_of("wardrobe", rule)
    assert access_of(plan.object("wardrobe")).doors
    assert not access_of(plan.object("bed")).doors
    lay = Layout(plan, {"wardrobe": Pose(1.5, 0.3, 0.0), "box": Pose(1.5, 1.0, 0.0)})
    assert check_layout(lay, access_clearance=True).failed("access") == blocked
    # a plan may say so of any object
    objects = plan.model_dump()["objects"]
    objects[0]["access"] = {"sides": ["front"], "depth": 0.6, "doors": False}
    lay = Layout(Plan.from_dict({**plan.model_dump(), "objects": objects}),
                 {"wardrobe": Pose(1.5, 0.3, 0.0), "box": Pose(1.5, 1.0, 0.0)})
    assert not check_layout(lay, access_clearance=True).failed("access")


@pytest.mark.parametrize("kwargs, says", [
    ({"max_access_overlap": "0.1"}, "max_access_overlap must be a finite number"),
    ({"agent_radius": True}, "agent_radius must be a finite number"),
    ({"access_clearance": "no"}, "access_clearance must be True or False"),
    ({"access_width": 0.0}, "access_width must be a finite number > 0"),
    ({"min_free_fraction": 1.5}, "min_free_fraction must lie in"),
])
def test_check_parameters_of_the_wrong_type_name_the_parameter(kwargs, says):
    import forcelayout as fl

    with pytest.raises(ValueError, match=says):
        check_layout(bedroom(), **kwargs)
    # and before any sampling
    with pytest.raises(ValueError, match=f"Options.check_kwargs: {says}"):
        fl.Options(check_kwargs=kwargs)


def test_check_kwargs_none_keeps_the_defaults_and_a_list_is_refused():
    import forcelayout as fl

    assert fl.Options(check_kwargs=None).check_kwargs == {}
    assert len(fl.generate("living_room", 1, seed=0, check_kwargs=None)) == 1
    with pytest.raises(TypeError, match="check_kwargs must be a dict"):
        fl.Options(check_kwargs=["access_clearance"])


def test_check_parameters_judges_only_what_is_given_and_refuses_an_unknown_name():
    from forcelayout.validate import check_parameters

    check_parameters()
    check_parameters(access_width=0.8, wall_band=True, min_free_fraction=0)
    with pytest.raises(ValueError, match="unknown check parameter 'acces_width'"):
        check_parameters(acces_width=0.8)


def test_access_parameters_without_the_access_check_warn():
    import forcelayout as fl

    with pytest.warns(UserWarning, match="access_width set but the access check is off"):
        fl.Options(check_kwargs={"access_width": 0.8})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fl.Options(check_kwargs={"access_width": 0.8, "access_clearance": True})


def test_an_unknown_check_parameter_is_refused_before_sampling():
    import forcelayout as fl

    with pytest.raises(ValueError, match="Did you mean 'access_clearance'"):
        fl.Options(check_kwargs={"acess_clearance": True})
    with pytest.raises(ValueError, match="unknown check parameter 'acess_clearance'"):
        fl.generate("bedroom", 1, check_kwargs={"acess_clearance": True})
