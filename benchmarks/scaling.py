"""How the cost of one layout grows with the number of objects.

Builds synthetic plans of 5, 10, 20, 40 and 80 floor objects (a cycle of
common furniture sizes, every third object ``at_wall``, every odd object
``next_to`` the previous one) in a square room sized so the footprints cover
20 % of the floor, and for each size reports:

* ``ms_per_layout`` — CPU milliseconds per raw sample (median and mean);
* ``ms_per_step`` — CPU milliseconds per simulation step, the per-step cost;
* ``ms_simulation`` / ``ms_checks`` — wall milliseconds in the simulation
  stages and in everything else (deterministic checks, rule judging);
* ``median_steps`` — simulation steps to settle (the step cap bounds it);
* ``peak_mib`` — peak memory traced by :mod:`tracemalloc` during one sample
  (Python and numpy allocations; Box2D's own C++ heap is not traced);
* ``validity_pct`` — samples passing the deterministic checks;

and the fitted exponents ``b`` of ``time ≈ a · N^b`` (per layout and per
step) by least squares on log-log axes.

Usage::

    python benchmarks/scaling.py                    # 5..80 objects, 5 samples each
    python benchmarks/scaling.py --quick            # 3 samples of 5..40, < 1 min
    python benchmarks/scaling.py --markdown --png scaling.png
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import tracemalloc
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _common as C  # noqa: E402

import forcelayout as fl  # noqa: E402
from forcelayout.sampling import sample_seed  # noqa: E402

#: (category, width, depth, height) cycled to make the objects.
FURNITURE = [("chair", 0.5, 0.5, 0.9), ("table", 1.2, 0.8, 0.75), ("cabinet", 0.8, 0.4, 1.2),
             ("sofa", 1.8, 0.85, 0.8), ("shelf", 1.0, 0.35, 1.8), ("stool", 0.4, 0.4, 0.5),
             ("desk", 1.2, 0.6, 0.75), ("armchair", 0.8, 0.8, 0.9)]


def synthetic_plan(n: int, *, fill: float = 0.2) -> fl.Plan:
    """A plan of ``n`` floor objects covering ``fill`` of a square room's floor."""
    if n < 1:
        raise ValueError(f"need at least one object, got {n}")
    objs = [FURNITURE[k % len(FURNITURE)] for k in range(n)]
    area = sum(w * d for _, w, d, _ in objs)
    side = max(math.sqrt(area / fill), 2.5)
    rules: list[dict[str, Any]] = []
    for k in range(n):
        if k % 3 == 0:
            rules.append({"rule": "at_wall", "object": f"o{k}"})
        if k % 2 == 1:
            rules.append({"rule": "next_to", "object": f"o{k}", "target": f"o{k - 1}"})
    return fl.Plan.from_dict({
        "name": f"synthetic_{n}",
        "room": {"polygon": [[0, 0], [side, 0], [side, side], [0, side]], "height": 2.7,
                 "doors": [{"wall": 0, "offset": side / 2, "width": 0.9}]},
        "objects": [{"id": f"o{k}", "category": c, "size": [w, d, h]}
                    for k, (c, w, d, h) in enumerate(objs)],
        "rules": rules,
    })


def measure(n: int, samples: int, seed: int) -> dict[str, Any]:
    """Time ``samples`` layouts of the ``n``-object plan, then trace one for memory."""
    plan = synthetic_plan(n)
    fl.solve(plan, 2**62)  # warm imports and caches
    cpu, steps, valid, sim, rest, rules = [], [], [], [], [], []
    for k in range(samples):
        t0 = time.process_time()
        lay = fl.solve(plan, sample_seed(seed, k), min_rule_satisfaction=0.0)
        cpu.append(time.process_time() - t0)
        steps.append(lay.report.steps)
        valid.append(lay.report.valid)  # the deterministic checks alone
        rules.append(lay.rule_satisfaction)
        stages = float(sum(lay.report.stages.values()))
        sim.append(stages)
        rest.append(max(lay.report.seconds - stages, 0.0))
    tracemalloc.start()
    try:
        fl.solve(plan, sample_seed(seed, samples))
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    cpu_a = np.array(cpu)
    steps_a = np.maximum(np.array(steps, dtype=float), 1.0)
    side = plan.room.polygon[1][0]
    return {
        "objects": n,
        "room_m2": round(side * side, 2),
        "samples": samples,
        "ms_per_layout": {"median": 1000 * float(np.median(cpu_a)),
                          "mean": 1000 * float(cpu_a.mean())},
        "ms_per_step": 1000 * float(np.median(cpu_a / steps_a)),
        "ms_simulation": 1000 * float(np.median(sim)),
        "ms_checks": 1000 * float(np.median(rest)),
        "median_steps": float(np.median(steps)),
        "peak_mib": peak / 2**20,
        "validity_pct": 100 * float(np.mean(valid)),
        "rules_pct": 100 * float(np.mean(rules)),
    }


def exponent(ns: list[int], values: list[float]) -> float | None:
    """Least-squares slope of log(value) on log(N) (None with fewer than 2 sizes)."""
    x, y = np.log(np.array(ns, dtype=float)), np.log(np.maximum(values, 1e-12))
    if len(x) < 2:
        return None
    return float(np.polyfit(x, y, 1)[0])


def chart(result: dict[str, Any], path: str) -> None:
    rows = result["results"]
    ns = [r["objects"] for r in rows]
    fig = C.new_figure(9, 3.4)
    for k, (key, label) in enumerate([("ms_per_layout", "ms per layout (median)"),
                                      ("ms_per_step", "ms per step"),
                                      ("peak_mib", "peak traced MiB")]):
        ax = fig.add_subplot(1, 3, k + 1)
        ys = [r[key]["median"] if isinstance(r[key], dict) else r[key] for r in rows]
        ax.loglog(ns, ys, "o-")
        ax.set_xlabel("objects")
        ax.set_title(label, fontsize=9)
    fig.suptitle("forcelayout scaling (CPU time of one core)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="*", default=None,
                    help="object counts (default 5 10 20 40 80; 5 10 20 40 with --quick)")
    ap.add_argument("--samples", type=int, default=None,
                    help="timed samples per size (default 5, 3 with --quick)")
    ap.add_argument("--quick", action="store_true", help="small run, under a minute")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=1,
                    help="sizes measured in parallel processes (timings are per-process CPU)")
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--png", metavar="PATH")
    ap.add_argument("--out", metavar="PATH")
    args = ap.parse_args(argv)
    sizes = args.sizes or ([5, 10, 20, 40] if args.quick else [5, 10, 20, 40, 80])
    samples = args.samples if args.samples is not None else (3 if args.quick else 5)
    if samples < 1 or any(s < 1 for s in sizes):
        ap.error("--samples and every size must be >= 1")
    t0 = time.perf_counter()
    rows = C.run_tasks(measure, [(n, samples, args.seed) for n in sizes], max(1, args.jobs))
    result = {
        "benchmark": "scaling",
        "forcelayout": fl.__version__,
        "config": {"sizes": sizes, "samples": samples, "seed": args.seed, "fill": 0.2},
        "results": rows,
        "exponent_per_layout": exponent(sizes, [r["ms_per_layout"]["median"] for r in rows]),
        "exponent_per_step": exponent(sizes, [r["ms_per_step"] for r in rows]),
        "exponent_simulation": exponent(sizes, [r["ms_simulation"] for r in rows]),
        "exponent_checks": exponent(sizes, [r["ms_checks"] for r in rows]),
        "exponent_memory": exponent(sizes, [r["peak_mib"] for r in rows]),
        "seconds": time.perf_counter() - t0,
    }
    C.dump(result, args.out)
    if args.markdown:
        print("\n| objects | room m² | ms / layout (median) | ms simulation | ms checks "
              "| ms / step | median steps | peak MiB | valid % |\n"
              "|---|---|---|---|---|---|---|---|---|")
        for r in rows:
            print(f"| {r['objects']} | {r['room_m2']} | {r['ms_per_layout']['median']:.1f} | "
                  f"{r['ms_simulation']:.1f} | {r['ms_checks']:.1f} | "
                  f"{r['ms_per_step']:.3f} | {r['median_steps']:.0f} | {r['peak_mib']:.2f} | "
                  f"{r['validity_pct']:.0f} |")
        fmt = (lambda v: "–" if v is None else f"{v:.2f}")  # noqa: E731
        print(f"\ntime per layout ∝ N^{fmt(result['exponent_per_layout'])}, per step ∝ "
              f"N^{fmt(result['exponent_per_step'])}, simulation ∝ "
              f"N^{fmt(result['exponent_simulation'])}, checks ∝ "
              f"N^{fmt(result['exponent_checks'])}, memory ∝ N^{fmt(result['exponent_memory'])}")
    if args.png:
        chart(result, args.png)
    return result


if __name__ == "__main__":
    main()
