"""How often layouts leave an object with no access zone free, beside the baseline.

An access zone is the free floor a person needs beside an object
(:mod:`forcelayout.access`: in front of a wardrobe, desk, counter, fridge;
beside a long side of a bed). The zones are kept free by a force and by
start poses, not by a check, so this script measures how often they fail:
for each plan, the valid layouts of ``forcelayout.generate`` and of the
rejection baseline (:func:`forcelayout.baselines.rejection_sample`, same
seed), and the share of them where some object has every zone blocked, as
the ``access`` check judges it (:func:`forcelayout.access.zone_states`):
a zone is free where some stretch of it ``--width`` metres wide has at most
``--area`` m2 covered by solid objects no rule relates to its owner, or off
the floor. Prints JSON: per plan and overall, ``blocked_pct`` of each
side and the pairs (``"intruder>owner"``) seen most often.

Then the same with the ``access`` check required (``check_kwargs=
{"access_clearance": True}``, the command line's ``--access``): for
forcelayout, ``--samples`` raw samples of a run with seed 0 and the share
that pass every check and meet >= 95 % of their rules (``yield_pct``) with
their CPU time (``good_per_s``); for the baseline, its yield per try and
good layouts per CPU second within ``--baseline-tries``.

Usage::

    python benchmarks/access.py [--plans DIR_OR_JSON ...] [--samples 30]
        [--baseline-tries 2000] [--area 0.1] [--width 0.6] [--jobs 2] [--markdown]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import forcelayout as fl
from forcelayout import baselines
from forcelayout.access import blocked_objects
from forcelayout.sampling import sample_seed, solve_many

HERE = Path(__file__).resolve().parent


def blocked_owners(layout: fl.Layout, area: float, width: float
                   ) -> list[tuple[str, list[str]]]:
    """Objects of a layout with every access zone blocked, each with what blocks it (an
    object's id or ``"wall"``), as the ``access`` check judges the zones
    (:func:`forcelayout.access.blocked_objects`)."""
    shut = blocked_objects(layout, max_access_overlap=area, access_width=width)
    return [(oid, [w for w, a in covers if a >= 0.01]) for oid, covers in shut.items()]


def _summary(layouts: list, area: float, width: float) -> dict:
    blocked, pairs = 0, Counter()
    for lay in layouts:
        found = blocked_owners(lay, area, width)
        blocked += bool(found)
        pairs.update(f"{w}>{k}" for k, who in found for w in dict.fromkeys(who))
    n = len(layouts)
    return {"layouts": n, "blocked": blocked,
            "blocked_pct": round(100 * blocked / n, 1) if n else None,
            "pairs": dict(pairs.most_common(3))}


REQUIRED = {"access_clearance": True}


def _required(plan: fl.Plan, samples: int, tries: int, area: float, width: float) -> dict:
    """Yield and speed of both samplers with the access check required."""
    kw = {**REQUIRED, "max_access_overlap": area, "access_width": width}
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


def bench_plan(source: str, samples: int, tries: int, area: float, width: float) -> dict:
    plan = fl.load_plan(source)
    gen = fl.generate(plan, samples, seed=0)
    base = baselines.rejection_sample(plan, samples, seed=0, max_tries=tries)
    return {"plan": Path(source).stem if source.endswith(".json") else source,
            "forcelayout": _summary(list(gen), area, width),
            "baseline": _summary(list(base), area, width),
            "required": _required(plan, samples, tries, area, width)}


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
    ap.add_argument("--area", type=float, default=0.1,
                    help="m2 of a stretch of a zone that blocks it (max_access_overlap)")
    ap.add_argument("--width", type=float, default=0.6,
                    help="width of the free stretch a person needs, m (access_width)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args(argv)
    sources = _sources(args.plans)
    job = [(s, args.samples, args.baseline_tries, args.area, args.width) for s in sources]
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
