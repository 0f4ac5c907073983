"""A floor arrangement's verdict: the failed checks, the unmet rules, and who is at fault.

Start poses (:mod:`forcelayout.initial`), settling and repair
(:mod:`forcelayout.repair`) all judge a floor the same way:
:func:`judge_floor` runs the deterministic checks on the floor objects and
every floor binding's own check, and names the objects to move.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from forcelayout.forces import ForceModel
from forcelayout.layout import Layout, Pose
from forcelayout.validate import check_layout

__all__ = ["FloorVerdict", "judge_floor", "allowed_misses"]

_QUOTED = re.compile(r"'([^']+)'")


@dataclass
class FloorVerdict:
    """How a floor arrangement fares, and which objects are at fault.

    Attributes
    ----------
    failures : list of str
        Failed checks (``"<check>: ..."``) and unmet bindings (``"rule(object, target)"``).
    at_fault : set of int
        Rows of the objects to move.
    missed : set of int
        Positions of the unmet bindings in the model's ``bindings``; each is
        one of ``failures`` (the rest are failed checks).
    """

    failures: list[str] = field(default_factory=list)
    at_fault: set[int] = field(default_factory=set)
    missed: set[int] = field(default_factory=set)

    @property
    def unmet(self) -> int:
        """How many of ``failures`` are unmet bindings."""
        return len(self.missed)

    @property
    def ok(self) -> bool:
        """Whether nothing failed."""
        return not self.failures

    def passes(self, misses: int = 0) -> bool:
        """Whether every check passed and at most ``misses`` bindings are unmet.

        A sample is accepted when it meets a share of its rules
        (``Options.min_rule_satisfaction``); ``misses`` is how many of the
        plan's bindings that share leaves unmet (see :func:`allowed_misses`).
        """
        return len(self.failures) - self.unmet == 0 and self.unmet <= misses


def allowed_misses(n_bindings: int, min_rule_satisfaction: float) -> int:
    """How many of ``n_bindings`` may be unmet while at least ``min_rule_satisfaction`` are met.

    >>> allowed_misses(20, 0.95), allowed_misses(19, 0.95), allowed_misses(40, 1.0)
    (1, 0, 0)
    """
    if n_bindings <= 0:
        return 0
    return max(0, int(np.floor(n_bindings * (1.0 - min_rule_satisfaction) + 1e-9)))


def judge_floor(model: ForceModel, pos: np.ndarray, yaw: np.ndarray,
                check_kwargs: dict | None = None, *, checks: bool = True) -> FloorVerdict:
    """Check a floor arrangement and name the objects at fault.

    Parameters
    ----------
    model : ForceModel
        The floor simulation's model (rows are the plan's floor objects).
    pos : ndarray, shape (N, 2)
    yaw : ndarray, shape (N,)
    check_kwargs : dict, optional
        Thresholds for :func:`forcelayout.validate.check_layout`.
    checks : bool
        Run the deterministic checks (default); ``False`` judges the rules
        alone (rows that are not objects of the plan, e.g. an area's
        rectangle, cannot be checked).

    Returns
    -------
    FloorVerdict
    """
    row = {oid: r for r, oid in enumerate(model.ids)}
    out = FloorVerdict()
    if checks:
        poses = {oid: Pose(float(p[0]), float(p[1]), float(y))
                 for oid, p, y in zip(model.ids, pos, yaw, strict=True)}
        report = check_layout(Layout(model.plan, poses), **(check_kwargs or {}))
        out.failures += report.failures
        for fail in report.failures:
            check = fail.split(":", 1)[0]
            if check in ("collision", "door", "window", "outside"):
                out.at_fault.update(row[n] for n in _QUOTED.findall(fail) if n in row)
        for blockers in report.blocked_by.values():
            out.at_fault.update(row[n] for n in blockers if n in row)
    met = model.satisfied(model.state(pos, yaw))
    for k, ok in met.items():
        if not ok:
            b = model.bindings[k]
            out.failures.append(str(b))
            out.missed.add(k)
            out.at_fault.add(row[b.object])
    return out
