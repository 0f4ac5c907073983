"""``forcelayout ground``: a plan grounded to an asset library, written as a new plan.

::

    forcelayout ground PLAN.json --assets DIR --out grounded_plan.json
        [--embedder auto|minilm|lexical|clip] [-k K] [--min-score S]
        [--scale-by fit|width|depth|height|longest] [--hull] [--report REPORT.json]

Prints each object's match and score (or why it stays a box). The grounded
plan records on each object the matched asset's id (``asset``) and the
scaled size; ``generate`` and ``dataset`` take ``--assets DIR`` to ground
their plans first.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from forcelayout.plan import Plan

if TYPE_CHECKING:  # pragma: no cover
    from forcelayout.grounding import GroundingReport

# Literals, so that building the parser imports nothing of the extra (tests check that
# they are forcelayout.grounding's EMBEDDERS, SCALE_BY and defaults).
EMBEDDERS = ("auto", "minilm", "lexical", "clip")
SCALE_BY = ("fit", "width", "depth", "height", "longest")
DEFAULT_MIN_SCORE = 0.2
DEFAULT_SIZE_WEIGHT = 0.1

__all__ = ["register", "add_embedder_options", "embedder_from_args", "ground_for_command"]


def add_embedder_options(p: argparse.ArgumentParser) -> None:
    """Add ``--embedder`` and the CLIP options to a parser."""
    p.add_argument("--embedder", choices=EMBEDDERS, default="auto",
                   help="text embedder: auto (the packaged MiniLM model when "
                        "forcelayout[grounding] is installed, else lexical), minilm, lexical, "
                        "clip (needs forcelayout[clip] and --clip-weights)")
    p.add_argument("--clip-model", default="ViT-B-32", help="open_clip architecture "
                   "(default ViT-B-32)")
    p.add_argument("--clip-weights", default=None, metavar="PATH_OR_TAG",
                   help="CLIP weights: a checkpoint file, or an open_clip tag found in "
                        "--clip-cache")
    p.add_argument("--clip-cache", default=None, type=Path, metavar="DIR",
                   help="folder holding open_clip weights")


def embedder_from_args(args: argparse.Namespace) -> Any:
    """The embedder the options ask for."""
    from forcelayout.grounding import get_embedder

    name = getattr(args, "embedder", "auto") or "auto"
    if name == "clip":
        if not args.clip_weights:
            raise ValueError("--embedder clip needs --clip-weights (a checkpoint file, or an "
                             "open_clip tag with --clip-cache); no package ships CLIP weights")
        return get_embedder("clip", model=args.clip_model, pretrained=args.clip_weights,
                            cache_dir=args.clip_cache)
    return get_embedder(name)


def _fallback_note(embedder: Any, asked: str) -> str | None:
    from forcelayout.grounding import LexicalEmbedder

    if asked == "auto" and isinstance(embedder, LexicalEmbedder):
        return ("note: the packaged sentence-embedding model is not installed, so retrieval "
                "uses the lexical fallback (words only, no synonyms); pip install "
                "\"forcelayout[grounding]\" for the model")
    return None


def ground_for_command(plans: Sequence[Plan], args: argparse.Namespace, *,
                       stream: TextIO | None = None) -> list[GroundingReport]:
    """Ground ``plans`` to ``args.assets`` for ``generate`` / ``dataset``; one line per plan.

    The embedder is built once and the library's index is loaded once for all plans.
    Lines go to ``stream`` (default: standard error).
    """
    from forcelayout.grounding import AssetIndex, ground_plan

    stream = sys.stderr if stream is None else stream
    embedder = embedder_from_args(args)
    note = _fallback_note(embedder, getattr(args, "embedder", "auto") or "auto")
    if note:
        print(note, file=stream)
    index = AssetIndex(args.assets, embedder)
    reports = []
    for plan in plans:
        rep = ground_plan(plan, args.assets, index=index)
        boxes = f"; boxes: {', '.join(rep.boxes)}" if rep.boxes else ""
        print(f"{plan.name}: {len(rep.matched)}/{len(rep.objects)} objects grounded to "
              f"{args.assets} ({rep.embedder}){boxes}", file=stream)
        reports.append(rep)
    return reports


def _cmd_ground(args: argparse.Namespace) -> int:
    from forcelayout.grounding import AssetLibraryError, ground_plan
    from forcelayout.sources import load_plan

    try:
        plan = load_plan(args.plan)
        embedder = embedder_from_args(args)
        note = _fallback_note(embedder, args.embedder)
        if note:
            print(note, file=sys.stderr)
        rep = ground_plan(plan, args.assets, embedder=embedder, k=args.k,
                          min_score=args.min_score, size_weight=args.size_weight,
                          category_filter=not args.no_category_filter,
                          scale_by=args.scale_by, hull=args.hull)
    except (AssetLibraryError, ValueError, KeyError, OSError) as e:
        if args.debug:
            raise
        msg = e.args[0] if isinstance(e, KeyError) and e.args else e
        print(f"error: {msg}", file=sys.stderr)
        return 2
    for line in rep.lines():
        print(line)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    rep.plan.save(args.out)
    if args.report is not None:
        args.report.parent.mkdir(parents=True, exist_ok=True)
        args.report.write_text(json.dumps(rep.to_dict(), indent=2) + "\n", encoding="utf-8")
    cache = " (index from cache)" if rep.index_from_cache else ""
    print(f"{plan.name}: {len(rep.matched)}/{len(rep.objects)} objects grounded with "
          f"{rep.embedder} in {rep.seconds:.2f} s{cache} -> {args.out}")
    return 0


def _number(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if v != v or v in (float("inf"), float("-inf")):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return v


def _positive_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"{v} is less than 1")
    return v


def register(sub: Any) -> None:
    """Add the ``ground`` sub-command to the ``forcelayout`` parser's sub-parsers."""
    g = sub.add_parser("ground", help="give each object of a plan a mesh from an asset library",
                       description=__doc__.split("\n\n")[0])
    g.add_argument("plan", help="plan JSON file or bundled plan name")
    g.add_argument("--assets", type=Path, required=True, metavar="DIR",
                   help="asset library folder (meshes + assets.json)")
    g.add_argument("-o", "--out", type=Path, required=True, help="the grounded plan's JSON file")
    add_embedder_options(g)
    g.add_argument("-k", type=_positive_int, default=5, help="candidates kept per object "
                   "(in --report; default 5)")
    g.add_argument("--min-score", type=_number, default=DEFAULT_MIN_SCORE,
                   help=f"below this score an object stays a box (default {DEFAULT_MIN_SCORE})")
    g.add_argument("--size-weight", type=_number, default=DEFAULT_SIZE_WEIGHT,
                   help="score lost per metre of size difference (default "
                        f"{DEFAULT_SIZE_WEIGHT})")
    g.add_argument("--no-category-filter", action="store_true",
                   help="let assets of every category compete")
    g.add_argument("--scale-by", choices=SCALE_BY, default="fit",
                   help="dimension that drives the uniform scale (default fit: the largest "
                        "scale that fits the planned box)")
    g.add_argument("--hull", action="store_true",
                   help="record each mesh's convex outline as the solver's fixture")
    g.add_argument("--report", type=Path, default=None, metavar="JSON",
                   help="also write the candidates and scores as JSON")
    g.set_defaults(func=_cmd_ground)
