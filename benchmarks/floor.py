"""Time per raw sample against the physical floor: a bare Box2D loop of the same size.

For each plan (default: every ``benchmarks/plans/*.json``), in one worker
process, ``--samples`` raw samples ``forcelayout.solve(plan, sample_seed(seed,
k))`` (no retries, no dedup), simulated ``--batch`` at a time as ``generate``
runs them (each sample's time is its share of its batch's), and for each
sample a bare Box2D loop measured in the same process: a zero-gravity world
with as many dynamic boxes as the plan has floor objects, stepped as many
times as the sample stepped, a force and a torque applied to and the pose
read back from every body at every step. That loop is what the physics alone
costs; the ratio of the two says how much the library spends around it
(rules, start poses, checks, surfaces).

Printed per plan and overall (JSON; ``--markdown`` adds a table): ms per raw
sample, mean steps, floor bodies, the bare loop's ms per sample, their ratio,
good layouts per CPU second of one core (valid AND >= 95 % of rules met), and
the rejection baseline's good layouts per CPU second in the same run; the
peak resident memory of a worker process (``peak_mib``: the batch's memory
shows there); and the three plans that take the largest shares of the suite's
CPU, with how many good layouts they gave (``most_cpu``).

Targets (speed issue): ratio <= 2 on plans of 8-20 floor objects, >= 100 good
layouts/s/core on the bundled living room, >= 5 x the baseline's good
layouts/s over the suite.

Usage::

    python benchmarks/floor.py [--plans living_room plans/] [--samples 30]
        [--baseline-tries 2000] [--batch 64] [--jobs 2] [--quick] [--markdown]
        [--out floor.json]
"""

from __future__ import annotations

import argparse
import resource
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import Box2D
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import dump, jsonable, raw_samples  # noqa: E402
from suite import (  # noqa: E402
    GOOD_RULES,
    add_plan_arguments,
    parse_plan_arguments,
    resolve_plans,
)

import forcelayout as fl  # noqa: E402
from forcelayout.baselines import rejection_sample  # noqa: E402
from forcelayout.forces import ForceModel  # noqa: E402
from forcelayout.options import SolverConfig  # noqa: E402

#: Targets: largest ratio on plans of FLOOR_RANGE floor objects, good layouts/s/core on the
#: bundled living room, and the speed ratio to the baseline over the suite.
RATIO, FLOOR_RANGE, LIVING_ROOM, SPEED_SUITE = 2.0, (8, 20), 100.0, 5.0


def bare_loop(bodies: int, steps: int, seed: int = 0) -> float:
    """CPU seconds of ``steps`` steps of a zero-gravity Box2D world of ``bodies`` boxes.

    Every step applies a force and a torque to every body and reads every
    body's pose back, with the solver's time step and iterations
    (:class:`forcelayout.SolverConfig`); the boxes stand apart on a grid.
    """
    cfg = SolverConfig()
    rng = np.random.default_rng(seed)
    world = Box2D.b2World(gravity=(0, 0), doSleep=False)
    side = max(1, int(np.ceil(np.sqrt(bodies))))
    body = []
    for k in range(bodies):
        b = world.CreateDynamicBody(position=(1.5 * (k % side), 1.5 * (k // side)))
        b.CreatePolygonFixture(box=(0.4, 0.3), density=1.0, friction=0.0)
        body.append(b)
    push = rng.normal(0.0, 0.1, (steps, bodies, 3)).tolist()
    t0 = time.process_time()
    for t in range(steps):
        for b, (fx, fy, tq) in zip(body, push[t], strict=True):
            b.ApplyForceToCenter((fx, fy), True)
            b.ApplyTorque(tq, True)
        world.Step(cfg.dt, cfg.velocity_iterations, cfg.position_iterations)
        np.array([(b.position.x, b.position.y, b.angle) for b in body])
    return time.process_time() - t0


def bench_plan(source: str, samples: int, tries: int, seed: int, batch: int
               ) -> dict[str, Any]:
    """One plan: raw samples timed beside their bare loops, and the baseline."""
    plan = fl.load_plan(source)
    floor = ForceModel(plan).n  # the bodies of the floor simulation
    fl.solve(plan, 2**62)  # warm imports and caches outside the timing
    bare_loop(floor, 5)
    cpu = bare = 0.0
    steps: list[int] = []
    good = 0
    for k, (lay, seconds) in enumerate(raw_samples(plan, seed, samples, batch)):
        cpu += seconds
        rep = lay.report
        steps.append(rep.steps)
        ok = not [f for f in rep.failures if not f.startswith("rules:")]
        good += ok and rep.rule_satisfaction >= GOOD_RULES
        bare += bare_loop(floor, rep.steps, seed=k)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux
    rejection_sample(plan, 1, seed=2**62, max_tries=1)
    t0 = time.process_time()
    res = rejection_sample(plan, samples, seed=seed, max_tries=tries)
    bl_cpu = time.process_time() - t0
    return {
        "plan": Path(source).stem if source.endswith(".json") else source,
        "objects": len(plan.objects),
        "floor_bodies": floor,
        "samples": samples,
        "ms_per_sample": 1000.0 * cpu / samples,
        "mean_steps": float(np.mean(steps)),
        "bare_ms_per_sample": 1000.0 * bare / samples,
        "ratio": cpu / bare if bare > 0 else None,
        "good": good,
        "good_per_s": good / cpu if cpu > 0 else None,
        "cpu_seconds": cpu,
        "peak_mib": peak,
        "baseline": {"tries": res.tries, "accepted": len(res), "cpu_seconds": bl_cpu,
                     "good_per_s": len(res) / bl_cpu if bl_cpu > 0 else None},
    }


def overall(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Suite totals and the targets."""
    cpu = sum(r["cpu_seconds"] for r in rows)
    bl_cpu = sum(r["baseline"]["cpu_seconds"] for r in rows)
    gs = sum(r["good"] for r in rows) / cpu if cpu > 0 else None
    bs = sum(r["baseline"]["accepted"] for r in rows) / bl_cpu if bl_cpu > 0 else None
    sized = [r for r in rows if FLOOR_RANGE[0] <= r["floor_bodies"] <= FLOOR_RANGE[1]]
    living = [r for r in rows if r["plan"] == "living_room"]
    speed = gs / bs if gs is not None and bs else None
    # where the suite's time goes: the plans taking the largest shares of its CPU
    costly = sorted(rows, key=lambda r: -r["cpu_seconds"])[:3]
    return {
        "plans": len(rows),
        "ms_per_sample": float(np.mean([r["ms_per_sample"] for r in rows])) if rows else None,
        "ratio_median": float(np.median([r["ratio"] for r in rows if r["ratio"]]))
        if rows else None,
        "good_per_s": gs,
        "baseline_good_per_s": bs,
        "speed_ratio": speed,
        "peak_mib": max((r["peak_mib"] for r in rows), default=None),
        "most_cpu": [{"plan": r["plan"], "cpu_share": r["cpu_seconds"] / cpu if cpu > 0
                      else None, "good": r["good"], "samples": r["samples"]} for r in costly],
        "targets": {
            "ratio": all(r["ratio"] is not None and r["ratio"] <= RATIO for r in sized)
            if sized else None,
            "living_room": living[0]["good_per_s"] >= LIVING_ROOM if living else None,
            "speed_suite": speed >= SPEED_SUITE if speed is not None else None,
        },
    }


def _num(x: float | None, digits: int = 1) -> str:
    return "-" if x is None else f"{x:.{digits}f}"


def markdown(result: dict[str, Any]) -> str:
    """The per-plan table and the overall line."""
    lines = ["| plan | floor bodies | steps | ms / sample | bare Box2D loop, ms | ratio "
             "| good/s | baseline good/s |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for r in result["plans"]:
        lines.append(f"| {r['plan']} | {r['floor_bodies']} | {r['mean_steps']:.0f} "
                     f"| {r['ms_per_sample']:.1f} | {r['bare_ms_per_sample']:.2f} "
                     f"| {_num(r['ratio'])} | {_num(r['good_per_s'])} "
                     f"| {_num(r['baseline']['good_per_s'])} |")
    o = result["overall"]
    lines.append(f"| **overall** | | | {_num(o['ms_per_sample'])} | | {_num(o['ratio_median'])} "
                 f"(median) | {_num(o['good_per_s'])} | {_num(o['baseline_good_per_s'])} |")
    t = o["targets"]
    lines.append("")
    lines.append(f"Targets: ratio <= {RATIO:g} on plans of {FLOOR_RANGE[0]}-{FLOOR_RANGE[1]} "
                 f"floor objects: {t['ratio']}; >= {LIVING_ROOM:g} good/s on the living room: "
                 f"{t['living_room']}; >= {SPEED_SUITE:g} x the baseline over the suite "
                 f"({_num(o['speed_ratio'], 2)} x): {t['speed_suite']}. Peak memory of a "
                 f"worker process: {_num(o['peak_mib'], 0)} MiB.")
    if o["most_cpu"]:
        lines.append("Most of the suite's CPU: " + ", ".join(
            f"{c['plan']} {_num(100 * (c['cpu_share'] or 0.0), 0)} % ({c['good']} of "
            f"{c['samples']} good)" for c in o["most_cpu"]) + ".")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_plan_arguments(ap, "raw samples per plan (default 30)")
    args = parse_plan_arguments(ap, argv)
    sources = resolve_plans(args.plans)
    task = (args.samples, args.baseline_tries, args.seed, args.batch)
    t0 = time.perf_counter()
    if args.jobs <= 1 or len(sources) <= 1:
        rows = [bench_plan(s, *task) for s in sources]
    else:
        with ProcessPoolExecutor(max_workers=args.jobs) as ex:
            rows = list(ex.map(bench_plan, sources, *([t] * len(sources) for t in task)))
    result = {
        "benchmark": "floor",
        "forcelayout": fl.__version__,
        "config": {"samples": args.samples, "baseline_tries": args.baseline_tries,
                   "seed": args.seed, "jobs": args.jobs, "batch": args.batch,
                   "good_rules": GOOD_RULES},
        "plans": rows,
        "overall": overall(rows),
        "wall_seconds": time.perf_counter() - t0,
    }
    dump(jsonable(result), args.out)
    if args.markdown:
        print()
        print(markdown(result))


if __name__ == "__main__":
    main()
