"""Rule plugins for real: the entry-point package in examples/plugin and examples/02."""

import os
import subprocess
import sys
from importlib.metadata import PackageNotFoundError, distribution
from pathlib import Path

import pytest

import forcelayout as fl
from forcelayout.testing import check_rule

ROOT = Path(__file__).parent.parent
try:
    distribution("forcelayout-plant-rules")
    INSTALLED = True
except PackageNotFoundError:
    INSTALLED = False
needs_plugin = pytest.mark.skipif(
    not INSTALLED, reason="example plugin not installed: pip install -e examples/plugin")

PLAN = {
    "name": "reading_corner",
    "room": {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]], "height": 2.7,
             "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}]},
    "objects": [{"id": "ficus", "category": "plant", "size": [0.5, 0.5, 1.4]},
                {"id": "armchair", "category": "armchair", "size": [0.8, 0.8, 0.9]}],
    "rules": [{"rule": "in_corner", "object": "ficus"},
              {"rule": "near_plant", "object": "armchair", "target": "ficus"}],
}


@needs_plugin
def test_entry_point_rule_is_found_by_name_without_importing_it_first():
    code = (
        "import sys, forcelayout\n"
        "from forcelayout import rules\n"
        "assert 'forcelayout_plant_rules' not in sys.modules\n"
        "print('near_plant' in rules.available_rules())\n"
        "print('forcelayout_plant_rules' in sys.modules)\n"
        "rule = rules.get_rule('near_plant')\n"
        "print(rule.kind, type(rule).__module__)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split("\n")
    # listed without importing the plugin; imported on first use
    assert out[:3] == ["True", "False", "binary forcelayout_plant_rules"]


@needs_plugin
def test_plan_with_the_plugin_rule_validates_and_solves():
    plan = fl.Plan.from_dict(PLAN)
    met = [fl.solve(plan, seed, check=False).rule_report()[1].satisfied for seed in range(3)]
    assert sum(met) >= 2, met


@needs_plugin
def test_plugin_rule_conforms_and_is_described():
    check_rule("near_plant", n_states=5)
    info = {i.name: i for i in fl.rules.describe_rules("near_plant")}["near_plant"]
    assert info.summary.startswith("Beside a potted plant")
    assert "distance" in info.params
    assert info.package == "forcelayout-plant-rules"  # not mistaken for a built-in
    assert {i.package for i in fl.rules.describe_rules("near*") if i.name != "near_plant"} \
        == {"forcelayout"}


def test_the_rules_listing_marks_plugin_rules_with_their_package(capsys):
    from forcelayout.cli import main

    assert main(["rules", "near*"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [ln for ln in lines if "(plugin: " in ln] == \
        [ln for ln in lines if ln.startswith("near_plant")]
    assert lines[[ln.split()[0] for ln in lines].index("near_plant")].endswith(
        "(plugin: forcelayout-plant-rules)")


def test_unknown_plugin_rule_suggests_installing_or_registering():
    bad = dict(PLAN, rules=[{"rule": "near_plnt", "object": "armchair", "target": "ficus"}])
    with pytest.raises(fl.PlanError, match="unknown rule 'near_plnt'"):
        fl.Plan.from_dict(bad)


def test_custom_rule_example_runs(tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "02_custom_rule.py")],
                          cwd=tmp_path, capture_output=True, text=True, timeout=300, env=env)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "look_out_window(armchair): met" in proc.stdout


def _broken(kind: str):
    """A plugin rule (turns its object to face +y) broken in one way."""
    import numpy as np

    from forcelayout.rules import Rule

    class Broken(Rule):
        """Faces +y, broken."""

        target = "none"
        batched = True

        def force(self, state, i, j, p):
            err = np.arctan2(state.front[i, 0], state.front[i, 1])  # minus the heading
            tau = np.clip(err, -1.0, 1.0)  # err = -yaw: turns back to yaw 0
            if kind == "shape":
                return np.zeros(len(i)), tau  # F of shape (B,)
            if kind == "nan":
                return np.zeros((len(i), 2)) * np.nan, tau
            if kind == "sign":
                return np.zeros((len(i), 2)), -tau  # turns away
            return np.zeros((len(i), 2)), tau

        def satisfied(self, state, i, j, p):
            err = np.abs(np.arctan2(state.front[i, 0], state.front[i, 1]))
            return err if kind == "float" else err <= np.radians(20)

    Broken.name = f"faces_north_{kind}"
    return Broken


@pytest.mark.parametrize("kind, says", [
    ("float", r"satisfied\(\) must return a bool array of shape \(\d+,\), got float64"),
    ("shape", r"force\(\) returned F of shape \(\d+,\) and tau"),
    ("nan", r"force\(\) returned non-finite values"),
])
def test_a_plugin_rule_that_returns_the_wrong_thing_is_named_while_sampling(kind, says):
    """Not a rule reported met that is not, a broadcast error or a failure of geometry
    far away: the rule, what it returned and what it should."""
    from forcelayout.errors import RuleOutputError
    from forcelayout.rules import register, unregister

    name = f"faces_north_{kind}"
    register(name)(_broken(kind))
    try:
        plan = {**PLAN, "rules": [{"rule": name, "object": "armchair"}]}
        with pytest.raises(RuleOutputError, match=f"rule '{name}': {says}"):
            fl.generate(plan, 2, seed=0)
    finally:
        unregister(name)


def test_check_rule_catches_a_torque_that_turns_the_wrong_way():
    from forcelayout.testing import RuleConformanceError

    check_rule(_broken("ok"), n_states=20)
    with pytest.raises(RuleConformanceError, match="pass less often"):
        check_rule(_broken("sign"), n_states=20)
