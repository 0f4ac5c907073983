"""Relax a plan whose rules no layout meets: a short trial run, then drop the rules it misses.

A plan can be valid and free of the contradictions :mod:`forcelayout.sanity`
finds, and still yield nothing: every object ``near`` every other one in a
small room, two corner objects that must also stand ``next_to`` each other,
thirty rules of which 95 % must hold at once. Such plans come from small
language models above all. :func:`relax` finds out by trying: it generates a
few samples and, while too few are accepted because rules are missed, drops
the floor rules the failed samples miss most often and tries again. Surface
rules (``on_top``, ``on_wall``, ...) are kept, so no object loses its
support; every rule dropped is reported with how often it was missed.

Examples
--------
>>> import forcelayout as fl
>>> from forcelayout.relax import relax
>>> plan, notes = relax(fl.load_plan("bedroom"))   # doctest: +SKIP
>>> notes                                          # doctest: +SKIP
[]
"""

from __future__ import annotations

import json
import warnings
from collections import Counter
from typing import Any

from forcelayout import rules as registry
from forcelayout.diagnose import missed_rules
from forcelayout.plan import Plan

__all__ = ["relax", "TRIAL_SAMPLES", "TRIAL_LAYOUTS", "TRIAL_ROUNDS"]

#: Samples of one trial run.
TRIAL_SAMPLES = 12
#: Layouts a trial run must accept for the plan to stand as it is.
TRIAL_LAYOUTS = 3
#: Most trial runs (each after the first drops rules).
TRIAL_ROUNDS = 4
#: Most rules dropped after one trial run.
_PER_ROUND = 3


def _droppable(name: str) -> bool:
    """Floor rules may go; surface rules (an object's support) stay."""
    return registry.is_registered(name) and registry.get_rule(name).kind != "surface"


def _missed(reports: list[Any]) -> Counter[str]:
    """How many failed samples miss each rule binding."""
    return Counter(b for r in reports for b in missed_rules(r.failures))


def relax(plan: Plan, *, samples: int = TRIAL_SAMPLES, wanted: int = TRIAL_LAYOUTS,
          rounds: int = TRIAL_ROUNDS, seed: int = 1, **generate_kwargs: Any
          ) -> tuple[Plan, list[str]]:
    """Drop the floor rules that keep a plan from yielding layouts, found by trial runs.

    Each round generates up to ``samples`` samples (stopping once ``wanted``
    are accepted). If fewer are accepted and missed rules are among the
    reasons, the droppable rules missed by at least half of the failed
    samples (at least the one missed most often, at most three) are removed,
    and the next round tries the lighter plan.

    Parameters
    ----------
    plan : Plan
        A valid plan.
    samples : int, default TRIAL_SAMPLES
        Samples of one trial run.
    wanted : int, default TRIAL_LAYOUTS
        Accepted layouts that make the plan stand.
    rounds : int, default TRIAL_ROUNDS
        Most trial runs.
    seed : int, default 1
        Seed of the trial runs (the same plan and seed relax the same way); not
        :func:`~forcelayout.generate`'s default 0, so the trial does not pick the
        very samples a later run with that seed draws.
    **generate_kwargs
        Passed to :func:`forcelayout.generate` (e.g. ``options``).

    Returns
    -------
    (Plan, list of str)
        The plan (the same object if nothing was dropped) and one note per
        rule dropped, plus one if the last trial still accepted too few.
    """
    from forcelayout.sampling import generate

    if samples < 1 or wanted < 1 or rounds < 1:
        raise ValueError(f"samples={samples}, wanted={wanted}, rounds={rounds}: give "
                         "positive numbers")
    notes: list[str] = []
    current = plan
    for number in range(1, rounds + 1):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            gen = generate(current, wanted, max_attempts=samples, seed=seed, **generate_kwargs)
        if len(gen) >= wanted:
            return current, notes
        failed = [r for r in gen.reports if not r.valid]
        missed = _missed(failed)
        keys = {r.label: r for r in current.rules if _droppable(r.rule)}
        ranked = [(b, k) for b, k in missed.most_common() if b in keys]
        drop = [b for b, k in ranked if 2 * k >= len(failed)][:_PER_ROUND] or \
            [b for b, _ in ranked[:1]]
        if not drop or number == rounds:
            notes.append(f"trial {number}: {len(gen)} of {wanted} layouts from {len(gen.reports)} "
                         f"samples; " + ("nothing more to drop" if not drop else
                                         "no rounds left"))
            return current, notes
        data = json.loads(current.to_json())
        gone = {id(keys[b]) for b in drop}
        data["rules"] = [d for r, d in zip(current.rules, data["rules"], strict=True)
                         if id(r) not in gone]
        for b in drop:
            notes.append(f"removed {b}: trial {number} missed it in {missed[b]} of "
                         f"{len(failed)} failed samples")
        current = Plan.from_dict(data)
    return current, notes
