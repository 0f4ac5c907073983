"""The LLM planner against a real local HTTP server that speaks chat completions.

No network: every test talks to :class:`fake_openai.FakeChatServer` on
127.0.0.1, through the unchanged ``openai`` SDK, or replays a recording.
"""

from __future__ import annotations

import json
import logging
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from fake_openai import (
    DECOR,
    GRAPH,
    OBJECTS,
    FakeChatServer,
    bedroom_script,
    with_unknown_rule,
)
from forcelayout import Plan
from forcelayout.errors import MissingExtraError
from forcelayout.llm import (
    DEFAULT_TEMPLATES,
    LLMRequestError,
    OpenAIChatClient,
    Planner,
    PlanningError,
    RecordingClient,
    ReplayClient,
    ReplayError,
    make_client,
    plan_from_prompt,
)
from forcelayout.rules import Rule, register, unregister

PROMPT = "a student's bedroom"
SECRET = "sk-test-secret-0123456789"


@pytest.fixture
def server(request):
    """A scripted server; the script comes from ``script(...)`` (indirect parametrization)."""
    srv = FakeChatServer(getattr(request, "param", None) or bedroom_script())
    yield srv
    srv.close()


def script(replies):
    """Run the test against a server answering with ``replies``."""
    return pytest.mark.parametrize("server", [replies], indirect=True, ids=["scripted"])


def client_for(srv: FakeChatServer, **kw) -> OpenAIChatClient:
    kw.setdefault("timeout", 2.0)
    return OpenAIChatClient(base_url=srv.url, model="fake-model", api_key=SECRET,
                            max_retries=0, **kw)


def test_import_optional_names_the_extra():
    from forcelayout._optional import import_optional

    with pytest.raises(ImportError, match=r'pip install "forcelayout\[llm\]"') as info:
        import_optional("no_such_module_for_forcelayout", "llm")
    assert isinstance(info.value, MissingExtraError)


def test_llm_without_openai_raises_import_error_naming_the_extra():
    code = ("import sys; sys.modules['openai'] = None\n"
            "try:\n    import forcelayout.llm\nexcept ImportError as e:\n    print(e)\n"
            "else:\n    print('imported')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60).stdout
    assert 'pip install "forcelayout[llm]"' in out


def test_the_plan_command_imports_openai_only_to_talk_to_a_server():
    code = ("import sys, forcelayout.llm.cli, forcelayout.llm\n"
            "print('openai' in sys.modules)\n"
            "forcelayout.llm.OpenAIChatClient(base_url='http://127.0.0.1:9', model='m')\n"
            "print('openai' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60).stdout.split()
    assert out == ["False", "True"]


def test_five_steps_give_a_valid_plan_with_structured_output(server):
    plan = Planner(client_for(server)).plan(PROMPT)
    assert isinstance(plan, Plan)
    assert plan.ids == ["bed", "nightstand_1", "desk", "desk_chair", "plant"]
    assert plan.object("plant").decor and not plan.object("bed").decor
    assert plan.object("bed").area == "sleeping"
    assert [a.name for a in plan.areas] == ["sleeping", "work"]
    assert plan.areas[0].rules[0].rule == "at_wall"
    assert len(server.requests) == 5 and server.remaining == 0
    fmt = server.requests[1]["response_format"]
    assert fmt["type"] == "json_schema" and fmt["json_schema"]["name"] == "objects"
    enum = fmt["json_schema"]["schema"]["$defs"]["RuleDraft"]["properties"]["rule"]["enum"]
    assert {"at_wall", "next_to"} <= set(enum)
    graph = server.requests[2]["response_format"]["json_schema"]["schema"]
    area_rules = graph["$defs"]["AreaRuleDraft"]["properties"]["rule"]["enum"]
    assert "at_wall" in area_rules and "next_to" not in area_rules  # area rules are unary
    assert all(r["model"] == "fake-model" for r in server.requests)
    # the plan so far is shown to later steps
    assert '"bed"' in server.requests[2]["messages"][-1]["content"]


@script(bedroom_script(decor=False, check=False))
def test_no_decor_and_no_self_check_skip_their_steps(server):
    plan = Planner(client_for(server), decor=False, self_check=False).plan(PROMPT)
    assert len(server.requests) == 3
    assert not any(o.decor for o in plan.objects)


@script(bedroom_script()[:1] + ["```json\n{\"objects\": [ {\"id\": ]\n```"]
                    + bedroom_script()[1:])
def test_malformed_json_is_fed_back_and_retried(server):
    planner = Planner(client_for(server))
    plan = planner.plan(PROMPT)
    assert "bed" in plan.ids
    assert [a.step for a in planner.failed_attempts] == ["objects"]
    repair = server.requests[2]["messages"]
    assert repair[-2]["role"] == "assistant" and "not valid JSON" in repair[-1]["content"]


def _cut_objects() -> str:
    """The objects reply broken off inside its third rule (a server's token limit)."""
    text = json.dumps(OBJECTS)
    return text[:text.index('{"rule": "at_wall", "object": "desk"}') + 20]


@script(bedroom_script()[:1] + [_cut_objects()] + bedroom_script()[2:])
def test_a_reply_cut_off_is_read_up_to_its_last_whole_item(server):
    planner = Planner(client_for(server))
    plan = planner.plan(PROMPT)
    assert len(server.requests) == 5 and planner.failed_attempts == []
    assert [(r.rule, r.object) for r in plan.rules][:2] == [("at_wall", "bed"),
                                                              ("next_to", "nightstand_1")]
    assert not any(r.object == "desk" and r.rule == "at_wall" for r in plan.rules)
    assert any("objects: the reply broke off after" in f for f in planner.fixes)


@script(bedroom_script()[:1] + ['{"objects": [{"id": "bed", "category": "bed", "size": [1'] * 3)
def test_a_reply_cut_off_without_a_whole_item_asks_for_a_shorter_one(server):
    with pytest.raises(PlanningError) as err:
        Planner(client_for(server)).plan(PROMPT)
    assert "not valid JSON" in str(err.value) and "answer shorter" in str(err.value)
    assert len(server.requests) == 4  # the room, then the same reply three times


@script(bedroom_script()[:1] + [with_unknown_rule()] + bedroom_script()[1:])
def test_unknown_rule_is_fed_back_with_its_path(server):
    planner = Planner(client_for(server))
    planner.plan(PROMPT)
    feedback = server.requests[2]["messages"][-1]["content"]
    assert "rules[1] (hovers_over)" in feedback and "unknown rule 'hovers_over'" in feedback


def _objects_with_huge_wardrobe() -> str:
    bad = json.loads(json.dumps(OBJECTS))
    bad["objects"].append({"id": "wardrobe", "category": "wardrobe", "size": [9.0, 0.6, 2.0]})
    return json.dumps(bad)


@script(bedroom_script()[:1] + [_objects_with_huge_wardrobe()]
                    + bedroom_script()[1:])
def test_object_that_cannot_fit_is_fed_back(server):
    Planner(client_for(server)).plan(PROMPT)
    feedback = server.requests[2]["messages"][-1]["content"]
    assert "objects[4].size" in feedback and "larger than the room" in feedback


def _decor_clashing_id() -> str:
    bad = json.loads(json.dumps(DECOR))
    bad["rules"].append({"rule": "next_to", "object": "lamp", "target": "bed"})
    return json.dumps(bad)


@script(bedroom_script()[:3] + [_decor_clashing_id()] + bedroom_script()[3:])
def test_decor_problems_name_paths_in_the_decor_reply(server):
    Planner(client_for(server)).plan(PROMPT)
    feedback = server.requests[4]["messages"][-1]["content"]
    # rules[4] of the plan is rules[1] of the decor reply
    assert "rules[1] (next_to).object: unknown object 'lamp'" in feedback


def _graph_with_unknown_names() -> str:
    bad = json.loads(json.dumps(GRAPH))
    bad["areas"][0]["objects"] += ["bedd", "sleeping"]
    bad["support"] = [{"object": "lamp", "parent": "work"}]
    return json.dumps(bad)


@script(bedroom_script()[:2] + [_graph_with_unknown_names()] + bedroom_script()[3:])
def test_scene_graph_names_are_mapped_or_dropped_without_asking(server):
    planner = Planner(client_for(server))
    plan = planner.plan(PROMPT)
    assert not planner.failed_attempts  # nothing was sent back
    assert "scene_graph: areas[0].objects[2]: 'bedd' read as 'bed'" in planner.fixes
    assert ("scene_graph: areas[0].objects[3]: dropped the membership naming 'sleeping', "
            "which is no object of the plan") in planner.fixes
    assert any(f.startswith("scene_graph: support[0].object: dropped the support bond")
               for f in planner.fixes)
    assert "sleeping" not in plan.ids


@script(bedroom_script()[:1] + [{"delay": 3.0, "content": "{}"}]
                    + bedroom_script()[1:])
def test_slow_reply_times_out_and_is_retried(server):
    planner = Planner(client_for(server, timeout=0.5), step_timeout=10)
    plan = planner.plan(PROMPT)
    assert "desk" in plan.ids
    (failure,) = planner.failed_attempts
    assert failure.step == "objects" and "no reply within 0.5 s" in failure.reason


@script(bedroom_script()[:1] + [{"status": 500, "message": "overloaded"}]
                    + bedroom_script()[1:])
def test_http_500_is_retried(server):
    planner = Planner(client_for(server))
    planner.plan(PROMPT)
    (failure,) = planner.failed_attempts
    assert "HTTP 500" in failure.reason and "overloaded" in failure.reason


@script(bedroom_script()[:1] + ["not json", "{\"objects\": []}",
                                            {"status": 502, "message": "bad gateway"}])
def test_final_failure_carries_every_attempts_reason(server):
    with pytest.raises(PlanningError) as info:
        Planner(client_for(server), max_attempts=3).plan(PROMPT)
    err = info.value
    assert err.step == "objects" and len(err.attempts) == 3
    text = str(err)
    assert "no JSON object found" in text
    assert "objects: List should have at least 1 item" in text
    assert "HTTP 502" in text


@script([{"status": 401, "message": f"Incorrect API key provided: {SECRET}"}])
def test_api_key_never_shows(server, tmp_path, caplog):
    caplog.set_level(logging.DEBUG)
    client = client_for(server)
    rec = RecordingClient(client, tmp_path / "run.jsonl")
    with pytest.raises(PlanningError) as info:
        Planner(rec).plan(PROMPT)
    # not worth retrying: one attempt only
    assert len(info.value.attempts) == 1 and "HTTP 401" in str(info.value)
    auth = {k.lower(): v for k, v in server.headers[0].items()}["authorization"]
    assert auth == f"Bearer {SECRET}"  # sent to the server only
    for text in (str(info.value), repr(client), repr(rec), repr(Planner(rec)),
                 (tmp_path / "run.jsonl").read_text(), caplog.text):
        assert SECRET not in text


def test_server_without_structured_output_gets_json_in_text():
    with FakeChatServer(bedroom_script(), json_schema=False, json_object=False) as srv:
        client = client_for(srv)
        plan = Planner(client).plan(PROMPT)
        assert "bed" in plan.ids and client.mode == "none"
        assert all("response_format" not in r for r in srv.requests)
        # the reply's keys are still in the prompt text, in the schema's order
        text = srv.requests[1]["messages"][-1]["content"]
        assert text.index("- rule:") < text.index("- object:") < text.index("- target")


def test_replay_of_a_recorded_run_gives_the_identical_plan(tmp_path):
    script = bedroom_script()
    script.insert(1, "Here you go:\n```json\n" + with_unknown_rule() + "\n```")
    script.insert(3, {"status": 500, "message": "flaky"})
    path = tmp_path / "run.jsonl"
    with FakeChatServer(script) as srv:
        recorded = plan_from_prompt(PROMPT, record=path, base_url=srv.url, api_key=SECRET,
                                    timeout=2.0, max_retries=0)
    lines = [json.loads(x) for x in path.read_text().splitlines()]
    assert [x["name"] for x in lines] == ["room", "objects", "objects", "scene_graph",
                                          "scene_graph", "decor", "self_check"]
    assert "error" in lines[3]
    replayed = plan_from_prompt(PROMPT, replay=path)  # no server
    assert replayed.to_json() == recorded.to_json()
    strict = Planner(ReplayClient(path, strict=True)).plan(PROMPT)
    assert strict.to_json() == recorded.to_json()


def test_replay_reports_a_run_that_does_not_match(tmp_path):
    with FakeChatServer(bedroom_script()) as srv:
        plan_from_prompt(PROMPT, record=tmp_path / "run.jsonl", base_url=srv.url,
                         timeout=2.0, max_retries=0)
    # without the decor step, the recording's 4th reply is for another step
    with pytest.raises(ReplayError, match="recorded step 'decor'"):
        Planner(ReplayClient(tmp_path / "run.jsonl"), decor=False).plan(PROMPT)
    short = tmp_path / "short.jsonl"
    short.write_text("\n".join(tmp_path.joinpath("run.jsonl").read_text().splitlines()[:2]))
    with pytest.raises(ReplayError, match="holds 2 replies"):
        Planner(ReplayClient(short)).plan(PROMPT)
    with pytest.raises(ReplayError, match="strict replay"):
        Planner(ReplayClient(tmp_path / "run.jsonl", strict=True)).plan("a kitchen")


def test_a_plugin_rule_is_offered_and_usable():
    @register("near_plant_llm_test")
    class NearPlant(Rule):
        """Within reach of a plant, for watering it (test plugin)."""

        kind = "binary"

        def force(self, state, i, j, p):
            return np.zeros((len(i), 2)), np.zeros(len(i))

        def satisfied(self, state, i, j, p):
            return np.ones(len(i), dtype=bool)

    objects = json.loads(json.dumps(OBJECTS))
    objects["rules"].append({"rule": "near_plant_llm_test", "object": "desk_chair",
                             "target": "bed"})
    script = bedroom_script()
    script[1] = json.dumps(objects)
    try:
        with FakeChatServer(script) as srv:
            plan = Planner(client_for(srv)).plan(PROMPT)
            text = srv.requests[1]["messages"][0]["content"]  # the system message
            schema = srv.requests[1]["response_format"]["json_schema"]["schema"]
    finally:
        unregister("near_plant_llm_test")
    assert "- near_plant_llm_test: Within reach of a plant" in text
    assert "near_plant_llm_test" in schema["$defs"]["RuleDraft"]["properties"]["rule"]["enum"]
    assert any(r.rule == "near_plant_llm_test" for r in plan.rules)


def test_a_registered_rule_outside_the_offered_pattern_is_refused():
    script = bedroom_script()
    script.insert(2, script[1])  # same objects again; refused, then retried with feedback
    with FakeChatServer(script) as srv:
        with pytest.raises(PlanningError, match="not one of the rules offered"):
            Planner(client_for(srv), rules="at_*", max_attempts=2).plan(PROMPT)


def test_templates_can_be_overridden():
    templates = replace(DEFAULT_TEMPLATES, objects="LIST FURNITURE for $prompt using\n"
                                                   "$vocabulary\n$schema")
    with FakeChatServer(bedroom_script()) as srv:
        Planner(client_for(srv), templates=templates).plan(PROMPT)
        text = srv.requests[1]["messages"][-1]["content"]
    assert text.startswith("LIST FURNITURE for a student's bedroom using")
    bad = replace(DEFAULT_TEMPLATES, room="$nonsense")
    with pytest.raises(ValueError, match=r"uses \$nonsense"):
        Planner(make_client(replay=_example_recording()), templates=bad).plan(PROMPT)


def test_self_check_correction_given_at_once_replaces_the_plan():
    check = json.dumps({"issues": ["the chair is not needed"], "plan": _without_the_chair()})
    script = bedroom_script(check=False) + [check]
    with FakeChatServer(script) as srv:
        planner = Planner(client_for(srv))
        plan = planner.plan(PROMPT)
    assert plan.ids == ["bed", "nightstand_1", "desk"] and planner.requests == 5


def _without_the_chair() -> dict:
    merged = {**json.loads(bedroom_script()[0]), "objects": OBJECTS["objects"][:3],
              "rules": OBJECTS["rules"][:3]}
    return merged


def test_self_check_lists_problems_then_a_correction_is_asked_for():
    issues = json.dumps({"issues": ["the chair is not needed"]})
    fixed = json.dumps({"issues": [], "plan": _without_the_chair()})
    with FakeChatServer(bedroom_script(check=False) + [issues, fixed]) as srv:
        planner = Planner(client_for(srv))
        plan = planner.plan(PROMPT)
        check, correct = srv.requests[4], srv.requests[5]
    assert plan.ids == ["bed", "nightstand_1", "desk"]
    assert planner.requests == 6 and planner.failed_attempts == []
    # the check asks for the problems only; the correction gets them
    assert set(check["response_format"]["json_schema"]["schema"]["properties"]) == {"issues"}
    assert "- the chair is not needed" in correct["messages"][-1]["content"]
    assert "plan" in correct["response_format"]["json_schema"]["schema"]["properties"]


def test_a_claimed_absence_of_what_the_plan_has_is_dropped_without_asking():
    issues = json.dumps({"issues": ["The plan lacks a bed.", "There is no desk chair",
                                    "The plan lacks the nightstand 1.",
                                    "The plan has no bedside table.",
                                    "The plan lacks a second bed."]})
    fixed = json.dumps({"issues": [], "plan": _without_the_chair()})
    with FakeChatServer(bedroom_script(check=False) + [issues, fixed]) as srv:
        planner = Planner(client_for(srv))
        planner.plan(PROMPT)
        correct = srv.requests[5]["messages"][-1]["content"]
    assert "self_check: dropped the issue 'The plan lacks a bed.': the plan has 'bed'" \
        in planner.fixes
    assert "self_check: dropped the issue 'There is no desk chair': the plan has " \
        "'desk_chair'" in planner.fixes
    assert "self_check: dropped the issue 'The plan lacks the nightstand 1.': the plan has " \
        "'nightstand_1'" in planner.fixes
    assert "self_check: dropped the issue 'The plan has no bedside table.': the plan has a " \
        "nightstand" in planner.fixes
    assert "- The plan lacks a second bed." in correct and "lacks a bed." not in correct


def test_a_claimed_absence_of_what_the_description_does_not_ask_for_is_dropped():
    issues = json.dumps({"issues": ["The plan lacks a ceiling light.", "There are no pictures",
                                    "The plan lacks the description of the beds."]})
    with FakeChatServer(bedroom_script(check=False) + [issues]) as srv:
        planner = Planner(client_for(srv))
        planner.plan("a small bedroom with a desk")
    assert planner.requests == 5   # nothing left to correct
    assert "self_check: dropped the issue 'The plan lacks a ceiling light.': the " \
        "description does not ask for ceiling light" in planner.fixes
    assert any("'There are no pictures'" in f for f in planner.fixes)
    # what the description names, or its room type needs, is asked for
    issues = json.dumps({"issues": ["The plan lacks a wardrobe.", "There is no second bed"]})
    fixed = json.dumps({"issues": [], "plan": _without_the_chair()})
    with FakeChatServer(bedroom_script(check=False) + [issues, fixed]) as srv:
        planner = Planner(client_for(srv))
        planner.plan("a bedroom with a wardrobe")
        correct = srv.requests[5]["messages"][-1]["content"]
    assert "- The plan lacks a wardrobe." in correct and "- There is no second bed" in correct


def test_the_plan_shown_for_correction_writes_a_rules_target_before_its_params():
    # servers that turn the schema into a grammar fix the order of keys; a model copying the
    # plan must meet "target" where the schema has it, or it cannot write it at all
    issues = json.dumps({"issues": ["the chair is not needed"]})
    fixed = json.dumps({"issues": [], "plan": _without_the_chair()})
    with FakeChatServer(bedroom_script(check=False) + [issues, fixed]) as srv:
        Planner(client_for(srv)).plan(PROMPT)
        correct = srv.requests[5]
    text = correct["messages"][-1]["content"]
    shown = json.loads(text.split("The plan:\n", 1)[1].split("\n", 1)[0])
    schema = correct["response_format"]["json_schema"]["schema"]
    order = list(schema["$defs"]["RuleDraft"]["properties"])
    for rule in shown["rules"]:
        assert list(rule) == [k for k in order if k in rule]
    assert any("target" in r for r in shown["rules"])


@script(bedroom_script(decor=False, check=False)
        + ['{"objects": [], "rules": [{"rule": "on_top", "object": "lamp", "target": "sofa"}]}']
        * 3 + [json.dumps({"issues": []})])
def test_decor_that_cannot_be_used_leaves_the_plan_without_it(server, caplog):
    planner = Planner(client_for(server))
    with caplog.at_level(logging.WARNING, logger="forcelayout.llm"):
        plan = planner.plan(PROMPT)
    assert plan.ids == ["bed", "nightstand_1", "desk", "desk_chair"]
    assert "step 'decor': its items could not be used" in caplog.text
    assert planner.unresolved and planner.unresolved[0].startswith("decor: items dropped")
    assert len(server.requests) == 7 and server.remaining == 0


def test_a_size_the_model_does_not_fix_is_brought_into_its_categorys_range():
    narrow = json.loads(json.dumps(OBJECTS))
    narrow["objects"][0]["size"] = [0.5, 2.0, 0.5]   # a bed 0.5 m wide
    script = bedroom_script()
    script[1:2] = [json.dumps(narrow)] * 2   # the second time, the model stands by it
    with FakeChatServer(script) as srv:
        planner = Planner(client_for(srv))
        plan = planner.plan(PROMPT)
        assert srv.remaining == 0
    assert plan.object("bed").size == (0.8, 2.0, 0.5)
    assert planner.unresolved == []
    assert "objects: objects[0].size: 'bed' was 0.5 x 2 x 0.5 m after every attempt; set to " \
        "0.8 x 2 x 0.5 m, the nearest usual size of its category" in planner.fixes


def test_no_problems_listed_as_a_problem_asks_for_nothing_more():
    issues = json.dumps({"issues": ["no problems found", "None."]})
    with FakeChatServer(bedroom_script(check=False) + [issues]) as srv:
        planner = Planner(client_for(srv))
        planner.plan(PROMPT)
    assert planner.requests == 5


def test_a_correction_cut_off_is_not_read_as_a_shorter_plan():
    issues = json.dumps({"issues": ["the chair is not needed"]})
    whole = json.dumps({"issues": [], "plan": _without_the_chair()})
    cut = whole[:whole.index('"rules"') + 40]
    with FakeChatServer(bedroom_script(check=False) + [issues, cut, cut]) as srv:
        planner = Planner(client_for(srv))
        plan = planner.plan(PROMPT)
    assert "desk_chair" in plan.ids and len(plan.rules) >= 4   # the plan before the check
    assert any("corrections dropped" in u for u in planner.unresolved)


def test_a_plan_repeated_without_problems_is_not_used():
    check = json.dumps({"issues": [], "plan": _without_the_chair()})
    with FakeChatServer(bedroom_script(check=False) + [check]) as srv:
        planner = Planner(client_for(srv))
        plan = planner.plan(PROMPT)
    assert "desk_chair" in plan.ids and planner.requests == 5


def test_client_needs_a_key_or_a_server(monkeypatch):
    monkeypatch.delenv("OPENAI_API_KEY", raising=False)
    monkeypatch.delenv("OPENAI_BASE_URL", raising=False)
    with pytest.raises(LLMRequestError, match="OPENAI_API_KEY"):
        OpenAIChatClient()
    monkeypatch.setenv("OPENAI_BASE_URL", "http://127.0.0.1:9/v1")
    monkeypatch.setenv("FORCELAYOUT_LLM_MODEL", "qwen-test")
    client = OpenAIChatClient()
    assert client.base_url == "http://127.0.0.1:9/v1" and client.model == "qwen-test"


def _example_recording():
    from pathlib import Path

    return Path(__file__).parent.parent / "examples" / "data" / "llm_bedroom.jsonl"


def test_the_shipped_example_recording_replays():
    planner = Planner(make_client(replay=_example_recording()))
    plan = planner.plan(PROMPT)
    assert "bed" in plan.ids and len(planner.failed_attempts) == 1


def test_support_bonds_of_the_scene_graph_become_on_top_rules():
    objects = json.loads(json.dumps(OBJECTS))
    objects["objects"].append({"id": "lamp", "category": "lamp", "size": [0.2, 0.2, 0.35],
                               "area": "sleeping"})
    graph = json.loads(json.dumps(GRAPH))
    graph["support"] = [{"object": "lamp", "parent": "nightstand_1"}]
    script = bedroom_script()
    script[1], script[2] = json.dumps(objects), json.dumps(graph)
    with FakeChatServer(script) as srv:
        plan = Planner(client_for(srv)).plan(PROMPT)
    assert plan.surface_of("lamp") == "on_top"
    assert [(r.object, r.target) for r in plan.rules if r.rule == "on_top"] == [
        ("lamp", "nightstand_1")]


@script(bedroom_script(check=False) + ["not json", "{\"issues\": [], \"plan\": {}}"])
def test_a_self_check_that_cannot_be_used_leaves_the_plan_as_it_was(server, caplog):
    planner = Planner(client_for(server))
    with caplog.at_level(logging.WARNING, logger="forcelayout.llm"):
        plan = planner.plan(PROMPT)
    assert len(server.requests) == 6  # two self-check attempts, then the plan stands
    assert {"bed", "desk", "plant"} <= set(plan.ids)
    assert "its corrections could not be used" in caplog.text
    assert planner.unresolved and planner.unresolved[-1].startswith(
        "self_check: corrections dropped")


def test_close_cut_reply_keeps_whole_items_only():
    from forcelayout.llm.steps import close_cut_reply

    assert close_cut_reply('{"objects": [{"id": "bed"}, {"id": "des') == \
        '{"objects": [{"id": "bed"}]}'
    assert close_cut_reply('{"objects": [{"id": "b}]ed"}, {"size": [1, 2') == \
        '{"objects": [{"id": "b}]ed"}]}'
    assert close_cut_reply('{"objects": [{"id": "bed", "size": [1, 2') is None  # no whole item
    assert close_cut_reply('{"objects": []}') is None                          # not cut off


def test_shape_of_outlines_the_keys_in_the_schemas_order():
    from forcelayout.llm.steps import ObjectsStep, SupportEdge, schema_for, shape_of

    assert shape_of(schema_for(SupportEdge)) == "- object: string\n- parent: string"
    lines = shape_of(schema_for(ObjectsStep, ["at_wall", "near"])).splitlines()
    assert lines[0] == "- objects: list of 1-24 objects, with keys:"
    assert "  - size: [number, number, number] — [width, depth, height] in metres; front is " \
        "the depth side" in lines
    assert [x.split(":")[0].strip() for x in lines if x.startswith("  - ")][-4:] == [
        "- rule", "- object", "- target (optional)", "- params (optional)"]
    assert "  - rule: one of \"at_wall\", \"near\" — Rule name from the vocabulary" in lines
