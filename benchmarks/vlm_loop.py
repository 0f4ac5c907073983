"""The V loop's acceptance and seconds per accepted scene with a scripted judge.

Runs :func:`forcelayout.validate.generate_validated` on each plan with a
judge whose verdicts are scripted: a sample is plausible with probability
``--accept`` (decided by a hash of its seed, so runs repeat exactly), after
``--latency`` seconds of simulated model time. With ``--judge http`` the
judge is the real :class:`forcelayout.validate.vlm.VLMJudge` (needs
``forcelayout[vlm]``) talking to a scripted chat-completions server on
127.0.0.1 (``tests/fake_openai.py``), so the figures include rendering the
two pictures and the HTTP round trip, but no model.

Prints JSON: per plan, samples drawn, the share passing the checks
(validity), the judge's acceptance rate (accepted / judged), seconds per
accepted scene, and how that time splits between sampling and the judge.

    python benchmarks/vlm_loop.py --plans bedroom living_room -n 10 --accept 0.85
    python benchmarks/vlm_loop.py --plans bedroom -n 5 --judge http
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path
from typing import Any

import forcelayout as fl
from forcelayout.validate import Verdict, generate_validated

ROOT = Path(__file__).resolve().parents[1]


def plausible(seed: int, accept: float) -> bool:
    """The scripted verdict of the sample with this seed."""
    return ((int(seed) * 2654435761) % 2**32) / 2**32 < accept


class ScriptedJudge:
    """Plausible with probability ``accept`` (by the seed), after ``latency`` seconds."""

    def __init__(self, accept: float, latency: float):
        self.accept, self.latency = accept, latency
        self.name = f"scripted:accept={accept:g},latency={latency:g}"

    def __call__(self, layout: fl.Layout) -> Verdict:
        if self.latency:
            time.sleep(self.latency)
        ok = plausible(layout.seed, self.accept)
        return Verdict(plausible=ok, reasons=[] if ok else ["scripted rejection"])


def http_script(count: int, accept: float) -> list[str]:
    """Replies of the scripted server: the k-th is plausible by the same hash of k."""
    return [json.dumps({"plausible": plausible(k, accept),
                        "reasons": [] if plausible(k, accept) else ["scripted rejection"],
                        "objects": []}) for k in range(count)]


def run_plan(plan: fl.Plan, args: argparse.Namespace, judge: Any) -> dict[str, Any]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = generate_validated(plan, args.n, args.max_attempts, judge=judge, seed=args.seed)
    s = run.summary()
    return {
        "plan": plan.name, "objects": len(plan.objects), "wanted": args.n,
        "accepted": s["accepted"], "attempted": s["attempted"], "valid": s["valid"],
        "judged": s["judged"], "unjudged": s["unjudged"],
        "validity_rate": round(s["validity_rate"], 4),
        "acceptance_rate": round(s["acceptance_rate"], 4) if s["judged"] else None,
        "seconds": round(s["seconds"], 3), "judge_seconds": round(s["judge_seconds"], 3),
        "seconds_per_accepted": round(s["seconds_per_accepted"], 3) if s["accepted"] else None,
        "judge_share_of_time": round(s["judge_seconds"] / s["seconds"], 4) if s["seconds"]
        else None,
        "rejection_reasons": s["rejection_reasons"],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--plans", nargs="+", default=["bedroom"],
                    help="bundled plan names or plan files (default bedroom)")
    ap.add_argument("-n", type=int, default=10, help="scenes to accept per plan (default 10)")
    ap.add_argument("--max-attempts", type=int, default=None,
                    help="sample budget per plan (default max(4 n, n + 20))")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--accept", type=float, default=0.85,
                    help="the scripted judge's acceptance probability (default 0.85, near the "
                         "paper's 87 %% VLM plausibility)")
    ap.add_argument("--latency", type=float, default=0.0,
                    help="simulated seconds per verdict of the scripted judge (default 0)")
    ap.add_argument("--judge", choices=["scripted", "http"], default="scripted",
                    help="scripted callable, or VLMJudge against a scripted local server")
    args = ap.parse_args()

    plans = [fl.load_plan(p) for p in args.plans]
    results = []
    for plan in plans:
        if args.judge == "scripted":
            results.append(run_plan(plan, args, ScriptedJudge(args.accept, args.latency)))
            continue
        sys.path.insert(0, str(ROOT / "tests"))
        from fake_openai import MAX_REQUESTS, FakeChatServer
        from forcelayout.validate.vlm import VLMJudge

        with FakeChatServer(http_script(MAX_REQUESTS, args.accept)) as srv:
            judge = VLMJudge(base_url=srv.url, model="scripted-fake-server", api_key="none",
                             timeout=30.0, max_retries=0)
            results.append(run_plan(plan, args, judge))
    accepted = sum(r["accepted"] for r in results)
    seconds = sum(r["seconds"] for r in results)
    print(json.dumps({
        "benchmark": "vlm_loop",
        "config": {"plans": [p.name for p in plans], "n": args.n, "seed": args.seed,
                   "max_attempts": args.max_attempts, "judge": args.judge,
                   "accept": args.accept, "latency": args.latency},
        "plans": results,
        "total": {"accepted": accepted, "seconds": round(seconds, 3),
                  "seconds_per_accepted": round(seconds / accepted, 3) if accepted else None},
    }, indent=2))


if __name__ == "__main__":
    main()
