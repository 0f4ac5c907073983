"""``forcelayout plan``, ``generate --prompt`` support, semantic diversity and reply parsing."""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fake_openai import FakeChatServer, bedroom_script
from forcelayout import Plan
from forcelayout.cli import main
from forcelayout.llm import (
    PlanningError,
    ReplyError,
    expand_prompts,
    make_client,
    parse_reply,
    plan_variants,
)
from forcelayout.llm.cli import plan_for_generate
from forcelayout.llm.steps import PromptList

ROOT = Path(__file__).parent.parent
RECORDING = ROOT / "examples" / "data" / "llm_bedroom.jsonl"


@pytest.fixture(autouse=True)
def _no_real_endpoint(monkeypatch):
    for name in ("OPENAI_API_KEY", "OPENAI_BASE_URL", "FORCELAYOUT_LLM_MODEL"):
        monkeypatch.delenv(name, raising=False)


def test_plan_command_writes_a_valid_plan(tmp_path, capsys):
    out = tmp_path / "plans" / "plan.json"
    with FakeChatServer(bedroom_script()) as srv:
        code = main(["plan", "a student's bedroom", "--out", str(out), "--base-url", srv.url,
                     "--model", "fake", "--llm-timeout", "2", "--record",
                     str(tmp_path / "run.jsonl")])
    assert code == 0
    plan = Plan.load(out)
    assert "bed" in plan.ids
    assert "5 objects" in capsys.readouterr().out
    # the recording replays from the command line, to stdout
    assert main(["plan", "a student's bedroom", "--replay", str(tmp_path / "run.jsonl")]) == 0
    assert Plan.from_json(capsys.readouterr().out).to_json() == plan.to_json()


def test_plan_command_no_decor(tmp_path):
    out = tmp_path / "plan.json"
    with FakeChatServer(bedroom_script(decor=False)) as srv:
        assert main(["plan", "a bedroom", "--out", str(out), "--no-decor",
                     "--base-url", srv.url, "--llm-timeout", "2"]) == 0
    assert not any(o.decor for o in Plan.load(out).objects)


def test_plan_command_reports_failure_with_exit_2(capsys):
    with FakeChatServer(["nonsense"] * 2) as srv:
        code = main(["plan", "a bedroom", "--base-url", srv.url, "--llm-timeout", "2",
                     "--llm-attempts", "2"])
    assert code == 2
    err = capsys.readouterr().err
    assert "planning step 'room' failed after 2 attempts" in err


def test_generate_prompt_plans_once_from_args(tmp_path):
    args = argparse.Namespace(prompt="a student's bedroom", replay=RECORDING, record=None,
                              base_url=None, model=None, llm_timeout=None, temperature=None,
                              llm_seed=None, llm_attempts=3, no_self_check=False)
    plan = plan_for_generate(args)
    assert plan.name == "student_bedroom" and any(o.decor for o in plan.objects)
    # options missing from the namespace fall back to defaults
    assert plan_for_generate(argparse.Namespace(prompt="x", replay=RECORDING)).to_json() \
        == plan.to_json()


def _prompts(*items: str) -> str:
    return json.dumps({"prompts": list(items)})


def test_expand_prompts_retries_until_distinct():
    script = [_prompts("a cosy bedroom", "A  cosy bedroom"),
              _prompts("a cosy bedroom", "a student's bedroom", "a guest bedroom")]
    with FakeChatServer(script) as srv:
        client = make_client(base_url=srv.url, timeout=2.0, max_retries=0)
        got = expand_prompts("bedroom", 2, client)
        feedback = srv.requests[1]["messages"][-1]["content"]
    assert got == ["a cosy bedroom", "a student's bedroom"]
    assert "1 distinct descriptions, 2 needed" in feedback


def test_plan_variants_plans_each_description():
    script = [_prompts("a student's bedroom", "a minimalist bedroom"),
              *bedroom_script(), *["broken"] * 2]
    with FakeChatServer(script) as srv:
        client = make_client(base_url=srv.url, timeout=2.0, max_retries=0)
        got = plan_variants("bedroom", 2, client, max_attempts=2)
        assert [p for p, _ in got] == ["a student's bedroom"]   # the second one failed
    with FakeChatServer(script) as srv:
        client = make_client(base_url=srv.url, timeout=2.0, max_retries=0)
        with pytest.raises(PlanningError):
            plan_variants("bedroom", 2, client, max_attempts=2, skip_failures=False)


def test_plan_command_variants_writes_one_plan_per_description(tmp_path):
    script = [_prompts("a student's bedroom"), *bedroom_script()]
    with FakeChatServer(script) as srv:
        assert main(["plan", "bedroom", "--variants", "1", "--out", str(tmp_path),
                     "--base-url", srv.url, "--llm-timeout", "2"]) == 0
    (path,) = tmp_path.glob("*.json")
    assert Plan.load(path).name == "student_bedroom"


texts = st.text(st.characters(blacklist_categories=("Cs",)), min_size=1, max_size=30)


@settings(max_examples=40, deadline=None)
@given(prompts=st.lists(texts, min_size=1, max_size=4),
       before=st.sampled_from(["", "Sure:\n", "Here is the JSON.\n"]),
       fence=st.booleans())
def test_replies_parse_with_or_without_fences_and_prose(prompts, before, fence):
    body = json.dumps({"prompts": prompts}, indent=1)
    text = before + ("```json\n" + body + "\n```" if fence else body)
    assert parse_reply(text, PromptList).prompts == prompts


@pytest.mark.parametrize("text,message", [
    ("", "no JSON object found"),
    ("[1, 2]", "expected a JSON object, got list"),
    ("{\"prompts\": [1}", "not valid JSON"),
    ("{\"prompts\": \"one\"}", "prompts: Input should be a valid list"),
    ("__import__('os').system('echo hi')", "no JSON object found"),
])
def test_bad_replies_are_errors_with_paths(text, message):
    with pytest.raises(ReplyError, match=message.replace("(", r"\(").replace(")", r"\)")):
        parse_reply(text, PromptList)


def test_example_runs_offline_in_replay_mode(tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    for name in ("OPENAI_API_KEY", "OPENAI_BASE_URL", "FORCELAYOUT_LLM_MODEL"):
        env.pop(name, None)
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "05_llm_plan.py"),
                           str(tmp_path / "out"), "--replay", str(RECORDING)],
                          cwd=tmp_path, capture_output=True, text=True, timeout=300, env=env)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert Plan.load(tmp_path / "out" / "plan.json").name == "student_bedroom"


def test_run_generate_plans_from_a_prompt_once(tmp_path):
    from forcelayout.generate_cmd import run_generate

    args = argparse.Namespace(
        prompt="a student's bedroom", replay=RECORDING, record=None, plan=None,
        out=tmp_path / "out", n=1, seed=0, workers=1, max_attempts=None, format="none",
        no_relations=False, no_decor=True, access=False, overwrite=False,
        quiet=True)
    assert run_generate(args) == 0
    assert Plan.load(tmp_path / "out" / "plan.json").name == "student_bedroom"
    assert len(list((tmp_path / "out").glob("student_bedroom_*.json"))) == 1


def test_bad_options_and_failed_generate_planning_are_clear_errors(tmp_path, capsys):
    assert main(["plan", "bedroom", "--variants", "500", "--out", str(tmp_path),
                 "--replay", str(RECORDING)]) == 2
    assert "ask for 1 to 100" in capsys.readouterr().err
    assert main(["plan", "bedroom", "--llm-attempts", "0", "--replay", str(RECORDING)]) == 2
    assert "max_attempts=0" in capsys.readouterr().err
    short = tmp_path / "short.jsonl"
    short.write_text(RECORDING.read_text().splitlines()[0] + "\n")
    with pytest.raises(SystemExit) as info:
        plan_for_generate(argparse.Namespace(prompt="a bedroom", replay=short))
    assert info.value.code == 2 and "holds 1 replies" in capsys.readouterr().err


def test_client_options_parse_into_what_plan_for_generate_reads(tmp_path):
    from forcelayout.llm.cli import add_client_options, client_options

    parser = argparse.ArgumentParser()
    parser.add_argument("--prompt")
    add_client_options(parser)
    args = parser.parse_args(["--prompt", "a bedroom", "--base-url", "http://127.0.0.1:9/v1",
                              "--model", "m", "--llm-timeout", "7", "--temperature", "0.5",
                              "--llm-seed", "3", "--record", str(tmp_path / "r.jsonl")])
    assert client_options(args) == {
        "record": tmp_path / "r.jsonl", "replay": None, "base_url": "http://127.0.0.1:9/v1",
        "model": "m", "timeout": 7.0, "temperature": 0.5, "seed": 3, "structured": "auto"}
    args = parser.parse_args(["--prompt", "a bedroom", "--replay", str(RECORDING)])
    assert plan_for_generate(args).name == "student_bedroom"


def test_dataset_plans_a_description_once_and_reuses_it_on_resume(tmp_path, capsys):
    out = tmp_path / "data"
    args = ["dataset", "a student's bedroom", "bedroom", "-n", "1", "--out", str(out),
            "--pictures", "none", "--quiet", "--replay", str(RECORDING)]
    assert main(args) == 0
    manifest = json.loads((out / "dataset.json").read_text())
    assert {"name": "student_bedroom", "prompt": "a student's bedroom"}.items() \
        <= manifest["plans"][0].items()
    assert (out / "student_bedroom" / "student_bedroom_000.json").exists()
    # resumed without the model: the plan comes from the folder
    assert main(args[:-2]) == 0
    assert "2 of them from an earlier run" in capsys.readouterr().out
