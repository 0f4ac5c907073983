"""forcelayout: one declarative scene plan, many physically valid room layouts."""

from forcelayout.errors import PlanError, Problem, UnknownRuleError
from forcelayout.plan import Plan, load_plan

__all__ = ["Plan", "load_plan", "PlanError", "Problem", "UnknownRuleError"]
__version__ = "0.1.0"
