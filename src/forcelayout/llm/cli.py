"""``forcelayout plan``: a scene description in, a plan JSON out (needs ``forcelayout[llm]``).

::

    forcelayout plan "a student's bedroom" --out plan.json
    forcelayout plan "living room" --variants 6 --out plans/       # semantic diversity
    forcelayout plan "a student's bedroom" --replay run.jsonl      # no server needed

The server, model and key come from ``--base-url`` / ``--model`` or the
environment (``OPENAI_BASE_URL``, ``FORCELAYOUT_LLM_MODEL``,
``OPENAI_API_KEY``); the key is never taken on the command line, where
other users could read it.

``forcelayout generate --prompt "..."`` plans once with
:func:`plan_for_generate` and generates many layouts of that plan.
"""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path
from typing import Any

from forcelayout.llm.client import STRUCTURED_MODES, LLMRequestError, ReplayError
from forcelayout.llm.diversity import MAX_VARIANTS, plan_variants
from forcelayout.llm.planner import Planner, PlanningError, make_client
from forcelayout.plan import Plan

__all__ = ["register", "add_client_options", "client_options", "plan_for_generate",
           "setup_logging"]


def add_client_options(p: argparse.ArgumentParser) -> None:
    """Add the options that choose and configure the language model to ``p``."""
    p.add_argument("--base-url", default=None,
                   help="OpenAI-compatible server, e.g. http://localhost:11434/v1 "
                        "(default $OPENAI_BASE_URL, else OpenAI)")
    p.add_argument("--model", default=None,
                   help="model name (default $FORCELAYOUT_LLM_MODEL, else gpt-4o-2024-08-06)")
    p.add_argument("--llm-timeout", type=float, default=300.0,
                   help="seconds one planning step may take, its retries and repairs included "
                        "(default 300)")
    p.add_argument("--structured", choices=list(STRUCTURED_MODES), default="auto",
                   help="how to ask the server for JSON: response_format json_schema, "
                        "json_object with the schema (llama-cpp-python), none (in the prompt "
                        "only), or auto: try them in that order (default)")
    p.add_argument("--temperature", type=float, default=None, help="sampling temperature")
    p.add_argument("--llm-seed", type=int, default=None, help="sampling seed for the model")
    p.add_argument("--llm-attempts", type=int, default=3,
                   help="attempts per planning step (default 3)")
    p.add_argument("--no-self-check", action="store_true", help="skip the self-check step")
    p.add_argument("--no-relax", action="store_true",
                   help="keep every rule even if trial samples show no layout meets them")
    p.add_argument("--record", type=Path, default=None,
                   help="write every request and reply to this JSONL file")
    p.add_argument("--replay", type=Path, default=None,
                   help="answer from a recorded JSONL file instead of a server")
    p.add_argument("-v", "--verbose", action="count", default=0,
                   help="show each planning step, request, repair and fix on stderr")


def client_options(args: argparse.Namespace) -> dict[str, Any]:
    """Keyword arguments of :func:`forcelayout.llm.make_client` from parsed options."""
    out: dict[str, Any] = {"record": getattr(args, "record", None),
                           "replay": getattr(args, "replay", None)}
    if out["replay"] is None:
        out.update(base_url=getattr(args, "base_url", None), model=getattr(args, "model", None),
                   timeout=getattr(args, "llm_timeout", None) or 300.0,
                   temperature=getattr(args, "temperature", None),
                   seed=getattr(args, "llm_seed", None),
                   structured=getattr(args, "structured", None) or "auto")
    return out


class _StderrHandler(logging.StreamHandler):  # type: ignore[type-arg]
    """A stream handler that writes to whatever ``sys.stderr`` is at the time."""

    @property  # type: ignore[override]
    def stream(self) -> Any:
        return sys.stderr

    @stream.setter
    def stream(self, value: Any) -> None:
        pass


def setup_logging(args: argparse.Namespace) -> None:
    """Show the planner's log on stderr: INFO with ``-v`` (each step, attempt, repair, fix)."""
    level = logging.INFO if getattr(args, "verbose", 0) else logging.WARNING
    log = logging.getLogger("forcelayout.llm")
    if not any(getattr(h, "_forcelayout_cli", False) for h in log.handlers):
        handler = _StderrHandler()
        handler.setFormatter(logging.Formatter("%(levelname)s: %(message)s"))
        handler._forcelayout_cli = True  # type: ignore[attr-defined]
        log.addHandler(handler)
        log.propagate = False
    log.setLevel(level)


def _planner_kwargs(args: argparse.Namespace) -> dict[str, Any]:
    return {"self_check": not getattr(args, "no_self_check", False),
            "relax": not getattr(args, "no_relax", False),
            "max_attempts": 3 if getattr(args, "llm_attempts", None) is None
            else args.llm_attempts,
            "step_timeout": getattr(args, "llm_timeout", None) or 300.0}


def _summary(planner: Planner) -> str:
    return (f"{planner.requests} requests, {len(planner.failed_attempts)} repairs, "
            f"{len(planner.fixes)} fixes without asking"
            + (f", {len(planner.unresolved)} findings left" if planner.unresolved else ""))


def plan_for_generate(args: argparse.Namespace) -> Plan:
    """The plan for ``forcelayout generate --prompt TEXT``: planned once, with decor.

    Decorative items are always planned, so ``--no-decor`` drops them in the
    simulation from the same plan (as in the paper's −Decor condition).
    Reads ``args.prompt`` and the options of :func:`add_client_options` that
    are present on ``args``. A planning failure is printed to stderr and
    exits the command with status 2.
    """
    setup_logging(args)
    try:
        client = make_client(**client_options(args))
        planner = Planner(client, decor=True, **_planner_kwargs(args))
        plan = planner.plan(args.prompt)
    except (PlanningError, LLMRequestError, ReplayError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        raise SystemExit(2) from None
    print(f"planned {plan.name!r} from the prompt: {len(plan.objects)} objects, "
          f"{len(plan.rules)} rules ({_summary(planner)})", file=sys.stderr)
    return plan


def _cmd_plan(args: argparse.Namespace) -> int:
    setup_logging(args)
    planner = None
    try:
        client = make_client(**client_options(args))
        kwargs = {"decor": not args.no_decor, **_planner_kwargs(args)}
        if args.variants:
            if args.out is None:
                print("error: --variants needs --out DIR", file=sys.stderr)
                return 2
            args.out.mkdir(parents=True, exist_ok=True)
            got = plan_variants(args.prompt, args.variants, client, **kwargs)
            for k, (prompt, plan) in enumerate(got):
                path = plan.save(args.out / f"{k:03d}_{plan.name}.json")
                print(f"{path}: {prompt}")
            if len(got) < args.variants:
                print(f"warning: {args.variants - len(got)} of {args.variants} descriptions "
                      "could not be planned", file=sys.stderr)
                return 1
            return 0
        planner = Planner(client, **kwargs)
        plan = planner.plan(args.prompt)
    except (PlanningError, LLMRequestError, ReplayError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    for note in planner.unresolved:
        print(f"warning: {note}", file=sys.stderr)
    if args.out is None:
        print(plan.to_json())
    else:
        if args.out.parent != Path(""):
            args.out.parent.mkdir(parents=True, exist_ok=True)
        plan.save(args.out)
        print(f"{args.out}: {plan.name!r}, {len(plan.objects)} objects, {len(plan.rules)} rules "
              f"({_summary(planner)})")
    return 0


def register(sub: Any) -> None:
    """Add the ``plan`` sub-command to the ``forcelayout`` command's subparsers."""
    p = sub.add_parser("plan", help="plan a scene from a description with an LLM "
                                    "(OpenAI-compatible server)")
    p.add_argument("prompt", help="the scene in words, e.g. \"a student's bedroom\"")
    p.add_argument("-o", "--out", type=Path, default=None,
                   help="plan JSON file (default: print it); a folder with --variants")
    p.add_argument("--variants", type=int, default=0, metavar="K",
                   help=f"expand the prompt (a room type) into K distinct descriptions and plan "
                        f"each (1..{MAX_VARIANTS})")
    p.add_argument("--no-decor", action="store_true",
                   help="plan without secondary decorative items")
    add_client_options(p)
    p.set_defaults(func=_cmd_plan)
