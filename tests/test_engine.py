"""The engine asks rules what they mean: compiled plans, force terms, plugins as built-ins."""

from __future__ import annotations

import ast
import warnings
from importlib.metadata import EntryPoint
from pathlib import Path

import networkx as nx
import numpy as np
import pytest

import forcelayout as fl
from forcelayout import rules as registry
from forcelayout.bindings import compile_plan
from forcelayout.forces import ForceModel
from forcelayout.rules import ParamArrays, Rule, StartHint, State
from forcelayout.rules.unary import InCorner
from forcelayout.solver import simulate

SRC = Path(__file__).resolve().parents[1] / "src" / "forcelayout"


# -- one force entry point ------------------------------------------------------------------


class Push:
    """A constant push along +x on every object."""

    annealed = False

    def __init__(self, strength: float):
        self.strength = strength
        self.calls = 0

    def __call__(self, state, temperature):
        self.calls += 1
        f = np.zeros((state.n, 2))
        f[:, 0] = self.strength
        return f, np.zeros(state.n)


def _two_boxes() -> fl.Plan:
    return fl.Plan.from_dict({
        "name": "two", "room": {"polygon": [[0, 0], [6, 0], [6, 4], [0, 4]]},
        "objects": [{"id": "a", "category": "box", "size": [0.5, 0.5, 0.5]},
                    {"id": "b", "category": "box", "size": [0.5, 0.5, 0.5]}]})


def test_an_added_term_is_summed_by_net_and_moves_the_objects():
    plan = _two_boxes()
    start = np.array([[1.0, 1.0], [1.0, 3.0]])
    plain = simulate(ForceModel(plan), start, np.zeros(2))
    push = Push(0.8)
    model = ForceModel(plan)
    model.add_term(push)
    f0, _ = ForceModel(plan).net(model.state(start, np.zeros(2)))
    f1, _ = model.net(model.state(start, np.zeros(2)))
    np.testing.assert_allclose(f1[:, 0] - f0[:, 0], 0.8)
    pushed = simulate(model, start, np.zeros(2))
    assert push.calls == pushed.steps + 1  # a physical term: every step (and net() above)
    assert (pushed.pos[:, 0] > plain.pos[:, 0] + 1.0).all()  # pushed towards the +x wall


def test_annealed_terms_are_sampled_every_semantic_interval():
    plan = _two_boxes()
    push = Push(0.0)
    push.annealed = True
    model = ForceModel(plan, terms=[push])
    cfg = fl.SolverConfig(semantic_interval=3, min_steps=30, max_steps=30)
    # a turned box is not at rest, so the simulation runs its steps
    simulate(model, np.array([[1.0, 1.0], [4.0, 3.0]]), np.array([0.3, 0.0]), cfg)
    assert push.calls == 10


def test_a_term_needs_an_annealed_flag():
    with pytest.raises(TypeError, match="annealed"):
        ForceModel(_two_boxes(), terms=[lambda state, t: (None, None)])


@pytest.mark.parametrize("seed", range(6))
def test_a_painting_above_the_bed_ends_centred_over_it(seed):
    """Centred over the bed; beside the window instead where a window is above the bed."""
    layout = fl.solve("bedroom", seed)
    plan = layout.plan
    bed, art = layout.poses["bed"], layout.poses["painting"]
    assert art.surface.startswith("wall:")
    wall = int(art.surface.split(":")[1])
    t = layout.room.tangent[wall]
    offset = (art.x - bed.x) * t[0] + (art.y - bed.y) * t[1]
    half_bed = 0.5 * plan.object("bed").size[0]
    half_art = 0.5 * plan.object("painting").size[0]
    windows = layout.room.windows
    above_bed = [k for k in range(len(windows)) if windows.wall[k] == wall
                 and abs((windows.centre[k] - [bed.x, bed.y]) @ t) < half_bed
                 + 0.5 * windows.width[k]]
    if not above_bed:
        assert abs(offset) <= 0.05
    else:  # within the bed's extent, clear of the window
        assert abs(offset) <= half_bed
        for k in above_bed:
            along = (np.array([art.x, art.y]) - windows.centre[k]) @ t
            assert abs(along) >= 0.5 * windows.width[k] + half_art - 1e-6


# -- a plan compiled once -------------------------------------------------------------------


def test_compiled_plan_resolves_every_binding_once():
    plan = fl.load_plan("living_room")
    cp = compile_plan(plan)
    assert compile_plan(plan) is cp
    assert len(cp.bindings) == len(plan.rules)
    assert [b.index for b in cp.bindings] == list(range(len(plan.rules)))
    assert set(cp.floor_ids) == {o.id for o in plan.floor_objects()}
    for b in cp.bindings:
        assert isinstance(b.params, b.rule.Params)


# -- plugins are as capable as built-ins ----------------------------------------------------


class _Corner(Rule):
    """Test plugin: start tucked into a corner; no force of its own."""

    start = StartHint(place="corner")

    def force(self, state: State, i, j, p: ParamArrays):
        return np.zeros((len(i), 2)), np.zeros(len(i))

    def satisfied(self, state: State, i, j, p: ParamArrays):
        return InCorner().satisfied(state, i, j, ParamArrays(
            {"tolerance": np.full(len(i), 0.05)}, p.weight))


class _LowShelf(Rule):
    """Test plugin: hang on a wall between 0.2 m and 1.0 m."""

    surface = "wall"

    class Params(Rule.Params):
        low: float = 0.2
        high: float = 1.0

    def force(self, state, i, j, p):
        return np.zeros((len(i), 2)), np.zeros(len(i))

    def satisfied(self, state, i, j, p):
        z = state.z[i]
        return np.array([s.startswith("wall:") for s in (state.surfaces[r] for r in i)]) \
            & (z >= 0.2 - 1e-6) & (z + state.size[i, 2] <= 1.0 + 1e-6)


class _Perched(Rule):
    """Test plugin: rest on the target's top."""

    surface = "top"
    target = "required"
    bond = True

    def force(self, state, i, j, p):
        return np.zeros((len(i), 2)), np.zeros(len(i))

    def satisfied(self, state, i, j, p):
        return np.array([state.surfaces[a] == state.ids[b] for a, b in zip(i, j, strict=True)])


@pytest.fixture
def plugins():
    registry.register("test_tucked", _Corner)
    registry.register("test_low_shelf", _LowShelf)
    registry.register("test_perched", _Perched)
    yield
    for name in ("test_tucked", "test_low_shelf", "test_perched"):
        registry.unregister(name)


def _plugin_plan() -> fl.Plan:
    return fl.Plan.from_dict({
        "name": "plugins",
        "room": {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]],
                 "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}]},
        "objects": [
            {"id": "plant", "category": "plant", "size": [0.4, 0.4, 1.0]},
            {"id": "desk", "category": "desk", "size": [1.2, 0.6, 0.75]},
            {"id": "shelf", "category": "shelf", "size": [0.8, 0.25, 0.3]},
            {"id": "cup", "category": "cup", "size": [0.1, 0.1, 0.1]},
        ],
        "rules": [{"rule": "test_tucked", "object": "plant"},
                  {"rule": "at_wall", "object": "desk"},
                  {"rule": "test_low_shelf", "object": "shelf"},
                  {"rule": "test_perched", "object": "cup", "target": "desk"}],
    })


def test_plugin_rules_get_start_hints_and_surfaces(plugins):
    plan = _plugin_plan()
    assert plan.surface_of("shelf") == "test_low_shelf"
    assert [o.id for o in plan.floor_objects()] == ["plant", "desk"]
    from forcelayout.hierarchy import scene_graph

    graph = scene_graph(plan)
    assert graph.edges["desk", "cup"]["strong"]
    met = []
    for seed in range(5):
        layout = fl.solve(plan, seed)
        assert layout.poses["shelf"].surface.startswith("wall:")
        assert layout.poses["cup"].surface == "desk"
        met.append([r.satisfied for r in layout.rule_report()])
    assert all(all(m) for m in met), met  # the plant starts, and stays, in a corner


def test_plan_validation_asks_the_rule_about_targets(plugins):
    d = _plugin_plan().model_dump()
    d["rules"][0]["target"] = "desk"  # test_tucked takes no target
    d["rules"][3]["target"] = None  # test_perched needs one
    with pytest.raises(fl.PlanError) as e:
        fl.Plan.from_dict(d)
    text = str(e.value)
    assert "'test_tucked' takes no target" in text
    assert "'test_perched' relates two objects" in text


def test_rules_written_for_the_first_release_keep_working():
    class Old(Rule):
        kind = "binary"

    assert Old.target == "required" and Old.kind == "binary"
    with pytest.raises(TypeError, match="surface = 'top', 'wall' or 'ceiling'"):
        class OldSurface(Rule):  # noqa: F841 - the class statement itself raises
            kind = "surface"


def test_an_entry_point_shadowing_a_registered_rule_warns(monkeypatch):
    fake = EntryPoint(name="at_wall", value="someplugin.rules:AtWall",
                      group=registry.ENTRY_POINT_GROUP)
    monkeypatch.setattr(registry, "entry_points", lambda group: [fake])
    monkeypatch.setattr(registry, "_entry_points_loaded", False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        registry.available_rules()
    msgs = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert any("'at_wall'" in m and "someplugin.rules:AtWall" in m and "forcelayout" in m
               for m in msgs), msgs
    assert registry.get_rule("at_wall").__class__.__module__ == "forcelayout.rules.unary"


# -- architecture ---------------------------------------------------------------------------


def _module_name(path: Path) -> str:
    rel = path.relative_to(SRC.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def test_no_import_cycles_among_modules():
    """Module-level imports of src/forcelayout form a directed acyclic graph."""
    graph = nx.DiGraph()
    for path in SRC.rglob("*.py"):
        mod = _module_name(path)
        graph.add_node(mod)
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:  # module level only; imports inside functions are lazy
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                if node.module.startswith("forcelayout"):
                    for alias in node.names:
                        sub = f"{node.module}.{alias.name}"
                        target = sub if (SRC.parent / (sub.replace(".", "/") + ".py")).exists() \
                            or (SRC.parent / sub.replace(".", "/")).is_dir() else node.module
                        if target != mod:
                            graph.add_edge(mod, target)
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name.startswith("forcelayout") and alias.name != mod:
                        graph.add_edge(mod, alias.name)
    # a package's __init__ importing its own submodules is not a cycle
    edges = [(a, b) for a, b in graph.edges if not b.startswith(a + ".")]
    dag = nx.DiGraph(edges)
    cycles = list(nx.simple_cycles(dag))
    assert not cycles, f"import cycles: {cycles[:3]}"


def test_no_built_in_rule_names_outside_the_rules_package():
    names = set(registry.builtin_rules())
    allowed = {"llm/prompts.py", "llm/steps.py"}  # prompt examples for the model
    offenders = []
    for path in SRC.rglob("*.py"):
        rel = path.relative_to(SRC).as_posix()
        if rel.startswith("rules/") or rel in allowed:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        docstrings = {id(n.body[0].value) for n in ast.walk(tree)
                      if isinstance(n, ast.Module | ast.ClassDef | ast.FunctionDef)
                      and n.body and isinstance(n.body[0], ast.Expr)
                      and isinstance(n.body[0].value, ast.Constant)}
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) \
                    and node.value in names and id(node) not in docstrings:
                offenders.append(f"{rel}:{node.lineno} {node.value!r}")
    assert not offenders, offenders


def test_a_rule_group_judges_every_sample_of_a_stacked_state_as_each_alone():
    """RuleGroup.satisfied_stacked: one call for all samples, the verdicts of each alone,
    for a batched rule and for one that is judged sample by sample."""
    import numpy as np

    from forcelayout.bindings import group_bindings
    from forcelayout.forces import ForceModel
    from forcelayout.initial import initial_poses

    model = ForceModel(fl.load_plan("bedroom"))
    starts = [initial_poses(model, np.random.default_rng(s)) for s in range(3)]
    alone = [model.state(p, y) for p, y in starts]
    stacked = model.stacked(3).state(np.concatenate([p for p, _ in starts]),
                                     np.concatenate([y for _, y in starts]))
    row = {oid: k for k, oid in enumerate(model.ids)}
    for g in group_bindings(model.bindings, row):
        for batched in (True, False):
            g.rule.batched, was = batched, g.rule.batched
            try:
                got = g.satisfied_stacked(stacked)
            finally:
                g.rule.batched = was
            assert got.shape == (3, len(g.i))
            for b, st in enumerate(alone):
                assert np.array_equal(got[b], g.satisfied(st))
