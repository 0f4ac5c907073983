"""The Box2D solver and the force model: annealing, determinism, convergence."""

import numpy as np
import pytest

import forcelayout as fl
from forcelayout.access import AccessTerm
from forcelayout.forces import ForceModel, PassageTerm, PhysicalTerm
from forcelayout.geometry import RoomGeometry
from forcelayout.rules.physical import (
    SWING_MARGIN,
    PhysicalWeights,
    alignment,
    boundary,
    door_clearance,
    repulsion,
)
from forcelayout.solver import SolverConfig, simulate, temperature

ROOM = {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]], "height": 2.7,
        "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}]}


def two_boxes(rules=()):
    return fl.Plan.from_dict({
        "name": "two", "room": ROOM,
        "objects": [{"id": "a", "category": "box", "size": [1.0, 0.5, 0.5]},
                    {"id": "b", "category": "box", "size": [0.6, 0.6, 0.5]}],
        "rules": list(rules)})


def test_temperature_follows_the_paper():
    assert temperature(0) == 1.0
    assert temperature(50, 0.02) == pytest.approx(0.5)
    t = temperature(np.arange(100))
    assert np.all(np.diff(t) < 0)


def test_repulsion_pushes_overlapping_bodies_apart():
    m = ForceModel(two_boxes())
    st = m.state(np.array([[2.0, 1.7], [2.5, 1.7]]), np.zeros(2))
    f, _ = repulsion(st, m.pi, m.pj, PhysicalWeights())
    assert f[0, 0] < 0 < f[1, 0]
    np.testing.assert_allclose(f[0], -f[1])


def test_repulsion_is_short_range():
    m = ForceModel(two_boxes())
    st = m.state(np.array([[1.0, 1.7], [3.0, 1.7]]), np.zeros(2))
    f, _ = repulsion(st, m.pi, m.pj, PhysicalWeights())
    assert np.all(f == 0)


def test_boundary_pushes_inwards_near_a_wall():
    m = ForceModel(two_boxes())
    st = m.state(np.array([[0.52, 1.7], [2.0, 1.7]]), np.zeros(2))
    f, _ = boundary(st, PhysicalWeights())
    assert f[0, 0] > 0
    assert np.all(f[1] == 0)


def test_alignment_settles_at_cardinal_angles():
    m = ForceModel(two_boxes())
    st = m.state(np.zeros((2, 2)) + 1.5, np.array([0.2, np.pi / 2 - 0.2]))
    _, tau = alignment(st, PhysicalWeights())
    assert tau[0] < 0 < tau[1]


def test_same_seed_same_layout_bit_for_bit():
    plan = two_boxes([{"rule": "at_wall", "object": "a"}])
    a = fl.solve(plan, seed=7, check=False)
    b = fl.solve(plan, seed=7, check=False)
    c = fl.solve(plan, seed=8, check=False)
    assert a.poses == b.poses
    assert a.poses != c.poses


def test_simulation_respects_step_cap():
    m = ForceModel(two_boxes())
    res = simulate(m, np.array([[1.0, 1.0], [3.0, 2.5]]), np.array([0.3, 0.1]),
                   SolverConfig(max_steps=5, min_steps=0))
    assert res.steps == 5 and not res.converged


def test_simulation_keeps_bodies_inside_and_apart():
    m = ForceModel(two_boxes())
    res = simulate(m, np.array([[2.0, 1.7], [2.1, 1.8]]), np.array([0.0, 0.5]))
    st = m.state(res.pos, res.yaw)
    assert RoomGeometry.from_room(m.plan.room).contains(st.corners.reshape(-1, 2)).all()
    assert st.gap(np.array([0]), np.array([1]))[0] >= 0.0
    assert st.separation(np.array([0]), np.array([1]))[0] > -0.01


def test_fixed_bodies_do_not_move():
    m = ForceModel(two_boxes([{"rule": "next_to", "object": "b", "target": "a"}]))
    pos = np.array([[1.0, 1.0], [3.0, 2.5]])
    res = simulate(m, pos, np.zeros(2), fixed=np.array([True, False]))
    np.testing.assert_allclose(res.pos[0], pos[0], atol=1e-6)


def test_solver_config_rejects_nonsense():
    with pytest.raises(ValueError):
        SolverConfig(max_steps=0)
    with pytest.raises(ValueError):
        SolverConfig(dt=0)
    with pytest.raises(ValueError):
        SolverConfig(settle_steps=-1)


def test_a_start_that_passes_is_settled_not_rearranged():
    """Samples whose start already passes settle in at most settle_steps floor steps, so a
    run with settling spends fewer floor steps than one that always runs the full
    simulation, and every layout it accepts still passes the checks."""
    plan = fl.load_plan("bedroom")
    seeds = range(8)

    def floor_steps(cfg):
        opts = fl.Options(solver=cfg, repair=0)
        lays = [fl.solve(plan, seed=s, options=opts) for s in seeds]
        return lays, sum(lay.report.steps for lay in lays)

    settled, with_settling = floor_steps(SolverConfig())
    _, without = floor_steps(SolverConfig(settle_steps=0))
    assert with_settling < without
    for lay in settled:
        if lay.report.valid:
            assert lay.check().ok


def test_a_settle_that_does_not_pass_yet_goes_on_once(monkeypatch):
    """A floor still moving that fails when the settle's steps run out settles as many steps
    again; one that passes then is kept as it is."""
    from forcelayout import pipeline, verdict
    from forcelayout.batching import drive
    from forcelayout.initial import propose_poses
    from forcelayout.verdict import FloorVerdict

    model = ForceModel(fl.load_plan("living_room"))
    pos, yaw = propose_poses(model, np.random.default_rng(0))
    yaw = yaw + 0.3  # turned off square: it moves for a while
    opts = fl.Options(solver=SolverConfig(settle_steps=6))
    verdicts = []

    def judge(model, pos, yaw, check_kwargs=None, *, checks=True, blockers=True, walls=True):
        for _ in pos:
            verdicts.append(FloorVerdict() if verdicts else FloorVerdict(["collision: x"], {0}))
        return verdicts[-len(pos):]

    monkeypatch.setattr(verdict, "judge_floors", judge)

    def settle():
        return drive([pipeline._settle(model, model, pos, yaw, opts, 0)])[0]

    res, ok = settle()
    assert ok and len(verdicts) == 2 and 6 < res.steps <= 12
    verdicts[:] = [FloorVerdict()]  # passes at once: one judgement, no more steps
    res, ok = settle()
    assert ok and len(verdicts) == 2 and res.steps <= 6


def test_a_start_nothing_acts_on_is_returned_at_once():
    m = ForceModel(two_boxes())
    pos = np.array([[1.0, 1.7], [3.0, 1.7]])  # square, apart, clear of the walls and the door
    res = simulate(m, pos, np.zeros(2), SolverConfig(min_steps=40))
    assert res.steps == 0 and res.converged
    np.testing.assert_array_equal(res.pos, pos)


def test_a_start_overlapping_an_obstacle_is_simulated():
    m = ForceModel(two_boxes())
    pos = np.array([[1.0, 1.7], [3.0, 1.7]])
    block = np.array([[0.8, 1.5], [1.2, 1.5], [1.2, 1.9], [0.8, 1.9]])  # inside box a
    corner = np.array([[3.5, 3.0], [4.0, 3.0], [4.0, 3.5]])  # clear of both
    res = simulate(m, pos, np.zeros(2), obstacles=[corner])
    assert res.steps == 0
    res = simulate(m, pos, np.zeros(2), obstacles=[block, corner])
    assert res.steps > 0
    assert not np.allclose(res.pos[0], pos[0])


# -- door clearance ---------------------------------------------------------------------------

CORNER_DOOR = {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]], "height": 2.7,
               "doors": [{"wall": 1, "offset": 2.9, "width": 0.8}]}  # east wall, by the corner


def bed_by_the_corner_door(x: float):
    """A 0.9 x 2 m bed with its head at the north wall, ``x`` from the west wall."""
    return fl.Plan.from_dict({
        "name": "bed", "room": CORNER_DOOR,
        "objects": [{"id": "bed", "category": "bed", "size": [0.9, 2.0, 0.5]}],
        "rules": [{"rule": "at_wall", "object": "bed"}]}), np.array([[x, 2.49]]), np.array([np.pi])


def test_door_clearance_moves_a_wall_object_along_its_own_wall():
    # the bed reaches 0.2 m into the door's entry zone from the wall across the door's:
    # it is pushed along the north wall, away from the door, never off that wall
    plan, pos, yaw = bed_by_the_corner_door(2.5)
    m = ForceModel(plan)
    term = next(t for t in m.terms if isinstance(t, PhysicalTerm))
    st = m.state(pos, yaw)
    f, _ = door_clearance(st, PhysicalWeights(), term.slide)
    assert term.slide is not None and term.slide[0]
    assert f[0, 0] < 0 and f[0, 1] == 0.0


def test_settling_keeps_only_the_swing_squares_clear():
    plan, pos, yaw = bed_by_the_corner_door(2.5)  # in the entry zone, clear of the swing
    m = ForceModel(plan)
    quiet = m.settling()
    assert not any(isinstance(t, (PassageTerm, AccessTerm)) for t in quiet.terms)
    full = next(t for t in m.terms if isinstance(t, PhysicalTerm))
    calm = next(t for t in quiet.terms if isinstance(t, PhysicalTerm))
    st = m.state(pos, yaw)
    w = PhysicalWeights()
    assert door_clearance(st, w, full.slide, full.entry)[0][0, 0] < 0
    np.testing.assert_array_equal(door_clearance(st, w, calm.slide, calm.entry)[0], 0.0)
    # within SWING_MARGIN of the swing square it is pushed away all the same
    plan, pos, yaw = bed_by_the_corner_door(3.2 - 0.45 - SWING_MARGIN + 0.01)
    st = ForceModel(plan).state(pos, yaw)
    assert door_clearance(st, w, calm.slide, calm.entry)[0][0, 0] < 0


def test_a_muted_binding_pulls_with_no_weight_and_the_others_as_before():
    plan = two_boxes([{"rule": "near", "object": "a", "target": "b"},
                      {"rule": "at_wall", "object": "b"}])
    m = ForceModel(plan)
    pos, yaw = np.array([[1.0, 1.0], [3.0, 2.5]]), np.zeros(2)
    near = next(g.position for g in m.groups if g.rule.name == "near")
    f_all, _ = m.net(m.state(pos, yaw), annealed=True)
    f_muted, _ = m.muting(near.tolist()).net(m.state(pos, yaw), annealed=True)
    np.testing.assert_array_equal(m.muting([]).net(m.state(pos, yaw), annealed=True)[0], f_all)
    assert np.abs(f_all[0]).max() > 0 and np.abs(f_muted[0]).max() == 0.0  # a: only near
    wall = ForceModel(two_boxes([{"rule": "at_wall", "object": "b"}]))
    f_wall, _ = wall.net(wall.state(pos, yaw), annealed=True)
    np.testing.assert_array_equal(f_muted[1], f_wall[1])  # b: at_wall alone
