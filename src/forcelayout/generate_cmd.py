"""``forcelayout generate``: many layouts of one plan written to a folder.

Writes, per accepted layout, ``<plan>_<k>.json`` (poses, report, rule
results) and a top-down picture, plus ``summary.json`` with counts, rates,
timing and the reasons rejected samples failed.

A plan that looks infeasible before sampling gets one ``warning:`` line on
stderr before the samples run; a run with fewer layouts than asked for ends
with one ``hint:`` line on stderr (the dominant cause and what to try) and
exit status 1.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from concurrent.futures import Executor, ProcessPoolExecutor
from pathlib import Path

from forcelayout.diagnose import FeasibilityWarning, FewLayoutsWarning
from forcelayout.plan import Plan
from forcelayout.sampling import Options, generate
from forcelayout.sources import load_plan

__all__ = ["run_generate"]


def _plan_from_args(args: argparse.Namespace) -> Plan:
    prompt = getattr(args, "prompt", None)
    if prompt:
        from forcelayout.llm.cli import plan_for_generate

        return plan_for_generate(args)
    if not args.plan:
        raise FileNotFoundError("give a plan JSON file or bundled plan name (or --prompt)")
    return load_plan(args.plan)


def run_generate(args: argparse.Namespace) -> int:
    """Run the ``generate`` sub-command; returns the exit status."""
    plan = _plan_from_args(args)
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    opts = Options(relations=not args.no_relations, decor=not args.no_decor)
    executor: Executor | None = ProcessPoolExecutor(args.workers) if args.workers > 1 else None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", FewLayoutsWarning)  # said below as a hint
            warnings.simplefilter("always", FeasibilityWarning)
            show = warnings.showwarning

            def say(message, category, *rest, **kw):  # a feasibility warning as one plain line
                if issubclass(category, FeasibilityWarning):
                    print(" ".join(f"warning: {message}".split()), file=sys.stderr, flush=True)
                else:
                    show(message, category, *rest, **kw)

            warnings.showwarning = say
            result = generate(plan, args.n, seed=args.seed, executor=executor,
                              max_attempts=args.max_attempts, progress=not args.quiet,
                              options=opts)
    finally:
        if executor is not None:
            executor.shutdown()
    (out / "plan.json").write_text(plan.to_json(), encoding="utf-8")
    for k, lay in enumerate(result):
        stem = out / f"{plan.name}_{k:03d}"
        lay.save(stem.with_suffix(".json"))
        if args.format != "none":
            lay.picture(stem.with_suffix(f".{args.format}"))
    summary = result.summary()
    summary["rejected"] = [{"seed": r.seed, "failures": r.failures} for r in result.rejected]
    (out / "summary.json").write_text(json.dumps(summary, indent=2), encoding="utf-8")
    print(f"{plan.name}: {summary['accepted']}/{args.n} layouts from {summary['attempted']} "
          f"samples in {summary['seconds']:.1f} s ({summary['valid_fraction']:.0%} valid, "
          f"{summary['mean_rule_satisfaction']:.0%} of rules met) -> {out}")
    if summary["failure_reasons"]:
        print("rejections: " + ", ".join(f"{k} x{v}" for k, v in
                                         summary["failure_reasons"].items()))
    hint = result.hint(cli=True)
    if hint is not None:
        print(f"hint: {hint}", file=sys.stderr)
        return 1
    return 0
