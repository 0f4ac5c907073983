"""Properties of forcelayout.metrics: zero for identical, one for disjoint, symmetry, hand cases."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from forcelayout import Layout, Plan, Pose
from forcelayout import metrics as M
from forcelayout import rules as registry
from forcelayout.baselines import random_layout

ROOM = {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]], "height": 2.7,
        "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}],
        "windows": [{"wall": 2, "offset": 2.0, "width": 1.0}]}
DIAG = math.sqrt(4**2 + 3**2 + 2.7**2)


def make_plan(objects: list[tuple[str, str, list[float]]], name: str = "t") -> Plan:
    return Plan.model_validate({
        "name": name, "room": ROOM,
        "objects": [{"id": i, "category": c, "size": s} for i, c, s in objects],
    })


@pytest.fixture(scope="module")
def bedroom() -> Plan:
    return make_plan([("bed", "bed", [1.4, 2.0, 0.5]), ("ns_1", "nightstand", [0.4, 0.4, 0.5]),
                      ("ns_2", "Bedside_Table", [0.4, 0.4, 0.5]),
                      ("chair", "chair", [0.5, 0.5, 0.9]), ("lamp", "lamp", [0.2, 0.2, 0.3])])


def bedroom_layout(plan: Plan) -> Layout:
    return Layout(plan, {"bed": Pose(2.0, 2.0, math.pi), "ns_1": Pose(1.05, 2.75, math.pi),
                         "ns_2": Pose(2.95, 2.75, math.pi), "chair": Pose(3.2, 0.6, 0.0),
                         "lamp": Pose(1.05, 2.75, 0.0, 0.5, "ns_1")})


def moved(layout: Layout, **changes: Pose) -> Layout:
    return Layout(layout.plan, {**layout.poses, **changes})


# -- labels -------------------------------------------------------------------------

@pytest.mark.parametrize(("label", "expected"), [
    ("couch", "sofa"), ("Sofa_2", "sofa"), ("settee", "sofa"), ("bedside table", "nightstand"),
    ("Bedside_Table", "nightstand"), ("nightstand_1", "nightstand"), ("couches", "sofa"),
    ("desk", "desk"),
])
def test_canonical_label(label: str, expected: str) -> None:
    assert M.canonical_label(label) == expected
    assert M.canonical_label(M.canonical_label(label)) == expected


# -- geometric ----------------------------------------------------------------------

def test_geometric_identical_is_zero(bedroom: Plan) -> None:
    a = bedroom_layout(bedroom)
    assert M.geometric_dissimilarity(a, a) == 0.0


def test_geometric_ignores_ids_within_a_category(bedroom: Plan) -> None:
    a = bedroom_layout(bedroom)
    # the two nightstands (two labels, one canonical category) swap places
    b = moved(a, ns_1=a.poses["ns_2"], ns_2=a.poses["ns_1"])
    assert M.geometric_dissimilarity(a, b) == pytest.approx(0.0)
    # taken literally, the labels differ: each nightstand moved 1.9 m (2 of 5 objects)
    assert M.geometric_dissimilarity(a, b, canonical=str) == pytest.approx(2 * 0.5 * 1.9 / DIAG / 5)


def test_geometric_known_move_and_turn(bedroom: Plan) -> None:
    a = bedroom_layout(bedroom)
    b = moved(a, chair=Pose(2.2, 0.6, 0.0))  # 1 m along x
    assert M.geometric_dissimilarity(a, b) == pytest.approx(0.5 * 1.0 / DIAG / 5)
    c = moved(a, chair=Pose(3.2, 0.6, math.pi / 2))  # quarter turn
    assert M.geometric_dissimilarity(a, c) == pytest.approx(0.25 * 0.5 / 5)
    d = moved(a, chair=Pose(3.2, 0.6, math.pi))  # half turn: same for a 180°-symmetric period
    assert M.geometric_dissimilarity(a, d) == pytest.approx(0.25 / 5)
    assert M.geometric_dissimilarity(a, d, yaw_period=math.pi) == pytest.approx(0.0, abs=1e-12)


def test_geometric_unmatched_penalty() -> None:
    two = make_plan([("c1", "chair", [0.5, 0.5, 0.9]), ("c2", "chair", [0.5, 0.5, 0.9])])
    one = make_plan([("c1", "chair", [0.5, 0.5, 0.9])])
    a = Layout(two, {"c1": Pose(1, 1, 0), "c2": Pose(3, 2, 0)})
    b = Layout(one, {"c1": Pose(3, 2, 0)})
    # c2 matches exactly, c1 has no partner: (0 + 1) / 2
    assert M.geometric_dissimilarity(a, b) == pytest.approx(0.5)
    assert M.geometric_dissimilarity(a, b, unmatched_cost=0.4) == pytest.approx(0.2)


def test_geometric_disjoint_categories_is_one(bedroom: Plan) -> None:
    other = make_plan([("s", "sofa", [2.0, 0.9, 0.8]), ("t", "tv", [1.0, 0.1, 0.6])])
    a = bedroom_layout(bedroom)
    b = Layout(other, {"s": Pose(2, 1, 0), "t": Pose(2, 2.9, math.pi)})
    assert M.geometric_dissimilarity(a, b) == 1.0


def test_geometric_synonyms_match() -> None:
    p1 = make_plan([("s", "couch", [2.0, 0.9, 0.8])])
    p2 = make_plan([("s", "sofa", [2.0, 0.9, 0.8])])
    a, b = Layout(p1, {"s": Pose(2, 1, 0)}), Layout(p2, {"s": Pose(2, 1, 0)})
    assert M.geometric_dissimilarity(a, b) == 0.0
    assert M.geometric_dissimilarity(a, b, canonical=str) == 1.0


def test_geometric_size_term() -> None:
    p1 = make_plan([("t", "table", [1.0, 1.0, 0.5])])
    p2 = make_plan([("t", "table", [2.0, 1.0, 0.5])])
    a, b = Layout(p1, {"t": Pose(2, 1.5, 0)}), Layout(p2, {"t": Pose(2, 1.5, 0)})
    expected = 0.25 * 1.0 / math.sqrt(2.0**2 + 1 + 0.25)
    assert M.geometric_dissimilarity(a, b) == pytest.approx(expected)


def test_geometric_rejects_bad_weights(bedroom: Plan) -> None:
    a = bedroom_layout(bedroom)
    with pytest.raises(ValueError, match="position_weight"):
        M.geometric_dissimilarity(a, a, position_weight=-1)
    with pytest.raises(ValueError, match="unmatched_cost"):
        M.geometric_dissimilarity(a, a, unmatched_cost=2)


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**31), st.integers(0, 2**31))
def test_dissimilarities_symmetric_and_bounded(s1: int, s2: int) -> None:
    plan = make_plan([("bed", "bed", [1.4, 2.0, 0.5]), ("c1", "chair", [0.5, 0.5, 0.9]),
                      ("c2", "chair", [0.5, 0.5, 0.9]), ("desk", "desk", [1.2, 0.6, 0.75])])
    a, b = random_layout(plan, s1), random_layout(plan, s2)
    for fn in (M.geometric_dissimilarity, M.topological_dissimilarity,
               M.relational_dissimilarity):
        d = fn(a, b)
        assert 0.0 <= d <= 1.0
        assert d == pytest.approx(fn(b, a), abs=1e-12)
        assert fn(a, a) == 0.0


# -- topological --------------------------------------------------------------------

def boxes(xs: list[float]) -> Layout:
    plan = make_plan([(f"b{k}", "box", [1.0, 1.0, 1.0]) for k in range(len(xs))])
    return Layout(plan, {f"b{k}": Pose(x, 1.5, 0.0) for k, x in enumerate(xs)})


def test_topological_known_overlap() -> None:
    a, b = boxes([1.5]), boxes([2.0])  # [1, 2] and [1.5, 2.5] along x: overlap 1/3 of the union
    assert M.topological_dissimilarity(a, b, agent_radius=0.0) == pytest.approx(2 / 3)
    # inflated: 1.4 x 1.4 squares with rounded corners overlapping by 0.9 m along x
    d = M.topological_dissimilarity(a, b)
    assert 0.3 < d < 2 / 3


def test_topological_identical_disjoint_empty() -> None:
    a, b = boxes([0.8]), boxes([3.2])
    assert M.topological_dissimilarity(a, a) == 0.0
    assert M.topological_dissimilarity(a, b) == 1.0
    empty = Layout(make_plan([("c", "chair", [0.5, 0.5, 0.9])]), {})
    assert M.topological_dissimilarity(empty, empty) == 0.0


def test_occupancy_ignores_objects_off_the_floor(bedroom: Plan) -> None:
    a = bedroom_layout(bedroom)
    b = moved(a, lamp=Pose(3.0, 1.0, 0.0, 1.8, "wall:1"))
    masks, origin = M.occupancy_masks([a, b])
    assert masks.shape[0] == 2 and origin.shape == (2,)
    assert np.array_equal(masks[0], masks[1])
    # the area of the footprints buffered by 0.2 m, clipped to the room (shapely, exact)
    feet = [shapely.Polygon(a.corners(i)).buffer(0.2) for i in ("bed", "ns_1", "ns_2", "chair")]
    area = shapely.union_all(feet).intersection(bedroom.room.shape).area
    assert masks[0].sum() * 0.05**2 == pytest.approx(area, rel=0.03)


def test_occupancy_masks_of_different_rooms_align() -> None:
    small = Plan.model_validate({"name": "s", "room": {"polygon": [[0, 0], [2, 0], [2, 2], [0, 2]]},
                                 "objects": [{"id": "b", "category": "box",
                                              "size": [1.0, 1.0, 1.0]}]})
    a = Layout(small, {"b": Pose(1.0, 1.0, 0.0)})
    b = Layout(boxes([1.0]).plan, {"b0": Pose(1.0, 1.0, 0.0)})
    assert M.topological_dissimilarity(a, b) == pytest.approx(0.0)


# -- relational ---------------------------------------------------------------------

def test_relation_triples_by_hand(bedroom: Plan) -> None:
    t = M.relation_triples(bedroom_layout(bedroom))
    for triple in [("bed", "at_wall", "room"), ("nightstand", "at_wall", "room"),
                   ("bed", "next_to", "nightstand"), ("nightstand", "next_to", "bed"),
                   ("lamp", "on_top", "nightstand"), ("nightstand", "near_window", "room"),
                   ("bed", "near", "chair"), ("chair", "facing", "nightstand")]:
        assert triple in t, triple
    assert ("bed", "facing", "chair") not in t  # 41° off the bed's front (-y)
    assert ("bed", "next_to", "chair") not in t  # 0.55 m apart
    assert not any(r == "on_top" and a != "lamp" for a, r, _ in t)
    assert {r for _, r, _ in t} <= set(M.relation_rules())


def test_relations_come_from_the_registry() -> None:
    vocab = M.relation_rules()
    assert vocab == M.RELATIONS
    for name, summary in vocab.items():
        cls = type(registry.get_rule(name))
        assert cls.relation and summary == cls.summary()
    relational = {n for n in registry.available_rules()
                  if getattr(type(registry.get_rule(n)), "relation", False)}
    assert set(vocab) == relational
    assert "far_from" not in vocab  # declares relation = False


def test_a_plugin_relation_joins_the_vocabulary(bedroom: Plan) -> None:
    @registry.register("metrics_test_left_half")
    class LeftHalf(registry.Rule):
        """In the left half of the room's bounding box."""

        relation = True

        def force(self, state, i, j, p):
            return np.zeros((len(i), 2)), np.zeros(len(i))

        def satisfied(self, state, i, j, p):
            mid = 0.5 * (state.room.bounds[0] + state.room.bounds[2])
            return state.pos[i, 0] < mid

    @registry.register("metrics_test_touching")
    class Touching(registry.Rule):
        """Footprint gap at most 0.1 m."""

        target = "required"
        relation = True

        def force(self, state, i, j, p):
            return np.zeros((len(i), 2)), np.zeros(len(i))

        def satisfied(self, state, i, j, p):
            return state.gap(i, j) <= 0.1

    try:
        assert "metrics_test_left_half" in M.RELATIONS
        t = M.relation_triples(bedroom_layout(bedroom))
        assert ("nightstand", "metrics_test_left_half", "room") in t  # ns_1 at x = 1.05
        assert ("bed", "metrics_test_left_half", "room") not in t  # centre at x = 2.0
        assert ("nightstand", "metrics_test_touching", "bed") in t  # 0.05 m apart
        assert ("bed", "metrics_test_touching", "nightstand") in t
        assert not any(r == "metrics_test_touching" and "chair" in (a, b) for a, r, b in t)
    finally:
        registry.unregister("metrics_test_left_half")
        registry.unregister("metrics_test_touching")
    assert "metrics_test_left_half" not in M.relation_rules()


def test_off_floor_relations() -> None:
    plan = Plan.model_validate({
        "name": "t", "room": ROOM,
        "objects": [{"id": "desk", "category": "desk", "size": [1.2, 0.6, 0.75]},
                    {"id": "art", "category": "poster", "size": [0.8, 0.05, 0.6]},
                    {"id": "light", "category": "light", "size": [0.4, 0.4, 0.1]}]})
    lay = Layout(plan, {"desk": Pose(2.0, 0.3, 0.0),
                        "art": Pose(2.0, 0.025, 0.0, 1.2, "wall:0"),
                        "light": Pose(2.0, 1.5, 0.0, 2.6, "ceiling")})
    t = M.relation_triples(lay)
    assert ("painting", "on_wall", "room") in t
    assert ("painting", "on_wall_mid", "room") in t  # bottom 1.2 m, top 1.8 m
    assert ("light", "on_ceiling", "room") in t
    assert not any(a in ("painting", "light") and r in ("at_wall", "next_to", "near")
                   for a, r, _ in t)  # floor rules judge floor objects only
    assert ("desk", "at_wall", "room") in t


def test_metrics_name_no_builtin_rule() -> None:
    """The metrics read rule meaning from the registry, never from built-in rule names."""
    import re
    from pathlib import Path

    import forcelayout.metrics

    names = "|".join(registry.available_rules())
    literal = re.compile(rf"[\"']({names})[\"']")
    for path in Path(forcelayout.metrics.__file__).parent.glob("*.py"):
        hits = literal.findall(path.read_text(encoding="utf-8"))
        assert not hits, f"{path.name} names rules {hits}"


def test_random_layout_moved_with_a_warning(bedroom: Plan) -> None:
    with pytest.warns(DeprecationWarning, match="forcelayout.baselines"):
        old = M.random_layout
    assert old(bedroom, 0) == random_layout(bedroom, 0)


def test_relational_identical_and_changed(bedroom: Plan) -> None:
    a = bedroom_layout(bedroom)
    assert M.relational_dissimilarity(a, a) == 0.0
    b = moved(a, lamp=Pose(2.95, 2.75, 0.0, 0.5, "ns_2"))  # same triples, other nightstand
    assert M.relational_dissimilarity(a, b) == 0.0
    c = moved(a, bed=Pose(2.0, 1.5, math.pi / 2))  # bed in the middle, not at a wall
    assert M.relational_dissimilarity(a, c) > 0.0


@pytest.mark.parametrize(("a", "b", "d"), [
    (set(), set(), 0.0), ({1}, {1}, 0.0), ({1, 2}, {3}, 1.0), ({1, 2}, {2, 3}, 2 / 3),
])
def test_jaccard_distance(a: set, b: set, d: float) -> None:
    assert M.jaccard_distance(a, b) == pytest.approx(d)
    assert M.jaccard_distance(b, a) == pytest.approx(d)


# -- sets of layouts ----------------------------------------------------------------

@pytest.mark.parametrize("metric", ["geometric", "topological", "relational"])
def test_pairwise_matches_the_pair_functions(bedroom: Plan, metric: str) -> None:
    layouts = [random_layout(bedroom, s) for s in range(4)]
    d = M.pairwise(layouts, metric)
    fn = {"geometric": M.geometric_dissimilarity, "topological": M.topological_dissimilarity,
          "relational": M.relational_dissimilarity}[metric]
    assert np.allclose(d, d.T) and np.all(np.diag(d) == 0)
    assert d[1, 3] == pytest.approx(fn(layouts[1], layouts[3]))
    assert M.intra_plan(layouts, metric) == pytest.approx(d[np.triu_indices(4, 1)].mean())


def test_intra_and_inter_plan(bedroom: Plan) -> None:
    a = bedroom_layout(bedroom)
    assert math.isnan(M.intra_plan([a]))
    assert M.intra_plan([a, a, a]) == 0.0
    other = boxes([1.0, 3.0])
    assert M.inter_plan([[a], [other]]) == 1.0
    assert M.inter_plan([[a, a], [a]], "topological") == 0.0
    assert math.isnan(M.inter_plan([[a, a], []]))
    with pytest.raises(ValueError, match="unknown metric"):
        M.pairwise([a, a], "nonsense")  # type: ignore[arg-type]


# -- rates and intervals ------------------------------------------------------------

def test_rates_and_throughput(bedroom: Plan) -> None:
    a = bedroom_layout(bedroom)
    a.report.valid, a.report.rule_satisfaction = False, 0.5
    assert M.validity_rate([True, False, True, True]) == 0.75
    assert M.validity_rate([a, a.report]) == 0.0
    assert M.rule_satisfaction_rate([a, 1.0]) == 0.75
    assert math.isnan(M.validity_rate([]))
    assert M.throughput(10, 4.0) == 2.5
    assert M.throughput(10, 4.0, cores=2) == 1.25
    with pytest.raises(ValueError):
        M.throughput(1, 1.0, cores=0)


def test_bootstrap_constant_and_deterministic() -> None:
    ci = M.bootstrap_ci([0.3] * 5)
    assert (ci.estimate, ci.low, ci.high) == pytest.approx((0.3, 0.3, 0.3))
    x = [0.1, 0.4, 0.2, 0.9, 0.5, 0.3]
    c1, c2 = M.bootstrap_ci(x, seed=1), M.bootstrap_ci(x, seed=1)
    assert c1 == c2
    assert c1.low <= c1.estimate <= c1.high and c1.low < c1.high
    assert min(x) <= c1.low and c1.high <= max(x)
    assert c1.n_groups == 6
    wide = M.bootstrap_ci(x, level=0.99)
    assert wide.low <= c1.low and wide.high >= c1.high


def test_bootstrap_groups_and_statistics() -> None:
    groups = [[1.0, 1.0, 1.0], [3.0], [5.0, 5.0]]
    ci = M.bootstrap_ci(groups, n_resamples=2000)
    assert ci.estimate == pytest.approx(np.mean([1, 1, 1, 3, 5, 5]))
    assert 1.0 <= ci.low <= ci.high <= 5.0
    med = M.bootstrap_ci(groups, np.median, n_resamples=500)
    assert med.estimate == 2.0
    custom = M.bootstrap_ci(groups, lambda v: float(np.max(v)), n_resamples=200)
    assert custom.estimate == 5.0 and custom.low >= 1.0
    within = M.bootstrap_ci([[0.0, 1.0] * 10], resample_within=True, n_resamples=2000)
    assert within.low < 0.5 < within.high  # one plan: only the within-plan stage varies
    single = M.bootstrap_ci([[0.0, 1.0] * 10], n_resamples=200)
    assert single.low == single.high == 0.5


def test_bootstrap_edge_cases() -> None:
    empty = M.bootstrap_ci([])
    assert math.isnan(empty.estimate) and empty.to_dict()["low"] is None
    assert M.bootstrap_ci([float("nan"), 2.0]).estimate == 2.0
    with pytest.raises(ValueError, match="level"):
        M.bootstrap_ci([1.0], level=95)
    with pytest.raises(ValueError, match="n_resamples"):
        M.bootstrap_ci([1.0], n_resamples=0)


def test_still_objects_are_those_in_one_spot_in_every_layout():
    import dataclasses

    import forcelayout as fl
    from forcelayout.metrics import still_objects

    g = fl.generate("bedroom", 6, seed=0)
    lays = list(g)
    assert still_objects(lays) == [] == g.summary()["still_objects"]
    bed = lays[0].poses["bed"]
    pinned = [Layout(lay.plan, {**lay.poses, "bed": dataclasses.replace(
        bed, x=bed.x + 0.01 * k, yaw=bed.yaw + 0.015 * k)}) for k, lay in enumerate(lays)]
    assert still_objects(pinned) == ["bed"]
    assert still_objects(pinned, tolerance=0.01) == []  # 2.5 cm from the mean
    assert still_objects(pinned, max_turn=1.0) == []  # turned up to 4.3 degrees
    assert still_objects(pinned[:4]) == []  # too few to say
