"""The rule registry: register/get, lazy discovery, errors with suggestions."""

import subprocess
import sys

import numpy as np
import pytest

from forcelayout import rules
from forcelayout.errors import UnknownRuleError
from forcelayout.rules import Rule, register, unregister

BUILTIN = ["at_wall", "in_corner", "in_middle", "near_window", "near_door", "away_from_door",
           "away_from_window",
           "next_to", "near", "far_from", "facing", "in_front_of", "behind", "left_of",
           "right_of", "aligned_with", "around", "face_same_as", "on_top", "on_wall",
           "on_wall_mid", "above", "on_ceiling"]


def test_builtin_vocabulary_is_registered():
    assert set(BUILTIN) <= set(rules.available_rules())


def test_pattern_filter():
    assert set(rules.available_rules("near*")) >= {"near", "near_window", "near_door"}
    assert all(n.startswith("on_") for n in rules.available_rules("on_*"))


def test_describe_lists_every_rule_with_its_doc():
    infos = {i.name: i for i in rules.describe_rules()}
    for name in BUILTIN:
        assert infos[name].summary, f"{name} has no docstring"
        assert infos[name].kind in {"unary", "binary", "surface"}


def test_unknown_rule_is_lookup_error_with_suggestion():
    with pytest.raises(LookupError) as e:
        rules.get_rule("nex_to")
    assert isinstance(e.value, UnknownRuleError)
    assert "Did you mean 'next_to'" in str(e.value)
    assert not str(e.value).startswith("'")  # not quoted like a KeyError


def test_register_decorator_and_duplicates():
    @register("stay_put_test")
    class StayPut(Rule):
        """Apply no force; always satisfied."""

        def force(self, state, i, j, p):
            return np.zeros((len(i), 2)), np.zeros(len(i))

        def satisfied(self, state, i, j, p):
            return np.ones(len(i), dtype=bool)

    try:
        assert rules.get_rule("stay_put_test").name == "stay_put_test"
        with pytest.raises(ValueError, match="already registered"):
            register("stay_put_test")(type("Other", (Rule,), {}))
        register("stay_put_test", replace=True)(type("Other", (Rule,), {"__doc__": "x"}))
        assert type(rules.get_rule("stay_put_test")).__name__ == "Other"
    finally:
        unregister("stay_put_test")
    assert "stay_put_test" not in rules.available_rules()


def test_register_rejects_non_rules_and_bad_names():
    with pytest.raises(TypeError):
        register("not_a_rule", object)  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        register("bad name")


def test_import_forcelayout_loads_no_rule_module():
    code = ("import sys, forcelayout; "
            "mods = [m for m in sys.modules if m.startswith('forcelayout.rules.')]; "
            "print(sorted(mods))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert "unary" not in out and "binary" not in out and "surface" not in out
