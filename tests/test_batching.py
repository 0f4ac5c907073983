"""The batched engine: samples simulated together give what each gives alone, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import forcelayout as fl
from forcelayout.forces import ForceModel
from forcelayout.initial import start_poses
from forcelayout.options import SolverConfig
from forcelayout.rules import Rule, register, unregister
from forcelayout.rules.base import State
from forcelayout.sampling import solve_many
from forcelayout.solver import simulate, simulate_batch
from forcelayout.testing import check_rule, plans

#: A room with two doors, a rug under a table, chairs around it and a sofa facing a TV:
#: every kind of built-in term (access zones, door squares, windows, views, covers).
ROOM = {
    "name": "batch_room",
    "room": {"polygon": [[0, 0], [4.6, 0], [4.6, 4.0], [0, 4.0]],
             "doors": [{"wall": 0, "offset": 0.6, "width": 0.9},
                       {"wall": 2, "offset": 0.5, "width": 0.8}],
             "windows": [{"wall": 1, "offset": 1.4, "width": 1.2}]},
    "objects": [
        {"id": "sofa", "category": "sofa", "size": [2.0, 0.9, 0.85]},
        {"id": "tv", "category": "tv stand", "size": [1.4, 0.4, 0.6]},
        {"id": "table", "category": "dining table", "size": [1.2, 0.8, 0.75]},
        {"id": "chair_1", "category": "chair", "size": [0.45, 0.5, 0.9]},
        {"id": "chair_2", "category": "chair", "size": [0.45, 0.5, 0.9]},
        {"id": "chair_3", "category": "chair", "size": [0.45, 0.5, 0.9]},
        {"id": "rug", "category": "rug", "size": [2.0, 1.6, 0.01]},
        {"id": "shelf", "category": "bookshelf", "size": [0.9, 0.35, 1.9]},
        {"id": "lamp", "category": "table lamp", "size": [0.25, 0.25, 0.4]},
    ],
    "rules": [
        {"rule": "at_wall", "object": "sofa"},
        {"rule": "at_wall", "object": "tv"},
        {"rule": "facing", "object": "sofa", "target": "tv"},
        {"rule": "around", "object": "chair_1", "target": "table"},
        {"rule": "around", "object": "chair_2", "target": "table"},
        {"rule": "around", "object": "chair_3", "target": "table"},
        {"rule": "under", "object": "rug", "target": "table"},
        {"rule": "at_wall", "object": "shelf"},
        {"rule": "far_from", "object": "shelf", "target": "tv", "params": {"distance": 1.0}},
        {"rule": "on_top", "object": "lamp", "target": "shelf"},
    ],
}


def _poses(layout: fl.Layout) -> list[tuple[str, float, float, float]]:
    return sorted((k, p.x, p.y, p.yaw) for k, p in layout.poses.items())


@pytest.mark.parametrize("plan", [ROOM, "living_room"])
def test_a_sample_is_the_same_whatever_batch_it_runs_in(plan):
    """Sample k of a run is the same layout, bit for bit, for batch sizes 1, 7 and 64."""
    runs = {}
    for batch in (1, 7, 64):
        g = fl.generate(plan, 64, seed=5, max_attempts=64, distinct_tol=0.0,
                        options=fl.Options(batch=batch))
        runs[batch] = [(r.seed, r.valid, r.steps, tuple(r.failures)) for r in g.reports], \
            [_poses(lay) for lay in g.layouts]
    assert len(runs[1][0]) == 64
    assert runs[7] == runs[1]
    assert runs[64] == runs[1]
    assert len(runs[1][1]) > 32  # most samples pass: the comparison covers real layouts


def test_solve_many_is_solve_of_each_seed():
    seeds = [3, 11, 2**40, 7]
    many = solve_many(ROOM, seeds)
    assert [lay.seed for lay in many] == seeds
    for seed, lay in zip(seeds, many, strict=True):
        alone = fl.solve(ROOM, seed)
        assert _poses(lay) == _poses(alone)
        assert lay.report.failures == alone.report.failures
        assert lay.report.seconds > 0


def test_solve_many_rejects_a_negative_seed():
    with pytest.raises(ValueError, match="non-negative"):
        solve_many(ROOM, [1, -2])


def test_options_batch_must_be_positive():
    with pytest.raises(ValueError, match="Options.batch"):
        fl.Options(batch=0)
    assert fl.Options(batch=np.int64(3)).batch == 3


def _starts(model: ForceModel, count: int) -> tuple[np.ndarray, np.ndarray]:
    pos, yaw = [], []
    for s in range(count):
        p, y, _ = next(iter(start_poses(model, np.random.default_rng(s), misses=99)))
        pos.append(p)
        yaw.append(y)
    return np.stack(pos), np.stack(yaw)


def test_simulate_batch_gives_each_sample_its_own_result():
    model = ForceModel(fl.load_plan(ROOM))
    pos, yaw = _starts(model, 5)
    together = simulate_batch(model, pos, yaw)
    for b in range(5):
        alone = simulate(model, pos[b], yaw[b])
        assert np.array_equal(together[b].pos, alone.pos)
        assert np.array_equal(together[b].yaw, alone.yaw)
        assert (together[b].steps, together[b].converged) == (alone.steps, alone.converged)


def test_each_sample_may_hold_its_own_rows_fixed():
    from forcelayout.repair import repairing

    model = repairing(ForceModel(fl.load_plan(ROOM)))  # with walking room that holds
    pos, yaw = _starts(model, 4)
    rng = np.random.default_rng(3)
    fixed = rng.random((4, model.n)) < 0.5
    fixed[0] = False  # one moves everything, one nothing
    fixed[1] = True
    together = simulate_batch(model, pos, yaw, fixed=fixed)
    for b in range(4):
        alone = simulate(model, pos[b], yaw[b], fixed=fixed[b])
        assert np.array_equal(together[b].pos, alone.pos)
        assert np.array_equal(together[b].yaw, alone.yaw)
        assert together[b].steps == alone.steps
        np.testing.assert_allclose(together[b].pos[fixed[b]], pos[b][fixed[b]], atol=1e-6)


def test_repairs_of_a_batch_run_together_and_give_what_each_gives_alone():
    from forcelayout.batching import drive
    from forcelayout.repair import repair_floor, repair_task

    model = ForceModel(fl.load_plan(ROOM))
    pos, yaw = _starts(model, 4)
    cfg = SolverConfig(max_steps=30)
    settled = simulate_batch(model, pos, yaw, cfg)
    seeds = [11, 12, 13, 14]
    together = drive([repair_task(model, s.pos, s.yaw, cfg, rounds=4,
                                  rng=np.random.default_rng(seed))
                      for s, seed in zip(settled, seeds, strict=True)])
    for s, seed, got in zip(settled, seeds, together, strict=True):
        alone = repair_floor(model, s.pos, s.yaw, cfg, rounds=4, rng=np.random.default_rng(seed))
        assert np.array_equal(got[0], alone[0]) and np.array_equal(got[1], alone[1])
        assert got[2:] == alone[2:]
    assert any(spent for _, _, spent, _ in together)  # some had something to repair


def test_a_sample_at_the_step_cap_says_so_and_holds_up_no_other():
    model = ForceModel(fl.load_plan(ROOM))
    pos, yaw = _starts(model, 3)
    cfg = SolverConfig(max_steps=30, min_steps=1)
    res = simulate_batch(model, pos, yaw, cfg)
    for r in res:
        assert r.steps <= 30
        assert r.converged or r.steps == 30  # stopped short of the cap only at rest
    assert not all(r.converged for r in res)  # one at the cap says so
    # a sample already at rest leaves at once; the others go on
    at_rest = simulate_batch(model, np.stack([res[0].pos, pos[1]]),
                             np.stack([res[0].yaw, yaw[1]]), cfg)
    assert at_rest[1].steps == res[1].steps


def test_the_stacked_forces_are_each_samples_own():
    model = ForceModel(fl.load_plan(ROOM))
    pos, yaw = _starts(model, 4)
    stack = model.stacked(4)
    state = stack.state(pos.reshape(-1, 2), yaw.reshape(-1))
    f, tau = stack.net(state)
    n = model.n
    for b in range(4):
        f1, t1 = model.net(model.state(pos[b], yaw[b]))
        assert np.array_equal(f[b * n:(b + 1) * n], f1)
        assert np.array_equal(tau[b * n:(b + 1) * n], t1)
    assert model.stacked(1) is model


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(plan=plans(max_objects=6), count=st.integers(2, 5), seed=st.integers(0, 2**16))
def test_random_plans_batch_like_single_samples(plan, count, seed):
    model = ForceModel(plan)
    if model.n == 0:
        return
    rng = np.random.default_rng(seed)
    lo, hi = model.room.bounds[:2], model.room.bounds[2:]
    pos = rng.uniform(lo, hi, (count, model.n, 2))
    yaw = rng.uniform(-np.pi, np.pi, (count, model.n))
    cfg = SolverConfig(max_steps=25)
    together = simulate_batch(model, pos, yaw, cfg)
    for b in range(count):
        alone = simulate(model, pos[b], yaw[b], cfg)
        assert np.array_equal(together[b].pos, alone.pos, equal_nan=True)
        assert together[b].steps == alone.steps


class _Crowd(Rule):
    """A plugin written against the one-sample API: reads the all-pairs matrix."""

    target = "none"

    def force(self, state, i, j, p):
        sep = state.separations  # every pair: one sample only
        near = (sep < 0.5).sum(1)[i] - 1.0
        f = np.zeros((len(i), 2))
        f[:, 0] = 0.1 * near * p.weight
        return f, np.zeros(len(i))

    def satisfied(self, state, i, j, p):
        return np.ones(len(i), dtype=bool)


def test_a_plugin_rule_that_is_not_batched_runs_once_per_sample():
    assert not _Crowd.batched
    register("crowd_test")(_Crowd)
    try:
        plan = {**ROOM, "rules": ROOM["rules"] + [{"rule": "crowd_test", "object": "shelf"}]}
        model = ForceModel(fl.load_plan(plan))
        pos, yaw = _starts(model, 3)
        stack = model.stacked(3)
        f, _ = stack.net(stack.state(pos.reshape(-1, 2), yaw.reshape(-1)))
        for b in range(3):
            f1, _ = model.net(model.state(pos[b], yaw[b]))
            assert np.array_equal(f[b * model.n:(b + 1) * model.n], f1)
        a = solve_many(plan, [1, 2])
        assert [_poses(x) for x in a] == [_poses(fl.solve(plan, s)) for s in (1, 2)]
    finally:
        unregister("crowd_test")


class _Lonely(_Crowd):
    """A plugin check that reads the all-pairs matrix: met with at most one neighbour."""

    def satisfied(self, state, i, j, p):
        return (state.separations < 0.5).sum(1)[i] <= 2


@pytest.mark.parametrize("plugin", [False, True])
def test_floors_judged_together_get_the_verdicts_they_get_alone(plugin):
    from forcelayout.verdict import judge_floor, judge_floors

    register("lonely_test")(_Lonely)
    try:
        extra = [{"rule": "lonely_test", "object": "shelf"}] if plugin else []
        model = ForceModel(fl.load_plan({**ROOM, "rules": ROOM["rules"] + extra}))
        pos, yaw = _starts(model, 3)
        rng = np.random.default_rng(5)  # and anywhere: collisions, unmet rules, blocked paths
        lo, hi = model.room.bounds[:2], model.room.bounds[2:]
        pos = np.concatenate([pos, rng.uniform(lo, hi, (5, model.n, 2))])
        yaw = np.concatenate([yaw, rng.uniform(-np.pi, np.pi, (5, model.n))])
        together = judge_floors(model, pos, yaw)
        alone = [judge_floor(model, p, y) for p, y in zip(pos, yaw, strict=True)]
        assert [(v.failures, v.at_fault, v.missed) for v in together] == \
            [(v.failures, v.at_fault, v.missed) for v in alone]
        assert sum(v.unmet for v in alone) > 0 and sum(not v.ok for v in alone) > 1
        assert any(v.missed != alone[0].missed for v in alone)
        # judged without naming what blocks the way: the same verdicts but for that
        plain = judge_floors(model, pos, yaw, blockers=False)
        for a, b in zip(together, plain, strict=True):
            assert [f.split(" (blocked by ")[0] for f in a.failures] == b.failures
            assert (a.missed, a.free) == (b.missed, b.free)
            assert a.passes(1) == b.passes(1) and a.rejecting(1) == b.rejecting(1)
            if not any(f.startswith("reachable:") for f in a.failures):
                assert a.at_fault == b.at_fault
    finally:
        unregister("lonely_test")


def test_a_subclass_with_its_own_force_is_not_batched_unless_it_says_so():
    from forcelayout.rules.binary import Near

    class MyNear(Near):
        def force(self, state, i, j, p):
            return super().force(state, i, j, p)

    class MyBatchedNear(Near):
        batched = True

        def force(self, state, i, j, p):
            return super().force(state, i, j, p)

    assert Near.batched and not MyNear.batched and MyBatchedNear.batched


def test_the_all_pairs_matrices_refuse_a_stacked_state():
    model = ForceModel(fl.load_plan(ROOM))
    pos, yaw = _starts(model, 2)
    state = model.stacked(2).state(pos.reshape(-1, 2), yaw.reshape(-1))
    assert isinstance(state, State) and state.samples == 2 and state.rows == model.n
    with pytest.raises(ValueError, match="separation"):
        _ = state.separations
    i = np.array([0, model.n])
    assert np.array_equal(state.peers(i)[1], np.arange(model.n, 2 * model.n))
    # each sample's own matrix, as its state alone gives it
    blocks = state.sample_separations
    assert blocks.shape == (2, model.n, model.n)
    for b in range(2):
        assert np.array_equal(blocks[b], state.sample(b).separations)


@pytest.mark.parametrize("name", ["near", "facing", "around", "at_wall", "under"])
def test_check_rule_checks_a_batched_rule_on_stacked_samples(name):
    assert check_rule(name, n_states=4, steps=5)["rule"] == name


def test_check_rule_catches_a_rule_that_claims_batched_wrongly():
    from forcelayout.testing import RuleConformanceError

    class Wrong(_Crowd):
        batched = True

        def force(self, state, i, j, p):
            near = (state.pos[:, None, 0] - state.pos[None, :, 0]) ** 2  # every row
            f = np.zeros((len(i), 2))
            f[:, 0] = 0.01 * near.sum(1)[i] * p.weight
            return f, np.zeros(len(i))

    register("wrong_batched_test")(Wrong)
    try:
        with pytest.raises(RuleConformanceError, match="batched"):
            check_rule("wrong_batched_test", n_states=3, steps=2)
    finally:
        unregister("wrong_batched_test")


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(plan=plans(max_objects=5), seed=st.integers(0, 2**20))
def test_random_plans_solve_the_same_in_a_batch(plan, seed):
    """Whole samples (start poses, settling, repair, surfaces, checks) of random plans: a
    batch of three gives each seed the layout and report it gets alone."""
    seeds = [seed, seed + 1, seed + 2]
    many = solve_many(plan, seeds)
    for s, lay in zip(seeds, many, strict=True):
        alone = fl.solve(plan, s)
        assert _poses(lay) == _poses(alone)
        assert lay.report.failures == alone.report.failures
        assert lay.report.steps == alone.report.steps


def test_a_child_draws_the_same_whether_or_not_its_batch_has_parents_at_a_wall():
    """An armchair to the left of another that stands near the door: where the parent stood
    at a wall in some sample of a batch, every sample drew numbers for the spots beside it
    on that wall, and sample 0 got another layout in a batch than alone (found by
    hypothesis)."""
    plan = fl.Plan.from_dict({
        "name": "generated",
        "room": {"polygon": [[0, 0], [4.45, 0], [4.45, 6.0], [0, 6.0]], "height": 2.9,
                 "doors": [{"wall": 3, "offset": 1.4845, "width": 0.85}]},
        "objects": [{"id": f"armchair_{k}", "category": "armchair",
                     "size": [0.64, 0.64, 0.72 if k < 2 else 0.73]} for k in range(3)],
        "rules": [{"rule": "near_door", "object": "armchair_0"},
                  {"rule": "left_of", "object": "armchair_1", "target": "armchair_0"},
                  {"rule": "at_wall", "object": "armchair_1"}]})
    for s, lay in enumerate(solve_many(plan, [0, 1, 2])):
        alone = fl.solve(plan, s)
        assert _poses(lay) == _poses(alone)
        assert lay.report.steps == alone.report.steps


def test_a_plan_with_nothing_on_the_floor_batches():
    plan = {"name": "gallery_wall",
            "room": {"polygon": [[0, 0], [3, 0], [3, 3], [0, 3]]},
            "objects": [{"id": "p", "category": "painting", "size": [0.6, 0.03, 0.4]}],
            "rules": [{"rule": "on_wall", "object": "p"}]}
    many = solve_many(plan, [1, 2, 3])
    assert [_poses(lay) for lay in many] == [_poses(fl.solve(plan, s)) for s in (1, 2, 3)]
    assert all(lay.report.valid for lay in many)
    assert len(fl.generate(plan, 3, seed=1)) == 3
    assert solve_many(plan, []) == []


def test_floor_checks_are_reused_only_within_a_batch():
    """Within reusing_floor_checks a floor checked before is not checked again (same report);
    outside it every call checks afresh, so a plan changed in place is judged as it is now."""
    from forcelayout.validate import checks

    lay = fl.solve("bedroom", 3)
    calls = []
    real = checks._floor_checks

    def counted(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)

    checks._floor_checks = counted
    try:
        first = lay.check()
        second = lay.check()
        assert len(calls) == 2  # no block: nothing reused
        with checks.reusing_floor_checks():
            a, b = lay.check(), lay.check()
            assert len(calls) == 3
            assert a.failures == b.failures == first.failures
            assert (a.free_mask == first.free_mask).all() and a.free_fraction == first.free_fraction
            a.free_mask[:] = False  # a report's arrays are its own
            assert lay.check().free_mask.any()
        lay.check()
        assert len(calls) == 4  # after the block: checked afresh
    finally:
        checks._floor_checks = real
    assert second.failures == first.failures


def test_a_term_without_a_stacked_form_runs_once_per_sample():
    """A user's force term (no ``stack`` method) sees one sample's state at a time."""
    seen = []

    class Pull:
        annealed = False

        def __call__(self, state, temperature):
            seen.append(state.samples)
            f = np.zeros((state.n, 2))
            f[:, 0] = 0.05 * (state.room.centroid[0] - state.pos[:, 0])
            return f, np.zeros(state.n)

    model = ForceModel(fl.load_plan(ROOM))
    model.add_term(Pull())
    pos, yaw = _starts(model, 3)
    stack = model.stacked(3)
    f, _ = stack.net(stack.state(pos.reshape(-1, 2), yaw.reshape(-1)))
    assert seen == [1, 1, 1]
    for b in range(3):
        f1, _ = model.net(model.state(pos[b], yaw[b]))
        assert np.array_equal(f[b * model.n:(b + 1) * model.n], f1)
    together = simulate_batch(model, pos, yaw, SolverConfig(max_steps=20))
    assert [r.steps for r in together] == [simulate(model, pos[b], yaw[b],
                                                    SolverConfig(max_steps=20)).steps
                                           for b in range(3)]


def test_simulations_wait_for_the_samples_still_drawing():
    """A request that waits (a simulation) is answered once no other kind is pending, so
    samples that need one, two or three cheap steps first still simulate in one batch."""
    from forcelayout.batching import drive

    batches: list[tuple[str, int]] = []

    class Cheap:
        wait = False

        def key(self):
            return 0

        @staticmethod
        def run(requests):
            batches.append(("cheap", len(requests)))
            return [None] * len(requests)

    class Sim(Cheap):
        wait = True

        @staticmethod
        def run(requests):
            batches.append(("sim", len(requests)))
            return [len(requests)] * len(requests)

    def task(cheap: int):
        for _ in range(cheap):
            yield Cheap()
        together = yield Sim()
        return together

    assert drive([task(0), task(1), task(3)]) == [3, 3, 3]
    assert batches == [("cheap", 2), ("cheap", 1), ("cheap", 1), ("sim", 3)]


class _Spring:
    """A user's term without ``join``: a pull of each row towards its own point."""

    annealed = True

    def __init__(self, to: np.ndarray):
        self.to = np.asarray(to, dtype=float)

    def __call__(self, state, temperature):
        return 0.2 * temperature * (self.to - state.pos), np.zeros(state.n)


@pytest.mark.parametrize("kind", ["anchor", "plain"])
def test_each_sample_may_have_its_own_terms_and_obstacles(kind):
    """``sample_terms`` / ``sample_obstacles`` give each sample what it gets alone with
    those terms in its model and those obstacles, bit for bit (an ``AnchorTerm``
    joined into one, a term without ``join`` called on its own sample)."""
    from forcelayout.surfaces import AnchorTerm

    plan = fl.load_plan(ROOM)
    base = ForceModel(plan)
    pos, yaw = _starts(base, 4)
    rng = np.random.default_rng(7)
    to = rng.uniform([0.5, 0.5], [4.1, 3.5], (4, base.n, 2))
    terms = [(AnchorTerm(to[b], np.full((base.n, 2), 0.3)) if kind == "anchor"
              else _Spring(to[b]),) for b in range(4)]
    # a small post in some samples' rooms, where no start stands
    post = [np.array([[x, 0.05], [x + 0.1, 0.05], [x + 0.1, 0.15], [x, 0.15]])
            for x in (1.0, 2.0, 3.0)]
    obstacles = [[], post[:1], post, post[1:]]
    cfg = SolverConfig(max_steps=60)
    together = simulate_batch(base, pos, yaw, cfg, sample_terms=terms,
                              sample_obstacles=obstacles)
    # the terms and the obstacles both move some sample
    no_posts = simulate_batch(base, pos, yaw, cfg, sample_terms=terms)
    assert not all(np.array_equal(a.pos, b.pos) for a, b in zip(together, no_posts, strict=True))
    bare = simulate_batch(base, pos, yaw, cfg)
    assert not any(np.array_equal(a.pos, b.pos) for a, b in zip(no_posts, bare, strict=True))
    for b in range(4):
        alone_model = ForceModel(plan, terms=terms[b])
        alone = simulate(alone_model, pos[b], yaw[b], cfg, obstacles=obstacles[b])
        assert np.array_equal(together[b].pos, alone.pos)
        assert np.array_equal(together[b].yaw, alone.yaw)
        assert (together[b].steps, together[b].converged) == (alone.steps, alone.converged)


def test_sample_terms_need_as_many_terms_in_every_sample():
    model = ForceModel(fl.load_plan(ROOM))
    pos, yaw = _starts(model, 2)
    with pytest.raises(ValueError, match="same number of terms"):
        simulate_batch(model, pos, yaw, sample_terms=[(_Spring(pos[0]),), ()])


def test_surfaces_of_a_batch_are_what_each_sample_gets_alone():
    """Walls and ceiling planes of many samples run as batches, each sample with its own
    spots and obstacles; every placement is the one ``place_surfaces`` gives alone."""
    from forcelayout.surfaces import place_surfaces, place_surfaces_batch

    plan = fl.examples.load_example("living_room")
    floors = [lay.poses for lay in solve_many(plan, range(6))]
    floors = [{k: p for k, p in f.items() if p.surface == "floor"} for f in floors]
    batch = place_surfaces_batch(plan, floors, [np.random.default_rng(s) for s in range(6)])
    for s, (floor, got) in enumerate(zip(floors, batch, strict=True)):
        alone = place_surfaces(plan, floor, np.random.default_rng(s))
        assert got.poses == alone.poses
        assert (got.missing, got.steps, got.converged) == (alone.missing, alone.steps,
                                                           alone.converged)
        assert set(got.stages) == {"tops", "walls", "ceiling"}
    assert any(p.surface.startswith("wall") for p in batch[0].poses.values())
    assert any(p.surface == "ceiling" for p in batch[0].poses.values())
