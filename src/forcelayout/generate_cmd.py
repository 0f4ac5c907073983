"""``forcelayout generate``: many layouts of one plan written to a folder.

Writes, per accepted layout and as soon as it is accepted,
``<plan>_<k>.json`` (poses, report, rule results; ``k`` zero-padded to the
width of ``n - 1``) and a top-down picture, plus ``plan.json`` first and
``summary.json`` at the end with counts, rates, timing and the reasons
rejected samples failed. The files of an earlier ``generate`` run in the same
folder are removed first. Ctrl-C keeps the layouts written so far. For large
runs that must survive interruptions, ``forcelayout dataset`` resumes.

With ``--assets DIR`` the plan is grounded to that asset library first
(:mod:`forcelayout.grounding`): ``plan.json`` is the grounded plan, each
object sized as its scaled mesh.

Before the samples run, a plan that looks tight or implausible gets a
``warning:`` line on stderr per note (those ``forcelayout validate`` prints),
and one that looks infeasible one more ``warning:`` line; a run with fewer
layouts than asked for ends with one ``hint:`` line on stderr (the dominant
cause and what to try) and exit status 1.
"""

from __future__ import annotations

import argparse
import glob
import json
import sys
import time
import warnings
from collections import Counter
from concurrent.futures import Executor, Future
from pathlib import Path

from forcelayout._text import one_line
from forcelayout.cli import _min_rules, _output_folder, _repaired_line
from forcelayout.dataset import layout_stem
from forcelayout.diagnose import FewLayoutsWarning, feasibility_warnings_as_lines
from forcelayout.errors import InputError
from forcelayout.layout import Layout
from forcelayout.pipeline import prepare
from forcelayout.plan import Plan
from forcelayout.sampling import (
    Options,
    generate,
    plan_feasibility,
    process_pool,
    solve,
    stop_executor,
)
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


def _remove_earlier_run(out: Path, name: str, overwrite: bool) -> None:
    """Remove the files an earlier ``generate`` run wrote to ``out`` (nothing else), saying
    so; the run of another plan only with ``overwrite``."""
    try:
        old = json.loads((out / "plan.json").read_text(encoding="utf-8"))["name"]
    except (OSError, ValueError, KeyError, TypeError):
        return
    files = [path for path in out.glob(f"{glob.escape(old)}_*")
             if path.stem[len(old) + 1:].isdigit() and path.suffix in (".json", ".png", ".svg")]
    layouts = sum(path.suffix == ".json" for path in files)
    some = f"{layouts} layout{'' if layouts == 1 else 's'} of plan {old!r}"
    if old != name and not overwrite:
        raise InputError(f"{out} holds {some} from an earlier run; give another --out, or "
                         f"--overwrite to replace them")
    for path in files:
        path.unlink()
    for kept in ("plan.json", "summary.json"):
        (out / kept).unlink(missing_ok=True)
    if layouts:
        print(f"replaced {some} an earlier run wrote to {out}", file=sys.stderr, flush=True)


def _draw(layout: Layout, path: Path, access: bool = False) -> None:
    """Write one layout's picture (in the main process or a worker), with its access
    zones when the run keeps them free."""
    layout.picture(path, show_access=access)


def _blocked_access(layouts: list[Layout]
                    ) -> tuple[list[int], Counter[str], dict[str, str]]:
    """Which of the layouts (their positions) leave some object with every access zone
    blocked (as the ``access`` check judges the zones), how often each such object, and
    what covers it most in the first layout where it is."""
    from forcelayout.access import blocked_objects

    which, objects, by = [], Counter[str](), {}
    for k, lay in enumerate(layouts):
        shut = blocked_objects(lay)
        if shut:
            which.append(k)
        objects.update(shut.keys())
        for oid, covers in shut.items():
            by.setdefault(oid, covers[0][0] if covers else "wall")
    return which, objects, by


def run_generate(args: argparse.Namespace) -> int:
    """Run the ``generate`` sub-command; returns the exit status."""
    _output_folder(args.out, make=False)
    plan = _plan_from_args(args)
    if getattr(args, "assets", None) is not None:
        from forcelayout.ground_cmd import ground_for_command

        plan = ground_for_command([plan], args)[0].plan
    opts = Options(relations=not args.no_relations, decor=not args.no_decor,
                   check_kwargs={"access_clearance": True} if args.access else {},
                   min_rule_satisfaction=_min_rules(args))
    # what `validate` warns of (a tight plan, implausible sizes), for the plan as this run
    # samples it (without decor with --no-decor); the infeasible notes come with the
    # feasibility warning of the run
    feas = plan_feasibility(plan, opts)
    for note in feas.notes[feas.blocking:]:
        print(f"warning: {note}", file=sys.stderr, flush=True)
    prepare(plan)  # a plan no sample can take is refused before anything is written
    out: Path = args.out
    _output_folder(out, make=True)
    _remove_earlier_run(out, plan.name, args.overwrite)
    (out / "plan.json").write_text(plan.to_json(), encoding="utf-8")
    written: list[Path] = []
    executor: Executor | None = process_pool(args.workers) if args.workers > 1 else None
    drawing: list[Future[None]] = []  # pictures drawn by the workers

    def write(lay: Layout) -> None:
        stem = out / layout_stem(plan.name, len(written), args.n)
        lay.save(stem.with_suffix(".json"))
        if args.format != "none":
            picture = stem.with_suffix(f".{args.format}")
            if executor is None:
                _draw(lay, picture, args.access)
            else:  # in a worker: drawing takes longer than sampling
                drawing.append(executor.submit(_draw, lay, picture, args.access))
        written.append(stem)

    start = time.perf_counter()
    try:
        with feasibility_warnings_as_lines():
            warnings.simplefilter("ignore", FewLayoutsWarning)  # said below as a hint
            result = generate(plan, args.n, seed=args.seed, executor=executor,
                              max_attempts=args.max_attempts, progress=not args.quiet,
                              on_layout=write, options=opts)
        for f in drawing:
            f.result()
        seconds = time.perf_counter() - start  # the pictures included
    except KeyboardInterrupt:
        if executor is not None:
            stop_executor(executor)
        print(f"interrupted: {len(written)} layouts written to {out}", file=sys.stderr)
        return 130
    finally:
        if executor is not None:
            executor.shutdown(cancel_futures=True)
    raised = next((r for r in result.rejected if any(f.startswith("error:") for f in r.failures)),
                  None)
    if raised is not None and getattr(args, "debug", False):
        solve(plan, raised.seed, options=opts)  # that sample again: raises with its traceback
    summary = result.summary()
    summary["rejected"] = [{"seed": r.seed, "failures": r.failures} for r in result.rejected]
    # how many accepted layouts leave each rule unmet (as the acceptance share allows)
    unmet = Counter(r.label for lay in result.layouts for r in lay.rule_report()
                    if r.satisfied is False)
    summary["unmet_rules"] = dict(unmet.most_common())
    (out / "summary.json").write_text(json.dumps(summary, indent=2), encoding="utf-8")
    print(f"{plan.name}: {summary['accepted']}/{args.n} layouts from {summary['attempted']} "
          f"samples in {seconds:.1f} s (of all samples: {summary['valid_fraction']:.0%} "
          f"passed the checks with at least {_min_rules(args):.0%} of their rules met; "
          f"{summary['mean_rule_satisfaction']:.0%} of rules met on average) -> {out}")
    short = sum(lay.report.rule_satisfaction < 1.0 for lay in result.layouts)
    if short:
        which = ", ".join(f"{label} x{k}" for label, k in unmet.most_common(3))
        if len(unmet) > 3:  # the rest counted, not dropped
            rest = sum(k for _, k in unmet.most_common()[3:])
            which += f"; {len(unmet) - 3} more x{rest}, each in summary.json"
        print(f"{short} of the {summary['accepted']} layouts leave a rule unmet, as "
              f"--min-rules {_min_rules(args):g} allows ({which}); --min-rules 1 asks for "
              "every rule")
    if summary["still_objects"]:
        still = summary["still_objects"]
        print(f"note: {', '.join(map(repr, still))} stand{'s' if len(still) == 1 else ''} in "
              f"the same spot in all {summary['accepted']} layouts: the room and rules leave "
              f"{'it' if len(still) == 1 else 'them'} one place (move a door or window, or "
              "loosen a rule, for variety)")
    if not args.access and result.layouts:  # kept free by forces only: say where it is not
        shut, objects, by = _blocked_access(result.layouts)
        if shut:
            which = ", ".join(f"{oid!r} x{k} (by {by[oid]!r})"
                              for oid, k in objects.most_common(3))
            files = [layout_stem(plan.name, k, args.n) for k in shut]  # as written
            named = ", ".join(files[:5]) + (f" and {len(files) - 5} more" if len(files) > 5
                                            else "")
            print(f"note: {len(shut)} of the {summary['accepted']} layouts leave an object no "
                  f"free access zone ({which}; {named}); --access asks for one in every "
                  "layout")
    if summary["failure_reasons"]:
        # the counts, and one line of the most common kind (summary.json has every line)
        top = next(iter(summary["failure_reasons"]))
        example = next((f for r in result.rejected for f in r.failures
                        if f.split(":")[0] == top), None)
        print("rejections: " + ", ".join(f"{k} x{v}" for k, v in
                                         summary["failure_reasons"].items())
              + (f" (e.g. {one_line(example, 160)})" if example else ""))
    fixed = _repaired_line(summary["repaired"], "samples", summary["attempted"], "samples")
    if fixed is not None:
        print(fixed)
    hint = result.hint(cli=True)
    if hint is not None:
        print(f"hint: {hint}", file=sys.stderr)
        return 1
    return 0
