"""The VLM judge against a real chat-completions server on 127.0.0.1 with image inputs."""

from __future__ import annotations

import json
import logging
import subprocess
import sys

import pytest

pytest.importorskip("openai")
pytest.importorskip("trimesh")

import forcelayout as fl  # noqa: E402
from fake_openai import FakeChatServer  # noqa: E402
from forcelayout.llm import LLMRequestError, ReplayError  # noqa: E402
from forcelayout.validate.vlm import (  # noqa: E402
    JudgePrompts,
    JudgeReplyError,
    VLMJudge,
    generate_validated,
    render_views,
)

SECRET = "sk-test-secret-0123456789"
PNG = b"\x89PNG\r\n\x1a\n"
PLAN = "bedroom"  # seed 0: samples 1, 2, 4, 5 pass the checks, 0 and 3 do not

YES = json.dumps({"plausible": True, "reasons": ["tidy"], "objects": []})
NO = json.dumps({"plausible": False, "reasons": ["the desk chair faces the wall"],
                 "objects": [{"object": "desk_chair", "complaint": "faces away from the desk"}]})


@pytest.fixture(scope="module")
def layout() -> fl.Layout:
    return fl.solve(PLAN, 1)


def judge_for(srv: FakeChatServer, **kw) -> VLMJudge:
    kw.setdefault("timeout", 5.0)
    return VLMJudge(base_url=srv.url, model="fake-vl", api_key=SECRET, max_retries=0, **kw)


def test_without_the_extra_the_import_names_it():
    for missing in ("openai", "trimesh"):
        code = (f"import sys; sys.modules[{missing!r}] = None\n"
                "try:\n    import forcelayout.validate.vlm\nexcept ImportError as e:\n"
                "    print(e)\nelse:\n    print('imported')")
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             timeout=60).stdout
        assert 'pip install "forcelayout[vlm]"' in out, out


def test_the_judge_sends_two_pictures_and_the_objects_and_parses_the_verdict(layout):
    with FakeChatServer([NO]) as srv:
        verdict = judge_for(srv)(layout)
        body = srv.requests[0]
        images = srv.images()
    assert not verdict.plausible and verdict.objects[0].object == "desk_chair"
    assert verdict.reason() == ("the desk chair faces the wall; desk_chair: faces away from "
                                "the desk")
    assert len(images) == 2 and all(img.startswith(PNG) for img in images)
    assert body["model"] == "fake-vl"
    assert body["response_format"]["type"] == "json_schema"
    assert "plausible" in body["response_format"]["json_schema"]["schema"]["properties"]
    system, user = body["messages"]
    assert system["role"] == "system" and "not instructions" in system["content"]
    text = user["content"][0]["text"]
    assert "- desk_chair: chair, 0.50 x 0.50 x 0.90" in text and "at_wall(bed)" in text
    assert [p["type"] for p in user["content"]] == ["text", "image_url", "image_url"]


def test_pictures_are_the_same_bytes_for_the_same_layout(layout):
    a, b = render_views(layout), render_views(layout)
    assert a == b and list(a) == ["top", "perspective"]
    with pytest.raises(ValueError, match="unknown view"):
        render_views(layout, ["side"])


def test_prompts_and_views_can_be_replaced(layout):
    prompts = JudgePrompts(system="Be strict.", user="Room {name} ({views}). Verdict?")
    with FakeChatServer([YES]) as srv:
        assert judge_for(srv, prompts=prompts, views=["top"], detail="low")(layout).plausible
        system, user = srv.requests[0]["messages"]
        assert len(srv.images()) == 1
    assert system["content"] == "Be strict."
    assert user["content"][0]["text"].startswith("Room bedroom (1. a top-down plan")
    assert user["content"][1]["image_url"]["detail"] == "low"
    with pytest.raises(ValueError, match="views"):
        VLMJudge(client=object(), views=[])  # type: ignore[arg-type]


def test_malformed_json_is_asked_again_with_the_problem(layout):
    with FakeChatServer(['{"plausible": tru', "```json\n" + YES + "\n```"]) as srv:
        assert judge_for(srv)(layout).plausible
        retry = srv.requests[1]["messages"]
    assert retry[-2] == {"role": "assistant", "content": '{"plausible": tru'}
    assert "not valid JSON" in retry[-1]["content"]


def test_replies_that_are_no_verdict_raise_after_the_retries(layout):
    with FakeChatServer(['{"reasons": ["?"]}', "Looks fine to me!"]) as srv:
        with pytest.raises(JudgeReplyError, match="no verdict from vlm:fake-vl after 2 replies"):
            judge_for(srv)(layout)
    with FakeChatServer([{"refusal": "I can't help with that."}]) as srv:
        with pytest.raises(JudgeReplyError, match=r"empty \(a refusal\?\)"):
            judge_for(srv, retries=0)(layout)


def test_the_loop_marks_refusals_errors_and_slow_replies_unjudged_and_goes_on(caplog):
    caplog.set_level(logging.DEBUG)
    script = [
        {"refusal": "I'm unable to judge images."}, {"refusal": "Still unable."},  # 1st judged
        {"status": 500, "message": "upstream crashed"},                            # 2nd
        {"content": YES, "delay": 2.0},                                            # 3rd
        "not json at all", "{still not",                                           # 4th
        NO,                                                                        # 5th
        YES,                                                                       # 6th
    ]
    with FakeChatServer(script) as srv:
        judge = judge_for(srv, timeout=0.5)
        run = generate_validated(PLAN, 1, 20, judge=judge, seed=0)
        headers = srv.headers
    judged = [c for c in run.candidates if c.status != "invalid"]  # those the judge saw
    assert [c.status for c in judged] == ["unjudged"] * 4 + ["implausible", "accepted"]
    reasons = [c.reason for c in judged]
    assert "refusal" in reasons[0]
    assert "HTTP 500" in reasons[1] and "upstream crashed" in reasons[1]
    assert "no reply within 0.5 s" in reasons[2]
    assert "not valid JSON" in reasons[3] or "no JSON object" in reasons[3]
    assert reasons[4].startswith("the desk chair faces the wall")
    assert run.summary()["rejection_reasons"]["unjudged"] == 4
    assert run.judged == 2 and run.acceptance_rate == 0.5 and run.judge == "vlm:fake-vl"
    # the key goes to the server and nowhere else
    assert all({k.lower(): v for k, v in h.items()}["authorization"] == f"Bearer {SECRET}"
               for h in headers)
    shown = caplog.text + repr(judge) + json.dumps([c.reason for c in run.candidates])
    assert SECRET not in shown


def test_a_run_is_recorded_and_replayed_without_a_server(tmp_path):
    rec = tmp_path / "judge.jsonl"
    with FakeChatServer([NO, YES, YES]) as srv:
        live = generate_validated(PLAN, 2, 20, judge=judge_for(srv, record=rec), seed=0)
    text = rec.read_text()
    assert "base64" not in text and text.count("sha256:") == 6 and SECRET not in text
    assert len(text) < 30_000  # pictures are kept as digests
    again = generate_validated(PLAN, 2, 20, judge=VLMJudge(replay=rec, strict=True), seed=0)
    assert [lay.seed for lay in again] == [lay.seed for lay in live]
    assert again.verdicts == live.verdicts and again.judge == "vlm:fake-vl"
    # a strict replay notices changed pictures
    other = VLMJudge(replay=rec, strict=True, dpi=60)
    with pytest.raises(ReplayError, match="differs"):
        other(fl.solve(PLAN, fl.sampling.sample_seed(0, 1)))


def test_a_server_without_json_schema_is_asked_for_a_json_object(layout):
    with FakeChatServer([YES], json_schema=False) as srv:
        assert judge_for(srv, structured="auto")(layout).plausible
        # the client steps down to the next mode the server takes (json_object with the schema)
        assert srv.requests[0].get("response_format", {}).get("type") == "json_object"


def test_an_unreachable_server_is_a_request_error(layout):
    judge = VLMJudge(base_url="http://127.0.0.1:9/v1", model="m", api_key=SECRET,
                     max_retries=0, timeout=2.0)
    with pytest.raises(LLMRequestError, match="could not reach"):
        judge(layout)


def test_forcelayout_dataset_judge_vlm_records_and_replays(tmp_path, capsys):
    import hashlib

    from forcelayout.cli import main

    def digest(folder):
        return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
                for p in sorted(folder.rglob("*")) if p.is_file() and p.name != "run.log"}

    rec = tmp_path / "judge.jsonl"
    common = ["dataset", "bedroom", "-n", "2", "--seed", "0", "--pictures", "none", "--quiet",
              "--judge", "vlm"]
    with FakeChatServer([NO, YES, YES]) as srv:
        assert main([*common, "--out", str(tmp_path / "live"), "--base-url", srv.url,
                     "--model", "fake-vl", "--judge-record", str(rec)]) == 0
        assert len(srv.requests) == 3 and len(srv.images(0)) == 2
    assert "2/2 layouts" in capsys.readouterr().out
    summary = json.loads((tmp_path / "live" / "bedroom" / "summary.json").read_text())
    assert summary["judge"] == "vlm:fake-vl" and summary["failure_reasons"]["implausible"] == 1
    assert main([*common, "--out", str(tmp_path / "again"), "--judge-replay", str(rec)]) == 0
    assert digest(tmp_path / "again") == digest(tmp_path / "live")
    assert main([*common, "--out", str(tmp_path / "x"), "--judge-replay",
                 str(tmp_path / "missing.jsonl")]) == 2
    assert "--judge vlm:" in capsys.readouterr().err
