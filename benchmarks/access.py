"""How often layouts leave an object with no access zone free, beside the baseline.

An access zone is the free floor a person needs beside an object
(:mod:`forcelayout.access`: in front of a wardrobe, desk, counter, fridge;
beside a long side of a bed). The zones are kept free by a force and by
start poses, not by a check, so this script measures how often they fail:
for each plan, the valid layouts of ``forcelayout.generate`` and of the
rejection baseline (:func:`forcelayout.baselines.rejection_sample`, same
seed), and the share of them where some object has every zone blocked. A
zone is blocked when an unrelated solid object stands more than
``--area`` m2 inside it, or more than that much of it lies off the floor
(objects a rule relates to the owner and walkable covers do not count, as
for the force). Prints JSON: per plan and overall, ``blocked_pct`` of each
side and the pairs (``"intruder>owner"``) seen most often.

Then the same with the ``access`` check required (``check_kwargs=
{"access_clearance": True}``, the command line's ``--access``): for
forcelayout, ``--samples`` raw samples of a run with seed 0 and the share
that pass every check and meet >= 95 % of their rules (``yield_pct``) with
their CPU time (``good_per_s``); for the baseline, its yield per try and
good layouts per CPU second within ``--baseline-tries``.

Usage::

    python benchmarks/access.py [--plans DIR_OR_JSON ...] [--samples 30]
        [--baseline-tries 2000] [--area 0.1] [--jobs 2] [--markdown]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import shapely

import forcelayout as fl
from forcelayout import baselines
from forcelayout.access import access_of
from forcelayout.bindings import compile_plan
from forcelayout.sampling import sample_seed, solve_many

HERE = Path(__file__).resolve().parent
SIDES = {"front": (0.0, 1.0), "back": (0.0, -1.0), "left": (-1.0, 0.0), "right": (1.0, 0.0)}


def _box(x: float, y: float, yaw: float, w: float, d: float,
         shift: tuple[float, float] = (0.0, 0.0)) -> shapely.Polygon:
    """A w x d rectangle centred at ``shift`` in the frame of a pose (x, y, yaw)."""
    rect = shapely.box(shift[0] - w / 2, shift[1] - d / 2, shift[0] + w / 2, shift[1] + d / 2)
    return shapely.affinity.translate(
        shapely.affinity.rotate(rect, yaw, origin=(0, 0), use_radians=True), x, y)


def blocked_owners(plan: fl.Plan, layout: fl.Layout, area: float) -> list[tuple[str, list[str]]]:
    """Objects of a layout with every access zone blocked, each with what blocks it."""
    objs = {o.id: o for o in plan.objects}
    floor = shapely.Polygon(plan.room.polygon)
    poses = layout.poses
    bindings = compile_plan(plan).bindings
    ids = [k for k, p in poses.items() if p.surface == "floor" and not objs[k].is_walkable]
    foot = {k: _box(poses[k].x, poses[k].y, poses[k].yaw, *objs[k].size[:2]) for k in ids}
    out = []
    for k in ids:
        acc = access_of(objs[k], [b for b in bindings if b.object == k])
        if acc is None:
            continue
        related = ({b.target for b in plan.rules if b.object == k}
                   | {b.object for b in plan.rules if b.target == k})
        w, d = objs[k].size[:2]
        who: list[str] = []
        free = False
        for side in acc.sides:
            sx, sy = SIDES[side]
            zw = abs(sy) * w + abs(sx) * acc.depth
            zd = abs(sy) * acc.depth + abs(sx) * d
            shift = (sx * (w + acc.depth) / 2, sy * (d + acc.depth) / 2)
            zone = _box(poses[k].x, poses[k].y, poses[k].yaw, zw, zd, shift)
            hits = [f for f in ids if f != k and f not in related
                    and foot[f].intersection(zone).area > area]
            off = zone.difference(floor).area > area
            if not hits and not off:
                free = True
                break
            who += hits + (["wall"] if off else [])
        if not free:
            out.append((k, who))
    return out


def _summary(plan: fl.Plan, layouts: list, area: float) -> dict:
    blocked, pairs = 0, Counter()
    for lay in layouts:
        found = blocked_owners(plan, lay, area)
        blocked += bool(found)
        pairs.update(f"{w}>{k}" for k, who in found for w in dict.fromkeys(who))
    n = len(layouts)
    return {"layouts": n, "blocked": blocked,
            "blocked_pct": round(100 * blocked / n, 1) if n else None,
            "pairs": dict(pairs.most_common(3))}


REQUIRED = {"access_clearance": True}


def _required(plan: fl.Plan, samples: int, tries: int, area: float) -> dict:
    """Yield and speed of both samplers with the access check required."""
    kw = {**REQUIRED, "max_access_overlap": area}
    fl.solve(plan, 2**62, check_kwargs=kw)  # warm caches outside the timing
    t0 = time.process_time()
    raw = solve_many(plan, [sample_seed(0, k) for k in range(samples)], check_kwargs=kw)
    cpu = time.process_time() - t0
    good = sum(lay.report.valid for lay in raw)  # checks passed, >= 95 % of rules met
    t0 = time.process_time()
    base = baselines.rejection_sample(plan, samples, seed=0, max_tries=tries, check_kwargs=kw)
    bcpu = time.process_time() - t0
    return {"forcelayout": {"samples": samples, "good": good,
                            "yield_pct": round(100 * good / samples, 1),
                            "good_per_s": round(good / cpu, 2) if cpu > 0 else None},
            "baseline": {"tries": base.tries, "good": len(base),
                         "yield_pct": round(100 * len(base) / base.tries, 2)
                         if base.tries else None,
                         "good_per_s": round(len(base) / bcpu, 2) if bcpu > 0 else None}}


def bench_plan(source: str, samples: int, tries: int, area: float) -> dict:
    plan = fl.load_plan(source)
    gen = fl.generate(plan, samples, seed=0)
    base = baselines.rejection_sample(plan, samples, seed=0, max_tries=tries)
    return {"plan": Path(source).stem if source.endswith(".json") else source,
            "forcelayout": _summary(plan, list(gen), area),
            "baseline": _summary(plan, list(base), area),
            "required": _required(plan, samples, tries, area)}


def _sources(items: list[str]) -> list[str]:
    out = []
    for item in items:
        p = Path(item)
        out += [str(f) for f in sorted(p.glob("*.json"))] if p.is_dir() else [item]
    return out


def markdown(result: dict) -> str:
    lines = ["| plan | layouts | blocked % | BL layouts | BL blocked % | with the check: good % "
             "| good/s | BL good % | BL good/s | most often |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in result["plans"]:
        f, b = r["forcelayout"], r["baseline"]
        rf, rb = r["required"]["forcelayout"], r["required"]["baseline"]
        lines.append(f"| {r['plan']} | {f['layouts']} | {f['blocked_pct']} | {b['layouts']} | "
                     f"{b['blocked_pct']} | {rf['yield_pct']} | {rf['good_per_s']} | "
                     f"{rb['yield_pct']} | {rb['good_per_s']} | {', '.join(f['pairs'])} |")
    o = result["overall"]
    rf, rb = o["required"]["forcelayout"], o["required"]["baseline"]
    lines.append(f"| **overall** | {o['forcelayout']['layouts']} | "
                 f"{o['forcelayout']['blocked_pct']} | {o['baseline']['layouts']} | "
                 f"{o['baseline']['blocked_pct']} | {rf['yield_pct']} | {rf['good_per_s']} | "
                 f"{rb['yield_pct']} | {rb['good_per_s']} | |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plans", nargs="+",
                    default=[str(HERE / "plans"), str(HERE / "plans_heldout")])
    ap.add_argument("--samples", type=int, default=30)
    ap.add_argument("--baseline-tries", type=int, default=2000)
    ap.add_argument("--area", type=float, default=0.1, help="m2 inside a zone that blocks it")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args(argv)
    sources = _sources(args.plans)
    job = [(s, args.samples, args.baseline_tries, args.area) for s in sources]
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as ex:
            rows = list(ex.map(bench_plan, *zip(*job, strict=True)))
    else:
        rows = [bench_plan(*j) for j in job]
    overall = {}
    for side in ("forcelayout", "baseline"):
        n = sum(r[side]["layouts"] for r in rows)
        k = sum(r[side]["blocked"] for r in rows)
        overall[side] = {"layouts": n, "blocked": k,
                         "blocked_pct": round(100 * k / n, 1) if n else None}
    req = [r["required"] for r in rows]

    def per_second(side: str) -> float | None:  # whole suite: layouts over CPU seconds
        secs = sum(q[side]["good"] / q[side]["good_per_s"] for q in req
                   if q[side]["good_per_s"])
        return round(sum(q[side]["good"] for q in req) / secs, 2) if secs else None

    fs = sum(q["forcelayout"]["samples"] for q in req)
    bt = sum(q["baseline"]["tries"] for q in req)
    overall["required"] = {
        "forcelayout": {"yield_pct": round(100 * sum(q["forcelayout"]["good"] for q in req)
                                           / fs, 1) if fs else None,
                        "good_per_s": per_second("forcelayout")},
        "baseline": {"yield_pct": round(100 * sum(q["baseline"]["good"] for q in req) / bt, 2)
                     if bt else None,
                     "good_per_s": per_second("baseline")}}
    result = {"benchmark": "access",
              "config": {"samples": args.samples, "baseline_tries": args.baseline_tries,
                         "area": args.area},
              "plans": rows, "overall": overall}
    print(json.dumps(result, indent=2))
    if args.markdown:
        print(markdown(result))


if __name__ == "__main__":
    sys.exit(main())
