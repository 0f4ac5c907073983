"""Datasets: written as accepted, resumable to the same bytes, the same on any executor."""

import hashlib
import json
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pytest

import forcelayout as fl
from forcelayout.cli import main
from forcelayout.dataset import DatasetError, build_dataset, layout_stem, plan_sources


def digest(folder: Path) -> dict[str, str]:
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file() and p.name != "run.log"}


@pytest.fixture(scope="module")
def whole(tmp_path_factory) -> Path:
    """An uninterrupted run: two plans, three layouts each, pictures."""
    out = tmp_path_factory.mktemp("whole")
    result = build_dataset(["bedroom", "home_office"], 3, out, seed=5, pictures="svg")
    assert result.complete and result.accepted == 6
    return out


def test_the_folder_holds_layouts_index_and_summaries(whole):
    index = [json.loads(line) for line in (whole / "index.jsonl").read_text().splitlines()]
    assert [(e["plan"], e["layout"]) for e in index] == [
        ("bedroom", 0), ("bedroom", 1), ("bedroom", 2),
        ("home_office", 0), ("home_office", 1), ("home_office", 2)]
    plan = fl.load_plan("bedroom")
    from test_docs import INDEX_LINE_KEYS  # the keys docs/scale.md shows

    for e in index:
        assert e.keys() - {"repairs"} == INDEX_LINE_KEYS  # "repairs": a repaired sample
        assert e["files"][0] == f"{e['plan']}_{e['layout']:03d}.json"
        assert e["checks"]["passed"] and e["rule_satisfaction"] >= 0.95
        assert e["seed"] == fl.sampling.sample_seed(5, e["sample"])
        for name in e["files"]:
            assert (whole / e["plan"] / name).is_file()
    lay = fl.Layout.load(whole / "bedroom" / "bedroom_000.json", plan)
    assert lay.check().ok
    # the same layouts generate() accepts, in the same order
    gen = fl.generate(plan, 3, seed=5)
    assert [g.to_json() for g in gen] == [
        (whole / "bedroom" / f"bedroom_{k:03d}.json").read_text() for k in range(3)]
    summary = json.loads((whole / "bedroom" / "summary.json").read_text())
    assert summary["accepted"] == 3 and summary["attempted"] == gen.attempted
    assert not list(whole.rglob(".*tmp*"))
    assert "elapsed_s" in (whole / "run.log").read_text()


def test_a_process_pool_writes_the_same_bytes(whole, tmp_path):
    with ProcessPoolExecutor(2) as pool:
        build_dataset(["bedroom", "home_office"], 3, tmp_path, seed=5, pictures="svg",
                      executor=pool)
    assert digest(tmp_path) == digest(whole)


class Stop(Exception):
    pass


@pytest.mark.parametrize("after, unfinished", [(1, "bedroom/bedroom_001"),
                                               (4, "home_office/home_office_001")])
def test_an_interrupted_run_resumes_to_the_same_bytes(whole, tmp_path, after, unfinished):
    def stop(done, total):
        if done == after:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        build_dataset(["bedroom", "home_office"], 3, tmp_path, seed=5, pictures="svg",
                      progress=stop)
    lines = (tmp_path / "index.jsonl").read_text().splitlines()
    assert len(lines) == after
    # a kill can also leave a torn index line, a stray half-written file, a file not yet indexed
    with (tmp_path / "index.jsonl").open("a") as f:
        f.write('{"plan": "bedr')
    folder, stem = unfinished.split("/")
    (tmp_path / folder).mkdir(exist_ok=True)
    (tmp_path / folder / f".{stem}.999.tmp.svg").write_text("<svg")
    (tmp_path / folder / f"{stem}.json").write_text("{}")
    seen = []
    result = build_dataset(["bedroom", "home_office"], 3, tmp_path, seed=5, pictures="svg",
                           progress=lambda done, total: seen.append(done))
    assert result.resumed == after and result.complete
    assert seen[0] == after + 1 and seen[-1] == 6
    assert digest(tmp_path) == digest(whole)


def test_repaired_layouts_say_how_and_the_summary_counts_them(tmp_path):
    """One start round per sample: most floors are repaired or started over. Each repaired
    layout's index line holds its report's repair notes, and summary.json counts them,
    the same when the run was stopped and resumed."""
    opts = fl.Options(starts=1)
    gen = fl.generate("bedroom", 4, seed=0, options=opts)
    result = build_dataset(["bedroom"], 4, tmp_path / "whole", seed=0, pictures="none",
                           options=opts)
    lines = [json.loads(x) for x in (tmp_path / "whole" / "index.jsonl").read_text().splitlines()]
    assert [e.get("repairs", []) for e in lines] == [lay.report.repairs for lay in gen]
    summary = json.loads((tmp_path / "whole" / "bedroom" / "summary.json").read_text())
    want = fl.sampling.repair_counts([lay.report.repairs for lay in gen], "layouts")
    assert summary["repaired"] == want and want["layouts"] >= 1
    assert result.plans[0].repaired == want

    def stop(done, total):
        if done == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        build_dataset(["bedroom"], 4, tmp_path / "resumed", seed=0, pictures="none",
                      options=opts, progress=stop)
    resumed = build_dataset(["bedroom"], 4, tmp_path / "resumed", seed=0, pictures="none",
                            options=opts)
    again = json.loads((tmp_path / "resumed" / "bedroom" / "summary.json").read_text())
    assert again["repaired"] == want and resumed.plans[0].repaired == want
    finished = build_dataset(["bedroom"], 4, tmp_path / "resumed", seed=0, pictures="none",
                             options=opts)  # finished before: read from its summary
    assert finished.plans[0].repaired == want


def test_the_command_line_says_how_many_layouts_were_repaired(tmp_path, capsys, monkeypatch):
    from forcelayout import dataset_cmd
    from forcelayout.dataset import DatasetResult, PlanOutcome

    def built(sources, n, out, **kwargs):
        counts = [{"layouts": 2, "resettled": 1, "moved elsewhere": 0, "started over": 1},
                  {"layouts": 1, "resettled": 0, "moved elsewhere": 1, "started over": 0}]
        return DatasetResult(Path(out), [PlanOutcome(f"p{k}", n, n, n + 1, repaired=c)
                                         for k, c in enumerate(counts)], 1.0)

    monkeypatch.setattr(dataset_cmd, "build_dataset", built)
    assert main(["dataset", "bedroom", "home_office", "-n", "3", "--out", str(tmp_path),
                 "--quiet"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[-1] == "repaired: 3 of 6 layouts (resettled x1, moved elsewhere x1, started over x1)"


def test_repair_counts_count_a_sample_once_under_each_kind():
    notes = [[], ["moved elsewhere bed: 1 -> 0 failures", "moved elsewhere desk: 1 -> 0"],
             ["started over (2 of 2)", "resettled: 1 -> 0 failures"]]
    assert fl.sampling.repair_counts(notes) == {
        "samples": 2, "resettled": 1, "moved elsewhere": 1, "started over": 1}
    assert fl.sampling.repair_counts([], "layouts")["layouts"] == 0


def test_a_finished_dataset_is_left_as_is(whole, tmp_path):
    before = digest(whole)
    result = build_dataset(["bedroom", "home_office"], 3, whole, seed=5, pictures="svg")
    assert result.resumed == 6 and result.complete and digest(whole) == before


def test_a_folder_of_another_run_is_refused_unless_overwrite(whole, tmp_path):
    with pytest.raises(DatasetError, match=r"another dataset .*n \(3 there, 4 now\).*--overwrite"):
        build_dataset(["bedroom", "home_office"], 4, whole, seed=5, pictures="svg")
    other = tmp_path / "other"
    other.mkdir()
    (other / "plan.json").write_text("{}")
    with pytest.raises(DatasetError, match="not a forcelayout dataset"):
        build_dataset("bedroom", 1, other, pictures="none")
    result = build_dataset("bedroom", 1, other, pictures="none", overwrite=True)
    assert result.complete and not (other / "plan.json").exists()
    assert sorted(p.name for p in (other / "bedroom").iterdir()) == [
        "bedroom_000.json", "plan.json", "summary.json"]


def test_names_are_padded_to_the_width_of_the_run(tmp_path):
    assert layout_stem("bedroom", 7, 10) == "bedroom_007"
    assert layout_stem("bedroom", 999, 1000) == "bedroom_999"
    assert layout_stem("bedroom", 7, 1001) == "bedroom_0007"
    assert layout_stem("bedroom", 12345, 100_000) == "bedroom_12345"
    names = [layout_stem("x", k, 20_000) for k in (9, 10, 100, 19_999)]
    assert names == sorted(names)


def test_a_short_plan_says_why(tmp_path):
    plan = fl.load_plan("bedroom").model_dump(mode="json")
    plan["room"]["polygon"] = [[0, 0], [4.2, 0], [4.2, 2.3], [0, 2.3]]
    plan["name"] = "tight"
    result = build_dataset([plan], 3, tmp_path, pictures="none", max_attempts=2)
    (outcome,) = result.plans
    assert outcome.accepted < 3 and outcome.attempted == 2 and outcome.why
    summary = json.loads((tmp_path / "tight" / "summary.json").read_text())
    assert summary["why"] == outcome.why and not result.complete
    assert sum(summary["failure_reasons"].values()) >= 2 - outcome.accepted  # or more


def test_sources_take_folders_and_refuse_clashing_names(tmp_path):
    for name in ("a", "b"):
        plan = fl.load_plan("bedroom").model_dump(mode="json")
        plan["name"] = f"room_{name}"
        (tmp_path / f"{name}.json").write_text(json.dumps(plan))
    assert [p.name for p in plan_sources([tmp_path, "bedroom"])] == ["room_a", "room_b",
                                                                      "bedroom"]
    with pytest.raises(DatasetError, match="two plans are named 'room_a'"):
        plan_sources([tmp_path, tmp_path / "a.json"])
    (tmp_path / "empty").mkdir()
    with pytest.raises(DatasetError, match="holds no plan file"):
        plan_sources([tmp_path / "empty"])


def test_the_command_line_writes_a_dataset_and_resumes(whole, tmp_path, capsys):
    args = ["dataset", "bedroom", "home_office", "-n", "3", "--out", str(tmp_path),
            "--seed", "5", "--pictures", "svg", "--quiet"]
    assert main(args) == 0
    assert "6/6 layouts of 2 plan(s)" in capsys.readouterr().out
    assert digest(tmp_path) == digest(whole)
    assert main(args) == 0
    assert "6 of them from an earlier run" in capsys.readouterr().out


@pytest.mark.parametrize("args, reason", [
    (["bedroom", "-n", "-1"], "-1 is less than 1"), (["bedroom", "-n", "0"], "0 is less than 1"),
    (["bedroom", "-n", "2", "--workers", "0"], "0 is less than 1"),
    (["bedroom", "-n", "2", "--workers", "2", "--scheduler", "tcp://x:1"], "not allowed with"),
    (["no_such_plan.json", "-n", "2"], "no plan file 'no_such_plan.json'"),
    (["bedroom", "-n", "2", "--pictures", "gif"], "invalid choice: 'gif'"),
    (["bedroom", "-n", "2", "--min-rules", "1.2"], "1.2 is not between 0 and 1"),
])
def test_the_command_line_refuses_bad_input_in_one_line(args, reason, tmp_path):
    proc = subprocess.run([sys.executable, "-m", "forcelayout.cli", "dataset", *args,
                           "--out", str(tmp_path / "o")], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 2
    assert reason in proc.stderr and "Traceback" not in proc.stderr
    assert not (tmp_path / "o").exists()


def test_min_rules_reaches_the_runs_options(tmp_path, capsys):
    assert main(["dataset", "bedroom", "-n", "1", "--out", str(tmp_path), "--quiet",
                 "--pictures", "none", "--min-rules", "1"]) == 0
    manifest = json.loads((tmp_path / "dataset.json").read_text())
    assert manifest["options"]["min_rule_satisfaction"] == 1.0
    (entry,) = [json.loads(line) for line in (tmp_path / "index.jsonl").open()]
    assert entry["rule_satisfaction"] == 1.0


def test_a_refused_folder_is_one_line(whole, capsys):
    assert main(["dataset", "bedroom", "-n", "9", "--out", str(whole), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--overwrite" in err


def test_a_dask_cluster_writes_the_same_bytes(whole, tmp_path):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        build_dataset(["bedroom", "home_office"], 3, tmp_path, seed=5, pictures="svg",
                      executor=client.get_executor())
    assert digest(tmp_path) == digest(whole)


def test_exports_are_written_in_the_workers_and_resume_to_the_same_bytes(tmp_path):
    pytest.importorskip("trimesh")
    pytest.importorskip("pxr")
    kw = dict(seed=1, pictures="none", exports=["glb", "usd", "mjcf", "habitat"],
              movable=["chair"])
    with ProcessPoolExecutor(2) as pool:
        build_dataset("home_office", 2, tmp_path / "a", executor=pool, **kw)
    (entry, _) = [json.loads(line) for line in (tmp_path / "a" / "index.jsonl").open()]
    assert entry["files"] == ["home_office_000.json", "home_office_000.glb",
                              "home_office_000.usda", "home_office_000.xml",
                              "home_office_000.habitat"]

    def stop(done, total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        build_dataset("home_office", 2, tmp_path / "b", progress=stop, **kw)
    build_dataset("home_office", 2, tmp_path / "b", **kw)
    assert digest(tmp_path / "b") == digest(tmp_path / "a")
    with pytest.raises(DatasetError, match="unknown export format.*'obj'"):
        build_dataset("home_office", 2, tmp_path / "c", exports=["obj"])


def test_ctrl_c_on_the_command_line_keeps_what_is_finished_and_says_how_to_resume(tmp_path):
    import os
    import signal
    import time

    out = tmp_path / "data"
    cmd = [sys.executable, "-m", "forcelayout.cli", "dataset", "bedroom", "-n", "12", "--out",
           str(out), "--workers", "2", "--pictures", "none", "--quiet"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)  # Ctrl-C reaches the whole group
    index = out / "index.jsonl"
    deadline = time.monotonic() + 120
    while (not index.exists() or not index.read_text()) and time.monotonic() < deadline:
        time.sleep(0.1)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    if proc.returncode == 0:
        pytest.skip("the run finished before the interrupt arrived")
    assert proc.returncode == 130
    assert "Traceback" not in err and err.strip().count("\n") == 0
    assert "run the same command again to resume" in err
    finished = len(index.read_text().splitlines())
    rerun = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert rerun.returncode == 0 and f"{finished} of them from an earlier run" in rerun.stdout


# ----------------------------------------------------------------------------- judged datasets


def even_seeds(layout: fl.Layout) -> dict:
    """A deterministic judge: plausible for even seeds."""
    ok = layout.seed % 2 == 0
    return {"plausible": ok, "reasons": ["scripted"],
            "objects": [] if ok else [{"object": "bed", "complaint": "odd seed"}]}


JUDGED = dict(seed=2, pictures="none", judge=even_seeds)


@pytest.fixture(scope="module")
def judged(tmp_path_factory) -> Path:
    """An uninterrupted judged run of one plan, three layouts."""
    out = tmp_path_factory.mktemp("judged")
    assert build_dataset("bedroom", 3, out, **JUDGED).complete
    return out


def test_a_judge_decides_which_layouts_are_written(judged):
    from forcelayout.validate import generate_validated

    entries = [json.loads(line) for line in (judged / "index.jsonl").open()]
    loop = generate_validated("bedroom", 3, judge=even_seeds, seed=2)
    assert [e["seed"] for e in entries] == [lay.seed for lay in loop]  # the V loop's choice
    assert all(e["seed"] % 2 == 0 for e in entries)
    assert entries[0]["judge"] == {"plausible": True, "reasons": ["scripted"], "objects": []}
    rejected = sum(e["rejected_before"].get("implausible", 0) for e in entries)
    summary = json.loads((judged / "bedroom" / "summary.json").read_text())
    assert summary["failure_reasons"]["implausible"] == rejected == loop.summary()[
        "rejection_reasons"].get("implausible", 0)
    assert summary["judge"].endswith("test_dataset:even_seeds")
    manifest = json.loads((judged / "dataset.json").read_text())
    assert manifest["judge"] == summary["judge"]
    written = sorted(p.name for p in (judged / "bedroom").glob("bedroom_*.json"))
    assert written == ["bedroom_000.json", "bedroom_001.json", "bedroom_002.json"]


def test_a_judged_run_resumes_to_the_same_bytes(judged, tmp_path):
    def stop(done, total):
        if done == 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        build_dataset("bedroom", 3, tmp_path, progress=stop, **JUDGED)
    assert build_dataset("bedroom", 3, tmp_path, **JUDGED).resumed == 1
    assert digest(tmp_path) == digest(judged)


def test_another_judge_does_not_resume_a_judged_folder(judged):
    with pytest.raises(DatasetError, match="judge"):
        build_dataset("bedroom", 3, judged, seed=2, pictures="none", judge=lambda lay: True)
    with pytest.raises(DatasetError, match="judge"):
        build_dataset("bedroom", 3, judged, seed=2, pictures="none")


def test_unjudged_layouts_are_not_written_and_counted(tmp_path):
    def flaky(layout: fl.Layout) -> bool:
        if layout.seed % 3 == 0:
            raise TimeoutError("no reply")
        return True

    result = build_dataset("home_office", 2, tmp_path, seed=0, pictures="none", judge=flaky)
    entries = [json.loads(line) for line in (tmp_path / "index.jsonl").open()]
    assert [e["seed"] % 3 != 0 for e in entries] == [True] * result.accepted
    summary = json.loads((tmp_path / "home_office" / "summary.json").read_text())
    unjudged = summary["failure_reasons"].get("unjudged", 0)
    assert unjudged == sum(e["rejected_before"].get("unjudged", 0) for e in entries)
    with pytest.raises(DatasetError, match="callable"):
        build_dataset("home_office", 1, tmp_path / "x", judge="vlm")


def test_the_command_line_takes_a_judge(judged, tmp_path, monkeypatch, capsys):
    (tmp_path / "my_judge.py").write_text(
        "def even_seeds(layout):\n"
        "    ok = layout.seed % 2 == 0\n"
        "    return {'plausible': ok, 'reasons': ['scripted'],\n"
        "            'objects': [] if ok else [{'object': 'bed', 'complaint': 'odd seed'}]}\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    out = tmp_path / "cli"
    args = ["dataset", "bedroom", "-n", "3", "--out", str(out), "--seed", "2", "--pictures",
            "none", "--quiet", "--judge", "my_judge:even_seeds"]
    assert main(args) == 0
    assert "3/3 layouts" in capsys.readouterr().out
    ours, theirs = digest(out), digest(judged)
    assert set(ours) == set(theirs)
    same = [k for k in ours if ours[k] == theirs[k]]  # only the judge's name differs
    assert set(ours) - set(same) == {"dataset.json", "bedroom/summary.json"}
    assert main(["dataset", "bedroom", "-n", "1", "--out", str(tmp_path / "bad"),
                 "--judge", "no_such_module_q:judge"]) == 2
    assert "--judge: judge 'no_such_module_q:judge': cannot import" in capsys.readouterr().err
