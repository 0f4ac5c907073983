"""Unary rules: force direction, torque sign, satisfied checks, and end to end.

Room used throughout: 4 x 3.5 m, wall 0 along y = 0 (door centred at (1, 0)),
wall 1 along x = 4, wall 2 along y = 3.5 (window centred at (2, 3.5)), wall 3
along x = 0.
"""

import numpy as np
import pytest

import forcelayout as fl
from forcelayout.sampling import solve
from forcelayout.testing import bind, make_state

NO_OPENINGS = {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]]}
L_ROOM = {"polygon": [[0, 0], [6, 0], [6, 3], [3.5, 3], [3.5, 5], [0, 5]],
          "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}]}


def run(name, pos, yaw, size, *, room=None, **params):
    st = make_state(pos, yaw, size, room=room)
    rule, p = bind(name, len(st.ids), **params)
    i = np.arange(len(st.ids))
    f, tau = rule.force(st, i, None, p)
    return f, tau, rule.satisfied(st, i, None, p), p.weight


# -- at_wall ---------------------------------------------------------------------------


def test_at_wall_pulls_to_the_nearest_wall_and_is_met_there():
    f, _, ok, _ = run("at_wall", [[2.0, 1.0]], [0.0], [[1.0, 0.5]])
    assert f[0, 1] < 0 and not ok[0]
    _, _, ok, _ = run("at_wall", [[2.0, 0.29]], [0.0], [[1.0, 0.5]])  # 4 cm off the wall
    assert ok[0]
    f, tau, ok, w = run("at_wall", [[2.0, 0.252]], [0.0], [[1.0, 0.5]])  # touching it
    assert ok[0]
    assert np.hypot(*f[0]) <= 0.5 * w[0] and abs(tau[0]) < 1e-9
    _, _, ok, _ = run("at_wall", [[2.0, 0.31]], [0.0], [[1.0, 0.5]])  # 6 cm off
    assert not ok[0]


def test_at_wall_turns_its_back_to_the_wall():
    _, tau, ok, _ = run("at_wall", [[2.0, 0.6]], [0.3], [[1.0, 0.5]])
    assert tau[0] < 0 and not ok[0]
    _, tau, _, _ = run("at_wall", [[2.0, 0.6]], [-0.3], [[1.0, 0.5]])
    assert tau[0] > 0


def test_at_wall_needs_the_front_facing_into_the_room():
    _, _, ok, _ = run("at_wall", [[2.0, 0.27]], [np.pi], [[1.0, 0.5]])
    assert not ok[0]
    # at the right wall (x = 4): back to it means front faces -x, i.e. yaw = +90 deg
    _, _, ok, _ = run("at_wall", [[3.73, 1.5]], [np.pi / 2], [[1.0, 0.5]])
    assert ok[0]
    _, _, ok, _ = run("at_wall", [[3.73, 1.5]], [np.pi / 2 + np.radians(15)], [[1.0, 0.5]])
    assert not ok[0]  # 15 deg off parallel > 10 deg
    _, _, ok, _ = run("at_wall", [[3.73, 1.5]], [np.pi / 2 + np.radians(15)], [[1.0, 0.5]],
                      max_angle=20.0, tolerance=0.2)
    assert ok[0]


# -- in_corner --------------------------------------------------------------------------


def test_in_corner_pulls_into_the_nearest_corner():
    f, _, ok, _ = run("in_corner", [[0.6, 2.9]], [0.0], [[0.5, 0.5]])
    assert f[0, 0] < 0 and f[0, 1] > 0 and not ok[0]


def test_in_corner_is_met_against_two_walls_in_any_orientation():
    _, _, ok, _ = run("in_corner", [[0.26, 3.24], [3.68, 0.22]], [0.0, np.pi / 2],
                      [[0.5, 0.5], [0.4, 0.6]])
    assert ok.all()
    _, _, ok, _ = run("in_corner", [[0.26, 2.0]], [0.0], [[0.5, 0.5]])
    assert not ok[0]  # at one wall only


def test_in_corner_squares_up():
    _, tau, _, _ = run("in_corner", [[0.3, 3.2]], [0.2], [[0.5, 0.5]])
    assert tau[0] < 0


def test_in_corner_skips_the_reflex_corner_of_an_l_room():
    # nearest vertex is the inner (reflex) corner (3.5, 3); it is not a corner to sit in
    f, _, _, _ = run("in_corner", [[3.3, 3.3]], [0.0], [[0.3, 0.3]], room=L_ROOM)
    assert np.all(np.isfinite(f))
    _, _, ok, _ = run("in_corner", [[3.3, 3.2]], [0.0], [[0.3, 0.3]], room=L_ROOM)
    assert not ok[0]


# -- in_middle ---------------------------------------------------------------------------


def test_in_middle_pulls_towards_the_centroid():
    f, _, ok, _ = run("in_middle", [[0.5, 0.5]], [0.0], [[0.6, 0.6]])
    assert f[0, 0] > 0 and f[0, 1] > 0 and not ok[0]


def test_in_middle_check_is_per_axis_within_a_quarter_of_the_extent():
    _, _, ok, _ = run("in_middle", [[2.1, 1.8], [3.5, 1.75], [2.0, 2.7]], [0, 0, 0],
                      [[0.6, 0.6]] * 3)
    assert ok.tolist() == [True, False, False]  # |dy| = 0.95 > 0.875


# -- near_window / near_door / away_from_door ----------------------------------------------


def test_near_window_pulls_towards_the_window():
    f, _, ok, _ = run("near_window", [[2.0, 0.5]], [0.0], [[0.6, 0.6]])
    assert f[0, 1] > 0 and abs(f[0, 0]) < 1e-9 and not ok[0]
    f, _, ok, w = run("near_window", [[2.5, 2.6]], [0.0], [[0.6, 0.6]])
    assert ok[0] and np.hypot(*f[0]) <= 0.5 * w[0]


def test_near_window_without_windows_is_unmet_and_still():
    f, _, ok, _ = run("near_window", [[2.0, 3.0]], [0.0], [[0.6, 0.6]], room=NO_OPENINGS)
    assert not ok[0] and np.all(f == 0)


def test_near_door_pulls_towards_the_door():
    f, _, ok, _ = run("near_door", [[3.5, 3.0]], [0.0], [[0.6, 0.6]])
    assert f[0, 0] < 0 and f[0, 1] < 0 and not ok[0]
    _, _, ok, _ = run("near_door", [[1.3, 1.0]], [0.0], [[0.6, 0.6]], distance=1.5)
    assert ok[0]


TWO_DOORS = {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]],
             "doors": [{"wall": 0, "offset": 1.0}, {"wall": 2, "offset": 3.0}]}


def test_near_door_with_a_door_index_means_that_door_only():
    # beside door 1 (top wall, centre (1, 3.5)); door 0 is at (1, 0)
    pos, size = [[1.2, 3.0], [1.2, 0.5]], [[0.6, 0.6]] * 2
    _, _, ok, _ = run("near_door", pos, [0.0, 0.0], size, room=TWO_DOORS)
    assert ok.tolist() == [True, True]  # the nearest door: either
    f, _, ok, _ = run("near_door", pos, [0.0, 0.0], size, room=TWO_DOORS, door=1)
    assert ok.tolist() == [True, False]
    assert f[1, 1] > 0  # pulled past the nearer door 0 towards door 1
    _, _, ok, _ = run("near_door", pos, [0.0, 0.0], size, room=TWO_DOORS, door=0)
    assert ok.tolist() == [False, True]


def test_a_door_index_the_room_has_not_is_refused_naming_the_field():
    plan = {"name": "hall", "room": TWO_DOORS,
            "objects": [{"id": "cabinet", "category": "shoe_cabinet", "size": [0.8, 0.35, 1.0]}],
            "rules": [{"rule": "near_door", "object": "cabinet", "params": {"door": 2}},
                      {"rule": "near_window", "object": "cabinet", "params": {"window": 0}}]}
    with pytest.raises(fl.PlanError) as info:
        fl.Plan.from_dict(plan)
    text = str(info.value)
    assert "rules[0] (near_door).params.door: there is no door 2" in text
    assert "index 0, 1" in text
    assert "rules[1] (near_window).params.window: there is no window 0" in text


def test_away_from_door_pushes_away_from_the_door():
    f, _, ok, _ = run("away_from_door", [[1.2, 0.8]], [0.0], [[0.6, 0.6]])
    assert f[0, 1] > 0 and not ok[0]
    f, _, ok, _ = run("away_from_door", [[3.5, 3.0]], [0.0], [[0.6, 0.6]])
    assert ok[0] and np.all(f == 0)
    _, _, ok, _ = run("away_from_door", [[1.0, 0.5]], [0.0], [[0.6, 0.6]], room=NO_OPENINGS)
    assert ok[0]


def test_away_from_window_slides_out_of_the_zone_in_front_of_it():
    # the window is 1.2 m wide, centred at (2, 3.5) on the top wall: its zone is x 1.4..2.6,
    # y 3.0..3.5; a low stand against that wall, a little right of the window's centre
    f, tau, ok, _ = run("away_from_window", [[2.2, 3.3]], [np.pi], [[1.0, 0.4]])
    assert not ok[0] and f[0, 0] > 0 and f[0, 1] == pytest.approx(0.0) and tau[0] == 0.0
    f, _, ok, _ = run("away_from_window", [[1.7, 3.3]], [np.pi], [[1.0, 0.4]])
    assert not ok[0] and f[0, 0] < 0  # left of the centre: out by the left end
    _, _, ok, _ = run("away_from_window", [[3.2, 3.3]], [np.pi], [[1.0, 0.4]])  # beside it
    assert ok[0]
    _, _, ok, _ = run("away_from_window", [[2.0, 2.7]], [np.pi], [[1.0, 0.4]])  # 0.6 m off
    assert ok[0]
    _, _, ok, _ = run("away_from_window", [[2.0, 2.7]], [np.pi], [[1.0, 0.4]], distance=0.9)
    assert not ok[0]
    _, _, ok, _ = run("away_from_window", [[2.0, 3.3]], [np.pi], [[1.0, 0.4]],
                      room=NO_OPENINGS)
    assert ok[0]


def test_unary_forces_are_clipped():
    for name in ["at_wall", "in_corner", "in_middle", "near_window", "near_door",
                 "away_from_door", "away_from_window"]:
        f, tau, _, w = run(name, [[-50.0, 80.0], [1.0, 0.0]], [3.0, 0.0], [[0.6, 0.6]] * 2)
        assert np.all(np.isfinite(f)) and np.all(np.isfinite(tau))
        assert np.all(np.hypot(f[:, 0], f[:, 1]) <= 3.0 * w), name


def test_placement_rules_outweigh_soft_relations():
    from forcelayout.rules import get_rule

    hard = min(get_rule(n).weight for n in ["at_wall", "in_corner"])
    soft = max(get_rule(n).weight for n in ["near", "far_from", "face_same_as"])
    assert hard > soft


# -- end to end through the public API ------------------------------------------------------

ROOM = {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]], "height": 2.7,
        "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}],
        "windows": [{"wall": 2, "offset": 2.0, "width": 1.2}]}
OBJECTS = [{"id": "table", "category": "table", "size": [1.2, 0.8, 0.75]},
           {"id": "chair", "category": "chair", "size": [0.5, 0.5, 0.9]},
           {"id": "shelf", "category": "shelf", "size": [0.8, 0.35, 1.8]}]
CASES = {"at_wall": "shelf", "in_corner": "shelf", "in_middle": "table",
         "near_window": "chair", "near_door": "shelf", "away_from_door": "table",
         "away_from_window": "shelf"}


@pytest.mark.parametrize("name", sorted(CASES))
def test_rule_is_met_in_most_solved_layouts(name):
    plan = fl.Plan.from_dict({"name": name, "room": ROOM, "objects": OBJECTS,
                              "rules": [{"rule": name, "object": CASES[name]}]})
    met = [solve(plan, seed, check=False).rule_report()[0].satisfied for seed in range(3)]
    assert sum(met) >= 2, met


def test_at_wall_in_an_l_shaped_room():
    plan = fl.Plan.from_dict({"name": "l", "room": L_ROOM, "objects": OBJECTS,
                              "rules": [{"rule": "at_wall", "object": o} for o in
                                        ("shelf", "table")]})
    met = [r.satisfied for seed in range(2)
           for r in solve(plan, seed, check=False).rule_report()]
    assert sum(met) >= 3, met


def test_docs_table_lists_every_floor_rule_with_its_defaults():
    from pathlib import Path

    from forcelayout.rules import describe_rules

    text = (Path(__file__).parent.parent / "docs" / "rules.md").read_text(encoding="utf-8")
    rows = {line.split("|")[1].strip(" `"): line for line in text.splitlines()
            if line.startswith("| `")}
    for info in describe_rules():
        if info.kind == "surface" or info.name not in {*CASES, "next_to", "near", "far_from",
                                                        "facing", "face_same_as", "in_front_of",
                                                        "behind", "left_of", "right_of",
                                                        "aligned_with", "around"}:
            continue
        row = rows[info.name]
        assert f"| {info.weight:g} |" in row, info.name
        for k, v in info.params.items():
            assert f"`{k}` = {v['default']:g}" in row, (info.name, k)
