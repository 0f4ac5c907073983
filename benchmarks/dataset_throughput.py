"""Dataset throughput: layouts/s written to disk with 1 and 2 processes and a Dask LocalCluster.

For each executor (one process, a process pool of 2, a Dask ``LocalCluster``
of 2 single-threaded worker processes) and pictures on and off, writes a
dataset of ``-n`` layouts of each plan with :func:`forcelayout.build_dataset`
into a fresh folder and times it (the cluster's start-up is timed apart),
with the disk space per layout. Beside it, the library's rejection-sampling
baseline's good layouts/s on one core for the same plans (no files
written). With ``--ratio`` it also times ``n`` and ``10 n`` layouts of the
first plan (2 processes, no pictures): near 10 means the cost grows
linearly with the dataset.

Prints JSON. Usage::

    python benchmarks/dataset_throughput.py [--plans bedroom living_room] [-n 40]
                                            [--ratio 200] [--no-dask]
"""

from __future__ import annotations

import argparse
import json
import shutil
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import forcelayout as fl
from forcelayout.baselines import rejection_sample
from forcelayout.dataset import build_dataset


def timed(plans: list[str], n: int, executor, pictures: str, root: Path) -> dict:
    out = Path(tempfile.mkdtemp(dir=root))
    t0 = time.perf_counter()
    result = build_dataset(plans, n, out, executor=executor, pictures=pictures)
    seconds = time.perf_counter() - t0
    size = sum(p.stat().st_size for p in out.rglob("*") if p.is_file())
    shutil.rmtree(out)
    return {"pictures": pictures, "layouts": result.accepted, "seconds": round(seconds, 2),
            "layouts_per_s": round(result.accepted / seconds, 2),
            "kb_per_layout": round(size / max(result.accepted, 1) / 1024, 1)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--plans", nargs="+", default=["bedroom", "living_room"])
    ap.add_argument("-n", type=int, default=40, help="layouts per plan")
    ap.add_argument("--ratio", type=int, default=0,
                    help="also time N and 10 N layouts of the first plan (0: skip)")
    ap.add_argument("--no-dask", action="store_true")
    args = ap.parse_args()
    root = Path(tempfile.mkdtemp(prefix="fl-throughput-"))
    rows: list[dict] = []
    try:
        for pictures in ("none", "png"):
            rows.append({"executor": "1 process", **timed(args.plans, args.n, None, pictures,
                                                           root)})
        with ProcessPoolExecutor(2) as pool:
            for pictures in ("none", "png"):
                rows.append({"executor": "2 processes",
                             **timed(args.plans, args.n, pool, pictures, root)})
        if not args.no_dask:
            import distributed

            t0 = time.perf_counter()
            with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                          dashboard_address=":0") as cluster, \
                    distributed.Client(cluster) as client:
                startup = time.perf_counter() - t0
                for pictures in ("none", "png"):
                    rows.append({"executor": "Dask LocalCluster, 2 workers",
                                 "cluster_start_s": round(startup, 2),
                                 **timed(args.plans, args.n, client.get_executor(), pictures,
                                         root)})
        base_layouts, base_s = 0, 0.0
        for plan in args.plans:
            base = rejection_sample(fl.load_plan(plan), args.n, seed=0)
            base_layouts += len(base)
            base_s += base.seconds
        baseline = {"method": "rejection-sampling baseline, 1 process, no files",
                    "layouts": base_layouts, "seconds": round(base_s, 2),
                    "layouts_per_s": round(base_layouts / base_s, 2)}
        ratio = None
        if args.ratio:
            with ProcessPoolExecutor(2) as pool:
                small = timed(args.plans[:1], args.ratio, pool, "none", root)
                large = timed(args.plans[:1], 10 * args.ratio, pool, "none", root)
            ratio = {"plan": args.plans[0], "small": small, "large": large,
                     "cost_ratio": round(large["seconds"] / small["seconds"], 2)}
    finally:
        shutil.rmtree(root, ignore_errors=True)
    print(json.dumps({"plans": args.plans, "n_per_plan": args.n, "runs": rows,
                      "baseline": baseline, "n_vs_10n": ratio}, indent=2))


if __name__ == "__main__":
    main()
