"""Where a batch's CPU goes: the time of each kind of batched request.

A batch of samples runs as coroutines whose expensive steps are requests
(:mod:`forcelayout.batching`): simulations (``SimRequest``), verdicts on
floors (``JudgeRequest``), start poses (``ProposeRequest``) and relocations
of objects at fault (``RelocateRequest``). For each plan, ``--samples`` raw
samples run as one ``solve_many`` batch (after a small warm-up batch), with
every kind's ``run`` timed (process CPU time): its calls, requests answered,
seconds, share of the batch's CPU, and the share spent in calls for three
samples or fewer (the few samples still drawing starts once the rest of
their batch is done). What no kind takes is the rest (tops, walls and the
ceiling outside their simulations, the final checks and rule reports).

Prints JSON (``--markdown`` adds a table).

Usage::

    python benchmarks/requests.py [--plans living_room plans/] [--samples 64] [--markdown]
        [--out requests.json]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import dump  # noqa: E402
from suite import resolve_plans  # noqa: E402

import forcelayout as fl  # noqa: E402
from forcelayout import batching, initial, verdict  # noqa: E402
from forcelayout.sampling import sample_seed, solve_many  # noqa: E402

#: The kinds of batched request, by the name shown.
KINDS = {"simulate": batching.SimRequest, "judge": verdict.JudgeRequest,
         "propose": initial.ProposeRequest, "relocate": initial.RelocateRequest}
#: Calls answering this many requests or fewer count as the batch's tail.
SMALL = 3


def _timed(stats: dict[str, dict[str, float]]) -> None:
    """Wrap every kind's ``run`` to add its calls, requests and CPU seconds to ``stats``."""
    for name, kind in KINDS.items():
        run = kind.__dict__["run"].__func__

        def timed(requests: list, _run: Any = run, _name: str = name) -> Any:
            t = time.process_time()
            out = _run(requests)
            dt = time.process_time() - t
            s = stats[_name]
            s["calls"] += 1
            s["requests"] += len(requests)
            s["seconds"] += dt
            if len(requests) <= SMALL:
                s["small_seconds"] += dt
            return out

        kind.run = staticmethod(timed)


def _reset(stats: dict[str, dict[str, float]]) -> None:
    for name in KINDS:
        stats[name] = {"calls": 0, "requests": 0, "seconds": 0.0, "small_seconds": 0.0}


def measure(plan: fl.Plan, samples: int, seed: int, stats: dict[str, dict[str, float]]
            ) -> dict[str, Any]:
    """The request kinds' share of one batch of ``samples`` raw samples of ``plan``
    (``stats`` is what :func:`_timed` fills)."""
    solve_many(plan, [sample_seed(seed + 1, k) for k in range(4)])  # warm caches
    _reset(stats)
    t = time.process_time()
    solve_many(plan, [sample_seed(seed, k) for k in range(samples)])
    total = max(time.process_time() - t, 1e-9)
    kinds = {name: {**s, "share": s["seconds"] / total, "small_share": s["small_seconds"] / total}
             for name, s in stats.items()}
    small = sum(s["small_seconds"] for s in stats.values())
    rest = total - sum(s["seconds"] for s in stats.values())
    return {"plan": plan.name, "samples": samples, "seconds": total,
            "ms_per_sample": 1e3 * total / samples, "kinds": kinds,
            "rest_share": rest / total, "small_share": small / total}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--plans", nargs="*", default=None,
                    help="bundled plan names, plan JSON files or folders of them "
                         "(default: the living room and the kids' room with two beds)")
    ap.add_argument("--samples", type=int, default=64, help="raw samples per plan, one batch")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--markdown", action="store_true", help="also print a table")
    ap.add_argument("--out", default=None, help="also write the JSON here")
    args = ap.parse_args(argv)
    if args.samples < 1:
        ap.error("--samples must be >= 1")
    plans = resolve_plans(args.plans or [
        "living_room", str(Path(__file__).resolve().parent / "plans" /
                           "bedroom_kids_two_beds.json")])
    stats: dict[str, dict[str, float]] = {}
    _reset(stats)
    _timed(stats)
    rows = [measure(fl.load_plan(source), args.samples, args.seed, stats) for source in plans]
    result = {"benchmark": "requests", "samples": args.samples, "plans": rows}
    dump(result, args.out)
    if args.markdown:
        head = " | ".join(f"{k} %" for k in KINDS)
        print(f"\n| plan | ms / sample | {head} | rest % | in calls of <= {SMALL} samples % |")
        print("|---|---:|" + "---:|" * (len(KINDS) + 2))
        for r in rows:
            shares = " | ".join(f"{100 * r['kinds'][k]['share']:.0f}" for k in KINDS)
            print(f"| {r['plan']} | {r['ms_per_sample']:.1f} | {shares} | "
                  f"{100 * r['rest_share']:.0f} | {100 * r['small_share']:.0f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
