"""Cost of telling layouts apart: the grid index of `generate` against comparing every pair.

Draws ``--n`` random layouts of a plan (every object anywhere in the room's
bounds) and times :class:`forcelayout.sampling.DistinctLayouts` and the plain
all-pairs comparison over them, for each ``n``; prints JSON with the seconds
and the ratio of the largest ``n`` to the smallest (near 10 for 200 -> 2,000
means linear; all pairs grow about 100x).

Usage::

    python benchmarks/distinct.py [--plan bedroom] [--n 200 2000] [--tol 0.05]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import forcelayout as fl
from forcelayout.layout import Layout, Pose


def random_layouts(plan: fl.Plan, n: int, rng: np.random.Generator) -> list[Layout]:
    lo = np.min(plan.room.polygon, axis=0)
    hi = np.max(plan.room.polygon, axis=0)
    return [Layout(plan, {o.id: Pose(*map(float, rng.uniform(lo, hi)), 0.0)
                          for o in plan.objects}) for _ in range(n)]


def all_pairs(layouts: list[Layout], tol: float) -> int:
    kept: list[np.ndarray] = []
    for lay in layouts:
        v = np.array([[p.x, p.y] for p in lay.poses.values()]).ravel()
        if all(np.abs(v - w).max() >= tol for w in kept):
            kept.append(v)
    return len(kept)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plan", default="bedroom")
    ap.add_argument("--n", type=int, nargs="+", default=[200, 2000])
    ap.add_argument("--tol", type=float, default=0.05)
    args = ap.parse_args()
    plan = fl.load_plan(args.plan)
    rows = []
    for n in args.n:
        layouts = random_layouts(plan, n, np.random.default_rng(n))
        t0 = time.process_time()
        seen = fl.sampling.DistinctLayouts(args.tol)
        kept = sum(seen.add_if_new(lay) for lay in layouts)
        t1 = time.process_time()
        kept_pairs = all_pairs(layouts, args.tol)
        t2 = time.process_time()
        rows.append({"n": n, "distinct": kept, "index_s": round(t1 - t0, 4),
                     "all_pairs_s": round(t2 - t1, 4), "agree": kept == kept_pairs})
    out = {"benchmark": "distinct", "plan": plan.name, "tol": args.tol, "results": rows,
           "index_ratio": round(rows[-1]["index_s"] / max(rows[0]["index_s"], 1e-9), 1),
           "all_pairs_ratio": round(rows[-1]["all_pairs_s"] / max(rows[0]["all_pairs_s"], 1e-9),
                                    1)}
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
