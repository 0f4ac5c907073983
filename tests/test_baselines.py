"""forcelayout.baselines: the Random baseline and the rule-aware rejection sampler."""

from __future__ import annotations

import math

import numpy as np
import pytest

from forcelayout import Plan
from forcelayout import metrics as M
from forcelayout.baselines import random_layout
from forcelayout.geometry import RoomGeometry, box_corners, box_separation

ROOM = {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]], "height": 2.7,
        "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}],
        "windows": [{"wall": 2, "offset": 2.0, "width": 1.0}]}


@pytest.fixture(scope="module")
def bedroom() -> Plan:
    return Plan.model_validate({
        "name": "t", "room": ROOM,
        "objects": [{"id": i, "category": c, "size": s} for i, c, s in [
            ("bed", "bed", [1.4, 2.0, 0.5]), ("ns_1", "nightstand", [0.4, 0.4, 0.5]),
            ("ns_2", "Bedside_Table", [0.4, 0.4, 0.5]), ("chair", "chair", [0.5, 0.5, 0.9]),
            ("lamp", "lamp", [0.2, 0.2, 0.3])]]})


# -- the Random baseline ------------------------------------------------------------------

def test_random_layout_inside_cardinal_and_seeded(bedroom: Plan) -> None:
    room = RoomGeometry.from_room(bedroom.room)
    a = random_layout(bedroom, 3)
    assert a == random_layout(bedroom, 3)
    assert a != random_layout(bedroom, 4)
    ids = [i for i in bedroom.ids if a.poses[i].surface == "floor"]
    pos = np.array([[a.poses[i].x, a.poses[i].y] for i in ids])
    yaw = np.array([a.poses[i].yaw for i in ids])
    half = np.array([bedroom.object(i).size[:2] for i in ids]) / 2
    c = box_corners(pos, yaw, half)
    assert room.contains(c).all()
    assert np.allclose(np.mod(yaw, math.pi / 2), 0.0)
    sep = box_separation(c[:, None], c[None])
    assert (sep[np.triu_indices(len(ids), 1)] > 0).all()  # rejection: no overlaps


def test_random_layout_places_off_floor_objects() -> None:
    plan = Plan.model_validate({
        "name": "t", "room": ROOM,
        "objects": [{"id": "desk", "category": "desk", "size": [1.2, 0.6, 0.75]},
                    {"id": "lamp", "category": "lamp", "size": [0.2, 0.2, 0.3]},
                    {"id": "light", "category": "light", "size": [0.4, 0.4, 0.1]}],
        "rules": [{"rule": "on_top", "object": "lamp", "target": "desk"},
                  {"rule": "on_ceiling", "object": "light"}],
    })
    lay = random_layout(plan, 0)
    assert lay.poses["lamp"].surface == "desk"
    assert lay.poses["lamp"].z == pytest.approx(0.75)
    assert lay.poses["light"].surface == "ceiling"
    assert ("lamp", "on_top", "desk") in M.relation_triples(lay)
