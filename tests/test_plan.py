"""The plan schema: loading, JSON round trip, JSON Schema and errors naming fields."""

import json
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcelayout import Plan, PlanError, load_plan
from forcelayout.examples import list_plans, load_example

DESIGN_PLAN = {
    "name": "bedroom",
    "room": {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]], "height": 2.7,
             "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}],
             "windows": [{"wall": 2, "offset": 2.0, "width": 1.2}]},
    "objects": [{"id": "bed", "category": "bed", "size": [1.6, 2.0, 0.5], "area": "sleeping",
                 "primary": True},
                {"id": "nightstand_1", "category": "nightstand", "size": [0.45, 0.4, 0.5]}],
    "rules": [{"rule": "at_wall", "object": "bed"},
              {"rule": "next_to", "object": "nightstand_1", "target": "bed"}],
}


def plan_with(**changes):
    data = json.loads(json.dumps(DESIGN_PLAN))
    for path, value in changes.items():
        node = data
        keys = path.split("__")
        for k in keys[:-1]:
            node = node[int(k)] if k.isdigit() else node[k]
        last = keys[-1]
        if last.isdigit():
            node[int(last)] = value
        else:
            node[last] = value
    return data


def problems(data):
    with pytest.raises(PlanError) as e:
        Plan.from_dict(data)
    return e.value.problems


def test_design_json_loads_unchanged():
    plan = Plan.from_json(json.dumps(DESIGN_PLAN))
    assert plan.object("bed").size == (1.6, 2.0, 0.5)
    assert plan.rules[1].target == "bed"
    assert plan.room.doors[0].width == 0.9


def test_json_round_trip():
    plan = Plan.from_dict(DESIGN_PLAN)
    again = Plan.from_json(plan.to_json())
    assert again == plan


def test_json_schema_is_usable_for_structured_output():
    schema = Plan.json_schema()
    assert schema["type"] == "object"
    assert {"room", "objects"} <= set(schema["required"])
    assert "SceneObject" in json.dumps(schema)


@pytest.mark.parametrize("name", list_plans())
def test_bundled_plans_load(name):
    plan = load_example(name)
    assert 8 <= len(plan.objects) <= 16
    assert load_plan(name) == plan


def test_unknown_rule_suggests_close_match():
    data = plan_with(rules__0__rule="at_wal")
    (p,) = problems(data)
    assert p.path == "rules[0] (at_wal)"
    assert "Did you mean 'at_wall'" in p.message


def test_unknown_object_suggests_close_match():
    data = plan_with(rules__1__target="bedd")
    (p,) = problems(data)
    assert p.path.endswith(".target")
    assert "unknown object 'bedd'" in p.message and "'bed'" in p.message


def test_an_alias_of_a_rule_names_the_rule_it_means():
    (p,) = problems(plan_with(rules__0__rule="beside"))
    assert "'beside' means 'next_to' here: write 'next_to'" in p.message


def test_an_unknown_object_with_no_close_match_lists_the_objects():
    (p,) = problems(plan_with(rules__1__target="cot"))
    assert "unknown object 'cot'. The plan's objects are 'bed'" in p.message


def test_an_unknown_object_sharing_only_a_word_is_not_taken_for_it():
    data = plan_with(rules__1__target="coffee_table")
    data["objects"][0]["id"] = "dining_table"
    data["rules"] = [r for r in data["rules"] if "bed" not in (r["object"], r.get("target"))]
    data["rules"].append({"rule": "next_to", "object": "dining_table", "target": "coffee_table"})
    found = [p.message for p in problems(data) if "coffee_table" in p.message]
    assert found and all("Did you mean" not in m and "The plan's objects are" in m
                         for m in found)


def test_a_window_or_door_as_a_target_names_the_rule_meant():
    """A window or a door is the room's: ``near`` the window is ``near_window``."""
    (p,) = problems(plan_with(rules__1__target="window"))
    assert p.path.endswith(".target")
    assert 'A window is part of the room (room.windows), not an object: use {"rule": ' \
           '"near_window", "object": "nightstand_1"} with no target.' in p.message
    data = plan_with(rules__1__target="door_0")
    data["rules"][1]["rule"] = "above"
    (p,) = problems(data)
    assert "A door is part of the room (room.doors), not an object; the rules about " \
           "doors: away_from_door, near_door." in p.message
    # an object with a close name is what a misspelt target means
    data = plan_with(rules__1__target="window_sea")
    data["objects"].append({"id": "window_seat", "category": "bench", "size": [1.0, 0.5, 0.45]})
    (p,) = problems(data)
    assert "Did you mean 'window_seat'?" in p.message


def test_an_unknown_object_as_close_to_two_ids_names_both():
    data = {"name": "beds", "room": {"polygon": [[0, 0], [4, 0], [4, 4], [0, 4]]},
            "objects": [{"id": i, "category": "nightstand", "size": [0.45, 0.4, 0.55]}
                        for i in ("nightstand_r", "nightstand_l")],
            "rules": [{"rule": "at_wall", "object": "nightstand_1"}]}
    (p,) = problems(data)
    assert p.message == ("unknown object 'nightstand_1'. Did you mean 'nightstand_l' or "
                         "'nightstand_r'?")


def test_all_problems_reported_at_once():
    data = plan_with(rules__0__rule="nope", rules__1__object="ghost")
    data["room"]["doors"][0]["wall"] = 9
    ps = problems(data)
    assert len(ps) == 3
    assert {p.path.split(".")[0].split(" ")[0] for p in ps} >= {"room", "rules[0]", "rules[1]"}


def test_object_larger_than_room():
    data = plan_with(objects__0__size=[4.5, 0.5, 0.5])
    (p,) = problems(data)
    assert p.path == "objects[0].size" and "larger than the room" in p.message


def test_a_crowded_floor_names_its_largest_objects():
    """Floor objects over 60 % of the floor: the message names the largest footprints, the
    ones to shrink (a new user's oversized table was not named)."""
    data = plan_with(objects__0__size=[3.0, 2.8, 0.5])  # 8.4 of 14 m², the nightstand 0.18
    (p,) = problems(data)
    assert p.path == "objects" and "enlarge the room (the largest: 'bed' 8.4 m², " \
        "'nightstand_1' 0.2 m²)" in p.message


def test_non_simple_polygon():
    data = plan_with(room__polygon=[[0, 0], [4, 3.5], [4, 0], [0, 3.5]])
    (p,) = problems(data)
    assert p.path == "room.polygon" and "simple" in p.message
    assert "walls 0 and 2 cross" in p.message


@pytest.mark.parametrize("polygon, says", [
    # the first corner again at the end: wall 3 would have no length (0 layouts before)
    ([[0, 0], [4, 0], [4, 3.5], [0, 3.5], [0, 0]], "corners 4 and 0 are the same point"),
    ([[0, 0], [4, 0], [4, 0], [4, 3.5], [0, 3.5]], "corners 1 and 2 are the same point"),
    ([[0, 0], [4, 0], [2, 0], [2, 3.5]], "walls 0 and 1 run back over each other"),
])
def test_a_polygon_that_is_not_simple_says_where(polygon, says):
    (p,) = problems(plan_with(room__polygon=polygon))
    assert p.path == "room.polygon" and says in p.message


@pytest.mark.parametrize("bad", [float("nan"), -1.0, 0.0, float("inf")])
def test_bad_sizes_name_the_field(bad):
    data = plan_with(objects__1__size=[bad, 0.4, 0.5])
    ps = problems(data)
    assert any(p.path.startswith("objects[1].size") for p in ps)


def test_door_wider_than_wall():
    data = plan_with(room__doors=[{"wall": 1, "offset": 1.0, "width": 4.0}])
    (p,) = problems(data)
    assert p.path == "room.doors[0].width"


def test_opening_off_the_wall():
    data = plan_with(room__doors=[{"wall": 1, "offset": 3.4, "width": 0.9}])
    (p,) = problems(data)
    assert p.path == "room.doors[0].offset"


def test_openings_that_overlap_on_a_wall():
    # two doors sharing a stretch of wall 0; a window over the first reaching below its top
    data = plan_with(room__doors=[{"wall": 0, "offset": 1.0, "width": 0.9},
                                  {"wall": 0, "offset": 1.6, "width": 0.9}],
                     room__windows=[{"wall": 0, "offset": 1.0, "width": 0.6, "sill": 1.5,
                                     "height": 0.5}])
    ps = problems(data)
    assert [p.path for p in ps] == ["room.doors[1].offset", "room.windows[0].offset"]
    assert "overlaps room.doors[0] on wall 0" in ps[0].message
    # side by side, or a window above a door's top, is fine
    Plan.from_dict(plan_with(
        room__doors=[{"wall": 0, "offset": 0.6, "width": 0.9},
                     {"wall": 0, "offset": 1.6, "width": 0.9}],
        room__windows=[{"wall": 0, "offset": 0.6, "width": 0.6, "sill": 2.1, "height": 0.4}]))


def test_on_top_cycle():
    data = plan_with()
    data["objects"].append({"id": "lamp", "category": "lamp", "size": [0.2, 0.2, 0.3]})
    data["rules"] += [{"rule": "on_top", "object": "lamp", "target": "nightstand_1"},
                      {"rule": "on_top", "object": "nightstand_1", "target": "lamp"}]
    ps = problems(data)
    assert any("cycle" in p.message for p in ps)


def test_child_larger_than_parent_top():
    data = plan_with()
    data["rules"].append({"rule": "on_top", "object": "bed", "target": "nightstand_1"})
    ps = problems(data)
    assert any("does not fit on top" in p.message for p in ps)


def test_binary_rule_needs_target():
    data = plan_with()
    data["rules"][1].pop("target")
    (p,) = problems(data)
    assert p.path.endswith(".target") and "give a target" in p.message


def test_bad_params_name_the_param():
    data = plan_with()
    data["rules"][1]["params"] = {"distanse": 0.2}
    (p,) = problems(data)
    assert "params.distanse" in p.path
    # the fix, in the library's words rather than the validator's
    assert "has no parameter 'distanse'. Did you mean 'distance'? It takes [" in p.message
    assert "Extra inputs" not in p.message


@pytest.mark.parametrize("given, says", [
    ("0.2m", "'0.2m' is not a number; write it without its unit: 0.2 (lengths are in metres"),
    ("20 cm", "'20 cm' is not a number; write it without its unit: 0.2 (lengths"),
    ("near", "'near' is not a number; give one, without quotes"),
])
def test_a_number_written_with_its_unit_says_to_drop_the_unit(given, says):
    """A parameter or size written as text with its unit gets the fix, not the validator's
    "unable to parse string as a number" (a new user's "0.2m")."""
    data = plan_with()
    data["rules"][1]["params"] = {"distance": given}
    (p,) = problems(data)
    assert p.path.endswith("params.distance") and says in p.message
    assert "unable to parse" not in p.message
    data = plan_with()
    data["objects"][0]["size"][0] = given
    (p,) = problems(data)
    assert p.path.endswith("size[0]") and says in p.message


def test_unknown_field_is_rejected():
    data = plan_with()
    data["objects"][0]["colour"] = "red"
    (p,) = problems(data)
    assert p.path == "objects[0].colour"


@pytest.mark.parametrize("where, typo, meant", [
    (("rules", 1), "taget", "target"), (("objects", 0), "sise", "size"),
    (("room",), "windws", "windows"), (("room", "doors", 0), "widht", "width"),
])
def test_a_misspelled_field_suggests_the_field_it_is_close_to(where, typo, meant):
    data = plan_with()
    node = data
    for k in where:
        node = node[k]
    node[typo] = node.pop(meant, 1)
    found = [p for p in problems(data) if p.path.endswith(typo)]
    assert len(found) == 1 and f"Did you mean {meant!r}?" in found[0].message


def test_too_much_furniture_fails_fast():
    data = plan_with()
    data["objects"] += [{"id": f"box_{k}", "category": "box", "size": [1.0, 1.0, 1.0]}
                        for k in range(12)]
    ps = problems(data)
    assert any(p.path == "objects" and "walk" in p.message for p in ps)


def test_l_shaped_room_loads():
    data = plan_with(room__polygon=[[0, 0], [6, 0], [6, 3], [3, 3], [3, 5], [0, 5]])
    plan = Plan.from_dict(data)
    assert math.isclose(plan.room.shape.area, 24.0)


@settings(max_examples=60, deadline=None)
@given(st.recursive(st.none() | st.booleans() | st.floats() | st.text(max_size=5),
                    lambda c: st.lists(c, max_size=3) | st.dictionaries(st.text(max_size=5), c,
                                                                        max_size=3),
                    max_leaves=10))
def test_random_json_never_crashes(data):
    """Any JSON value either loads or raises PlanError, nothing else."""
    try:
        Plan.from_dict(data if isinstance(data, dict) else {"objects": data})
    except PlanError as e:
        assert e.problems


def with_object(extra: dict) -> dict:
    data = plan_with()
    data["objects"].append(extra)
    return data


@pytest.mark.parametrize("category", ["rug", "Rug", "area rug", "bath_mat", "DOORMAT", "runner",
                                      "carpet", "yoga-mat", "rugs"])
def test_floor_covers_are_walkable_by_default(category):
    data = with_object({"id": "cover", "category": category, "size": [1.6, 1.2, 0.02]})
    assert Plan.from_dict(data).object("cover").is_walkable
    tall = with_object({"id": "cover", "category": category, "size": [1.6, 1.2, 0.3]})
    assert Plan.from_dict(tall).object("cover").is_walkable  # by category, whatever its height


@pytest.mark.parametrize("category", ["mattress", "format_shelf", "bed"])
def test_other_categories_are_not_walkable(category):
    data = with_object({"id": "thing", "category": category, "size": [0.5, 0.5, 0.4]})
    assert not Plan.from_dict(data).object("thing").is_walkable


def test_anything_at_most_5_cm_high_is_walkable_and_the_field_overrides_the_default():
    flat = with_object({"id": "tile", "category": "play_tile", "size": [0.5, 0.5, 0.05]})
    assert Plan.from_dict(flat).object("tile").is_walkable
    raised = with_object({"id": "tile", "category": "play_tile", "size": [0.5, 0.5, 0.06]})
    assert not Plan.from_dict(raised).object("tile").is_walkable
    solid_rug = with_object({"id": "rug", "category": "rug", "size": [2, 1.4, 0.01],
                             "walkable": False})
    assert not Plan.from_dict(solid_rug).object("rug").is_walkable
    stage = with_object({"id": "stage", "category": "platform", "size": [2, 1, 0.2],
                         "walkable": True})
    plan = Plan.from_dict(stage)
    assert plan.object("stage").is_walkable
    assert Plan.from_json(plan.to_json()).object("stage").walkable is True
    assert Plan.from_dict(DESIGN_PLAN).object("bed").walkable is None


def test_window_clearance_defaults_and_must_not_be_negative():
    plan = Plan.from_dict(DESIGN_PLAN)
    assert plan.room.windows[0].clearance == 0.5
    data = plan_with(room__windows__0={"wall": 2, "offset": 2.0, "width": 1.2, "clearance": 0.0})
    assert Plan.from_dict(data).room.windows[0].clearance == 0.0
    bad = plan_with(room__windows__0={"wall": 2, "offset": 2.0, "width": 1.2, "clearance": -0.1})
    with pytest.raises(PlanError, match=r"room\.windows\[0\]\.clearance"):
        Plan.from_dict(bad)
    schema = json.dumps(Plan.json_schema())
    assert "clearance" in schema and "walkable" in schema


def test_a_rule_binding_is_labelled_as_reports_name_it():
    from forcelayout.plan import RuleSpec

    assert RuleSpec(rule="near", object="sofa", target="tv").label == "near(sofa, tv)"
    assert RuleSpec(rule="at_wall", object="bed").label == "at_wall(bed)"
    layout = __import__("forcelayout").generate("bedroom", 1, seed=0)[0]
    assert all(r.label == layout.plan.rules[r.index].label for r in layout.rule_report())


@pytest.mark.parametrize("size", [[1.4, 2.0], [1.4, 2.0, 0.5, 1.0], "1.4 x 2.0"])
def test_a_size_of_the_wrong_shape_says_what_a_size_is(size):
    data = with_object({"id": "bed2", "category": "bed", "size": size})
    k = len(data["objects"]) - 1
    with pytest.raises(PlanError, match=rf"objects\[{k}\]\.size.*\[width, depth, height\]"):
        Plan.from_dict(data)


@pytest.mark.parametrize("access, says", [
    ({"sides": ["frontt"]}, "objects[0].access: sides.0: Input should be 'front'"),
    ("front", "got 'front'"),
    ({"sides": ["fronts"], "depth": -1}, "access: 2 mistakes in it: sides.0: Input should be"),
])
def test_a_bad_access_is_one_problem_that_shows_its_shape(access, says):
    data = plan_with(objects__0__access=access)
    (p,) = problems(data)
    assert p.path == "objects[0].access" and says in f"{p.path}: {p.message}"
    assert '{"sides": ["front", ...], "depth": metres}' in p.message


def test_access_true_is_the_category_default():
    plan = Plan.model_validate(plan_with(objects__0__access=True))
    assert plan.objects[0].access is None


def test_a_room_in_centimetres_is_named_as_such():
    """A room and its objects all in centimetres fit one another: the room's own size says
    it (it had passed ``validate`` and failed in the free-space grid, asking for a coarser
    grid)."""
    data = {"name": "cm", "room": {"polygon": [[0, 0], [340, 0], [340, 380], [0, 380]],
                                   "height": 260},
            "objects": [{"id": "desk", "category": "desk", "size": [120, 60, 75]}]}
    with pytest.raises(PlanError) as err:
        Plan.from_dict(data)
    assert "room.polygon: the room is 340 x 380 m" in str(err.value)
    assert "divide them by 100 or 1000" in str(err.value)
    data["room"]["polygon"] = [[0, 0], [60, 0], [60, 40], [0, 40]]  # a hall: no finding
    data["room"]["height"], data["objects"][0]["size"] = 6, [1.2, 0.6, 0.75]
    Plan.from_dict(data)


def test_sizes_in_millimetres_are_named_as_such():
    data = {"name": "mm", "room": {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]]},
            "objects": [{"id": "bed", "category": "bed", "size": [900, 1900, 450]},
                        {"id": "desk", "category": "desk", "size": [1.2, 0.6, 0.75]}]}
    with pytest.raises(PlanError) as err:
        Plan.from_dict(data)
    lines = [p for p in str(err.value).splitlines() if "objects[0].size" in p]
    assert lines and all("looks like centimetres or millimetres" in p for p in lines)
    assert "objects[1]" not in str(err.value)


def test_text_that_is_not_json_says_where_and_shows_the_line():
    text = '{"name": "x",\n "room": {"polygon": [[0, 0], [3, 0], [3, 3]], "height": 2.5,,\n}'
    with pytest.raises(PlanError) as e:
        Plan.from_json(text)
    (p,) = e.value.problems
    assert p.path == "line 2, column 62"
    assert p.message.startswith("not valid JSON: Expecting property name enclosed in double "
                                "quotes (a doubled or trailing comma")
    assert p.message.endswith('the line reads: "room": {"polygon": [[0, 0], [3, 0], [3, 3]], '
                              '"height": 2.5,,')


def test_json_on_one_long_line_shows_the_text_where_it_fails():
    text = '{"name": "x", "description": "' + "a" * 200 + '", "room": {"polygon": "open'
    with pytest.raises(PlanError) as e:
        Plan.from_json(text)
    (p,) = e.value.problems
    column = text.index('"open') + 1
    assert p.path == f"line 1, column {column}"
    assert f"Unterminated string starting at line 1, column {column} (" in p.message
    shown = p.message.split("the line reads: ")[1]
    assert shown.startswith("...") and '"polygon": "open' in shown  # not the line's start


@pytest.mark.parametrize("data", [[], [{"name": "x"}], "a plan", 3])
def test_a_plan_that_is_not_one_object_says_so(data):
    with pytest.raises(PlanError) as e:
        Plan.from_json(json.dumps(data))
    (p,) = e.value.problems
    assert p.message.startswith("a plan is one JSON object (with room, objects and rules), "
                                f"not a {type(data).__name__}")


@pytest.mark.parametrize("text", ["{\n", '{"name": "x",\n\n', "", "   "])
def test_json_cut_short_or_empty_says_the_text_ends_there(text):
    with pytest.raises(PlanError) as e:
        Plan.from_json(text)
    (p,) = e.value.problems
    assert p.path.startswith("line ") and p.message.startswith("not valid JSON: ")
    assert p.message.endswith("the text ends there")
