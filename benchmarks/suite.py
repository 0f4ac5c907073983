"""A plan suite, forcelayout side by side with the rule-aware rejection baseline.

For each plan (default: every ``benchmarks/plans/*.json``; the bundled plans
when that folder is empty), in one worker process:

* **forcelayout** — ``--samples`` raw samples ``forcelayout.solve(plan,
  sample_seed(seed, k))``, simulated ``--batch`` at a time
  (``forcelayout.sampling.solve_many``, as ``generate`` runs them; the
  layouts do not depend on it); a sample is *good* when it passes the
  deterministic checks AND meets >= 95 % of its rules. Reported: good yield
  per raw sample, good layouts per CPU second of one core, the geometric and
  topological intra-plan diversity of the good layouts
  (:mod:`forcelayout.metrics`), the share of samples whose report says they
  were repaired, and failure counts;
* **baseline** — :func:`forcelayout.baselines.rejection_sample` with the same
  seed, until ``--samples`` layouts are accepted or ``--baseline-tries``
  tries are spent: yield per try, good layouts per CPU second, diversity.

Then per plan and overall, the targets of the robustness issue as pass/fail:
good yield >= 90 % on every plan where the baseline finds a good layout
(mean >= 95 %), never below the baseline's yield, diversity >= 0.95 x the
baseline's, good layouts/s >= the baseline's on every plan of >= 10 objects
and >= 3 x over the suite. A plan that fails to load or run is an error row.

Diversity from 30 layouts is a rough figure, so each plan also gets a 90 %
bootstrap interval of its two diversity ratios (forcelayout over baseline;
both sets of layouts drawn again with replacement); a plan below the target
is *clearly below* when a whole interval lies under 0.95. Each side also
reports the share of its good layouts that meet every rule
(``every_rule_pct``), printed beside each plan below the target: a good
layout may leave a rule unmet, and a sampler that leaves one unmet in most of
its layouts can owe its diversity to that.

How often does a sampler exactly as diverse as the baseline pass that test?
``--baseline-again`` runs the baseline a second time on each plan, with the
next seed, and judges it against the first run as forcelayout is judged:
the share of plans it passes is the test's chance level at this many
layouts.

Usage::

    python benchmarks/suite.py [--plans bedroom living_room my_plans/ x.json]
        [--samples 30] [--baseline-tries 2000] [--batch 64] [--jobs 2] [--quick]
        [--baseline-again] [--markdown] [--out suite.json]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import traceback
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import default_jobs, dump, jsonable, raw_samples  # noqa: E402

import forcelayout as fl  # noqa: E402
from forcelayout import metrics  # noqa: E402
from forcelayout import rules as registry  # noqa: E402
from forcelayout.baselines import rejection_sample  # noqa: E402

PLANS_DIR = Path(__file__).resolve().parent / "plans"
#: A sample that passes the checks and meets at least this fraction of its rules is good.
GOOD_RULES = 0.95
#: Targets (robustness issue): yield on every solvable plan, mean yield, diversity ratio,
#: speed ratio over the suite, and the plan size from which speed is compared per plan.
YIELD_EACH, YIELD_MEAN, DIVERSITY_RATIO, SPEED_SUITE, SPEED_MIN_OBJECTS = 0.90, 0.95, 0.95, 3.0, 10
#: Baseline layouts below which the markdown flags a plan's baseline diversity as a rough figure.
FEW_LAYOUTS = 10
#: Bootstrap resamples and coverage of the interval of each plan's diversity ratio.
RATIO_RESAMPLES, RATIO_LEVEL = 2000, 0.90
METRICS = ("geometric", "topological")


# -- one plan -----------------------------------------------------------------------------


def floor_fill(plan: fl.Plan) -> float:
    """Footprint of the floor obstacles over the floor area, in [0, 1].

    Objects placed off the floor by their rules and walkable covers (rugs) are
    not counted.
    """
    off = {s.object for s in plan.rules if type(registry.get_rule(s.rule)).surface != "floor"}
    area = sum(o.size[0] * o.size[1] for o in plan.objects
               if o.id not in off and not o.is_walkable)
    return area / plan.room.shape.area


def dissimilarities(layouts: list[fl.Layout], pairs_of: int) -> dict[str, np.ndarray | None]:
    """Geometric and topological dissimilarity matrices of at most ``pairs_of`` layouts
    (None for fewer than two)."""
    keep = layouts[:pairs_of]
    return {m: (metrics.pairwise(keep, m) if len(keep) >= 2 else None) for m in METRICS}


def diversity(pairs: dict[str, np.ndarray | None]) -> dict[str, float | None]:
    """Intra-plan diversity: the mean dissimilarity over all pairs of layouts."""
    return {m: (float(d[np.triu_indices(len(d), 1)].mean()) if d is not None else None)
            for m, d in pairs.items()}


def every_rule_pct(satisfaction: list[float]) -> float | None:
    """Percent of layouts, given their shares of rules met, that meet every rule (None for
    none): a good layout may leave some unmet (``GOOD_RULES``), and a sampler that leaves
    one unmet in most of its layouts may owe its diversity to it (a desk under the window,
    its wall shelf then hung elsewhere)."""
    if not satisfaction:
        return None
    return 100.0 * sum(s >= 1.0 for s in satisfaction) / len(satisfaction)


def ratio_interval(a: np.ndarray, b: np.ndarray, *, resamples: int = RATIO_RESAMPLES,
                   level: float = RATIO_LEVEL, seed: int = 0) -> list[float]:
    """Percentile bootstrap interval of diversity(a) / diversity(b), from the two sets'
    dissimilarity matrices: each set's layouts are drawn again with replacement, and the
    mean is over pairs of two different layouts (a layout drawn twice is no pair)."""
    rng = np.random.default_rng(seed)

    def means(d: np.ndarray) -> np.ndarray:
        k = rng.integers(0, len(d), (resamples, len(d)))
        pair = k[:, :, None] != k[:, None, :]
        sub = d[k[:, :, None], k[:, None, :]]
        count = pair.sum((1, 2))
        with np.errstate(invalid="ignore", divide="ignore"):  # one layout drawn: no pair
            return np.where(count > 0, (sub * pair).sum((1, 2)) / count, np.nan)

    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = means(a) / means(b)
    ratio = ratio[np.isfinite(ratio)]
    if not len(ratio):
        return [float("nan"), float("nan")]
    tail = 50.0 * (1.0 - level)
    return [float(np.percentile(ratio, tail)), float(np.percentile(ratio, 100.0 - tail))]


def run_forcelayout(plan: fl.Plan, samples: int, seed: int, pairs_of: int, batch: int
                    ) -> dict[str, Any]:
    """Raw samples of the method, judged as the baseline is judged (``"pairs"``: the
    dissimilarity matrices, not written out)."""
    fl.solve(plan, 2**62)  # warm imports and caches outside the measured samples
    good: list[fl.Layout] = []
    checks_ok = rules = repaired = 0
    repaired_known = False
    reasons: Counter[str] = Counter()
    cpu = 0.0
    for lay, seconds in raw_samples(plan, seed, samples, batch):
        cpu += seconds
        rep = lay.report
        failures = [f for f in rep.failures if not f.startswith("rules:")]
        ok = not failures
        checks_ok += ok
        rules += rep.rule_satisfaction
        if ok and rep.rule_satisfaction >= GOOD_RULES:
            good.append(lay)
        reasons.update({f.split(":", 1)[0] for f in rep.failures})
        flag = getattr(rep, "repaired", None)
        if flag is not None:
            repaired_known = True
            repaired += bool(flag)
    return {
        "samples": samples,
        "good": len(good),
        "yield_pct": 100.0 * len(good) / samples,
        "valid_pct": 100.0 * checks_ok / samples,
        "rules_pct": 100.0 * rules / samples,
        "good_per_s": len(good) / cpu if cpu > 0 else None,
        "ms_per_sample": 1000.0 * cpu / samples,
        "repaired_pct": 100.0 * repaired / samples if repaired_known else None,
        "every_rule_pct": every_rule_pct([lay.report.rule_satisfaction for lay in good]),
        **diversity(pairs := dissimilarities(good, pairs_of)),
        "failures": dict(reasons.most_common()),
        "pairs": pairs,
    }


def run_baseline(plan: fl.Plan, samples: int, tries: int, seed: int, pairs_of: int
                 ) -> dict[str, Any]:
    """The rule-aware rejection sampler with the same seed (``"pairs"`` as above)."""
    rejection_sample(plan, 1, seed=2**62, max_tries=1)  # warm imports and caches
    t0 = time.process_time()
    res = rejection_sample(plan, samples, seed=seed, max_tries=tries)
    cpu = time.process_time() - t0
    return {
        "tries": res.tries,
        "accepted": len(res),
        "yield_pct": 100.0 * res.yield_per_try if res.tries else None,
        "good_per_s": len(res) / cpu if cpu > 0 else None,
        "ms_per_try": 1000.0 * cpu / res.tries if res.tries else None,
        # judged when accepted: no rule is judged again
        "every_rule_pct": every_rule_pct([lay.rule_satisfaction for lay in res.layouts]),
        **diversity(pairs := dissimilarities(res.layouts, pairs_of)),
        "failures": dict(sorted(res.failures.items(), key=lambda kv: -kv[1])),
        "pairs": pairs,
    }


def diversity_targets(f: dict[str, Any], b: dict[str, Any],
                      ratio: dict[str, list[float]]) -> dict[str, bool | None]:
    """Whether diversities ``f`` reach the target against ``b`` (both metrics), and
    whether one is clearly below it (the whole interval of its ``ratio`` under it);
    None where ``b`` has no diversity."""
    div, clear = [], []
    for m in METRICS:
        if b[m] is not None:
            div.append(f[m] is not None and f[m] >= DIVERSITY_RATIO * b[m])
            ci = ratio.get(m)
            clear.append(ci is not None and bool(ci[1] < DIVERSITY_RATIO))
    return {"diversity": all(div) if div else None,
            "diversity_clearly_below": any(clear) if clear else None}


def plan_targets(row: dict[str, Any]) -> dict[str, bool | None]:
    """Pass/fail of one plan against the targets (None where a target does not apply)."""
    f, b = row["forcelayout"], row["baseline"]
    solvable = b["accepted"] > 0
    out: dict[str, bool | None] = {
        "yield": (f["yield_pct"] >= 100 * YIELD_EACH) if solvable else None,
        "not_below_baseline": (f["yield_pct"] >= b["yield_pct"]
                               if b["yield_pct"] is not None else None),
        **diversity_targets(f, b, row["diversity_ratio"]),
    }
    if row["objects"] >= SPEED_MIN_OBJECTS and solvable:
        out["speed"] = (f["good_per_s"] or 0.0) >= (b["good_per_s"] or 0.0)
    else:
        out["speed"] = None
    return out


def bench_plan(source: str, samples: int, tries: int, seed: int, pairs_of: int, batch: int,
               again: bool = False) -> dict[str, Any]:
    """Everything measured on one plan (with ``again``, the baseline's second run too);
    an error becomes an error row."""
    try:
        plan = fl.load_plan(source)
        row: dict[str, Any] = {
            "plan": plan.name,
            "source": source,
            "objects": len(plan.objects),
            "fill_pct": 100.0 * floor_fill(plan),
            "forcelayout": run_forcelayout(plan, samples, seed, pairs_of, batch),
            "baseline": run_baseline(plan, samples, tries, seed, pairs_of),
        }
        fp, bp = row["forcelayout"].pop("pairs"), row["baseline"].pop("pairs")
        row["diversity_ratio"] = {m: ratio_interval(fp[m], bp[m]) for m in METRICS
                                  if fp[m] is not None and bp[m] is not None}
        row["targets"] = plan_targets(row)
        if again:  # the baseline with the next seed, judged against its first run
            second = run_baseline(plan, samples, tries, seed + 1, pairs_of)
            sp = second.pop("pairs")
            ratio = {m: ratio_interval(sp[m], bp[m]) for m in METRICS
                     if sp[m] is not None and bp[m] is not None}
            row["baseline_again"] = {"seed": seed + 1, **second, "diversity_ratio": ratio,
                                     "targets": diversity_targets(second, row["baseline"],
                                                                  ratio)}
        return row
    except Exception as e:  # one bad plan must not stop the suite
        return {"plan": Path(source).stem, "source": source,
                "error": f"{type(e).__name__}: {e}",
                "traceback": traceback.format_exc(limit=4)}


# -- the suite ----------------------------------------------------------------------------


def resolve_plans(specs: list[str] | None) -> list[str]:
    """Plan sources from names, files and folders (every ``*.json`` in a folder)."""
    if not specs:
        found = sorted(PLANS_DIR.glob("*.json")) if PLANS_DIR.is_dir() else []
        if found:
            return [str(p) for p in found]
        print(f"suite: no plans in {PLANS_DIR}; using the bundled plans", file=sys.stderr)
        return fl.examples.list_plans()
    out: list[str] = []
    for spec in specs:
        p = Path(spec)
        if p.is_dir():
            out.extend(str(q) for q in sorted(p.glob("*.json")))
        else:
            out.append(spec)
    return out


def run_all(sources: list[str], args: argparse.Namespace) -> list[dict[str, Any]]:
    task = (args.samples, args.baseline_tries, args.seed, args.pairs_of, args.batch,
            args.baseline_again)
    if args.jobs <= 1 or len(sources) <= 1:
        return [bench_plan(s, *task) for s in sources]
    rows: list[dict[str, Any]] = []
    with ProcessPoolExecutor(max_workers=args.jobs) as ex:
        futures = [ex.submit(bench_plan, s, *task) for s in sources]
        for s, fut in zip(sources, futures, strict=True):
            try:
                rows.append(fut.result())
            except (BrokenProcessPool, Exception) as e:  # a worker died (e.g. out of memory)
                rows.append({"plan": Path(s).stem, "source": s,
                             "error": f"{type(e).__name__}: {e}"})
    return rows


def _mean(values: list[float | None]) -> float | None:
    v = [x for x in values if x is not None and math.isfinite(x)]
    return float(np.mean(v)) if v else None


def overall(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Suite means and the suite-wide targets."""
    ok = [r for r in rows if "error" not in r]
    f = [r["forcelayout"] for r in ok]
    b = [r["baseline"] for r in ok]
    solvable = [r for r in ok if r["baseline"]["accepted"] > 0]
    f_good = sum(x["good"] for x in f)
    f_cpu = sum(x["samples"] * x["ms_per_sample"] / 1000 for x in f)
    b_good = sum(x["accepted"] for x in b)
    b_cpu = sum(x["tries"] * (x["ms_per_try"] or 0.0) / 1000 for x in b)
    f_rate = f_good / f_cpu if f_cpu > 0 else None
    b_rate = b_good / b_cpu if b_cpu > 0 else None
    mean_solvable = _mean([r["forcelayout"]["yield_pct"] for r in solvable])

    def every(key: str) -> bool | None:
        v = [r["targets"][key] for r in ok if r["targets"][key] is not None]
        return all(v) if v else None

    targets = {
        "yield_each": every("yield"),
        "yield_mean": (mean_solvable >= 100 * YIELD_MEAN) if mean_solvable is not None else None,
        "not_below_baseline": every("not_below_baseline"),
        "diversity": every("diversity"),
        "speed_each": every("speed"),
        "speed_suite": (f_rate >= SPEED_SUITE * b_rate) if f_rate and b_rate else None,
    }
    return {
        "plans": len(rows),
        "errors": len(rows) - len(ok),
        "baseline_solvable": len(solvable),
        "objects": _mean([r["objects"] for r in ok]),
        "fill_pct": _mean([r["fill_pct"] for r in ok]),
        "forcelayout": {
            "yield_pct": _mean([x["yield_pct"] for x in f]),
            "yield_pct_solvable": mean_solvable,
            "good_per_s": f_rate,
            "geometric": _mean([x["geometric"] for x in f]),
            "topological": _mean([x["topological"] for x in f]),
            "repaired_pct": _mean([x["repaired_pct"] for x in f]),
        },
        "baseline": {
            "yield_pct": _mean([x["yield_pct"] for x in b]),
            "good_per_s": b_rate,
            "geometric": _mean([x["geometric"] for x in b]),
            "topological": _mean([x["topological"] for x in b]),
        },
        "speed_ratio": f_rate / b_rate if f_rate and b_rate else None,
        "targets": targets,
        **({"baseline_again": _chance(ok)} if any("baseline_again" in r for r in ok) else {}),
    }


def _chance(rows: list[dict[str, Any]]) -> dict[str, int]:
    """How many plans the baseline's second run passes the diversity target on against its
    first, of how many judged, and on how many it is clearly below."""
    t = [r["baseline_again"]["targets"] for r in rows if "baseline_again" in r
         and r["baseline_again"]["targets"]["diversity"] is not None]
    return {"judged": len(t), "diversity": sum(bool(x["diversity"]) for x in t),
            "clearly_below": sum(bool(x["diversity_clearly_below"]) for x in t)}


# -- output -------------------------------------------------------------------------------


def _num(x: Any, digits: int = 1) -> str:
    return "–" if x is None or (isinstance(x, float) and not math.isfinite(x)) \
        else f"{x:.{digits}f}"


def _mark(v: bool | None) -> str:
    return "–" if v is None else ("pass" if v else "FAIL")


def _diversity_count(rows: list[dict[str, Any]]) -> str:
    """How many plans pass the diversity target, and on how few baseline layouts the failures'
    baseline figures rest (a mean over 3 layouts is a rough estimate)."""
    judged = [r for r in rows if "error" not in r and r["targets"]["diversity"] is not None]
    failed = [r for r in judged if not r["targets"]["diversity"]]
    thin = sum(r["baseline"]["accepted"] < FEW_LAYOUTS for r in failed)
    clear = sum(bool(r["targets"].get("diversity_clearly_below")) for r in failed)
    return (f"{len(judged) - len(failed)} of {len(judged)} plans; of the {len(failed)} below, "
            f"{thin} against fewer than {FEW_LAYOUTS} baseline layouts, {clear} clearly "
            f"below (the {RATIO_LEVEL:.0%} bootstrap interval of a ratio wholly under "
            f"{DIVERSITY_RATIO})")


def _diversity_below(rows: list[dict[str, Any]]) -> str:
    """The plans below the diversity target, each ratio under it with its interval."""
    out = []
    for r in rows:
        if "error" in r or r["targets"]["diversity"] is not False:
            continue
        f, b = r["forcelayout"], r["baseline"]
        parts = []
        for m, short in zip(METRICS, ("geo", "topo"), strict=True):
            if b[m] is None or (f[m] is not None and f[m] >= DIVERSITY_RATIO * b[m]):
                continue
            ratio = (f[m] or 0.0) / b[m]
            ci = r["diversity_ratio"].get(m)
            span = f" [{ci[0]:.2f}, {ci[1]:.2f}]" if ci and math.isfinite(ci[1]) else ""
            parts.append(f"{short} {ratio:.2f}{span}")
        rules = ""
        if f.get("every_rule_pct") is not None and b.get("every_rule_pct") is not None:
            rules = (f"; every rule met in {f['every_rule_pct']:.0f} % of its good layouts, "
                     f"the baseline's {b['every_rule_pct']:.0f} %")
        out.append(f"\n  - {r['plan']}: " + ", ".join(parts) + rules)
    return "".join(out)


def _below(rows: list[dict[str, Any]], target: str, *, count: bool = True) -> str:
    """How many judged plans meet a per-plan target (with ``count``) and which do not."""
    judged = [r for r in rows if "error" not in r and r["targets"][target] is not None]
    failed = [r["plan"] for r in judged if not r["targets"][target]]
    text = f"{len(judged) - len(failed)} of {len(judged)} plans" if count else ""
    return text + (f"; below: {', '.join(failed)}" if failed else "")


def markdown(result: dict[str, Any]) -> str:
    head = ("| plan | objects | fill % | good % FL | good % BL | good/s FL | good/s BL "
            "| geo FL | geo BL | topo FL | topo BL | BL layouts | repaired % | yield | ≥ BL "
            "| diversity | speed |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in result["plans"]:
        if "error" in r:
            err = " ".join(r["error"].split()).replace("|", "/")
            lines.append(f"| {r['plan']} | error: {err[:100]} |" + " |" * 15)
            continue
        f, b, t = r["forcelayout"], r["baseline"], r["targets"]
        lines.append(
            f"| {r['plan']} | {r['objects']} | {_num(r['fill_pct'], 0)} "
            f"| {_num(f['yield_pct'], 0)} | {_num(b['yield_pct'], 1)} "
            f"| {_num(f['good_per_s'])} | {_num(b['good_per_s'])} "
            f"| {_num(f['geometric'], 3)} | {_num(b['geometric'], 3)} "
            f"| {_num(f['topological'], 3)} | {_num(b['topological'], 3)} "
            f"| {b['accepted']} | {_num(f['repaired_pct'], 0)} | {_mark(t['yield'])} "
            f"| {_mark(t['not_below_baseline'])} | {_mark(t['diversity'])} "
            f"| {_mark(t['speed'])} |")
    o = result["overall"]
    fo, bo, to = o["forcelayout"], o["baseline"], o["targets"]
    lines.append(
        f"| **overall** | {_num(o['objects'])} | {_num(o['fill_pct'], 0)} "
        f"| {_num(fo['yield_pct'], 0)} | {_num(bo['yield_pct'], 1)} "
        f"| {_num(fo['good_per_s'])} | {_num(bo['good_per_s'])} "
        f"| {_num(fo['geometric'], 3)} | {_num(bo['geometric'], 3)} "
        f"| {_num(fo['topological'], 3)} | {_num(bo['topological'], 3)} "
        f"| | {_num(fo['repaired_pct'], 0)} | {_mark(to['yield_each'])} "
        f"| {_mark(to['not_below_baseline'])} | {_mark(to['diversity'])} "
        f"| {_mark(to['speed_each'])} |")
    lines += [
        "",
        f"Targets over {o['plans']} plans ({o['errors']} errors; the baseline solves "
        f"{o['baseline_solvable']}):",
        f"- good yield ≥ {YIELD_EACH:.0%} on every plan the baseline solves: "
        f"{_mark(to['yield_each'])} ({_below(result['plans'], 'yield')}); "
        f"mean ≥ {YIELD_MEAN:.0%} there "
        f"({_num(fo['yield_pct_solvable'])} %): {_mark(to['yield_mean'])}",
        f"- never below the baseline's yield: {_mark(to['not_below_baseline'])}",
        f"- diversity ≥ {DIVERSITY_RATIO} × the baseline's on every plan: "
        f"{_mark(to['diversity'])} ({_diversity_count(result['plans'])})"
        + _diversity_below(result["plans"]),
        *([f"- the same test, the baseline's second run (the next seed) against its "
           f"first: {c['diversity']} of {c['judged']} plans at ≥ {DIVERSITY_RATIO} ×, "
           f"{c['clearly_below']} clearly below (a sampler as diverse as the baseline "
           f"passes it this often)"] if (c := o.get("baseline_again")) else []),
        f"- good/s ≥ the baseline's on every plan of ≥ {SPEED_MIN_OBJECTS} objects: "
        f"{_mark(to['speed_each'])} ({_below(result['plans'], 'speed')}); "
        f"≥ {SPEED_SUITE:g} × over the suite "
        f"({_num(o['speed_ratio'], 2)} ×): {_mark(to['speed_suite'])}",
    ]
    return "\n".join(lines)


def add_plan_arguments(ap: argparse.ArgumentParser, samples_help: str) -> None:
    """The options every plan-suite script takes: plans, samples, baseline tries, seed, jobs,
    ``--quick``, ``--markdown``, ``--out``."""
    ap.add_argument("--plans", nargs="*", default=None,
                    help="bundled plan names, plan JSON files or folders of them "
                         f"(default: {PLANS_DIR.name}/*.json)")
    ap.add_argument("--samples", type=int, default=30, help=samples_help)
    ap.add_argument("--baseline-tries", type=int, default=2000,
                    help="most tries of the rejection baseline per plan (default 2000)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--batch", type=int, default=fl.Options().batch,
                    help="forcelayout samples simulated together (default "
                         f"{fl.Options().batch}, as generate runs them)")
    ap.add_argument("--jobs", type=int, default=None,
                    help=f"worker processes over plans (default {default_jobs()})")
    ap.add_argument("--quick", action="store_true",
                    help="3 samples, 60 baseline tries: a smoke run")
    ap.add_argument("--markdown", action="store_true", help="also print a Markdown table")
    ap.add_argument("--out", default=None, help="also write the JSON to this file")


def parse_plan_arguments(ap: argparse.ArgumentParser, argv: list[str] | None,
                         counts: tuple[str, ...] = ("samples", "baseline_tries", "batch")
                         ) -> argparse.Namespace:
    """Parse, apply ``--quick``, refuse ``counts`` below 1 and fill in ``--jobs``."""
    args = ap.parse_args(argv)
    if args.quick:
        args.samples, args.baseline_tries = min(args.samples, 3), min(args.baseline_tries, 60)
    for name in counts:
        if getattr(args, name) < 1:
            ap.error(f"--{name.replace('_', '-')} must be >= 1")
    if args.jobs is None:
        args.jobs = default_jobs()
    if args.jobs < 1:
        ap.error("--jobs must be >= 1")
    return args


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_plan_arguments(ap, "raw forcelayout samples per plan, and layouts the baseline is "
                           "asked for (default 30)")
    ap.add_argument("--pairs-of", type=int, default=30,
                    help="diversity over at most this many good layouts per plan (default 30)")
    ap.add_argument("--baseline-again", action="store_true",
                    help="run the baseline again with the next seed and judge its diversity "
                         "against the first run's: the diversity test's chance level")
    args = parse_plan_arguments(ap, argv, ("samples", "baseline_tries", "pairs_of", "batch"))
    sources = resolve_plans(args.plans)
    t0 = time.perf_counter()
    rows = run_all(sources, args)
    result = {
        "benchmark": "suite",
        "forcelayout": fl.__version__,
        "config": {"plans": [r["plan"] for r in rows], "samples": args.samples,
                   "baseline_tries": args.baseline_tries, "pairs_of": args.pairs_of,
                   "seed": args.seed, "jobs": args.jobs, "batch": args.batch,
                   "good_rules": GOOD_RULES, "baseline_again": args.baseline_again},
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
