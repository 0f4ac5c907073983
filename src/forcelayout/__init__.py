"""forcelayout: one declarative scene plan, many physically valid room layouts.

A plan (room + objects + placement rules) is realised by an annealed,
force-directed 2D physics simulation (Box2D) into many distinct layouts that
share the plan's semantics and differ in geometry.

Examples
--------
>>> import forcelayout as fl
>>> plan = fl.examples.load_example("bedroom")
>>> result = fl.generate(plan, 2, seed=0)          # doctest: +SKIP
>>> result[0].picture("bedroom.png")               # doctest: +SKIP
"""

from forcelayout import examples, rules
from forcelayout.dataset import build_dataset
from forcelayout.errors import MissingExtraError, PlanError, Problem, UnknownRuleError
from forcelayout.layout import Layout, Pose, RuleResult, SampleReport
from forcelayout.options import Options, SolverConfig
from forcelayout.plan import Area, Door, Plan, Room, RuleSpec, SceneObject, Window
from forcelayout.sampling import Generation, generate, solve
from forcelayout.sources import load_plan

__all__ = [
    "Plan",
    "Room",
    "Door",
    "Window",
    "SceneObject",
    "RuleSpec",
    "Area",
    "load_plan",
    "Layout",
    "Pose",
    "RuleResult",
    "SampleReport",
    "generate",
    "solve",
    "Generation",
    "build_dataset",
    "Options",
    "SolverConfig",
    "rules",
    "examples",
    "PlanError",
    "Problem",
    "UnknownRuleError",
    "MissingExtraError",
]
__version__ = "0.1.0"

_LAZY = {"metrics", "validate", "render", "testing", "diagnose"}


def __getattr__(name: str):  # submodules loaded on first use: `fl.metrics`, `fl.validate`, ...
    if name in _LAZY:
        import importlib

        return importlib.import_module(f"forcelayout.{name}")
    raise AttributeError(f"module 'forcelayout' has no attribute {name!r}")
