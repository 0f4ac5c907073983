"""Saying why, early: feasibility of a plan before sampling, the dominant cause after."""

from __future__ import annotations

import pytest

from forcelayout import Plan, SampleReport
from forcelayout.diagnose import Feasibility, dominant_cause, feasibility, missed_rules
from forcelayout.examples import list_plans


def room_plan(objects: list[dict], rules: list[dict], *, polygon=None, windows=None) -> Plan:
    return Plan.from_dict({
        "name": "test",
        "room": {"polygon": polygon or [[0, 0], [3, 0], [3, 2.4], [0, 2.4]],
                 "doors": [{"wall": 0, "offset": 0.6, "width": 0.8}],
                 "windows": [{"wall": 2, "offset": 1.5, "width": 1.0}] if windows is None
                 else windows},
        "objects": objects, "rules": rules})


@pytest.mark.parametrize("name", list_plans())
def test_bundled_plans_are_feasible(name):
    f = feasibility(name)
    assert isinstance(f, Feasibility)
    assert f.verdict in ("ok", "tight") and f.ok
    assert 0.0 < f.fill < 0.6
    assert 0.3 < f.free_fraction <= f.free_fraction_best <= 1.0
    assert f.misfits == []
    assert f.wall_bound and 0 < f.wall_demand < f.wall_available
    text = str(f)
    assert text.splitlines()[0] == f"plan {name!r}: {f.verdict}"
    assert 4 <= len(text.splitlines()) <= 8


def test_shelves_that_need_more_wall_than_the_room_has_are_infeasible():
    shelves = [{"id": f"shelf_{k}", "category": "bookshelf", "size": [1.2, 0.35, 2.0]}
               for k in range(8)]
    plan = room_plan(shelves, [{"rule": "at_wall", "object": s["id"]} for s in shelves])
    f = feasibility(plan)
    assert f.verdict == "infeasible" and not f.ok
    assert f.wall_bound == [s["id"] for s in shelves]
    assert f.tall_demand == pytest.approx(9.6)
    assert f.tall_available == pytest.approx(10.8 - 0.8 - 1.0)
    assert any("wall" in n and "9.60 m" in n for n in f.notes)
    # the same shelves without wall rules need no wall
    loose = feasibility(room_plan(shelves, []))
    assert loose.wall_bound == [] and loose.wall_demand == 0.0


def test_corner_objects_take_wall_on_both_sides_and_are_found_by_the_registry():
    objs = [{"id": "plant", "category": "plant", "size": [0.4, 0.4, 0.9]},
            {"id": "desk", "category": "desk", "size": [1.2, 0.6, 0.75]},
            {"id": "chair", "category": "chair", "size": [0.5, 0.5, 0.9]}]
    plan = room_plan(objs, [{"rule": "in_corner", "object": "plant"},
                            {"rule": "at_wall", "object": "desk"},
                            {"rule": "in_corner", "object": "desk"},
                            {"rule": "in_front_of", "object": "chair", "target": "desk"}])
    f = feasibility(plan)
    assert f.wall_bound == ["plant", "desk"]
    assert f.wall_demand == pytest.approx(0.8 + 1.8)
    assert f.verdict == "ok"


def test_an_object_that_fits_nowhere_in_an_l_shaped_room_is_infeasible():
    l_room = [[0, 0], [4, 0], [4, 1.8], [1.8, 1.8], [1.8, 4], [0, 4]]  # arms 1.8 m wide
    plan = room_plan([{"id": "bed", "category": "bed", "size": [2.0, 2.0, 0.5]},
                      {"id": "lamp", "category": "lamp", "size": [0.3, 0.3, 1.6]}], [],
                     polygon=l_room, windows=[])
    f = feasibility(plan)
    assert f.misfits == ["bed"] and f.verdict == "infeasible"
    assert f.notes[0].startswith("'bed' (2 x 2 m) fits nowhere")


def test_too_little_free_floor_for_a_wide_agent_is_infeasible_and_walkable_covers_do_not_count():
    objs = [{"id": "bed", "category": "bed", "size": [1.4, 2.0, 0.5]},
            {"id": "desk", "category": "desk", "size": [1.0, 0.5, 0.75]},
            {"id": "rug", "category": "rug", "size": [1.2, 0.8, 0.01]}]
    plan = room_plan(objs, [{"rule": "at_wall", "object": "bed"}])
    f = feasibility(plan)
    assert f.footprint_area == pytest.approx(2.8 + 0.5)  # the rug takes no floor
    assert f.verdict != "infeasible"
    wide = feasibility(plan, agent_radius=0.8)
    assert wide.verdict == "infeasible" and wide.free_fraction_best < 0.3
    assert "remove objects or enlarge the room" in wide.notes[0]
    assert feasibility(plan, min_free_fraction=0.6).verdict in ("tight", "infeasible")


def test_a_long_object_across_a_narrow_room_is_tight():
    plan = room_plan([{"id": "sofa", "category": "sofa", "size": [2.3, 0.9, 0.8]}], [])
    f = feasibility(plan)
    assert f.largest == "sofa" and f.largest_size == (2.3, 0.9)
    assert f.room_span == pytest.approx((2.4, 3.0))
    assert f.verdict == "tight" and "'sofa'" in f.notes[0]
    assert "along the long walls" in f.notes[0]


def test_a_long_object_in_a_square_room_is_tight_both_ways():
    square = [[0, 0], [2.5, 0], [2.5, 2.5], [0, 2.5]]
    plan = room_plan([{"id": "bed", "category": "bed", "size": [2.3, 0.9, 0.5]}], [],
                     polygon=square)
    note = next(n for n in feasibility(plan).notes if "bed" in n)
    assert "'bed'" in note and "long walls" not in note and "at either heading" in note


def test_feasibility_rejects_bad_parameters():
    with pytest.raises(ValueError, match="agent_radius"):
        feasibility("bedroom", agent_radius=-1)
    with pytest.raises(ValueError, match="min_free_fraction"):
        feasibility("bedroom", min_free_fraction=2)


# -- dominant_cause ----------------------------------------------------------------------------


def fail(*lines: str, seed: int = 0) -> SampleReport:
    return SampleReport(seed=seed, valid=False, failures=list(lines))


BLOCKED = "reachable: 'bed' cannot be reached from door 0 (blocked by 'wardrobe', 'desk')"
UNMET = "rules: 80% met, below 95%; unmet: next_to(nightstand_2, bed), at_wall(desk)"


def test_nothing_failed_means_no_cause():
    assert dominant_cause([]) is None
    assert dominant_cause([SampleReport(seed=k) for k in range(3)]) is None


def test_the_most_common_check_rules_and_blockers_are_named():
    reports = ([fail(BLOCKED, "navigable: only 25% of the floor is free for an agent of radius "
                     "0.2 m (need 30%)")] * 5
               + [fail(BLOCKED)] * 3
               + [fail(UNMET)] * 2
               + [SampleReport(seed=9)] * 2)
    line = dominant_cause(reports)
    assert dominant_cause(reports[:8] + [fail(UNMET.replace(", at_wall(desk)", ""))]) == (
        "89 % of samples fail 'reachable'; 11 % miss rule next_to(nightstand_2, bed); "
        "wardrobe and desk block the path to bed")
    assert line == ("67 % of samples fail 'reachable'; 17 % miss rules next_to(nightstand_2, bed) "
                    "and at_wall(desk); wardrobe and desk block the path to bed")


def test_a_way_closed_between_two_doors_is_named():
    closed = fail("reachable: door 1 cannot be reached from door 0 (blocked by 'sofa', "
                  "'bookcase')")
    assert dominant_cause([closed, SampleReport(seed=1)]) == (
        "50 % of samples fail 'reachable'; sofa and bookcase block the path to door 1")


def test_rules_as_the_dominant_cause_name_the_missed_bindings():
    reports = [fail(UNMET)] * 3 + [fail("rules: 90% met, below 95%; unmet: "
                                        "next_to(nightstand_2, bed)")] + [fail(BLOCKED)]
    line = dominant_cause(reports)
    assert line.startswith("80 % of samples fail 'rules' (miss next_to(nightstand_2, bed)")
    assert "at_wall(desk)" in line
    assert line.endswith("wardrobe and desk block the path to bed")


def test_other_checks_name_the_objects_they_quote():
    reports = [fail("collision: 'desk' and 'chair_1' overlap by 0.03 m²",
                    "collision: 'bed' and 'chair_1' overlap by 0.01 m²"),
               fail("collision: 'chair_1' and 'sofa' overlap by 0.2 m²"),
               fail("window: 'wardrobe' (2.00 m tall) stands in front of window 0 (sill 0.90 m)"),
               SampleReport(seed=3)]
    line = dominant_cause(reports)
    assert line == "50 % of samples fail 'collision' (most often chair_1)"


def test_a_missing_line_names_the_objects_missing_not_where_they_were_to_go():
    why = ("missing: mirror: no free stretch 0.6 m wide on walls [0] near 'shoe_cabinet' in "
           "the band 0.90..2.10 m (doors, windows and furniture block it)")
    reports = [fail(why), fail(why + "; lamp: does not fit on top of 'shoe_cabinet' in any "
                                     "orientation"), SampleReport(seed=3)]
    line = dominant_cause(reports)
    assert line == "67 % of samples fail 'missing' (most often mirror)"


def test_one_failure_line_counts_once_per_sample_and_odd_lines_do_not_crash():
    reports = [fail(BLOCKED, BLOCKED.replace("door 0", "door 1")),
               fail("error: RuntimeError: boom"),
               fail("no colon here"), fail(": empty check")]
    line = dominant_cause(reports)
    assert line.startswith("25 % of samples fail 'error' and 'other' and 'reachable' and "
                           "'unknown'")
    assert "wardrobe and desk block the path to bed" in line
    assert dominant_cause(iter([fail("reachable: 'bed' cannot be reached from door 0 "
                                     "(the walls leave no way through)")])) == (
        "100 % of samples fail 'reachable' (most often bed)")


def test_missed_rules_reads_the_rules_line_of_a_rejected_sample():
    failures = ["missing: lamp: its parent 'desk' was not placed",
                "rules: 60% met, below 95%; unmet: next_to(nightstand_2,bed), at_wall(desk), "
                "next_to(nightstand_2, bed)",
                "reachable: 'desk' cannot be reached (blocked by 'bed')"]
    assert missed_rules(failures) == ["next_to(nightstand_2, bed)", "at_wall(desk)"]
    assert missed_rules(["navigable: 20 % free"]) == []
