"""Start poses: parents anywhere, children beside their parents, wall objects at walls."""

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import forcelayout as fl
from forcelayout import rules
from forcelayout.forces import ForceModel, RuleTerm
from forcelayout.initial import (
    RelocateRequest,
    Starts,
    initial_poses,
    parents,
    propose_poses,
    relocate,
    start_poses,
)
from forcelayout.testing import plans
from sample_plans import BED_AND_NIGHTSTAND, RECEPTION, TABLE_FOR_FOUR, backs_offset


@pytest.fixture(scope="module")
def bedroom():
    return ForceModel(fl.load_plan("bedroom"))


def test_children_have_their_targets_as_parents(bedroom):
    par = parents(bedroom)
    row = {oid: k for k, oid in enumerate(bedroom.ids)}
    assert par[row["nightstand_1"]] == row["bed"]
    assert par[row["nightstand_2"]] == row["bed"]
    assert par[row["desk_chair"]] == row["desk"]
    assert par[row["bed"]] == -1


def test_same_generator_state_same_start(bedroom):
    a = initial_poses(bedroom, np.random.default_rng(5))
    b = initial_poses(bedroom, np.random.default_rng(5))
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


def test_starts_lean_towards_the_rules(bedroom):
    """Most starts already meet most rules: children beside parents, backs to walls."""
    met = []
    for seed in range(12):
        pos, yaw = initial_poses(bedroom, np.random.default_rng(seed))
        st = bedroom.state(pos, yaw)
        assert bedroom.room.contains(st.corners.reshape(-1, 2)).mean() > 0.95
        met.append(np.mean(list(bedroom.satisfied(st).values())))
    assert np.mean(met) > 0.8


def test_starts_differ_between_seeds(bedroom):
    a, _ = propose_poses(bedroom, np.random.default_rng(1))
    b, _ = propose_poses(bedroom, np.random.default_rng(2))
    assert np.abs(a - b).max() > 0.3


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(plan=plans(max_objects=8))
def test_random_plans_get_finite_starts_inside_the_bounds(plan):
    model = ForceModel(plan)
    pos, yaw = initial_poses(model, np.random.default_rng(0))
    assert pos.shape == (model.n, 2) and np.isfinite(pos).all() and np.isfinite(yaw).all()
    lo, hi = model.room.bounds[:2], model.room.bounds[2:]
    assert ((pos >= lo - 1e-9) & (pos <= hi + 1e-9)).all()


def test_start_poses_yields_each_start_with_its_verdict():
    from forcelayout.initial import start_poses
    from forcelayout.verdict import judge_floor

    model = ForceModel(fl.load_plan("bedroom"))
    starts = list(start_poses(model, np.random.default_rng(0), restarts=3))
    assert len(starts) == 3
    for pos, yaw, verdict in starts:
        assert pos.shape == (model.n, 2) and yaw.shape == (model.n,)
        assert judge_floor(model, pos, yaw).failures == verdict.failures
    with model.without(RuleTerm):  # a with block leaves those terms out, then restores them
        assert not any(isinstance(t, RuleTerm) for t in model.terms)
    assert any(isinstance(t, RuleTerm) for t in model.terms)


def _one_nightstand(width: float = 4.0) -> fl.Plan:
    return fl.Plan.model_validate({
        "room": {"polygon": [[0, 0], [width, 0], [width, 3.0], [0, 3.0]],
                 "doors": [{"wall": 0, "offset": 0.5, "width": 0.8}]},
        "objects": [
            {"id": "bed", "category": "bed", "size": [1.6, 2.0, 0.5]},
            {"id": "nightstand", "category": "nightstand", "size": [0.45, 0.4, 0.55]},
        ],
        "rules": [
            {"rule": "at_wall", "object": "bed"},
            {"rule": "next_to", "object": "nightstand", "target": "bed"},
            {"rule": "at_wall", "object": "nightstand"},
        ],
    })


def test_one_side_child_needs_room_on_one_side_only():
    """A bed with one nightstand may start close to a corner, the nightstand on its open side
    (no room is kept on the side nobody needs)."""
    model = ForceModel(_one_nightstand())
    bed = model.ids.index("bed")
    lo, hi = model.room.bounds[:2], model.room.bounds[2:]
    beside = next(k for k, b in enumerate(model.bindings) if b.rule.name == "next_to")
    in_corner = 0
    for seed in range(40):
        pos, yaw = propose_poses(model, np.random.default_rng(seed))
        st = model.state(pos, yaw)
        c = st.corners[bed].reshape(-1, 2)
        touched = (np.abs(c.min(0) - lo) < 0.3).sum() + (np.abs(c.max(0) - hi) < 0.3).sum()
        in_corner += bool(touched >= 2 and model.satisfied(st)[beside])
    assert in_corner >= 5


def test_a_start_within_the_rule_share_is_not_searched_further():
    """A start whose only failures are unmet bindings within ``misses`` is not drawn again:
    kept as drawn, or with the objects of its unmet bindings drawn once more where that
    meets more of them and still passes."""
    from forcelayout.verdict import FloorVerdict, allowed_misses, judge_floor

    assert allowed_misses(20, 0.95) == 1 and allowed_misses(19, 0.95) == 0
    assert allowed_misses(0, 0.5) == 0 and allowed_misses(10, 1.0) == 0
    v = FloorVerdict(["next_to(a, b)"], {0}, missed={3})
    assert v.passes(1) and not v.passes(0) and not v.ok
    assert not FloorVerdict(["collision: 'a' overlaps 'b'"], {0, 1}).passes(5)
    model = ForceModel(fl.load_plan("living_room"))
    kept = mended = 0
    for seed in range(24):
        fresh = propose_poses(model, np.random.default_rng(seed))
        first = judge_floor(model, *fresh)
        met = model.satisfied(model.state(*fresh))  # the unmet bindings, named by position
        assert first.missed == {k for k, ok in met.items() if not ok}
        assert first.unmet == len(first.missed)
        drawn = next(start_poses(model, np.random.default_rng(seed), misses=first.unmet,
                                 fixes=0))
        loose = next(start_poses(model, np.random.default_rng(seed), misses=first.unmet))
        strict = next(start_poses(model, np.random.default_rng(seed), misses=0))
        if first.passes(first.unmet):  # accepted as drawn, unmet bindings and all
            np.testing.assert_array_equal(drawn[0], fresh[0])
            kept += first.unmet > 0
            if not np.array_equal(loose[0], fresh[0]):  # or drawn again: meets more
                assert loose[2].passes(first.unmet) and loose[2].unmet < first.unmet
                mended += 1
        assert len(strict[2].failures) <= len(first.failures)
    assert kept >= 1 and mended >= 1


def _desk_by_a_low_window(width: float, distance: float) -> fl.Plan:
    """A 4 x 4 m room, a window ``width`` wide with a 0.5 m sill, a desk at a wall within
    ``distance`` of it."""
    return fl.Plan.model_validate({
        "room": {"polygon": [[0, 0], [4.0, 0], [4.0, 4.0], [0, 4.0]],
                 "doors": [{"wall": 0, "offset": 0.6, "width": 0.8}],
                 "windows": [{"wall": 2, "offset": 2.0, "width": width, "sill": 0.5}]},
        "objects": [{"id": "desk", "category": "desk", "size": [1.1, 0.55, 0.75]}],
        "rules": [{"rule": "at_wall", "object": "desk"},
                  {"rule": "near_window", "object": "desk",
                   "params": {"distance": distance}}],
    })


def test_a_start_misses_a_rule_rather_than_block_a_window():
    """Where a desk can be near the window only in front of it (a low sill), it starts
    clear of the window zone (a failed check rejects a sample; a missed rule may not)."""
    model = ForceModel(_desk_by_a_low_window(3.2, 1.0))
    blocked = 0
    for seed in range(12):
        pos, yaw, verdict = next(start_poses(model, np.random.default_rng(seed), misses=1))
        blocked += any(f.startswith("window") for f in verdict.failures)
    assert blocked <= 1


def test_a_start_too_tall_for_a_window_sill_draws_more_spots_near_it():
    """A desk above a low sill, near a wide window: most spots near it are in front of it,
    so the draw keeps the ones clear of its zone first, from twice as many (a few
    candidates find a spot that meets the rule and blocks nothing 80 times in 100, where
    57 did from as many draws)."""
    from forcelayout.verdict import judge_floor

    model = ForceModel(_desk_by_a_low_window(2.4, 2.0))
    ok = [judge_floor(model, *propose_poses(model, np.random.default_rng(s), tries=4)).ok
          for s in range(100)]
    assert sum(ok) >= 70


def test_a_start_near_a_door_spreads_over_the_distance_the_rule_allows():
    """A long counter within 2.5 m of a door in the corner: the swing square takes the wall
    right beside the door, so only starts spread over the rule's distance meet it."""
    plan = fl.Plan.from_dict({
        "name": "door corner",
        "room": {"polygon": [[0, 0], [6.2, 0], [6.2, 4.4], [0, 4.4]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 5.6, "width": 0.9}]},
        "objects": [{"id": "counter", "category": "counter", "size": [1.8, 0.6, 0.9]}],
        "rules": [{"rule": "at_wall", "object": "counter"},
                  {"rule": "near_door", "object": "counter", "params": {"distance": 2.5}}]})
    model = ForceModel(plan)
    met = [all(model.satisfied(model.state(*propose_poses(model, np.random.default_rng(s),
                                                          tries=8))).values())
           for s in range(40)]
    assert np.mean(met) >= 0.9


def test_a_start_may_stand_right_beside_a_door_swing():
    """A 2 m bed along a 3 m room's side wall: towards the door its foot comes within 4 cm
    of the swing square. Clear of the square is what the door check asks, so starts use
    that end of the wall too, and none fails the check."""
    plan = fl.Plan.from_dict({
        "name": "bed by the door",
        "room": {"polygon": [[0, 0], [3.0, 0], [3.0, 3.2], [0, 3.2]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 0.55, "width": 0.8}]},
        "objects": [{"id": "bed", "category": "bed", "size": [1.4, 2.0, 0.5]}],
        "rules": [{"rule": "at_wall", "object": "bed"}]})
    model = ForceModel(plan)
    starts = [propose_poses(model, np.random.default_rng(s)) for s in range(80)]
    pos = np.array([p[0] for p, _ in starts])
    along_side = np.array([abs(np.cos(y[0])) < 0.1 for _, y in starts])
    assert (along_side & (pos[:, 1] < 1.5)).sum() >= 5
    for p, y in starts:
        lay = fl.Layout(plan, {"bed": fl.Pose(float(p[0, 0]), float(p[0, 1]), float(y[0]))})
        assert not [f for f in lay.report.failures if f.startswith("door")]


def test_a_start_reach_must_name_a_parameter_near_an_opening():
    with pytest.raises(ValueError, match="reach"):  # only near an opening or the middle
        rules.StartHint(place="wall", reach="distance")
    with pytest.raises(TypeError, match="radius"):
        class Near(rules.Rule):
            name = "near_door_test_reach"
            start = rules.StartHint(place="door", reach="radius")



def test_a_start_which_must_name_a_parameter_picking_a_window_or_door():
    with pytest.raises(ValueError, match="which"):  # only with place window or door
        rules.StartHint(place="wall", which="door")
    with pytest.raises(TypeError, match="which names 'entrance'"):
        class ByDoor(rules.Rule):
            name = "near_door_test_which"
            start = rules.StartHint(place="door", which="entrance")


def test_a_start_cone_must_name_a_parameter_of_a_rule_turning_to_its_target():
    with pytest.raises(ValueError, match="cone"):  # only with turn face_target
        rules.StartHint(place="wall", cone="max_angle")
    with pytest.raises(TypeError, match="cone names 'angle'"):
        class Faces(rules.Rule):
            name = "facing_test_cone"
            target = "required"
            start = rules.StartHint(turn="face_target", cone="angle")


def test_a_start_across_the_room_spreads_over_the_cone_its_rule_allows():
    """A stove facing the sink from the other long wall of a galley within 45 degrees:
    starts take that wall anywhere the cone reaches, not only straight across, and every
    one of them meets the rule."""
    plan = fl.Plan.from_dict({
        "name": "galley",
        "room": {"polygon": [[0, 0], [2.4, 0], [2.4, 4.2], [0, 4.2]], "height": 2.6},
        "objects": [{"id": "sink", "category": "sink", "size": [0.8, 0.6, 0.9]},
                    {"id": "stove", "category": "stove", "size": [0.6, 0.6, 0.9]}],
        "rules": [{"rule": "at_wall", "object": "sink"},
                  {"rule": "at_wall", "object": "stove"},
                  {"rule": "facing", "object": "stove", "target": "sink",
                   "params": {"max_angle": 45}}]})
    model = ForceModel(plan)
    row = {oid: k for k, oid in enumerate(model.ids)}
    off, met = [], []
    for s in range(120):
        pos, yaw = propose_poses(model, np.random.default_rng(s))
        sink, stove = pos[row["sink"]], pos[row["stove"]]
        if abs(np.cos(yaw[row["sink"]])) < 0.1 and abs(sink[0] - stove[0]) > 1.5:
            off.append(abs(sink[1] - stove[1]))  # across the galley: the sideways offset
            met.append(model.satisfied(model.state(pos, yaw))[2])  # the facing rule
    assert len(off) >= 40 and all(met)
    # straight across (as before the cone was drawn from): 4 % past 0.6 m, none past 0.8 m
    assert np.mean(np.array(off) > 0.6) >= 0.15 and max(off) > 1.0


def test_a_child_in_front_of_its_parent_starts_beyond_its_own_zone_towards_it():
    """An island kept in front of a counter, facing the same way, with 0.9 m of free floor
    declared behind it: it starts with that much floor between the two (it had started
    0.1 to 0.4 m off the counter, its zone holding the counter, and stayed there)."""
    plan = fl.Plan.from_dict({
        "name": "kitchen", "room": {"polygon": [[0, 0], [6, 0], [6, 4.5], [0, 4.5]],
                                    "height": 2.6},
        "objects": [{"id": "counter", "category": "counter", "size": [1.8, 0.62, 0.9]},
                    {"id": "island", "category": "kitchen_island", "size": [1.8, 0.9, 0.92],
                     "access": {"sides": ["back"], "depth": 0.9}}],
        "rules": [{"rule": "at_wall", "object": "counter"},
                  {"rule": "in_front_of", "object": "island", "target": "counter",
                   "params": {"distance": 1.3}},
                  {"rule": "face_same_as", "object": "island", "target": "counter"}]})
    model = ForceModel(plan)
    for s in range(20):
        pos, yaw = propose_poses(model, np.random.default_rng(s))
        lay = fl.Layout(plan, {oid: fl.Pose(float(p[0]), float(p[1]), float(y))
                               for oid, p, y in zip(model.ids, pos, yaw, strict=True)})
        assert 0.9 <= lay.gap("island", "counter") <= 1.3


def _rows_of_seats(extra: list[dict]) -> fl.Plan:
    """A screen on a console at a wall, a seat in front of it and a seat 0.6 m behind that
    one (seats keep 0.5 m of leg room in front), and ``extra`` rules."""
    return fl.Plan.from_dict({
        "name": "cinema", "room": {"polygon": [[0, 0], [5, 0], [5, 6], [0, 6]], "height": 2.6},
        "objects": [{"id": "console", "category": "tv_stand", "size": [1.8, 0.45, 0.5]},
                    {"id": "seat_1", "category": "armchair", "size": [0.8, 0.85, 0.9]},
                    {"id": "seat_2", "category": "armchair", "size": [0.8, 0.85, 0.9]}],
        "rules": [{"rule": "at_wall", "object": "console"},
                  {"rule": "in_front_of", "object": "seat_1", "target": "console",
                   "params": {"distance": 3.0}},
                  {"rule": "facing", "object": "seat_1", "target": "console"},
                  {"rule": "behind", "object": "seat_2", "target": "seat_1",
                   "params": {"distance": 0.6}},
                  {"rule": "face_same_as", "object": "seat_2", "target": "seat_1"},
                  *extra]})


def _start_layouts(plan: fl.Plan, n: int) -> list[fl.Layout]:
    model = ForceModel(plan)
    out = []
    for s in range(n):
        pos, yaw = propose_poses(model, np.random.default_rng(s))
        out.append(fl.Layout(plan, {oid: fl.Pose(float(p[0]), float(p[1]), float(y))
                                    for oid, p, y in zip(model.ids, pos, yaw, strict=True)}))
    return out


def test_a_child_behind_its_parent_starts_within_the_gap_its_rule_allows():
    """A second row of seats 0.6 m behind the first starts 0.5 m behind it, beyond its own
    leg room and within the rule's distance (it had started 0.6 to 0.9 m behind, and the
    start kept ``behind`` as the one rule it may leave unmet in 19 of 20 layouts)."""
    for lay in _start_layouts(_rows_of_seats([]), 20):
        assert 0.45 <= lay.gap("seat_2", "seat_1") <= 0.6


def test_a_child_in_front_of_its_parent_starts_as_far_as_a_rule_keeps_it():
    """``far_from`` the screen by 2 m: the front row starts 2 m or more from the console,
    within its ``in_front_of`` distance (it had started 0.6 to 0.9 m off it)."""
    plan = _rows_of_seats([{"rule": "far_from", "object": "seat_1", "target": "console",
                            "params": {"distance": 2.0}}])
    for lay in _start_layouts(plan, 20):
        assert 2.0 <= lay.gap("seat_1", "console") <= 3.0
    for lay in _start_layouts(_rows_of_seats([]), 20):  # without it, close in front
        assert lay.gap("seat_1", "console") <= 1.0


def test_a_child_near_its_parent_starts_anywhere_within_the_gap_its_rule_allows():
    """``near`` within 1.5 m: a beanbag starts all round the TV stand up to about 1.5 m off
    it, not only the few centimetres beyond touching where a rule allowing 0.3 m starts it
    (it had started within 0.4 m whatever the distance, so the layouts a plan yields kept
    what the rule lets apart closer together than the rule asks)."""
    def plan(distance):
        return fl.Plan.from_dict({
            "name": "near",
            "room": {"polygon": [[0, 0], [6, 0], [6, 5], [0, 5]], "height": 2.6},
            "objects": [
                {"id": "stand", "category": "tv_stand", "size": [1.2, 0.4, 0.5]},
                {"id": "beanbag", "category": "beanbag", "size": [0.7, 0.7, 0.5]}],
            "rules": [{"rule": "in_middle", "object": "stand"},
                      {"rule": "near", "object": "beanbag", "target": "stand",
                       "params": {"distance": distance}}]})
    far = [lay.gap("beanbag", "stand") for lay in _start_layouts(plan(1.5), 40)]
    close = [lay.gap("beanbag", "stand") for lay in _start_layouts(plan(0.3), 40)]
    assert max(far) <= 1.6 and max(close) <= 0.45
    assert np.percentile(far, 75) > 0.7  # spread over the distance, not bunched at contact
    assert min(far) < 0.3


def test_a_start_in_the_middle_spreads_over_the_share_the_rule_allows():
    plan = fl.Plan.from_dict({
        "name": "middle",
        "room": {"polygon": [[0, 0], [6, 0], [6, 5], [0, 5]], "height": 2.6},
        "objects": [{"id": "table", "category": "table", "size": [0.6, 0.6, 0.7]}],
        "rules": [{"rule": "in_middle", "object": "table", "params": {"fraction": 0.3}}]})
    model = ForceModel(plan)
    pos = np.array([propose_poses(model, np.random.default_rng(s))[0][0] for s in range(60)])
    off = np.abs(pos - [3.0, 2.5]) / [6.0, 5.0]
    assert (off <= 0.3 + 1e-9).all()
    assert off.max(axis=0).min() > 0.2  # not bunched around the centroid


def test_a_child_stands_round_the_corner_from_a_parent_that_fills_its_corner():
    """A counter flush in a corner with a wardrobe on its other side: its fridge can only
    stand against the side wall, past the counter's front edge."""
    from forcelayout.initial import relocate

    plan = fl.Plan.model_validate({
        "room": {"polygon": [[0, 0], [4.0, 0], [4.0, 3.5], [0, 3.5]],
                 "doors": [{"wall": 2, "offset": 3.0, "width": 0.8}]},
        "objects": [
            {"id": "counter", "category": "counter", "size": [1.8, 0.6, 0.9]},
            {"id": "wardrobe", "category": "wardrobe", "size": [1.2, 0.6, 2.0]},
            {"id": "fridge", "category": "fridge", "size": [0.6, 0.65, 1.8]},
        ],
        "rules": [
            {"rule": "at_wall", "object": "counter"},
            {"rule": "at_wall", "object": "wardrobe"},
            {"rule": "at_wall", "object": "fridge"},
            {"rule": "next_to", "object": "fridge", "target": "counter"},
        ],
    })
    model = ForceModel(plan)
    row = {oid: k for k, oid in enumerate(model.ids)}
    pos, yaw = np.zeros((3, 2)), np.zeros(3)
    pos[row["counter"]] = [4.0 - 0.9 - 0.01, 0.31]  # back to the bottom wall, in the corner
    pos[row["wardrobe"]] = [4.0 - 1.8 - 0.6 - 0.02, 0.31]  # right beside it
    met = 0
    for seed in range(20):
        p, y = relocate(model, [row["fridge"]], pos, yaw, np.random.default_rng(seed))
        st = model.state(p, y)
        met += all(model.satisfied(st).values()) and p[row["fridge"], 0] > 3.5
    assert met >= 16


def test_a_parent_keeps_room_for_each_child_beside_it():
    """A counter near a door with a stove and a fridge beside it: the spot by the door
    with room for one child ranks below one a little further off with room for both."""
    plan = fl.Plan.from_dict({
        "name": "kitchen wall",
        "room": {"polygon": [[0, 0], [3.2, 0], [3.2, 4.0], [0, 4.0]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 2.6, "width": 0.9}]},
        "objects": [{"id": "counter", "category": "counter", "size": [1.8, 0.6, 0.9]},
                    {"id": "stove", "category": "stove", "size": [0.6, 0.6, 0.9]},
                    {"id": "fridge", "category": "fridge", "size": [0.6, 0.65, 1.8]}],
        "rules": [{"rule": "at_wall", "object": "counter"},
                  {"rule": "near_door", "object": "counter", "params": {"distance": 1.8}},
                  {"rule": "at_wall", "object": "stove"},
                  {"rule": "next_to", "object": "stove", "target": "counter"},
                  {"rule": "at_wall", "object": "fridge"},
                  {"rule": "next_to", "object": "fridge", "target": "counter"}]})
    model = ForceModel(plan)
    children = [k for k, b in enumerate(model.bindings) if b.rule.name == "next_to"]
    both = 0
    for seed in range(30):
        met = model.satisfied(model.state(*propose_poses(model, np.random.default_rng(seed))))
        both += all(met[k] for k in children)
    assert both >= 18


def test_a_small_object_goes_when_the_largest_object_it_leads_would():
    """A sofa facing a small TV stand is placed (with the stand) before the cabinets that
    are smaller than the sofa, so the walls opposite the stand are still free for it."""
    from forcelayout.initial import _Placer

    plan = fl.Plan.from_dict({
        "name": "order",
        "room": {"polygon": [[0, 0], [4.0, 0], [4.0, 4.0], [0, 4.0]], "height": 2.6},
        "objects": [{"id": "tv_stand", "category": "tv_stand", "size": [1.0, 0.4, 0.5]},
                    {"id": "sofa", "category": "sofa", "size": [2.0, 0.9, 0.85]},
                    {"id": "cabinet", "category": "cabinet", "size": [1.2, 0.5, 1.0]},
                    {"id": "shelf", "category": "bookshelf", "size": [0.9, 0.35, 1.8]}],
        "rules": [{"rule": "at_wall", "object": "tv_stand"},
                  {"rule": "at_wall", "object": "sofa"},
                  {"rule": "facing", "object": "sofa", "target": "tv_stand"},
                  {"rule": "at_wall", "object": "cabinet"},
                  {"rule": "at_wall", "object": "shelf"}]})
    model = ForceModel(plan)
    order = [model.ids[r] for r in _Placer(model).order]
    assert order == ["tv_stand", "sofa", "cabinet", "shelf"]


def test_a_start_keeps_room_above_an_object_for_what_hangs_there():
    """A sideboard near a wide window with a painting above it: where it meets its rule only
    under the window, it starts elsewhere (the painting would find no wall and go missing,
    which fails the sample; a missed rule may not)."""
    plan = fl.Plan.from_dict({
        "name": "painting above",
        "room": {"polygon": [[0, 0], [4.0, 0], [4.0, 4.0], [0, 4.0]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 0.6, "width": 0.8}],
                 "windows": [{"wall": 2, "offset": 2.0, "width": 3.2, "sill": 1.0}]},
        "objects": [{"id": "sideboard", "category": "sideboard", "size": [1.4, 0.45, 0.8]},
                    {"id": "painting", "category": "painting", "size": [1.0, 0.04, 0.7]}],
        "rules": [{"rule": "at_wall", "object": "sideboard"},
                  {"rule": "near_window", "object": "sideboard", "params": {"distance": 1.0}},
                  {"rule": "above", "object": "painting", "target": "sideboard"}]})
    missing = [bool(fl.solve(plan, seed).report.missing) for seed in range(12)]
    assert sum(missing) <= 1


def test_objects_facing_one_wall_object_start_turned_to_the_same_wall():
    """A bed and a beanbag both facing the TV on the wall: the TV is hung after the floor
    settles, where it meets the most of their rules, so the beanbag starts turned to where
    the bed looks (in a new user's teen bedroom, 17 of 60 samples then missed the beanbag's
    rule, 33 before)."""
    plan = fl.Plan.from_dict({
        "name": "tv wall",
        "room": {"polygon": [[0, 0], [3.2, 0], [3.2, 3.8], [0, 3.8]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 0.6, "width": 0.85}]},
        "objects": [{"id": "bed", "category": "bed", "size": [1.2, 2.0, 0.5]},
                    {"id": "beanbag", "category": "beanbag", "size": [0.8, 0.8, 0.6]},
                    {"id": "tv", "category": "tv", "size": [1.0, 0.08, 0.6]}],
        "rules": [{"rule": "at_wall", "object": "bed"},
                  {"rule": "on_wall_mid", "object": "tv"},
                  {"rule": "facing", "object": "bed", "target": "tv"},
                  {"rule": "facing", "object": "beanbag", "target": "tv"}]})
    model = ForceModel(plan)
    bed, bag = model.ids.index("bed"), model.ids.index("beanbag")
    room = model.room
    turned = 0
    for seed in range(20):
        pos, yaw = propose_poses(model, np.random.default_rng(seed))
        front = np.array([-np.sin(yaw[bed]), np.cos(yaw[bed])])
        # where the bed looks: the first wall its front meets
        s = [(((room.a[k] - pos[bed]) @ [-room.tangent[k, 1], room.tangent[k, 0]])
              / (front @ [-room.tangent[k, 1], room.tangent[k, 0]]))
             for k in range(room.n_walls)
             if abs(front @ [-room.tangent[k, 1], room.tangent[k, 0]]) > 1e-9]
        seen = pos[bed] + min(v for v in s if v > 1e-9) * front
        aim = seen - pos[bag]
        look = np.array([-np.sin(yaw[bag]), np.cos(yaw[bag])])
        turned += aim @ look >= np.cos(np.radians(1.0)) * np.linalg.norm(aim)
    assert turned >= 18


def test_an_object_facing_a_wall_object_starts_looking_at_a_wall_it_can_hang_on():
    """A bed facing the TV on the wall, in a room whose one short wall is mostly window:
    a start whose foot faces that wall leaves the TV nowhere within the rule's cone (6 of
    these 40 starts did so before the start looked)."""
    plan = fl.Plan.from_dict({
        "name": "tv wall",
        "room": {"polygon": [[0, 0], [3.2, 0], [3.2, 3.8], [0, 3.8]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 0.6, "width": 0.85}],
                 "windows": [{"wall": 2, "offset": 1.6, "width": 2.4, "sill": 0.9,
                              "height": 1.3}]},
        "objects": [{"id": "bed", "category": "bed", "size": [1.2, 2.0, 0.5]},
                    {"id": "tv", "category": "tv", "size": [1.0, 0.08, 0.6]}],
        "rules": [{"rule": "at_wall", "object": "bed"},
                  {"rule": "on_wall_mid", "object": "tv"},
                  {"rule": "facing", "object": "bed", "target": "tv"}]})
    model = ForceModel(plan)
    bed = model.ids.index("bed")
    at_window = 0
    for seed in range(40):
        pos, yaw = propose_poses(model, np.random.default_rng(seed))
        front = np.array([-np.sin(yaw[bed]), np.cos(yaw[bed])])
        at_window += front[1] > 0.9  # its foot towards wall 2 (y = 3.8)
    assert at_window <= 1


def _bed_and_tv(extra: dict, rules: list[dict]) -> fl.Plan:
    """A bed at a wall facing a TV on the wall, an ``extra`` object with its ``rules``."""
    return fl.Plan.from_dict({
        "name": "tv wall",
        "room": {"polygon": [[0, 0], [3.2, 0], [3.2, 3.8], [0, 3.8]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 0.6, "width": 0.85}]},
        "objects": [{"id": "bed", "category": "bed", "size": [1.2, 2.0, 0.5]}, extra,
                    {"id": "tv", "category": "tv", "size": [1.0, 0.08, 0.6]}],
        "rules": [{"rule": "at_wall", "object": "bed"},
                  {"rule": "on_wall_mid", "object": "tv"},
                  {"rule": "facing", "object": "bed", "target": "tv"}, *rules]})


def _misses(plan: fl.Plan, samples: int) -> dict[str, int]:
    out: dict[str, int] = {}
    for lay in fl.sampling.solve_many(plan, list(range(samples))):
        for r in lay.rule_report():
            if r.satisfied is False:
                out[r.label] = out.get(r.label, 0) + 1
    return out


def test_a_tall_object_placed_after_keeps_off_the_wall_a_bed_looks_at_for_its_tv():
    """A wardrobe against the wall at the foot of a bed that faces the TV on the wall
    leaves the TV no room there (the TV is hung after the floor settles): the wardrobe's
    start keeps off that stretch of wall (4 of these 60 samples missed the bed's rule
    before, none after)."""
    plan = _bed_and_tv({"id": "wardrobe", "category": "wardrobe", "size": [1.2, 0.6, 2.0]},
                       [{"rule": "at_wall", "object": "wardrobe"}])
    assert _misses(plan, 60).get("facing(bed, tv)", 0) <= 1


def test_an_object_turned_towards_a_wall_object_is_not_squared_up_by_the_floor():
    """A beanbag facing the TV on the wall: no term of the floor turns it (the TV is hung
    after it settles), so the alignment that squares objects up with the room leaves it
    turned as it starts, towards where the TV will hang (before: square in all 60 samples
    and the beanbag's rule missed in 6, the bed's in 5; after: 1 miss in all)."""
    plan = _bed_and_tv({"id": "beanbag", "category": "beanbag", "size": [0.8, 0.8, 0.6]},
                       [{"rule": "facing", "object": "beanbag", "target": "tv"}])
    assert sum(_misses(plan, 60).values()) <= 3
    model = ForceModel(plan)
    bag = model.ids.index("beanbag")
    # the bed is turned to the TV too, but held square by its wall
    assert sorted((b.object, b.target) for b in model.wall_views) == [("beanbag", "tv"),
                                                                      ("bed", "tv")]
    assert model.turned_to_wall.tolist() == [True, True]
    assert (model.turned_to_wall & ~model.held).tolist() == [k == bag for k in range(model.n)]


def test_a_crowded_bedroom_faces_its_wall_tv_from_the_bed_and_the_beanbag():
    """A new user's 3.2 x 3.8 m teenager's bedroom (held out): a bed and a beanbag facing
    the TV on the wall, a wardrobe, a desk and its chair. A tall object placed after the
    bed ranks a spot at the wall the bed looks at, moving the TV's spot, half a miss, and
    an object facing the TV draws more starts from where the spot can be seen: 25 of 60
    samples missed one of the two rules before the start poses looked at the TV at all, 10
    with the sights alone, 4 now."""

    plan = fl.load_plan(Path(__file__).parents[1] / "benchmarks" / "plans_heldout"
                        / "teen_bedroom_wall_tv.json")
    missed = sum(any(r.satisfied is False and r.rule == "facing" and r.target == "tv"
                     for r in lay.rule_report())
                 for lay in fl.sampling.solve_many(plan, [fl.sampling.sample_seed(0, k)
                                                          for k in range(60)]))
    assert missed <= 6


def test_a_bed_and_its_nightstands_start_at_every_wall_they_fit():
    """Nightstands stand with their backs level with the bed's, so the room kept beside a
    bed is as deep as they are, not as deep as the bed: along the side wall the bed's foot
    end would have come 5 cm into the door's swing (the bed started at the wall across
    from the door in all 60 of these samples before, at two walls after)."""
    plan = fl.Plan.from_dict({
        "name": "double bed by a door",
        "room": {"polygon": [[0, 0], [3.2, 0], [3.2, 3.4], [0, 3.4]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 0.75, "width": 0.85}]},
        "objects": [{"id": "bed", "category": "bed", "size": [1.6, 2.05, 0.55]},
                    *({"id": f"nightstand_{s}", "category": "nightstand",
                       "size": [0.45, 0.4, 0.55]} for s in "lr")],
        "rules": [{"rule": "at_wall", "object": "bed"},
                  {"rule": "away_from_door", "object": "bed", "params": {"distance": 1.0}},
                  *({"rule": side, "object": f"nightstand_{side[0]}", "target": "bed",
                     "params": {"distance": 0.1}} for side in ("left_of", "right_of")),
                  *({"rule": "at_wall", "object": f"nightstand_{s}"} for s in "lr")]})
    fronts = [(round(-np.sin(lay.poses["bed"].yaw)), round(np.cos(lay.poses["bed"].yaw)))
              for lay in fl.sampling.solve_many(plan, list(range(60)))
              if lay.report.valid and lay.rule_satisfaction == 1.0]
    assert len(fronts) == 60
    assert min(fronts.count(f) for f in set(fronts)) >= 10 and len(set(fronts)) >= 2


def test_a_dresser_with_a_mirror_above_it_keeps_off_the_wall_a_bed_looks_at():
    """A new user's double bedroom (held out): a bed facing the TV on the wall, and a
    dresser 0.8 m tall with a mirror above it. The mirror hides the wall to about 1.8 m,
    where the TV would hang: the dresser's start ranks that stretch of the wall the bed
    looks at as it ranks a wardrobe there (the bed's rule missed in 12 of these 60 samples
    before, 4 after)."""

    plan = fl.load_plan(Path(__file__).parents[1] / "benchmarks" / "plans_heldout"
                        / "bedroom_double.json")
    assert _misses(plan, 60).get("facing(bed, tv)", 0) <= 6


def test_a_desk_leaves_its_chair_a_view_of_the_whiteboard_the_chair_faces():
    """An office chair in front of its desk, facing the desk and the whiteboard on the
    wall: a desk at the window leaves the whiteboard no room where the chair looks, so a
    desk's start ranks one such chair's rule as missed there (17 of these 60 samples
    missed it before, none after)."""
    plan = fl.Plan.from_dict({
        "name": "office",
        "room": {"polygon": [[0, 0], [2.8, 0], [2.8, 3.6], [0, 3.6]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 1.6, "width": 0.85}],
                 "windows": [{"wall": 2, "offset": 0.8, "width": 1.2}]},
        "objects": [{"id": "desk", "category": "desk", "size": [1.4, 0.7, 0.75]},
                    {"id": "chair", "category": "office_chair", "size": [0.6, 0.6, 1.1]},
                    {"id": "whiteboard", "category": "whiteboard", "size": [1.2, 0.03, 0.9]}],
        "rules": [{"rule": "at_wall", "object": "desk"},
                  {"rule": "near_window", "object": "desk", "params": {"distance": 1.0}},
                  {"rule": "in_front_of", "object": "chair", "target": "desk",
                   "params": {"distance": 0.3}},
                  {"rule": "facing", "object": "chair", "target": "desk"},
                  {"rule": "on_wall_mid", "object": "whiteboard"},
                  {"rule": "facing", "object": "chair", "target": "whiteboard",
                   "params": {"view_height": 1.5}}]})
    assert _misses(plan, 60).get("facing(chair, whiteboard)", 0) <= 2



def test_a_desk_may_stand_by_the_window_at_the_side_of_a_sofa_bed_under_it():
    """The held-out guest room (3 x 3 m): the sofa bed fits under the window only with the
    desk that must stand near the window on the side wall beside it, a corner of the sofa
    bed by one end of the desk's front. One office chair needs a stretch of that front as
    wide as itself, not all of it; and a sofa bed's long sides, where a person gets in,
    are its front and back, not its ends. In 1 of these 60 samples before, in 16 after;
    every sample meets every rule."""
    plan = fl.load_plan(Path(__file__).parents[1] / "benchmarks" / "plans_heldout"
                        / "guest_room.json")
    layouts = fl.sampling.solve_many(plan, list(range(60)))
    assert all(lay.report.valid and lay.rule_satisfaction == 1.0 for lay in layouts)
    under = [lay for lay in layouts if lay.poses["sofa_bed"].y > 2.3]  # its back at wall 2
    assert sum(lay.poses["desk"].x > 2.5 for lay in under) >= 8


def test_objects_facing_a_wall_object_start_a_viewing_distance_from_it():
    """An armchair, a treadmill and an exercise bike facing one TV on the wall: a start
    whose front comes nearer the TV's spot than a viewer sits ranks as missing its rule
    (a treadmill with its console under the TV stood in the others' view of it: all
    three rules met in 46 of these 60 samples before, 57 after)."""
    plan = fl.Plan.from_dict({
        "name": "den",
        "room": {"polygon": [[0, 0], [4.0, 0], [4.0, 4.5], [0, 4.5]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 0.7, "width": 0.9}]},
        "objects": [{"id": "tv", "category": "tv", "size": [1.15, 0.06, 0.7]},
                    {"id": "armchair", "category": "armchair", "size": [0.85, 0.85, 0.95]},
                    {"id": "treadmill", "category": "treadmill", "size": [0.8, 1.9, 1.4]},
                    {"id": "bike", "category": "exercise_bike", "size": [0.6, 1.2, 1.2]},
                    {"id": "rack", "category": "dumbbell_rack", "size": [1.0, 0.4, 0.8]}],
        "rules": [{"rule": "on_wall_mid", "object": "tv"},
                  *({"rule": "facing", "object": o, "target": "tv"}
                    for o in ("armchair", "treadmill", "bike")),
                  {"rule": "at_wall", "object": "rack"}]})
    met = sum(all(r.satisfied for r in lay.rule_report() if r.rule == "facing")
              for lay in fl.sampling.solve_many(plan, list(range(60))))
    assert met >= 53


def test_an_object_draws_again_where_no_candidate_meets_its_rules():
    """A table that should stand 3.5 m from a sofa in the corner of a 6 x 4 m room: few
    spots qualify, so where the first draw has none, a second one is made."""
    plan = fl.Plan.from_dict({
        "name": "apart",
        "room": {"polygon": [[0, 0], [6.0, 0], [6.0, 4.0], [0, 4.0]], "height": 2.6},
        "objects": [{"id": "sofa", "category": "sofa", "size": [2.0, 0.9, 0.85]},
                    {"id": "table", "category": "table", "size": [0.6, 0.6, 0.7]}],
        "rules": [{"rule": "in_corner", "object": "sofa"},
                  {"rule": "far_from", "object": "table", "target": "sofa",
                   "params": {"distance": 3.5}}]})
    model = ForceModel(plan)
    far = next(k for k, b in enumerate(model.bindings) if b.rule.name == "far_from")
    met = sum(model.satisfied(model.state(*propose_poses(model, np.random.default_rng(s),
                                                         tries=2)))[far]
              for s in range(100))
    assert met >= 18  # one draw of 3 candidates: 11 of these 100


def test_chairs_around_a_table_start_at_its_sides_square_to_it():
    model = ForceModel(fl.Plan.from_dict(TABLE_FOR_FOUR))  # a 1.6 x 0.9 m table
    for seed in range(6):
        pos, yaw = propose_poses(model, np.random.default_rng(seed))
        t = model.ids.index("table")
        c, s = np.cos(yaw[t]), np.sin(yaw[t])
        for k in range(4):
            r = model.ids.index(f"chair_{k}")
            d = pos[r] - pos[t]
            lx, ly = d @ [c, s], d @ [-s, c]
            long_side = abs(lx) <= 0.8 + 1e-9 and abs(ly) >= 0.45  # table 1.6 x 0.9 m
            short_side = abs(ly) <= 0.45 + 1e-9 and abs(lx) >= 0.8
            assert long_side or short_side  # beside a side, not off a corner
            turn = (yaw[r] - yaw[t]) % (np.pi / 2)
            assert min(turn, np.pi / 2 - turn) < 1e-9  # square to the table


def test_relocations_batched_are_the_ones_drawn_alone():
    """Samples that draw different objects again, batched together, get what each gets
    alone, bit for bit (each draws from its own generator, judged in its own room: an
    object that another sample has not placed yet blocks no view in this one)."""
    for name, trials in (("living_room", 1), ("l_shaped_studio", 6)):
        model = ForceModel(fl.load_plan(name))
        for trial in range(trials):
            pick = np.random.default_rng(trial)
            ask = []
            for k in range(16):  # some move nothing, some one object, some half of them
                size = [0, 1, 3, model.n // 2][k % 4]
                rows = sorted(pick.choice(model.n, size=size, replace=False).tolist())
                pos, yaw = propose_poses(model, np.random.default_rng(1000 * trial + k))
                ask.append(RelocateRequest(Starts.placer_of(model),
                                           np.random.default_rng(100 + k), tuple(rows), pos,
                                           yaw, 16, 0.3))
            alone = [relocate(model, list(q.rows), q.pos, q.yaw,
                              np.random.default_rng(100 + k)) for k, q in enumerate(ask)]
            placer = Starts.placer_of(model)
            for q in ask:
                q.placer = placer
            together = RelocateRequest.run(ask)
            for (p1, y1), (p2, y2), q in zip(alone, together, ask, strict=True):
                np.testing.assert_array_equal(p1, p2)
                np.testing.assert_array_equal(y1, y2)
                still = [r for r in range(model.n) if r not in q.rows]
                np.testing.assert_array_equal(p2[still], q.pos[still])  # the others stay


def test_an_object_beside_its_parent_starts_with_the_backs_level():
    """A nightstand bound to a bed by next_to alone starts at the head of the bed, its back
    level with the bed's, not at the middle of the bed's long side; so it stays there."""
    plan = fl.Plan.from_dict(BED_AND_NIGHTSTAND)
    model = ForceModel(plan)
    bed, ns = model.ids.index("bed"), model.ids.index("nightstand")
    level = 0
    for seed in range(12):
        pos, yaw = propose_poses(model, np.random.default_rng(seed))
        off = backs_offset((*pos[bed], yaw[bed]), (*pos[ns], yaw[ns]), 2.0, 0.4)
        level += abs(off) < 0.05
    assert level >= 11
    lay = fl.solve(plan, 3)
    b, n = lay.poses["bed"], lay.poses["nightstand"]
    assert abs(backs_offset((b.x, b.y, b.yaw), (n.x, n.y, n.yaw), 2.0, 0.4)) < 0.15


def test_starts_keep_out_of_access_zones():
    """A small kitchen with a fridge, a dishwasher and a tall cabinet at its walls: starts
    keep each one out of the others' access zones (37 of 60 starts had one in another's
    zone while starts ignored the zones)."""
    from forcelayout import geometry as geo
    from forcelayout.access import AccessTerm

    plan = fl.Plan.from_dict({
        "name": "small kitchen",
        "room": {"polygon": [[0, 0], [2.6, 0], [2.6, 2.4], [0, 2.4]], "height": 2.5,
                 "doors": [{"wall": 0, "offset": 2.0, "width": 0.8}]},
        "objects": [{"id": "fridge", "category": "fridge", "size": [0.7, 0.7, 1.8]},
                    {"id": "dishwasher", "category": "dishwasher", "size": [0.6, 0.6, 0.85]},
                    {"id": "wardrobe", "category": "wardrobe", "size": [1.0, 0.6, 2.0]}],
        "rules": [{"rule": "at_wall", "object": o} for o in ("fridge", "dishwasher", "wardrobe")]})
    model = ForceModel(plan)
    zones = next(t for t in model.terms if isinstance(t, AccessTerm))
    blocked = 0
    for s in range(60):
        st = model.state(*propose_poses(model, np.random.default_rng(s)))
        c, out, lat, half = zones.zones(st)
        sep = geo.obb_separation(st.pos[None] - c[:, None], lat[:, None], out[:, None],
                                 half[:, None], st.right[None], st.front[None], st.half[None])
        blocked += ((sep < -0.02) & ~zones.exempt).any()
    assert blocked <= 3


def test_starts_drawn_ahead_are_the_same_alone_or_in_a_batch():
    """A sample whose first starts fail draws several at once (``ahead``); what it gets
    depends on its own generator only, whatever else is in its batch."""

    from forcelayout.batching import drive

    plan = fl.load_plan(Path(__file__).resolve().parents[1]
                        / "benchmarks/plans/bedroom_crowded_3x3_2.json")
    model = ForceModel(plan)
    placer = Starts.placer_of(model)

    def run(seeds, ahead):
        starts = [Starts(model, np.random.default_rng(s), placer=placer, ahead=ahead)
                  for s in seeds]

        def first_passing(st):  # the sample's starts until one passes
            while True:
                got = yield from st.next()
                if got is None or got[2].ok:
                    return got, st.drawn

        return drive([first_passing(st) for st in starts])

    seeds = list(range(12))
    together = run(seeds, 4)
    assert max(drawn for _, drawn in together) > 2  # some drew ahead
    for s, (got, drawn) in zip(seeds, together, strict=True):
        (alone, drawn_alone), = run([s], 4)
        assert drawn == drawn_alone
        assert (got is None) == (alone is None)
        if got is not None:
            np.testing.assert_array_equal(got[0], alone[0])
            np.testing.assert_array_equal(got[1], alone[1])


@given(seed=st.integers(0, 2**16), w=st.floats(2.0, 6.0), d=st.floats(2.0, 6.0))
@settings(max_examples=30, deadline=None)
def test_a_rectangular_floor_holds_a_candidate_exactly_when_shapely_says_so(seed, w, d):
    """The start draw's quick test of a box room (corners within its bounds) agrees with
    ``shapely.contains`` on every footprint, those pressed against a wall included."""
    import shapely

    from forcelayout.initial import _Placer

    plan = fl.Plan.from_dict({
        "name": "box", "room": {"polygon": [[0.3, -0.2], [0.3 + w, -0.2], [0.3 + w, d - 0.2],
                                            [0.3, d - 0.2]]},
        "objects": [{"id": "a", "category": "desk", "size": [1.0, 0.5, 0.75]}], "rules": []})
    placer = _Placer(ForceModel(plan))
    assert placer.box_floor
    rng = np.random.default_rng(seed)
    yaw = rng.integers(0, 4, (3, 40)) * 0.5 * np.pi
    yaw[0] = rng.uniform(-np.pi, np.pi, 40)
    c, s = np.cos(yaw), np.sin(yaw)
    rgt, fwd = np.stack([c, s], 2), np.stack([-s, c], 2)
    ext = placer.half[0]
    cand = rng.uniform(placer.lo - 0.3, placer.hi + 0.3, (3, 40, 2))
    reach = np.abs(rgt) * ext[0] + np.abs(fwd) * ext[1]  # half extent along x and y
    cand[:, ::3, 0] = placer.lo[0] + reach[:, ::3, 0]  # pressed against a wall
    cand[:, 1::3, 1] = placer.hi[1] - reach[:, 1::3, 1]
    inside, _ = placer._clearance(cand, rgt, fwd, ext, [], np.zeros(0), np.zeros((3, 1, 2)),
                                  np.zeros((3, 1)), False)
    hr, hf = rgt * ext[0], fwd * ext[1]
    corners = np.stack([cand - hr - hf, cand + hr - hf, cand + hr + hf, cand - hr + hf], 2)
    exact = shapely.contains(placer.room.shape, shapely.polygons(corners.reshape(-1, 4, 2)))
    assert np.array_equal(inside, exact.reshape(3, 40))


@pytest.fixture
def faces_window_rule():
    from forcelayout.rules.shaping import signed_angle, unit

    @rules.register("test_faces_window")
    class FacesWindow(rules.Rule):
        """Front within 30 degrees of the direction to the nearest window's centre."""

        start = rules.StartHint(turn="face_window")

        def force(self, state, i, j, p):
            return np.zeros((len(i), 2)), np.zeros(len(i))

        def satisfied(self, state, i, j, p):
            c = state.room.windows.centre
            d = c[None] - state.pos[i][:, None]
            u, _ = unit(d[np.arange(len(i)), np.argmin((d * d).sum(-1), axis=1)])
            return np.abs(signed_angle(state.front[i], u)) <= np.radians(30.0)

    yield
    rules.unregister("test_faces_window")


FACING_A_WINDOW = {
    "name": "armchair_by_the_window",
    "room": {"polygon": [[0, 0], [5, 0], [5, 4], [0, 4]],
             "windows": [{"wall": 0, "offset": 1.0, "width": 1.2}],
             "doors": [{"wall": 2, "offset": 2.0, "width": 0.9}]},
    "objects": [{"id": "armchair", "category": "armchair", "size": [0.8, 0.8, 0.9]},
                {"id": "lamp", "category": "floor_lamp", "size": [0.3, 0.3, 1.6]}],
    "rules": [{"rule": "test_faces_window", "object": "armchair"},
              {"rule": "test_faces_window", "object": "lamp"},
              {"rule": "at_wall", "object": "lamp"}],
}


def test_a_start_turned_to_face_the_window(faces_window_rule):
    """``StartHint(turn="face_window")``: a free-standing object starts facing the nearest
    window; an object backed against a wall keeps the wall's heading."""
    from forcelayout.baselines import rule_aware_layout

    plan = fl.Plan.from_dict(FACING_A_WINDOW)
    model = ForceModel(plan)
    chair, lamp = model.ids.index("armchair"), model.ids.index("lamp")
    window = model.room.windows.centre[0]
    for s in range(20):
        pos, yaw = propose_poses(model, np.random.default_rng(s))
        to = window - pos[chair]
        front = np.array([-np.sin(yaw[chair]), np.cos(yaw[chair])])
        assert front @ to / np.linalg.norm(to) > 1 - 1e-9
        back = pos[lamp] - 0.15 * np.array([-np.sin(yaw[lamp]), np.cos(yaw[lamp])])
        assert model.room.wall_distance(back[None])[0].min() < 0.05  # its back at a wall
    # the rejection baseline turns it as well: the rule holds in every draw
    met = [rule_aware_layout(plan, s).rule_report()[0].satisfied for s in range(10)]
    assert all(met)


def test_stools_left_of_a_peninsula_they_face_start_along_it_square_to_it():
    """Three stools left_of a 1.6 m peninsula and facing it start anywhere along its left
    side, each turned squarely to it (left_of alone starts an object at the back end with
    the parent's heading, as a nightstand)."""
    stools = [f"stool_{k}" for k in range(3)]
    plan = fl.Plan.from_dict({
        "name": "kitchen",
        "room": {"polygon": [[0, 0], [4, 0], [4, 3.6], [0, 3.6]], "height": 2.6,
                 "doors": [{"wall": 0, "offset": 3.3, "width": 0.8}]},
        "objects": [{"id": "peninsula", "category": "counter", "size": [0.9, 1.6, 0.9]},
                    *({"id": s, "category": "bar stool", "size": [0.4, 0.4, 0.75]}
                      for s in stools)],
        "rules": [{"rule": "at_wall", "object": "peninsula"},
                  *({"rule": "left_of", "object": s, "target": "peninsula",
                     "params": {"distance": 0.3}} for s in stools),
                  *({"rule": "facing", "object": s, "target": "peninsula"} for s in stools)]})
    model = ForceModel(plan)
    p, rows = model.ids.index("peninsula"), [model.ids.index(s) for s in stools]
    square = along = 0
    for seed in range(20):
        pos, yaw = propose_poses(model, np.random.default_rng(seed))
        c, s = np.cos(yaw[p]), np.sin(yaw[p])
        for r in rows:
            d = pos[r] - pos[p]
            lx, ly = d @ [c, s], d @ [-s, c]  # in the peninsula's frame: left is -x
            turned = np.degrees((yaw[r] - yaw[p] + np.pi) % (2 * np.pi) - np.pi)
            square += lx < -0.45 and abs(turned + 90.0) < 1.0  # front towards +x
            along += abs(ly) < 0.8
    # of 60: 44 and 51 (the rest where the peninsula's left side is against a wall); 0 of
    # 60 square while such stools started with the peninsula's heading
    assert square >= 38 and along >= 42


def test_chairs_around_a_table_start_with_room_behind_them():
    """A 1.2 m table in the middle of a 3.6 x 3 m room and four chairs around it: each chair
    owns a zone behind it (``around`` declares it), and the table starts with room for the
    chairs and their zones, so fewer chairs start with their backs near a wall (the middle
    of the zone's far side off the floor: 65 of 192 while chairs had no zone, 38 now; the
    room is 2.4 m across for a table, two chairs and their zones in the middle only)."""
    from forcelayout.access import AccessTerm

    plan = fl.Plan.from_dict({
        "name": "tutoring room",
        "room": {"polygon": [[0, 0], [3.6, 0], [3.6, 3.0], [0, 3.0]], "height": 2.7,
                 "doors": [{"wall": 0, "offset": 3.0, "width": 0.9}]},
        "objects": [{"id": "table", "category": "table", "size": [1.2, 0.8, 0.75]},
                    *({"id": f"chair_{k}", "category": "chair", "size": [0.45, 0.5, 0.85]}
                      for k in range(4)),
                    {"id": "bookshelf", "category": "bookshelf", "size": [0.8, 0.35, 1.8]},
                    {"id": "cabinet", "category": "cabinet", "size": [0.8, 0.45, 0.9]}],
        "rules": [{"rule": "in_middle", "object": "table"},
                  *({"rule": "around", "object": f"chair_{k}", "target": "table"}
                    for k in range(4)),
                  *({"rule": "facing", "object": f"chair_{k}", "target": "table"}
                    for k in range(4)),
                  {"rule": "at_wall", "object": "bookshelf"},
                  {"rule": "at_wall", "object": "cabinet"}]})
    model = ForceModel(plan)
    zones = next(t for t in model.terms if isinstance(t, AccessTerm))
    chairs = [model.ids.index(f"chair_{k}") for k in range(4)]
    assert sorted(zones.owner[zones.direction[:, 1] < 0].tolist()) == chairs
    off = 0
    for s in range(48):
        st = model.state(*propose_poses(model, np.random.default_rng(s)))
        c, out, lat, half = zones.zones(st)
        far = c + out * half[:, 1:]
        off += (~model.room.contains(far[np.isin(zones.owner, chairs)])).sum()
    assert off <= 48


def test_two_beds_face_one_wall_tv_in_every_layout_of_a_kids_room():
    """A new user's kids' room (held out): two single beds facing one TV on the wall. The
    TV's one spot serves both only where they look at one stretch of wall; a floor, its
    start too, whose second bed looks elsewhere is judged as missing that bed's rule, and
    both beds are drawn again (52 of these 60 samples met every rule before, 60 after)."""

    plan = fl.load_plan(Path(__file__).parents[1] / "benchmarks" / "plans_heldout"
                        / "kids_room_two_beds_tv.json")
    assert sum(_misses(plan, 60).values()) <= 3


def test_a_table_may_start_against_a_wall_with_its_chairs_on_the_other_sides():
    """A 1.2 x 0.8 m table and three chairs ``around`` it in a 3 x 3 m room: the long side
    seats two, an end one, so the table may stand with a side to a wall (as a kitchen table
    for two or three does). It had started with room all round only: 1 of 60 starts had it
    within 0.3 m of a wall, 25 now."""
    plan = fl.Plan.from_dict({
        "name": "nook", "room": {"polygon": [[0, 0], [3.0, 0], [3.0, 3.0], [0, 3.0]]},
        "objects": [{"id": "table", "category": "dining_table", "size": [1.2, 0.8, 0.75]},
                    *({"id": f"chair_{k}", "category": "chair", "size": [0.45, 0.5, 0.9]}
                      for k in range(3))],
        "rules": [{"rule": "around", "object": f"chair_{k}", "target": "table"}
                  for k in range(3)]})
    model = ForceModel(plan)
    t = model.ids.index("table")
    near = 0
    for s in range(60):
        pos, yaw = propose_poses(model, np.random.default_rng(s))
        c, sn = abs(np.cos(yaw[t])), abs(np.sin(yaw[t]))
        ext = np.array([0.6 * c + 0.4 * sn, 0.6 * sn + 0.4 * c])
        near += min((pos[t] - ext).min(), (3.0 - pos[t] - ext).min()) < 0.3
    assert near >= 12


def test_a_desk_whose_chair_belongs_at_a_wall_starts_facing_that_wall():
    """A reception desk near the door, its chair ``in_front_of`` it and ``at_wall``: the
    desk also draws spots facing a wall, its chair's room off it, and its front zone ends
    at the chair (no floor is free beyond a chair held at a wall). Of 60 starts the chair
    met its wall rule in 1 drawn at once and 27 chosen from restarts; 10 and 60 now."""
    model = ForceModel(fl.Plan.from_dict(RECEPTION))
    k = next(k for k, b in enumerate(model.bindings)
             if b.rule.name == "at_wall" and b.object == "desk_chair")
    drawn = sum(model.satisfied(model.state(*propose_poses(model, np.random.default_rng(s))))[k]
                for s in range(60))
    chosen = sum(model.satisfied(model.state(*initial_poses(model, np.random.default_rng(s))))[k]
                 for s in range(60))
    assert drawn >= 6 and chosen >= 54


def test_two_desks_each_behind_the_other_start_back_to_back():
    """``behind`` both ways (desks back to back): the one that starts behind its parent is
    turned about, so both rules can be met; it had started facing as its parent did, and
    a new user's office for two took 49 samples (47 s) for 20 layouts, 20 now (1.5 s)."""
    plan = fl.Plan.from_dict({
        "name": "office for two", "room": {"polygon": [[0, 0], [4.2, 0], [4.2, 3.6], [0, 3.6]]},
        "objects": [{"id": "desk_a", "category": "desk", "size": [1.4, 0.7, 0.75]},
                    {"id": "desk_b", "category": "desk", "size": [1.4, 0.7, 0.75]}],
        "rules": [{"rule": "behind", "object": "desk_b", "target": "desk_a",
                   "params": {"distance": 0.05, "lateral": 0.05}},
                  {"rule": "behind", "object": "desk_a", "target": "desk_b",
                   "params": {"distance": 0.05, "lateral": 0.05}}]})
    model = ForceModel(plan)
    a, b = model.ids.index("desk_a"), model.ids.index("desk_b")
    for s in range(12):
        pos, yaw = initial_poses(model, np.random.default_rng(s))
        assert abs(np.cos(yaw[a] - yaw[b]) + 1.0) < 1e-9
        assert all(model.satisfied(model.state(pos, yaw)).values())


def test_a_desk_near_a_whiteboard_on_a_named_wall_starts_within_reach_of_that_wall():
    """A whiteboard hung on wall 3 (the plan names it) and a desk ``near`` it: the wall
    object hangs after the floor settles, so the floor had no notion of where it would be;
    the desk now draws spots within the rule's reach of wall 3, misses the rule where it
    stands beyond (a start's verdict names it), and starts there. A new user's seminar
    room met the rule in 0 of 20 layouts, 15 now."""
    from forcelayout.verdict import judge_floor

    plan = fl.Plan.from_dict({
        "name": "classroom", "room": {"polygon": [[0, 0], [6, 0], [6, 5], [0, 5]],
                                      "doors": [{"wall": 0, "offset": 5.2, "width": 0.9}]},
        "objects": [{"id": "desk", "category": "desk", "size": [1.4, 0.7, 0.75]},
                    {"id": "chair", "category": "office_chair", "size": [0.55, 0.55, 1.0]},
                    {"id": "shelf", "category": "bookshelf", "size": [0.9, 0.35, 1.9]},
                    {"id": "whiteboard", "category": "whiteboard", "size": [2.4, 0.05, 1.2]}],
        "rules": [{"rule": "on_wall", "object": "whiteboard", "params": {"wall": 3}},
                  {"rule": "near", "object": "whiteboard", "target": "desk",
                   "params": {"distance": 1.0}},
                  {"rule": "in_front_of", "object": "chair", "target": "desk"},
                  {"rule": "at_wall", "object": "shelf"}]})
    model = ForceModel(plan)
    d = model.ids.index("desk")
    within = 0
    for s in range(20):
        pos, yaw = initial_poses(model, np.random.default_rng(s))
        c, sn = abs(np.cos(yaw[d])), abs(np.sin(yaw[d]))
        within += pos[d, 0] - (0.7 * c + 0.35 * sn) <= 1.05 + 1e-9  # wall 3 is x = 0
    assert within == 20
    pos, yaw = initial_poses(model, np.random.default_rng(0))
    pos[d] = [4.5, 2.5]  # 3.8 m and more from wall 3
    verdict = judge_floor(model, pos, yaw)
    assert "near(whiteboard, desk)" in verdict.failures and d in verdict.at_fault
