"""The V loop (forcelayout.validate.generate_validated) with plain-callable judges."""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor

import pytest

import forcelayout as fl
from forcelayout.diagnose import FewLayoutsWarning
from forcelayout.validate import Verdict, generate_validated, judge_layout, load_judge
from forcelayout.validate.loop import judge_name

PLAN = "bedroom"


def every_other(layout: fl.Layout) -> bool:
    """A deterministic scripted judge: plausible for even seeds."""
    return layout.seed % 2 == 0


def test_an_always_yes_judge_accepts_what_generate_accepts():
    want = fl.generate(PLAN, 3, seed=2)
    run = generate_validated(PLAN, 3, judge=lambda lay: True, seed=2)
    assert [lay.seed for lay in run] == [lay.seed for lay in want]
    assert run.attempted == want.attempted
    assert run.judged == 3 and run.acceptance_rate == 1.0
    assert len(run.verdicts) == 3 and all(v.plausible for v in run.verdicts)


def test_the_judge_sees_only_valid_distinct_samples_and_the_loop_stops_at_n():
    seen: list[int] = []

    def judge(layout: fl.Layout) -> dict:
        seen.append(layout.seed)
        assert layout.report.valid
        ok = layout.seed % 2 == 0
        return {"plausible": ok, "reasons": [] if ok else ["the bed blocks the window"],
                "objects": [] if ok else [{"object": "bed", "complaint": "under the window"}]}

    run = generate_validated(PLAN, 2, 30, judge=judge, seed=0)
    assert len(run) == 2
    judged = [c for c in run.candidates if c.status in ("accepted", "implausible")]
    assert [c.layout.seed for c in judged] == seen
    assert run.candidates[-1].status == "accepted"  # stopped as soon as 2 were accepted
    for c in run.rejections:
        if c.status == "implausible":
            assert c.reason == "the bed blocks the window; bed: under the window"
            assert c.layout.report.failures[-1].startswith("implausible: the bed")
        else:
            assert c.status in ("invalid", "duplicate") and c.reason
    s = run.summary()
    assert s["accepted"] == 2 and s["attempted"] == run.attempted
    assert s["judged"] == len(seen) and s["acceptance_rate"] == pytest.approx(2 / len(seen))
    assert s["seconds_per_accepted"] == pytest.approx(run.seconds / 2)
    assert sum(s["rejection_reasons"].values()) == run.attempted - 2


def test_the_budget_ends_the_loop_with_a_warning_that_says_why():
    with pytest.warns(FewLayoutsWarning, match="judge"):
        run = generate_validated(PLAN, 3, 6, judge=lambda lay: Verdict(
            plausible=False, reasons=["no"]))
    assert len(run) == 0 and run.attempted == 6
    assert run.why and "implausible" in run.why
    assert run.seconds_per_accepted == float("inf")


def test_a_failing_judge_leaves_scenes_unjudged_and_never_crashes():
    calls = []

    def broken(layout: fl.Layout) -> bool:
        calls.append(layout.seed)
        if len(calls) == 1:
            raise ConnectionError("endpoint down")
        if len(calls) == 2:
            return "yes"  # type: ignore[return-value]
        if len(calls) == 3:
            return {"plausible": "perhaps"}  # type: ignore[return-value]
        return True

    run = generate_validated(PLAN, 1, 30, judge=broken)
    unjudged = [c for c in run.candidates if c.status == "unjudged"]
    assert [c.reason.split(":")[0] for c in unjudged] == [
        "ConnectionError", "the judge returned str, not a verdict (give a Verdict, a bool or a "
        "dict with 'plausible')", "the judge's answer is not a verdict"]
    assert len(run) == 1 and run.unjudged == 3 and run.judged == 1


def test_a_judge_that_keeps_failing_stops_the_loop_early():
    def down(layout: fl.Layout) -> bool:
        raise OSError("connection refused")

    with pytest.warns(FewLayoutsWarning):
        run = generate_validated(PLAN, 2, 40, judge=down, max_unjudged_in_a_row=2)
    assert run.unjudged == 2 and "2 times in a row" in run.why and "connection refused" in run.why


def test_a_slow_judge_times_out():
    lay = fl.solve(PLAN, 0)
    t0 = time.perf_counter()
    j = judge_layout(lambda _: time.sleep(1.0) or True, lay, timeout=0.1)
    assert time.perf_counter() - t0 < 0.8
    assert j.status == "unjudged" and j.reason == "no verdict within 0.1 s" and j.verdict is None
    assert judge_layout(every_other, lay, timeout=5).status in ("plausible", "implausible")


def test_the_result_does_not_depend_on_the_executor():
    here = generate_validated(PLAN, 2, 20, judge=every_other, seed=5)
    with ThreadPoolExecutor(2) as ex:
        there = generate_validated(PLAN, 2, 20, judge=every_other, seed=5, executor=ex)
    assert [c.status for c in here.candidates] == [c.status for c in there.candidates]
    assert [lay.to_json() for lay in here] == [lay.to_json() for lay in there]


def test_on_layout_gets_each_accepted_scene_with_its_verdict():
    got = []
    run = generate_validated(PLAN, 2, judge=lambda lay: True,
                             on_layout=lambda lay, v: got.append((lay.seed, v.plausible)))
    assert got == [(lay.seed, True) for lay in run]


def test_bad_arguments_are_refused_before_sampling():
    with pytest.raises(ValueError, match="n_accepted"):
        generate_validated(PLAN, -1, judge=every_other)
    with pytest.raises(ValueError, match="max_attempts"):
        generate_validated(PLAN, 1, 2.5, judge=every_other)
    with pytest.raises(TypeError, match="callable"):
        generate_validated(PLAN, 1, judge="vlm")
    with pytest.raises(ValueError, match="judge_timeout"):
        generate_validated(PLAN, 1, judge=every_other, judge_timeout=0)


def test_load_judge_and_its_name(tmp_path, monkeypatch):
    import operator

    assert load_judge("operator:truth") is operator.truth
    assert judge_name(every_other).endswith("test_validated:every_other")
    for spec, msg in [("nocolon", "module:callable"), ("no_such_mod_x:f", "cannot import"),
                      ("json:nothing", "has no"), ("json:__doc__", "not callable")]:
        with pytest.raises(ValueError, match=msg):
            load_judge(spec)
    (tmp_path / "my_judges.py").write_text(
        "class Strict:\n    name = 'strict-v1'\n    def __call__(self, layout):\n"
        "        return False\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    judge = load_judge("my_judges:Strict")  # a class is instantiated
    assert judge(None) is False and judge_name(judge) == "strict-v1"
