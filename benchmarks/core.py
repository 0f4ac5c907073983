"""Raw-sample quality and speed of the core solver on the bundled plans.

For each plan, draws ``--samples`` raw samples with :func:`forcelayout.solve`
(one process, one core; ``--batch`` at a time, as ``generate`` runs them) and
prints JSON with:

* ``valid_pct`` — samples passing the deterministic checks (and placing
  every object);
* ``rules_pct`` — mean fraction of rule bindings met;
* ``good_pct`` — samples that pass the checks AND meet >= 95 % of their rules
  (the figure the method is judged on);
* ``good_per_second`` — such layouts per second of CPU on one core;
* ``median_steps`` and ``ms_per_sample``;
* ``failures`` — counts of rejection reasons.

Usage::

    python benchmarks/core.py [--samples 40] [--batch 64] [--plans bedroom living_room]
        [--markdown]
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import raw_samples  # noqa: E402

import forcelayout as fl  # noqa: E402


def bench_plan(name: str, samples: int, seed: int, batch: int) -> dict:
    plan = fl.examples.load_example(name)
    fl.solve(plan, seed=10**9)  # warm caches and imports outside the timing
    reports = []
    cpu = 0.0
    for lay, seconds in raw_samples(plan, seed, samples, batch):
        reports.append(lay.report)
        cpu += seconds
    # passes the deterministic checks (every failure other than too few rules met)
    valid = np.array([not [f for f in r.failures if not f.startswith("rules:")]
                      for r in reports])
    rules = np.array([r.rule_satisfaction for r in reports])
    good = valid & (rules >= 0.95)
    reasons = Counter(f.split(":")[0] for r in reports for f in r.failures)
    n_floor = len(plan.floor_objects())
    return {
        "plan": name,
        "objects": len(plan.objects),
        "floor_objects": n_floor,
        "samples": samples,
        "valid_pct": round(100 * valid.mean(), 1),
        "rules_pct": round(100 * rules.mean(), 1),
        "good_pct": round(100 * good.mean(), 1),
        "good_per_second": round(good.sum() / cpu, 2),
        "samples_per_second": round(samples / cpu, 2),
        "ms_per_sample": round(1000 * cpu / samples, 1),
        "median_steps": float(np.median([r.steps for r in reports])),
        "converged_pct": round(100 * np.mean([r.converged for r in reports]), 1),
        "failures": dict(reasons.most_common()),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=40)
    ap.add_argument("--batch", type=int, default=fl.Options().batch,
                    help="samples simulated together (default: as generate runs them)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--plans", nargs="*", default=fl.examples.list_plans())
    ap.add_argument("--markdown", action="store_true", help="also print a Markdown table")
    args = ap.parse_args()
    rows = [bench_plan(p, args.samples, args.seed, args.batch) for p in args.plans]
    print(json.dumps({"benchmark": "core", "forcelayout": fl.__version__, "results": rows},
                     indent=2))
    if args.markdown:
        print("\n| plan | objects | valid % | rules % | valid & ≥95 % rules | per s (1 core) "
              "| median steps |\n|---|---|---|---|---|---|---|")
        for r in rows:
            print(f"| {r['plan']} | {r['objects']} | {r['valid_pct']} | {r['rules_pct']} | "
                  f"{r['good_pct']} | {r['good_per_second']} | {r['median_steps']} |")


if __name__ == "__main__":
    main()
