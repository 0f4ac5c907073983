"""Kill ``forcelayout dataset`` at random moments, resume it, and compare with an unbroken run.

Runs the command once without interruption, then again in a second folder
killed (SIGKILL, or SIGINT with --signal int) after a random delay and
restarted with the same arguments until it finishes. Prints JSON: the number
of kills, whether every file of the two folders (``run.log`` aside) is byte
identical, and the wall times.

    python benchmarks/dataset_resume.py --plans bedroom living_room -n 40 --workers 2 --kills 5
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def digest(folder: Path) -> dict[str, str]:
    """sha256 of every file under ``folder`` except the run log."""
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file() and p.name != "run.log"}


def command(args: argparse.Namespace, out: Path) -> list[str]:
    cmd = [sys.executable, "-m", "forcelayout.cli", "dataset", *args.plans, "-n", str(args.n),
           "--out", str(out), "--seed", str(args.seed), "--workers", str(args.workers),
           "--pictures", args.pictures, "--quiet"]
    if args.export:
        cmd += ["--export", args.export]
    return cmd


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--plans", nargs="+", default=["bedroom", "living_room"])
    ap.add_argument("-n", type=int, default=40)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--pictures", default="png")
    ap.add_argument("--export", default="")
    ap.add_argument("--kills", type=int, default=5, help="kills before the run may finish")
    ap.add_argument("--signal", choices=["kill", "int"], default="kill")
    ap.add_argument("--rng", type=int, default=0, help="seed of the kill times")
    args = ap.parse_args()
    rng = random.Random(args.rng)
    root = Path(tempfile.mkdtemp(prefix="fl-resume-"))
    try:
        t0 = time.perf_counter()
        subprocess.run(command(args, root / "whole"), check=True, capture_output=True)
        whole_s = time.perf_counter() - t0
        sig = signal.SIGKILL if args.signal == "kill" else signal.SIGINT
        kills, runs, t0 = 0, 0, time.perf_counter()
        while runs < args.kills + 50:  # a cap: every run makes progress, so this ends
            runs += 1
            proc = subprocess.Popen(command(args, root / "broken"), stdout=subprocess.DEVNULL,
                                    stderr=subprocess.DEVNULL, start_new_session=True)
            if kills < args.kills:
                try:
                    proc.wait(timeout=rng.uniform(0.5, max(1.0, whole_s / 2)))
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, sig)
                    proc.wait()
                    kills += 1
                    continue
            else:
                proc.wait()
            if proc.returncode == 0:
                break
        broken_s = time.perf_counter() - t0
        a, b = digest(root / "whole"), digest(root / "broken")
        print(json.dumps({
            "plans": args.plans, "n": args.n, "workers": args.workers, "signal": args.signal,
            "kills": kills, "runs": runs, "files": len(a),
            "identical": a == b,
            "differing": sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))[:10],
            "uninterrupted_s": round(whole_s, 2), "killed_and_resumed_s": round(broken_s, 2),
        }, indent=2))
    finally:
        shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main()
