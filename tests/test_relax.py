"""Trial runs that drop the rules no layout meets (forcelayout.relax)."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest

import forcelayout as fl
from forcelayout import Plan
from forcelayout.relax import relax

ROOM = {"polygon": [[0, 0], [5, 0], [5, 4], [0, 4]], "doors": [{"wall": 0, "offset": 2.5}]}


def stuck_plan() -> Plan:
    """Two cabinets tucked into corners that must also stand next to each other, and a lamp on
    one of them: no layout meets 95 % of these rules."""
    objects = [{"id": "cab_a", "category": "cabinet", "size": [0.6, 0.5, 0.9]},
               {"id": "cab_b", "category": "cabinet", "size": [0.6, 0.5, 0.9]},
               {"id": "desk", "category": "desk", "size": [1.2, 0.6, 0.75]},
               {"id": "lamp", "category": "lamp", "size": [0.2, 0.2, 0.4]}]
    rules = [{"rule": "in_corner", "object": "cab_a"}, {"rule": "in_corner", "object": "cab_b"},
             {"rule": "next_to", "object": "cab_a", "target": "cab_b"},
             {"rule": "next_to", "object": "cab_b", "target": "cab_a"},
             {"rule": "at_wall", "object": "desk"},
             {"rule": "on_top", "object": "lamp", "target": "cab_a"}]
    return Plan.from_dict({"name": "storage_room", "room": ROOM, "objects": objects,
                           "rules": rules})


def layouts(plan: Plan) -> int:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return len(fl.generate(plan, 3, max_attempts=12, seed=5))


def test_a_plan_no_layout_meets_loses_the_rules_its_samples_miss():
    plan = stuck_plan()
    assert layouts(plan) == 0
    relaxed, notes = relax(plan)
    assert notes and all(n.startswith("removed ") and "failed samples" in n for n in notes)
    dropped = {r.rule + "/" + r.object for r in plan.rules} - \
        {r.rule + "/" + r.object for r in relaxed.rules}
    assert dropped and len(relaxed.rules) == len(plan.rules) - len(notes)
    # the surface rule stays: the lamp keeps its support
    assert any(r.rule == "on_top" and r.object == "lamp" for r in relaxed.rules)
    assert layouts(relaxed) >= 1
    # the same plan and seed relax the same way
    assert relax(plan) == (relaxed, notes)


def test_a_plan_that_yields_stands_as_it_is():
    plan = fl.load_plan("bedroom")
    relaxed, notes = relax(plan)
    assert relaxed is plan and notes == []


def test_bad_arguments_are_refused():
    with pytest.raises(ValueError, match="positive"):
        relax(stuck_plan(), samples=0)


def test_rules_missed_by_fewer_than_half_of_the_failed_samples_go_one_a_round():
    """A kids' room a small model planned (two beds aligned, near, facing ...), asked for
    half of its trial's samples (it gives about 3 of 12 as planned): its failed samples
    miss different rules; the one missed most often goes, alone."""
    plan = Plan.load(Path(__file__).parent / "data" / "relax_kids_room.json")
    relaxed, notes = relax(plan, wanted=6)
    assert len(notes) == 1  # the counts move with the solver; the rule and the form do not
    assert re.fullmatch(r"removed aligned_with\(bed_1, bed_2\): trial 1 missed it in (\d+) of "
                        r"(\d+) failed samples", notes[0]), notes
    assert len(relaxed.rules) == len(plan.rules) - 1
