"""The hierarchical path against the flat one: validity, rules, distinct rooms, time per stage.

For each plan, prints JSON with, for the flat path (one floor simulation)
and the hierarchical path (area variants + combinatorial assembly):

* ``valid_pct``, ``rules_pct`` and ``good_pct`` (valid AND >= 95 % of rules
  met) over ``--samples`` raw samples drawn with :func:`forcelayout.solve`;
* ``good_per_second`` — such layouts per CPU second on one core;
* ``stage_ms`` — mean milliseconds per stage (floor or variants/assembly,
  tops, walls, ceiling);

and, for combinatorial assembly from ``--variants`` variants per area:

* ``library_ms`` — time to make the variants once;
* ``combinations`` — how many combinations there are (v ** areas) and how
  many were instantiated (``--budget``);
* ``distinct_valid_rooms`` (pass the checks, all objects placed, no two
  within 5 cm of each other) and ``distinct_good_rooms`` (also >= 95 % of
  rules met), each also per CPU second including the library.

``--ablations`` adds the −Relations and −Decor runs of both paths.

Usage::

    python benchmarks/hierarchy.py [--samples 30] [--variants 3] [--budget 27]
                                   [--plans bedroom living_room] [--ablations]
"""

from __future__ import annotations

import argparse
import json
import time
from collections import Counter
from dataclasses import dataclass

import numpy as np

import forcelayout as fl
from forcelayout.hierarchy import VariantLibrary, assemble
from forcelayout.layout import Layout, SampleReport
from forcelayout.sampling import Options, _judge, sample_seed
from forcelayout.surfaces import place_surfaces


@dataclass(frozen=True)
class _Hierarchical(Options):  # until Options has these fields
    hierarchy: bool = True
    variants: int = 3
    variant_seed: int = 0


def options(hierarchy: bool, variants: int, **kw) -> Options:
    if not hierarchy:
        return Options(**kw)
    if "hierarchy" in Options.__dataclass_fields__:
        return Options(hierarchy=True, variants=variants, **kw)
    return _Hierarchical(variants=variants, **kw)


def run_path(plan: fl.Plan, opts: Options, samples: int, seed: int) -> dict:
    fl.solve(plan, seed=2**40, options=opts)  # warm imports and the variant library
    reports = []
    t0 = time.process_time()
    for k in range(samples):
        reports.append(fl.solve(plan, sample_seed(seed, k), options=opts).report)
    cpu = time.process_time() - t0
    valid = np.array([r.valid and not r.missing for r in reports])
    rules = np.array([r.rule_satisfaction for r in reports])
    good = valid & (rules >= 0.95)
    stages: Counter[str] = Counter()
    for r in reports:
        stages.update(r.stages)
    return {
        "valid_pct": round(100 * valid.mean(), 1),
        "rules_pct": round(100 * rules.mean(), 1),
        "good_pct": round(100 * good.mean(), 1),
        "good_per_second": round(good.sum() / cpu, 2),
        "ms_per_sample": round(1000 * cpu / samples, 1),
        "stage_ms": {k: round(1000 * v / samples, 2) for k, v in stages.items()},
        "missing": sum(len(r.missing) for r in reports),
        "failures": dict(Counter(f.split(":")[0] for r in reports for f in r.failures)),
    }


def distinct_rooms(plan: fl.Plan, v: int, budget: int, seed: int, tol: float = 0.05) -> dict:
    t0 = time.process_time()
    lib = VariantLibrary(plan, v, seed=seed)
    lib_cpu = time.process_time() - t0
    rng = np.random.default_rng(seed)
    accepted: list[np.ndarray] = []
    good: list[np.ndarray] = []
    tried = 0
    t1 = time.process_time()
    for combo in lib.combinations(budget, rng):
        tried += 1
        floor, steps, conv = assemble(plan, combo, rng)
        surf = place_surfaces(plan, floor, rng)
        lay = Layout(plan, surf.poses, tried,
                     SampleReport(seed=tried, steps=steps, missing=surf.missing))
        _judge(lay, Options())
        if not lay.report.valid or surf.missing:
            continue
        xy = np.array([[lay.poses[i].x, lay.poses[i].y] for i in plan.ids])
        if all(np.abs(xy - q).max() >= tol for q in accepted):
            accepted.append(xy)
            if lay.report.rule_satisfaction >= 0.95:
                good.append(xy)
    cpu = time.process_time() - t1
    return {
        "variants_per_area": v,
        "areas": len(lib.variants),
        "library_ms": round(1000 * lib_cpu, 1),
        "combinations": lib.n_combinations,
        "instantiated": tried,
        "distinct_valid_rooms": len(accepted),
        "distinct_good_rooms": len(good),
        "distinct_valid_per_second": round(len(accepted) / (cpu + lib_cpu), 2),
        "distinct_good_per_second": round(len(good) / (cpu + lib_cpu), 2),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--samples", type=int, default=30)
    ap.add_argument("--variants", type=int, default=3)
    ap.add_argument("--budget", type=int, default=27)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--plans", nargs="*", default=["bedroom", "living_room", "home_office"])
    ap.add_argument("--ablations", action="store_true")
    args = ap.parse_args()
    out = []
    for name in args.plans:
        plan = fl.load_plan(name)  # a bundled name or a path
        row: dict = {"plan": name, "objects": len(plan.objects)}
        for label, h in (("flat", False), ("hierarchy", True)):
            row[label] = run_path(plan, options(h, args.variants), args.samples, args.seed)
            if args.ablations:
                for abl in ("relations", "decor"):
                    row[f"{label}-{abl}"] = run_path(
                        plan, options(h, args.variants, **{abl: False}), args.samples, args.seed)
        row["assembly"] = distinct_rooms(plan, args.variants, args.budget, args.seed)
        out.append(row)
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
