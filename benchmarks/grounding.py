"""Asset grounding: retrieval accuracy per embedder, grounding time, solver yield with meshes.

Builds the example asset library (examples/09_asset_library.py) and prints JSON with

* ``retrieval`` — per embedder (lexical always; MiniLM with the ``grounding``
  extra; CLIP with the ``clip`` extra and ``--clip-weights``): top-1 accuracy on
  the labelled plan objects of tests/grounding_queries.py, both as
  :func:`forcelayout.grounding.ground_plan` searches (category filter + size
  penalty, ``top1``) and on the words alone (no category, no size,
  ``top1_words``); the seconds to build the index (``index_s``) and per query;
* ``grounding`` — seconds to ground each bundled plan (index already built)
  and how many objects got an asset;
* ``yield`` — for each bundled plan, ``--samples`` raw samples of the plan
  with its planned boxes, of the grounded plan (each object sized as its
  scaled mesh), and of the grounded plan with convex hull fixtures
  (``hull=True``): the fraction that passes the checks, rules met, and
  valid layouts per CPU second.

Usage::

    python benchmarks/grounding.py [--samples 20] [--plans bedroom living_room]
                                   [--embedders lexical minilm] [--clip-weights PATH]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

import forcelayout as fl
from forcelayout.grounding import AssetIndex, get_embedder, ground_plan
from forcelayout.sampling import sample_seed

ROOT = Path(__file__).resolve().parents[1]


def _load(path: Path, name: str) -> Any:
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def retrieval(library: Path, embedder: Any, queries: list) -> dict[str, Any]:
    """Top-1 accuracy of one embedder on the labelled queries."""
    t0 = time.perf_counter()
    index = AssetIndex(library, embedder, cache=False)
    index_s = time.perf_counter() - t0
    t1 = time.perf_counter()
    full = [index.search(d, category=c, size=s, k=1)[0].asset == want
            for c, d, s, want in queries]
    per_query = (time.perf_counter() - t1) / len(queries)
    words = [index.search(d, k=1)[0].asset == want for c, d, s, want in queries]
    return {"embedder": index.embedder.name, "queries": len(queries),
            "top1": round(float(np.mean(full)), 4), "top1_words": round(float(np.mean(words)), 4),
            "index_s": round(index_s, 3), "query_ms": round(per_query * 1000, 2),
            "misses": [q[1] for q, hit in zip(queries, full, strict=True) if not hit]}


def yield_of(plan: fl.Plan, samples: int, seed: int) -> dict[str, Any]:
    """Raw samples of ``plan``: valid fraction, rules met, valid layouts per CPU second."""
    valid, rules = [], []
    fl.solve(plan, 10**9, min_rule_satisfaction=0.0)  # warm-up: caches are not measured
    t0 = time.process_time()
    for k in range(samples):
        # validity is the deterministic checks alone; rules are measured apart
        lay = fl.solve(plan, sample_seed(seed, k), min_rule_satisfaction=0.0)
        valid.append(bool(lay.report.valid))
        rules.append(lay.rule_satisfaction)
    cpu = time.process_time() - t0
    return {"samples": samples, "valid_pct": round(100 * float(np.mean(valid)), 1),
            "rules_pct": round(100 * float(np.mean(rules)), 1),
            "valid_per_cpu_s": round(sum(valid) / cpu, 3) if cpu > 0 else None,
            "cpu_s": round(cpu, 2)}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=20, help="raw samples per plan and variant")
    ap.add_argument("--plans", nargs="+", default=list(fl.examples.list_plans()))
    ap.add_argument("--embedders", nargs="+", default=["lexical", "minilm"],
                    help="embedders to compare (those whose extra is missing are skipped)")
    ap.add_argument("--clip-weights", default=None, help="a CLIP checkpoint: adds 'clip'")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)

    example = _load(ROOT / "examples" / "09_asset_library.py", "asset_library_example")
    queries = _load(ROOT / "tests" / "grounding_queries.py", "grounding_queries").LABELLED_QUERIES
    with tempfile.TemporaryDirectory() as tmp:
        library = example.build_library(Path(tmp) / "assets")
        out: dict[str, Any] = {"benchmark": "grounding", "assets": len(example.ASSETS),
                               "config": {"samples": args.samples, "plans": args.plans,
                                          "seed": args.seed},
                               "retrieval": {}, "skipped": {}}
        embedders: dict[str, Any] = {}
        names = list(args.embedders) + (["clip"] if args.clip_weights else [])
        for name in names:
            try:
                kw = {"pretrained": args.clip_weights} if name == "clip" else {}
                embedders[name] = get_embedder(name, **kw)
            except ImportError as e:
                out["skipped"][name] = str(e).split(" Install")[0]
                continue
            out["retrieval"][name] = retrieval(library, embedders[name], queries)
        best = embedders.get("minilm") or embedders.get("lexical") or get_embedder("lexical")
        index = AssetIndex(library, best)
        out["grounding"] = {"embedder": index.embedder.name, "plans": {}}
        out["yield"] = {}
        for name in args.plans:
            plan = fl.load_plan(name)
            t0 = time.perf_counter()
            rep = ground_plan(plan, library, index=index)
            secs = time.perf_counter() - t0
            hull = ground_plan(plan, library, index=index, hull=True).plan
            out["grounding"]["plans"][name] = {"seconds": round(secs, 4),
                                               "objects": len(rep.objects),
                                               "matched": len(rep.matched)}
            out["yield"][name] = {"boxes": yield_of(plan, args.samples, args.seed),
                                  "meshes": yield_of(rep.plan, args.samples, args.seed),
                                  "meshes_hull": yield_of(hull, args.samples, args.seed)}
            print(f"{name}: done", file=sys.stderr)
    print(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
