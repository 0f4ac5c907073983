"""Ablations of a plan used in the paper's evaluation (−Decor, −Relations)."""

from __future__ import annotations

from forcelayout import rules as registry
from forcelayout.plan import Plan

__all__ = ["without_decor", "without_relations"]


def without_decor(plan: Plan) -> Plan:
    """The plan minus its secondary (``decor``) objects and every rule naming them."""
    keep = {o.id for o in plan.objects if not o.decor}
    if len(keep) == len(plan.objects):
        return plan
    data = plan.model_dump()
    data["objects"] = [o for o in data["objects"] if o["id"] in keep]
    data["rules"] = [r for r in data["rules"]
                     if r["object"] in keep and (r["target"] is None or r["target"] in keep
                                                 or r["target"] in {a.name for a in plan.areas})]
    data["name"] = f"{plan.name}-decor"
    return Plan.from_dict(data)


def without_relations(plan: Plan) -> Plan:
    """The plan with weight 0 on every object-object (binary) rule.

    The objects are still simulated together; only the forces that define
    their relative arrangement are gone.
    """
    data = plan.model_dump()
    for r in data["rules"]:
        if registry.get_rule(r["rule"]).kind == "binary":
            r["weight"] = 0.0
    data["name"] = f"{plan.name}-relations"
    return Plan.from_dict(data)
