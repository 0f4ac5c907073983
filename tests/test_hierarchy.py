"""Hierarchical generation: scene graph, area variants, combinatorial assembly, ablations."""

from dataclasses import dataclass

import networkx as nx
import numpy as np
import pytest

import forcelayout as fl
from forcelayout.errors import PlanError
from forcelayout.geometry import box_corners
from forcelayout.hierarchy import (
    VariantLibrary,
    area_units,
    area_variants,
    assemble,
    scene_graph,
)
from forcelayout.sampling import Options


@dataclass(frozen=True)
class _Hierarchical(Options):  # until Options has these fields
    hierarchy: bool = True
    variants: int = 3
    variant_seed: int = 0


def hierarchical(**kw) -> Options:
    if "hierarchy" in Options.__dataclass_fields__:
        return Options(hierarchy=True, variants=kw.pop("variants", 3), **kw)
    return _Hierarchical(**kw)


@pytest.fixture(scope="module")
def bedroom():
    return fl.examples.load_example("bedroom")


@pytest.fixture(scope="module")
def library(bedroom):
    return VariantLibrary(bedroom, 2, seed=1)


def test_scene_graph_edges(bedroom):
    g = scene_graph(bedroom)
    assert isinstance(g, nx.DiGraph)
    assert set(g.nodes) == set(bedroom.ids)
    strong = {(a, b) for a, b, s in g.edges(data="strong") if s}
    # on_top and above: parent -> child; next_to / in_front_of in one area: default bonds
    assert {("nightstand_1", "lamp"), ("bed", "painting"), ("bed", "nightstand_1"),
            ("bed", "nightstand_2"), ("desk", "desk_chair")} <= strong
    assert g.nodes["lamp"]["surface"] == "on_top"
    assert g.nodes["bed"]["area"] == "sleeping"
    assert nx.is_directed_acyclic_graph(g.edge_subgraph(strong))


def test_peer_relations_are_weak_edges():
    plan = fl.Plan.from_dict({
        "name": "tv", "room": {"polygon": [[0, 0], [4, 0], [4, 4], [0, 4]]},
        "objects": [{"id": "sofa", "category": "sofa", "size": [2.0, 0.9, 0.8]},
                    {"id": "tv", "category": "tv", "size": [1.2, 0.4, 0.6]},
                    {"id": "a", "category": "box", "size": [0.4, 0.4, 0.4]},
                    {"id": "b", "category": "box", "size": [0.4, 0.4, 0.4]}],
        "rules": [{"rule": "facing", "object": "sofa", "target": "tv"},
                  {"rule": "next_to", "object": "a", "target": "b"},
                  {"rule": "next_to", "object": "b", "target": "a"}]})
    g = scene_graph(plan)
    assert g.edges["sofa", "tv"] == {"rules": ["facing"], "strong": False}
    # two default bonds that would close a cycle: one of them stays a peer relation
    assert g.has_edge("b", "a") and g.edges["b", "a"]["strong"]
    assert g.edges["b", "a"]["rules"] == ["next_to", "next_to"]


def test_explicit_bond_cycle_is_a_plan_error():
    plan = fl.Plan.from_dict({
        "name": "cycle", "room": {"polygon": [[0, 0], [4, 0], [4, 4], [0, 4]]},
        "objects": [{"id": "a", "category": "box", "size": [0.4, 0.4, 0.4]},
                    {"id": "b", "category": "box", "size": [0.4, 0.4, 0.4]}],
        "rules": [{"rule": "near", "object": "a", "target": "b"},
                  {"rule": "near", "object": "b", "target": "a"}]})
    for spec in plan.rules:  # the plan schema's `bond` flag, set directly
        object.__setattr__(spec, "bond", True)
    with pytest.raises(PlanError, match="bond cycle"):
        scene_graph(plan)


def test_area_units_follow_the_areas(bedroom):
    units = area_units(bedroom)
    assert units == {"sleeping": ["bed", "nightstand_1", "nightstand_2"],
                     "storage": ["wardrobe", "dresser"], "work": ["desk", "desk_chair"]}


def test_area_variants_fit_their_extent(bedroom):
    vs = area_variants(bedroom, "sleeping", 3, np.random.default_rng(0))
    assert len(vs) == 3
    size = np.array([bedroom.object(i).size for i in vs[0].ids])
    for v in vs:
        c = box_corners(v.pos, v.yaw, size[:, :2] / 2)
        assert (np.abs(c) <= np.array(v.extent) / 2 + 1e-6).all()
    # variants differ
    assert not np.allclose(vs[0].pos, vs[1].pos, atol=0.05)
    with pytest.raises(KeyError, match="areas"):
        area_variants(bedroom, "kitchen", 1, np.random.default_rng(0))


def test_combinations_give_more_distinct_rooms_than_variants(bedroom, library):
    assert library.n_combinations == 8  # 2 variants x 3 areas
    rng = np.random.default_rng(0)
    rooms = []
    for combo in library.combinations():
        poses, _, _ = assemble(bedroom, combo, rng)
        assert set(poses) == {o.id for o in bedroom.floor_objects()}
        rooms.append(np.array([[poses[i].x, poses[i].y] for i in sorted(poses)]))
    distinct = [r for k, r in enumerate(rooms)
                if all(np.abs(r - q).max() >= 0.05 for q in rooms[:k])]
    assert len(distinct) > library.v


def test_hierarchical_solve_places_every_object_and_is_seeded(bedroom):
    opts = hierarchical(check=False)
    a = fl.solve(bedroom, 5, options=opts)
    b = fl.solve(bedroom, 5, options=opts)
    assert a.report.missing == [] and set(a.poses) == set(bedroom.ids)
    assert a.poses == b.poses
    assert {"variants", "assembly", "tops", "walls", "ceiling"} <= set(a.report.stages)
    assert a.poses["lamp"].surface == "nightstand_1"
    room = a.room
    floor = a.state()
    assert room.contains(floor.corners.reshape(-1, 2) + 0.0).mean() > 0.99


def test_ablations_run_through_the_hierarchy(bedroom):
    lay = fl.solve(bedroom, 2, options=hierarchical(check=False, decor=False, relations=False))
    keep = {o.id for o in bedroom.objects if not o.decor}
    assert set(lay.poses) == keep
    assert lay.report.missing == []
