"""The shape of the paper's Tables I and II on the bundled plans.

For every plan and every condition — **Full** (the method), **-Relations**
(object-object rules switched off), **-Decor** (secondary objects removed)
and **Random** (random poses and cardinal yaws, draws rejected while they
leave the room or overlap earlier objects, judged by the same checks) — draws
``--n`` raw samples with the same seeds and reports, with bootstrap 95 %
confidence intervals that resample plans:

* ``validity_pct`` — samples passing the deterministic checks;
* ``rules_pct`` — mean fraction of rule bindings met;
* ``good_pct`` — samples that are valid AND meet >= 95 % of their rules;
* ``valid_per_s`` / ``good_per_s`` — such layouts per CPU second (per core);
* ``geometric_intra`` / ``topological_intra`` / ``relational_intra`` —
  mean dissimilarity over all pairs of (at most ``--pairs-of``) valid layouts
  of one plan;

plus ``inter_plan``: the three dissimilarities between the first valid Full
layout of each plan. Timings are CPU seconds of the process that drew the
sample, so ``--jobs`` changes the wall time but not the per-core figures.

Usage::

    python benchmarks/paper_tables.py                 # all plans, n=100, ~3 min on 2 cores
    python benchmarks/paper_tables.py --quick         # n=8, < 1 min on one core
    python benchmarks/paper_tables.py --markdown --png tables.png --out tables.json

Prints JSON to stdout; ``--markdown`` adds the two tables after it.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _common as C  # noqa: E402

import forcelayout as fl  # noqa: E402
from forcelayout import metrics  # noqa: E402

METRICS = ("validity_pct", "rules_pct", "good_pct", "valid_per_s", "good_per_s",
           "geometric_intra", "topological_intra", "relational_intra")


def plan_row(name: str, samples: list[C.Sample], pairs_of: int) -> dict[str, Any]:
    """Per-plan figures of one condition."""
    valid = [s for s in samples if s.valid]
    cpu = float(sum(s.cpu_seconds for s in samples))
    keep = [s.layout for s in valid[:pairs_of]]
    row: dict[str, Any] = {
        "plan": name,
        "samples": len(samples),
        "objects": len(samples[0].layout.plan.objects) if samples else 0,
        "validity_pct": 100 * metrics.validity_rate([s.valid for s in samples]),
        "rules_pct": 100 * metrics.rule_satisfaction_rate([s.rule_satisfaction for s in samples]),
        "good_pct": 100 * float(np.mean([s.good for s in samples])),
        "valid_per_s": metrics.throughput(len(valid), cpu),
        "good_per_s": metrics.throughput(sum(s.good for s in samples), cpu),
        "ms_per_sample": 1000 * cpu / max(len(samples), 1),
    }
    for m in ("geometric", "topological", "relational"):
        row[f"{m}_intra"] = metrics.intra_plan(keep, m)
    failures: dict[str, int] = {}
    for s in samples:
        for f in s.failures:
            key = f.split(":")[0]
            failures[key] = failures.get(key, 0) + 1
    row["failures"] = dict(sorted(failures.items(), key=lambda kv: -kv[1]))
    return row


def summarise(rows: list[dict[str, Any]], samples: list[list[C.Sample]], resamples: int,
              seed: int) -> dict[str, Any]:
    """One condition across plans: estimates with CIs resampling plans."""
    out: dict[str, Any] = {"samples": int(sum(len(s) for s in samples))}
    per_sample = {
        "validity_pct": [[100.0 * x.valid for x in s] for s in samples],
        "rules_pct": [[100.0 * x.rule_satisfaction for x in s] for s in samples],
        "good_pct": [[100.0 * x.good for x in s] for s in samples],
    }
    for k, groups in per_sample.items():
        out[k] = C.ci(groups, within=True, resamples=resamples, seed=seed)
    for k in METRICS[3:]:
        out[k] = C.ci([r[k] for r in rows], within=False, resamples=resamples, seed=seed)
    out["per_plan"] = rows
    return out


def inter_plan(first: list[fl.Layout]) -> dict[str, Any]:
    """Dissimilarities between the first valid Full layouts of different plans."""
    if len(first) < 2:
        return {"plans": len(first)}
    out: dict[str, Any] = {"plans": len(first)}
    for m in ("geometric", "topological", "relational"):
        d = metrics.pairwise(first, m)
        vals = d[np.triu_indices(len(first), 1)]
        out[m] = {"estimate": float(vals.mean()), "min": float(vals.min()),
                  "max": float(vals.max())}
    return out


def markdown(result: dict[str, Any]) -> str:
    conds = result["conditions"]
    lines = ["", "Table I — relational forces", "",
             "| condition | validity % | rules met % | valid & rules ≥95 % |", "|---|---|---|---|"]
    for c in ("Full", "-Relations"):
        if c in conds:
            r = conds[c]
            lines.append(f"| {c} | {C.fmt(r['validity_pct'], 1)} | {C.fmt(r['rules_pct'], 1)} "
                         f"| {C.fmt(r['good_pct'], 1)} |")
    lines += ["", "Table II — decor, Random baseline", "",
              "| condition | validity % | good / s / core | valid / s / core "
              "| geometric (intra) | topological (intra) |", "|---|---|---|---|---|---|"]
    for c in ("Full", "-Decor", "Random", "-Relations"):
        if c in conds:
            r = conds[c]
            lines.append(f"| {c} | {C.fmt(r['validity_pct'], 1)} | {C.fmt(r['good_per_s'], 1)} | "
                         f"{C.fmt(r['valid_per_s'], 1)} | {C.fmt(r['geometric_intra'])} | "
                         f"{C.fmt(r['topological_intra'])} |")
    inter = result.get("inter_plan", {})
    if "geometric" in inter:
        lines += ["", f"Inter-plan ({inter['plans']} plans, first valid Full layout each): "
                  f"geometric {inter['geometric']['estimate']:.2f}, topological "
                  f"{inter['topological']['estimate']:.2f}, relational "
                  f"{inter['relational']['estimate']:.2f}"]
    return "\n".join(lines)


def chart(result: dict[str, Any], path: str) -> None:
    """Bar chart per figure, one bar per condition, whiskers at the CI."""
    conds = list(result["conditions"])
    panels = [("validity_pct", "valid %"), ("rules_pct", "rules met %"),
              ("good_per_s", "good layouts / s / core"), ("geometric_intra", "geometric (intra)"),
              ("topological_intra", "topological (intra)"),
              ("relational_intra", "relational (intra)")]
    fig = C.new_figure(11, 6)
    colors = ["#2b6cb0", "#dd6b20", "#38a169", "#718096"]
    for k, (key, title) in enumerate(panels):
        ax = fig.add_subplot(2, 3, k + 1)
        est, lo, hi = [], [], []
        for c in conds:
            d = result["conditions"][c][key]
            e = d.get("estimate")
            est.append(np.nan if e is None else e)
            lo.append(np.nan if d.get("low") is None or e is None else e - d["low"])
            hi.append(np.nan if d.get("high") is None or e is None else d["high"] - e)
        x = np.arange(len(conds))
        ax.bar(x, np.nan_to_num(est), color=colors[: len(conds)],
               yerr=np.nan_to_num(np.array([lo, hi])), capsize=3)
        ax.set_xticks(x, conds, fontsize=8)
        ax.set_title(title, fontsize=9)
    fig.suptitle(f"forcelayout {fl.__version__}: {', '.join(result['config']['plans'])} "
                 f"(n={result['config']['n']} per plan, 95 % CI over plans)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=None, help="raw samples per plan and condition "
                    "(default 100, 8 with --quick)")
    ap.add_argument("--quick", action="store_true", help="small run, under a minute on one core")
    ap.add_argument("--plans", nargs="*", default=None,
                    help="bundled plan names or plan JSON paths (default: all bundled plans)")
    ap.add_argument("--conditions", nargs="*", default=list(C.CONDITIONS),
                    choices=list(C.CONDITIONS))
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=None,
                    help="worker processes (default: available cores, at most 2)")
    ap.add_argument("--resamples", type=int, default=10_000, help="bootstrap resamples")
    ap.add_argument("--pairs-of", type=int, default=None, help="valid layouts per plan used "
                    "for the intra-plan dissimilarities (default 30, 8 with --quick)")
    ap.add_argument("--markdown", action="store_true", help="also print Markdown tables")
    ap.add_argument("--png", metavar="PATH", help="write a bar chart of the results")
    ap.add_argument("--out", metavar="PATH", help="also write the JSON to this file")
    args = ap.parse_args(argv)
    n = args.n if args.n is not None else (8 if args.quick else 100)
    pairs_of = args.pairs_of if args.pairs_of is not None else (8 if args.quick else 30)
    jobs = args.jobs if args.jobs is not None else (1 if args.quick else C.default_jobs())
    if n < 1 or pairs_of < 2 or jobs < 1:
        ap.error("--n and --jobs must be >= 1 and --pairs-of >= 2")
    plans = args.plans if args.plans else fl.examples.list_plans()
    names = [fl.load_plan(p).name for p in plans]  # fail early on a bad plan
    t0 = time.perf_counter()
    tasks = [(p, c, n, args.seed) for c in args.conditions for p in plans]
    done = C.run_tasks(C.draw_many, tasks, jobs)
    by_cond: dict[str, list[tuple[str, list[C.Sample]]]] = {}
    for (p, c, _, _), (_, _, samples) in zip(tasks, done, strict=True):
        by_cond.setdefault(c, []).append((names[plans.index(p)], samples))
    conditions = {}
    for c, items in by_cond.items():
        rows = [plan_row(name, s, pairs_of) for name, s in items]
        conditions[c] = summarise(rows, [s for _, s in items], args.resamples, args.seed)
    first = [next(x.layout for x in s if x.valid) for _, s in by_cond.get("Full", [])
             if any(x.valid for x in s)]
    result = {
        "benchmark": "paper_tables",
        "forcelayout": fl.__version__,
        "config": {"n": n, "plans": names, "conditions": args.conditions, "seed": args.seed,
                   "jobs": jobs, "resamples": args.resamples, "pairs_of": pairs_of,
                   "good_rules": C.GOOD_RULES, "agent_radius": 0.2},
        "conditions": conditions,
        "inter_plan": inter_plan(first),
        "seconds": time.perf_counter() - t0,
    }
    C.dump(result, args.out)
    if args.markdown:
        print(markdown(C.jsonable(result)))
    if args.png:
        chart(C.jsonable(result), args.png)
    return result


if __name__ == "__main__":
    main()
