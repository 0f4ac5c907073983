"""Plan a room from a sentence with a language model, then generate layouts of it.

Shows the L stage: a multi-step planner asks an OpenAI-compatible server
(OpenAI, vLLM, Ollama, LM Studio, ...) for the room, the objects with rules
from the registry's vocabulary, the scene graph, decorative items and a
self-check, validating every step. The plan is then realised into layouts.
Needs ``pip install "forcelayout[llm]"``.

The server comes from the environment: ``OPENAI_BASE_URL`` (e.g.
``http://localhost:11434/v1`` for Ollama), ``OPENAI_API_KEY`` and
``FORCELAYOUT_LLM_MODEL``. Without them, or with ``--replay FILE``, the
example answers from a recording instead: the bundled
``examples/data/llm_bedroom.jsonl`` holds scripted replies recorded from a
test server (one of them names an unknown rule, to show the repair loop).

Run: ``python examples/05_llm_plan.py [OUT_DIR] [--replay FILE] [--record FILE]
[--prompt TEXT]``
"""

# %%
import argparse
import os
import tempfile
from pathlib import Path

import forcelayout as fl
from forcelayout.llm import Planner, make_client

RECORDING = Path(__file__).parent / "data" / "llm_bedroom.jsonl"

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("out", nargs="?", type=Path, default=None, help="output folder")
parser.add_argument("--prompt", default="a student's bedroom")
parser.add_argument("--replay", type=Path, default=None, help="recorded JSONL run")
parser.add_argument("--record", type=Path, default=None, help="record the run to JSONL")
args = parser.parse_args()
out = args.out or Path(tempfile.mkdtemp())
out.mkdir(parents=True, exist_ok=True)

# %% A client: a live server from the environment, or a recorded run.
live = args.replay is None and bool(os.environ.get("OPENAI_BASE_URL")
                                    or os.environ.get("OPENAI_API_KEY"))
if live:
    client = make_client(record=args.record, timeout=120.0)
else:
    replay = args.replay or RECORDING
    print(f"no server configured: replaying {replay.name}")
    client = make_client(replay=replay, record=args.record)
print(client)

# %% Plan in five steps; every reply is validated, problems are sent back.
planner = Planner(client, decor=True, self_check=True, max_attempts=3)
plan = planner.plan(args.prompt)
print(f"{plan.name}: {len(plan.objects)} objects, {len(plan.rules)} rules")
for attempt in planner.failed_attempts:
    print(f"  repaired: {attempt}")
plan.save(out / "plan.json")

# %% The vocabulary the model chose from (generated from the rule registry).
names = [info.name for info in planner.vocabulary()]
print(f"{len(names)} rules offered: {', '.join(names)}")

# %% One plan, many layouts.
result = fl.generate(plan, 2, seed=0)
for k, layout in enumerate(result):
    layout.save(out / f"{plan.name}_{k}.json")
    layout.picture(out / f"{plan.name}_{k}.png")
print(f"{len(result)} layouts -> {out}")
