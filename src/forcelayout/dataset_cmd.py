"""``forcelayout dataset``: many layouts of many plans, resumable, on processes or a cluster.

::

    forcelayout dataset SOURCES... -n N --out DIR [--seed S]
        [--workers W | --scheduler ADDRESS] [--pictures png|svg|none]
        [--export glb,usd,mjcf,habitat] [--assets DIR] [--overwrite]
        [--judge vlm | --judge MODULE:CALLABLE] [--judge-timeout S]

SOURCES are plan files, folders of plan files, bundled plan names, or
scene descriptions (with the ``llm`` extra; planned once, and reused when
the run is resumed). See :mod:`forcelayout.dataset` for the folder it
writes. ``--assets DIR`` grounds every plan to an asset library first
(:mod:`forcelayout.grounding`), so sizes and footprints are the meshes'.
Ctrl-C keeps every finished layout and says how to resume.

``--judge`` sends each layout that passes the checks to a plausibility
judge before it is written (the paper's V stage): ``vlm`` is
:class:`forcelayout.validate.vlm.VLMJudge` (needs ``forcelayout[vlm]``) on the
server of ``--base-url`` / ``--model`` (or ``--judge-replay FILE``), and
``MODULE:CALLABLE`` any judge of your own (see :mod:`forcelayout.validate.loop`).
"""

from __future__ import annotations

import argparse
import json
import sys
from concurrent.futures import Executor
from contextlib import ExitStack
from pathlib import Path
from typing import Any

from forcelayout import examples
from forcelayout.cli import ACCESS_HELP, MIN_RULES_HELP, _min_rules, _repaired_line
from forcelayout.dataset import INDEX, MANIFEST, DatasetError, build_dataset
from forcelayout.diagnose import feasibility_warnings_as_lines
from forcelayout.options import Options
from forcelayout.plan import Plan
from forcelayout.sampling import process_pool, stop_executor

__all__ = ["add_dataset_parser", "run_dataset"]


def add_dataset_parser(sub: Any, count: Any, share: Any) -> argparse.ArgumentParser:
    """Add the ``dataset`` sub-command to ``sub`` (``count(k)`` parses a whole number >= k,
    ``share`` a number between 0 and 1)."""
    d = sub.add_parser("dataset", help="a resumable dataset: N layouts of each plan, written as "
                       "they are accepted", description=__doc__.split("\n\n")[0])
    d.add_argument("sources", nargs="+", metavar="SOURCE",
                   help="plan JSON file, folder of plan files, bundled plan name, or (with "
                        "forcelayout[llm]) a scene description in quotes")
    d.add_argument("-n", type=count(1), required=True, help="layouts per plan")
    d.add_argument("-o", "--out", type=Path, required=True, help="the dataset's folder")
    d.add_argument("--seed", type=count(0), default=0, help="seed of the run (default 0)")
    where = d.add_mutually_exclusive_group()
    where.add_argument("--workers", type=count(1), default=1,
                       help="local processes (default 1)")
    where.add_argument("--scheduler", default=None, metavar="ADDRESS",
                       help="a Dask scheduler, e.g. tcp://10.0.0.5:8786 (needs forcelayout[dask])")
    d.add_argument("--pictures", choices=["png", "svg", "none"], default="png",
                   help="a top-down picture per layout (default png)")
    d.add_argument("--export", default="", metavar="FORMATS",
                   help="comma-separated 3D formats per layout: glb,usd,mjcf,habitat "
                        "(needs forcelayout[export])")
    d.add_argument("--movable", default="", metavar="CATEGORIES",
                   help="comma-separated categories exported as movable bodies")
    d.add_argument("--assets", type=Path, default=None, metavar="DIR",
                   help="ground every plan to this asset library first (needs "
                        "forcelayout[grounding]; see `forcelayout ground --help`)")
    d.add_argument("--max-attempts", type=count(0), default=None,
                   help="sample budget per plan (default max(4 N, N + 20))")
    d.add_argument("--access", action="store_true", help=ACCESS_HELP)
    d.add_argument("--min-rules", type=share, default=0.95, metavar="SHARE",
                   help=MIN_RULES_HELP)
    d.add_argument("--overwrite", action="store_true",
                   help="empty --out first if it holds another run's files")
    d.add_argument("--quiet", action="store_true", help="no progress bar")
    d.add_argument("--judge", default=None, metavar="JUDGE",
                   help="judge each layout before it is written: 'vlm' (a vision-language "
                        "model on --base-url/--model; needs forcelayout[vlm]) or "
                        "MODULE:CALLABLE (your own judge)")
    d.add_argument("--judge-timeout", type=float, default=None, metavar="S",
                   help="seconds to wait for each verdict; a late one leaves the layout "
                        "unjudged (default: none; the VLM judge's requests time out after "
                        "--llm-timeout)")
    d.add_argument("--judge-record", type=Path, default=None, metavar="FILE",
                   help="with --judge vlm: write every request and reply to this JSONL file")
    d.add_argument("--judge-replay", type=Path, default=None, metavar="FILE",
                   help="with --judge vlm: answer from a recording instead of a server")
    try:
        from forcelayout.llm.cli import add_client_options
    except ImportError:
        pass
    else:
        add_client_options(d)
    return d


def _is_prompt(text: str) -> bool:
    path = Path(text)
    return (not path.exists() and text not in examples.list_plans()
            and not text.lower().endswith(".json") and len(text.split()) > 1)


def _plans(args: argparse.Namespace) -> tuple[list[Any], dict[str, str]]:
    """Sources with scene descriptions replaced by plans (reused from the folder on resume)."""
    sources: list[Any] = []
    prompts: dict[str, str] = {}
    known: dict[str, str] = {}
    try:
        old = json.loads((args.out / MANIFEST).read_text(encoding="utf-8"))
        known = {e["prompt"]: e["name"] for e in old.get("plans", []) if "prompt" in e}
    except (OSError, ValueError, AttributeError, TypeError, KeyError):
        pass
    for text in args.sources:
        if not _is_prompt(text):
            sources.append(text)
            continue
        if text in known and not args.overwrite and (args.out / known[text] / "plan.json").exists():
            plan = Plan.load(args.out / known[text] / "plan.json")
        else:
            try:
                from forcelayout.llm.cli import plan_for_generate
            except ImportError:
                raise DatasetError(
                    f"{text!r} is neither a plan file, a folder nor a bundled plan "
                    f"({', '.join(examples.list_plans())}); planning from a description needs "
                    "pip install \"forcelayout[llm]\"") from None
            plan = plan_for_generate(argparse.Namespace(**{**vars(args), "prompt": text}))
        prompts[plan.name] = text
        sources.append(plan)
    return sources, prompts


def _executor(args: argparse.Namespace, stack: ExitStack) -> Executor | None:
    if args.scheduler:
        from forcelayout._optional import import_optional

        distributed = import_optional("distributed", "dask")
        try:
            client = stack.enter_context(distributed.Client(args.scheduler, timeout="20s"))
        except OSError as e:
            raise DatasetError(f"cannot reach the Dask scheduler at {args.scheduler}: {e}") \
                from None
        return client.get_executor()
    if args.workers > 1:
        return stack.enter_context(process_pool(args.workers))
    return None


def _judge(args: argparse.Namespace) -> Any:
    """The judge of ``--judge``, or None; a bad one is a :class:`DatasetError` in one line."""
    spec = getattr(args, "judge", None)
    if not spec:
        if getattr(args, "judge_record", None) or getattr(args, "judge_replay", None):
            raise DatasetError("--judge-record and --judge-replay need --judge vlm")
        return None
    if spec != "vlm":
        from forcelayout.validate.loop import load_judge

        try:
            return load_judge(spec)
        except ValueError as e:
            raise DatasetError(f"--judge: {e}") from None
    try:
        from forcelayout.validate.vlm import LLMRequestError, ReplayError, VLMJudge
    except ImportError as e:
        raise DatasetError(f"--judge vlm: {e}") from None
    kwargs: dict[str, Any] = {"record": args.judge_record, "replay": args.judge_replay}
    if args.judge_replay is None:
        kwargs.update(base_url=getattr(args, "base_url", None),
                      model=getattr(args, "model", None),
                      timeout=getattr(args, "llm_timeout", None) or 120.0,
                      temperature=getattr(args, "temperature", None),
                      seed=getattr(args, "llm_seed", None))
    try:
        return VLMJudge(**kwargs)
    except (LLMRequestError, ReplayError, OSError, ValueError) as e:
        raise DatasetError(f"--judge vlm: {e}") from None


def run_dataset(args: argparse.Namespace) -> int:
    """Run the ``dataset`` sub-command; returns the exit status."""
    exports = [f.strip() for f in args.export.split(",") if f.strip()]
    movable = [c.strip() for c in args.movable.split(",") if c.strip()]
    judge = _judge(args)
    sources, prompts = _plans(args)
    if args.assets is not None:
        from forcelayout.dataset import plan_sources
        from forcelayout.ground_cmd import ground_for_command

        sources = [r.plan for r in ground_for_command(plan_sources(sources), args)]
    try:
        with ExitStack() as stack:
            stack.enter_context(feasibility_warnings_as_lines())
            executor = _executor(args, stack)
            try:
                result = build_dataset(sources, args.n, args.out, seed=args.seed,
                                       executor=executor, pictures=args.pictures,
                                       exports=exports, movable=movable,
                                       max_attempts=args.max_attempts, overwrite=args.overwrite,
                                       options=Options(
                                           check_kwargs={"access_clearance": True}
                                           if args.access else {},
                                           min_rule_satisfaction=_min_rules(args)),
                                       prompts=prompts,
                                       progress=not args.quiet, judge=judge,
                                       assets=args.assets, judge_timeout=args.judge_timeout)
            except KeyboardInterrupt:
                if executor is not None:
                    stop_executor(executor)  # not after the batches running now
                raise
    except KeyboardInterrupt:  # also while the workers shut down
        index = Path(args.out) / INDEX
        done = len(index.read_text(encoding="utf-8").splitlines()) if index.exists() else 0
        where = (f"{done} finished layouts are in {args.out} ({INDEX})" if done
                 else "no layout was finished yet")
        print(f"interrupted: {where}; run the same command again to resume",
              file=sys.stderr)
        return 130
    resumed = f", {result.resumed} of them from an earlier run" if result.resumed else ""
    print(f"{result.accepted}/{result.wanted} layouts of {len(result.plans)} plan(s) in "
          f"{args.out}{resumed} ({result.seconds:.1f} s)")
    totals: dict[str, int] = {}  # over the plans' finished layouts
    for p in result.plans:
        for k, v in p.repaired.items():
            totals[k] = totals.get(k, 0) + v
    fixed = _repaired_line(totals, "layouts", result.accepted, "layouts")
    if fixed is not None:
        print(fixed)
    short = [p for p in result.plans if p.accepted < p.wanted]
    for p in short:
        print(f"hint: only {p.accepted} of {p.wanted} layouts of plan {p.name!r} from "
              f"{p.attempted} samples: {p.why}; loosen the plan or raise --max-attempts",
              file=sys.stderr)
    return 1 if short else 0
