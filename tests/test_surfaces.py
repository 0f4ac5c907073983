"""Surface placement: objects on tops, on walls (height bands, above) and on the ceiling."""

import copy

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import forcelayout as fl
from forcelayout.bindings import compile_plan
from forcelayout.errors import PlanError
from forcelayout.geometry import RoomGeometry, box_corners
from forcelayout.surfaces import check_surfaces, free_wall_stretches
from forcelayout.surfaces.walls import back_wall, binding_walls, hanging_centres, wall_pose
from forcelayout.validate import check_layout

ROOM = {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]], "height": 2.7,
        "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}],
        "windows": [{"wall": 2, "offset": 2.0, "width": 1.2, "sill": 0.9, "height": 1.2}]}

PLAN = {
    "name": "surfaces",
    "room": ROOM,
    "objects": [
        {"id": "bed", "category": "bed", "size": [1.4, 2.0, 0.5], "primary": True},
        {"id": "nightstand", "category": "nightstand", "size": [0.45, 0.4, 0.5]},
        {"id": "lamp", "category": "lamp", "size": [0.2, 0.2, 0.35]},
        {"id": "book", "category": "book", "size": [0.15, 0.2, 0.04]},
        {"id": "painting", "category": "painting", "size": [0.9, 0.04, 0.6]},
        {"id": "clock", "category": "clock", "size": [0.3, 0.05, 0.3]},
        {"id": "light", "category": "ceiling_light", "size": [0.4, 0.4, 0.15]},
    ],
    "rules": [
        {"rule": "at_wall", "object": "bed"},
        {"rule": "next_to", "object": "nightstand", "target": "bed"},
        {"rule": "on_top", "object": "lamp", "target": "nightstand"},
        {"rule": "on_top", "object": "book", "target": "nightstand"},
        {"rule": "above", "object": "painting", "target": "bed"},
        {"rule": "on_wall_mid", "object": "clock", "params": {"wall": 2}},
        {"rule": "on_ceiling", "object": "light"},
    ],
}


@pytest.fixture(scope="module")
def layouts():
    return [fl.solve(PLAN, seed, check=False) for seed in range(4)]


def _inside_top(lay, child, parent):
    st_ = lay.state([child, parent])
    c = st_.corners[0] - st_.pos[1]
    x, y = c @ st_.right[1], c @ st_.front[1]
    w, d = st_.size[1, :2] / 2
    return bool((np.abs(x) <= w + 1e-6).all() and (np.abs(y) <= d + 1e-6).all())


def test_every_object_gets_a_pose(layouts):
    for lay in layouts:
        assert lay.report.missing == []
        assert set(lay.poses) == set(lay.plan.ids)


def test_on_top_children_rest_inside_the_parents_top(layouts):
    for lay in layouts:
        for kid in ("lamp", "book"):
            p = lay.poses[kid]
            assert p.surface == "nightstand"
            assert p.z == pytest.approx(0.5)
            assert _inside_top(lay, kid, "nightstand")
        assert lay.gap("lamp", "book") >= -1e-6  # they do not overlap on the top


def test_painting_hangs_on_a_wall_over_the_bed(layouts):
    for lay in layouts:
        p = lay.poses["painting"]
        assert p.surface.startswith("wall:")
        w = int(p.surface[5:])
        room = lay.room
        assert p.z >= 0.5 + 0.1 - 1e-6  # above the bed's top
        assert p.z + 0.6 <= 2.7 + 1e-6
        bed = lay.corners("bed") @ room.tangent[w] - room.tangent_offset[w]
        u = np.array([p.x, p.y]) @ room.tangent[w] - room.tangent_offset[w]
        assert bed.min() - 1e-6 <= u <= bed.max() + 1e-6
        # back on the wall, front into the room
        back = lay.state(["painting"]).corners[0, :2] @ room.normal[w] - room.normal_offset[w]
        assert np.abs(back).max() < 1e-6
        # on a wall the bed stands by
        off = lay.corners("bed") @ room.normal[w] - room.normal_offset[w]
        assert off.min() <= 0.3 + 1e-6


def _above_met(bed: fl.Pose, wall: int, u: float, **params: float) -> bool:
    room = RoomGeometry.from_room(fl.load_plan(PLAN).room)
    poses = {"bed": bed, "painting": wall_pose(room, wall, u, 1.0, 0.04)}
    plan = copy.deepcopy(PLAN)
    plan["objects"] = [o for o in plan["objects"] if o["id"] in poses]
    plan["rules"] = [r for r in plan["rules"] if r["rule"] in ("above", "at_wall")]
    for r in plan["rules"]:
        if r["rule"] == "above":
            r["params"] = params
    report = fl.Layout(fl.load_plan(plan), poses).rule_report()
    return next(r.satisfied for r in report if r.rule == "above")


def test_above_needs_the_target_by_the_wall_it_hangs_on():
    # head against wall 3 (x = 0), the bed's foot towards x = 2; the painting over its head
    at_wall = fl.Pose(1.0, 1.5, -np.pi / 2, 0.0, "floor")
    assert _above_met(at_wall, 3, 1.5)
    # the same bed pulled 0.5 m out into the room: the painting is no longer above it
    assert not _above_met(fl.Pose(1.5, 1.5, -np.pi / 2, 0.0, "floor"), 3, 1.5)
    # a bed in the corner of walls 2 and 3, head against wall 3: over its head on wall 3
    # counts; on side wall 2, over the bed's side end (half over the floor), it does not
    corner = fl.Pose(1.0, 2.3, -np.pi / 2, 0.0, "floor")
    assert _above_met(corner, 3, 0.7)
    assert not _above_met(corner, 2, 4.0 - 0.45)
    assert not _above_met(corner, 0, 0.45)
    # unless the plan allows the target's side to the wall, or a larger gap
    assert _above_met(corner, 2, 4.0 - 1.0, max_angle=90.0)
    assert _above_met(fl.Pose(1.5, 1.5, -np.pi / 2, 0.0, "floor"), 3, 1.5, wall_gap=0.6)


def test_above_wants_the_centre_over_the_middle_of_the_target():
    # the bed's side along wall 2 spans x = 0..2 (u = 4 - x): the middle half is u = 2.5..3.5
    corner = fl.Pose(1.0, 2.3, -np.pi / 2, 0.0, "floor")
    side = {"max_angle": 90.0}
    assert _above_met(corner, 2, 3.0, **side) and _above_met(corner, 2, 3.5, **side)
    assert not _above_met(corner, 2, 3.55, **side)  # over the bed's end
    assert _above_met(corner, 2, 3.55, middle=1.0, **side)  # anywhere over the bed
    assert not _above_met(corner, 2, 3.3, middle=0.2, **side) and _above_met(corner, 2, 3.3, **side)


def test_back_wall_is_the_wall_a_footprint_stands_with_its_back_to():
    room = RoomGeometry.from_room(fl.load_plan(PLAN).room)
    half = np.array([0.7, 1.0])
    # flush in the corner of walls 0 and 3 facing +y; against wall 0 facing +y; the same
    # turned to face +x (its side to wall 0, its back to nothing within 0.3 m); mid-room
    pos = np.array([[0.71, 1.01], [2.0, 1.01], [2.0, 0.71], [2.0, 1.5]])
    yaw = np.array([0.0, 0.0, -np.pi / 2, 0.0])
    corners = box_corners(pos, yaw, np.broadcast_to(half, (4, 2)))
    front = np.stack([-np.sin(yaw), np.cos(yaw)], axis=1)
    wall, behind = back_wall(room, corners, front, 0.3, 45.0)
    assert wall[:3].tolist() == [0, 0, 0] and behind.tolist() == [True, True, False, False]
    # any turn: the nearest wall within the gap, the side wall of the corner too
    wall, behind = back_wall(room, corners, front, 0.3)
    assert behind[:3].all() and not behind[3]


def _hanging_centres(size: list[float] | None = None, **params: object) -> np.ndarray:
    plan = copy.deepcopy(PLAN)
    if size is not None:
        next(o for o in plan["objects"] if o["id"] == "painting")["size"] = size
    next(r for r in plan["rules"] if r["rule"] == "above")["params"] = params
    plan = fl.load_plan(plan)
    above = next(b for b in compile_plan(plan).bindings if b.rule.name == "above")
    return hanging_centres(plan, above, target_top=0.5)


# the door's stretch (0.55 to 1.45 m along wall 0) and the window's (1.4 to 2.6 m along
# wall 2) cut out, 0.02 m wider each side
CUT = [[0, 1.47 + 0.45, 3.55], [1, 0.45, 2.55], [2, 0.45, 1.38 - 0.45],
       [2, 2.62 + 0.45, 3.55], [3, 0.45, 2.55]]


def test_hanging_centres_leave_out_openings_the_object_cannot_pass():
    # a 0.9 x 0.6 painting from 0.6 m (the bed's top and 0.1 m) up to 1.5 m (max_gap: 1 m
    # above the bed's top) passes neither the window (0.9 to 2.1 m) nor the door (to 2.1 m)
    assert np.allclose(_hanging_centres(), CUT)
    # with any gap allowed, it fits above both in this 2.7 m room: every wall whole
    spots = _hanging_centres(max_gap=None)
    assert spots[:, 0].tolist() == [0, 1, 2, 3]
    assert np.allclose(spots[:, 1], 0.45) and np.allclose(spots[:, 2], [3.55, 2.55] * 2)
    # a 0.8 m tall one does not, even then
    assert np.allclose(_hanging_centres([0.9, 0.04, 0.8], max_gap=None), CUT)
    # a wall object with no target, pinned to a wall: on that wall only (the clock, on wall
    # 2 beside its window, in its 0.9..2.1 m band)
    plan = fl.load_plan(PLAN)
    clock = next(b for b in compile_plan(plan).bindings if b.object == "clock")
    assert binding_walls(clock, 4) == [2]
    assert np.allclose(hanging_centres(plan, clock, None), [[2, 0.15, 1.23], [2, 2.77, 3.85]])


def test_above_keeps_the_object_within_max_gap_of_the_target():
    bed = fl.Pose(1.0, 1.5, -np.pi / 2, 0.0, "floor")  # head against wall 3, top 0.5 m
    room = RoomGeometry.from_room(fl.load_plan(PLAN).room)
    plan = copy.deepcopy(PLAN)
    plan["objects"] = [o for o in plan["objects"] if o["id"] in ("bed", "painting")]
    plan["rules"] = [r for r in plan["rules"] if r["rule"] == "above"]

    def met(z: float, **params: float | None) -> bool:
        plan["rules"][0]["params"] = params
        poses = {"bed": bed, "painting": wall_pose(room, 3, 1.5, z, 0.04)}
        report = fl.Layout(fl.load_plan(plan), poses).rule_report()
        return report[0].satisfied

    assert met(1.5) and not met(1.6)  # its bottom at most 1 m above the bed's top
    assert met(1.6, max_gap=None) and met(2.0, max_gap=1.5) and not met(1.3, max_gap=0.7)
    with pytest.raises(PlanError, match=r"rules\[0\] \(above\)\.params: max_gap \(0\.3 m\) is "
                       r"below clearance \(0\.5 m\): no height is left between them; raise "
                       r"max_gap or lower clearance$"):
        fl.load_plan(plan | {"rules": [{"rule": "above", "object": "painting", "target": "bed",
                                        "params": {"clearance": 0.5, "max_gap": 0.3}}]})


def test_hung_objects_stay_within_reach_of_their_targets():
    """A shelf above a desk near a window: before ``max_gap``, the desk stood under the
    window in 7 of these 12 layouts, and the shelf hung over the window, 1.35 m above the
    desk's top; now the desk stands beside the window and the shelf within reach."""
    plan = fl.Plan.from_dict({
        "name": "shelf above desk",
        "room": {"polygon": [[0, 0], [3.6, 0], [3.6, 3.0], [0, 3.0]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 0.6, "width": 0.8}],
                 "windows": [{"wall": 2, "offset": 1.8, "width": 1.4, "sill": 0.9}]},
        "objects": [{"id": "desk", "category": "desk", "size": [1.0, 0.6, 0.75]},
                    {"id": "bed", "category": "bed", "size": [0.9, 2.0, 0.5]},
                    {"id": "shelf", "category": "shelf", "size": [0.8, 0.25, 0.25]}],
        "rules": [{"rule": "at_wall", "object": "desk"}, {"rule": "at_wall", "object": "bed"},
                  {"rule": "near_window", "object": "desk", "params": {"distance": 1.6}},
                  {"rule": "above", "object": "shelf", "target": "desk"}]})
    lays = fl.generate(plan, n=12, seed=0, max_attempts=48)
    assert len(lays) == 12
    for lay in lays:
        assert lay.poses["shelf"].z - 0.75 <= 1.0 + 1e-6
        assert all(r.satisfied for r in lay.rule_report())


def test_with_no_wall_within_max_gap_the_object_hangs_higher_its_rule_unmet():
    """A desk that must stand under the window: its shelf is not left out (which would fail
    the sample) but hangs over the window, and ``above`` reports the miss."""
    plan = {"name": "desk under the window",
            "room": {"polygon": [[0, 0], [3.6, 0], [3.6, 3.0], [0, 3.0]], "height": 2.6,
                     "windows": [{"wall": 2, "offset": 1.8, "width": 1.4, "sill": 0.9,
                                  "height": 1.2}]},
            "objects": [{"id": "desk", "category": "desk", "size": [1.0, 0.6, 0.75]},
                        {"id": "shelf", "category": "shelf", "size": [0.8, 0.25, 0.25]}],
            "rules": [{"rule": "at_wall", "object": "desk"},
                      {"rule": "near_window", "object": "desk", "weight": 5.0,
                       "params": {"distance": 0.4}},
                      {"rule": "above", "object": "shelf", "target": "desk"}]}
    for seed in range(4):
        lay = fl.solve(plan, seed)
        assert lay.report.missing == [] and lay.poses["shelf"].surface == "wall:2"
        assert lay.poses["shelf"].z >= 2.1 - 1e-6  # over the window's top
        verdict = {r.rule: r.satisfied for r in lay.rule_report()}
        assert verdict == {"at_wall": True, "near_window": True, "above": False}
    # a floor judge counts the shelf as a rule the sample may leave unmet, not a failure
    from forcelayout.forces import ForceModel
    from forcelayout.verdict import judge_floor
    model = ForceModel(fl.load_plan(plan))
    under = judge_floor(model, np.array([[1.8, 2.7]]), np.array([np.pi]))
    assert under.failures == ["above(shelf, desk)"] and len(under.missed) == 1
    assert under.passes(misses=1) and not under.passes(misses=0)
    assert judge_floor(model, np.array([[0.6, 2.7]]), np.array([np.pi])).failures == [
        "near_window(desk)"]  # beside the window: room above it
    # where no wall has room within max_gap of the desk's top, the plan is refused
    plan["room"]["windows"] = [{"wall": w, "offset": (1.8, 1.5)[w % 2], "sill": 0.8,
                                "width": (3.4, 2.8)[w % 2], "height": 1.3} for w in range(4)]
    with pytest.raises(PlanError, match="band 0.85..2.00 m is 0.10 m .* or raise max_gap"):
        check_surfaces(fl.Plan.from_dict(plan))


def test_clock_keeps_its_band_and_clears_the_window(layouts):
    for lay in layouts:
        p = lay.poses["clock"]
        assert p.surface == "wall:2"
        assert 0.9 - 1e-6 <= p.z and p.z + 0.3 <= 2.1 + 1e-6
        room = lay.room
        u = np.array([p.x, p.y]) @ room.tangent[2] - room.tangent_offset[2]
        # the window spans u in [1.4, 2.6] and heights [0.9, 2.1]: the clock is beside it
        assert u + 0.15 <= 1.4 + 1e-6 or u - 0.15 >= 2.6 - 1e-6


def test_ceiling_light(layouts):
    for lay in layouts:
        p = lay.poses["light"]
        assert p.surface == "ceiling"
        assert p.z == pytest.approx(2.7 - 0.15)
        assert np.hypot(p.x - 2.0, p.y - 1.5) <= 0.3


def test_surface_rules_judge_the_layout(layouts):
    for lay in layouts:
        verdict = {(r.rule, r.object): r.satisfied for r in lay.rule_report()}
        for key in [("on_top", "lamp"), ("on_top", "book"), ("above", "painting"),
                    ("on_wall_mid", "clock"), ("on_ceiling", "light")]:
            assert verdict[key] is True, key


def test_surface_checks_fail_on_a_moved_object(layouts):
    lay = layouts[0]
    poses = dict(lay.poses)
    lamp = poses["lamp"]
    poses["lamp"] = fl.Pose(lamp.x + 2.0, lamp.y, lamp.yaw, lamp.z, lamp.surface)
    poses["light"] = fl.Pose(poses["light"].x, poses["light"].y, 0.0, 1.0, "ceiling")
    moved = fl.Layout(lay.plan, poses)
    verdict = {(r.rule, r.object): r.satisfied for r in moved.rule_report()}
    assert verdict[("on_top", "lamp")] is False
    assert verdict[("on_ceiling", "light")] is False


def test_layout_json_keeps_z_and_surface(layouts):
    lay = layouts[0]
    back = fl.Layout.from_json(lay.to_json(), plan=lay.plan)
    assert back.poses["lamp"].surface == "nightstand"
    assert back.poses["painting"].surface.startswith("wall:")
    assert back.poses["light"].z == pytest.approx(lay.poses["light"].z)


def test_wall_object_wider_than_every_free_stretch_is_a_plan_error():
    plan = copy.deepcopy(PLAN)
    plan["objects"].append({"id": "banner", "category": "banner", "size": [3.5, 0.02, 1.0]})
    plan["rules"].append({"rule": "on_wall", "object": "banner"})
    with pytest.raises(PlanError) as e:
        fl.solve(plan, 0, check=False)
    msg = str(e.value)
    assert "rules[7] (on_wall)" in msg and "banner" in msg and "free stretch" in msg


def test_object_taller_than_its_band_is_a_plan_error():
    plan = copy.deepcopy(PLAN)
    plan["objects"][5]["size"] = [0.3, 0.05, 1.5]  # clock taller than the 0.9..2.1 m band
    with pytest.raises(PlanError, match=r"rules\[5\] \(on_wall_mid\)\.params.*clock"):
        check_surfaces(fl.Plan.from_dict(plan))


@pytest.mark.parametrize("low, high, h", [(0.3, 1.4, 1.1), (0.1, 1.2, 1.1), (0.3, 1.2, 0.9)])
def test_a_wall_object_as_tall_as_its_band_hangs(low, high, h):
    """A band exactly the object's height holds it (``high - low`` rounds below ``h`` for
    these: a towel radiator 1.1 m tall from 0.3 to 1.4 m went missing)."""
    plan = copy.deepcopy(PLAN)
    plan["objects"].append({"id": "radiator", "category": "radiator", "size": [0.5, 0.1, h]})
    plan["rules"].append({"rule": "on_wall", "object": "radiator",
                          "params": {"low": low, "high": high}})
    check_surfaces(fl.Plan.from_dict(plan))
    lay = fl.solve(plan, 0, check=False)
    assert lay.poses["radiator"].z == pytest.approx(low, abs=1e-9)
    assert not lay.report.missing and lay.report.rule_satisfaction == 1.0


def test_free_wall_stretches_take_out_openings():
    plan = fl.Plan.from_dict(PLAN)
    # a 1 m tall object in [0.3, 2.7] cannot pass above or below the door or the window
    assert free_wall_stretches(plan, 0, 0.3, 2.7, 1.0) == [(0.0, 0.55), (1.45, 4.0)]
    assert free_wall_stretches(plan, 2, 0.3, 2.7, 1.0) == [(0.0, 1.4), (2.6, 4.0)]
    # a 0.5 m tall one fits above the door
    assert free_wall_stretches(plan, 0, 0.3, 2.7, 0.5) == [(0.0, 4.0)]


def test_crowded_top_reports_the_missing_object_with_a_reason():
    plan = {
        "name": "crowded",
        "room": {"polygon": [[0, 0], [3, 0], [3, 3], [0, 3]]},
        "objects": [{"id": "stool", "category": "stool", "size": [0.45, 0.45, 0.5]},
                    {"id": "a", "category": "box", "size": [0.4, 0.4, 0.2]},
                    {"id": "b", "category": "box", "size": [0.4, 0.4, 0.2]}],
        "rules": [{"rule": "on_top", "object": "a", "target": "stool"},
                  {"rule": "on_top", "object": "b", "target": "stool"}],
    }
    lay = fl.solve(plan, 0, check=False)
    assert lay.report.missing
    assert all("stool" in m for m in lay.report.missing)
    placed_or_missing = set(lay.poses) | {m.split(":")[0] for m in lay.report.missing}
    assert placed_or_missing == {"stool", "a", "b"}


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**31), n=st.integers(2, 6))
def test_a_crowded_top_that_can_hold_its_objects_holds_them(seed, n):
    """n boxes of 0.1 x 0.1 m on a 0.2 x 0.4 m shelf top: up to 75 % of it covered."""
    plan = {
        "name": "shelf",
        "room": {"polygon": [[0, 0], [3, 0], [3, 3], [0, 3]]},
        "objects": [{"id": "shelf", "category": "bookshelf", "size": [0.2, 0.4, 0.7]},
                    *({"id": f"box_{k}", "category": "box", "size": [0.1, 0.1, 0.1]}
                      for k in range(n))],
        "rules": [{"rule": "at_wall", "object": "shelf"},
                  *({"rule": "on_top", "object": f"box_{k}", "target": "shelf"}
                    for k in range(n))],
    }
    lay = fl.solve(plan, seed, check=False)
    assert lay.report.missing == []
    for k in range(n):
        assert lay.poses[f"box_{k}"].surface == "shelf"
        assert _inside_top(lay, f"box_{k}", "shelf")
    assert check_layout(lay).failures == []


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**31), w=st.floats(0.1, 0.45), d=st.floats(0.1, 0.4))
def test_any_child_that_fits_lands_on_its_parent(seed, w, d):
    plan = copy.deepcopy(PLAN)
    plan["objects"][2]["size"] = [w, d, 0.3]
    plan["objects"] = [o for o in plan["objects"] if o["id"] != "book"]
    plan["rules"] = [r for r in plan["rules"] if r["object"] != "book"]
    lay = fl.solve(plan, seed, check=False)
    assert lay.poses["lamp"].surface == "nightstand"
    assert _inside_top(lay, "lamp", "nightstand")
    assert lay.poses["lamp"].z == pytest.approx(0.5)


def test_ceiling_light_centred_over_an_area():
    plan = fl.load_plan("bedroom").model_dump()
    for r in plan["rules"]:
        if r["rule"] == "on_ceiling":
            r["target"] = "sleeping"
    plan = fl.Plan.from_dict(plan)
    for seed in range(3):
        lay = fl.solve(plan, seed, check=False)
        members = [o.id for o in plan.objects if o.area == "sleeping"
                   and lay.poses[o.id].surface == "floor"]
        centre = np.mean([[lay.poses[m].x, lay.poses[m].y] for m in members], axis=0)
        light = lay.poses["ceiling_light"]
        assert light.surface == "ceiling"
        assert np.hypot(light.x - centre[0], light.y - centre[1]) <= 0.3


def test_pinned_wall_that_does_not_exist_is_a_plan_error():
    plan = copy.deepcopy(PLAN)
    plan["rules"][5]["params"] = {"wall": 7}
    with pytest.raises(PlanError, match=r"rules\[5\] \(on_wall_mid\)\.params\.wall.*walls 0\.\.3"):
        check_surfaces(fl.Plan.from_dict(plan))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(0.05, 0.6), st.floats(0.05, 0.6)), min_size=1, max_size=6),
       st.floats(0.3, 1.5), st.floats(0.3, 0.8))
def test_what_a_top_holds_by_the_row_test_lands_on_it(sizes, w, d):
    from forcelayout.surfaces.tops import holds

    if not holds(sizes, w, d):
        return
    plan = fl.Plan.from_dict({
        "name": "top", "room": {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]]},
        "objects": [{"id": "table", "category": "table", "size": [w, d, 0.7]}]
        + [{"id": f"item_{k}", "category": "box", "size": [a, b, 0.1]}
           for k, (a, b) in enumerate(sizes)],
        "rules": [{"rule": "on_top", "object": f"item_{k}", "target": "table"}
                  for k in range(len(sizes))]})
    layouts = fl.generate(plan, 1, max_attempts=3, seed=1)
    assert len(layouts) == 1, layouts.failures


@pytest.mark.parametrize("seed", range(5))
def test_a_child_at_the_wall_on_a_top_stands_at_the_wall_behind_its_parent(seed):
    """A TV on a stand against a wall, itself ``at_wall``, ends at the stand's back edge."""
    plan = fl.Plan.model_validate({
        "room": {"polygon": [[0, 0], [4.0, 0], [4.0, 3.5], [0, 3.5]],
                 "doors": [{"wall": 0, "offset": 0.6, "width": 0.8}]},
        "objects": [
            {"id": "tv_stand", "category": "tv_stand", "size": [1.6, 0.45, 0.5]},
            {"id": "tv", "category": "tv", "size": [1.2, 0.2, 0.7]},
            {"id": "vase", "category": "vase", "size": [0.15, 0.15, 0.3]},
        ],
        "rules": [
            {"rule": "at_wall", "object": "tv_stand"},
            {"rule": "on_top", "object": "tv", "target": "tv_stand"},
            {"rule": "at_wall", "object": "tv"},
            {"rule": "on_top", "object": "vase", "target": "tv_stand"},
        ],
    })
    layout = fl.solve(plan, seed)
    assert layout.poses["tv"].surface == "tv_stand"
    met = {r.label: r.satisfied for r in layout.rule_report()}
    assert met["at_wall(tv_stand)"] and met["at_wall(tv)"]


def test_a_plane_model_is_made_once_per_key_and_shared():
    """Samples that share ``models`` share a plane's force model, so their simulations of it
    batch; the model's room is the plane."""
    import numpy as np

    from forcelayout.bindings import compile_plan
    from forcelayout.surfaces.plane import plane_model, rect

    cp = compile_plan(fl.examples.load_example("bedroom"))
    models: dict = {}
    one = plane_model(models, ("wall", 1), cp, ["bed"], rect(0.0, 0.0, 4.0, 2.7), True)
    assert plane_model(models, ("wall", 1), cp, ["bed"], rect(0.0, 0.0, 4.0, 2.7), True) is one
    other = plane_model(models, ("wall", 2), cp, ["bed"], rect(0.0, 0.0, 3.0, 2.7), True,
                        sizes={"bed": (2.0, 0.5, 1.0)})
    assert other is not one and len(models) == 2
    np.testing.assert_allclose(other.room.bounds, [0.0, 0.0, 3.0, 2.7])
    np.testing.assert_allclose(other.size, [[2.0, 0.5, 1.0]])


WALL_RELATIONS = {
    "name": "bathroom",
    "room": {"polygon": [[0, 0], [3.0, 0], [3.0, 3.0], [0, 3.0]], "height": 2.5,
             "doors": [{"wall": 0, "offset": 0.6, "width": 0.8}]},
    "objects": [
        {"id": "bathtub", "category": "bathtub", "size": [1.7, 0.75, 0.55]},
        {"id": "bed", "category": "bed", "size": [0.9, 1.9, 0.5]},
        {"id": "towel_rack", "category": "towel rack", "size": [0.6, 0.12, 0.5]},
        {"id": "tv", "category": "tv", "size": [0.8, 0.06, 0.5]},
    ],
    "rules": [{"rule": "on_wall", "object": "towel_rack", "params": {"low": 0.9, "high": 1.8}},
              {"rule": "near", "object": "towel_rack", "target": "bathtub",
               "params": {"distance": 0.6}},
              {"rule": "on_wall_mid", "object": "tv"},
              {"rule": "facing", "object": "bed", "target": "tv"}],
}


def test_a_wall_object_near_a_floor_object_in_a_large_room_finds_the_wall_beside_it():
    """A towel rack within 0.1 m of a bathtub in the corner of an 8 x 6 m room: the
    wall beside the tub is a tenth of the walls, so random spots alone missed it in some
    samples; the spots drawn beside the tub find it in every one."""
    from forcelayout.surfaces import place_surfaces

    data = {**WALL_RELATIONS,
            "room": {"polygon": [[0, 0], [8.0, 0], [8.0, 6.0], [0, 6.0]], "height": 2.5,
                     "doors": [{"wall": 0, "offset": 0.6, "width": 0.8}]},
            "rules": [{"rule": "on_wall", "object": "towel_rack",
                       "params": {"low": 0.9, "high": 1.8}},
                      {"rule": "near", "object": "towel_rack", "target": "bathtub",
                       "params": {"distance": 0.1}}]}
    plan = fl.Plan.from_dict(data)
    floor = {"bathtub": fl.Pose(7.1, 5.6, np.pi), "bed": fl.Pose(1.0, 3.0, 0.0)}
    for seed in range(20):
        out = place_surfaces(plan, floor, np.random.default_rng(seed))
        lay = fl.Layout(plan, out.poses)
        assert {r.label: r.satisfied for r in lay.rule_report()}["near(towel_rack, bathtub)"]


def test_a_wall_object_goes_where_its_rules_with_floor_objects_hold():
    """A towel rack on the wall near the bathtub, a TV on the wall the bed faces: floor
    rules between a floor object and a wall object are met by where the wall object goes
    (the floor does not move for it)."""
    from forcelayout.surfaces import place_surfaces

    plan = fl.Plan.from_dict(WALL_RELATIONS)
    floor = {"bathtub": fl.Pose(2.1, 2.6, np.pi), "bed": fl.Pose(0.5, 1.8, -np.pi / 2)}
    met = []
    for seed in range(12):
        out = place_surfaces(plan, floor, np.random.default_rng(seed))
        report = {r.label: r.satisfied for r in fl.Layout(plan, out.poses).rule_report()}
        met.append([report["near(towel_rack, bathtub)"], report["facing(bed, tv)"]])
    assert np.all(met)  # 4 walls: a random wall would miss most of them


def test_a_wall_object_hangs_first_where_the_objects_facing_it_look():
    """Three seats facing one TV, none at a wall, each a little turned from the others:
    the TV's first spots are where each of them looks, so the spot that meets the most of
    their rules is found among them (a random spot on a random wall seldom is)."""
    from forcelayout.surfaces import place_surfaces

    plan = fl.Plan.from_dict({
        "name": "den", "room": {"polygon": [[0, 0], [4, 0], [4, 4.5], [0, 4.5]]},
        "objects": [{"id": f"seat_{k}", "category": "armchair", "size": [0.8, 0.8, 0.9]}
                    for k in range(3)] + [{"id": "tv", "category": "tv",
                                           "size": [1.15, 0.06, 0.7]}],
        "rules": [{"rule": "on_wall_mid", "object": "tv"},
                  *({"rule": "facing", "object": f"seat_{k}", "target": "tv",
                     "params": {"max_angle": 12}} for k in range(3))]})
    # looking at the left wall (x = 0) at y = 1.2, 1.5 and 1.7
    floor = {"seat_0": fl.Pose(1.5, 1.0, np.pi / 2 - 0.13),
             "seat_1": fl.Pose(2.0, 2.3, np.pi / 2 + 0.39),
             "seat_2": fl.Pose(3.2, 3.4, np.pi / 2 + 0.53)}
    met = 0
    for seed in range(12):
        out = place_surfaces(plan, floor, np.random.default_rng(seed))
        met += all(r.satisfied for r in fl.Layout(plan, out.poses).rule_report()
                   if r.rule == "facing")
    assert met == 12


def test_two_pendants_over_one_island_share_it_along_its_length():
    plan = fl.Plan.from_dict({
        "name": "kitchen", "room": {"polygon": [[0, 0], [5, 0], [5, 4], [0, 4]]},
        "objects": [{"id": "island", "category": "kitchen_island", "size": [1.8, 0.95, 0.92]},
                    {"id": "pendant_1", "category": "pendant_light", "size": [0.3, 0.3, 0.4]},
                    {"id": "pendant_2", "category": "pendant_light", "size": [0.3, 0.3, 0.4]}],
        "rules": [{"rule": "in_middle", "object": "island"},
                  {"rule": "on_ceiling", "object": "pendant_1", "target": "island"},
                  {"rule": "on_ceiling", "object": "pendant_2", "target": "island"}]})
    for seed in range(4):
        lay = fl.solve(plan, seed)
        assert lay.report.valid and lay.rule_satisfaction == 1.0, lay.report.failures
        isl = lay.poses["island"]
        axis = np.array([np.cos(isl.yaw), np.sin(isl.yaw)])  # the island's long (width) axis
        along = sorted(float(np.dot([lay.poses[p].x - isl.x, lay.poses[p].y - isl.y], axis))
                       for p in ("pendant_1", "pendant_2"))
        assert along[0] == pytest.approx(-0.45, abs=0.05)  # over each half of its 1.8 m
        assert along[1] == pytest.approx(0.45, abs=0.05)


def test_wall_units_over_a_row_of_counters_stay_over_their_targets():
    """A range hood over a stove between two counters, a wall cabinet over each counter
    as wide as it: settling the wall must not press the hood below its clearance or off
    the stove (the settled wall is kept only where every object keeps its band and its
    target's extent)."""
    from forcelayout.surfaces import place_surfaces

    plan = fl.Plan.from_dict({
        "name": "kitchen", "room": {"polygon": [[0, 0], [3.2, 0], [3.2, 3.0], [0, 3.0]],
                                    "height": 2.5},
        "objects": [{"id": "counter_a", "category": "counter", "size": [0.8, 0.6, 0.9]},
                    {"id": "stove", "category": "stove", "size": [0.6, 0.6, 0.9]},
                    {"id": "counter_b", "category": "counter", "size": [1.0, 0.6, 0.9]},
                    {"id": "hood", "category": "range_hood", "size": [0.6, 0.5, 0.3]},
                    {"id": "cab_a", "category": "wall_cabinet", "size": [0.8, 0.35, 0.7]},
                    {"id": "cab_b", "category": "wall_cabinet", "size": [1.0, 0.35, 0.7]}],
        "rules": [{"rule": "above", "object": "hood", "target": "stove",
                   "params": {"clearance": 0.65}},
                  {"rule": "above", "object": "cab_a", "target": "counter_a",
                   "params": {"clearance": 0.5}},
                  {"rule": "above", "object": "cab_b", "target": "counter_b",
                   "params": {"clearance": 0.5}}]})
    y = 3.0 - 0.3  # backs to the top wall, facing into the room
    floor = {"counter_a": fl.Pose(0.45, y, np.pi), "stove": fl.Pose(1.2, y, np.pi),
             "counter_b": fl.Pose(2.0, y, np.pi)}
    for seed in range(8):
        out = place_surfaces(plan, floor, np.random.default_rng(seed))
        assert not out.missing
        report = fl.Layout(plan, out.poses).rule_report()
        assert all(r.satisfied for r in report), [r.label for r in report if not r.satisfied]


def test_a_floor_leaving_a_wall_object_nowhere_to_hang_fails_its_verdict():
    """A painting above a sofa: with the sofa under a window (its band above the sofa is
    all window) the floor's verdict fails on the walls, the sofa at fault, before the
    sample would fail with the painting missing; at the wall without a window it passes.
    A mirror with no target needs a free stretch of some wall: with every wall lined
    with tall cabinets it has none, and the cabinets are at fault."""
    from forcelayout.forces import ForceModel
    from forcelayout.verdict import FloorVerdict, judge_floor

    plan = fl.Plan.from_dict({
        "name": "sofa under a window",
        "room": {"polygon": [[0, 0], [4, 0], [4, 4], [0, 4]], "height": 2.5,
                 "doors": [{"wall": 0, "offset": 3.4, "width": 0.8}],
                 "windows": [{"wall": 2, "offset": 2.0, "width": 2.4, "sill": 0.9,
                              "height": 1.5}]},
        "objects": [{"id": "sofa", "category": "sofa", "size": [2.0, 0.9, 0.85]},
                    {"id": "painting", "category": "painting", "size": [0.9, 0.04, 0.6]}],
        "rules": [{"rule": "at_wall", "object": "sofa"},
                  {"rule": "above", "object": "painting", "target": "sofa"}]})
    model = ForceModel(plan)
    under = judge_floor(model, np.array([[2.0, 3.54]]), np.array([np.pi]))
    assert any(f.startswith("walls:") and "'painting'" in f for f in under.failures)
    assert model.ids.index("sofa") in under.at_fault
    apart = judge_floor(model, np.array([[0.46, 2.0]]), np.array([-np.pi / 2]))
    assert not any(f.startswith("walls:") for f in apart.failures)

    def lined(walls: int) -> FloorVerdict:
        cabinets = [{"id": f"cabinet_{k}", "category": "cabinet", "size": [3.9, 0.4, 2.2]}
                    for k in range(walls)]
        plan = fl.Plan.from_dict({
            "name": "lined room",
            "room": {"polygon": [[0, 0], [5, 0], [5, 5], [0, 5]], "height": 2.5},
            "objects": [*cabinets,
                        {"id": "mirror", "category": "mirror", "size": [0.9, 0.03, 1.0]}],
            "rules": [{"rule": "on_wall_mid", "object": "mirror"}]})
        # each cabinet against a wall, along it
        pos = np.array([[2.5, 0.2], [4.8, 2.5], [2.5, 4.8], [0.2, 2.5]])[:walls]
        yaw = np.array([0.0, np.pi / 2, np.pi, -np.pi / 2])[:walls]
        return judge_floor(ForceModel(plan), pos, yaw)

    every = lined(4)
    assert any(f.startswith("walls:") and "'mirror'" in f for f in every.failures)
    assert every.at_fault == {0, 1, 2, 3}
    assert not any(f.startswith("walls:") for f in lined(3).failures)


def _tv_room(objects: list[dict], rules: list[dict]) -> fl.Plan:
    """A 3.2 x 3.4 m bedroom with a TV on the wall and the given floor objects."""
    return fl.Plan.from_dict({
        "name": "tv room",
        "room": {"polygon": [[0, 0], [3.2, 0], [3.2, 3.4], [0, 3.4]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 0.5, "width": 0.8}]},
        "objects": [*objects, {"id": "tv", "category": "tv", "size": [1.0, 0.06, 0.6]}],
        "rules": [{"rule": "on_wall_mid", "object": "tv"}, *rules]})


def test_unseen_names_a_view_whose_wall_is_taken_where_the_object_looks():
    """A bed against the top wall faces the bottom wall, where its TV is to hang: a
    dresser there leaves the TV room beside it within the bed's angle, the dresser with a
    mirror above it (hiding the wall to about 1.8 m) none, and the dresser is named."""
    from forcelayout.bindings import compile_plan
    from forcelayout.surfaces.walls import unseen

    bed = {"id": "bed", "category": "bed", "size": [1.6, 2.0, 0.5]}
    dresser = {"id": "dresser", "category": "dresser", "size": [1.4, 0.45, 0.8]}
    mirror = {"id": "mirror", "category": "mirror", "size": [0.7, 0.03, 0.9]}
    facing = {"rule": "facing", "object": "bed", "target": "tv"}
    pos = np.array([[[1.6, 2.4], [1.9, 0.25]]])  # the bed's foot looks at the dresser
    yaw = np.array([[np.pi, 0.0]])
    ids = ["bed", "dresser"]
    plain = compile_plan(_tv_room([bed, dresser], [facing]))
    assert unseen(plain, ids, pos, yaw) == [[]]
    hung = compile_plan(_tv_room([bed, dresser, mirror], [
        facing, {"rule": "above", "object": "mirror", "target": "dresser"}]))
    [[(binding, near)]] = unseen(hung, ids, pos, yaw)
    assert (binding.object, binding.target, near) == ("bed", "tv", ["dresser"])
    # turned to the side wall, the bed looks at a free wall
    assert unseen(hung, ids, pos, np.array([[np.pi / 2, 0.0]])) == [[]]


def test_unseen_names_the_second_of_two_objects_facing_one_wall_object_from_apart():
    """Two beds facing one TV: its one spot meets both where they look at one stretch of
    wall, the first bed's alone where they look at different walls."""
    from forcelayout.bindings import compile_plan
    from forcelayout.surfaces.walls import unseen

    beds = [{"id": f"bed_{k}", "category": "bed", "size": [0.9, 1.9, 0.45]} for k in (1, 2)]
    cp = compile_plan(_tv_room(beds, [{"rule": "facing", "object": f"bed_{k}", "target": "tv"}
                                      for k in (1, 2)]))
    ids = ["bed_1", "bed_2"]
    side_by_side = np.array([[[1.0, 2.4], [2.2, 2.4]]])
    assert unseen(cp, ids, side_by_side, np.array([[np.pi, np.pi]])) == [[]]
    apart = np.array([[[1.0, 2.4], [2.4, 0.9]]])  # the second looks at the right wall
    [[(binding, near)]] = unseen(cp, ids, apart, np.array([[np.pi, -np.pi / 2]]))
    assert (binding.object, near) == ("bed_2", [])


def test_hidden_heights_count_what_hangs_above_a_floor_object():
    """A dresser 0.8 m tall hides its wall to 0.8 m; with a 0.9 m mirror ``above`` it
    (0.1 m clearance by default) to 1.8 m. The bed facing the TV is the plan's one wall
    view; the mirror, hung above the dresser, is no view."""
    from forcelayout.bindings import compile_plan
    from forcelayout.surfaces.walls import hidden_heights

    bed = {"id": "bed", "category": "bed", "size": [1.6, 2.0, 0.5]}
    dresser = {"id": "dresser", "category": "dresser", "size": [1.4, 0.45, 0.8]}
    mirror = {"id": "mirror", "category": "mirror", "size": [0.7, 0.03, 0.9]}
    facing = {"rule": "facing", "object": "bed", "target": "tv"}
    plain = compile_plan(_tv_room([bed, dresser], [facing]))
    assert hidden_heights(plain, ["bed", "dresser"]).tolist() == pytest.approx([0.5, 0.8])
    hung = compile_plan(_tv_room([bed, dresser, mirror], [
        facing, {"rule": "above", "object": "mirror", "target": "dresser"}]))
    assert hidden_heights(hung, ["bed", "dresser"]).tolist() == pytest.approx([0.5, 1.8])
    assert [(b.object, b.target) for b in hung.wall_views(["bed", "dresser"])] == [
        ("bed", "tv")]
    assert hung.wall_views(["dresser"]) == ()
