"""forcelayout.testing: strategies make valid plans; check_rule accepts good rules, rejects bad."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from pydantic import Field

import forcelayout as fl
from forcelayout.geometry import RoomGeometry
from forcelayout.rules import Rule
from forcelayout.testing import (
    BINARY_RULES,
    UNARY_RULES,
    RuleConformanceError,
    check_rule,
    plans,
    rooms,
    scene_objects,
)

FAST = settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])


# -- strategies -------------------------------------------------------------------------


@FAST
@given(rooms())
def test_rooms_are_simple_polygons_with_openings_on_their_walls(room):
    assert room.shape.is_valid and room.shape.area > 4.0
    assert len(room.doors) == 1
    geo = RoomGeometry.from_room(room)
    for o in (geo.doors, geo.windows):
        if len(o):  # opening centres lie on the floor's boundary
            assert np.all(geo.wall_distance(o.centre)[0].min(axis=1) < 1e-6)


@FAST
@given(scene_objects())
def test_scene_objects_have_plausible_sizes(obj):
    assert all(0.2 < s < 2.5 for s in obj.size)


@FAST
@given(plans(min_objects=2, max_objects=6))
def test_plans_validate_and_are_feasible(plan):
    assert isinstance(plan, fl.Plan)
    assert 2 <= len(plan.objects) <= 6
    footprint = sum(o.size[0] * o.size[1] for o in plan.objects)
    assert footprint <= 0.31 * plan.room.shape.area
    for r in plan.rules:
        assert r.rule in UNARY_RULES + BINARY_RULES
        assert (r.target is not None) == (r.rule in BINARY_RULES)
    fl.Plan.from_json(plan.to_json())  # round-trips through validation


@settings(max_examples=3, deadline=None)
@given(plans(max_objects=4))
def test_generated_plans_solve(plan):
    layout = fl.solve(plan, 0, check=False)
    assert set(layout.poses) == set(plan.ids)


def test_plans_without_rules():
    @FAST
    @given(plans(max_objects=3, rules=False))
    def inner(plan):
        assert plan.rules == []

    inner()


def test_bad_strategy_arguments_raise():
    with pytest.raises(ValueError):
        plans(min_objects=3, max_objects=2)
    with pytest.raises(ValueError):
        rooms(min_side=1.0)


# -- check_rule: every built-in rule conforms ----------------------------------------------


@pytest.mark.parametrize("name", UNARY_RULES + BINARY_RULES)
def test_builtin_rules_conform(name):
    report = check_rule(name, n_states=8, seed=1)
    assert report["rule"] == name
    assert report["satisfied_after"] >= report["satisfied_before"] - 0.1


def test_check_rule_takes_classes_and_params():
    from forcelayout.rules.binary import Near

    report = check_rule(Near, n_states=3, params={"distance": 0.4})
    assert report["states"] == 3
    with pytest.raises(RuleConformanceError, match="Params"):
        check_rule(Near, n_states=1, params={"distance": -1})


def test_check_rule_refuses_surface_rules():
    with pytest.raises(TypeError, match="floor rules"):
        check_rule("on_top", n_states=1)


# -- check_rule: deliberately broken rules -------------------------------------------------


class _Good(Rule):
    """Pull towards the room's first wall start, fading out within 1 m (a working baseline)."""

    kind = "unary"

    def force(self, state, i, j, p):
        d = state.room.polygon[0] - state.pos[i]
        dist = np.sqrt((d * d).sum(1))
        mag = np.clip(dist - 0.9, 0.0, 1.0) * p.weight / np.maximum(dist, 1e-9)
        return d * mag[:, None], np.zeros(len(i))

    def satisfied(self, state, i, j, p):
        d = state.room.polygon[0] - state.pos[i]
        return np.sqrt((d * d).sum(1)) <= 1.0


class _WrongShape(_Good):
    """Forces of shape (B,) instead of (B, 2)."""

    def force(self, state, i, j, p):
        return np.zeros(len(i)), np.zeros(len(i))


class _ScalarTorque(_Good):
    """A scalar torque instead of one per binding."""

    def force(self, state, i, j, p):
        return super().force(state, i, j, p)[0], 0.0


class _NotFinite(_Good):
    """Divides by the distance to the target without a guard."""

    kind = "binary"

    def force(self, state, i, j, p):
        d = state.pos[j] - state.pos[i]
        return d / (d * d).sum(1, keepdims=True), np.zeros(len(i))

    def satisfied(self, state, i, j, p):
        return np.ones(len(i), dtype=bool)


class _Absolute(_Good):
    """Pulls towards the world origin instead of a room feature."""

    def force(self, state, i, j, p):
        return -np.clip(state.pos[i], -1, 1), np.zeros(len(i))


class _FloatCheck(_Good):
    """Returns 0/1 floats from satisfied()."""

    def satisfied(self, state, i, j, p):
        return super().satisfied(state, i, j, p).astype(float)


class _ListCheck(_Good):
    """Returns a list from satisfied()."""

    def satisfied(self, state, i, j, p):
        return super().satisfied(state, i, j, p).tolist()


class _Restless(_Good):
    """Keeps pulling hard where its own check says it is met."""

    def force(self, state, i, j, p):
        return np.tile([2.0, 0.0], (len(i), 1)) * p.weight[:, None], np.zeros(len(i))

    def satisfied(self, state, i, j, p):
        return np.ones(len(i), dtype=bool)


class _Backwards(_Good):
    """Gently pulls towards the corner its check wants it away from."""

    def force(self, state, i, j, p):
        d = state.room.polygon[0] - state.pos[i]
        u = d / np.maximum(np.sqrt((d * d).sum(1, keepdims=True)), 1e-9)
        return 0.45 * u * p.weight[:, None], np.zeros(len(i))

    def satisfied(self, state, i, j, p):
        d = state.room.polygon[0] - state.pos[i]
        return np.sqrt((d * d).sum(1)) >= 2.5


class _NoDefaults(_Good):
    """A parameter without a default."""

    class Params(Rule.Params):
        distance: float = Field(gt=0, description="m")


def test_a_working_rule_passes():
    check_rule(_Good, n_states=5)


@pytest.mark.parametrize(("rule", "match"), [
    (_WrongShape, r"F has shape \(4,\)"),
    (_ScalarTorque, "tau has shape"),
    (_NotFinite, "non-finite"),
    (_Absolute, "translation invariant"),
    (_FloatCheck, "numpy bool array"),
    (_ListCheck, "numpy bool array"),
    (_Restless, "satisfied with margin"),
    (_Backwards, "pass less often"),
    (_NoDefaults, "default"),
])
def test_broken_rules_fail_with_a_clear_message(rule, match):
    with pytest.raises(RuleConformanceError, match=match) as e:
        check_rule(rule, n_states=6)
    assert rule.__name__ in str(e.value) or e.value.args[0].split(".")[0] == rule.__name__
    assert not isinstance(e.value, AssertionError)
